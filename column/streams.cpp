#include "column/streams.h"

#include <cmath>

#include "core/error.h"
#include "core/quadrature.h"

namespace littoral::column {

namespace {

// The n-point Gauss-Legendre rule on [a, b], nodes ascending.
void appendGauss(int n, double a, double b, Streams* s) {
    const GaussLegendre g(n);
    for (int i = n - 1; i >= 0; --i) {  // GaussLegendre's nodes are descending
        s->mu.push_back(0.5 * (a + b) + 0.5 * (b - a) * g.x[static_cast<size_t>(i)]);
        s->w.push_back(0.5 * (b - a) * g.w[static_cast<size_t>(i)]);
    }
}

}  // namespace

Streams Streams::snellSplit(int perHalf, double waterIndex) {
    LITTORAL_CHECK_GE(perHalf, 1);
    LITTORAL_CHECK_GE(waterIndex, 1.0);
    Streams s;
    s.perHalf = perHalf;
    if (waterIndex > 1.0 + 1e-9) {
        s.muCritical = std::sqrt(1.0 - 1.0 / (waterIndex * waterIndex));
        appendGauss(perHalf, 0.0, s.muCritical, &s);
        appendGauss(perHalf, s.muCritical, 1.0, &s);
    } else {
        appendGauss(2 * perHalf, 0.0, 1.0, &s);
    }
    s.mu.push_back(1.0);
    s.w.push_back(0.0);
    return s;
}

}  // namespace littoral::column
