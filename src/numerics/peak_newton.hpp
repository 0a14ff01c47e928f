// hbfriction — internal: a maximum of Y(w) located by Newton on dY/dw = 0 with the derivatives
// from central differences of values (the FRF's peak refinement and the peak tracking share it).
//
// A maximum located by comparing values is only found to about sqrt(eps / c) relative (eps the
// values' relative rounding, c = -Y'' w^2 / Y the peak's curvature): 1e-8 to 1e-7 on sharp
// exact resonances. The root of a difference derivative does better: with the 5-point rule
// (truncation ~ h^4 Y^(5), rounding ~ eps Y / h) at h = 1e-4 w the error stays near 1e-11 w for
// eps ~ 1e-13 and c ~ 1e2..1e4. The search starts with the 3-point rule at h = h_rel w (cheaper,
// truncation h^2 Y''' / (6 Y'') ~ 1e-9 w at h_rel = 1e-5) and switches to the 5-point rule
// at 10 h once a step is below 1e-6 w.
#pragma once

#include <functional>
#include <limits>
#include <string>

namespace hbf::detail {

struct PeakNewton {
    bool ok = false;
    bool no_maximum = false;  ///< Y is not concave near the start, or the search left max_move
    bool corner = false;      ///< `corner` said the regimes change within the stencil at the end
    bool kink = false;        ///< Y' changes sign across 1e-12 w: a kink of Y is the maximum (omega)
    double omega = 0, value = 0;
    double curvature = std::numeric_limits<double>::quiet_NaN();  ///< Y'' w^2 / Y at the end
    int iterations = 0;
    std::string message;  ///< why not ok
};

/// The maximum of value(w, ok) near w0: Newton steps -Y'/Y'' (a step at most 2 % of w; on a
/// convex stretch a step of 0.2 % of w uphill), 3-point until a step is below 1e-6 w, then
/// 5-point until a step is below 1e-8 w (usually one: the error left is ~1e-3 of the last
/// step, plus the stencil's; both scale with the peak's width) or no longer halves (the values'
/// rounding: harmonic balance's tolerance). no_maximum when the search
/// moves more than max_move w0 from w0 or does not settle in 40 iterations. `corner(lo, hi)`
/// (may be empty) says whether the regimes differ between lo and hi: when they do across the
/// final stencil, the search stops with corner = true at its last w (the caller locates the
/// corner). Once Y' has shown both signs, steps that leave the bracket bisect it; a bracket
/// closed to 1e-12 w is a kink of Y (kink = true: the maximum over one period switches between
/// two turning points in time). value(w, ok) sets ok = false for a failed solve (the search
/// stops: message names w).
PeakNewton peak_newton(const std::function<double(double, bool&)>& value, double w0, double h_rel, double max_move,
                       const std::function<bool(double, double)>& corner = {});

}  // namespace hbf::detail
