// hbfriction — internal to studies: a peak or a stick-slip boundary located at fixed p from a
// predicted frequency (track_locate.hpp).
#include "studies/track_locate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "hbf/error.hpp"
#include "numerics/peak_newton.hpp"

namespace hbf::detail {

bool bisect_regime(ResponseSolver& solver, double p, int contact, ResponseSolver::Solution& lo, double& w_lo,
                   ResponseSolver::Solution& hi, double& w_hi, double tol) {
    const std::string a = lo.regime(contact);
    for (int it = 0; it < 200 && std::abs(w_hi - w_lo) > tol * std::abs(w_hi); ++it) {
        const double mid = 0.5 * (w_lo + w_hi);
        ResponseSolver::Solution s = solver.at(p, mid, lo.state);
        if (!s.ok) s = solver.at(p, mid, hi.state);
        if (!s.ok) return false;
        if (s.regime(contact) == a) {
            lo = std::move(s);
            w_lo = mid;
        } else {
            hi = std::move(s);
            w_hi = mid;
        }
    }
    return true;
}

/// The peak of Y(w) at p near w0 (peak_newton.hpp), or the stick/slip corner it sits on.
Fix locate_peak(ResponseSolver& solver, double p, double w0, const Eigen::VectorXd& start, double wmin, double wmax) {
    Fix f;
    ResponseSolver::Solution last;
    last.state = start;
    std::string failure;
    std::vector<std::pair<double, ResponseSolver::Solution>> recent;  // the stencil's solutions
    const auto value = [&](double w, bool& good) {
        if (!(w > 0.0 && std::isfinite(w))) {  // a Newton step past w = 0: no maximum there
            good = false;
            failure = "a step reached w = " + format_number(w);
            return 0.0;
        }
        ResponseSolver::Solution s = solver.at(p, w, last.state);
        if (!s.ok) {
            good = false;
            failure = s.message;
            return 0.0;
        }
        last = std::move(s);
        if (recent.size() == 6) recent.erase(recent.begin());
        recent.emplace_back(w, last);
        return last.y;
    };
    const auto solution_at = [&](double w) {
        for (const auto& [x, s] : recent)
            if (x == w) return s;
        return solver.at(p, w, last.state);
    };
    ResponseSolver::Solution lo, hi;
    double w_lo = 0, w_hi = 0;
    const auto corner = [&](double a, double b) {
        lo = solution_at(a);
        hi = solution_at(b);
        w_lo = a;
        w_hi = b;
        return lo.ok && hi.ok && lo.regimes != hi.regimes;
    };
    const detail::PeakNewton r = detail::peak_newton(value, w0, solver.exact() ? 1e-5 : 1e-4, 0.05, corner);
    f.iterations = r.iterations;
    if (!r.ok) {
        f.no_feature = r.no_maximum;
        f.message = r.message + (failure.empty() ? "" : ": " + failure);
        return f;
    }
    if (r.corner) {
        // The maximum is the transition between the two sides: located by bisection.
        int changed = 0;
        for (std::size_t k = 0; k < lo.regimes.size(); ++k)
            if (lo.regimes[k] != hi.regimes[k]) {
                changed = static_cast<int>(k);
                break;
            }
        if (!bisect_regime(solver, p, changed, lo, w_lo, hi, w_hi, 1e-12)) {
            f.message = "a solve failed while locating the corner near w = " + format_number(r.omega);
            return f;
        }
        const bool low_side = lo.y >= hi.y;
        last = low_side ? lo : hi;
        f.corner = true;
        f.omega = low_side ? w_lo : w_hi;
    } else {
        f.omega = r.omega;
        f.curvature = r.curvature;
        f.corner = r.kink;
    }
    f.ok = true;
    f.value = last.y;
    f.regime = last.regime(0);
    f.state = last.state;
    f.outside = f.omega < wmin || f.omega > wmax;
    return f;
}

/// Contact `contact`'s boundary between the regimes below and above it near w0 at p.
Fix locate_boundary(ResponseSolver& solver, double p, double w0, double spread, const Eigen::VectorXd& start,
                    int contact, const std::string& below, const std::string& above, double wmin, double wmax) {
    Fix f;
    // The regime at the prediction says on which side the boundary lies; steps outward from it
    // (the first a tenth of the last step's change of w, growing 4 times) until the other
    // regime shows: the bracket [lo, hi] keeps the last two solves.
    ResponseSolver::Solution near = solver.at(p, w0, start);
    if (!near.ok) {
        f.message = "the solve at w = " + format_number(w0) + " failed: " + near.message;
        return f;
    }
    const std::string r0 = near.regime(contact);
    if (r0 != below && r0 != above) {
        f.no_feature = true;
        f.message = "the regime at w = " + format_number(w0) + " is " + r0 + ", neither " + below + " nor " + above;
        return f;
    }
    const bool up = r0 == below;  // the boundary lies above w0
    const std::string& wanted = up ? above : below;
    double d = std::clamp(0.1 * spread, 1e-6 * w0, 1e-3 * w0), w_near = w0, w_far = w0;
    ResponseSolver::Solution far;
    bool found = false;
    for (int it = 0; it < 12 && !found; ++it) {
        w_far = w0 + (up ? d : -d);
        far = solver.at(p, w_far, near.state);
        if (!far.ok) {
            f.message = "the solve at w = " + format_number(w_far) + " failed: " + far.message;
            return f;
        }
        if (far.regime(contact) == wanted) {
            found = true;
            break;
        }
        if (far.regime(contact) != r0) break;  // a third regime: another boundary came first
        near = far;
        w_near = w_far;
        d *= 4.0;
        if (d > 0.05 * w0) break;
    }
    f.iterations = 1;
    if (!found) {
        f.no_feature = true;
        f.message = "no " + below + "|" + above + " boundary of contact " + std::to_string(contact + 1) +
                    " within 5 % of w = " + format_number(w0);
        return f;
    }
    ResponseSolver::Solution lo = up ? near : far, hi = up ? far : near;
    double w_lo = up ? w_near : w_far, w_hi = up ? w_far : w_near;
    const System& system = solver.system(p);
    bool closed_form = false;
    if (solver.exact() && (below == "stick" || above == "stick")) {
        // From full stick: where the permanent-stick load crosses 1 (closed form), if every
        // contact sticks on the stuck side and contact `contact` is the one at its limit.
        const bool low_stuck = below == "stick";
        const ResponseSolver::Solution& stuck = low_stuck ? lo : hi;
        bool all = true;
        for (const std::string& r : stuck.regimes) all = all && r == "stick";
        double ws = low_stuck ? w_lo : w_hi, wx = low_stuck ? w_hi : w_lo;
        if (all && permanent_stick_load(system, ws) <= 1.0 && permanent_stick_load(system, wx) > 1.0) {
            for (int it = 0; it < 200 && std::abs(wx - ws) > 1e-13 * std::abs(wx); ++it) {
                const double mid = 0.5 * (ws + wx);
                (permanent_stick_load(system, mid) <= 1.0 ? ws : wx) = mid;
            }
            if (permanent_stick_load(system, ws, contact) >= (1.0 - 1e-9) * permanent_stick_load(system, ws)) {
                ResponseSolver::Solution s = solver.at(p, ws, stuck.state);
                if (s.ok && s.regime(contact) == "stick") {
                    (low_stuck ? lo : hi) = s;
                    (low_stuck ? w_lo : w_hi) = ws;
                    closed_form = true;
                }
            }
        }
    }
    if (!closed_form && !bisect_regime(solver, p, contact, lo, w_lo, hi, w_hi, solver.exact() ? 1e-12 : 1e-10)) {
        f.message = "a solve failed while bisecting the boundary near w = " + format_number(w0);
        return f;
    }
    // The point on the stick side of the boundary (stick, else stick-slip).
    const bool low_side = closed_form ? below == "stick" : (below == "stick" || (below == "stick-slip" && above == "slip"));
    const ResponseSolver::Solution& side = low_side ? lo : hi;
    f.ok = true;
    f.omega = low_side ? w_lo : w_hi;
    f.value = side.y;
    f.regime = side.regime(contact);
    f.state = side.state;
    f.outside = f.omega < wmin || f.omega > wmax;
    return f;
}

std::string short_number(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
}

TrackPoint point_of(double p, const Fix& f, const std::string& kind) {
    TrackPoint t;
    t.p = p;
    t.omega = f.omega;
    t.value = f.value;
    t.kind = kind;
    t.regime = f.regime;
    t.curvature = f.curvature;
    t.corner = f.corner;
    t.state = f.state;
    return t;
}


}  // namespace hbf::detail
