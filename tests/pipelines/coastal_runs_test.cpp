// `littoral coastal A..J`: the dissertation's coastal simulations (Table 10.1) at quick settings.
// Every configuration's scene passes check-scene; the renders show what Ch. 10 says they show,
// checked on regions of the images chosen through the truth layers (NAME_truth.exr).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/scene_ir.h"
#include "pipelines/lib_coastal.h"
#include "render/camera.h"
#include "render/image_output.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
using namespace littoral;
using littoral::testing_support::legendId;
using littoral::testing_support::medianOf;
using littoral::testing_support::pngSize;
using littoral::testing_support::runLittoral;
using littoral::testing_support::scratchDir;

namespace {

// One sensor's radiance, truth and legend in a run's output folder.
struct Render {
    fs::path out;
    std::string name;
    render::Film film;
    render::TruthImages truth;
    fs::path legend;
};

Render readRender(const fs::path& out, const std::string& name) {
    return {out, name, render::readExr(out / (name + ".exr")), render::readTruthExr(out / (name + "_truth.exr")),
            out / (name + "_legend.csv")};
}

Render renderConfiguration(const fs::path& dir, char id) {
    const fs::path out = dir / std::string(1, id);
    const auto r = runLittoral(fmt::format("-q coastal {} --out {}", id, out.string()));
    EXPECT_EQ(r.status, 0) << r.output;
    return readRender(out, fmt::format("sim-{}", static_cast<char>(std::tolower(id))));
}

// Band `band` of `image` (the radiance or a water product of the same sensor) at the pixels whose
// first hit is the water surface.
std::vector<double> waterValues(const Render& r, const render::Film& image, int band) {
    const int water = legendId(r.legend, "air-water-interface");
    EXPECT_GE(water, 0);
    std::vector<double> v;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (r.truth.materialId[r.truth.index(x, y)] == water) v.push_back(image.at(x, y, band));
    return v;
}

// The share of the water pixels (first hit: the interface) brighter than 20 times their median,
// in the 0.47-0.53 um band: glints of the sun on facets that mirror it into the sensor.
double glintFraction(const Render& r) {
    const std::vector<double> v = waterValues(r, r.film, 1);
    const double m = medianOf(v);
    size_t bright = 0;
    for (double L : v) bright += L > 20 * m ? 1 : 0;
    return v.empty() ? 0.0 : static_cast<double>(bright) / static_cast<double>(v.size());
}

// Nadir views (C, D, I, J) have north up and the target (0, 0) at the image centre: the ground
// point of pixel (i, j) is x = (i + 0.5 - W/2) gsd, y = (H/2 - j - 0.5) gsd (depths of a metre move
// it by 1/500 of the range, far below a pixel).
struct NadirGrid {
    int W, H;
    double gsd;
    int col(double x) const { return static_cast<int>(std::floor(x / gsd + 0.5 * W)); }
    int row(double y) const { return static_cast<int>(std::floor(0.5 * H - y / gsd)); }
};

// The share of the wet-sand seabed in the strip south of the pier's south edge (y = -25.25; the
// strip runs from y = -25.4 to -29 and from x = -18 to -8, 4-14 m offshore) that lies in shadow:
// darker than half the median of the same sand 5-10 m north of the pier (y from -19 to -14). The
// deck's top is 2 m above the water. The sun comes from the north-west, so the shadow moves
// south-east: by h tan(theta) sin(45 deg) on the water, plus d tan(theta_w) sin(45 deg) through
// the 0.6-1.25 m of water. That is about 1.1 m at a 30-deg sun (C) and 3.1 m at 60 deg (D), so
// D's strip is much more shadowed.
double pierShadowFraction(const Render& r, double gsd) {
    const NadirGrid g{r.film.width, r.film.height, gsd};
    const int sand = legendId(r.legend, "wet-sand");
    EXPECT_GE(sand, 0);
    auto values = [&](double y0, double y1) {
        std::vector<double> v;
        for (int j = g.row(y1); j <= g.row(y0); ++j)
            for (int i = g.col(-18); i <= g.col(-8); ++i)
                if (r.truth.surfaceId[r.truth.index(i, j)] == sand) v.push_back(r.film.at(i, j, 1));
        return v;
    };
    const double lit = medianOf(values(-19, -14));
    const auto strip = values(-29, -25.4);
    size_t dark = 0;
    for (double L : strip) dark += L < 0.5 * lit ? 1 : 0;
    EXPECT_GT(strip.size(), 500u);
    return strip.empty() ? 0.0 : static_cast<double>(dark) / static_cast<double>(strip.size());
}

// The southern edge of the pier's shadow on the seabed over the columns x0..x1 of the nadir view
// D, measured and predicted (m of y).
// - Measured: per column, the top of the first row south of y = -25.6 whose radiance exceeds the
//   mean of the shadow's level (median over y -26.5..-25.6) and the lit seabed's just south of it
//   (y -29.5..-28.9). The median over the columns is used, since a few columns meet a piling.
// - Predicted, apart from the renderer: the deck's south top edge (y = -25.25, z = 2 m) is cast
//   along the sun's azimuth (135 deg, so the y offset is 0.707 of the horizontal one). The cast
//   runs (2 - eta) tan 60 to the water surface at its local level eta, then (d + eta) tan(theta_w)
//   to the seabed at depth d, with sin theta_w = sin 60 / 1.34. eta and d are medians over the
//   edge's neighbourhood from the truth layers: eta = 500 - range cos(alpha) (the camera is 500 m
//   above z = 0, alpha is the ray's angle off nadir), d = hitDepth.
struct ShadowEdge {
    double measured, predicted;
};
ShadowEdge pierShadowEdge(const Render& r, double x0, double x1) {
    const NadirGrid g{r.film.width, r.film.height, 0.1};
    auto medianIn = [&](double ya, double yb, auto value) {
        std::vector<double> v;
        for (int j = g.row(yb); j <= g.row(ya); ++j)
            for (int i = g.col(x0); i <= g.col(x1); ++i) v.push_back(value(i, j));
        return medianOf(v);
    };
    auto radiance = [&](int i, int j) { return static_cast<double>(r.film.at(i, j, 1)); };
    const double mid = 0.5 * (medianIn(-26.5, -25.6, radiance) + medianIn(-29.5, -28.9, radiance));
    std::vector<double> edges;
    for (int i = g.col(x0); i <= g.col(x1); ++i)
        for (int j = g.row(-25.6); j < r.film.height; ++j)
            if (r.film.at(i, j, 1) > mid) {
                edges.push_back((0.5 * g.H - j) * g.gsd);
                break;
            }
    const double eta = medianIn(-28.5, -27.0, [&](int i, int j) {
        const double x = (i + 0.5 - 0.5 * g.W) * g.gsd, y = (0.5 * g.H - j - 0.5) * g.gsd;
        return 500.0 - r.truth.range[r.truth.index(i, j)] * 500.0 / std::sqrt(500.0 * 500.0 + x * x + y * y);
    });
    const double d = medianIn(-28.5, -27.5, [&](int i, int j) { return static_cast<double>(r.truth.hitDepth[r.truth.index(i, j)]); });
    const double thetaW = std::asin(std::sin(M_PI / 3) / 1.34);
    const double predicted = -25.25 - std::sqrt(0.5) * ((2.0 - eta) * std::tan(M_PI / 3) + (d + eta) * std::tan(thetaW));
    std::printf("x %.0f..%.0f: water level %.3f m, seabed %.3f m deep; shadow edge y = %.3f m (predicted %.3f)\n", x0,
                x1, eta, d, medianOf(edges), predicted);
    return {medianOf(edges), predicted};
}

// The boat's shadow in B, seen on the water beside the boat (Ch. 10: "the boat shadow is
// symmetric, so it must be cast onto the air-water interface"). B's sun (zenith 30 deg, from the
// north-west) and view (zenith 30 deg, from the south-east) are mirror images, so a view ray that
// meets the water at a distance s from the boat's gunwale (across the hull, on the side away from
// the sun) reaches the sand at (d + eta) tan(theta_w) cos(phi) nearer the boat, and the sun's ray
// to that sand point rises as far again before it leaves the water, then climbs h - eta to the
// gunwale's height over (h - eta) tan(30 deg) cos(phi). The sand the pixel sees is shadowed while
//   s < s_edge = 2 (d + eta) tan(theta_w) cos(phi) + (h - eta) tan(30 deg) cos(phi),
// with sin(theta_w) = sin(30 deg) / 1.34, phi the 15 deg between the shadow's azimuth (135 deg)
// and the hull's normal (heading 30 deg), h the gunwale's height (the mesh's top), eta the water's
// local level (the first hits' median z) and d the sand's depth (truth layer), both medians over
// 1 < s < 2 m. The second term (0.42 m) is the shadow cast on the interface itself: without it the
// edge would sit that far nearer the boat, beyond the tolerance. Only the straight part of the hull
// is used (the bow tapers from amidships): pixels 0-2.2 m aft of the hull's centre, whose shadow
// the gunwale casts from where it is 1.0 m out.
// Each pixel's water point is its centre ray (generated by the IR's camera) at the truth range.
struct BoatShadow {
    double dark, lit, edge, predicted;
};
BoatShadow boatShadow(const Render& r) {
    const ir::SceneIR scene = ir::readIR(r.out / "ir");
    const render::Camera camera(scene.sensors.at(0));
    const TriMesh* boat = nullptr;
    for (const auto& m : scene.meshes)
        if (m.name == "boat") boat = &m.data;
    EXPECT_NE(boat, nullptr);
    if (boat == nullptr) return {};
    const double heading = 30 * M_PI / 180, shadowAzimuth = 135 * M_PI / 180;  // clockwise from north
    const Vec3 along{std::sin(heading), std::cos(heading), 0}, across{std::cos(heading), -std::sin(heading), 0};
    const Vec3 shadowDir{std::sin(shadowAzimuth), std::cos(shadowAzimuth), 0};
    double a0 = 1e30, a1 = -1e30, gunwale = -1e30, h = -1e30;
    for (const Point3& p : boat->positions) {
        a0 = std::min(a0, dot(p, along));
        a1 = std::max(a1, dot(p, along));
        gunwale = std::max(gunwale, dot(p, across));
        h = std::max(h, p.z);
    }
    const double centre = 0.5 * (a0 + a1);
    const int water = legendId(r.legend, "air-water-interface"), sand = legendId(r.legend, "wet-sand");
    struct Pixel {
        double s, L, z, depth;
    };
    std::vector<Pixel> px;
    for (int y = 0; y < r.film.height; ++y)
        for (int x = 0; x < r.film.width; ++x) {
            const size_t k = r.truth.index(x, y);
            if (r.truth.materialId[k] != water || r.truth.surfaceId[k] != sand) continue;
            const Point3 p = camera.generateRay(x + 0.5, y + 0.5).at(r.truth.range[k]);
            const double a = dot(p, along) - centre;
            if (a < -2.2 || a > 0.0) continue;
            px.push_back({dot(p, across) - gunwale, r.film.at(x, y, 1), p.z, r.truth.hitDepth[k]});
        }
    auto medianIn = [&](double s0, double s1, double Pixel::*field) {
        std::vector<double> v;
        for (const Pixel& p : px)
            if (p.s >= s0 && p.s < s1) v.push_back(p.*field);
        EXPECT_GE(v.size(), 3u) << s0 << ".." << s1;
        return medianOf(v);
    };
    BoatShadow b{medianIn(0.1, 0.9, &Pixel::L), medianIn(2, 4, &Pixel::L), 0, 0};
    // The edge: where the medians of 0.2 m bins cross the mid-level, interpolated between bins.
    const double mid = 0.5 * (b.dark + b.lit);
    double previous = medianIn(0.8, 1.0, &Pixel::L);
    for (double s = 1.0; s < 2.0 && b.edge == 0; s += 0.2) {
        const double next = medianIn(s, s + 0.2, &Pixel::L);
        if (previous < mid && next >= mid) b.edge = s - 0.1 + 0.2 * (mid - previous) / (next - previous);
        previous = next;
    }
    const double eta = medianIn(1, 2, &Pixel::z), d = medianIn(1, 2, &Pixel::depth);
    const double cosPhi = dot(across, shadowDir), thetaW = std::asin(0.5 / 1.34);
    b.predicted = 2 * (d + eta) * std::tan(thetaW) * cosPhi + (h - eta) * std::tan(M_PI / 6) * cosPhi;
    std::printf("boat's shadow in B: sand seen through the water %.2f in shadow, %.2f lit; edge %.3f m from the "
                "gunwale (predicted %.3f: water level %.3f m, sand %.3f m deep, gunwale %.2f m up)\n",
                b.dark, b.lit, b.edge, b.predicted, eta, d, h);
    return b;
}

// Michelson contrast (B - D) / (B + D) of the medians over the pixels whose first opaque surface is
// a target's bright or dark half (all four targets, 0.5-2.75 m deep).
double targetContrast(const Render& r) {
    const int bright = legendId(r.legend, "target-bright"), dark = legendId(r.legend, "target-dark");
    EXPECT_GE(bright, 0);
    EXPECT_GE(dark, 0);
    std::vector<double> b, d;
    for (int y = 0; y < r.film.height; ++y)
        for (int x = 0; x < r.film.width; ++x) {
            const float id = r.truth.surfaceId[r.truth.index(x, y)];
            if (id == bright) b.push_back(r.film.at(x, y, 1));
            if (id == dark) d.push_back(r.film.at(x, y, 1));
        }
    EXPECT_GT(b.size(), 600u);  // four targets x 1 m x 2 m halves: 800 pixels at 0.1 m
    EXPECT_GT(d.size(), 600u);
    const double mb = medianOf(b), md = medianOf(d);
    return (mb - md) / (mb + md);
}

// The share of the sand pixels (dry and wet, seen in air or through the water) darker than 0.35
// times their class's median: shadows, lit by the sky alone (about a tenth of the sunlit value).
// The sands' textures vary by 6-8 % (stddev), so unshadowed sand never falls that low.
double shadowedSandFraction(const Render& r) {
    size_t n = 0, dark = 0;
    for (const char* cls : {"dry-sand", "wet-sand"}) {
        const int id = legendId(r.legend, cls);
        EXPECT_GE(id, 0) << cls;
        std::vector<double> v;
        for (int y = 0; y < r.film.height; ++y)
            for (int x = 0; x < r.film.width; ++x)
                if (r.truth.surfaceId[r.truth.index(x, y)] == id) v.push_back(r.film.at(x, y, 1));
        const double m = medianOf(v);
        for (double L : v) dark += L < 0.35 * m ? 1 : 0;
        n += v.size();
    }
    return n == 0 ? 0.0 : static_cast<double>(dark) / static_cast<double>(n);
}

}  // namespace

// Every row of Table 10.1, H with and without photon maps, passes every check `run` makes.
TEST(CoastalRuns, EveryConfigurationPassesCheckScene) {
    const fs::path dir = scratchDir("coastal", "check");
    for (const auto& c : pipelines::coastalConfigurations()) {
        pipelines::CoastalOptions o;
        o.configuration = std::string(1, c.id);
        for (bool pm : {true, false}) {
            if (!pm && c.id != 'H') continue;
            const fs::path scene = pipelines::writeCoastalSite(o, dir / fmt::format("{}{}", c.id, pm ? "" : "-nopm"), pm);
            const auto r = runLittoral("-q check-scene " + scene.string());
            EXPECT_EQ(r.status, 0) << c.id << ": " << r.output;
        }
    }
    const auto bad = runLittoral("-q coastal K --out " + (dir / "k").string());
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.output.find("A to J"), std::string::npos) << bad.output;
    EXPECT_FALSE(fs::exists(dir / "k"));
}

// B looks at the sun's mirror point (sensor elevation = sun elevation, azimuth opposite): the
// facets within about 0.13 deg of level mirror the sun's disc. With facet slopes of rms 0.03 rad
// (Table 10.2) that is of order 0.5 % of the water pixels, each hundreds of times the water's
// radiance. A looks along the sun: a facet would need a 30-deg tilt to mirror it, and none has.
//
// A is also the hotspot: seen along the sun's own rays, every surface the sensor sees is sunlit
// (a refracted view ray is the sun's ray reversed), so its shadows are hidden behind what casts
// them. B, looking back toward the sun, sees the shadows of the pier, the boat and the targets on
// the sand.
TEST(CoastalRuns, GlintAndTheBoatsShadowInBNoGlintAndNoShadowsInAsHotspot) {
    const fs::path dir = scratchDir("coastal", "glint");
    const Render ra = renderConfiguration(dir, 'A'), rb = renderConfiguration(dir, 'B');
    const double a = glintFraction(ra), b = glintFraction(rb);
    std::printf("glint fraction of the water pixels: A %.5f, B %.5f\n", a, b);
    EXPECT_GT(b, 5e-4);
    EXPECT_LT(a, 2e-5);
    const double sa = shadowedSandFraction(ra), sb = shadowedSandFraction(rb);
    std::printf("shadowed share of the sand: A %.5f, B %.5f\n", sa, sb);
    EXPECT_GT(sb, 5e-3);
    EXPECT_LT(sa, 0.1 * sb);
    // The boat's shadow on the water in B. In shadow the sand has the sky alone (a tenth of the
    // light; about 0.15 of the lit radiance, with the water's own path radiance): below 0.3.
    // The edge: within 0.15 m of the prediction, half the 0.23 m footprint of B's 0.2 m pixels on
    // the water along the view plus a few centimetres for eta's median (which moves the prediction
    // by 0.22 of it) and the 0.4 m surface-map disc, which blurs the edge symmetrically about the
    // mid-level.
    const BoatShadow boat = boatShadow(rb);
    EXPECT_LT(boat.dark, 0.3 * boat.lit);
    EXPECT_NEAR(boat.edge, boat.predicted, 0.15);
}

// C and D differ only in the sun (30 and 60 deg): D's pier shadow reaches farther from the pier.
// D, I and J differ only in the water (Low, Moderate, High of Table 10.3): the step targets'
// contrast falls as the water's extinction and in-scattered veil grow.
TEST(CoastalRuns, ShadowsLengthenFromCToDAndTargetContrastFallsFromDToIToJ) {
    const fs::path dir = scratchDir("coastal", "nadir");
    const Render c = renderConfiguration(dir, 'C');
    const Render d = renderConfiguration(dir, 'D');
    const double sc = pierShadowFraction(c, 0.2), sd = pierShadowFraction(d, 0.1);
    std::printf("shadowed share of the strip south of the pier: C %.3f, D %.3f\n", sc, sd);
    EXPECT_GT(sd, 0.4);
    EXPECT_GT(sd, 1.8 * sc);
    // The shadow is longer over deeper water ("elongated at deeper water depths"; Ch. 10 on B),
    // measured in D, whose rows map to y: over sand about 0.6 m deep (x -19..-16) and 1.25 m deep
    // (x -10..-7). Tolerance 0.15 m: the reported edge is the top of a 0.1 m row (the true edge lies
    // within the row above it), and eta's median is good to a few centimetres, which moves the
    // prediction by 0.6 of that. The surface map's 0.4 m disc blurs the edge symmetrically about
    // the mid-level.
    const ShadowEdge shallow = pierShadowEdge(d, -19, -16), deep = pierShadowEdge(d, -10, -7);
    EXPECT_NEAR(shallow.measured, shallow.predicted, 0.15);
    EXPECT_NEAR(deep.measured, deep.predicted, 0.15);
    EXPECT_GT(shallow.measured - deep.measured, 0.15);  // the predicted lengthening is about 0.33 m
    const double kd = targetContrast(d);
    const double ki = targetContrast(renderConfiguration(dir, 'I'));
    const double kj = targetContrast(renderConfiguration(dir, 'J'));
    std::printf("target contrast: D %.3f, I %.3f, J %.3f\n", kd, ki, kj);
    EXPECT_GT(kd, ki + 0.03);
    EXPECT_GT(ki, kj + 0.03);
}

// H is rendered twice, as in Fig. 10.7. Without photon maps the water's in-scattered light is
// counted as loss (solver: attenuation) and the Surface PM materials take the Classic solver: the
// run emits no photons, and the water seen from the rowboat is darker, by the path radiance the
// volume map adds. The two runs run in one process: the second's TIFF textures follow the first's
// GeoTIFF, and no library noise (libtiff's notes through GDAL) reaches the output.
TEST(CoastalRuns, HWithAndWithoutPhotonMaps) {
    const fs::path dir = scratchDir("coastal", "h");
    const auto r = runLittoral("-q coastal H --out " + (dir / "H").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("ERROR"), std::string::npos) << r.output;
    const auto noPm = r.output.find("without photon maps");
    ASSERT_NE(noPm, std::string::npos) << r.output;
    EXPECT_NE(r.output.find("photons emitted"), std::string::npos);
    EXPECT_EQ(r.output.find("photons emitted", noPm), std::string::npos) << r.output;
    double water[2];
    int k = 0;
    for (const char* sub : {"photon-maps", "no-photon-maps"}) {
        const Render h = readRender(dir / "H" / sub, "sim-h");
        const std::vector<double> v = waterValues(h, h.film, 0);
        EXPECT_GT(v.size(), 10000u);
        water[k++] = medianOf(v);
    }
    std::printf("H water median, 0.40-0.47 um: with photon maps %.3f, without %.3f\n", water[0], water[1]);
    EXPECT_LT(water[1], 0.95 * water[0]);
}

// E and F keep the sensor 90 deg from the sun, F at a grazing 30-deg elevation (view zenith 60
// deg) against E's 60 deg (zenith 30). The sky-reflected radiance of the water (a water product)
// is the Fresnel reflectance times the sky radiance, which the simple sky keeps the same for both
// suns (sky_fraction x hemisphere irradiance / pi). Fresnel at n = 1.34, worked here apart from the
// renderer: R(30 deg) = 0.02221, R(60 deg) = 0.06096, a ratio of 2.745. Facet slopes of rms 0.03
// rad move the local view angle by about 2 deg, which changes the ratio by under 2 %; 5 % is
// allowed for that and for the few reflected rays that meet a wave, the pier or the boat.
TEST(CoastalRuns, FresnelReflectanceHigherAtFsGrazingViewThanAtEs) {
    const fs::path dir = scratchDir("coastal", "fresnel");
    double sky[2];
    int k = 0;
    for (char id : {'E', 'F'}) {
        const Render r = renderConfiguration(dir, id);
        const std::vector<double> v = waterValues(r, render::readEnvi(r.out / (r.name + "_sky_reflected.img")), 1);
        EXPECT_GT(v.size(), 10000u);
        sky[k++] = medianOf(v);
    }
    std::printf("sky-reflected water radiance, 0.47-0.53 um: E %.4f, F %.4f, ratio %.4f (Fresnel 2.745)\n", sky[0],
                sky[1], sky[1] / sky[0]);
    EXPECT_NEAR(sky[1] / sky[0], 2.745, 0.05 * 2.745);
}

// Section 10.4's demonstrations run by name: `coastal cube` writes its scene file and cube mesh to
// DIR/scene and renders the cube; both demonstrations refuse --full and --seed (they have one
// setting) before writing anything. (What the shadow series shows is measured by `littoral
// validate`'s box-shadows case, tests/pipelines/validate_test.cpp; the caustic by
// tests/pipelines/dielectric_object_test.cpp.)
TEST(CoastalRuns, Section104DemonstrationsRunByNameAndRefuseTheSiteOptions) {
    const fs::path dir = scratchDir("coastal", "demonstrations");
    for (const std::string& args : {std::string("shadows --full"), std::string("cube --seed 3")}) {
        const auto r = runLittoral("-q coastal " + args + " --out " + (dir / "refused").string());
        EXPECT_EQ(r.status, 1) << args << ": " << r.output;
        EXPECT_NE(r.output.find("applies to the configurations A to J"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "refused")) << args;
    }
    const auto r = runLittoral("-q coastal cube --out " + (dir / "cube").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::is_regular_file(dir / "cube" / "scene" / "scene.yaml"));
    EXPECT_TRUE(fs::is_regular_file(dir / "cube" / "scene" / "cube.obj"));
    EXPECT_GT(pngSize(dir / "cube" / "cube.png").first, 100u);
    const auto check = runLittoral("-q check-scene " + (dir / "cube" / "scene" / "scene.yaml").string());
    EXPECT_EQ(check.status, 0) << check.output;
}
