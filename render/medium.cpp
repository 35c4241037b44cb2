#include "render/medium.h"

#include <bit>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/units.h"

namespace littoral::render {

namespace {
// Band-averaged scatterer weights of a layer for the bands of g.
void averageWeights(const MediumLayer& l, BandGroup g, double* w) {
    for (size_t i = 0; i < l.phases.size(); ++i) {
        w[i] = 0;
        for (int k = 0; k < g.count; ++k) w[i] += l.weights[g.begin + k][i];
        w[i] /= g.count;
    }
}
}  // namespace

Medium Medium::air(size_t bandCount) {
    Medium m;
    m.n_.assign(bandCount, 1.0);
    MediumLayer l;
    l.a.assign(bandCount, 0.0);
    l.b = l.a;
    l.c = l.a;
    l.cEff = l.a;
    l.outsideCone.assign(bandCount, 1.0);
    m.layers_.push_back(std::move(l));
    return m;
}

Medium::Medium(const ir::Medium& m, const std::vector<Band>& bands, const std::string& who) : name_(m.name) {
    const size_t nb = bands.size();
    n_ = m.refractiveIndex.bandAverages(bands, who + " refractive_index");
    for (size_t k = 0; k < nb; ++k)
        if (!(n_[k] >= 1.0 - 1e-12))
            throw InputError(fmt::format("{}: refractive index {} in band {} (need n >= 1)", who, n_[k], k));
    if (const std::string err = ir::checkLayers(m); !err.empty()) throw InputError(fmt::format("{}: {}", who, err));
    for (size_t li = 0; li < m.layers.size(); ++li) {
        const ir::Layer& L = m.layers[li];
        const std::string lw = m.layers.size() == 1 ? who : fmt::format("{} layer {}", who, li);
        MediumLayer d;
        d.zTop = L.zTop;
        d.zBottom = L.zBottom;
        d.a = L.absorption.bandAverages(bands, lw + " absorption");
        d.b.assign(nb, 0.0);
        std::vector<std::vector<double>> bi;
        if (L.scatterers.size() > static_cast<size_t>(kMaxScatterers))
            throw InputError(fmt::format("{}: {} scatterers; at most {} per layer", lw, L.scatterers.size(), kMaxScatterers));
        for (const ir::Scatterer& s : L.scatterers) {
            const std::string sw = fmt::format("{} scatterer '{}'", lw, s.name);
            bi.push_back(s.scattering.bandAverages(bands, sw + " scattering"));
            d.phases.push_back(makePhaseFunction(s.phase.type, s.phase.params, sw + " phase"));
            forwardPeaked_ |= d.phases.back().evalOneMinusCos(1e-6) > 10.0 / (4.0 * kPi);
            for (size_t k = 0; k < nb; ++k) {
                if (!(bi.back()[k] >= 0))
                    throw InputError(fmt::format("{}: scattering coefficient {} in band {} (need b >= 0)", sw,
                                                 bi.back()[k], k));
                d.b[k] += bi.back()[k];
            }
        }
        d.c.resize(nb);
        d.cEff.resize(nb);
        d.outsideCone.resize(nb);
        d.weights.assign(nb, std::vector<double>(bi.size(), bi.empty() ? 0.0 : 1.0 / bi.size()));
        for (size_t k = 0; k < nb; ++k) {
            if (!(d.a[k] >= 0))
                throw InputError(fmt::format("{}: absorption coefficient {} in band {} (need a >= 0)", lw, d.a[k], k));
            d.c[k] = d.a[k] + d.b[k];
            double fCone = 0;  // b-weighted fraction of scattering into the 0.01 sr forward cone
            for (size_t i = 0; i < bi.size(); ++i)
                if (d.b[k] > 0) fCone += bi[i][k] / d.b[k] * d.phases[i].forwardConeFraction(1.0 - 0.01 / (2.0 * kPi));
            d.cEff[k] = d.a[k] + d.b[k] * (1.0 - fCone);
            d.outsideCone[k] = fCone < 1.0 ? 1.0 / (1.0 - fCone) : 0.0;
            attenuating_ |= d.c[k] > 0;
            scattering_ |= d.b[k] > 0;
            if (d.b[k] > 0)
                for (size_t i = 0; i < bi.size(); ++i) d.weights[k][i] = bi[i][k] / d.b[k];
        }
        d.combined = LayerPhase(d.phases, d.weights);
        layers_.push_back(std::move(d));
    }
}

int Medium::layerAt(double z) const {
    // Layers are ordered top to bottom; layer i holds zBottom_i <= z < zTop_i.
    for (size_t i = 0; i + 1 < layers_.size(); ++i)
        if (z >= layers_[i].zBottom) return static_cast<int>(i);
    return static_cast<int>(layers_.size()) - 1;
}

double Medium::majorant(BandGroup g) const {
    double m = 0;
    for (const MediumLayer& l : layers_)
        for (int i = 0; i < g.count; ++i) m = std::max(m, l.c[g.begin + i]);
    return m;
}

template <class F> void Medium::walk(const Ray& r, double t, F&& f) const {
    if (layers_.size() == 1) {
        f(0, 0.0, t);
        return;
    }
    int li = layerAt(r.o.z);
    double t0 = 0;
    while (t0 < t) {
        // Distance to leave layer li along the ray (through its top when rising, bottom when sinking).
        double tExit = ir::kInfinity;
        if (r.d.z > 0 && std::isfinite(layers_[li].zTop)) tExit = (layers_[li].zTop - r.o.z) / r.d.z;
        else if (r.d.z < 0 && std::isfinite(layers_[li].zBottom)) tExit = (layers_[li].zBottom - r.o.z) / r.d.z;
        const double t1 = std::min(t, std::max(tExit, t0));
        f(li, t0, t1);
        if (t1 >= t) return;
        t0 = t1;
        li += r.d.z > 0 ? -1 : 1;
        if (li < 0 || li >= static_cast<int>(layers_.size())) return;  // cannot happen: outer layers unbounded
    }
}

Spec Medium::opticalDepth(const Ray& r, double t, BandGroup g, bool effective) const {
    Spec tau(g.count, 0.0);
    walk(r, t, [&](int li, double t0, double t1) {
        const MediumLayer& l = layers_[li];
        for (int i = 0; i < g.count; ++i) {
            const double c = effective ? l.cEff[g.begin + i] : l.c[g.begin + i];
            if (c > 0) tau[i] += c * (t1 - t0);  // inf * c = inf for an infinite leg
        }
    });
    return tau;
}

Spec Medium::transmittance(const Ray& r, double t, BandGroup g) const { return transmittance(r, t, g, false); }

Spec Medium::attenuatedTransmittance(const Ray& r, double t, BandGroup g, bool effective) const {
    Spec tau = opticalDepth(r, t, g, effective);
    for (int i = 0; i < g.count; ++i) tau[i] = std::exp(-tau[i]);
    return tau;
}

FreeFlight Medium::sampleFreeFlight(const Ray& r, double tMax, BandGroup g, double uBand, double u) const {
    FreeFlight ff;
    const int n = g.count;
    const int hero = std::min(n - 1, static_cast<int>(uBand * n));
    // Optical depth at which the hero band collides. For u from RandomStream (a multiple of 2^-53)
    // 1 - u is exact, so log loses nothing against log1p, and glibc's log is several times faster.
    const double target = -std::log(1.0 - u);
    Spec tau(n, 0.0);                       // optical depth so far, per band
    double heroTau = 0;
    bool done = false;
    walk(r, tMax, [&](int li, double t0, double t1) {
        if (done) return;
        const MediumLayer& l = layers_[li];
        const double ch = l.c[g.begin + hero];
        const double dt = t1 - t0;
        if (ch > 0 && heroTau + ch * dt > target) {
            // Collision inside this layer.
            const double t = t0 + (target - heroTau) / ch;
            for (int i = 0; i < n; ++i) tau[i] += l.c[g.begin + i] * (t - t0);
            ff.t = t;
            ff.layer = li;
            ff.scattered = true;
            done = true;
            return;
        }
        if (ch > 0) heroTau += ch * dt;
        for (int i = 0; i < n; ++i)
            if (l.c[g.begin + i] > 0) tau[i] += l.c[g.begin + i] * dt;
    });
    ff.weight = Spec(n, 0.0);
    if (n == 1) {
        // One band: the weights below are T b / (c T) and T / T, whatever T is (T > 0: a flight
        // that passes has tau <= target <= 53 ln 2), so no exponential is needed.
        ff.weight[0] = ff.scattered ? layers_[ff.layer].b[g.begin] / layers_[ff.layer].c[g.begin] : 1.0;
        if (!ff.scattered) ff.t = tMax;
        return ff;
    }
    if (ff.scattered) {
        const MediumLayer& l = layers_[ff.layer];
        double pdf = 0;
        Spec T(n);
        for (int i = 0; i < n; ++i) {
            T[i] = std::exp(-tau[i]);
            pdf += l.c[g.begin + i] * T[i];
        }
        pdf /= n;
        if (pdf > 0)
            for (int i = 0; i < n; ++i) ff.weight[i] = T[i] * l.b[g.begin + i] / pdf;
        return ff;
    }
    ff.t = tMax;
    double pass = 0;
    Spec T(n);
    for (int i = 0; i < n; ++i) {
        T[i] = std::exp(-tau[i]);
        pass += T[i];
    }
    pass /= n;
    if (pass > 0)
        for (int i = 0; i < n; ++i) ff.weight[i] = T[i] / pass;
    return ff;
}

LayerPhase::LayerPhase(const std::vector<PhaseFunction>& phases, const std::vector<std::vector<double>>& weights)
    : bands_(static_cast<int>(weights.size())) {
    const size_t nb = weights.size();
    quadratic_.assign(3 * nb, 0.0);
    for (size_t i = 0; i < phases.size(); ++i)
        for (int c = 0; c < phases[i].componentCount(); ++c) {
            std::vector<double> w(nb);
            for (size_t k = 0; k < nb; ++k) w[k] = weights[k][i] * phases[i].componentWeight(c);
            const PhaseFunction::Component& part = phases[i].part(c);
            const auto* table = std::get_if<std::shared_ptr<const TabulatedPhase>>(&part);
            if (table && (!table_ || *table == table_)) {
                table_ = *table;
                tableWeight_.resize(nb, 0.0);
                for (size_t k = 0; k < nb; ++k) tableWeight_[k] += w[k];
            } else if (std::holds_alternative<IsotropicPhase>(part)) {
                for (size_t k = 0; k < nb; ++k) quadratic_[3 * k] += w[k] * 0.25 / kPi;
            } else if (const auto* r = std::get_if<RayleighLikePhase>(&part)) {
                // (1 + k (1 - t)^2) / (4 pi (1 + k / 3)) = C (1 + k) - 2 C k t + C k t^2
                const double C = 0.25 / kPi / (1.0 + r->k / 3.0);
                for (size_t k = 0; k < nb; ++k) {
                    quadratic_[3 * k] += w[k] * C * (1.0 + r->k);
                    quadratic_[3 * k + 1] -= w[k] * 2.0 * C * r->k;
                    quadratic_[3 * k + 2] += w[k] * C * r->k;
                }
            } else {
                others_.push_back({phases[i].component(c), std::move(w)});
            }
        }
    if (!table_) return;
    node_ = table_->nodesOneMinusCos();
    const std::vector<double>& p = table_->nodeValues();
    value_.resize(node_.size() * nb);
    slope_.resize(node_.size() * nb, 0.0);
    for (size_t j = 0; j < node_.size(); ++j)
        for (size_t k = 0; k < nb; ++k) {
            value_[j * nb + k] = tableWeight_[k] * p[j];
            if (j + 1 < node_.size()) slope_[j * nb + k] = tableWeight_[k] * (p[j + 1] - p[j]) / (node_[j + 1] - node_[j]);
        }
    // The last node is t = 2: the search stops there at the latest (t < 2 is evaluated here).
    node_.back() = ir::kInfinity;
    logBase_ = std::bit_cast<uint64_t>(std::max(node_.front(), 1e-12)) >> kLogShift;  // below: bin 0, scanned
    const uint64_t last = std::bit_cast<uint64_t>(2.0) >> kLogShift;
    logLookup_.resize(static_cast<size_t>(last - logBase_ + 1));
    size_t j = 0;
    for (uint64_t b = logBase_; b <= last; ++b) {
        const double t = std::bit_cast<double>(b << kLogShift);  // the bin's start
        while (j + 2 < node_.size() && t >= node_[j + 1]) ++j;
        logLookup_[static_cast<size_t>(b - logBase_)] = static_cast<uint32_t>(j);
    }
}

void LayerPhase::evalOutsideTable(double t, int begin, int count, double* out) const {
    const double v = table_ ? table_->evalOneMinusCos(t) : 0.0;
    for (int k = 0; k < count; ++k) out[k] = table_ ? tableWeight_[static_cast<size_t>(begin + k)] * v : 0.0;
}

Vec3 Medium::samplePhase(int layer, BandGroup g, const Vec3& dir, RandomStream& rng, Spec* weight) const {
    const MediumLayer& l = layers_[layer];
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    if (l.phases.size() == 1) {
        const Vec3 w = l.phases[0].sample(dir, u1, u2, u3, nullptr);  // weight p / pdf = 1: no pdf needed
        *weight = Spec(g.count, 1.0);
        return w;
    }
    // Mixture: pick a scatterer by its band-averaged weight, then weight each band by p_b / pdf.
    // That pdf, sum_i (mean_k w_ki) p_i, is the mean over the group's bands of p_k = sum_i w_ki p_i.
    const Vec3 w = sampleAround(layer, g, dir, u0, u1, u2, u3);
    const double t = std::max(0.5 * lengthSquared(w - dir), 1e-18);
    *weight = Spec(g.count);
    l.combined.eval(t, g.begin, g.count, weight->v.data());
    double pdf = 0;
    for (int k = 0; k < g.count; ++k) pdf += (*weight)[k];
    pdf /= g.count;
    for (int k = 0; k < g.count; ++k) (*weight)[k] = pdf > 0 ? (*weight)[k] / pdf : 0.0;
    return w;
}

Vec3 Medium::sampleAround(int layer, BandGroup g, const Vec3& dir, double u0, double u1, double u2, double u3) const {
    const MediumLayer& l = layers_[layer];
    double pdf;
    if (l.phases.size() == 1) return l.phases[0].sample(dir, u1, u2, u3, &pdf);
    double w[kMaxScatterers];
    averageWeights(l, g, w);
    size_t pick = l.phases.size() - 1;
    double acc = 0;
    for (size_t i = 0; i < l.phases.size(); ++i) {
        acc += w[i];
        if (u0 < acc) {
            pick = i;
            break;
        }
    }
    return l.phases[pick].sample(dir, u1, u2, u3, &pdf);
}

double Medium::pdfAround(int layer, BandGroup g, const Vec3& dir, const Vec3& wOut) const {
    const MediumLayer& l = layers_[layer];
    const double t = std::max(0.5 * lengthSquared(wOut - dir), 1e-18);
    double p[kMaxGroupBands];  // one scatterer: p in every band
    l.combined.eval(t, g.begin, g.count, p);
    double mean = 0;  // sum_i (mean_k w_ki) p_i
    for (int k = 0; k < g.count; ++k) mean += p[k];
    return mean / g.count;
}

double Medium::meanCosine(int layer) const {
    const MediumLayer& l = layers_[layer];
    double g = 0;
    const size_t nb = l.weights.size();
    for (size_t k = 0; k < nb; ++k)
        for (size_t i = 0; i < l.phases.size(); ++i) g += l.weights[k][i] * l.phases[i].meanCosine();
    return nb ? g / nb : 0.0;
}

}  // namespace littoral::render
