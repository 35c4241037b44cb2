#pragma once
// Water constituents and the inherent optical properties (IOPs) they give: absorption a(lambda)
// and scattering b(lambda) in m^-1, wavelengths in micrometres, plus the split of b among
// scatterers that a phase-function mixture weights by (p = sum b_i p_i / sum b_i).
//
// Data sources (each function below names its own):
//   pure water absorption   Pope and Fry (1997), Appl. Opt. 36, 8710-8723: integrating-cavity
//                           measurements, 22 deg C, every 2.5 nm over 380-700 nm (the range of the
//                           paper's title). Outside it: InputError.
//   pure water scattering   Morel (1974): b_w(lambda) = b_w(500 nm) (lambda/500 nm)^-4.32 with
//                           b_w(500) = 0.00222 m^-1 (fresh) or 0.00288 m^-1 (sea water,
//                           S = 35-39, 1.30 x fresh). Molecular phase function: the pure-water
//                           kind, 1 + (1 - d)/(1 + d) cos^2 with depolarisation ratio d = 0.09
//                           (1 + 0.835 cos^2), not isotropic.
//   phytoplankton           absorption: Bricaud et al. (1998), J. Geophys. Res. 103, 31033:
//                           a_ph = A(lambda) Chl^E(lambda), their 2-nm table over 400-700 nm;
//                           scattering: Gordon and Morel (1983): b_p(550) = 0.30 Chl^0.62 m^-1
//                           with a lambda^-1 shape (550/lambda).
//   mineral sediment        Babin et al. (2003b), Limnol. Oceanogr. 48, 843: mass-specific
//                           scattering at 555 nm 0.5 m^2 g^-1 (their coastal "case 2" mean),
//                           spectrally flat by default ("small on average"); absorption after
//                           Babin et al. (2003a), J. Geophys. Res. 108(C7): a*(443) =
//                           0.041 m^2 g^-1 with an exponential slope of 0.0123 nm^-1 (means for
//                           mineral-rich European coastal waters). Both are parameters.
//   CDOM                    a_g(lambda) = a_g(440) exp(-S (lambda - 440 nm)), S = 0.014 nm^-1
//                           by default (Bricaud et al. 1981).
//
// The dissertation's presets (waterPreset) are expressed through the same structure: a list of
// named components, each with its own a and b spectra and phase function. They do NOT include
// pure water, exactly as the dissertation's tables (which list constituents only); includesPure
// Water is false for them. Table 10.3 (low, moderate, high) is the Table 9.6 constituent spectra
// x 0.01 / 0.05 / 0.10; Table 9.3 (coastal, bay, turbid) is one spectrally flat bulk component.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/kinds.h"
#include "core/scene_ir.h"
#include "core/spectrum.h"

namespace littoral::scenegen {

// Phase functions are named as in the Scene IR (ir::PhaseFunction: a kind from
// core/phase_functions.h and its parameters), e.g. {"henyey-greenstein", {{"g", 0.88}}}.

// ---- the single-constituent models (wavelength in um, concentration as named) -----------------

inline constexpr double kPopeFryMinUm = 0.380, kPopeFryMaxUm = 0.700;
inline constexpr double kBricaudMinUm = 0.400, kBricaudMaxUm = 0.700;
inline constexpr double kPureWaterDepolarization = 0.09;  // Morel (1974): (1 - 0.09)/(1 + 0.09) = 0.835

enum class WaterKind { Fresh, Sea };

Spectrum pureWaterAbsorptionTable();                 // Pope and Fry (1997), m^-1
double pureWaterAbsorption(double wavelengthUm);     // InputError outside 0.380-0.700 um
double pureWaterScattering(double wavelengthUm, WaterKind kind);  // Morel (1974), m^-1
double phytoplanktonAbsorption(double wavelengthUm, double chlorophyllMgM3);  // Bricaud et al. (1998)
double phytoplanktonScattering(double wavelengthUm, double chlorophyllMgM3);  // Gordon and Morel (1983)

struct MineralModel {
    double specificScattering555 = 0.5;   // m^2 g^-1 at 555 nm (Babin et al. 2003b)
    double scatteringExponent = 0.0;      // b ~ (555 nm / lambda)^exponent
    double specificAbsorption443 = 0.041; // m^2 g^-1 at 443 nm (Babin et al. 2003a)
    double absorptionSlope = 0.0123;      // nm^-1 (Babin et al. 2003a)
};
double mineralAbsorption(double wavelengthUm, double sedimentGM3, const MineralModel& m = {});
double mineralScattering(double wavelengthUm, double sedimentGM3, const MineralModel& m = {});
double cdomAbsorption(double wavelengthUm, double a440PerM, double slopePerNm = 0.014);

// ---- a composition and the IOPs it gives -----------------------------------------------------

struct WaterComposition {
    double chlorophyllMgM3 = 0.0;  // chlorophyll a, mg m^-3
    double sedimentGM3 = 0.0;      // mineral suspended matter, g m^-3
    double cdomA440PerM = 0.0;     // CDOM absorption at 440 nm, m^-1
    double cdomSlopePerNm = 0.014;
    bool includePureWater = true;
    WaterKind water = WaterKind::Sea;
    MineralModel mineral;
    // Morel (1974): depolarisation ratio 0.09, p proportional to 1 + 0.835 cos^2.
    ir::PhaseFunction pureWaterPhase{"pure-water", {{"depolarization_ratio", kPureWaterDepolarization}}};
    ir::PhaseFunction phytoplanktonPhase{"petzold", {}};
    ir::PhaseFunction sedimentPhase{"petzold", {}};
};

// One absorber and/or scatterer. Spectra are tabulated (or constant); `phase` matters only where
// the component scatters.
struct IopComponent {
    std::string name;
    Spectrum absorption;  // m^-1
    Spectrum scattering;  // m^-1
    ir::PhaseFunction phase;
    std::string source;   // the data source, for reports
};

struct WaterIops {
    std::string name;
    std::vector<IopComponent> components;
    bool includesPureWater = false;

    // Totals: sums over the components, tabulated on the union of their wavelengths (constant if
    // every component is constant). InputError if two tabulated components do not overlap.
    Spectrum absorption() const;
    Spectrum scattering() const;
    double absorptionAt(double wavelengthUm) const;
    double scatteringAt(double wavelengthUm) const;
    // (b_i, phase_i) of each component that scatters at this wavelength (or, band-averaged, in
    // this band): the weights of the phase-function mixture.
    std::vector<std::pair<double, ir::PhaseFunction>> phaseWeightsAt(double wavelengthUm) const;
    std::vector<std::pair<double, ir::PhaseFunction>> phaseWeights(const Band& band) const;
    const IopComponent* component(const std::string& name) const;  // nullptr if absent
};

// IOPs of a composition on the given wavelength grid (um, strictly increasing). Components with
// zero concentration are left out. InputError for negative concentrations or parameters and for
// wavelengths outside the data range of a constituent that is present.
WaterIops computeIops(const WaterComposition& composition, const std::vector<double>& wavelengthsUm,
                      const std::string& name = "water");

// ---- the medium models: how water.optics (or a layer) gives its IOPs ---------------------------
// Family "medium model", one descriptor each, read by the scene-file parser, its messages and
// docs/scene-format.md (checked by tests/pipelines/kinds_test.cpp):
//   preset        a named IOP table (the "water preset" family below);
//   constituents  computeIops from concentrations: its numeric parameters are ParamSpecs (keys under
//                 `constituents:`, default, range, unit, doc), each bound to its WaterComposition
//                 member; `pure_water` (sea, fresh, none) and `particle_phase` (a phase function) are
//                 not numbers and are read by the parser itself;
//   explicit      absorption_per_m and scattering_per_m given as spectra (m^-1).
struct MediumModelKind {
    KindInfo info;                       // family "medium model"
    std::vector<std::string> sceneKeys;  // the water.optics keys that choose this model
    std::vector<double WaterComposition::*> fields;  // constituents: the member of each of info.params
};
inline const KindInfo& kindInfo(const MediumModelKind& k) { return k.info; }
const KindRegistry<MediumModelKind>& mediumModelKinds();

// ---- the dissertation's presets ---------------------------------------------------------------

// "low", "moderate", "high" (Table 10.3, tabulated at 0.4, 0.5, 0.6 um, HG g = 0.88 as in
// Chapter 10), "coastal", "bay", "turbid" (Table 9.3, spectrally flat; HG g = 0.92, one of the
// four phase functions each group was run with), and "pure": no absorption and no scattering (a
// purely refracting medium; it is not pure water). None includes pure water.
// Each preset is a kind of family "water preset": its name, a doc line naming its table and
// whether it includes pure water (none does), and its factory.
struct WaterPresetKind {
    KindInfo info;  // family "water preset"; no parameters
    std::function<WaterIops()> make;  // the source's IOPs as published
    // Pure water in the preset (docs/scene-format.md's "pure water" column):
    //   "added"    the source lists the constituents alone; a scene file adds pure water (its key
    //              `pure_water` beside `preset`: sea (default), fresh, or none for the source as printed);
    //   "in total" the source's a and b are measured totals, which hold the water's own;
    //   "no"       none (a purely refracting medium).
    std::string pureWater = "no";
};
inline const KindInfo& kindInfo(const WaterPresetKind& k) { return k.info; }
const KindRegistry<WaterPresetKind>& waterPresetKinds();

std::vector<std::string> waterPresetNames();     // waterPresetKinds().names()
WaterIops waterPreset(const std::string& name);  // InputError naming the allowed values, with a did-you-mean

}  // namespace littoral::scenegen
