#pragma once
// Images encoded in memory with OpenImageIO, so that the bytes reach the disk through the checked,
// atomic writer of core/atomic_file.h (OIIO's own file writers do not report a full disk).
// Internal to scenegen: includes OpenImageIO.
#include <filesystem>
#include <string>

#include <OpenImageIO/imageio.h>

namespace littoral::scenegen {

// Encodes `pixels` (interleaved, `type` per channel) as the format named by `formatName` (an
// extension such as "png" or "tif"). InputError naming `target` if OIIO cannot encode it.
std::string encodeImage(const std::filesystem::path& target, const std::string& formatName,
                        const OIIO_NAMESPACE::ImageSpec& spec, OIIO_NAMESPACE::TypeDesc type, const void* pixels);

// encodeImage + writeFileAtomic.
void writeImageFile(const std::filesystem::path& target, const std::string& formatName,
                    const OIIO_NAMESPACE::ImageSpec& spec, OIIO_NAMESPACE::TypeDesc type, const void* pixels);

}  // namespace littoral::scenegen
