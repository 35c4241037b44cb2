#include "scenegen/water_constituents.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/suggest.h"

namespace littoral::scenegen {

namespace {

// Pope and Fry (1997), pure water absorption (m^-1) at 380, 382.5, ..., 700 nm.
constexpr double kPopeFry[] = {
    0.01137, 0.01044, 0.00941, 0.00917, 0.00851, 0.00829, 0.00813, 0.00775, 0.00663, 0.00579, 0.0053, 0.00503,
    0.00473, 0.00452, 0.00444, 0.00442, 0.00454, 0.00474, 0.00478, 0.00482, 0.00495, 0.00504, 0.0053, 0.0058,
    0.00635, 0.00696, 0.00751, 0.0083, 0.00922, 0.00969, 0.00962, 0.00957, 0.00979, 0.01005, 0.01011, 0.0102,
    0.0106, 0.0109, 0.0114, 0.0121, 0.0127, 0.0131, 0.0136, 0.0144, 0.015, 0.0162, 0.0173, 0.0191, 0.0204,
    0.0228, 0.0256, 0.028, 0.0325, 0.0372, 0.0396, 0.0399, 0.0409, 0.0416, 0.0417, 0.0428, 0.0434, 0.0447,
    0.0452, 0.0466, 0.0474, 0.0489, 0.0511, 0.0537, 0.0565, 0.0593, 0.0596, 0.0606, 0.0619, 0.064, 0.0642,
    0.0672, 0.0695, 0.0733, 0.0772, 0.0836, 0.0896, 0.0989, 0.11, 0.122, 0.1351, 0.1516, 0.1672, 0.1925,
    0.2224, 0.247, 0.2577, 0.2629, 0.2644, 0.2665, 0.2678, 0.2707, 0.2755, 0.281, 0.2834, 0.2904, 0.2916,
    0.2995, 0.3012, 0.3077, 0.3108, 0.322, 0.325, 0.335, 0.34, 0.358, 0.371, 0.393, 0.41, 0.424, 0.429, 0.436,
    0.439, 0.448, 0.448, 0.461, 0.465, 0.478, 0.486, 0.502, 0.516, 0.538, 0.559, 0.592, 0.624,
};
constexpr int kPopeFryCount = static_cast<int>(sizeof(kPopeFry) / sizeof(kPopeFry[0]));
static_assert(kPopeFryCount == 129, "380-700 nm every 2.5 nm");

// Bricaud et al. (1998), phytoplankton absorption a_ph = A Chl^E: wavelength (nm), A (m^2 mg^-1
// at Chl = 1 mg m^-3), E.
struct BricaudRow {
    double nm, a, e;
};
constexpr BricaudRow kBricaud[] = {
    {400, 0.0240515, 0.687735}, {402, 0.0248166, 0.688701}, {404, 0.0255988, 0.686988},
    {406, 0.0265531, 0.686489}, {408, 0.027581, 0.685867}, {410, 0.0287352, 0.683414},
    {412, 0.029655, 0.681803}, {414, 0.0305583, 0.676545}, {416, 0.0314484, 0.673274},
    {418, 0.0321773, 0.669766}, {420, 0.032834, 0.666439}, {422, 0.0332152, 0.658423},
    {424, 0.0335617, 0.651111}, {426, 0.03421, 0.647587}, {428, 0.0349403, 0.645798},
    {430, 0.0359357, 0.647841}, {432, 0.0364578, 0.642507}, {434, 0.0368482, 0.636881},
    {436, 0.03728, 0.631562}, {438, 0.0375477, 0.627259}, {440, 0.037824, 0.626633},
    {442, 0.0374489, 0.619551}, {444, 0.0367647, 0.610037}, {446, 0.0360619, 0.603779},
    {448, 0.0353548, 0.59799}, {450, 0.0349905, 0.599299}, {452, 0.0344152, 0.596627},
    {454, 0.033776, 0.592427}, {456, 0.0333615, 0.592019}, {458, 0.0329797, 0.591989},
    {460, 0.0328336, 0.596114}, {462, 0.0324544, 0.596732}, {464, 0.0320227, 0.595636},
    {466, 0.0316415, 0.595456}, {468, 0.0312368, 0.595546}, {470, 0.0309118, 0.597029},
    {472, 0.0302978, 0.594761}, {474, 0.0296197, 0.590984}, {476, 0.0290199, 0.588654},
    {478, 0.0284796, 0.586772}, {480, 0.0280519, 0.589011}, {482, 0.0275088, 0.58888},
    {484, 0.0269574, 0.590095}, {486, 0.0264469, 0.59367}, {488, 0.0258937, 0.598583},
    {490, 0.0253719, 0.607395}, {492, 0.0246401, 0.613784}, {494, 0.0237919, 0.620913},
    {496, 0.0229018, 0.629698}, {498, 0.021947, 0.639874}, {500, 0.0209906, 0.652915},
    {502, 0.0199717, 0.665039}, {504, 0.0189531, 0.677825}, {506, 0.0179645, 0.691096},
    {508, 0.0170429, 0.704961}, {510, 0.0161767, 0.721246}, {512, 0.0153331, 0.73487},
    {514, 0.0145366, 0.748164}, {516, 0.0138247, 0.763636}, {518, 0.013169, 0.77829},
    {520, 0.0126114, 0.793886}, {522, 0.0120616, 0.806798}, {524, 0.0115413, 0.81826},
    {526, 0.0111019, 0.827539}, {528, 0.0106782, 0.837822}, {530, 0.0102702, 0.850035},
    {532, 0.00986676, 0.864371}, {534, 0.00945034, 0.876105}, {536, 0.00913158, 0.883664},
    {538, 0.00879997, 0.891514}, {540, 0.00847894, 0.9036376}, {542, 0.00822898, 0.9059528},
    {544, 0.00791535, 0.9135778}, {546, 0.00758758, 0.9210046}, {548, 0.00730458, 0.9262056},
    {550, 0.00702755, 0.9311673}, {552, 0.00668777, 0.9389103}, {554, 0.00637847, 0.9444716},
    {556, 0.00611841, 0.9434622}, {558, 0.00586209, 0.9438741}, {560, 0.00567919, 0.9345194},
    {562, 0.00545193, 0.9381874}, {564, 0.00528849, 0.9308322}, {566, 0.00516659, 0.9308692},
    {568, 0.0050977, 0.9251119}, {570, 0.00498617, 0.9298118}, {572, 0.00498028, 0.9192422},
    {574, 0.00498036, 0.9105802}, {576, 0.0050036, 0.9000773}, {578, 0.00500971, 0.9019533},
    {580, 0.00508712, 0.893336}, {582, 0.00512157, 0.893499}, {584, 0.00524069, 0.876441},
    {586, 0.00531486, 0.869708}, {588, 0.00535469, 0.863694}, {590, 0.00539004, 0.858931},
    {592, 0.00541207, 0.852832}, {594, 0.00536942, 0.848167}, {596, 0.00531406, 0.844824},
    {598, 0.00527335, 0.838523}, {600, 0.00521658, 0.841018}, {602, 0.00523014, 0.840204},
    {604, 0.00524094, 0.840631}, {606, 0.00526082, 0.849918}, {608, 0.0053529, 0.850798},
    {610, 0.00548048, 0.854777}, {612, 0.00559993, 0.859506}, {614, 0.00572303, 0.865122},
    {616, 0.00587009, 0.866815}, {618, 0.00598422, 0.868395}, {620, 0.00608558, 0.870417},
    {622, 0.00618479, 0.869253}, {624, 0.00624575, 0.869809}, {626, 0.00636318, 0.866418},
    {628, 0.00646156, 0.866135}, {630, 0.00662103, 0.86376}, {632, 0.00672107, 0.866048},
    {634, 0.00685261, 0.863431}, {636, 0.00696853, 0.859451}, {638, 0.00703712, 0.857394},
    {640, 0.00713341, 0.852402}, {642, 0.00725082, 0.840696}, {644, 0.00733407, 0.834597},
    {646, 0.00743778, 0.825136}, {648, 0.0075651, 0.821646}, {650, 0.00777566, 0.815461},
    {652, 0.00801624, 0.818002}, {654, 0.00842427, 0.815772}, {656, 0.00903046, 0.815501},
    {658, 0.00980814, 0.820503}, {660, 0.0108322, 0.823337}, {662, 0.0120323, 0.826962},
    {664, 0.0134507, 0.82256}, {666, 0.014952, 0.817174}, {668, 0.0162698, 0.814107},
    {670, 0.017388, 0.813791}, {672, 0.0180721, 0.811783}, {674, 0.018238, 0.813274},
    {676, 0.0179744, 0.816196}, {678, 0.0172436, 0.82082}, {680, 0.016057, 0.8284},
    {682, 0.0143849, 0.843146}, {684, 0.0124842, 0.861145}, {686, 0.010429, 0.882873},
    {688, 0.00854401, 0.9022806}, {690, 0.0068551, 0.9255264}, {692, 0.00548901, 0.9417016},
    {694, 0.00438385, 0.967679}, {696, 0.00359814, 0.9821707}, {698, 0.00298877, 0.999734295},
    {700, 0.00248126, 1.028608},
};
constexpr int kBricaudCount = static_cast<int>(sizeof(kBricaud) / sizeof(kBricaud[0]));
static_assert(kBricaudCount == 151, "400-700 nm every 2 nm");

// Position on a uniform grid (index units), snapped to the node when within rounding of it, so a
// tabulated wavelength returns its table entry exactly.
double gridPosition(double wlNm, double firstNm, double stepNm, int count) {
    double x = (wlNm - firstNm) / stepNm;
    if (std::abs(x - std::round(x)) < 1e-9) x = std::round(x);
    return std::clamp(x, 0.0, count - 1.0);
}

std::string rangeText(double lo, double hi) { return fmt::format("{:.3f}-{:.3f} um", lo, hi); }

void checkWavelength(double wl, double lo, double hi, const char* what) {
    constexpr double eps = 1e-9;
    if (!std::isfinite(wl) || wl < lo - eps || wl > hi + eps)
        throw InputError(fmt::format("{} is tabulated over {}; {} um is outside it", what, rangeText(lo, hi), wl));
}

void checkNonNegative(double v, const char* what, const char* unit) {
    if (!std::isfinite(v) || v < 0)
        throw InputError(fmt::format("water constituents: {} = {} {} must be finite and >= 0", what, v, unit));
}

void checkPositiveWavelength(double wl) {
    if (!std::isfinite(wl) || wl <= 0) throw InputError(fmt::format("water constituents: wavelength {} um is not positive", wl));
}

// Sum of spectra on the union of their tabulated wavelengths (within the range they all cover).
Spectrum sumSpectra(const std::vector<const Spectrum*>& parts, const std::string& what) {
    double constantSum = 0, lo = 0, hi = INFINITY;
    std::vector<double> grid;
    for (const Spectrum* s : parts) {
        if (s->isConstant()) {
            constantSum += s->at(1.0);
            continue;
        }
        lo = std::max(lo, s->minWavelength());
        hi = std::min(hi, s->maxWavelength());
        grid.insert(grid.end(), s->wavelengths().begin(), s->wavelengths().end());
    }
    if (grid.empty()) return Spectrum::constant(constantSum);
    if (lo > hi) throw InputError(fmt::format("{}: the components' wavelength ranges do not overlap", what));
    std::sort(grid.begin(), grid.end());
    std::vector<double> wl, v;
    for (double w : grid) {
        if (w < lo - 1e-12 || w > hi + 1e-12) continue;
        if (!wl.empty() && w - wl.back() < 1e-12) continue;
        wl.push_back(w);
        double sum = 0;
        for (const Spectrum* s : parts) sum += s->at(w);
        v.push_back(sum);
    }
    return Spectrum::tabulated(std::move(wl), std::move(v), what);
}

}  // namespace

// ---- single constituents ----------------------------------------------------------------------

Spectrum pureWaterAbsorptionTable() {
    std::vector<double> wl(kPopeFryCount), v(kPopeFryCount);
    for (int i = 0; i < kPopeFryCount; ++i) {
        wl[static_cast<size_t>(i)] = (380.0 + 2.5 * i) / 1000.0;
        v[static_cast<size_t>(i)] = kPopeFry[i];
    }
    return Spectrum::tabulated(std::move(wl), std::move(v), "pure-water absorption (Pope and Fry 1997)");
}

double pureWaterAbsorption(double wl) {
    checkWavelength(wl, kPopeFryMinUm, kPopeFryMaxUm, "pure-water absorption (Pope and Fry 1997)");
    const double x = gridPosition(wl * 1000.0, 380.0, 2.5, kPopeFryCount);
    const int i = std::min(static_cast<int>(x), kPopeFryCount - 2);
    return kPopeFry[i] + (x - i) * (kPopeFry[i + 1] - kPopeFry[i]);
}

// Morel (1974): beta_w(90 deg) ~ lambda^-4.32 and b_w = 16.06 beta_w(90 deg); b_w(500 nm) =
// 0.00222 m^-1 for pure water and 0.00288 m^-1 (x 1.30) for pure sea water.
double pureWaterScattering(double wl, WaterKind kind) {
    checkPositiveWavelength(wl);
    const double b500 = kind == WaterKind::Sea ? 0.00288 : 0.00222;
    return b500 * std::pow(wl / 0.500, -4.32);
}

double phytoplanktonAbsorption(double wl, double chl) {
    checkWavelength(wl, kBricaudMinUm, kBricaudMaxUm, "phytoplankton absorption (Bricaud et al. 1998)");
    checkNonNegative(chl, "chlorophyll concentration", "mg m^-3");
    if (chl == 0) return 0.0;
    const double x = gridPosition(wl * 1000.0, 400.0, 2.0, kBricaudCount);
    const int i = std::min(static_cast<int>(x), kBricaudCount - 2);
    const double f = x - i;
    const double a = kBricaud[i].a + f * (kBricaud[i + 1].a - kBricaud[i].a);
    const double e = kBricaud[i].e + f * (kBricaud[i + 1].e - kBricaud[i].e);
    return a * std::pow(chl, e);
}

// Gordon and Morel (1983): b_p(550 nm) = 0.30 Chl^0.62 m^-1, b_p ~ 1/lambda.
double phytoplanktonScattering(double wl, double chl) {
    checkPositiveWavelength(wl);
    checkNonNegative(chl, "chlorophyll concentration", "mg m^-3");
    return 0.30 * std::pow(chl, 0.62) * (0.550 / wl);
}

double mineralAbsorption(double wl, double spm, const MineralModel& m) {
    checkPositiveWavelength(wl);
    checkNonNegative(spm, "sediment concentration", "g m^-3");
    return spm * m.specificAbsorption443 * std::exp(-m.absorptionSlope * (wl * 1000.0 - 443.0));
}

double mineralScattering(double wl, double spm, const MineralModel& m) {
    checkPositiveWavelength(wl);
    checkNonNegative(spm, "sediment concentration", "g m^-3");
    return spm * m.specificScattering555 * std::pow(0.555 / wl, m.scatteringExponent);
}

// Bricaud et al. (1981).
double cdomAbsorption(double wl, double a440, double slope) {
    checkPositiveWavelength(wl);
    checkNonNegative(a440, "CDOM absorption at 440 nm", "m^-1");
    checkNonNegative(slope, "CDOM spectral slope", "nm^-1");
    return a440 * std::exp(-slope * (wl * 1000.0 - 440.0));
}

// ---- composition ----------------------------------------------------------------------------

WaterIops computeIops(const WaterComposition& c, const std::vector<double>& wls, const std::string& name) {
    checkNonNegative(c.chlorophyllMgM3, "chlorophyll concentration", "mg m^-3");
    checkNonNegative(c.sedimentGM3, "sediment concentration", "g m^-3");
    checkNonNegative(c.cdomA440PerM, "CDOM absorption at 440 nm", "m^-1");
    checkNonNegative(c.cdomSlopePerNm, "CDOM spectral slope", "nm^-1");
    checkNonNegative(c.mineral.specificScattering555, "mineral specific scattering", "m^2 g^-1");
    checkNonNegative(c.mineral.specificAbsorption443, "mineral specific absorption", "m^2 g^-1");
    checkNonNegative(c.mineral.absorptionSlope, "mineral absorption slope", "nm^-1");
    if (!std::isfinite(c.mineral.scatteringExponent))
        throw InputError("water constituents: mineral scattering exponent must be finite");
    if (wls.empty()) throw InputError("water constituents: give at least one wavelength");

    WaterIops out;
    out.name = name;
    out.includesPureWater = c.includePureWater;
    auto tab = [&](const std::string& what, auto&& f) {
        std::vector<double> v;
        v.reserve(wls.size());
        for (double w : wls) v.push_back(f(w));
        return Spectrum::tabulated(wls, std::move(v), what);
    };
    if (c.includePureWater)
        out.components.push_back(
            {"pure water", tab("pure-water absorption", [](double w) { return pureWaterAbsorption(w); }),
             tab("pure-water scattering", [&](double w) { return pureWaterScattering(w, c.water); }),
             c.pureWaterPhase,
             c.water == WaterKind::Sea ? "Pope and Fry (1997); Morel (1974) sea water" : "Pope and Fry (1997); Morel (1974) fresh water"});
    if (c.chlorophyllMgM3 > 0)
        out.components.push_back(
            {"phytoplankton", tab("phytoplankton absorption", [&](double w) { return phytoplanktonAbsorption(w, c.chlorophyllMgM3); }),
             tab("phytoplankton scattering", [&](double w) { return phytoplanktonScattering(w, c.chlorophyllMgM3); }),
             c.phytoplanktonPhase, "Bricaud et al. (1998); Gordon and Morel (1983)"});
    if (c.sedimentGM3 > 0)
        out.components.push_back(
            {"mineral sediment", tab("mineral absorption", [&](double w) { return mineralAbsorption(w, c.sedimentGM3, c.mineral); }),
             tab("mineral scattering", [&](double w) { return mineralScattering(w, c.sedimentGM3, c.mineral); }),
             c.sedimentPhase, "Babin et al. (2003a, 2003b)"});
    if (c.cdomA440PerM > 0)
        out.components.push_back(
            {"CDOM", tab("CDOM absorption", [&](double w) { return cdomAbsorption(w, c.cdomA440PerM, c.cdomSlopePerNm); }),
             Spectrum::constant(0.0), ir::PhaseFunction{"isotropic", {}}, "Bricaud et al. (1981)"});
    return out;
}

Spectrum WaterIops::absorption() const {
    std::vector<const Spectrum*> parts;
    for (const auto& c : components) parts.push_back(&c.absorption);
    return sumSpectra(parts, "absorption of '" + name + "'");
}

Spectrum WaterIops::scattering() const {
    std::vector<const Spectrum*> parts;
    for (const auto& c : components) parts.push_back(&c.scattering);
    return sumSpectra(parts, "scattering of '" + name + "'");
}

double WaterIops::absorptionAt(double wl) const {
    double s = 0;
    for (const auto& c : components) s += c.absorption.at(wl);
    return s;
}

double WaterIops::scatteringAt(double wl) const {
    double s = 0;
    for (const auto& c : components) s += c.scattering.at(wl);
    return s;
}

std::vector<std::pair<double, ir::PhaseFunction>> WaterIops::phaseWeightsAt(double wl) const {
    std::vector<std::pair<double, ir::PhaseFunction>> out;
    for (const auto& c : components) {
        const double b = c.scattering.at(wl);
        if (b > 0) out.push_back({b, c.phase});
    }
    return out;
}

std::vector<std::pair<double, ir::PhaseFunction>> WaterIops::phaseWeights(const Band& band) const {
    std::vector<std::pair<double, ir::PhaseFunction>> out;
    for (const auto& c : components) {
        const double b = c.scattering.bandAverage(band, "scattering of '" + c.name + "' in '" + name + "'");
        if (b > 0) out.push_back({b, c.phase});
    }
    return out;
}

const IopComponent* WaterIops::component(const std::string& n) const {
    for (const auto& c : components)
        if (c.name == n) return &c;
    return nullptr;
}

// ---- presets ----------------------------------------------------------------------------------

namespace {

// Speir (2010) Table 9.6, m^-1 at 0.4, 0.5, 0.6 um: the constituent IOPs of the 12 Oct 2009
// Lake Ontario collect (Raqueno 1999 specific coefficients), as printed
// (spec/seed-ch08-09.md section 4.1). Table 10.3 = 0.01 / 0.05 / 0.10 x these
// (spec/seed-ch05-10.md section 3.4).
constexpr double kTable96Wavelengths[3] = {0.4, 0.5, 0.6};
constexpr double kTable96ChlA[3] = {0.18623, 0.146969, 0.0401584};
constexpr double kTable96ChlB[3] = {0.518596, 0.565279, 0.541272};
constexpr double kTable96TssA[3] = {1.147829, 0.396356, 0.152813};
constexpr double kTable96TssB[3] = {7.9333, 6.34667, 5.288889};
constexpr double kTable96CdomA[3] = {0.7222, 0.1472, 0.0184};

Spectrum table96(const double (&v)[3], double scale, const std::string& what) {
    return Spectrum::tabulated({kTable96Wavelengths[0], kTable96Wavelengths[1], kTable96Wavelengths[2]},
                               {scale * v[0], scale * v[1], scale * v[2]}, what);
}

WaterIops table103(const std::string& name, double scale) {
    const std::string src = fmt::format("Speir (2010) Table 10.3 = {} x Table 9.6", scale);
    const ir::PhaseFunction hg{"henyey-greenstein", {{"g", 0.88}}};  // Chapter 10: all scatterers HG g = 0.88
    WaterIops w;
    w.name = name;
    w.includesPureWater = false;
    w.components.push_back({"chlorophyll", table96(kTable96ChlA, scale, name + " chlorophyll absorption"),
                            table96(kTable96ChlB, scale, name + " chlorophyll scattering"), hg, src});
    w.components.push_back({"TSS", table96(kTable96TssA, scale, name + " TSS absorption"),
                            table96(kTable96TssB, scale, name + " TSS scattering"), hg, src});
    w.components.push_back({"CDOM", table96(kTable96CdomA, scale, name + " CDOM absorption"), Spectrum::constant(0.0),
                            ir::PhaseFunction{"isotropic", {}}, src});
    return w;
}

// Speir (2010) Table 9.3 (spec/seed-ch08-09.md section 3.2): spectrally flat a and b, m^-1.
WaterIops table93(const std::string& name, const char* group, double a, double b) {
    WaterIops w;
    w.name = name;
    w.includesPureWater = false;
    w.components.push_back({"bulk", Spectrum::constant(a), Spectrum::constant(b),
                            ir::PhaseFunction{"henyey-greenstein", {{"g", 0.92}}},
                            fmt::format("Speir (2010) Table 9.3, {}", group)});
    return w;
}

}  // namespace

namespace {

WaterPresetKind presetKind(const std::string& name, std::string doc, std::function<WaterIops()> make,
                           std::string pureWater = "no") {
    return {KindInfo{"water preset", name, std::move(doc), {}}, std::move(make), std::move(pureWater)};
}

WaterPresetKind table103Kind(const std::string& name, double scale) {
    return presetKind(name,
                      fmt::format("Speir (2010) Table 10.3: {} x the Table 9.6 chlorophyll, TSS and CDOM spectra, "
                                  "tabulated at 0.4, 0.5, 0.6 um, HG g = 0.88; the source lists no pure water, so a "
                                  "scene file adds it (pure_water: sea, the default; fresh; or none for the table as "
                                  "printed)",
                                  scale),
                      [name, scale] { return table103(name, scale); }, "added");
}

WaterPresetKind table93Kind(const std::string& name, const char* group, double a, double b) {
    return presetKind(name,
                      fmt::format("Speir (2010) Table 9.3, {}: spectrally flat a = {}, b = {} m^-1, HG g = 0.92; "
                                  "measured totals, which hold the pure water's own absorption and scattering",
                                  group, a, b),
                      [name, group, a, b] { return table93(name, group, a, b); }, "in total");
}

WaterIops pureKind() {
    WaterIops w;
    w.name = "pure";
    w.includesPureWater = false;  // no attenuation at all: a purely refracting medium
    return w;
}

}  // namespace

const KindRegistry<WaterPresetKind>& waterPresetKinds() {
    static const KindRegistry<WaterPresetKind> registry = [] {
        KindRegistry<WaterPresetKind> r("water preset");
        r.add(presetKind("pure",
                         "no absorption and no scattering: a purely refracting medium (it is not pure water, which "
                         "is constituents: {})",
                         pureKind));
        r.add(table103Kind("low", 0.01));
        r.add(table103Kind("moderate", 0.05));
        r.add(table103Kind("high", 0.10));
        r.add(table93Kind("coastal", "Clear, Coastal (Group #1)", 0.038, 0.350));
        r.add(table93Kind("bay", "Bay (Group #3)", 0.143, 0.180));
        r.add(table93Kind("turbid", "Turbid (Group #4b)", 0.268, 0.680));
        return r;
    }();
    return registry;
}

std::vector<std::string> waterPresetNames() { return waterPresetKinds().names(); }

WaterIops waterPreset(const std::string& name) { return waterPresetKinds().get(name, "").make(); }

// ---- the medium models ------------------------------------------------------------------------

namespace {

MediumModelKind constituentsKind() {
    MediumModelKind k;
    k.info = {"medium model", "constituents",
              "IOPs from concentrations: pure water, phytoplankton, mineral sediment and CDOM (the sources above)", {}};
    k.sceneKeys = {"constituents"};
    k.info.params = {
        {"chlorophyll_mg_m3", "", ParamType::Real, 0.0, 0, 1000, "mg m^-3",
         "phytoplankton: absorption Bricaud et al. (1998), scattering Gordon & Morel (1983)"},
        {"sediment_g_m3", "", ParamType::Real, 0.0, 0, 10000, "g m^-3", "mineral particles (Babin et al. 2003)"},
        {"cdom_440_per_m", "", ParamType::Real, 0.0, 0, 100, "m^-1", "CDOM absorption at 440 nm"},
        {"cdom_slope_per_nm", "", ParamType::Real, 0.014, 0.001, 0.1, "nm^-1",
         "the exponential slope of CDOM absorption (Bricaud et al. 1981)"},
    };
    k.fields = {&WaterComposition::chlorophyllMgM3, &WaterComposition::sedimentGM3, &WaterComposition::cdomA440PerM,
                &WaterComposition::cdomSlopePerNm};
    return k;
}

}  // namespace

const KindRegistry<MediumModelKind>& mediumModelKinds() {
    static const KindRegistry<MediumModelKind> registry = [] {
        KindRegistry<MediumModelKind> r("medium model");
        r.add({{"medium model", "preset", "a named IOP table (the water presets)", {}}, {"preset"}, {}});
        r.add(constituentsKind());
        r.add({{"medium model", "explicit", "absorption and scattering given directly as spectra (m^-1): one "
                                            "scatterer (HG g = 0.88 unless phase is given), or a list of scatterers, "
                                            "each with its own b and phase function", {}},
               {"absorption_per_m", "scattering_per_m", "scatterers"}, {}});
        for (const MediumModelKind& k : r.kinds())
            if (k.fields.size() != k.info.params.size())
                throw InternalError("medium model '" + k.info.name + "': its fields do not match its parameters");
        return r;
    }();
    return registry;
}

}  // namespace littoral::scenegen
