#include "core/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "core/error.h"

namespace littoral {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(fs::path target) : target_(std::move(target)) {
    if (target_.has_parent_path()) fs::create_directories(target_.parent_path());
    // Keep the extension last so that libraries choosing a format by extension (OIIO) still work.
    temp_ = target_.parent_path() /
            (target_.stem().string() + ".tmp-" + std::to_string(::getpid()) + target_.extension().string());
}

AtomicOutput::~AtomicOutput() {
    if (!committed_) {
        std::error_code ec;
        fs::remove(temp_, ec);
    }
}

void AtomicOutput::commit() {
    std::error_code ec;
    fs::rename(temp_, target_, ec);
    if (ec) throw InputError(SourceLoc{target_.string()}, "cannot write output: " + ec.message());
    committed_ = true;
}

void writeFileAtomic(const fs::path& target, const std::function<void(const fs::path&)>& writer) {
    AtomicOutput out(target);
    writer(out.tempPath());
    out.commit();
}

void writeTextFileAtomic(const fs::path& target, const std::string& text) {
    writeFileAtomic(target, [&](const fs::path& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) throw InputError(SourceLoc{target.string()}, "cannot write output file");
    });
}

std::string readTextFile(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(SourceLoc{path.string()}, "cannot open file for reading");
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

}  // namespace littoral
