#include "core/text_checks.h"

#include <algorithm>

#include <fmt/format.h>

namespace littoral {

std::optional<size_t> firstInvalidUtf8(std::string_view s) {
    const auto* p = reinterpret_cast<const unsigned char*>(s.data());
    const size_t n = s.size();
    size_t i = 0;
    while (i < n) {
        const unsigned char c = p[i];
        if (c < 0x80) {
            ++i;
            continue;
        }
        size_t len;
        unsigned char lo = 0x80, hi = 0xbf;  // allowed range of the second byte
        if (c >= 0xc2 && c <= 0xdf) len = 2;
        else if (c == 0xe0) { len = 3; lo = 0xa0; }
        else if (c >= 0xe1 && c <= 0xec) len = 3;
        else if (c == 0xed) { len = 3; hi = 0x9f; }  // no UTF-16 surrogates
        else if (c >= 0xee && c <= 0xef) len = 3;
        else if (c == 0xf0) { len = 4; lo = 0x90; }
        else if (c >= 0xf1 && c <= 0xf3) len = 4;
        else if (c == 0xf4) { len = 4; hi = 0x8f; }  // nothing above U+10FFFF
        else return i;
        if (i + len > n) return i;
        if (p[i + 1] < lo || p[i + 1] > hi) return i;
        for (size_t k = 2; k < len; ++k)
            if (p[i + k] < 0x80 || p[i + k] > 0xbf) return i;
        i += len;
    }
    return std::nullopt;
}

SourceLoc locationOf(std::string_view text, size_t offset, const std::string& file) {
    offset = std::min(offset, text.size());
    int line = 1;
    size_t lineStart = 0;
    for (size_t i = 0; i < offset; ++i)
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    return SourceLoc{file, line, static_cast<int>(offset - lineStart) + 1};
}

void requireUtf8(std::string_view text, const std::string& file) {
    const auto bad = firstInvalidUtf8(text);
    if (!bad) return;
    throw InputError(locationOf(text, *bad, file),
                     fmt::format("the file is not UTF-8 text: byte 0x{:02x} does not begin a valid UTF-8 character "
                                 "(save the file as UTF-8)",
                                 static_cast<unsigned char>(text[*bad])));
}

}  // namespace littoral
