#pragma once
// Spectra and spectral bands. Wavelengths are in micrometres everywhere.
//
// A Spectrum is a tabulated function of wavelength, linearly interpolated between samples.
// Outside its tabulated range it is undefined: asking for it is an InputError, because silently
// extrapolating a reflectance or an absorption coefficient corrupts every radiometric number.
// A constant spectrum (one value, no wavelengths) is defined everywhere.
//
// A Band is an interval [lo, hi] um; the renderer works on a list of bands (BandSet) and
// carries one value per band (band-averaged coefficients, band-integrated radiance).
#include <string>
#include <vector>

namespace littoral {

struct Band {
    double lo = 0.4, hi = 0.6;  // um
    double center() const { return 0.5 * (lo + hi); }
    double width() const { return hi - lo; }
};

class Spectrum {
public:
    Spectrum() = default;                 // constant 0
    static Spectrum constant(double v);
    // Wavelengths strictly increasing (um), same count as values, at least one sample.
    // Throws InputError naming `what` on malformed tables.
    static Spectrum tabulated(std::vector<double> wavelengths, std::vector<double> values,
                              const std::string& what = "spectrum");

    bool isConstant() const { return wl_.empty(); }
    const std::vector<double>& wavelengths() const { return wl_; }
    const std::vector<double>& values() const { return val_; }
    double minWavelength() const;
    double maxWavelength() const;
    bool covers(double lo, double hi) const;

    // Value at one wavelength (linear interpolation). Throws InputError outside the table.
    double at(double wavelengthUm) const;
    // Integral over [lo, hi] of the piecewise-linear function (units: value * um).
    double integrate(double lo, double hi) const;
    // Band average: integrate(lo, hi) / (hi - lo). Throws InputError naming `what` if the band
    // is not covered by the table.
    double bandAverage(const Band& b, const std::string& what = "spectrum") const;
    std::vector<double> bandAverages(const std::vector<Band>& bands, const std::string& what = "spectrum") const;

    Spectrum scaled(double s) const;

private:
    std::vector<double> wl_, val_;
};

// `n` equal-width contiguous bands spanning [lo, hi].
std::vector<Band> uniformBands(double lo, double hi, int n);

}  // namespace littoral
