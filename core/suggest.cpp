#include "core/suggest.h"

#include <algorithm>

namespace littoral {

int editDistance(std::string_view a, std::string_view b) {
    // Optimal-string-alignment distance: Levenshtein plus adjacent transposition ("lwo" -> "low"
    // costs 1), the commonest typing slip.
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i)
        for (size_t j = 1; j <= m; ++j) {
            const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates) {
    std::string best;
    int bestD = 1 << 30;
    const int limit = std::max<int>(1, static_cast<int>(std::min<size_t>(word.size(), 1u << 20)) / 3);
    for (const auto& c : candidates) {
        // The distance is at least the difference in length: a candidate that cannot come within
        // the limit is not compared (a garbage "word" of kilobytes costs nothing).
        const size_t diff = word.size() > c.size() ? word.size() - c.size() : c.size() - word.size();
        if (diff > static_cast<size_t>(limit)) continue;
        const int d = editDistance(word, c);
        if (d < bestD) { bestD = d; best = c; }
    }
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
