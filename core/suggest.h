#pragma once
// "Did you mean" support for strict input parsing.
#include <string>
#include <string_view>
#include <vector>

namespace littoral {

// Edit distance (insert, delete, substitute, transpose adjacent: each cost 1), case-sensitive.
int editDistance(std::string_view a, std::string_view b);

// The candidate closest to `word` if it is close enough to be a plausible typo
// (distance <= max(1, len/3)), else "".
std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates);

// "a, b, c" for messages.
std::string joinList(const std::vector<std::string>& items, std::string_view sep = ", ");

}  // namespace littoral
