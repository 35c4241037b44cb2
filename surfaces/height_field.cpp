#include "surfaces/height_field.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace littoral::surfaces {

HeightField makeHeightField(int nx, int ny, double x0, double y0, double x1, double y1) {
    LITTORAL_CHECK_GE(nx, 2);
    LITTORAL_CHECK_GE(ny, 2);
    LITTORAL_CHECK_LT(x0, x1);
    LITTORAL_CHECK_LT(y0, y1);
    HeightField f;
    f.nx = nx;
    f.ny = ny;
    f.x0 = x0;
    f.y0 = y0;
    f.x1 = x1;
    f.y1 = y1;
    f.z.assign(static_cast<size_t>(nx) * ny, 0.0);
    return f;
}

double HeightField::sample(double x, double y) const {
    const double u = std::clamp((x - x0) / dx(), 0.0, static_cast<double>(nx - 1));
    const double v = std::clamp((y - y0) / dy(), 0.0, static_cast<double>(ny - 1));
    const int i = std::min(static_cast<int>(u), nx - 2);
    const int j = std::min(static_cast<int>(v), ny - 2);
    const double fu = u - i, fv = v - j;
    return (1 - fv) * ((1 - fu) * at(i, j) + fu * at(i + 1, j)) +
           fv * ((1 - fu) * at(i, j + 1) + fu * at(i + 1, j + 1));
}

}  // namespace littoral::surfaces
