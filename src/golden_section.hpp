// hbfriction — internal: golden-section search for the maximum of a unimodal function.
#pragma once

#include <cmath>

namespace hbf::detail {

struct GoldenMaximum {
    double x = 0, value = 0;
};

/// Maximises `f` on [lo, hi] to hi - lo <= relative * hi. `f(x, ok)` may set ok = false
/// (a failed evaluation): the search stops and ok stays false for the caller.
template <class F>
GoldenMaximum golden_section_maximum(F&& f, double lo, double hi, double relative, bool& ok) {
    const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = hi - golden * (hi - lo), d = lo + golden * (hi - lo);
    double yc = f(c, ok), yd = f(d, ok);
    while (ok && hi - lo > relative * hi) {
        if (yc >= yd) {
            hi = d;
            d = c;
            yd = yc;
            c = hi - golden * (hi - lo);
            yc = f(c, ok);
        } else {
            lo = c;
            c = d;
            yc = yd;
            d = lo + golden * (hi - lo);
            yd = f(d, ok);
        }
    }
    return yc >= yd ? GoldenMaximum{c, yc} : GoldenMaximum{d, yd};
}

}  // namespace hbf::detail
