#pragma once
// Writing and reading the renderer's images. Formats and conventions are documented for users in
// docs/outputs.md; in short:
//
//   EXR   multi-band float32 radiance, one channel per band named "L_<centre>um" (e.g.
//         "L_0.4500um"), ZIP (lossless) compression, with attributes
//           littoral:quantity  "band-averaged spectral radiance"
//           littoral:units     "W m^-2 sr^-1 um^-1"
//           littoral:channels  the channel names in band order (comma separated)
//           littoral:band_lo_um, littoral:band_hi_um  band edges in um (comma separated,
//                              shortest round-trip decimal, so they read back bit-exactly)
//         plus any caller metadata as "littoral:<key>" string attributes.
//   ENVI  "<name>.img" raw float32 little-endian band-sequential (BSQ) + "<name>.hdr" with
//         wavelength units = Micrometers, wavelength = band centres, fwhm = band widths,
//         data type 4, byte order 0, interleave bsq — what ENVI, DIRSIG tools, GDAL and
//         spectral-python load.
//   PNG   8-bit preview: bands mapped to R, G, B (or one band as grey), exposure, a power-law
//         gamma (default 0.65, the dissertation's post-processing, seed-ch05-10.md §1.10; no
//         sRGB curve on top) and an optional Gaussian sensor blur.
//   Truth EXR with float channels materialId (first hit), surfaceId (first opaque surface through
//         the interfaces), range (m), hitDepth (m); a TIFF of material ids as int32; a
//         false-colour PNG of surface ids and its CSV legend.
//
// Every writer goes through AtomicOutput: the data is written to a temporary beside the target
// and renamed only when complete, so a failed run never leaves a partial file. An unwritable
// destination is an InputError naming the path.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "render/film.h"

namespace littoral::render {

// ---- EXR --------------------------------------------------------------------------------------

// Channel names for the bands of a film: "L_" + centre in um + "um", with the fewest decimals in
// [4, 7] that make every name unique (4 decimals = 0.1 nm).
std::vector<std::string> bandChannelNames(const std::vector<Band>& bands);

// Writes `film` to `path` (extension .exr). `metadata` entries become string attributes named
// "littoral:<key>" (e.g. scene name, seed, sensor). InputError if the file cannot be written.
void writeExr(const std::filesystem::path& path, const Film& film,
              const std::map<std::string, std::string>& metadata = {});

// Reads an EXR written by writeExr back into a Film (bands from the littoral:band_* attributes,
// channels matched by name). `metadata`, if given, receives the littoral:<key> attributes with the
// prefix stripped. InputError if the file is missing, unreadable, or lacks the attributes.
Film readExr(const std::filesystem::path& path, std::map<std::string, std::string>* metadata = nullptr);

// ---- ENVI -------------------------------------------------------------------------------------

// "<dir>/<stem>.hdr" for "<dir>/<stem>.<ext>" — the name ENVI and GDAL look for first.
std::filesystem::path enviHeaderPath(const std::filesystem::path& imgPath);

// Writes `imgPath` (raw data, conventionally .img) and its header enviHeaderPath(imgPath).
// `description` goes into the header's description field (braces are replaced by parentheses,
// they would end the field). Both files are written to temporaries and renamed together at the
// end; if the header cannot be renamed the just-renamed data file is removed again. InputError if imgPath ends in .hdr or cannot be written.
// What a film's values are, for the header: the quantity and its units; and any further header
// lines (e.g. `map info` and `coordinate system string`, each ending in a newline).
inline constexpr const char* kEnviRadianceUnits = "W m^-2 sr^-1 um^-1";
struct EnviFields {
    std::string quantity = "band-averaged spectral radiance";
    std::string units = kEnviRadianceUnits;
    std::string extraHeader;
};
void writeEnvi(const std::filesystem::path& imgPath, const Film& film, const std::string& description = "",
               const EnviFields& quantity = {});

// The header of an ENVI file: every "key = value" pair, keys lower-cased, braces stripped from
// values; list values are available split by commas through list().
struct EnviHeader {
    std::map<std::string, std::string> fields;
    bool has(const std::string& key) const { return fields.count(key) != 0; }
    const std::string& get(const std::string& key) const;  // InputError if missing
    int getInt(const std::string& key) const;
    std::vector<double> getDoubles(const std::string& key) const;
    std::vector<std::string> list(const std::string& key) const;
};
// Parses header text; `fileForErrors` names the file in messages. InputError if the first line
// is not "ENVI" or a brace is left open.
EnviHeader parseEnviHeader(const std::string& text, const std::string& fileForErrors);

// Reads an ENVI float32 image (any interleave bsq/bil/bip, either byte order, with a header
// offset) into a Film. Bands come from `wavelength` and `fwhm` (micrometres; nanometres are
// converted if `wavelength units` says so): [centre - fwhm/2, centre + fwhm/2].
Film readEnvi(const std::filesystem::path& imgPath);

// ---- Previews ---------------------------------------------------------------------------------

struct PreviewOptions {
    enum class Mapping { Rgb, Grey };
    Mapping mapping = Mapping::Rgb;
    // Rgb: each channel shows the band whose centre is nearest to this wavelength (um).
    double redUm = 0.65, greenUm = 0.55, blueUm = 0.45;
    // Grey: the band nearest to this wavelength (um).
    double greyUm = 0.5;
    // Exposure: display value = L / white. If whiteLevel > 0 it is used as given
    // (W m^-2 sr^-1 um^-1); otherwise white = the `percentile` quantile of the finite values of
    // the mapped bands (the largest over R, G, B so the colour balance is kept). A white of 0
    // (black image) is replaced by 1.
    double whiteLevel = 0.0;
    double percentile = 0.99;
    // Power-law display gamma: v = clamp(L / white, 0, 1)^gamma, 8-bit = round(255 v).
    // 0.65 is the value applied to the dissertation's final images (seed-ch05-10.md §1.10).
    double gamma = 0.65;
    // Gaussian sensor blur, sigma in pixels (0 = none). Applied after gamma, as in §1.10
    // ("gamma applied, then convolved"). The dissertation's kernel (0.2909, 1, 0.2909) is
    // sigma = kDissertationBlurSigma.
    double blurSigma = 0.0;
};

// sigma (px) with exp(-1 / (2 sigma^2)) = 0.2909, the dissertation's Gaussian PSF (§1.10):
// sigma = 1 / sqrt(-2 ln 0.2909) = 0.636343 px.
inline constexpr double kDissertationBlurSigma = 0.636343;

// Writes an 8-bit PNG (RGB, or one channel for Grey). InputError on bad options (gamma <= 0,
// percentile outside (0, 1], negative sigma) or an unwritable path.
void writePngPreview(const std::filesystem::path& path, const Film& film, const PreviewOptions& options = {});

// The true-colour preview of a film whose bands span the visible (spansVisible, core/colour.h):
// each pixel's spectrum (reconstructed from its band radiances) through the CIE 1931
// colour-matching functions to XYZ, to linear sRGB (D65 white, no chromatic adaptation: a white
// surface under an equal-energy sun is shown at x = y = 1/3), exposure, the sRGB transfer curve,
// the optional blur, 8 bits. Exposure: linear / white, white = options.whiteLevel if > 0 (in the
// units of Y, which for a flat spectrum is its radiance) else the `percentile` quantile of the
// pixels' max(R, G, B). `gamma` and the band mapping are not used. InputError if the bands do not
// span the visible.
void writeTrueColourPng(const std::filesystem::path& path, const Film& film, const PreviewOptions& options = {});
// The linear sRGB of every pixel, as writeTrueColourPng computes it (before exposure).
std::vector<std::array<float, 3>> linearSrgbPixels(const Film& film);

// The display mapping used by writePngPreview for one value: round(255 clamp(v / white, 0, 1)^gamma).
uint8_t displayValue(double value, double white, double gamma);

// Normalised, symmetric sampled Gaussian: k[i] for x = i - r, r = ceil(4 sigma), k proportional to
// exp(-x^2 / (2 sigma^2)), sum k = 1. Its variance sum k x^2 equals sigma^2 within 0.2% for
// sigma >= 1 px (truncation at 4 sigma keeps 99.9% of it); below 1 px integer sampling makes it
// smaller (sigma = 0.636: 0.4004 px^2 instead of 0.4049, -1.1%). Truncation at 3 sigma would lose
// 2.7% of the variance, hence 4. sigma = 0 gives {1}. InputError if sigma < 0 or not finite.
std::vector<double> gaussianKernel(double sigma);

// Separable Gaussian blur of a single-channel width x height plane (row-major). At the borders the
// kernel is renormalised over the pixels inside the image, so a constant image stays constant.
std::vector<float> gaussianBlur(const std::vector<float>& plane, int width, int height, double sigma);
// Every band of a film, in linear radiance (use this for a physical sensor PSF before writing EXR).
Film gaussianBlur(const Film& film, double sigma);

// An ENVI float64 BSQ image of named layers (each width x height, row-major): `imgPath` and its
// header, with `band names` and `description`; float64 so that latitudes and longitudes keep
// millimetres (float32 holds only about 0.4 m of a latitude). `extraHeader`: further header lines
// (the georeferencing's map info or geo points). Written like writeEnvi.
void writeEnviLayers(const std::filesystem::path& imgPath, int width, int height, const std::vector<std::string>& names,
                     const std::vector<std::vector<double>>& layers, const std::string& description,
                     const std::string& extraHeader = "");

// ---- Truth images -----------------------------------------------------------------------------

// EXR with float32 channels "materialId" (exact for ids below 2^24), "range" (m) and "hitDepth"
// (m), attribute littoral:units. `materialNames`, if not empty, is stored as the attribute
// littoral:materials (comma separated, index = id; ',' and '%' inside a name written as %2C, %25).
void writeTruthExr(const std::filesystem::path& path, const TruthImages& truth,
                   const std::vector<std::string>& materialNames = {});
TruthImages readTruthExr(const std::filesystem::path& path);

// Single-channel int32 TIFF of material ids (-1 = nothing hit).
void writeMaterialIdTiff(const std::filesystem::path& path, const TruthImages& truth);
std::vector<int32_t> readMaterialIdTiff(const std::filesystem::path& path, int* width, int* height);

// A fixed, well-separated colour per material id (golden-ratio hue walk); id -1 is black.
void materialIdColour(int32_t id, uint8_t rgb[3]);
// False-colour 8-bit RGB PNG of the first opaque surface's material (surfaceId: through the water,
// the seabed class) using materialIdColour.
void writeMaterialIdPng(const std::filesystem::path& path, const TruthImages& truth);
// The legend of the truth images: one CSV row per id (-1 = nothing, then every material): id,
// material name, type, the PNG's red, green, blue, and the fractions of pixels whose first hit
// (materialId) and first opaque surface (surfaceId) it is.
std::string truthLegendCsv(const TruthImages& truth, const std::vector<std::string>& names,
                           const std::vector<std::string>& types);

}  // namespace littoral::render
