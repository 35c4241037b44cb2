#include "surfaces/beaufort.h"

#include <array>
#include <cmath>

namespace littoral::surfaces {

BeaufortPrediction beaufortPrediction(double U) {
    BeaufortPrediction p;
    p.rmsHeight = 0.016 * U * U;           // m; Speir (2010) Tables 9.5/10.2, predicted column
    p.rmsSlope = 0.003 + 0.00512 * U;      // Cox and Munk (1954) total mean-square slope
    p.correlationLength = std::sqrt(2.0) * p.rmsHeight / p.rmsSlope;  // m, Gaussian ACF
    return p;
}

namespace {
struct ForceRow {
    double lowerBound;  // m/s: force applies from this speed up to the next row's bound
    const char* name;
    const char* waves;
    const char* seaState;
};
// WMO Beaufort scale. Lower limits in m/s as tabulated by the WMO (force 4 = 5.5-7.9 m/s).
constexpr std::array<ForceRow, 13> kForces{{
    {0.0, "calm", "Calm", "Sea like a mirror"},
    {0.3, "light air", "Ripples", "Ripples with the appearance of scales are formed, but without foam crests"},
    {1.6, "light breeze", "Small wavelets", "Small wavelets, still short but more pronounced; crests have a glassy appearance and do not break"},
    {3.4, "gentle breeze", "Large wavelets", "Large wavelets; crests begin to break; foam of glassy appearance; perhaps scattered white horses"},
    {5.5, "moderate breeze", "Small waves", "Small waves, becoming longer; fairly frequent white horses"},
    {8.0, "fresh breeze", "Moderate waves", "Moderate waves, taking a more pronounced long form; many white horses are formed (chance of some spray)"},
    {10.8, "strong breeze", "Large waves", "Large waves begin to form; the white foam crests are more extensive everywhere (probably some spray)"},
    {13.9, "near gale", "Sea heaps up", "Sea heaps up and white foam from breaking waves begins to be blown in streaks along the direction of the wind"},
    {17.2, "gale", "Moderately high waves", "Moderately high waves of greater length; edges of crests begin to break into spindrift; foam is blown in well-marked streaks"},
    {20.8, "strong gale", "High waves", "High waves; dense streaks of foam along the direction of the wind; crests of waves begin to topple, tumble and roll over"},
    {24.5, "storm", "Very high waves", "Very high waves with long overhanging crests; the surface of the sea takes on a white appearance"},
    {28.5, "violent storm", "Exceptionally high waves", "Exceptionally high waves; the sea is completely covered with long white patches of foam"},
    {32.7, "hurricane", "Phenomenal seas", "The air is filled with foam and spray; sea completely white with driving spray; visibility very seriously affected"},
}};
}  // namespace

BeaufortForce beaufortForce(double U) {
    int n = 0;
    for (int i = 1; i < static_cast<int>(kForces.size()); ++i)
        if (U >= kForces[i].lowerBound) n = i;
    return {n, kForces[n].name, kForces[n].waves, kForces[n].seaState};
}

}  // namespace littoral::surfaces
