// Soundings CSV: latitude, longitude, depth per row (terrain.h, readSoundingsCsv).
#include <charconv>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "bathymetry/terrain.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/suggest.h"

namespace littoral::bathymetry {

namespace {

std::string trim(std::string_view s) {
    size_t b = 0, e = s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
    s = s.substr(b, e - b);
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
    return std::string(s);
}

// Fields of one CSV line with the 1-based column where each starts. Quoted fields may not contain
// commas (numbers never do); a quote inside a field is kept as text and then fails to parse.
std::vector<std::pair<std::string, int>> splitCsv(const std::string& line) {
    std::vector<std::pair<std::string, int>> out;
    size_t start = 0;
    while (true) {
        const size_t comma = line.find(',', start);
        const size_t end = comma == std::string::npos ? line.size() : comma;
        out.emplace_back(trim(std::string_view(line).substr(start, end - start)), int(start) + 1);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool parseDouble(const std::string& tok, double* out) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b != e && *b == '+') ++b;
    const auto res = std::from_chars(b, e, *out);
    return b != e && res.ec == std::errc() && res.ptr == e && std::isfinite(*out);
}

}  // namespace

std::vector<Sounding> parseSoundingsCsv(std::string_view text, const std::string& file) {
    std::istringstream in{std::string(text)};
    std::string line;
    int lineNo = 0;
    int colLat = -1, colLon = -1, colDepth = -1;
    size_t nFields = 0;
    std::vector<Sounding> out;
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (lineNo == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 byte-order mark
        const std::string t = trim(line);
        if (t.empty() || t[0] == '#') continue;
        const auto fields = splitCsv(line);
        if (colLat < 0) {
            // Header line: map column names (case-insensitive) to roles.
            static const std::vector<std::string> kNames = {"latitude", "lat", "longitude", "lon", "long", "depth"};
            for (size_t c = 0; c < fields.size(); ++c) {
                const std::string name = lower(fields[c].first);
                int* slot = name == "latitude" || name == "lat"                     ? &colLat
                            : name == "longitude" || name == "lon" || name == "long" ? &colLon
                            : name == "depth"                                        ? &colDepth
                                                                                     : nullptr;
                if (!slot) continue;  // extra columns (time, uncertainty, ...) are ignored
                if (*slot >= 0)
                    throw InputError(SourceLoc{file, lineNo, fields[c].second},
                                     fmt::format("column '{}' repeats an earlier column", fields[c].first));
                *slot = int(c);
            }
            if (colLat < 0 || colLon < 0 || colDepth < 0) {
                std::vector<std::string> missing;
                if (colLat < 0) missing.push_back("latitude");
                if (colLon < 0) missing.push_back("longitude");
                if (colDepth < 0) missing.push_back("depth");
                std::string hint;
                for (const auto& f : fields) {
                    const std::string m = closestMatch(lower(f.first), kNames);
                    if (!m.empty()) hint += fmt::format(" ('{}': did you mean '{}'?)", f.first, m);
                }
                throw InputError(SourceLoc{file, lineNo},
                                 fmt::format("the header must name the columns latitude, longitude, depth; missing: "
                                             "{}{}", joinList(missing), hint));
            }
            nFields = fields.size();
            continue;
        }
        if (fields.size() != nFields)
            throw InputError(SourceLoc{file, lineNo},
                             fmt::format("{} field(s); the header has {}", fields.size(), nFields));
        const auto number = [&](int col, const char* what) {
            double v;
            const auto& [tok, column] = fields[size_t(col)];
            if (tok.empty())
                throw InputError(SourceLoc{file, lineNo, column}, fmt::format("{} is missing", what));
            if (!parseDouble(tok, &v))
                throw InputError(SourceLoc{file, lineNo, column}, fmt::format("{} '{}' is not a finite number", what, tok));
            return v;
        };
        Sounding s;
        s.latDeg = number(colLat, "latitude");
        s.lonDeg = number(colLon, "longitude");
        s.depth = number(colDepth, "depth");
        s.line = lineNo;
        if (s.latDeg < -90 || s.latDeg > 90)
            throw InputError(SourceLoc{file, lineNo, fields[size_t(colLat)].second},
                             fmt::format("latitude {} is out of range; allowed [-90, 90] degrees", s.latDeg));
        if (s.lonDeg < -180 || s.lonDeg > 180)
            throw InputError(SourceLoc{file, lineNo, fields[size_t(colLon)].second},
                             fmt::format("longitude {} is out of range; allowed [-180, 180] degrees", s.lonDeg));
        if (std::abs(s.depth) > 12000)
            throw InputError(SourceLoc{file, lineNo, fields[size_t(colDepth)].second},
                             fmt::format("depth {} m is not plausible; allowed [-12000, 12000] m (positive down)",
                                         s.depth));
        out.push_back(s);
    }
    if (colLat < 0) throw InputError(SourceLoc{file}, "empty soundings file: expected a header latitude,longitude,depth");
    if (out.empty()) throw InputError(SourceLoc{file, lineNo}, "the soundings file has a header but no data rows");
    return out;
}

std::vector<Sounding> readSoundingsCsv(const std::filesystem::path& path) {
    requireRegularInputFile(path, "soundings file");
    return parseSoundingsCsv(readTextFile(path), path.string());
}


}  // namespace littoral::bathymetry
