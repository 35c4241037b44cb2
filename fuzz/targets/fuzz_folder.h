#pragma once
// A folder of files packed into one fuzz input, for the targets whose input is a folder (an IR:
// scene.json and its meshes; a progressive-render checkpoint: state.json and its image sums).
//
// The container: each file is a section that starts with a header line "--- PATH" and holds the
// bytes after that line up to the "\n" before the next header line (or to the end of the input),
// so a file's bytes are exact, binary ones included:
//
//   --- scene.json
//   {"format": "littoral-scene-ir", ...}
//   --- meshes/water.ply
//   ply
//   ...
//
// PATH is relative to the folder: 1 to 4 components of 1 to 64 characters from A-Z a-z 0-9 . _ -,
// none of them "." or "..", separated by "/". A section whose PATH is not of that form, or that
// would write through or over a file already unpacked, is skipped (the container must never
// write outside the scratch folder). An input that does not begin with "--- " is one file, named
// `wholeName`. fuzz/pack.sh packs a folder into this form.
//
// The scratch folder is under /dev/shm (memory, no disk wear) when it exists, one per process.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

namespace littoral::fuzz {

inline bool isPackedPath(std::string_view p) {
    if (p.empty() || p.size() > 4 * 65) return false;
    int parts = 0;
    size_t start = 0;
    while (start <= p.size()) {
        const size_t end = std::min(p.find('/', start), p.size());
        const std::string_view c = p.substr(start, end - start);
        if (c.empty() || c.size() > 64 || c == "." || c == ".." || ++parts > 4) return false;
        for (const char ch : c)
            if (!((ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '.' ||
                  ch == '_' || ch == '-'))
                return false;
        start = end + 1;
    }
    return true;
}

// A fresh, empty folder for this process's unpacked inputs and outputs (emptied on every call).
inline std::filesystem::path scratchFolder(const char* target) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    const fs::path dir = base / (std::string("littoral-") + target + "-" + std::to_string(getpid()));
    fs::remove_all(dir, ec);
    fs::create_directories(dir);
    return dir;
}

// Writes the sections of `bytes` as files under `dir` (which exists and is empty).
inline void unpackFolder(std::string_view bytes, const std::filesystem::path& dir, const char* wholeName) {
    namespace fs = std::filesystem;
    auto write = [&](std::string_view path, std::string_view content) {
        if (!isPackedPath(path)) return;
        const fs::path target = dir / fs::path(std::string(path));
        std::error_code ec;
        fs::create_directories(target.parent_path(), ec);
        if (ec || fs::exists(target, ec)) return;  // through a file, or over one already unpacked
        std::ofstream f(target, std::ios::binary);
        f.write(content.data(), static_cast<std::streamsize>(content.size()));
    };
    constexpr std::string_view kHeader = "--- ";
    if (bytes.substr(0, kHeader.size()) != kHeader) {
        write(wholeName, bytes);
        return;
    }
    size_t at = 0;  // start of a header line
    while (at < bytes.size()) {
        const size_t eol = bytes.find('\n', at);
        const std::string_view path =
            bytes.substr(at + kHeader.size(), (eol == std::string_view::npos ? bytes.size() : eol) - at - kHeader.size());
        if (eol == std::string_view::npos) {
            write(path, {});
            return;
        }
        const size_t next = bytes.find("\n--- ", eol);
        const size_t end = next == std::string_view::npos ? bytes.size() : next;
        // end == eol: an empty file whose header is followed at once by the next header.
        write(path, end > eol ? bytes.substr(eol + 1, end - eol - 1) : std::string_view{});
        if (next == std::string_view::npos) return;
        at = next + 1;
    }
}

}  // namespace littoral::fuzz
