#pragma once
// The interface between core/image_io.cpp and the OpenImageIO plugin (core/image_io_oiio.cpp).
// Internal to core/image_io: plain types and virtual calls only, so that no exception and no
// Littoral type but these crosses the plugin's boundary.
#include <memory>
#include <string>

#include "core/image_io.h"

namespace littoral::imageio {

class ReaderBackend {
  public:
    virtual ~ReaderBackend() = default;
    virtual bool read(int channels, PixelType type, void* dst, std::string& error) = 0;
};

enum class EncodeStatus : int { Ok, NoWriter, NoMemoryOutput, Failed };

class Backend {
  public:
    virtual ~Backend() = default;
    // nullptr and `error` if the file cannot be opened as an image; else its header in `header`.
    virtual std::unique_ptr<ReaderBackend> open(const std::string& path, Header& header, std::string& error) const = 0;
    virtual EncodeStatus encode(const std::string& format, const WriteSpec& spec, const void* pixels, std::string& bytes,
                                std::string& error) const = 0;
};

// Bumped whenever Backend, ReaderBackend, Header or WriteSpec change: a stale plugin is refused.
inline constexpr int kBackendVersion = 2;

}  // namespace littoral::imageio

// The plugin's one exported symbol: its backend, and the interface version it was built with.
extern "C" const littoral::imageio::Backend* littoral_imageio_backend(int* version);
