#pragma once
// Checks on text read from files: every text input of Littoral is UTF-8 (YAML requires it, JSON
// requires it, and names end up in JSON and EXR attributes). A byte sequence that is not UTF-8 is
// reported where it is, instead of surfacing later as an exception deep inside a JSON writer.
#include <cstddef>
#include <optional>
#include <string_view>

#include "core/error.h"

namespace littoral {

// Offset of the first byte that does not start a well-formed UTF-8 sequence (RFC 3629: no
// overlong forms, no surrogates, nothing above U+10FFFF), or nullopt if `text` is valid.
std::optional<size_t> firstInvalidUtf8(std::string_view text);

// 1-based line and column (in bytes) of `offset` in `text`.
SourceLoc locationOf(std::string_view text, size_t offset, const std::string& file);

// InputError at the first invalid byte: "file:line:col: the file is not UTF-8 text: byte 0xff ...".
void requireUtf8(std::string_view text, const std::string& file);

}  // namespace littoral
