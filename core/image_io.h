#pragma once
// Image files (EXR, TIFF, PNG, ...) read and encoded through OpenImageIO, which is loaded on first
// use from a plugin (core/image_io_oiio.cpp, built as liblittoral_imageio.so) instead of being
// linked into every program. OpenImageIO brings about 250 shared libraries with it (OpenCV, FFmpeg,
// GStreamer, DCMTK, ...), and resolving their symbols took 0.35-0.4 s at the start of every
// process, whether or not it touched an image: `littoral check-scene`, each MPI rank, each of the
// test suite's 500 test processes (docs/architecture.md, "Image files").
//
// The plugin is found at LITTORAL_IMAGEIO_PLUGIN (environment) if set, else where the build put it.
// A program that links the plugin's source statically (the fuzz targets) uses it directly.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace littoral::imageio {

enum class PixelType : int { UInt8, UInt16, Int32, Float };

// One attribute of an image header: its value as text, and whether it is stored as a string (a
// number's text is OpenImageIO's formatting of it).
struct Attribute {
    std::string name, value;
    enum class Kind : int { String, Int, Float, Other } kind = Kind::String;
};

struct Header {
    int width = 0, height = 0, channels = 0;
    std::string storedType;  // the file's pixel type as OpenImageIO names it: "uint8", "half", ...
    std::vector<std::string> channelNames;
    std::vector<Attribute> attributes;  // every attribute of the header but the channel names

    // The value of the string attribute `name`, or nullptr.
    const std::string* stringAttribute(const std::string& name) const;
    // Whether the file stores its pixels as `type` (read from storedType).
    bool storedAs(PixelType type) const;
};

class ReaderBackend;

// An open image file. Construction never throws for a file that cannot be decoded: ok() is false
// and error() says why (one line, libraryMessage()); the caller words the error for its context.
class Reader {
  public:
    explicit Reader(const std::filesystem::path& path);
    ~Reader();
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;
    bool ok() const { return backend_ != nullptr; }
    const std::string& error() const { return error_; }
    const Header& header() const { return header_; }
    // Channels [0, channels) of every pixel, converted to `type`, interleaved, into `dst` (room for
    // width x height x channels values). False, with error() set, if the pixels cannot be decoded.
    bool read(int channels, PixelType type, void* dst);
    // Channel 0 of an image stored as 8- or 16-bit unsigned integers (a class or index map), in the
    // file's own type widened to 16 bits: asked for 16 bits, OpenImageIO would rescale 8-bit values
    // (1 -> 257). Needs header().storedAs(UInt8) or storedAs(UInt16); false, with error(), else.
    bool readIndices(uint16_t* dst);

  private:
    std::unique_ptr<ReaderBackend> backend_;
    Header header_;
    std::string error_;
};

// What an encoded image holds: size, channels, the type it is stored as, the channel names (empty:
// the format's defaults) and string attributes ("compression", "DateTime", "littoral:..."). No
// channel is marked as alpha: a fourth channel is data like the others.
struct WriteSpec {
    int width = 0, height = 0, channels = 0;
    PixelType type = PixelType::Float;
    std::vector<std::string> channelNames;
    std::vector<std::pair<std::string, std::string>> attributes;
    int tileWidth = 0, tileHeight = 0;  // 0: scanlines
};

// `pixels` (interleaved, spec.type per channel) encoded in memory as the format named `format` (an
// extension: "exr", "png", "tif"). With SOURCE_DATE_EPOCH set (the reproducible-builds convention)
// an EXR's DateTime is that time rather than now, unless the spec sets DateTime. InputError naming
// `target` if the format has no writer or the pixels cannot be encoded.
std::string encode(const std::filesystem::path& target, const std::string& format, const WriteSpec& spec,
                   const void* pixels);

// encode() + writeFileAtomic(): the bytes reach the disk through core/atomic_file.h's checked,
// atomic writer (OpenImageIO's own file writers do not report a full disk: an 8 KB EXR and a 0-byte
// PNG were once left as finished outputs). The format is the target's extension ("exr" if none)
// unless `format` names one.
void writeFile(const std::filesystem::path& target, const WriteSpec& spec, const void* pixels,
               const std::string& format = "");

}  // namespace littoral::imageio
