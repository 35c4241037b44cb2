#pragma once
// The sensor model applied to a rendered radiance film (docs/outputs.md, "Sensor model"):
//
//   PSF       a point-spread function on the radiance itself: a Gaussian given by its FWHM in
//             pixels, or a tabulated kernel (odd width and height, normalised to sum 1). Each
//             pixel's radiance is spread over its neighbours by the kernel; the part that would
//             fall outside the image is shared over the kernel's cells inside it, so the image's
//             total is conserved exactly (a point source in the interior gives the kernel).
//   Detector  photo-electrons from the radiance of each pixel and band,
//               N = QE A Omega t (lambda / (h c)) L dLambda,
//             A the aperture's area, Omega = (pitch / focal)^2 the pixel's solid angle (at the
//             image centre; the cos^4 fall-off is not modelled), t the integration time, lambda the
//             band centre and dLambda its width; then shot noise (Poisson in N), read noise
//             (Gaussian, sigma in electrons), clipping at the full well and quantisation to
//             `bits` bits with gain g = full well / (2^bits - 1) electrons per count. The counts
//             are converted back to radiance (DN g / k, k = N / L) so that the noisy image sits
//             beside the noiseless one in the same units. Seeded: the same seed gives the same
//             noise whatever the thread count.
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene_ir.h"
#include "render/film.h"

namespace littoral::render {

// Spectral response (core/spectral_response.h): the output bands of `film`, each the weighted mean
// of its (internal sub-)bands; the bands of the result are the response bands' nominal ones.
Film combineBands(const Film& film, const std::vector<ir::ResponseBand>& responses);
// The same for one value per band (a probe's mean).
std::vector<double> combineValues(const std::vector<double>& perBand, const std::vector<ir::ResponseBand>& responses);
std::vector<Band> nominalBands(const std::vector<ir::ResponseBand>& responses);

// sigma = FWHM / (2 sqrt(2 ln 2)).
double gaussianSigmaFromFwhm(double fwhmPx);

// The kernel of a PSF: a normalised width x height table (odd sizes), row-major. A Gaussian is
// sampled at integer offsets to ceil(4 sigma) (gaussianKernel's rule) and normalised.
struct PsfKernel {
    int width = 1, height = 1;
    std::vector<double> values{1.0};
    std::vector<double> separable;  // a Gaussian's 1-D factor (values = its outer product): two 1-D passes
};
PsfKernel psfKernel(const ir::SensorPsf& psf);

// Every band of `film` convolved with the kernel, conserving each band's total (above).
Film applyPsf(const Film& film, const PsfKernel& kernel);

// Photo-electrons per unit radiance (W m^-2 sr^-1 um^-1) in each band of a pinhole sensor.
std::vector<double> electronsPerRadiance(const ir::Sensor& sensor, const ir::SensorDetector& d,
                                         const std::vector<Band>& bands);

struct DetectorBandStats {
    double electronsPerRadiance = 0;  // k
    double gain = 0;                  // electrons per count
    double meanSignalE = 0;           // mean noiseless electrons over the image
    double meanNoiseE = 0;            // sqrt(mean of the modelled variance: N + read^2 + g^2/12)
    double snr = 0;                   // meanSignalE / meanNoiseE
    double clippedFraction = 0;       // pixels at the full well
};
struct DetectorImage {
    Film radiance;                          // DN g / k per band
    std::vector<std::vector<uint32_t>> dn;  // per band, the counts (row-major)
    std::vector<DetectorBandStats> bands;
};
// InputError if the sensor is not a pinhole (the detector needs its optics).
DetectorImage applyDetector(const Film& film, const ir::Sensor& sensor, const ir::SensorDetector& d);

// The detector's report as JSON text (per band: centre, k, gain, mean signal, noise, SNR).
std::string detectorReportJson(const DetectorImage& img, const ir::SensorDetector& d, const std::vector<Band>& bands);

}  // namespace littoral::render
