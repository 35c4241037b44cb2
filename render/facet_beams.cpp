#include "render/facet_beams.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"
#include "core/frame.h"
#include "core/log.h"
#include "core/units.h"
#include "render/bxdf_types.h"
#include "render/scene.h"

namespace littoral::render {

namespace {

constexpr int kRim = 8;                 // disc rim directions sampled for a footprint's extent
constexpr double kRimMargin = 1.15;     // the rim's polygon inscribes the disc: widen it
constexpr int kMaxSlabs = 128;
constexpr double kMaxCells = 1 << 22;     // 16 MB of cell offsets
constexpr double kMaxEntries = 1 << 23;   // 96 MB of facet lists (12 B each)
constexpr int kMaxCellsPerAxis = 4096;

// The directions whose footprints bound a facet's beams over the disc: the centre and the rim.
std::array<Vec3, kRim + 1> discDirections(const Vec3& sun, double halfAngle) {
    std::array<Vec3, kRim + 1> w;
    w[0] = sun;
    const Frame f = Frame::fromNormal(sun);
    const double a = std::min(0.5, halfAngle * kRimMargin), s = std::sin(a), c = std::cos(a);
    for (int k = 0; k < kRim; ++k) {
        const double phi = 2 * M_PI * k / kRim;
        w[static_cast<size_t>(k + 1)] = normalize(f.toWorld(Vec3{s * std::cos(phi), s * std::sin(phi), c}));
    }
    return w;
}

double wrapInto(double v, double lo, double period) { return v - period * std::floor((v - lo) / period); }

}  // namespace

FacetBeams::FacetBeams(const Scene& scene, int medium, const std::vector<double>& index,
                       const std::vector<bool>& skyMedia, const Vec3& sunDir, double halfAngle, int maxOrder)
    : eta_(1.0 / index[static_cast<size_t>(medium)]), periodic_(scene.domain().periodic) {
    const ir::Domain& dom = scene.domain();
    px_ = dom.x1 - dom.x0, py_ = dom.y1 - dom.y0;
    auto sky = [&](int m) { return skyMedia[static_cast<size_t>(m)]; };
    const double minCos = -std::sin(std::min(0.5, halfAngle * kRimMargin));
    scene.geometry().forEachTriangle([&](int mesh, int inst, uint32_t face, const Point3& a, const Point3& b,
                                         const Point3& c) {
        const int in = scene.insideMedium(mesh), out = scene.outsideMedium(mesh);
        if (in != medium && out != medium) return;
        SurfaceHit h;
        h.mesh = mesh, h.instance = inst, h.face = face;
        h.slot = scene.ir().meshes[static_cast<size_t>(mesh)].data.materialOf(face);
        h.p = (a + b + c) * (1.0 / 3.0);
        const MaterialData& m = scene.material(h);
        if (!m.isInterface()) return;
        const bool skyOut = sky(out) && in == medium, skyIn = sky(in) && out == medium;
        if (!skyOut && !skyIn) {
            if (in != out) objects_ = true;  // an interface to another dense medium (a dielectric object)
            return;
        }
        if (m.isRough()) return;
        const Vec3 N = cross(b - a, c - a);
        const double len = length(N);
        if (!(len > 0)) return;
        const Normal3 nAir = N * ((skyOut ? 1.0 : -1.0) / len);
        if (dot(nAir, sunDir) <= minCos) return;  // the disc cannot light this side
        const double extent = std::max({std::max({a.x, b.x, c.x}) - std::min({a.x, b.x, c.x}),
                                        std::max({a.y, b.y, c.y}) - std::min({a.y, b.y, c.y})});
        facets_.push_back({a, b, c, nAir, mesh, inst, face, extent, extent > 0.25 * std::min(px_, py_)});
        horizontal_ = horizontal_ && std::abs(nAir.z) >= 1 - 1e-12;
    });
    // Flat water without objects is not indexed: its beams are the straight path's, which
    // SunConnection traces.
    if (!facets_.empty() && (!horizontal_ || objects_)) build(sunDir, halfAngle, scene.geometry().bounds().lo.z, dom);
    if (objects_ && maxOrder > 1) buildChains(scene, medium, index, skyMedia, sunDir, halfAngle, maxOrder);
}

int FacetBeams::chainOf(int j, std::array<int, kMaxChainOrder>* links) const {
    int n = 0;
    for (int l = j; l >= 0; l = links_[static_cast<size_t>(l)].parent) (*links)[static_cast<size_t>(n++)] = l;
    return n;
}

int FacetBeams::faces(int i, std::array<BeamFace, kMaxChainOrder>* out) const {
    const int nf = static_cast<int>(facets_.size());
    if (i < nf) {
        const BeamFacet& f = facets_[static_cast<size_t>(i)];
        (*out)[0] = {f.mesh, f.instance, f.face};
        return 1;
    }
    std::array<int, kMaxChainOrder> chain{};
    const int n = chainOf(finals_[static_cast<size_t>(i - nf)], &chain);
    for (int k = 0; k < n; ++k) {
        const BeamLink& l = links_[static_cast<size_t>(chain[static_cast<size_t>(k)])];
        (*out)[static_cast<size_t>(k)] = {l.mesh, l.instance, l.face};
    }
    return n;
}

namespace {
// The direction light travelling along t takes across a face with unit normal nFrom on its side
// (eta = n_from / n_to); false if it does not cross from that side or reflects totally.
bool crossFace(const Vec3& t, const Normal3& nFrom, double eta, Vec3* out) {
    if (!(dot(t, nFrom) < 0)) return false;
    Vec3 wt;
    if (!refract(-t, nFrom, eta, &wt)) return false;
    *out = normalize(wt);
    return true;
}

bool inTriangle(const Point3& q, const Point3& a, const Point3& b, const Point3& c) {
    const Vec3 N = cross(b - a, c - a);
    return dot(cross(b - a, q - a), N) >= 0 && dot(cross(c - b, q - b), N) >= 0 && dot(cross(a - c, q - c), N) >= 0;
}
}  // namespace

bool FacetBeams::chainDirections(int j, const Vec3& ws, std::array<Vec3, kMaxChainOrder>* d) const {
    std::array<int, kMaxChainOrder> chain{};
    const int n = chainOf(j, &chain);
    Vec3 t = -ws;
    for (int i = n - 1, o = 0; i >= 0; --i, ++o) {
        const BeamLink& L = links_[static_cast<size_t>(chain[static_cast<size_t>(i)])];
        if (!crossFace(t, L.nFrom, L.eta, &t)) return false;
        (*d)[static_cast<size_t>(o)] = t;
    }
    return true;
}

double FacetBeams::weight(int i, const Vec3& ws) const {
    // The faces beam i crosses, first face first: the facet, or the chain's links from its root.
    const int nf = static_cast<int>(facets_.size());
    std::array<std::pair<Normal3, double>, kMaxChainOrder> faces;  // normal on the incoming side, eta
    int n = 1;
    if (i < nf) {
        faces[0] = {facets_[static_cast<size_t>(i)].nAir, eta_};
    } else {
        std::array<int, kMaxChainOrder> chain{};
        n = chainOf(finals_[static_cast<size_t>(i - nf)], &chain);
        for (int k = 0; k < n; ++k) {
            const BeamLink& l = links_[static_cast<size_t>(chain[static_cast<size_t>(n - 1 - k)])];
            faces[static_cast<size_t>(k)] = {l.nFrom, l.eta};
        }
    }
    double w = 1;
    Vec3 t = -ws;
    for (int k = 0; k < n; ++k) {
        const auto& [nFrom, eta] = faces[static_cast<size_t>(k)];
        const double cosI = -dot(t, nFrom);
        if (!crossFace(t, nFrom, eta, &t)) return 0;
        const double cosT = -dot(t, nFrom);
        if (!(cosT > 0)) return 0;
        w *= (1.0 - fresnelDielectric(cosI, eta, 1.0)) * cosI / cosT;
    }
    return w;
}

bool FacetBeams::chainContains(int j, const Point3& p, const Vec3& ws, Vec3* d, double* s) const {
    std::array<Vec3, kMaxChainOrder> dirs;
    if (!chainDirections(j, ws, &dirs)) return false;
    const int n = links_[static_cast<size_t>(j)].order;
    // Back from p along each leg to the face that sent it, the parent's image moved by the shifts.
    Point3 x = p;
    Vec3 S{0, 0, 0};
    int o = n - 1;
    for (int l = j; l >= 0; l = links_[static_cast<size_t>(l)].parent, --o) {
        const BeamLink& L = links_[static_cast<size_t>(l)];
        const Vec3& t = dirs[static_cast<size_t>(o)];
        const double dn = dot(L.nFrom, t);  // < 0 (crossFace)
        const double tau = dot(L.nFrom, x - (L.a + S)) / dn;
        if (!(tau > 0)) return false;
        const Point3 q = x - t * tau;
        if (!inTriangle(q, L.a + S, L.b + S, L.c + S)) return false;
        if (l == j) *s = tau;
        x = q;
        S = S + L.shift;
    }
    *d = dirs[static_cast<size_t>(n - 1)];
    return true;
}

namespace {
constexpr size_t kMaxLinks = 200000;

// The beam's directions over the disc (NaN where a direction makes none): their mean and the
// largest angle of one from it, widened by 1.25 (the rim is sampled at kRim points, and the image of
// the disc between two of them bulges past their chord, more where a refraction is near critical).
struct Spread {
    Vec3 mean;
    double tanAngle = 0;
};
Spread spreadOf(const std::array<Vec3, kRim + 1>& t) {
    Vec3 sum{0, 0, 0};
    for (const Vec3& d : t)
        if (!std::isnan(d.x)) sum = sum + d;
    Spread s;
    s.mean = normalize(sum);
    double cosMin = 1;
    for (const Vec3& d : t)
        if (!std::isnan(d.x)) cosMin = std::min(cosMin, dot(d, s.mean));
    const double angle = std::min(1.25 * std::acos(std::clamp(cosMin, -1.0, 1.0)), 1.4);
    s.tanAngle = std::tan(angle);
    return s;
}

std::array<Point3, 8> corners(const BBox3& b) {
    std::array<Point3, 8> c;
    for (int k = 0; k < 8; ++k)
        c[static_cast<size_t>(k)] = {(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
    return c;
}

// A box around a beam: the corners of the box of the face's lit part swept along each of its
// directions to the scene's box (in a periodic domain only its top and bottom end the sweep,
// capped at `cap`), widened by what the directions between the sampled ones may add.
BBox3 sweptBox(const BeamLink& L, const std::array<Vec3, kRim + 1>& dirs, const BBox3& scene, bool periodic,
               double cap) {
    BBox3 box;
    double longest = 0;
    for (const Point3& v : corners(L.faceBox)) {
        box.expand(v);
        for (const Vec3& d : dirs) {
            if (std::isnan(d.x)) continue;
            double t = cap;
            for (int axis = periodic ? 2 : 0; axis < 3; ++axis) {
                const double dv = axis == 0 ? d.x : axis == 1 ? d.y : d.z, pv = axis == 0 ? v.x : axis == 1 ? v.y : v.z;
                const double lo = axis == 0 ? scene.lo.x : axis == 1 ? scene.lo.y : scene.lo.z;
                const double hi = axis == 0 ? scene.hi.x : axis == 1 ? scene.hi.y : scene.hi.z;
                if (dv > 0) t = std::min(t, std::max(0.0, (hi - pv) / dv));
                if (dv < 0) t = std::min(t, std::max(0.0, (lo - pv) / dv));
            }
            box.expand(v + d * t);
            longest = std::max(longest, t);
        }
    }
    const double e = 1e-6 * (1 + length(box.extent())) + 0.25 * longest * spreadOf(dirs).tanAngle;
    box.lo = box.lo - Vec3{e, e, e}, box.hi = box.hi + Vec3{e, e, e};
    return box;
}

bool boxesOverlap(const BBox3& a, const BBox3& b, const Vec3& shiftB) {
    return a.lo.x <= b.hi.x + shiftB.x && b.lo.x + shiftB.x <= a.hi.x && a.lo.y <= b.hi.y + shiftB.y &&
           b.lo.y + shiftB.y <= a.hi.y && a.lo.z <= b.hi.z + shiftB.z && b.lo.z + shiftB.z <= a.hi.z;
}

// Can the beam of L (its image moved by S), along any of its directions, reach face F (vertices
// fa, fb, fc, crossed from the side nFrom)? Conservative: across the mean direction, F's bounding
// rectangle overlaps L's widened by how far the other directions drift over the distance between
// them, F lies ahead of L, and some direction crosses F from the side nFrom.
bool beamReaches(const BeamLink& L, const Vec3& S, const std::array<Vec3, kRim + 1>& dirs, const Point3& fa,
                 const Point3& fb, const Point3& fc, const Normal3& nFrom) {
    bool crosses = false;
    for (const Vec3& d : dirs) crosses = crosses || (!std::isnan(d.x) && dot(d, nFrom) < 0);
    if (!crosses) return false;
    const Spread sp = spreadOf(dirs);
    const Frame f = Frame::fromNormal(sp.mean);
    double l[5] = {ir::kInfinity, -ir::kInfinity, ir::kInfinity, -ir::kInfinity, ir::kInfinity};
    double r[5] = {ir::kInfinity, -ir::kInfinity, ir::kInfinity, -ir::kInfinity, -ir::kInfinity};
    for (const Point3& v : {L.a + S, L.b + S, L.c + S}) {
        const Vec3 q = f.toLocal(v - Point3{0, 0, 0});
        l[0] = std::min(l[0], q.x), l[1] = std::max(l[1], q.x), l[2] = std::min(l[2], q.y), l[3] = std::max(l[3], q.y);
        l[4] = std::min(l[4], q.z);
    }
    for (const Point3& v : {fa, fb, fc}) {
        const Vec3 q = f.toLocal(v - Point3{0, 0, 0});
        r[0] = std::min(r[0], q.x), r[1] = std::max(r[1], q.x), r[2] = std::min(r[2], q.y), r[3] = std::max(r[3], q.y);
        r[4] = std::max(r[4], q.z);
    }
    const double e = 1e-6 * (1 + length(fa - L.a - S));
    if (!(r[4] > l[4] - e)) return false;  // F lies behind L
    const double m = e + (r[4] - l[4]) * sp.tanAngle;
    return l[0] <= r[1] + m && r[0] <= l[1] + m && l[2] <= r[3] + m && r[2] <= l[3] + m;
}
}  // namespace

namespace {
// The enumeration of chains: every smooth face the sun lights from the air starts one (a root),
// and each link is carried to every face between two dense media its beam can reach.
struct ChainBuilder {
    struct DenseFace {
        Point3 a, b, c;
        Normal3 nOut;
        int mesh, instance;
        uint32_t face;
        int in, out;
    };
    BBox3 bounds;
    double cap = 0;
    bool periodic = false;
    std::vector<Vec3> shifts{Vec3{0, 0, 0}};  // the periodic images tried
    std::vector<DenseFace> dense;             // smooth faces between two dense media
    std::vector<BeamLink> links;
    std::vector<std::array<Vec3, kRim + 1>> travel;  // per link, its direction for each disc direction

    // Adds L if light arriving along `before` (toward the sun for a root) crosses it for some disc
    // direction.
    void add(BeamLink L, const std::array<Vec3, kRim + 1>& before, bool root) {
        std::array<Vec3, kRim + 1> t;
        bool any = false;
        for (size_t k = 0; k < t.size(); ++k) {
            const bool ok = !std::isnan(before[k].x) && crossFace(root ? -before[k] : before[k], L.nFrom, L.eta, &t[k]);
            if (!ok) t[k] = Vec3{NAN, NAN, NAN};
            any = any || ok;
        }
        if (!any) return;
        if (L.faceBox.empty())
            for (const Point3& v : {L.a, L.b, L.c}) L.faceBox.expand(v);
        L.box = sweptBox(L, t, bounds, periodic, cap);
        const Spread sp = spreadOf(t);
        L.mean = sp.mean, L.tanSpread = sp.tanAngle;
        links.push_back(L);
        travel.push_back(t);
    }

    void collect(const Scene& scene, const std::vector<double>& index, const std::vector<bool>& sky,
                 const std::array<Vec3, kRim + 1>& dirs, double minCos) {
        scene.geometry().forEachTriangle([&](int mesh, int inst, uint32_t face, const Point3& a, const Point3& b,
                                             const Point3& c) {
            const int in = scene.insideMedium(mesh), out = scene.outsideMedium(mesh);
            const bool skyIn = sky[static_cast<size_t>(in)], skyOut = sky[static_cast<size_t>(out)];
            if (in == out || (skyIn && skyOut)) return;
            SurfaceHit h;
            h.mesh = mesh, h.instance = inst, h.face = face;
            h.slot = scene.ir().meshes[static_cast<size_t>(mesh)].data.materialOf(face);
            h.p = (a + b + c) * (1.0 / 3.0);
            const MaterialData& m = scene.material(h);
            const Vec3 N = cross(b - a, c - a);
            const double len = length(N);
            if (!m.isInterface() || m.isRough() || !(len > 0)) return;
            const Normal3 nOut = N * (1.0 / len);
            if (!skyIn && !skyOut) {
                dense.push_back({a, b, c, nOut, mesh, inst, face, in, out});
                return;
            }
            BeamLink L;
            L.a = a, L.b = b, L.c = c;
            L.nFrom = skyOut ? nOut : -nOut;
            if (dot(L.nFrom, dirs[0]) <= minCos) return;
            L.from = skyOut ? out : in, L.to = skyOut ? in : out;
            L.eta = index[static_cast<size_t>(L.from)] / index[static_cast<size_t>(L.to)];
            L.mesh = mesh, L.instance = inst, L.face = face;
            add(L, dirs, true);
        });
    }

    // The box of the part of F that L's beam (its image moved by S) can light: the corners of L's
    // lit part carried along each of its directions to F's plane, widened for the directions
    // between the sampled ones, and clipped to F's box (empty: it lights none of F).
    static BBox3 litPart(const BeamLink& L, const Vec3& S, const std::array<Vec3, kRim + 1>& tr, const DenseFace& F,
                         const BBox3& fbox) {
        BBox3 lit;
        double far = 0;
        for (const Vec3& d : tr) {
            if (std::isnan(d.x)) continue;
            const double dn = dot(F.nOut, d);
            if (std::abs(dn) < 1e-3) return fbox;  // (nearly) parallel to F: no bound but F's
            for (const Point3& v : corners(L.faceBox)) {
                const double t = dot(F.nOut, F.a - (v + S)) / dn;
                lit.expand(v + S + d * t);
                far = std::max(far, std::abs(t));
            }
        }
        const double e = 1e-6 * (1 + length(fbox.extent())) + 1.2 * far * spreadOf(tr).tanAngle;
        lit.lo = vmax(lit.lo - Vec3{e, e, e}, fbox.lo), lit.hi = vmin(lit.hi + Vec3{e, e, e}, fbox.hi);
        return lit;
    }

    // The links of order `order` from those of order - 1, links[begin, end).
    void extend(size_t begin, size_t end, int order, const std::vector<double>& index) {
        for (size_t li = begin; li < end; ++li) {
            const BeamLink L = links[li];  // copies: add() grows both vectors
            const std::array<Vec3, kRim + 1> tr = travel[li];
            for (const DenseFace& F : dense) {
                if ((L.to != F.in && L.to != F.out) || (L.mesh == F.mesh && L.instance == F.instance && L.face == F.face))
                    continue;
                BBox3 fbox;
                for (const Point3& v : {F.a, F.b, F.c}) fbox.expand(v);
                const Normal3 nFrom = L.to == F.out ? F.nOut : -F.nOut;
                for (const Vec3& S : shifts) {
                    // The parent's image moved by S lights F: F moved by -S overlaps the parent's beam.
                    if (!boxesOverlap(L.box, fbox, -S) || !beamReaches(L, S, tr, F.a, F.b, F.c, nFrom)) continue;
                    BeamLink K;
                    K.faceBox = litPart(L, S, tr, F, fbox);
                    if (K.faceBox.empty()) continue;
                    K.a = F.a, K.b = F.b, K.c = F.c, K.nFrom = nFrom;
                    K.from = L.to, K.to = L.to == F.out ? F.in : F.out;
                    K.eta = index[static_cast<size_t>(K.from)] / index[static_cast<size_t>(K.to)];
                    K.mesh = F.mesh, K.instance = F.instance, K.face = F.face;
                    K.parent = static_cast<int>(li), K.shift = S, K.order = order;
                    add(K, tr, false);
                }
            }
        }
    }
};
}  // namespace

void FacetBeams::buildChains(const Scene& scene, int medium, const std::vector<double>& index,
                             const std::vector<bool>& sky, const Vec3& sunDir, double halfAngle, int maxOrder) {
    maxOrder = std::min(maxOrder, kMaxChainOrder);
    ChainBuilder cb;
    cb.bounds = scene.geometry().bounds();
    cb.cap = 10 * (1 + length(cb.bounds.extent()));
    cb.periodic = periodic_;
    if (periodic_)
        for (int ix = -1; ix <= 1; ++ix)
            for (int iy = -1; iy <= 1; ++iy)
                if (ix != 0 || iy != 0) cb.shifts.push_back(Vec3{ix * px_, iy * py_, 0});
    cb.collect(scene, index, sky, discDirections(sunDir, halfAngle), -std::sin(std::min(0.5, halfAngle * kRimMargin)));
    size_t begin = 0, end = cb.links.size();
    maxOrder_ = maxOrder;
    for (int order = 2; order <= maxOrder && begin < end; ++order) {
        cb.extend(begin, end, order, index);
        if (cb.links.size() > kMaxLinks) {
            // Too many to test at every query: index the chains one refraction shorter, completely.
            cb.links.resize(end);
            maxOrder_ = order - 1;
            log::warn("facet beams into medium {}: more than {} chains of {} refractions through dielectric "
                      "objects; chains of up to {} are indexed, longer ones are reached by sampling only",
                      medium, kMaxLinks, order, order - 1);
            break;
        }
        begin = end, end = cb.links.size();
    }
    // Keep the chains of two or more refractions that end in this medium, and their ancestors.
    const std::vector<BeamLink>& links = cb.links;
    std::vector<int> keep(links.size(), -1), finals;
    for (size_t i = 0; i < links.size(); ++i) {
        if (links[i].order < 2 || links[i].to != medium) continue;
        finals.push_back(static_cast<int>(i));
        for (int l = static_cast<int>(i); l >= 0 && keep[static_cast<size_t>(l)] < 0; l = links[static_cast<size_t>(l)].parent)
            keep[static_cast<size_t>(l)] = 0;
    }
    for (size_t i = 0; i < links.size(); ++i) {
        if (keep[i] < 0) continue;
        keep[i] = static_cast<int>(links_.size());
        links_.push_back(links[i]);
        if (links_.back().parent >= 0) links_.back().parent = keep[static_cast<size_t>(links_.back().parent)];
    }
    for (const int f : finals) finals_.push_back(keep[static_cast<size_t>(f)]);
    buildChainGrid(scene.domain());
    log::debug("facet beams into medium {}: {} chains through dielectric objects ({} links)", medium, finals_.size(),
               links_.size());
}

bool FacetBeams::nearBeam(const BeamLink& l, const Point3& p) {
    // Back from p along the mean direction to the face's plane; a disc direction within the spread
    // meets the plane within t tan(spread) / cos(incidence) of that point (widened by 1.2 for the
    // second-order terms). Near grazing incidence the test is skipped.
    const double c = -dot(l.nFrom, l.mean);
    if (!(c > 0.05)) return true;
    const double t = -dot(l.nFrom, p - l.a) / c;
    if (!(t > 0)) return false;  // p lies before the face
    const Point3 q = p - l.mean * t;
    const double m = 1.2 * t * l.tanSpread / c + 1e-6 * (1 + t + length(l.faceBox.extent()));
    return q.x >= l.faceBox.lo.x - m && q.x <= l.faceBox.hi.x + m && q.y >= l.faceBox.lo.y - m &&
           q.y <= l.faceBox.hi.y + m && q.z >= l.faceBox.lo.z - m && q.z <= l.faceBox.hi.z + m;
}

std::pair<const FacetBeams::ChainEntry*, const FacetBeams::ChainEntry*> FacetBeams::chainCell(const Point3& p) const {
    double x = p.x, y = p.y;
    if (periodic_) x = wrapInto(x, cx0_, px_), y = wrapInto(y, cy0_, py_);
    const double fi = (x - cx0_) / ccell_, fj = (y - cy0_) / ccell_;
    if (!(fi >= 0 && fj >= 0 && fi < cnx_ && fj < cny_)) return {nullptr, nullptr};
    const size_t k = static_cast<size_t>(static_cast<int>(fj)) * cnx_ + static_cast<size_t>(static_cast<int>(fi));
    return {chainEntries_.data() + chainOffsets_[k], chainEntries_.data() + chainOffsets_[k + 1]};
}

void FacetBeams::buildChainGrid(const ir::Domain& dom) {
    // Over the domain when periodic (each chain's box moved into it by its images), else over
    // the boxes; cells about half the boxes' mean width, at most 256 a side.
    BBox3 all;
    double width = 0;
    for (const int f : finals_) {
        const BBox3& b = links_[static_cast<size_t>(f)].box;
        all.expand(b);
        width += std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y) / static_cast<double>(finals_.size());
    }
    if (finals_.empty()) return;
    cx0_ = periodic_ ? dom.x0 : all.lo.x, cy0_ = periodic_ ? dom.y0 : all.lo.y;
    const double sx = periodic_ ? px_ : all.hi.x - all.lo.x, sy = periodic_ ? py_ : all.hi.y - all.lo.y;
    ccell_ = std::max({0.5 * width, std::max(sx, sy) / 256, 1e-6});
    cnx_ = std::clamp(static_cast<int>(std::ceil(sx / ccell_)), 1, 256);
    cny_ = std::clamp(static_cast<int>(std::ceil(sy / ccell_)), 1, 256);
    chainOffsets_.assign(static_cast<size_t>(cnx_) * cny_ + 1, 0);
    std::vector<std::pair<size_t, ChainEntry>> entries;
    for (size_t k = 0; k < finals_.size(); ++k) {
        const BBox3& b = links_[static_cast<size_t>(finals_[k])].box;
        const int r = periodic_ ? 1 : 0;
        for (int ix = -r; ix <= r; ++ix)
            for (int iy = -r; iy <= r; ++iy) {
                // The points p whose image p + (ix px, iy py) lies in the box: the box moved back.
                const double x0 = b.lo.x - ix * px_, x1 = b.hi.x - ix * px_, y0 = b.lo.y - iy * py_, y1 = b.hi.y - iy * py_;
                const int i0 = std::max(0, static_cast<int>(std::floor((x0 - cx0_) / ccell_)));
                const int i1 = std::min(cnx_ - 1, static_cast<int>(std::floor((x1 - cx0_) / ccell_)));
                const int j0 = std::max(0, static_cast<int>(std::floor((y0 - cy0_) / ccell_)));
                const int j1 = std::min(cny_ - 1, static_cast<int>(std::floor((y1 - cy0_) / ccell_)));
                for (int j = j0; j <= j1; ++j)
                    for (int i = i0; i <= i1; ++i)
                        entries.push_back({static_cast<size_t>(j) * cnx_ + i,
                                           ChainEntry{static_cast<int32_t>(k), static_cast<int8_t>(ix), static_cast<int8_t>(iy)}});
            }
    }
    std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& e : entries) ++chainOffsets_[e.first + 1];
    for (size_t k = 1; k < chainOffsets_.size(); ++k) chainOffsets_[k] += chainOffsets_[k - 1];
    chainEntries_.reserve(entries.size());
    for (const auto& e : entries) chainEntries_.push_back(e.second);
}

bool FacetBeams::refracted(int i, const Vec3& ws, Vec3* d) const {
    return crossFace(-ws, facets_[static_cast<size_t>(i)].nAir, eta_, d) && d->z < -kMinSlope;
}

bool FacetBeams::containsImage(const BeamFacet& f, const Point3& p, const Vec3& d, const Vec3& S, double* s) const {
    const double dn = dot(f.nAir, d);  // < 0: d leaves the air side
    if (!(dn < 0)) return false;
    // The line p - t d meets the plane of the facet's image moved by S at t.
    const double t = dot(f.nAir, p - f.a - S) / dn;
    if (!(t > 0)) return false;
    const Point3 q = p - d * t, a = f.a + S, b = f.b + S, c = f.c + S;
    const Vec3 N = cross(b - a, c - a);
    if (dot(cross(b - a, q - a), N) < 0 || dot(cross(c - b, q - b), N) < 0 || dot(cross(a - c, q - c), N) < 0)
        return false;
    *s = t;
    return true;
}

bool FacetBeams::contains(int i, const Point3& p, const Vec3& d, double* s) const {
    const BeamFacet& f = facets_[static_cast<size_t>(i)];
    if (!periodic_) return containsImage(f, p, d, Vec3{0, 0, 0}, s);
    // The image whose centroid lies nearest the point where the line through p along d reaches the
    // centroid's height. (Not where it meets the facet's plane: under a steep facet that plane is
    // nearly parallel to the line, its crossing lies far from the facet, and the image nearest it
    // is the wrong one; those beams were lost where they crossed a periodic wall, 22 % of the
    // light under the 68-degree sinusoid.) It is the only candidate for a facet smaller than a
    // quarter period; a larger one is tested in the images around it too.
    const Point3 g = (f.a + f.b + f.c) * (1.0 / 3.0);
    const Point3 q = p + d * ((g.z - p.z) / d.z);  // d.z < -kMinSlope (refracted)
    const Vec3 S{px_ * std::round((q.x - g.x) / px_), py_ * std::round((q.y - g.y) / py_), 0};
    if (!f.large) return containsImage(f, p, d, S, s);
    for (int jx = -1; jx <= 1; ++jx)
        for (int jy = -1; jy <= 1; ++jy)
            if (containsImage(f, p, d, S + Vec3{jx * px_, jy * py_, 0}, s)) return true;
    return false;
}

const FacetBeams::Entry* FacetBeams::cellOf(const Point3& p, int* count, double* sxOut, double* syOut) const {
    *count = 0;
    if (offsets_.empty()) return nullptr;  // no facets, or flat ones (not indexed)
    const double depth = (zTop_ - p.z) / slab_;
    if (!(depth >= 0)) return nullptr;  // above every facet: no beam reaches up here
    const int s = std::min(nz_ - 1, static_cast<int>(depth));
    double sx = p.x - p.z * k0x_, sy = p.y - p.z * k0y_;
    if (periodic_) sx = wrapInto(sx, x0_, px_), sy = wrapInto(sy, y0_, py_);
    const double fi = (sx - x0_) / cellX_, fj = (sy - y0_) / cellY_;
    if (!(fi >= 0 && fj >= 0) || (!periodic_ && (fi >= nx_ || fj >= ny_))) return nullptr;
    const int i = std::min(static_cast<int>(fi), nx_ - 1), j = std::min(static_cast<int>(fj), ny_ - 1);
    const size_t k = (static_cast<size_t>(s) * ny_ + j) * nx_ + i;
    *count = static_cast<int>(offsets_[k + 1] - offsets_[k]);
    // The position within the cell, in the entries' fixed-point units.
    *sxOut = (fi - i) * kEntryScale, *syOut = (fj - j) * kEntryScale;
    return entries_.data() + offsets_[k];
}

struct FacetBeams::Drifts {
    std::vector<std::array<Vec2, kRim + 1>> k;
};

void FacetBeams::build(const Vec3& sunDir, double halfAngle, double zBottom, const ir::Domain& dom) {
    Vec3 d0;
    if (!refract(sunDir, Vec3{0, 0, 1}, eta_, &d0)) d0 = Vec3{0, 0, -1};
    d0 = normalize(d0);
    k0x_ = d0.x / d0.z, k0y_ = d0.y / d0.z;
    const auto dirs = discDirections(sunDir, halfAngle);
    Drifts drifts;
    drifts.k.resize(facets_.size());
    double zTop = -ir::kInfinity, sizeSum = 0, maxDrift = 1e-3;
    for (size_t i = 0; i < facets_.size(); ++i) {
        const BeamFacet& f = facets_[i];
        for (size_t k = 0; k < dirs.size(); ++k) {
            Vec3 d;
            drifts.k[i][k] = Vec2{NAN, NAN};
            if (!refracted(static_cast<int>(i), dirs[k], &d)) continue;
            drifts.k[i][k] = Vec2{d.x / d.z - k0x_, d.y / d.z - k0y_};
            maxDrift = std::max({maxDrift, std::abs(drifts.k[i][k].x), std::abs(drifts.k[i][k].y)});
        }
        zTop = std::max({zTop, f.a.z, f.b.z, f.c.z});
        sizeSum += f.extent;
    }
    zTop_ = zTop;
    zBottom = std::min(zBottom, zTop - 1e-3);
    // The sheared plane: the domain's period, or the footprints' extent at the top and the bottom.
    double x0 = dom.x0, x1 = dom.x1, y0 = dom.y0, y1 = dom.y1;
    if (!periodic_) {
        x0 = y0 = ir::kInfinity, x1 = y1 = -ir::kInfinity;
        for (size_t i = 0; i < facets_.size(); ++i) {
            const BeamFacet& f = facets_[i];
            const auto b = footprint(i, drifts, zBottom, std::min({zTop, std::max({f.a.z, f.b.z, f.c.z})}));
            x0 = std::min(x0, b[0]), x1 = std::max(x1, b[1]), y0 = std::min(y0, b[2]), y1 = std::max(y1, b[3]);
        }
        if (!(x1 >= x0)) x0 = x1 = y0 = y1 = 0;
    }
    x0_ = x0, y0_ = y0;
    // Cells half a facet wide (a cell then lists about 2 (1 + 1/2)^2 = 4.5 triangles of a regular
    // grid, 8 with whole-facet cells), slabs in which a beam drifts about one cell; both coarsened
    // until the grid holds at most kMaxCells cells and kMaxEntries entries (a deep column under
    // small facets would otherwise need billions).
    const double span = std::max(dom.x1 - dom.x0, dom.y1 - dom.y0);
    const double meanExtent = sizeSum / static_cast<double>(facets_.size());
    double cell = std::max(0.5 * meanExtent, span / kMaxCellsPerAxis);
    for (;; cell *= 1.25) {
        nz_ = std::clamp(static_cast<int>(std::ceil((zTop - zBottom) * maxDrift / cell)), 1, kMaxSlabs);
        nx_ = std::clamp(static_cast<int>(std::ceil((x1 - x0) / cell)), 1, kMaxCellsPerAxis);
        ny_ = std::clamp(static_cast<int>(std::ceil((y1 - y0) / cell)), 1, kMaxCellsPerAxis);
        // Each facet lies in about (extent / cell + 2)^2 cells of each slab below it.
        const double entries = static_cast<double>(facets_.size()) * nz_ * sqr(meanExtent / cell + 2);
        if (static_cast<double>(nz_) * nx_ * ny_ <= kMaxCells && entries <= kMaxEntries) break;
    }
    slab_ = (zTop - zBottom) / nz_;
    cellX_ = std::max((x1 - x0) / nx_, 1e-12), cellY_ = std::max((y1 - y0) / ny_, 1e-12);
    offsets_.assign(static_cast<size_t>(nz_) * nx_ * ny_ + 1, 0);
    fill(drifts, true);
    for (size_t k = 1; k < offsets_.size(); ++k) offsets_[k] += offsets_[k - 1];
    entries_.resize(offsets_.back());
    fill(drifts, false);
    log::debug("facet beams: {} facets, {} slabs of {:.3g} m, {} x {} cells of {:.3g} m, {} entries", facets_.size(),
               nz_, slab_, nx_, ny_, cellX_, entries_.size());
}

std::array<double, 4> FacetBeams::footprint(size_t i, const Drifts& drifts, double zLo, double zHi) const {
    // Vertex v's beam along a direction of drift k reaches depth z at sigma = v.xy - v.z k0 + (z - v.z) k:
    // affine in z, so the slab's two ends bound it.
    const BeamFacet& f = facets_[i];
    std::array<double, 4> box{ir::kInfinity, -ir::kInfinity, ir::kInfinity, -ir::kInfinity};
    for (const Point3& v : {f.a, f.b, f.c})
        for (const Vec2& k : drifts.k[i])
            for (const double z : {zLo, zHi}) {
                if (std::isnan(k.x)) continue;
                const double sx = v.x - v.z * k0x_ + (z - v.z) * k.x, sy = v.y - v.z * k0y_ + (z - v.z) * k.y;
                box = {std::min(box[0], sx), std::max(box[1], sx), std::min(box[2], sy), std::max(box[3], sy)};
            }
    return box;
}

FacetBeams::Entry FacetBeams::entry(int32_t facet, int ci, int cj, double x0, double x1, double y0, double y1) const {
    // The box in units of the cell (0 at its low edge, kEntryScale at its high one), clipped to it and
    // rounded outward (a hair wider than the doubles' rounding).
    auto lo = [](double v) {
        v = std::floor(v * kEntryScale - 1e-6 * kEntryScale);
        return static_cast<uint16_t>(std::clamp(v, 0.0, kEntryScale));
    };
    auto hi = [](double v) {
        v = std::ceil(v * kEntryScale + 1e-6 * kEntryScale);
        return static_cast<uint16_t>(std::clamp(v, 0.0, kEntryScale));
    };
    const double cx = x0_ + ci * cellX_, cy = y0_ + cj * cellY_;
    return Entry{facet, lo((x0 - cx) / cellX_), hi((x1 - cx) / cellX_), lo((y0 - cy) / cellY_), hi((y1 - cy) / cellY_)};
}

// Lists every facet in the cells its footprint overlaps in every slab below its top: counting
// into offsets_[k + 1] (count), or writing entries_ at offsets_[k] onward (the offsets advance and
// are restored at the end).
void FacetBeams::fill(const Drifts& drifts, bool count) {
    std::vector<uint32_t> next;
    if (!count) next.assign(offsets_.begin(), offsets_.end() - 1);
    for (size_t i = 0; i < facets_.size(); ++i) {
        const BeamFacet& f = facets_[i];
        const double fTop = std::max({f.a.z, f.b.z, f.c.z});
        for (int s = 0; s < nz_; ++s) {
            const double zb = zTop_ - s * slab_, za = zb - slab_;
            if (za >= fTop) continue;  // the whole slab lies above this facet
            const auto [x0, x1, y0, y1] = footprint(i, drifts, za, std::min(zb, fTop));
            if (!(x1 >= x0)) continue;
            // Cells overlapped (a hair wider, for points on a cell's edge), wrapped when periodic.
            const double e = 1e-9 * (1 + std::abs(x0) + std::abs(y0));
            int i0 = static_cast<int>(std::floor((x0 - e - x0_) / cellX_)), i1 = static_cast<int>(std::floor((x1 + e - x0_) / cellX_));
            int j0 = static_cast<int>(std::floor((y0 - e - y0_) / cellY_)), j1 = static_cast<int>(std::floor((y1 + e - y0_) / cellY_));
            bool wideX = false, wideY = false;  // the footprint spans the period: its box rejects nothing
            if (periodic_) {
                if (i1 - i0 >= nx_) i0 = 0, i1 = nx_ - 1, wideX = true;
                if (j1 - j0 >= ny_) j0 = 0, j1 = ny_ - 1, wideY = true;
            } else {
                i0 = std::max(i0, 0), j0 = std::max(j0, 0), i1 = std::min(i1, nx_ - 1), j1 = std::min(j1, ny_ - 1);
            }
            for (int j = j0; j <= j1; ++j)
                for (int ii = i0; ii <= i1; ++ii) {
                    const int ci = ((ii % nx_) + nx_) % nx_, cj = ((j % ny_) + ny_) % ny_;
                    const size_t k = (static_cast<size_t>(s) * ny_ + cj) * nx_ + ci;
                    if (count) {
                        ++offsets_[k + 1];
                        continue;
                    }
                    // The box in the cell's periodic image (the unwrapped cell ii is cell ci).
                    const double sx = (ii - ci) / nx_ * px_, sy = (j - cj) / ny_ * py_;
                    entries_[next[k]++] = entry(static_cast<int32_t>(i), ci, cj, wideX ? -ir::kInfinity : x0 - sx,
                                                wideX ? ir::kInfinity : x1 - sx, wideY ? -ir::kInfinity : y0 - sy,
                                                wideY ? ir::kInfinity : y1 - sy);
                }
        }
    }
}

}  // namespace littoral::render
