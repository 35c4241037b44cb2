#pragma once
// Internal: the triangulated-irregular-network builder behind fromSoundings and fromLocalPoints
// (tin.cpp, the only translation unit that includes CGAL).
#include <memory>
#include <string>
#include <vector>

#include "bathymetry/terrain.h"

namespace littoral::bathymetry::detail {

struct TinInput {
    std::vector<Point3> points;                    // local frame, metres
    std::vector<std::string> labels;               // per point, for messages ("soundings.csv:12"); may be empty
    std::vector<std::vector<Point3>> constraints;  // polylines, local frame
    OutsideHull outside = OutsideHull::Error;
    double mergeDistance = 1e-3;                   // metres, plan distance
    std::string sourceName;                        // for describe() and messages
};

std::unique_ptr<Terrain> buildTin(TinInput in);

}  // namespace littoral::bathymetry::detail
