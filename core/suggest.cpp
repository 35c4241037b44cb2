#include "core/suggest.h"

#include <algorithm>
#include <numeric>

namespace littoral {

int editDistance(std::string_view a, std::string_view b) {
    std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
    std::iota(prev.begin(), prev.end(), 0);
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = static_cast<int>(i);
        for (size_t j = 1; j <= b.size(); ++j) {
            const int sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    int bestD = 1 << 30;
    for (const auto& c : candidates) {
        const int d = editDistance(word, c);
        if (d < bestD) { bestD = d; best = c; }
    }
    const int limit = std::max<int>(1, static_cast<int>(word.size()) / 3);
    if (bestD <= limit) return best;
    // A unit suffix left off ("gsd" for "gsd_m", "range" for "range_m") is a common slip.
    if (word.size() >= 3)
        for (const auto& c : candidates)
            if (c.size() > word.size() && c.compare(0, word.size(), word) == 0 && c[word.size()] == '_') return c;
    return std::string();
}

std::string joinList(const std::vector<std::string>& items, std::string_view sep) {
    std::string s;
    for (size_t i = 0; i < items.size(); ++i) {
        if (i) s += sep;
        s += items[i];
    }
    return s;
}

}  // namespace littoral
