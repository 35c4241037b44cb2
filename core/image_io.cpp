#include "core/image_io.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io_backend.h"

// Defined where the plugin's source is linked in statically (the fuzz targets); elsewhere null, and
// the plugin is loaded.
extern "C" const littoral::imageio::Backend* littoral_imageio_backend(int* version) __attribute__((weak));

namespace littoral::imageio {

namespace {

const Backend* fromEntry(const Backend* (*entry)(int*), const std::string& where) {
    int version = 0;
    const Backend* b = entry(&version);
    if (!b || version != kBackendVersion)
        throw InternalError(fmt::format("the image plugin {} has interface version {}, this program needs {}: "
                                        "rebuild Littoral (or point LITTORAL_IMAGEIO_PLUGIN at this build's plugin)",
                                        where, version, kBackendVersion));
    return b;
}

const Backend* load() {
    if (littoral_imageio_backend) return fromEntry(littoral_imageio_backend, "linked in");
    const char* env = std::getenv("LITTORAL_IMAGEIO_PLUGIN");
#ifdef LITTORAL_IMAGEIO_PLUGIN
    const std::string path = env && *env ? env : LITTORAL_IMAGEIO_PLUGIN;
#else
    const std::string path = env && *env ? env : "liblittoral_imageio.so";
#endif
    // RTLD_LOCAL: OpenImageIO's symbols stay out of the program's namespace; the plugin is never
    // unloaded (its readers may outlive any one call).
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!handle) {
        const char* why = dlerror();
        throw InternalError(fmt::format("cannot load the image plugin {}: {} (it is built beside Littoral as "
                                        "liblittoral_imageio.so; LITTORAL_IMAGEIO_PLUGIN names another)",
                                        path, why ? why : "unknown error"));
    }
    auto entry = reinterpret_cast<const Backend* (*)(int*)>(dlsym(handle, "littoral_imageio_backend"));
    if (!entry) throw InternalError("the image plugin " + path + " has no littoral_imageio_backend");
    return fromEntry(entry, path);
}

const Backend& backend() {
    static const Backend* b = load();  // once, thread-safe
    return *b;
}

// SOURCE_DATE_EPOCH (seconds since 1970, UTC) as an EXR DateTime, or "" if unset or malformed.
std::string epochDateTime() {
    const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
    if (!epoch) return "";
    char* end = nullptr;
    const long long t = std::strtoll(epoch, &end, 10);
    if (end == epoch || *end != '\0' || t < 0) return "";
    const std::time_t tt = static_cast<std::time_t>(t);
    std::tm utc{};
    gmtime_r(&tt, &utc);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y:%m:%d %H:%M:%S", &utc);
    return buf;
}

}  // namespace

const std::string* Header::stringAttribute(const std::string& name) const {
    for (const Attribute& a : attributes)
        if (a.name == name && a.kind == Attribute::Kind::String) return &a.value;
    return nullptr;
}

Reader::Reader(const std::filesystem::path& path) {
    std::string error;
    backend_ = backend().open(path.string(), header_, error);
    if (!backend_) error_ = libraryMessage(error);
}

Reader::~Reader() = default;

bool Header::storedAs(PixelType type) const {
    switch (type) {
        case PixelType::UInt8: return storedType == "uint8";
        case PixelType::UInt16: return storedType == "uint16";
        case PixelType::Int32: return storedType == "int";  // OpenImageIO's name for 32-bit signed
        case PixelType::Float: return storedType == "float";
    }
    return false;
}

bool Reader::readIndices(uint16_t* dst) {
    if (header_.storedAs(PixelType::UInt16)) return read(1, PixelType::UInt16, dst);
    if (!header_.storedAs(PixelType::UInt8)) {
        error_ = "not an 8- or 16-bit unsigned integer image (" + header_.storedType + ")";
        return false;
    }
    std::vector<uint8_t> bytes(static_cast<size_t>(header_.width) * static_cast<size_t>(header_.height));
    if (!read(1, PixelType::UInt8, bytes.data())) return false;
    std::copy(bytes.begin(), bytes.end(), dst);
    return true;
}

bool Reader::read(int channels, PixelType type, void* dst) {
    std::string error;
    if (backend_ && backend_->read(channels, type, dst, error)) return true;
    error_ = libraryMessage(error);
    return false;
}

std::string encode(const std::filesystem::path& target, const std::string& format, const WriteSpec& spec,
                   const void* pixels) {
    const SourceLoc where{target.string()};
    WriteSpec stamped = spec;
    const bool dated = std::any_of(spec.attributes.begin(), spec.attributes.end(),
                                   [](const auto& a) { return a.first == "DateTime"; });
    if (format == "exr" && !dated)
        if (const std::string t = epochDateTime(); !t.empty()) stamped.attributes.emplace_back("DateTime", t);
    std::string bytes, error;
    switch (backend().encode(format, stamped, pixels, bytes, error)) {
        case EncodeStatus::Ok: return bytes;
        case EncodeStatus::NoWriter:
            throw InputError(where, "no image writer for " + format + ": " + libraryMessage(error));
        case EncodeStatus::NoMemoryOutput:
            throw InternalError("the OpenImageIO " + format + " writer cannot encode into memory");
        case EncodeStatus::Failed: break;
    }
    throw InputError(where, "cannot encode the image: " + libraryMessage(error));
}

void writeFile(const std::filesystem::path& target, const WriteSpec& spec, const void* pixels, const std::string& format) {
    std::string f = format;
    if (f.empty()) f = target.extension().empty() ? std::string("exr") : target.extension().string().substr(1);
    writeFileAtomic(target, encode(target, f, spec, pixels));
}

}  // namespace littoral::imageio
