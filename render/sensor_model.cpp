#include "render/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/error.h"
#include "core/rng.h"
#include "core/units.h"
#include "render/image_output.h"

namespace littoral::render {

std::vector<Band> nominalBands(const std::vector<ir::ResponseBand>& responses) {
    std::vector<Band> b;
    for (const ir::ResponseBand& r : responses) b.push_back(r.nominal);
    return b;
}

std::vector<double> combineValues(const std::vector<double>& v, const std::vector<ir::ResponseBand>& responses) {
    std::vector<double> out;
    for (const ir::ResponseBand& r : responses) {
        double s = 0;
        for (const auto& [i, w] : r.weights) s += w * v.at(static_cast<size_t>(i));
        out.push_back(s);
    }
    return out;
}

Film combineBands(const Film& film, const std::vector<ir::ResponseBand>& responses) {
    Film out(film.width, film.height, nominalBands(responses));
    const size_t nb = film.bands.size(), no = responses.size();
    for (size_t p = 0; p < film.pixelCount(); ++p)
        for (size_t o = 0; o < no; ++o) {
            double s = 0;
            for (const auto& [i, w] : responses[o].weights) s += w * film.pixels[p * nb + static_cast<size_t>(i)];
            out.pixels[p * no + o] = static_cast<float>(s);
        }
    return out;
}

double gaussianSigmaFromFwhm(double fwhmPx) { return fwhmPx / (2.0 * std::sqrt(2.0 * std::log(2.0))); }

PsfKernel psfKernel(const ir::SensorPsf& psf) {
    PsfKernel k;
    if (psf.type == "gaussian") {
        const std::vector<double> g = gaussianKernel(gaussianSigmaFromFwhm(psf.fwhmPx));
        const int n = static_cast<int>(g.size());
        k.width = k.height = n;
        k.values.assign(static_cast<size_t>(n) * n, 0.0);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) k.values[static_cast<size_t>(y) * n + x] = g[y] * g[x];
        k.separable = g;
    } else {
        LITTORAL_CHECK(psf.type == "kernel");
        k.width = psf.width;
        k.height = psf.height;
        k.values = psf.values;
    }
    double sum = 0;
    for (double v : k.values) sum += v;
    LITTORAL_CHECK(sum > 0 && k.width % 2 == 1 && k.height % 2 == 1);
    for (double& v : k.values) v /= sum;
    return k;
}

namespace {

// One flux-conserving 1-D pass of `g` (odd length, sum 1) along x (alongX) or y over every band:
// each source pixel's value is spread over the taps inside the image, renormalised by their share.
// For a separable kernel the 2-D share inside is the product of the two 1-D shares, so two passes
// give exactly the 2-D scatter at a cost of (2 r + 1) instead of (2 r + 1)^2 per pixel.
std::vector<double> scatter1d(const std::vector<double>& in, int width, int height, size_t nb,
                              const std::vector<double>& g, bool alongX) {
    const int r = static_cast<int>(g.size()) / 2, n = alongX ? width : height;
    std::vector<double> out(in.size(), 0.0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int c = alongX ? x : y;
            double inside = 0;
            for (int i = std::max(-r, -c); i <= std::min(r, n - 1 - c); ++i) inside += g[static_cast<size_t>(i + r)];
            const size_t src = (static_cast<size_t>(y) * width + x) * nb;
            for (int i = std::max(-r, -c); i <= std::min(r, n - 1 - c); ++i) {
                const double w = g[static_cast<size_t>(i + r)] / inside;
                const size_t dst = alongX ? src + static_cast<size_t>(i) * nb
                                          : src + static_cast<size_t>(i) * static_cast<size_t>(width) * nb;
                for (size_t b = 0; b < nb; ++b) out[dst + b] += w * in[src + b];
            }
        }
    return out;
}

}  // namespace

Film applyPsf(const Film& film, const PsfKernel& k) {
    if (!k.separable.empty()) {
        std::vector<double> v(film.pixels.size());
        for (size_t p = 0; p < v.size(); ++p) v[p] = std::isfinite(film.pixels[p]) ? film.pixels[p] : 0.0;
        const size_t nb = film.bands.size();
        v = scatter1d(scatter1d(v, film.width, film.height, nb, k.separable, true), film.width, film.height, nb,
                      k.separable, false);
        Film out(film.width, film.height, film.bands);
        for (size_t p = 0; p < v.size(); ++p) out.pixels[p] = static_cast<float>(v[p]);
        return out;
    }
    Film out(film.width, film.height, film.bands);
    const int rx = k.width / 2, ry = k.height / 2;
    const size_t nb = film.bands.size();
    std::fill(out.pixels.begin(), out.pixels.end(), 0.0f);
    std::vector<double> acc(out.pixels.size(), 0.0);
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            // The kernel's share inside the image from this source pixel (1 in the interior).
            double inside = 0;
            for (int j = -ry; j <= ry; ++j)
                for (int i = -rx; i <= rx; ++i)
                    if (x + i >= 0 && x + i < film.width && y + j >= 0 && y + j < film.height)
                        inside += k.values[static_cast<size_t>(j + ry) * k.width + (i + rx)];
            const size_t src = (static_cast<size_t>(y) * film.width + x) * nb;
            for (int j = -ry; j <= ry; ++j)
                for (int i = -rx; i <= rx; ++i) {
                    if (x + i < 0 || x + i >= film.width || y + j < 0 || y + j >= film.height) continue;
                    const double w = k.values[static_cast<size_t>(j + ry) * k.width + (i + rx)] / inside;
                    const size_t dst = (static_cast<size_t>(y + j) * film.width + (x + i)) * nb;
                    for (size_t b = 0; b < nb; ++b) {
                        const float v = film.pixels[src + b];
                        if (std::isfinite(v)) acc[dst + b] += w * v;
                    }
                }
        }
    for (size_t p = 0; p < acc.size(); ++p) out.pixels[p] = static_cast<float>(acc[p]);
    return out;
}

std::vector<double> electronsPerRadiance(const ir::Sensor& s, const ir::SensorDetector& d, const std::vector<Band>& bands) {
    if (s.type != ir::Sensor::Type::Pinhole || !(s.focalLength > 0) || !(s.pixelPitch > 0))
        throw InputError(fmt::format("sensor '{}': a detector needs a pinhole or frame camera's optics (focal length and "
                                     "pixel pitch) for its pixel's solid angle",
                                     s.name));
    constexpr double kPlanck = 6.62607015e-34, kLight = 299792458.0;  // SI, exact (2019 definitions)
    const double area = kPi * 0.25 * d.apertureDiameter * d.apertureDiameter;
    const double omega = (s.pixelPitch / s.focalLength) * (s.pixelPitch / s.focalLength);
    std::vector<double> k;
    for (const Band& b : bands) {
        const double photonEnergy = kPlanck * kLight / (b.center() * 1e-6);  // J per photon
        // L [W m^-2 sr^-1 um^-1] x width [um] x A [m^2] x Omega [sr] x t [s] / E_photon x QE.
        k.push_back(d.quantumEfficiency * area * omega * d.integrationTime * b.width() / photonEnergy);
    }
    return k;
}

DetectorImage applyDetector(const Film& film, const ir::Sensor& sensor, const ir::SensorDetector& d) {
    const std::vector<double> k = electronsPerRadiance(sensor, d, film.bands);
    const double maxCount = std::ldexp(1.0, d.bits) - 1.0;
    const double gain = d.fullWell / maxCount;
    DetectorImage out;
    out.radiance = Film(film.width, film.height, film.bands);
    const size_t nb = film.bands.size(), np = film.pixelCount();
    out.dn.assign(nb, std::vector<uint32_t>(np, 0));
    out.bands.resize(nb);
    for (size_t b = 0; b < nb; ++b) {
        double signal = 0, variance = 0;
        int64_t clipped = 0;
        for (int y = 0; y < film.height; ++y) {
            // One generator per (seed, band, row): independent of threads and of the image's other rows.
            std::mt19937_64 rng(streamKey(d.seed, b, static_cast<uint64_t>(y)));
            std::normal_distribution<double> read(0.0, 1.0);
            for (int x = 0; x < film.width; ++x) {
                const size_t p = static_cast<size_t>(y) * film.width + x;
                const float L = film.pixels[p * nb + b];
                const double n = std::isfinite(L) && L > 0 ? k[b] * L : 0.0;
                double e = n > 0 ? static_cast<double>(std::poisson_distribution<int64_t>(n)(rng)) : 0.0;
                e += d.readNoise * read(rng);
                e = std::clamp(e, 0.0, d.fullWell);
                clipped += e >= d.fullWell ? 1 : 0;
                const double count = std::clamp(std::round(e / gain), 0.0, maxCount);
                out.dn[b][p] = static_cast<uint32_t>(count);
                out.radiance.pixels[p * nb + b] = static_cast<float>(count * gain / k[b]);
                signal += n;
                variance += n + d.readNoise * d.readNoise + gain * gain / 12.0;
            }
        }
        DetectorBandStats& st = out.bands[b];
        st.electronsPerRadiance = k[b];
        st.gain = gain;
        st.meanSignalE = signal / static_cast<double>(np);
        st.meanNoiseE = std::sqrt(variance / static_cast<double>(np));
        st.snr = st.meanNoiseE > 0 ? st.meanSignalE / st.meanNoiseE : 0.0;
        st.clippedFraction = static_cast<double>(clipped) / static_cast<double>(np);
    }
    return out;
}

std::string detectorReportJson(const DetectorImage& img, const ir::SensorDetector& d, const std::vector<Band>& bands) {
    std::string s = "{\n";
    s += fmt::format("  \"aperture_diameter_m\": {},\n  \"integration_time_s\": {},\n  \"quantum_efficiency\": {},\n"
                     "  \"read_noise_e\": {},\n  \"full_well_e\": {},\n  \"bits\": {},\n  \"seed\": {},\n  \"bands\": [\n",
                     d.apertureDiameter, d.integrationTime, d.quantumEfficiency, d.readNoise, d.fullWell, d.bits, d.seed);
    for (size_t b = 0; b < img.bands.size(); ++b) {
        const DetectorBandStats& st = img.bands[b];
        s += fmt::format("    {{\"band_lo_um\": {}, \"band_hi_um\": {}, \"electrons_per_radiance\": {:.6g}, "
                         "\"gain_e_per_count\": {:.6g}, \"mean_signal_e\": {:.6g}, \"mean_noise_e\": {:.6g}, "
                         "\"snr\": {:.6g}, \"clipped_fraction\": {:.6g}}}{}\n",
                         bands[b].lo, bands[b].hi, st.electronsPerRadiance, st.gain, st.meanSignalE, st.meanNoiseE,
                         st.snr, st.clippedFraction, b + 1 < img.bands.size() ? "," : "");
    }
    return s + "  ]\n}\n";
}

}  // namespace littoral::render
