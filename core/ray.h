#pragma once
#include <limits>

#include "core/vec.h"

namespace littoral {

// A ray o + t d for t in [tMin, tMax]. d need not be unit length, but renderer code keeps it unit
// so that t is a distance in metres (Beer–Lambert attenuation uses it directly).
struct Ray {
    Point3 o;
    Vec3 d{0, 0, 1};
    double tMin = 0.0;
    double tMax = std::numeric_limits<double>::infinity();
    Point3 at(double t) const { return o + d * t; }
};

}  // namespace littoral
