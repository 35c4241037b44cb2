#pragma once
// The Beaufort/RMS wave model of the dissertation (Speir 2010, Tables 9.5 and 10.2; digest in
// spec/seed-ch05-10.md section 1.9) and the WMO Beaufort wind force.
//
// From the wind speed U (m/s, referenced to 12.5 m above mean sea level as in Cox and Munk
// 1954) the model predicts
//   RMS height          h = 0.016 U^2                         (m)
//   RMS slope           s = 0.003 + 0.00512 U                 (per axis, dimensionless)
//   correlation length  L = sqrt(2) h / s                     (m)
// s is numerically the Cox-Munk total mean-square slope; the dissertation calls it an RMS slope
// and we keep its numbers. L = sqrt(2) h / s holds when s is the RMS slope along one axis of a
// Gaussian random surface with autocorrelation C(r) = h^2 exp(-r^2 / L^2), because then the
// per-axis slope variance is -C''(0) = 2 h^2 / L^2.
#include <string>

namespace littoral::surfaces {

struct BeaufortPrediction {
    double rmsHeight = 0;          // h, m
    double rmsSlope = 0;           // s, per axis (dimensionless; "radians" in the tables)
    double correlationLength = 0;  // L, m (1/e distance of the autocorrelation)
};

// Requires windSpeed > 0 (checked by the callers that validate user input).
BeaufortPrediction beaufortPrediction(double windSpeed);

// WMO Beaufort scale (WMO-No. 306 / Manual on Codes; force limits in m/s at 10 m).
struct BeaufortForce {
    int number = 0;            // 0..12
    std::string name;          // "moderate breeze"
    std::string waves;         // short wave description used in the tables: "Small waves"
    std::string seaState;      // full WMO specification of the sea
};

BeaufortForce beaufortForce(double windSpeed);

}  // namespace littoral::surfaces
