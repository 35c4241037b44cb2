#include "render/forward_tally.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/log.h"
#include "core/material_kinds.h"
#include "core/units.h"
#include "core/progress.h"
#include "render/distributed.h"
#include "render/embree_scene.h"
#include "render/photon_pass.h"

namespace littoral::render {

namespace {

// Random-stream passes of the forward tallies: far from the photon maps' (pass x 64 + band).
constexpr uint64_t kForwardPassBase = 1ull << 20;
constexpr uint64_t kForwardPilotPassBase = 1ull << 21;  // the pilot's (render/probes.cpp)
constexpr uint64_t kPilotStageStride = 1ull << 19;      // between the pilot's two stages
// Random streams of the tallies' own directions (CrossingTally::upwardSample), one per chunk: apart
// from the photons' (render/photon_pass.cpp, 2^50 + pass).
constexpr uint64_t kNextFlightStreams = (1ull << 50) + (1ull << 49);
constexpr uint64_t kChunk = 4096;  // photons per chunk (one task; sums added in chunk order)
// Weight window of the tallies' roulette: photons lose power by the albedo at each collision and
// play roulette only below a half (of the power times the importance), so that each one crosses
// the deep planes with its weight instead of ending early (survival biasing; unbiased either way).
// The splitting's importance is the profile's (E(shallowest) / E(z))^kImportanceExponent. Both were
// chosen by the time to 1 % of the worst cell (bench_forward_column, 2 x 10^6 photons, 200 batches):
// on problem 2 at albedo 0.9, a window from 0.5 and the exponent 1.25 took 25-30 % off it against
// 0.25 and 1 at 1-2 x 10^6 photons (the worst se 0.384 -> 0.328 % at 2 x 10^6), 8 % at 4 x 10^6
// (where Eou at tau 5 becomes the worst cell), and neither the stratified column nor problem 5
// lost (docs/performance.md). A lower window (0.25, 0.35) walks low-weight photons that add little;
// a higher one (0.7, 1) or a larger exponent (1.5, 2) cuts or splits more than the cells gain.
constexpr double kRouletteBelow = 0.5;
constexpr double kImportanceExponent = 1.25;

// A crossing at direction cosine mu adds w / |mu| to the scalar irradiance; the second moment of
// that is log-divergent at grazing angles (Int L / mu dmu), and one grazing photon can carry a
// batch. Below kGrazingMu the weight is 2 / kGrazingMu instead (the usual grazing correction of
// crossing tallies): the expected value is the same when L is constant over |mu| < kGrazingMu, and
// for radiance L0 + L1 mu there the difference is 2 pi L1 kGrazingMu^2 / 6, at most 1.7e-5 of
// Eo = 2 pi <L> when |L1| <= <L> (docs/rendering.md, "Forward probe tallies").
constexpr double kGrazingMu = 0.01;
// A face within this height of a flight's start is the one it leaves, not one between it and a plane.
constexpr double kFaceTol = 1e-6;

struct Level {
    int medium;
    double z;
    // The planes of the nearest horizontal faces below and above z (-/+infinity: none): a flight
    // reaches the plane only from between them. Lu: collisions between floor and z, and diffuse
    // reflections on the floor, send light up to the probe with no surface between.
    double floor = -ir::kInfinity, ceiling = ir::kInfinity;
    bool radiance = false;
};
const Vec3 kUp{0, 0, 1};

// Upward directions for the expected crossings after collisions (CrossingTally::upwardSample): mu
// with density (A / max(mu, kGrazingMu) + 1) / 2 on [0, 1] (A = 1 / (1 + ln(1 / kGrazingMu))) and a
// uniform azimuth. The first half falls as 1 / mu like the scalar irradiance's crossing weight, so
// that grazing directions are drawn as often as they weigh near a plane; the second, uniform in mu,
// serves collisions far below a plane, which reach it only steeply.
constexpr double kGrazingA = 1.0 / (1.0 + 4.605170185988091);  // ln(1 / 0.01)
static_assert(kGrazingMu == 0.01, "kGrazingA is made for kGrazingMu = 0.01");
Vec3 grazingDirection(double u0, double u1) {
    double mu;
    if (u0 < 0.5) {
        const double u = 2.0 * u0;
        mu = u < kGrazingA ? kGrazingMu * u / kGrazingA : kGrazingMu * std::exp((u - kGrazingA) / kGrazingA);
    } else {
        mu = 2.0 * u0 - 1.0;
    }
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    const CosSin phi = cosSinTurns(u1);
    return Vec3{s * phi.c, s * phi.s, mu};
}
// Its density per steradian (0 downward).
double grazingPdf(double dz) { return dz > 0 ? 0.5 * (kGrazingA / std::max(dz, kGrazingMu) + 1.0) / (2.0 * kPi) : 0.0; }

// Sums the crossings of one chunk's photons through the probe planes, per level, tally and band.
class CrossingTally final : public PhotonObserver {
public:
    CrossingTally(const Scene& scene, BandGroup g, const std::vector<Level>& levels, RandomStream rng)
        : scene_(scene), g_(g), levels_(levels), sums_(levels.size() * kTallies, Spec(g.count)), rng_(rng) {}

    void flight(const Ray& ray, double tEnd, int medium, const Spec& w, bool sampled, const Scattered* from) override {
        if (ray.d.z == 0) return;
        const Medium& md = scene_.media()[static_cast<size_t>(medium)];
        if (sampled) {
            // The expected crossings: a flight of sampled length reaches a plane at distance t with
            // probability mean_i T_i(t) and then carries w_b T_b(t) / mean_i T_i(t), so its expected
            // score is w_b T_b(t), whether or not this photon got there. Planes beyond the side
            // walls are scored by the flight that continues from the opposite wall. An upward flight
            // from a collision shares its direction's expectation with collision()'s grazing sample.
            if (!anyAhead(medium, ray.o.z, ray.d.z)) return;
            const double mis =
                from && ray.d.z > 0 ? misPhase(md, from->layer, from->dIn, ray.d, upwardProbability(md, medium, from->layer, from->z))
                                    : 1.0;
            expectedCrossings(ray, medium, w * mis, wallDistance(ray));
            return;
        }
        // The flight crosses a plane if it ends beyond it. Half-open, so that a photon turning exactly
        // on a plane is counted once.
        const double dz = ray.d.z, z0 = ray.o.z;
        const double z1 = std::isfinite(tEnd) ? z0 + tEnd * dz : (dz > 0 ? ir::kInfinity : -ir::kInfinity);
        for (size_t k = 0; k < levels_.size(); ++k) {
            const Level& l = levels_[k];
            if (l.medium != medium) continue;
            if (!(dz < 0 ? (z1 <= l.z && l.z < z0) : (z0 < l.z && l.z <= z1))) continue;
            Spec wt = w;
            if (md.attenuating()) {
                const Spec T = md.transmittance(ray, (l.z - z0) / dz, g_);
                if (!sampled) wt *= T;
                else {
                    double mean = 0;
                    for (int i = 0; i < g_.count; ++i) mean += T[i];
                    mean /= g_.count;
                    if (!(mean > 0)) continue;
                    wt *= T * (1.0 / mean);
                }
            }
            add(k, dz, wt);
        }
    }
    // Lu (nadir-viewing, light travelling up) as a collision estimator: a collision at x below the
    // plane sends w p(dIn -> up) T(x -> plane) per unit area into the upward direction at the plane
    // (w carries the albedo already), and a Lambertian floor w rho / pi T (docs/rendering.md).
    void collision(const Point3& x, const Vec3& dIn, int medium, int layer, const Spec& w) override {
        const Medium& md = scene_.media()[static_cast<size_t>(medium)];
        upwardSample(md, x, dIn, medium, layer, w);
        for (size_t k = 0; k < levels_.size(); ++k) {
            const Level& l = levels_[k];
            if (!l.radiance || l.medium != medium || !(x.z < l.z && x.z > l.floor)) continue;
            const Spec p = md.phase(layer, g_, dIn, kUp);
            sums_[k * kTallies + kLu] += w * p * md.transmittance(Ray{x, kUp}, l.z - x.z, g_);
        }
    }
    void diffuse(const SurfaceHit& h, int medium, const Spec& rho, const Spec& w) override {
        const Normal3 n = h.front ? h.ng : -h.ng;
        if (!(n.z > 0) || rho.isBlack()) return;
        const Medium& md = scene_.media()[static_cast<size_t>(medium)];
        for (size_t k = 0; k < levels_.size(); ++k) {
            const Level& l = levels_[k];
            if (!l.radiance || l.medium != medium || std::abs(h.p.z - l.floor) > 1e-6 * std::max(1.0, std::abs(l.floor)))
                continue;
            const Ray up{Point3{h.p.x, h.p.y, l.floor}, kUp};
            sums_[k * kTallies + kLu] += w * rho * (1.0 / kPi) * md.transmittance(up, l.z - l.floor, g_);
        }
    }
    void cut(const Spec& w) override {
        ++cuts_;
        (void)w;
    }
    const std::vector<Spec>& sums() const { return sums_; }
    uint64_t cuts() const { return cuts_; }

private:
    void add(size_t k, double dz, const Spec& wt) {
        const size_t base = k * kTallies;
        const double inv = std::abs(dz) >= kGrazingMu ? 1.0 / std::abs(dz) : 2.0 / kGrazingMu;
        sums_[base + (dz < 0 ? kEd : kEu)] += wt;
        sums_[base + (dz < 0 ? kEod : kEou)] += wt * inv;
    }
    // Whether a straight flight from height z0 in `medium`, going up (dz > 0) or down, reaches
    // plane l with no face between.
    static bool ahead(const Level& l, int medium, double z0, double dz) {
        return l.medium == medium &&
               (dz < 0 ? l.z < z0 && l.ceiling >= z0 - kFaceTol : l.z > z0 && l.floor <= z0 + kFaceTol);
    }
    bool anyAhead(int medium, double z0, double dz) const {
        for (const Level& l : levels_)
            if (ahead(l, medium, z0, dz)) return true;
        return false;
    }
    // Adds w_b T_b(t) at every plane of `medium` that a straight flight from ray.o reaches within
    // tMax with no face between.
    void expectedCrossings(const Ray& ray, int medium, const Spec& w, double tMax) {
        const double dz = ray.d.z, z0 = ray.o.z;
        const Medium& md = scene_.media()[static_cast<size_t>(medium)];
        for (size_t k = 0; k < levels_.size(); ++k) {
            const Level& l = levels_[k];
            if (!ahead(l, medium, z0, dz)) continue;
            const double t = (l.z - z0) / dz;
            if (t > tMax) continue;
            add(k, dz, w * md.transmittance(ray, t, g_));
        }
    }
    // Upward light after a collision. A forward-peaked phase function sends few photons up (Petzold:
    // 2 %), so the upward planes' expected crossings of the flight after a collision are estimated
    // from two directions: the flight's own, drawn from the phase function (density q1 = the band
    // mean of p, Medium::pdfAround), and one drawn here from the grazing density q2
    // (grazingDirection), combined by the balance heuristic: each scores w p S / (q1 + q2), the
    // flight through its weight w p / q1 times q1 / (q1 + q2) (misPhase). Downward planes are scored
    // by the flight alone.
    //
    // The second direction is drawn with probability P (upwardProbability): 1 within one attenuation
    // length of the lowest plane above the collision, e^(1 - c dz) beyond, so that collisions far
    // below every plane, whose upward light hardly reaches one, do not pay for it. With the second
    // strategy taken with probability P, the balance heuristic's densities are q1 and P q2: the
    // drawn direction scores w p S / (q1 + P q2) and the flight is weighted q1 / (q1 + P q2), which
    // keeps the sum's expectation (E = Int f q1 / (q1 + P q2) + P Int f q2 / (q1 + P q2) = Int f).
    double misPhase(const Medium& md, int layer, const Vec3& dIn, const Vec3& d, double P) const {
        const double q1 = md.pdfAround(layer, g_, dIn, d);
        return q1 / (q1 + P * grazingPdf(d.z));
    }
    // P for a collision at height z in `layer` of `medium` (0 with no plane above it); c is the
    // layer's smallest extinction over the group's bands. Asked twice per collision (its upward
    // sample, then the flight that leaves it), so the last answer is kept.
    double upwardProbability(const Medium& md, int medium, int layer, double z) {
        if (z == memo_.z && layer == memo_.layer && medium == memo_.medium) return memo_.P;
        memo_ = {z, layer, medium, upwardProbabilityOf(md, medium, layer, z)};
        return memo_.P;
    }
    double upwardProbabilityOf(const Medium& md, int medium, int layer, double z) const {
        double dz = ir::kInfinity;
        for (const Level& l : levels_)
            if (ahead(l, medium, z, 1.0)) dz = std::min(dz, l.z - z);
        if (!std::isfinite(dz)) return 0.0;
        const MediumLayer& ml = md.layers()[static_cast<size_t>(layer)];
        double c = ir::kInfinity;
        for (int i = 0; i < g_.count; ++i) c = std::min(c, ml.c[g_.begin + i]);
        const double x = c * dz;
        return x <= 1.0 ? 1.0 : std::exp(1.0 - x);
    }
    void upwardSample(const Medium& md, const Point3& x, const Vec3& dIn, int medium, int layer, const Spec& w) {
        const double P = upwardProbability(md, medium, layer, x.z);
        if (!(P > 0) || (P < 1.0 && rng_.uniform() >= P)) return;
        const double v0 = rng_.uniform(), v1 = rng_.uniform();
        const Vec3 d = grazingDirection(v0, v1);
        const Spec p = md.phase(layer, g_, dIn, d);
        double q1 = 0;  // Medium::pdfAround, from the values at hand
        for (int i = 0; i < g_.count; ++i) q1 += p[i];
        q1 /= g_.count;
        expectedCrossings(Ray{x, d}, medium, w * p * (1.0 / (q1 + P * grazingPdf(d.z))), ir::kInfinity);
    }

    // The distance along `ray` to the domain's side walls, where a periodic photon wraps and goes
    // on as a new flight. (Embree places the wall hit within ~1e-5 m of it, so a plane within that
    // sliver of a wrap may be scored twice or not at all: a bias of that order relative to the
    // flight's length, ~1e-5.)
    double wallDistance(const Ray& ray) const {
        const ir::Domain& D = scene_.ir().domain;
        double t = ir::kInfinity;
        if (ray.d.x != 0) t = std::min(t, ((ray.d.x > 0 ? D.x1 : D.x0) - ray.o.x) / ray.d.x);
        if (ray.d.y != 0) t = std::min(t, ((ray.d.y > 0 ? D.y1 : D.y0) - ray.o.y) / ray.d.y);
        return std::max(t, 0.0);
    }

    const Scene& scene_;
    BandGroup g_;
    const std::vector<Level>& levels_;
    std::vector<Spec> sums_;
    uint64_t cuts_ = 0;
    RandomStream rng_;
    struct {
        double z = std::numeric_limits<double>::quiet_NaN();  // equal to no height
        int layer = -1, medium = -1;
        double P = 0;
    } memo_;
};

// A horizontal face's plane, material and media: the faces of one level together must cover the
// domain once.
struct LevelKey {
    double z;
    std::string material, inside, outside;
    bool operator<(const LevelKey& o) const {
        return std::tie(z, material, inside, outside) < std::tie(o.z, o.material, o.inside, o.outside);
    }
};

// Why one mesh breaks horizontal invariance (""), adding its horizontal faces' areas per level.
std::string meshProblem(const ir::SceneIR& ir, const ir::Mesh& mesh, std::map<LevelKey, double>* levels) {
    const TriMesh& m = mesh.data;
    for (size_t f = 0; f < m.numTriangles(); ++f) {
        const size_t slot = m.materialOf(f);
        const std::string name = slot < mesh.materials.size() ? mesh.materials[slot] : std::string();
        const ir::Material* mat = ir.findMaterial(name);
        if (!mat) return fmt::format("mesh '{}' face {} has no material", mesh.name, f);
        if (mat->type == ir::Material::Type::Periodic) continue;
        if (mat->type == ir::Material::Type::Textured || mat->type == ir::Material::Type::Classified)
            return fmt::format("mesh '{}' uses material '{}', which varies across the plane", mesh.name, name);
        const Vec3 n = m.faceNormalArea(f);
        const double len = length(n);
        if (!(len > 0)) continue;  // degenerate: no area
        const auto& tri = m.triangles[f];
        const double z = m.positions[tri[0]].z;
        if (std::abs(n.x) + std::abs(n.y) > 1e-9 * len || std::abs(m.positions[tri[1]].z - z) > 1e-9 ||
            std::abs(m.positions[tri[2]].z - z) > 1e-9)
            return fmt::format("mesh '{}' face {} is not horizontal", mesh.name, f);
        (*levels)[LevelKey{z, name, mesh.inside, mesh.outside}] += 0.5 * len;
    }
    return "";
}

}  // namespace

namespace {

// As horizontalInvarianceProblem; *levels receives the horizontal faces' planes.
std::string invarianceProblem(const ir::SceneIR& ir, std::map<LevelKey, double>* faces) {
    if (!ir.domain.periodic) return "the domain is not periodic (water.horizontal: periodic)";
    if (!ir.instances.empty()) return fmt::format("the scene places {} mesh instance(s) (objects)", ir.instances.size());
    const double area = (ir.domain.x1 - ir.domain.x0) * (ir.domain.y1 - ir.domain.y0);
    std::map<LevelKey, double>& levels = *faces;
    for (const ir::Mesh& mesh : ir.meshes) {
        const std::string p = meshProblem(ir, mesh, &levels);
        if (!p.empty()) return p;
    }
    for (const auto& [key, a] : levels)
        if (std::abs(a - area) > 1e-6 * area)
            return fmt::format("the horizontal faces of material '{}' at z = {:g} m cover {:.6g} m^2 of the domain's "
                               "{:.6g} m^2",
                               key.material, key.z, a, area);
    return "";
}

}  // namespace

std::string horizontalInvarianceProblem(const ir::SceneIR& ir) {
    std::map<LevelKey, double> faces;
    return invarianceProblem(ir, &faces);
}

bool horizontalFacePlanes(const ir::SceneIR& ir, std::vector<double>* planes) {
    std::map<LevelKey, double> faces;
    if (!invarianceProblem(ir, &faces).empty()) return false;
    planes->clear();
    for (const auto& [key, a] : faces)
        if (planes->empty() || planes->back() != key.z) planes->push_back(key.z);  // the keys sort by z first
    return true;
}

namespace {

// The plane of the highest horizontal face below z (-infinity: none), and whether that face only
// reflects diffusely or absorbs (then Lu at z comes from the water between and that floor alone).
std::pair<double, bool> floorBelow(const ir::SceneIR& ir, const std::map<LevelKey, double>& faces, double z) {
    double floor = -ir::kInfinity;
    bool diffuseOnly = true;
    for (const auto& [key, a] : faces) {
        if (!(key.z < z) || key.z < floor) continue;
        const ir::Material* mat = ir.findMaterial(key.material);
        const bool d = mat && !(materialKind(mat->type).lobes & (kTransmission | kSpecular | kGlossy));
        diffuseOnly = key.z > floor ? d : diffuseOnly && d;
        floor = key.z;
    }
    return {floor, diffuseOnly};
}

// The plane of the lowest horizontal face above z (+infinity: none).
double ceilingAbove(const std::map<LevelKey, double>& faces, double z) {
    double ceiling = ir::kInfinity;
    for (const auto& [key, a] : faces)
        if (key.z > z) ceiling = std::min(ceiling, key.z);
    return ceiling;
}

// Whether every phase function of the medium is finite in the exact forward direction. Lu's
// collision weights w p(d -> up) have a finite variance only then: Petzold and Fournier-Forand
// rise as a power of the angle, p ~ psi^-1.35 (Petzold), and Int p^2 dw diverges at psi = 0.
bool boundedForwardPeak(const Medium& md) {
    for (const MediumLayer& l : md.layers())
        for (const PhaseFunction& p : l.phases)
            if (!std::isfinite(p.evalOneMinusCos(0.0))) return false;
    return true;
}

// Whether the forward tallies answer quantity `q` of a probe at depth z in `medium`: Ed, Eu, Eod
// and Eou in a scattering medium; Lu too when the face below it only reflects diffusely and the
// medium's phase functions are bounded.
bool answers(const Scene& scene, const std::map<LevelKey, double>& faces, const std::string& q, int medium, double z) {
    if (!(medium > 0 && scene.media()[static_cast<size_t>(medium)].scattering()) || tallyOf(q) < 0) return false;
    return q != "Lu" ||
           (boundedForwardPeak(scene.media()[static_cast<size_t>(medium)]) && floorBelow(scene.ir(), faces, z).second);
}

// The planes: one per (medium, depth) that some answered quantity reads, and for each answered
// (probe, quantity) its plane.
struct Plan {
    std::vector<Level> levels;
    std::vector<std::tuple<int, std::string, size_t>> asked;  // probe, quantity, level
};
Plan planOf(const Scene& scene, const std::set<std::pair<int, std::string>>& only) {
    Plan plan;
    const ir::SceneIR& ir = scene.ir();
    std::map<LevelKey, double> faces;
    if (!invarianceProblem(ir, &faces).empty()) return plan;
    for (size_t i = 0; i < ir.probes.size(); ++i) {
        const ir::Probe& p = ir.probes[i];
        const int medium = scene.mediumIndex(p.medium, fmt::format("probe '{}' medium", p.name));
        for (const std::string& q : p.quantities) {
            if (!answers(scene, faces, q, medium, p.position.z)) continue;
            if (!only.empty() && !only.count({static_cast<int>(i), q})) continue;
            size_t k = 0;
            while (k < plan.levels.size() && !(plan.levels[k].medium == medium && plan.levels[k].z == p.position.z)) ++k;
            if (k == plan.levels.size())
                plan.levels.push_back({medium, p.position.z, floorBelow(ir, faces, p.position.z).first,
                                       ceilingAbove(faces, p.position.z)});
            if (q == "Lu") plan.levels[k].radiance = true;
            plan.asked.emplace_back(static_cast<int>(i), q, k);
        }
    }
    return plan;
}

// How the photons are cut: B batches of perBatch photons, in chunks of at most kChunk.
struct Batches {
    int B;
    uint64_t perBatch, chunksPerBatch;
    size_t chunks() const { return static_cast<size_t>(chunksPerBatch) * static_cast<size_t>(B); }
};

// The tallies of one band group: per chunk, per level and tally, the band sums (scaled to
// irradiance); photons cut at max_bounces are added to *cuts. Shared by the ranks.
std::vector<std::vector<Spec>> tallyGroup(const Scene& scene, const EstimatorSet& estimators, BandGroup g,
                                          const std::vector<Level>& levels, const Batches& bt, const ForwardTallyRun& run,
                                          tbb::task_arena& arena, Progress* progress, uint64_t* cuts) {
    const RenderConfig& cfg = estimators.config();
    PhotonPassSettings ps;
    ps.seed = scene.ir().render.seed;
    ps.pass = (run.pilot ? kForwardPilotPassBase + static_cast<uint64_t>(run.pilotStage) * kPilotStageStride : kForwardPassBase) +
              static_cast<uint64_t>(estimators.pass()) * 64 + static_cast<uint64_t>(g.begin);
    ps.maxBounces = cfg.maxBounces;
    ps.maxSpecularDepth = cfg.maxSpecularDepth;
    ps.importance = false;
    ps.rouletteBelow = kRouletteBelow;
    // Below the deepest plane the importance falls at the profile's last attenuation
    // (DepthImportance::fromProfile): on problem 2 that cut the collisions by 19 % for a 3.5 % larger
    // se of Eou at tau 10 (bench_forward_column, docs/performance.md).
    ps.depthImportance = DepthImportance::fromProfile(run.profile, kImportanceExponent, 1e4, true);
    const ObservedPhotons tracer(scene, g, ps);
    const PhotonSource& src = tracer.source();
    const double scale = src.area > 0 ? src.meanFlux / src.area : 0.0;  // W um^-1 m^-2 per unit relative power
    const size_t n = bt.chunks(), values = levels.size() * kTallies;
    std::vector<std::vector<Spec>> chunkSums(n);
    std::vector<uint64_t> chunkCuts(n, 0);
    auto sumChunk = [&](size_t c) {
        const uint64_t batch = c / bt.chunksPerBatch, k0 = (c % bt.chunksPerBatch) * kChunk;
        const uint64_t k1 = std::min(bt.perBatch, k0 + kChunk);
        CrossingTally tally(scene, g, levels, RandomStream(ps.seed, kNextFlightStreams + ps.pass, c));
        if (scale > 0)
            for (uint64_t k = k0; k < k1; ++k) tracer.trace(batch * bt.perBatch + k, tally);
        chunkSums[c] = tally.sums();
        for (Spec& x : chunkSums[c]) x *= scale;
        chunkCuts[c] = tally.cuts();
        flushRayStats();
        if (progress) progress->advance();
    };
    distributeItems(
        n, 0, ShareWith::AllRanks,
        [&](uint64_t c0, uint64_t c1) {
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<size_t>(c0, c1, 1), [&](const tbb::blocked_range<size_t>& r) {
                    for (size_t c = r.begin(); c != r.end(); ++c) sumChunk(c);
                });
            });
        },
        [&](uint64_t c, ByteWriter& w) {
            w.put(chunkCuts[c]);
            for (const Spec& s : chunkSums[c])
                for (int b = 0; b < g.count; ++b) w.put(s[b]);
        },
        [&](uint64_t c, ByteReader& r) {
            chunkCuts[c] = r.get<uint64_t>();
            chunkSums[c].assign(values, Spec(g.count));
            for (Spec& s : chunkSums[c])
                for (int b = 0; b < g.count; ++b) s[b] = r.get<double>();
        });
    for (uint64_t x : chunkCuts) *cuts += x;
    return chunkSums;
}

// Per plane (z, E): the weakest band-mean irradiance asked there (Ed, Eu, Eod or Eou), or the scalar
// irradiance Eod + Eou where only Lu is. Splitting by depth with I ~ 1 / E sends photons where the
// faintest answer needs them: over a black bottom Eou falls 8 times faster with depth than Eod
// (the stratified column: 3 x 10^-4 against 2.4 x 10^-3 from 5 to 59 m), and splitting by Eo left
// Eou at 59 m with 4.5 times the variance for 0.9 times the time.
std::vector<std::pair<double, double>> weakestAsked(const Plan& plan, const std::vector<ProbeValue>& tallied, int nb) {
    auto bandMean = [&](size_t k, int tally) {
        double m = 0;
        for (int b = 0; b < nb; ++b) m += tallied[k * kTallies + static_cast<size_t>(tally)].mean[b] / nb;
        return m;
    };
    std::vector<std::pair<double, double>> profile;
    for (size_t k = 0; k < plan.levels.size(); ++k) {
        double weakest = ir::kInfinity;
        for (const auto& [i, q, level] : plan.asked)
            if (level == k && q != "Lu") weakest = std::min(weakest, bandMean(k, tallyOf(q)));
        profile.emplace_back(plan.levels[k].z, std::isfinite(weakest) ? weakest : bandMean(k, kEod) + bandMean(k, kEou));
    }
    return profile;
}

}  // namespace

ForwardTallies::ForwardTallies(const Scene& scene, const EstimatorSet& estimators, const RenderOptions& opts,
                               const ForwardTallyRun& run) {
    const RenderConfig& cfg = estimators.config();
    const ir::SceneIR& ir = scene.ir();
    if (cfg.estimator != ir::Estimator::Path || cfg.probePhotons == 0) return;
    const Plan plan = planOf(scene, run.only);
    if (plan.asked.empty()) return;
    const int B = run.batches > 0 ? run.batches : cfg.probeBatches;
    const uint64_t perBatch = std::max<uint64_t>(1, (run.photons > 0 ? run.photons : cfg.probePhotons) / static_cast<uint64_t>(B));
    const Batches bt{B, perBatch, (perBatch + kChunk - 1) / kChunk};
    const uint64_t photons = perBatch * static_cast<uint64_t>(B);
    const int nb = scene.bandCount();
    const size_t values = plan.levels.size() * kTallies;
    std::vector<ProbeValue> tallied(values);  // per level and tally: mean and se for every band
    for (ProbeValue& v : tallied) v.mean.assign(nb, 0.0), v.stderr_.assign(nb, 0.0);
    std::unique_ptr<Progress> progress;
    if (opts.progress && !run.pilot) progress = std::make_unique<Progress>("forward probe tallies", bt.chunks() * estimators.size(), "chunks");
    tbb::task_arena arena(opts.threads > 0 ? opts.threads : tbb::task_arena::automatic);
    uint64_t cuts = 0;
    for (size_t gi = 0; gi < estimators.size(); ++gi) {
        const BandGroup g = estimators.groups()[gi];
        const auto chunkSums = tallyGroup(scene, estimators, g, plan.levels, bt, run, arena, progress.get(), &cuts);
        for (size_t v = 0; v < values; ++v) {
            std::vector<Spec> sums(chunkSums.size());
            for (size_t c = 0; c < chunkSums.size(); ++c) sums[c] = chunkSums[c][v];
            batchStatistics(sums, B, static_cast<int>(bt.chunksPerBatch), static_cast<double>(perBatch), g, &tallied[v]);
        }
    }
    if (progress) progress->finish();
    const uint64_t traced = photons * estimators.size();
    if (!run.pilot && static_cast<double>(cuts) > 1e-4 * static_cast<double>(traced))
        log::warn("{} of the forward probe tallies' {} photons reached render.max_bounces = {} with power left and were "
                  "ended: the probes' irradiances are low. Raise render.max_bounces",
                  cuts, traced, cfg.maxBounces);
    profile_ = weakestAsked(plan, tallied, nb);
    for (const auto& [i, q, k] : plan.asked) {
        const ir::Probe& p = ir.probes[static_cast<size_t>(i)];
        ProbeValue v = tallied[k * kTallies + static_cast<size_t>(tallyOf(q))];
        v.probe = p.name;
        v.quantity = q;
        v.units = q == "Lu" ? "W m^-2 sr^-1 um^-1" : "W m^-2 um^-1";
        v.position = p.position;
        v.medium = p.medium.empty() ? "air" : p.medium;
        v.samples = static_cast<int64_t>(photons);
        v.batches = B;
        v.method = "forward";
        set(i, q, std::move(v));
    }
}


}  // namespace littoral::render
