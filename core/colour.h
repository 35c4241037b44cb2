#pragma once
// Colorimetry for the true-colour previews: the CIE 1931 2-degree standard observer, the
// reconstruction of a spectrum from band-averaged radiances, and sRGB (IEC 61966-2-1).
//
// A film's bands give the band averages L_b of a spectrum. The preview takes the spectrum to be
// L_b inside band b (the mean of the bands that contain a wavelength, where bands overlap),
// linear between the facing edges of two neighbouring bands across a gap, and the outermost
// band's value beyond the bands. Then X = int S(l) xbar(l) dl, and so on, which is linear in the
// L_b: X = sum_b wx_b L_b. A spectrally flat radiance is reproduced exactly, so its colour is that
// of the equal-energy illuminant whatever the bands.
#include <array>
#include <vector>

#include "core/spectrum.h"

namespace littoral {

struct Xyz {
    double x = 0, y = 0, z = 0;
};

// The CIE 1931 2-degree colour-matching functions at `um` micrometres (linear interpolation of
// the 5 nm table of CIE 15:2004, 380-780 nm; 0 outside).
Xyz cieCmf(double um);

// Per band, the weights that give XYZ from band-averaged radiances (the reconstruction above),
// scaled so that a flat spectrum of radiance L has Y = L. Bands must be valid (lo < hi).
std::vector<Xyz> xyzBandWeights(const std::vector<Band>& bands);

// Whether bands span the visible enough for a true-colour preview: at least 3 bands whose range
// [min lo, max hi] holds at least kVisibleCoverage of the integral of each of xbar, ybar, zbar.
inline constexpr double kVisibleCoverage = 0.9;
double visibleCoverage(const std::vector<Band>& bands);  // the smallest of the three shares
bool spansVisible(const std::vector<Band>& bands);

// XYZ <-> linear sRGB (D65 white; IEC 61966-2-1 matrices), and the sRGB transfer curve.
std::array<double, 3> xyzToLinearSrgb(const Xyz& c);
Xyz linearSrgbToXyz(const std::array<double, 3>& rgb);
double srgbEncode(double linear);  // [0, 1] -> [0, 1]
double srgbDecode(double encoded);

// Chromaticity (x, y) of an XYZ colour ({0, 0} for black).
std::array<double, 2> chromaticity(const Xyz& c);

}  // namespace littoral
