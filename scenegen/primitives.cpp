#include "scenegen/primitives.h"

#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "scenegen/water_volume.h"

namespace littoral::scenegen {
namespace {

uint32_t addVertex(TriMesh& m, double x, double y, double z) {
    m.positions.push_back({x, y, z});
    return static_cast<uint32_t>(m.positions.size() - 1);
}

// Appends a planar convex polygon (counter-clockwise seen from outside) as a fan from its first
// corner; callers order corners so that no fan triangle is degenerate.
void addPolygon(TriMesh& m, const std::vector<uint32_t>& c, uint16_t slot) {
    for (size_t k = 1; k + 1 < c.size(); ++k) {
        m.triangles.push_back({c[0], c[k], c[k + 1]});
        m.faceMaterial.push_back(slot);
    }
}

// Reverses every face if the enclosed volume came out negative (a construction convention slip
// must not produce an inward solid).
void orientOutward(TriMesh& m) {
    if (m.signedVolume() < 0)
        for (auto& t : m.triangles) std::swap(t[1], t[2]);
}

}  // namespace

TriMesh makeBox(double lx, double ly, double lz, double z0, uint16_t sideSlot, uint16_t topSlot) {
    LITTORAL_CHECK(lx > 0 && ly > 0 && lz > 0);
    TriMesh m;
    const double x = 0.5 * lx, y = 0.5 * ly, z1 = z0 + lz;
    // Corners: bottom 0..3 counter-clockwise from above, top 4..7 above them.
    for (double z : {z0, z1}) {
        addVertex(m, -x, -y, z);
        addVertex(m, x, -y, z);
        addVertex(m, x, y, z);
        addVertex(m, -x, y, z);
    }
    addPolygon(m, {0, 3, 2, 1}, sideSlot);  // bottom, normal -z
    addPolygon(m, {4, 5, 6, 7}, topSlot);   // top, normal +z
    addPolygon(m, {0, 1, 5, 4}, sideSlot);  // -y
    addPolygon(m, {1, 2, 6, 5}, sideSlot);  // +x
    addPolygon(m, {2, 3, 7, 6}, sideSlot);  // +y
    addPolygon(m, {3, 0, 4, 7}, sideSlot);  // -x
    return m;
}

TriMesh makeBarge(double beam, double length, double depth) { return makeBox(beam, length, depth, 0.0, 0, 1); }

TriMesh makeBoat(double length, double beam, double depth, int stations) {
    LITTORAL_CHECK(length > 0 && beam > 0 && depth > 0 && stations >= 3);
    TriMesh m;
    // Each station is a pentagon ring in the x-z plane at y: deck port, chine port, keel, chine
    // starboard, deck starboard. Half-breadth tapers toward the bow as sqrt(1 - s^2) (s = 0 at
    // midship, 1 at the bow), never below 8% so the stem stays a thin solid; the keel rises toward
    // the bow (rocker) as 0.5 depth s^2.
    const int ring = 5;
    for (int i = 0; i < stations; ++i) {
        const double u = static_cast<double>(i) / (stations - 1);  // 0 stern, 1 bow
        const double y = (u - 0.5) * length;
        const double s = std::max(0.0, 2.0 * u - 1.0);
        const double b = 0.5 * beam * std::max(0.08, std::sqrt(std::max(0.0, 1.0 - s * s)));
        const double keel = 0.5 * depth * s * s;
        const double chineZ = keel + 0.35 * (depth - keel);
        addVertex(m, -b, y, depth);
        addVertex(m, -0.8 * b, y, chineZ);
        addVertex(m, 0.0, y, keel);
        addVertex(m, 0.8 * b, y, chineZ);
        addVertex(m, b, y, depth);
    }
    auto v = [&](int station, int k) { return static_cast<uint32_t>(station * ring + k); };
    for (int i = 0; i + 1 < stations; ++i)
        for (int k = 0; k < ring; ++k) {
            const int k2 = (k + 1) % ring;
            // Ring order port-deck -> keel -> starboard-deck goes clockwise seen from the stern
            // (looking +y); the quad (i,k) (i,k2) (i+1,k2) (i+1,k) then faces outward.
            const uint16_t slot = (k == ring - 1) ? 1 : 0;  // the starboard->port deck edge segment is the deck
            addPolygon(m, {v(i, k), v(i + 1, k), v(i + 1, k2), v(i, k2)}, slot);
        }
    // Transom (stern, normal -y) and stem (bow, normal +y): pentagons fanned from the keel corner
    // (not collinear with any other pair), wound against the ring edges the adjacent quads use.
    addPolygon(m, {v(0, 2), v(0, 3), v(0, 4), v(0, 0), v(0, 1)}, 0);
    addPolygon(m, {v(stations - 1, 2), v(stations - 1, 1), v(stations - 1, 0), v(stations - 1, 4), v(stations - 1, 3)}, 0);
    orientOutward(m);
    return m;
}

TriMesh makeCylinder(double r, double z0, double z1, int segments, uint16_t slot) {
    LITTORAL_CHECK(r > 0 && z1 > z0 && segments >= 3);
    TriMesh m;
    for (double z : {z0, z1})
        for (int i = 0; i < segments; ++i) {
            const double a = 2 * kPi * i / segments;
            addVertex(m, r * std::cos(a), r * std::sin(a), z);
        }
    const uint32_t cb = addVertex(m, 0, 0, z0), ct = addVertex(m, 0, 0, z1);
    const auto n = static_cast<uint32_t>(segments);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        addPolygon(m, {i, j, n + j, n + i}, slot);  // side, counter-clockwise from outside
        addPolygon(m, {cb, j, i}, slot);            // bottom, normal -z
        addPolygon(m, {ct, n + i, n + j}, slot);    // top, normal +z
    }
    return m;
}

TriMesh makeBuoy(double radius, double height, int segments) {
    LITTORAL_CHECK(radius > 0 && height > 0 && segments >= 3);
    TriMesh m;
    for (double z : {0.0, height})
        for (int i = 0; i < segments; ++i) {
            const double a = 2 * kPi * i / segments;
            addVertex(m, radius * std::cos(a), radius * std::sin(a), z);
        }
    const uint32_t cb = addVertex(m, 0, 0, 0), apex = addVertex(m, 0, 0, height + 0.5 * radius);
    const auto n = static_cast<uint32_t>(segments);
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        addPolygon(m, {i, j, n + j, n + i}, 0);
        addPolygon(m, {cb, j, i}, 0);
        addPolygon(m, {apex, n + i, n + j}, 0);
    }
    return m;
}

TriMesh makePier(const PierParams& p) {
    LITTORAL_CHECK(p.length > 0 && p.width > 0 && p.deckThickness > 0 && p.pilingRadius > 0 && p.pilingSpacing > 0);
    LITTORAL_CHECK(p.pilingBottom < p.deckBottom);
    LITTORAL_CHECK_LT(2 * p.pilingRadius, p.width);
    // Deck along y from 0 to length (shore end at y = 0).
    TriMesh deck = makeBox(p.width, p.length, p.deckThickness, p.deckBottom, 0, 0);
    for (auto& q : deck.positions) q.y += 0.5 * p.length;
    TriMesh pier = deck;
    // Pilings rise 0.2 m into the deck so the union is a proper overlap, not a face contact.
    const int pairs = std::max(1, static_cast<int>(std::floor((p.length - 2 * p.pilingRadius) / p.pilingSpacing)) + 1);
    const double xOff = 0.5 * p.width - 1.5 * p.pilingRadius;
    TriMesh pilings;
    for (int i = 0; i < pairs; ++i) {
        const double y = std::min(p.length - 1.5 * p.pilingRadius, 1.5 * p.pilingRadius + i * p.pilingSpacing);
        for (double x : {-xOff, xOff}) {
            TriMesh c = makeCylinder(p.pilingRadius, p.pilingBottom, p.deckBottom + 0.2, p.segments, 1);
            for (auto& q : c.positions) q = q + Vec3{x, y, 0};
            pier = booleanSolids(pier, c, BooleanOp::Union, "pier piling");
        }
    }
    return pier;
}

TriMesh makeStepTarget(double size, double height) {
    LITTORAL_CHECK(size > 0 && height > 0);
    TriMesh m;
    const double h = 0.5 * size;
    // Bottom corners 0..3 (z = -height), top corners 4..7 (z = 0), top mid-points 8 (y = -h), 9 (y = +h).
    for (double z : {-height, 0.0}) {
        addVertex(m, -h, -h, z);
        addVertex(m, h, -h, z);
        addVertex(m, h, h, z);
        addVertex(m, -h, h, z);
    }
    addVertex(m, 0, -h, 0);
    addVertex(m, 0, h, 0);
    addPolygon(m, {0, 3, 2, 1}, 1);       // bottom
    addPolygon(m, {4, 8, 9, 7}, 0);       // top, bright half (x < 0)
    addPolygon(m, {8, 5, 6, 9}, 1);       // top, dark half (x > 0)
    addPolygon(m, {0, 1, 5, 8, 4}, 1);    // -y side (fan from a bottom corner)
    addPolygon(m, {1, 2, 6, 5}, 1);       // +x side
    addPolygon(m, {2, 3, 7, 9, 6}, 1);    // +y side
    addPolygon(m, {3, 0, 4, 7}, 1);       // -x side
    return m;
}

}  // namespace littoral::scenegen
