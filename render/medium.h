#pragma once
// The Medium interface: what a ray travelling through water (or air) needs to know.
//
//  * majorant: the largest extinction coefficient c = a + b anywhere in the medium (per band group);
//  * transmittance along a ray, exp(-Int c ds) (Eq. 2.4, through every layer it crosses);
//  * free-flight (distance) sampling, with the spectral weights of the bands traced together;
//  * the phase function at a point, with eval / sample / pdf.
//
// A medium is a stack of horizontal layers (depth-stratified water, Mobley et al. 1993 problem 3);
// homogeneous water is one layer without bounds. Each layer has an absorption a(lambda) and a list
// of scatterers (pure water, particles, ...) with their own b_i(lambda) and phase functions; the
// layer's phase function is the mixture sum b_i p_i / sum b_i, whose weights may differ by band.
//
// Spectral sampling (one-sample MIS over the bands of a group, pbrt-v4's approach): a distance is
// drawn from the band chosen uniformly at random, so its density is the band average
// pdf(t) = (1/n) sum_b c_b(t) T_b(t); each band's weight T_b(t) b_b(t) / pdf(t) is exact. When all
// bands share c the weights reduce to the single-scattering albedo b/c.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/phase_functions.h"
#include "core/ray.h"
#include "core/rng.h"
#include "core/scene_ir.h"
#include "render/spectral.h"

namespace littoral::render {

// Consecutive render bands traced together: at most kMaxGroupBands, and every medium has the same
// refractive index in all of them (so they share ray geometry; dispersion splits groups).
struct BandGroup {
    int begin = 0, count = 0;
};

inline constexpr int kMaxScatterers = 16;  // per layer

// A layer's phase functions combined for every render band, evaluated for a band group in one
// pass (volume photon-map queries evaluate it for every photon they gather). The value is the
// b-weighted sum of the components, as Medium::phase defines it, regrouped:
// - the tabulated components that share one table (Petzold's particles: most natural waters) are
//   summed per band into one function linear in t = 1 - cos between the table's nodes, whose
//   segment is found once, through a lookup of its own (bins by the top bits of t, each holding
//   the first segment it meets: a segment search is a step or two);
// - the isotropic and Rayleigh-like components are polynomials in t, summed per band into one
//   quadratic;
// - any other (Henyey-Greenstein, Fournier-Forand, another table) is evaluated once and weighted
//   per band.
class LayerPhase {
public:
    LayerPhase() = default;
    // From the scatterers' phase functions and weights [band][scatterer].
    LayerPhase(const std::vector<PhaseFunction>& phases, const std::vector<std::vector<double>>& weights);
    // p for the bands [begin, begin + count) at t = 1 - cos (> 0) into out[0, count).
    void eval(double t, int begin, int count, double* out) const {
        const size_t nb = static_cast<size_t>(bands_), b0 = static_cast<size_t>(begin);
        const double* q = &quadratic_[3 * b0];
        if (table_ && t >= node_.front() && t < 2.0) {
            size_t j = logLookup_[std::max(std::bit_cast<uint64_t>(t) >> kLogShift, logBase_) - logBase_];
            while (t >= node_[j + 1]) ++j;
            while (t < node_[j]) --j;  // a bin index rounded up past a node (t >= node_[0] ends it)
            const double dt = t - node_[j];
            const double* v = &value_[j * nb + b0];
            const double* s = &slope_[j * nb + b0];
            for (int k = 0; k < count; ++k) out[k] = v[k] + s[k] * dt + q[3 * k] + t * (q[3 * k + 1] + t * q[3 * k + 2]);
        } else {
            evalOutsideTable(t, begin, count, out);
            for (int k = 0; k < count; ++k) out[k] += q[3 * k] + t * (q[3 * k + 1] + t * q[3 * k + 2]);
        }
        for (const Part& part : others_) {
            const double v = part.f.evalOneMinusCos(t);
            for (int k = 0; k < count; ++k) out[k] += part.weight[b0 + static_cast<size_t>(k)] * v;
        }
    }

private:
    // The segment lookup: bin k holds the t whose representation's top bits are k (after
    // logBase_), 2^(52 - kLogShift) = 512 bins per octave, so nearly uniform in log t. A table
    // refined log-log over the forward peak (Petzold: 32 nodes per 0.1 decade of angle) has a node
    // per bin or fewer there, where most phase samples fall, and about one elsewhere. Measured
    // against 4096 bins uniform in sin(psi / 2) (Petzold, one thread): 6.7 against 22.5 ns per
    // value at phase-sampled angles, 9.0 against 8.9 at t uniform in [0, 2); 40 KB per table.
    static constexpr int kLogShift = 43;
    // The table's part where its nodes do not reach: the forward power law, and t >= 2.
    void evalOutsideTable(double t, int begin, int count, double* out) const;

    int bands_ = 0;
    std::shared_ptr<const TabulatedPhase> table_;  // null: no tabulated component
    std::vector<double> tableWeight_;              // [band]: the table's total weight
    std::vector<double> node_, value_, slope_;     // t_j (and +inf last); [j * bands + band]: the weighted table at t_j, d/dt
    std::vector<uint32_t> logLookup_;              // [bin]: the segment holding the bin's start
    uint64_t logBase_ = 0;                         // the first of those bins: node_[0]'s top bits (t >= 1e-12)
    std::vector<double> quadratic_;                // [3 band + i]: the polynomial parts' t^i coefficient
    struct Part {
        PhaseFunction f;              // one component
        std::vector<double> weight;   // [band]
    };
    std::vector<Part> others_;
};

// One layer on the render bands.
struct MediumLayer {
    double zTop = ir::kInfinity, zBottom = -ir::kInfinity;
    std::vector<double> a, b, c;                 // per render band, m^-1
    std::vector<double> cEff;                    // a + b (1 - f), f = fraction scattered into the 0.01 sr
                                                 // forward cone (DIRSIG's effective scattering coefficient)
    std::vector<double> outsideCone;             // per render band, 1 / (1 - f) (0 where f = 1, 1 where b = 0):
                                                 // the phase function outside the cone, renormalised
    std::vector<PhaseFunction> phases;           // one per scatterer
    std::vector<std::vector<double>> weights;    // [band][scatterer] = b_i / b (b > 0), else 1/n
    LayerPhase combined;                         // phases and weights, for Medium::phase
};

// Result of free-flight sampling along [0, tMax).
struct FreeFlight {
    bool scattered = false;  // a scattering event at distance t; otherwise the ray reached tMax
    double t = 0;
    int layer = -1;          // layer of the event
    Spec weight;             // per band: T(t) b(t) / pdf (scattered) or T(tMax) / P(no event)
};

class Medium {
public:
    Medium() = default;
    // Averages an IR medium over the render bands; InputError naming `who` for bands outside a
    // spectrum's table, negative coefficients, n < 1 or bad phase-function parameters.
    Medium(const ir::Medium& m, const std::vector<Band>& bands, const std::string& who);
    static Medium air(size_t bandCount);

    const std::string& name() const { return name_; }
    double n(int band) const { return n_[band]; }
    const std::vector<double>& indices() const { return n_; }
    bool attenuating() const { return attenuating_; }  // c > 0 somewhere in some band
    bool scattering() const { return scattering_; }    // b > 0 somewhere in some band
    const std::vector<MediumLayer>& layers() const { return layers_; }
    bool homogeneous() const { return layers_.size() == 1; }

    int layerAt(double z) const;
    Spec a(int layer, BandGroup g) const { return slice(layers_[layer].a, g); }
    Spec b(int layer, BandGroup g) const { return slice(layers_[layer].b, g); }
    Spec c(int layer, BandGroup g) const { return slice(layers_[layer].c, g); }
    double majorant(BandGroup g) const;

    // exp(-Int_0^t c ds) per band along the unit-direction ray; t may be infinite (0 where c > 0).
    Spec transmittance(const Ray& r, double t, BandGroup g) const;
    // Optical depth Int_0^t c ds per band (infinite where c > 0 and t is). With `effective`, the
    // effective extinction a + b (1 - f_cone) (small-angle scattering counted as unscattered).
    Spec opticalDepth(const Ray& r, double t, BandGroup g, bool effective = false) const;
    Spec transmittance(const Ray& r, double t, BandGroup g, bool effective) const {
        if (!attenuating_) return Spec(g.count, 1.0);  // inline: the air's segments are most rays
        return attenuatedTransmittance(r, t, g, effective);
    }
    Spec attenuatedTransmittance(const Ray& r, double t, BandGroup g, bool effective) const;
    // Free-flight sampling along [0, tMax) (tMax may be infinite); uBand picks the hero band.
    FreeFlight sampleFreeFlight(const Ray& r, double tMax, BandGroup g, double uBand, double u) const;

    // Phase function of `layer` for the bands of g, for light travelling along `in` scattered into
    // `out` (unit vectors; sr^-1). Evaluated through 1 - cos = |out - in|^2 / 2, which stays
    // accurate near the forward peak of Petzold and Fournier–Forand (infinite at exactly 0).
    Spec phase(int layer, BandGroup g, const Vec3& in, const Vec3& out) const {
        // 1 - cos from the chord; a tiny floor keeps an exactly forward connection finite (a
        // measure-zero event with the sampled solar disc).
        const double t = std::max(0.5 * lengthSquared(out - in), 1e-18);
        Spec p(g.count);
        layers_[static_cast<size_t>(layer)].combined.eval(t, g.begin, g.count, p.v.data());
        return p;
    }
    // Samples a new propagation direction after scattering of a ray travelling along `dir`; weight
    // receives p_b / pdf per band (1 for a single scatterer).
    Vec3 samplePhase(int layer, BandGroup g, const Vec3& dir, RandomStream& rng, Spec* weight) const;
    // Sampling directions around `dir` from the layer's phase function with the band-averaged
    // mixture weights (the density samplePhase draws from), and that density (sr^-1). Used as an
    // importance distribution, e.g. for probe directions near the sun's forward-scattering peak.
    Vec3 sampleAround(int layer, BandGroup g, const Vec3& dir, double u0, double u1, double u2, double u3) const;
    double pdfAround(int layer, BandGroup g, const Vec3& dir, const Vec3& w) const;
    // Whether some layer's phase function has a strong forward peak: p at 0.08 deg (1 - cos = 1e-6)
    // above 10 times the isotropic 1/(4 pi). Decides where sampling is guided toward the sun.
    bool forwardPeaked() const { return forwardPeaked_; }
    // Band-averaged mean cosine of the layer's phase function (for documentation and heuristics).
    double meanCosine(int layer) const;

private:
    Spec slice(const std::vector<double>& v, BandGroup g) const {
        Spec s(g.count);
        for (int i = 0; i < g.count; ++i) s[i] = v[g.begin + i];
        return s;
    }
    // Calls f(layer, t0, t1) for each layer the ray crosses within [0, t), in order.
    template <class F> void walk(const Ray& r, double t, F&& f) const;

    std::string name_;
    std::vector<double> n_;
    std::vector<MediumLayer> layers_;
    bool attenuating_ = false, scattering_ = false, forwardPeaked_ = false;
};

}  // namespace littoral::render
