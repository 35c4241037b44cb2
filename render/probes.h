#pragma once
// Point radiometers (the Scene IR's probes): plane irradiances Ed and Eu, scalar irradiances Eod
// and Eou, and nadir-viewing upwelling radiance Lu at a point, by integrating traced radiance.
//
//   Ed  = Int_{up}   L(w) |cos theta| dw   cosine-weighted stratified sampling: Ed = pi <L>
//   Eu  = Int_{down} L(w) |cos theta| dw   (the same toward the lower hemisphere)
//   Eod = Int_{up}   L(w) dw              uniform stratified sampling: Eod = 2 pi <L>
//   Eou = Int_{down} L(w) dw
//   Lu  = L arriving from straight below (the radiance a nadir-looking sensor reads), <L> over
//         the samples of the same ray
// L(w) is the radiance arriving at the probe from direction w (traced with the Integrator; the
// probe itself casts no shadow). The sun's direct beam is added by a shadow ray (E_sun cos theta_s
// for Ed, E_sun for Eod) instead of waiting for a sample to land in the 6.7e-5 sr disc; rays that
// reach the disc through a specular interface still count it. The standard error is
// s / sqrt(N) with s the sample standard deviation of the N per-sample estimates (conservative
// for stratified sampling, which has smaller variance than independent sampling).
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace littoral::render {

struct ProbeValue {
    std::string probe, quantity;
    std::string units;                // W m^-2 um^-1 (irradiances) or W m^-2 sr^-1 um^-1 (Lu)
    std::vector<double> mean, stderr_;  // per render band
};

// Evaluates every quantity of one probe. InputError for an unknown quantity, an unknown medium or
// a probe inside a closed opaque object.
std::vector<ProbeValue> evaluateProbe(const Scene& scene, const ir::Probe& probe, int probeIndex,
                                      const RenderOptions& opts = {});

// CSV (one row per probe, quantity and band) and JSON renderings of probe results.
std::string probesCsv(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);
std::string probesJson(const std::vector<ProbeValue>& values, const std::vector<Band>& bands);

}  // namespace littoral::render
