#include "render/image_output.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/resource_limits.h"

namespace littoral::render {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRadianceUnits = "W m^-2 sr^-1 um^-1";
constexpr const char* kQuantity = "band-averaged spectral radiance";

// Band centres and widths in an ENVI header: 12 significant digits, so 0.5 - 0.4 prints as 0.1
// rather than its binary neighbour 0.09999999999999998 (a picometre is far below any band edge).
std::string headerNumber(double v) {
    std::string s = fmt::format("{:.12g}", v);
    return s;
}

// Shortest decimal that reads back to the same double (std::to_chars round-trip guarantee).
std::string shortest(double v) {
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

double parseDouble(const std::string& s, const std::string& what, const std::string& file) {
    std::string t = s;
    t.erase(0, t.find_first_not_of(" \t\r\n"));
    t.erase(t.find_last_not_of(" \t\r\n") + 1);
    double v = 0;
    auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
        throw InputError(SourceLoc{file}, what + ": '" + s + "' is not a number");
    return v;
}

std::vector<std::string> splitCommas(const std::string& s) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream is(s);
    while (std::getline(is, cur, ',')) {
        cur.erase(0, cur.find_first_not_of(" \t\r\n"));
        cur.erase(cur.find_last_not_of(" \t\r\n") + 1);
        out.push_back(cur);
    }
    if (!s.empty() && s.back() == ',') out.emplace_back();
    return out;
}

std::string joinCommas(const std::vector<std::string>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
    return s;
}

void checkFilm(const Film& film, const fs::path& path) {
    if (film.width <= 0 || film.height <= 0 || film.bands.empty() ||
        film.pixels.size() != film.pixelCount() * film.bands.size())
        throw InputError(SourceLoc{path.string()},
                         fmt::format("cannot write an empty or inconsistent film ({} x {} px, {} bands, {} values)",
                                     film.width, film.height, film.bands.size(), film.pixels.size()));
}

struct FloatImage {
    imageio::Header spec;
    std::vector<float> data;  // interleaved floats, spec.channels per pixel
};

FloatImage readFloatImage(const fs::path& path) {
    if (!fs::exists(path)) throw InputError(SourceLoc{path.string()}, "image file does not exist");
    requireRegularInputFile(path, "image file");
    noteInput(path);  // no output may replace it
    imageio::Reader in(path);
    if (!in.ok()) throw InputError(SourceLoc{path.string()}, "cannot read image: " + in.error());
    FloatImage img;
    img.spec = in.header();
    requireMemory(8.0 * double(img.spec.width) * double(img.spec.height) * double(img.spec.channels),
                  fmt::format("an image of {} x {} px x {} channels would", img.spec.width, img.spec.height,
                              img.spec.channels),
                  SourceLoc{path.string()});
    img.data.resize(static_cast<std::size_t>(img.spec.width) * img.spec.height * img.spec.channels);
    if (!in.read(img.spec.channels, imageio::PixelType::Float, img.data.data()))
        throw InputError(SourceLoc{path.string()}, "cannot read pixels: " + in.error());
    return img;
}

std::string stringAttribute(const imageio::Header& spec, const std::string& name, const fs::path& path) {
    const std::string* v = spec.stringAttribute(name);
    if (!v)
        throw InputError(SourceLoc{path.string()},
                         "attribute '" + name + "' is missing (not an image written by Littoral?)");
    return *v;
}

}  // namespace

// ---- EXR --------------------------------------------------------------------------------------

std::vector<std::string> bandChannelNames(const std::vector<Band>& bands) {
    std::vector<std::string> names(bands.size());
    for (int decimals = 4; decimals <= 7; ++decimals) {
        for (std::size_t b = 0; b < bands.size(); ++b)
            names[b] = fmt::format("L_{:.{}f}um", bands[b].center(), decimals);
        std::vector<std::string> sorted = names;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) return names;
    }
    // Centres equal to 0.1 pm: tell the bands apart by index.
    for (std::size_t b = 0; b < bands.size(); ++b) names[b] += fmt::format("_b{}", b);
    return names;
}

void writeExr(const fs::path& path, const Film& film, const std::map<std::string, std::string>& metadata) {
    checkFilm(film, path);
    const int nb = film.bandCount();
    imageio::WriteSpec spec{film.width, film.height, nb, imageio::PixelType::Float, {}, {}};
    const std::vector<std::string> names = bandChannelNames(film.bands);
    spec.channelNames = names;
    spec.attributes.emplace_back("compression", "zip");  // lossless: a round trip is bit-exact
    std::vector<std::string> lo, hi;
    for (const Band& b : film.bands) {
        lo.push_back(shortest(b.lo));
        hi.push_back(shortest(b.hi));
    }
    spec.attributes.emplace_back("littoral:quantity", kQuantity);
    spec.attributes.emplace_back("littoral:units", kRadianceUnits);
    spec.attributes.emplace_back("littoral:channels", joinCommas(names));
    spec.attributes.emplace_back("littoral:band_lo_um", joinCommas(lo));
    spec.attributes.emplace_back("littoral:band_hi_um", joinCommas(hi));
    for (const auto& [k, v] : metadata) spec.attributes.emplace_back("littoral:" + k, v);
    imageio::writeFile(path, spec, film.pixels.data());
}

Film readExr(const fs::path& path, std::map<std::string, std::string>* metadata) {
    FloatImage img = readFloatImage(path);
    const std::vector<std::string> channels = splitCommas(stringAttribute(img.spec, "littoral:channels", path));
    const std::vector<std::string> lo = splitCommas(stringAttribute(img.spec, "littoral:band_lo_um", path));
    const std::vector<std::string> hi = splitCommas(stringAttribute(img.spec, "littoral:band_hi_um", path));
    if (channels.size() != lo.size() || lo.size() != hi.size() || channels.empty())
        throw InputError(SourceLoc{path.string()}, "littoral:channels and littoral:band_* attributes disagree in length");
    std::vector<Band> bands;
    for (std::size_t b = 0; b < lo.size(); ++b)
        bands.push_back(Band{parseDouble(lo[b], "littoral:band_lo_um", path.string()),
                             parseDouble(hi[b], "littoral:band_hi_um", path.string())});
    Film film(img.spec.width, img.spec.height, bands);
    const int nc = img.spec.channels;
    for (std::size_t b = 0; b < channels.size(); ++b) {
        // The EXR library stores channels sorted by name; find each band's channel by its name.
        auto it = std::find(img.spec.channelNames.begin(), img.spec.channelNames.end(), channels[b]);
        if (it == img.spec.channelNames.end())
            throw InputError(SourceLoc{path.string()}, "channel '" + channels[b] + "' is missing");
        const std::size_t c = static_cast<std::size_t>(it - img.spec.channelNames.begin());
        for (std::size_t p = 0; p < film.pixelCount(); ++p) film.pixels[p * bands.size() + b] = img.data[p * nc + c];
    }
    if (metadata) {
        metadata->clear();
        for (const imageio::Attribute& p : img.spec.attributes) {
            const std::string& name = p.name;
            if (name.rfind("littoral:", 0) != 0 || p.kind != imageio::Attribute::Kind::String) continue;
            const std::string key = name.substr(9);
            if (key == "channels" || key == "band_lo_um" || key == "band_hi_um" || key == "units" || key == "quantity")
                continue;
            (*metadata)[key] = p.value;
        }
    }
    return film;
}

// ---- ENVI -------------------------------------------------------------------------------------

fs::path enviHeaderPath(const fs::path& imgPath) {
    fs::path h = imgPath;
    h.replace_extension(".hdr");
    return h;
}

namespace {
// An ENVI data file and its header, through atomic temporaries. Both temporaries are complete
// before either is renamed; the data goes first so that a header never names missing data. If the
// header cannot be renamed, the data just committed is removed: a .img without its .hdr (or beside
// an older, mismatched .hdr) is worse than no output. (Inside an OutputSet both are only staged
// here, and the set publishes or removes them together.)
void writeEnviPair(const fs::path& imgPath, std::string_view data, const std::string& hdr) {
    AtomicOutput imgOut(imgPath);
    AtomicOutput hdrOut(enviHeaderPath(imgPath));
    imgOut.write(data);
    hdrOut.write(hdr);
    imgOut.commit();
    try {
        hdrOut.commit();
    } catch (...) {
        if (!OutputSet::active()) {
            std::error_code ec;
            fs::remove(imgPath, ec);
        }
        throw;
    }
}
}  // namespace

void writeEnvi(const fs::path& imgPath, const Film& film, const std::string& description, const EnviFields& q) {
    checkFilm(film, imgPath);
    if (imgPath.extension() == ".hdr" || imgPath.extension() == ".HDR")
        throw InputError(SourceLoc{imgPath.string()},
                         "ENVI image path must name the data file (e.g. radiance.img), not the .hdr header");
    const int nb = film.bandCount();

    // Header (ENVI Header Format, L3Harris "ENVI Header Files" reference): byte order 0 = little
    // endian, data type 4 = 32-bit IEEE float, interleave bsq = all of band 0, then band 1, ...
    std::string desc = description.empty() ? std::string("Littoral rendered radiance") : description;
    std::replace(desc.begin(), desc.end(), '{', '(');
    std::replace(desc.begin(), desc.end(), '}', ')');
    std::vector<std::string> wl, fwhm, names = bandChannelNames(film.bands);
    for (const Band& b : film.bands) {
        wl.push_back(headerNumber(b.center()));
        fwhm.push_back(headerNumber(b.width()));
    }
    std::string hdr;
    hdr += "ENVI\n";
    hdr += "description = {" + desc + " [" + q.quantity + ", " + q.units + "]}\n";
    hdr += fmt::format("samples = {}\nlines = {}\nbands = {}\n", film.width, film.height, nb);
    hdr += "header offset = 0\nfile type = ENVI Standard\ndata type = 4\ninterleave = bsq\nbyte order = 0\n";
    hdr += "wavelength units = Micrometers\n";
    hdr += "data units = " + q.units + "\n";
    hdr += "band names = {" + [&] { std::string s; for (int b = 0; b < nb; ++b) s += (b ? ", " : "") + names[b]; return s; }() + "}\n";
    hdr += "wavelength = {" + [&] { std::string s; for (int b = 0; b < nb; ++b) s += (b ? ", " : "") + wl[b]; return s; }() + "}\n";
    hdr += "fwhm = {" + [&] { std::string s; for (int b = 0; b < nb; ++b) s += (b ? ", " : "") + fwhm[b]; return s; }() + "}\n";
    hdr += q.extraHeader;

    // Data: BSQ float32 little endian.
    std::vector<float> bsq(film.pixels.size());
    for (int b = 0; b < nb; ++b) {
        const std::vector<float> plane = film.bandPlane(b);
        std::copy(plane.begin(), plane.end(), bsq.begin() + static_cast<std::ptrdiff_t>(b) * plane.size());
    }
    if constexpr (std::endian::native == std::endian::big) {
        for (float& v : bsq) {
            uint32_t u;
            std::memcpy(&u, &v, 4);
            u = __builtin_bswap32(u);
            std::memcpy(&v, &u, 4);
        }
    }

    writeEnviPair(imgPath, std::string_view(reinterpret_cast<const char*>(bsq.data()), bsq.size() * sizeof(float)), hdr);
}

const std::string& EnviHeader::get(const std::string& key) const {
    auto it = fields.find(key);
    if (it == fields.end()) throw InputError("ENVI header: required field '" + key + "' is missing");
    return it->second;
}

int EnviHeader::getInt(const std::string& key) const {
    const std::string& s = get(key);
    int v = 0;
    auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size())
        throw InputError("ENVI header: field '" + key + "' = '" + s + "' is not an integer");
    return v;
}

std::vector<double> EnviHeader::getDoubles(const std::string& key) const {
    std::vector<double> v;
    for (const std::string& s : list(key)) v.push_back(parseDouble(s, "ENVI header field '" + key + "'", ""));
    return v;
}

std::vector<std::string> EnviHeader::list(const std::string& key) const { return splitCommas(get(key)); }

EnviHeader parseEnviHeader(const std::string& text, const std::string& file) {
    EnviHeader h;
    std::istringstream is(text);
    std::string line;
    int lineNo = 0;
    if (!std::getline(is, line) || line.substr(0, 4) != "ENVI")
        throw InputError(SourceLoc{file, 1, 1}, "not an ENVI header (the first line must be 'ENVI')");
    ++lineNo;
    while (std::getline(is, line)) {
        ++lineNo;
        const int startLine = lineNo;
        if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == ';') continue;
        const std::size_t eq = line.find('=');
        if (eq == std::string::npos)
            throw InputError(SourceLoc{file, lineNo, 1}, "expected 'key = value'");
        std::string key = line.substr(0, eq), value = line.substr(eq + 1);
        key.erase(0, key.find_first_not_of(" \t"));
        key.erase(key.find_last_not_of(" \t\r") + 1);
        std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        value.erase(0, value.find_first_not_of(" \t"));
        if (!value.empty() && value[0] == '{') {
            // A brace value may span lines: collect until the closing brace.
            while (value.find('}') == std::string::npos) {
                std::string more;
                if (!std::getline(is, more))
                    throw InputError(SourceLoc{file, startLine, 1}, "field '" + key + "': '{' is never closed");
                ++lineNo;
                value += " " + more;
            }
            value = value.substr(1, value.find('}') - 1);
        }
        value.erase(0, value.find_first_not_of(" \t\r\n"));
        value.erase(value.find_last_not_of(" \t\r\n") + 1);
        h.fields[key] = value;
    }
    return h;
}

Film readEnvi(const fs::path& imgPath) {
    const fs::path hdrPath = enviHeaderPath(imgPath);
    const std::string file = hdrPath.string();
    const EnviHeader h = parseEnviHeader(readTextFile(hdrPath), file);
    try {
        const int w = h.getInt("samples"), ht = h.getInt("lines"), nb = h.getInt("bands");
        if (h.getInt("data type") != 4)
            throw InputError(SourceLoc{file}, "data type " + h.get("data type") + " is not supported (only 4 = float32)");
        const int offset = h.has("header offset") ? h.getInt("header offset") : 0;
        const int order = h.has("byte order") ? h.getInt("byte order") : 0;
        std::string il = h.has("interleave") ? h.get("interleave") : "bsq";
        std::transform(il.begin(), il.end(), il.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (il != "bsq" && il != "bil" && il != "bip")
            throw InputError(SourceLoc{file}, "interleave '" + il + "' is not one of bsq, bil, bip");
        std::vector<double> wl = h.getDoubles("wavelength"), fw = h.getDoubles("fwhm");
        if (static_cast<int>(wl.size()) != nb || static_cast<int>(fw.size()) != nb)
            throw InputError(SourceLoc{file}, fmt::format("wavelength and fwhm need {} entries (one per band), found {} and {}",
                                                          nb, wl.size(), fw.size()));
        double scale = 1.0;  // to micrometres
        if (h.has("wavelength units")) {
            std::string u = h.get("wavelength units");
            std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
            if (u == "nanometers" || u == "nm") scale = 1e-3;
            else if (u != "micrometers" && u != "um" && u != "microns")
                throw InputError(SourceLoc{file}, "wavelength units '" + u + "' not supported (Micrometers or Nanometers)");
        }
        if (w <= 0 || ht <= 0 || nb <= 0 || offset < 0)
            throw InputError(SourceLoc{file}, fmt::format("samples, lines and bands must be positive and the header "
                                                          "offset >= 0 (found {}, {}, {}, {})", w, ht, nb, offset));
        std::vector<Band> bands;
        for (int b = 0; b < nb; ++b)
            bands.push_back(Band{scale * (wl[b] - 0.5 * fw[b]), scale * (wl[b] + 0.5 * fw[b])});
        // The data file must hold exactly what the header describes: checked (in double, so hostile
        // sizes cannot overflow) before the film is allocated.
        requireRegularInputFile(imgPath, "ENVI data file");
        std::ifstream f(imgPath, std::ios::binary);
        if (!f) throw InputError(SourceLoc{imgPath.string()}, "cannot open ENVI data file");
        f.seekg(0, std::ios::end);
        const auto size = static_cast<std::size_t>(f.tellg());
        const double expected = double(offset) + 4.0 * double(w) * double(ht) * double(nb);
        if (double(size) != expected)
            throw InputError(SourceLoc{imgPath.string()},
                             fmt::format("file holds {} bytes; the header implies {:.0f} ({} x {} x {} float32 + offset {})",
                                         size, expected, w, ht, nb, offset));
        requireMemory(8.0 * double(w) * double(ht) * double(nb),
                      fmt::format("an ENVI image of {} x {} px x {} bands would", w, ht, nb), SourceLoc{imgPath.string()});
        Film film(w, ht, bands);
        const std::size_t n = film.pixels.size();
        f.seekg(offset);
        std::vector<float> raw(n);
        f.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(n * 4));
        if (!f) throw InputError(SourceLoc{imgPath.string()}, "cannot read ENVI data");
        const bool fileBig = order == 1;
        if (fileBig != (std::endian::native == std::endian::big)) {
            for (float& v : raw) {
                uint32_t u;
                std::memcpy(&u, &v, 4);
                u = __builtin_bswap32(u);
                std::memcpy(&v, &u, 4);
            }
        }
        const std::size_t W = w, H = ht, B = nb;
        for (std::size_t y = 0; y < H; ++y)
            for (std::size_t x = 0; x < W; ++x)
                for (std::size_t b = 0; b < B; ++b) {
                    std::size_t src = 0;
                    if (il == "bsq") src = (b * H + y) * W + x;
                    else if (il == "bil") src = (y * B + b) * W + x;
                    else src = (y * W + x) * B + b;
                    film.pixels[(y * W + x) * B + b] = raw[src];
                }
        return film;
    } catch (const InputError& e) {
        if (!e.where().file.empty()) throw;
        throw InputError(SourceLoc{file}, e.message());
    }
}

// ---- Previews ---------------------------------------------------------------------------------

uint8_t displayValue(double value, double white, double gamma) {
    double v = value / white;
    if (!(v > 0.0)) v = 0.0;  // also maps NaN to black
    if (v > 1.0) v = 1.0;
    return static_cast<uint8_t>(std::lround(255.0 * std::pow(v, gamma)));
}

std::vector<double> gaussianKernel(double sigma) {
    if (!std::isfinite(sigma) || sigma < 0.0)
        throw InputError(fmt::format("Gaussian blur sigma {} px is invalid (must be finite and >= 0)", sigma));
    if (sigma == 0.0) return {1.0};
    // Truncated at 4 sigma (rounded up to whole pixels). At 3 sigma the dropped tails hold only
    // 0.27% of the weight but 2.7% of the variance (1 - 6 phi(3) / (2 Phi(3) - 1) = 0.973), so
    // the blur would be visibly narrower than asked; at 4 sigma they hold 6e-5 of the weight and
    // 0.1% of the variance. For the dissertation's sigma = 0.636 px this adds taps of 1.5e-5.
    const int r = static_cast<int>(std::ceil(4.0 * sigma));
    std::vector<double> k(2 * r + 1);
    double sum = 0.0;
    for (int i = -r; i <= r; ++i) sum += k[i + r] = std::exp(-(double(i) * i) / (2.0 * sigma * sigma));
    for (double& v : k) v /= sum;
    return k;
}

std::vector<float> gaussianBlur(const std::vector<float>& plane, int width, int height, double sigma) {
    LITTORAL_CHECK_EQ(plane.size(), static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    const std::vector<double> k = gaussianKernel(sigma);
    const int r = static_cast<int>(k.size() / 2);
    if (r == 0) return plane;
    // Separable: rows then columns, accumulating in double. Border: renormalise over the taps
    // that fall inside the image.
    auto pass = [&](const std::vector<float>& in, bool horizontal) {
        std::vector<float> out(in.size());
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                double acc = 0.0, wsum = 0.0;
                for (int i = -r; i <= r; ++i) {
                    const int xx = horizontal ? x + i : x, yy = horizontal ? y : y + i;
                    if (xx < 0 || xx >= width || yy < 0 || yy >= height) continue;
                    acc += k[i + r] * in[static_cast<std::size_t>(yy) * width + xx];
                    wsum += k[i + r];
                }
                out[static_cast<std::size_t>(y) * width + x] = static_cast<float>(acc / wsum);
            }
        return out;
    };
    return pass(pass(plane, true), false);
}

Film gaussianBlur(const Film& film, double sigma) {
    Film out = film;
    for (int b = 0; b < film.bandCount(); ++b)
        out.setBandPlane(b, gaussianBlur(film.bandPlane(b), film.width, film.height, sigma));
    return out;
}

void writePngPreview(const fs::path& path, const Film& film, const PreviewOptions& o) {
    checkFilm(film, path);
    if (!(o.gamma > 0.0) || !std::isfinite(o.gamma))
        throw InputError(SourceLoc{path.string()}, fmt::format("preview gamma {} must be positive", o.gamma));
    if (!(o.percentile > 0.0 && o.percentile <= 1.0))
        throw InputError(SourceLoc{path.string()}, fmt::format("preview percentile {} must be in (0, 1]", o.percentile));
    if (!(o.whiteLevel >= 0.0) || !std::isfinite(o.whiteLevel))
        throw InputError(SourceLoc{path.string()}, fmt::format("preview white level {} must be >= 0", o.whiteLevel));
    if (!(o.blurSigma >= 0.0) || !std::isfinite(o.blurSigma))
        throw InputError(SourceLoc{path.string()}, fmt::format("preview blur sigma {} px must be >= 0", o.blurSigma));

    std::vector<int> src;
    if (o.mapping == PreviewOptions::Mapping::Rgb)
        src = {film.nearestBand(o.redUm), film.nearestBand(o.greenUm), film.nearestBand(o.blueUm)};
    else
        src = {film.nearestBand(o.greyUm)};
    double white = o.whiteLevel;
    if (white == 0.0) {
        for (int b : src) white = std::max(white, bandQuantile(film, b, o.percentile));
        if (!(white > 0.0)) white = 1.0;
    }
    const int nc = static_cast<int>(src.size());
    const std::size_t np = film.pixelCount();
    // Display planes in [0, 1] after gamma, then the optional blur (§1.10 order), then 8 bits.
    std::vector<uint8_t> bytes(np * nc);
    for (int c = 0; c < nc; ++c) {
        const std::vector<float> plane = film.bandPlane(src[c]);
        std::vector<float> disp(np);
        for (std::size_t p = 0; p < np; ++p) {
            double v = plane[p] / white;
            if (!(v > 0.0)) v = 0.0;
            if (v > 1.0) v = 1.0;
            disp[p] = static_cast<float>(std::pow(v, o.gamma));
        }
        if (o.blurSigma > 0.0) disp = gaussianBlur(disp, film.width, film.height, o.blurSigma);
        for (std::size_t p = 0; p < np; ++p)
            bytes[p * nc + c] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(static_cast<double>(disp[p]), 0.0, 1.0)));
    }
    imageio::WriteSpec spec{film.width, film.height, nc, imageio::PixelType::UInt8, {}, {}};
    spec.attributes.emplace_back("Software", "Littoral");
    spec.attributes.emplace_back("ImageDescription",
                   fmt::format("Littoral preview: white = {} {}, gamma = {}, blur sigma = {} px", white, kRadianceUnits,
                               o.gamma, o.blurSigma));
    imageio::writeFile(path, spec, bytes.data());
}

std::vector<std::array<float, 3>> linearSrgbPixels(const Film& film) {
    const std::vector<Xyz> w = xyzBandWeights(film.bands);
    const std::size_t nb = film.bands.size();
    std::vector<std::array<float, 3>> rgb(film.pixelCount());
    for (std::size_t p = 0; p < rgb.size(); ++p) {
        Xyz c;
        for (std::size_t b = 0; b < nb; ++b) {
            const double v = film.pixels[p * nb + b];
            if (!std::isfinite(v)) continue;
            c.x += w[b].x * v, c.y += w[b].y * v, c.z += w[b].z * v;
        }
        const std::array<double, 3> l = xyzToLinearSrgb(c);
        rgb[p] = {static_cast<float>(l[0]), static_cast<float>(l[1]), static_cast<float>(l[2])};
    }
    return rgb;
}

void writeTrueColourPng(const fs::path& path, const Film& film, const PreviewOptions& o) {
    checkFilm(film, path);
    if (!spansVisible(film.bands))
        throw InputError(SourceLoc{path.string()},
                         fmt::format("a true-colour preview needs at least 3 bands whose range holds {:.0f} % of each "
                                     "CIE colour-matching function (these {} band(s) hold {:.1f} %)",
                                     100 * kVisibleCoverage, film.bands.size(), 100 * visibleCoverage(film.bands)));
    const std::vector<std::array<float, 3>> rgb = linearSrgbPixels(film);
    Film peak(film.width, film.height, {Band{}});  // max(R, G, B): the exposure keeps hues unclipped
    for (std::size_t p = 0; p < rgb.size(); ++p) peak.pixels[p] = std::max({rgb[p][0], rgb[p][1], rgb[p][2]});
    double white = o.whiteLevel;
    if (white == 0.0) white = bandQuantile(peak, 0, o.percentile);
    if (!(white > 0.0)) white = 1.0;
    const std::size_t np = film.pixelCount();
    std::vector<uint8_t> bytes(np * 3);
    for (int c = 0; c < 3; ++c) {
        std::vector<float> disp(np);
        for (std::size_t p = 0; p < np; ++p) disp[p] = static_cast<float>(srgbEncode(rgb[p][c] / white));
        if (o.blurSigma > 0.0) disp = gaussianBlur(disp, film.width, film.height, o.blurSigma);
        for (std::size_t p = 0; p < np; ++p)
            bytes[p * 3 + c] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(static_cast<double>(disp[p]), 0.0, 1.0)));
    }
    imageio::WriteSpec spec{film.width, film.height, 3, imageio::PixelType::UInt8, {}, {}};
    spec.attributes.emplace_back("Software", "Littoral");
    spec.attributes.emplace_back("oiio:ColorSpace", "sRGB");
    spec.attributes.emplace_back("ImageDescription",
                   fmt::format("Littoral true-colour preview: CIE 1931 XYZ of the band radiances, sRGB (D65, no "
                               "chromatic adaptation); linear white = {} {} (as Y of a flat spectrum), blur sigma = {} px",
                               white, kRadianceUnits, o.blurSigma));
    imageio::writeFile(path, spec, bytes.data());
}

void writeEnviLayers(const fs::path& imgPath, int width, int height, const std::vector<std::string>& names,
                     const std::vector<std::vector<double>>& layers, const std::string& description,
                     const std::string& extraHeader) {
    const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    LITTORAL_CHECK(width > 0 && height > 0 && names.size() == layers.size() && !names.empty());
    std::string desc = description;
    std::replace(desc.begin(), desc.end(), '{', '(');
    std::replace(desc.begin(), desc.end(), '}', ')');
    std::string hdr = "ENVI\ndescription = {" + desc + "}\n";
    hdr += fmt::format("samples = {}\nlines = {}\nbands = {}\n", width, height, names.size());
    // data type 5 = 64-bit IEEE float; byte order 0 = little endian.
    hdr += "header offset = 0\nfile type = ENVI Standard\ndata type = 5\ninterleave = bsq\nbyte order = 0\n";
    hdr += "band names = {" + joinCommas(names) + "}\n";
    hdr += extraHeader;
    std::string data;
    data.reserve(n * names.size() * sizeof(double));
    for (const std::vector<double>& layer : layers) {
        LITTORAL_CHECK_EQ(layer.size(), n);
        for (double v : layer) {
            uint64_t u;
            std::memcpy(&u, &v, 8);
            if constexpr (std::endian::native == std::endian::big) u = __builtin_bswap64(u);
            data.append(reinterpret_cast<const char*>(&u), 8);
        }
    }
    writeEnviPair(imgPath, data, hdr);
}

// ---- Truth images -----------------------------------------------------------------------------

namespace {
void checkTruth(const TruthImages& t, const fs::path& path) {
    const std::size_t n = static_cast<std::size_t>(std::max(t.width, 0)) * static_cast<std::size_t>(std::max(t.height, 0));
    if (t.width <= 0 || t.height <= 0 || t.materialId.size() != n || t.range.size() != n || t.hitDepth.size() != n)
        throw InputError(SourceLoc{path.string()},
                         fmt::format("cannot write empty or inconsistent truth images ({} x {} px)", t.width, t.height));
}
}  // namespace

void writeTruthExr(const fs::path& path, const TruthImages& t, const std::vector<std::string>& materialNames) {
    checkTruth(t, path);
    const std::size_t n = t.materialId.size();
    std::vector<float> data(n * 4);
    for (std::size_t p = 0; p < n; ++p) {
        // float holds such integers exactly
        LITTORAL_CHECK(std::abs(t.materialId[p]) < (1 << 24) && std::abs(t.surfaceId[p]) < (1 << 24));
        data[4 * p + 0] = static_cast<float>(t.materialId[p]);
        data[4 * p + 1] = static_cast<float>(t.surfaceId[p]);
        data[4 * p + 2] = t.range[p];
        data[4 * p + 3] = t.hitDepth[p];
    }
    imageio::WriteSpec spec{t.width, t.height, 4, imageio::PixelType::Float, {}, {}};
    spec.channelNames = {"materialId", "surfaceId", "range", "hitDepth"};
    spec.attributes.emplace_back("compression", "zip");
    spec.attributes.emplace_back("littoral:quantity", "first-hit truth along each pixel's centre ray, and the first opaque surface "
                                        "through the interfaces");
    spec.attributes.emplace_back("littoral:units", "materialId: index of the first hit (-1 = none); surfaceId: index of the first "
                                     "opaque surface through refraction (-1 = none); range: m (+inf = none); hitDepth: m "
                                     "below z = 0 of that surface (NaN = none)");
    if (!materialNames.empty()) {
        // Comma separated; a comma or percent sign inside a name is percent-encoded (%2C, %25).
        std::vector<std::string> escaped;
        for (const std::string& m : materialNames) {
            std::string e;
            for (char ch : m) e += ch == ',' ? std::string("%2C") : ch == '%' ? std::string("%25") : std::string(1, ch);
            escaped.push_back(e);
        }
        spec.attributes.emplace_back("littoral:materials", joinCommas(escaped));
    }
    imageio::writeFile(path, spec, data.data());
}

TruthImages readTruthExr(const fs::path& path) {
    FloatImage img = readFloatImage(path);
    TruthImages t(img.spec.width, img.spec.height);
    int idx[3];
    const char* names[3] = {"materialId", "range", "hitDepth"};
    for (int c = 0; c < 3; ++c) {
        auto it = std::find(img.spec.channelNames.begin(), img.spec.channelNames.end(), names[c]);
        if (it == img.spec.channelNames.end())
            throw InputError(SourceLoc{path.string()}, std::string("truth channel '") + names[c] + "' is missing");
        idx[c] = static_cast<int>(it - img.spec.channelNames.begin());
    }
    const int nc = img.spec.channels;
    auto sid = std::find(img.spec.channelNames.begin(), img.spec.channelNames.end(), "surfaceId");
    const int surface = sid == img.spec.channelNames.end() ? -1 : static_cast<int>(sid - img.spec.channelNames.begin());
    for (std::size_t p = 0; p < t.materialId.size(); ++p) {
        t.materialId[p] = static_cast<int32_t>(img.data[p * nc + idx[0]]);
        if (surface >= 0) t.surfaceId[p] = static_cast<int32_t>(img.data[p * nc + surface]);
        t.range[p] = img.data[p * nc + idx[1]];
        t.hitDepth[p] = img.data[p * nc + idx[2]];
    }
    return t;
}

void writeMaterialIdTiff(const fs::path& path, const TruthImages& t) {
    checkTruth(t, path);
    imageio::WriteSpec spec{t.width, t.height, 1, imageio::PixelType::Int32, {}, {}};
    spec.channelNames = {"materialId"};
    spec.attributes.emplace_back("compression", "zip");
    spec.attributes.emplace_back("ImageDescription", "Littoral material id per pixel (index into the IR materials, -1 = nothing hit)");
    imageio::writeFile(path, spec, t.materialId.data());
}

std::vector<int32_t> readMaterialIdTiff(const fs::path& path, int* width, int* height) {
    if (!fs::exists(path)) throw InputError(SourceLoc{path.string()}, "image file does not exist");
    noteInput(path);  // no output may replace it
    imageio::Reader in(path);
    if (!in.ok()) throw InputError(SourceLoc{path.string()}, "cannot read image: " + in.error());
    const imageio::Header spec = in.header();
    if (spec.channels != 1)
        throw InputError(SourceLoc{path.string()}, fmt::format("expected one channel, found {}", spec.channels));
    std::vector<int32_t> ids(static_cast<std::size_t>(spec.width) * spec.height);
    if (!in.read(1, imageio::PixelType::Int32, ids.data()))
        throw InputError(SourceLoc{path.string()}, "cannot read pixels: " + in.error());
    if (width) *width = spec.width;
    if (height) *height = spec.height;
    return ids;
}

void materialIdColour(int32_t id, uint8_t rgb[3]) {
    if (id < 0) {
        rgb[0] = rgb[1] = rgb[2] = 0;
        return;
    }
    // Hue advances by the golden ratio conjugate per id, so consecutive ids get far-apart hues;
    // saturation and value alternate in two levels to separate ids whose hues come close.
    const double h = std::fmod(0.1 + 0.618033988749895 * id, 1.0) * 6.0;
    const double s = (id % 2) ? 0.65 : 0.9, v = ((id / 2) % 2) ? 0.8 : 1.0;
    const int sector = static_cast<int>(h) % 6;
    const double f = h - std::floor(h);
    const double p = v * (1 - s), q = v * (1 - s * f), tt = v * (1 - s * (1 - f));
    double r = 0, g = 0, b = 0;
    switch (sector) {
        case 0: r = v; g = tt; b = p; break;
        case 1: r = q; g = v; b = p; break;
        case 2: r = p; g = v; b = tt; break;
        case 3: r = p; g = q; b = v; break;
        case 4: r = tt; g = p; b = v; break;
        default: r = v; g = p; b = q; break;
    }
    rgb[0] = static_cast<uint8_t>(std::lround(255 * r));
    rgb[1] = static_cast<uint8_t>(std::lround(255 * g));
    rgb[2] = static_cast<uint8_t>(std::lround(255 * b));
}

void writeMaterialIdPng(const fs::path& path, const TruthImages& t) {
    checkTruth(t, path);
    std::vector<uint8_t> bytes(t.surfaceId.size() * 3);
    for (std::size_t p = 0; p < t.surfaceId.size(); ++p) materialIdColour(t.surfaceId[p], &bytes[3 * p]);
    imageio::WriteSpec spec{t.width, t.height, 3, imageio::PixelType::UInt8, {}, {}};
    spec.attributes.emplace_back("Software", "Littoral");
    spec.attributes.emplace_back("ImageDescription", "Littoral material of the first opaque surface seen through the water, false "
                                       "colour (black = nothing); the legend is NAME_legend.csv");
    imageio::writeFile(path, spec, bytes.data());
}

std::string truthLegendCsv(const TruthImages& t, const std::vector<std::string>& names,
                           const std::vector<std::string>& types) {
    LITTORAL_CHECK_EQ(names.size(), types.size());
    std::vector<int64_t> first(names.size() + 1, 0), surface(names.size() + 1, 0);  // [0] = id -1
    for (std::size_t p = 0; p < t.materialId.size(); ++p) {
        ++first[static_cast<std::size_t>(t.materialId[p] + 1)];
        ++surface[static_cast<std::size_t>(t.surfaceId[p] + 1)];
    }
    const double np = static_cast<double>(t.materialId.size());
    std::string csv = "id,material,type,red,green,blue,first_hit_fraction,surface_fraction\n";
    for (int id = -1; id < static_cast<int>(names.size()); ++id) {
        uint8_t rgb[3];
        materialIdColour(id, rgb);
        const std::string name = id < 0 ? "(nothing)" : names[static_cast<std::size_t>(id)];
        const std::string type = id < 0 ? "" : types[static_cast<std::size_t>(id)];
        const bool quote = name.find_first_of(",\"") != std::string::npos;
        std::string q;
        for (char ch : name) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        csv += fmt::format("{},{},{},{},{},{},{:.6f},{:.6f}\n", id, quote ? "\"" + q + "\"" : name, type, rgb[0], rgb[1],
                           rgb[2], static_cast<double>(first[static_cast<std::size_t>(id + 1)]) / np,
                           static_cast<double>(surface[static_cast<std::size_t>(id + 1)]) / np);
    }
    return csv;
}

}  // namespace littoral::render
