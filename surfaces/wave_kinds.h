#pragma once
// The wave-model kinds: one descriptor per WaveModel (family "wave model"), each beside its
// synthesis in wave_kinds.cpp. A descriptor holds the model's name and doc line, the keys of a
// scene file's water.surface section that only this model takes (typed parameters with defaults,
// ranges and units; and named choices such as cox-munk's `sea`), how those values set WaveParams,
// and the synthesis that generateWaveSurface calls. The scene-file parser (scenegen/
// surface_section.cpp), its messages ("does not apply to model X; it is used by: ...") and
// docs/scene-format.md (checked by tests/pipelines/kinds_test.cpp) read them. The keys every model
// takes (model, size, centre, spacing, triangles, roughness) are not part of any descriptor.
#include <optional>
#include <string>
#include <vector>

#include "core/kinds.h"
#include "surfaces/synthesis.h"
#include "surfaces/wave_spectra.h"
#include "surfaces/wave_surface.h"

namespace littoral::surfaces {

// A key whose value is one of a few names (cox-munk's `sea`).
struct WaveChoice {
    std::string key;
    std::vector<std::string> allowed;
    std::string defaultValue;
    std::string doc;  // one line
};

struct WaveKind {
    KindInfo info;  // family "wave model"
    WaveModel model;
    std::vector<WaveChoice> choices;
    // Sets the model's fields of `p` from `values` (every parameter of `info`, defaults filled in)
    // and `choices` (one name per entry of `choices`, in order). Fields the model does not use keep
    // their WaveParams defaults.
    void (*apply)(const ParamValues& values, const std::vector<std::string>& choices, WaveParams& p);
    // Keys whose out-of-range values validateWaveParams words itself (cox-munk's wind: Cox and
    // Munk's range, with what they measured); the scene parser leaves their range to it, and it
    // reports them at the key.
    std::vector<std::string> rangeCheckedByValidation;
    // Fills out.field, out.description and the model's predictions; returns the power of the grid's
    // modes for the random models.
    std::optional<ModePower> (*synthesize)(const WaveParams& p, const GridSpec& g, WaveSurface& out);

    const WaveChoice* choice(std::string_view key) const;
    bool takes(std::string_view key) const { return info.param(key) || choice(key); }
};
inline const KindInfo& kindInfo(const WaveKind& k) { return k.info; }

// Registered in the order of the enum, so waveKind(m) is an index.
const KindRegistry<WaveKind>& waveModelKinds();
const WaveKind& waveKind(WaveModel m);

// Every model-specific key (parameters and choices) once, in registration order.
std::vector<std::string> waveModelKeys();
// The models that take `key`, as "beaufort, pierson-moskowitz, ..." ("" for none).
std::string waveModelsTaking(std::string_view key);

// The spectrum of a spectral model (pierson-moskowitz, jonswap, elfouhaily).
SpectrumParams spectrumParamsFor(const WaveParams& p);

}  // namespace littoral::surfaces
