// The OpenImageIO side of core/image_io.h, built as the plugin liblittoral_imageio.so (loaded on
// first use) or linked statically (the fuzz targets). Reports failures as text; core/image_io.cpp
// turns them into Littoral's errors.
#include <cstdio>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "core/image_io_backend.h"

namespace littoral::imageio {
namespace {

namespace OIIO = OIIO_NAMESPACE;

OIIO::TypeDesc typeDesc(PixelType t) {
    switch (t) {
        case PixelType::UInt8: return OIIO::TypeDesc::UINT8;
        case PixelType::UInt16: return OIIO::TypeDesc::UINT16;
        case PixelType::Int32: return OIIO::TypeDesc::INT32;
        case PixelType::Float: return OIIO::TypeDesc::FLOAT;
    }
    return OIIO::TypeDesc::FLOAT;
}

Attribute::Kind kindOf(const OIIO::ParamValue& p) {
    if (p.type() == OIIO::TypeDesc::STRING) return Attribute::Kind::String;
    if (p.type() == OIIO::TypeDesc::INT) return Attribute::Kind::Int;
    if (p.type() == OIIO::TypeDesc::FLOAT) return Attribute::Kind::Float;
    return Attribute::Kind::Other;
}

class OiioReader final : public ReaderBackend {
  public:
    explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {}
    ~OiioReader() override { in_->close(); }
    bool read(int channels, PixelType type, void* dst, std::string& error) override {
        if (in_->read_image(0, 0, 0, channels, typeDesc(type), dst)) return true;
        error = in_->geterror();
        return false;
    }

  private:
    std::unique_ptr<OIIO::ImageInput> in_;
};

class OiioBackend final : public Backend {
  public:
    std::unique_ptr<ReaderBackend> open(const std::string& path, Header& header, std::string& error) const override {
        auto in = OIIO::ImageInput::open(path);
        if (!in) {
            error = OIIO::geterror();
            return nullptr;
        }
        const OIIO::ImageSpec& spec = in->spec();
        header.width = spec.width;
        header.height = spec.height;
        header.channels = spec.nchannels;
        header.storedType = spec.format.c_str();
        header.channelNames = spec.channelnames;
        for (const OIIO::ParamValue& p : spec.extra_attribs) {
            const Attribute::Kind kind = kindOf(p);
            std::string value = p.get_string();
            if (kind == Attribute::Kind::Int) value = std::to_string(p.get_int());
            if (kind == Attribute::Kind::Float) {
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(p.get_float()));  // round-trips a float
                value = buf;
            }
            header.attributes.push_back({p.name().string(), value, kind});
        }
        return std::make_unique<OiioReader>(std::move(in));
    }

    EncodeStatus encode(const std::string& format, const WriteSpec& w, const void* pixels, std::string& bytes,
                        std::string& error) const override {
        auto out = OIIO::ImageOutput::create(format);
        if (!out) {
            error = OIIO::geterror();
            return EncodeStatus::NoWriter;
        }
        std::vector<unsigned char> buffer;
        OIIO::Filesystem::IOVecOutput vec(buffer);
        if (!out->supports("ioproxy") || !out->set_ioproxy(&vec)) return EncodeStatus::NoMemoryOutput;
        OIIO::ImageSpec spec(w.width, w.height, w.channels, typeDesc(w.type));
        if (!w.channelNames.empty()) spec.channelnames = w.channelNames;
        spec.alpha_channel = -1;
        spec.tile_width = w.tileWidth;
        spec.tile_height = w.tileHeight;  // Littoral writes no alpha: a fourth channel is data
        for (const auto& [name, value] : w.attributes) spec.attribute(name, value);
        if (!out->open("memory." + format, spec) || !out->write_image(typeDesc(w.type), pixels)) {
            error = out->geterror();
            out->close();
            return EncodeStatus::Failed;
        }
        if (!out->close()) {
            error = out->geterror();
            return EncodeStatus::Failed;
        }
        bytes.assign(buffer.begin(), buffer.end());
        return EncodeStatus::Ok;
    }
};

}  // namespace
}  // namespace littoral::imageio

extern "C" __attribute__((visibility("default"))) const littoral::imageio::Backend* littoral_imageio_backend(int* version) {
    static const littoral::imageio::OiioBackend backend;
    *version = littoral::imageio::kBackendVersion;
    return &backend;
}
