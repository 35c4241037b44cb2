#include "scenegen/image_encode.h"

#include <OpenImageIO/filesystem.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace littoral::scenegen {

namespace OIIO = OIIO_NAMESPACE;

std::string encodeImage(const std::filesystem::path& target, const std::string& formatName, const OIIO::ImageSpec& spec,
                        OIIO::TypeDesc type, const void* pixels) {
    const SourceLoc where{target.string()};
    auto out = OIIO::ImageOutput::create(formatName);
    if (!out) throw InputError(where, "no image writer for " + formatName + ": " + libraryMessage(OIIO::geterror()));
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput vec(bytes);
    if (!out->supports("ioproxy") || !out->set_ioproxy(&vec))
        throw InternalError("the OpenImageIO " + formatName + " writer cannot encode into memory");
    if (!out->open("memory." + formatName, spec) || !out->write_image(type, pixels) || !out->close())
        throw InputError(where, "cannot encode the image: " + libraryMessage(out->geterror()));
    return std::string(bytes.begin(), bytes.end());
}

void writeImageFile(const std::filesystem::path& target, const std::string& formatName, const OIIO::ImageSpec& spec,
                    OIIO::TypeDesc type, const void* pixels) {
    writeFileAtomic(target, encodeImage(target, formatName, spec, type, pixels));
}

}  // namespace littoral::scenegen
