// hbfriction — folds and stick-slip transitions located between the points of a traced
// branch (locate.hpp; see continue_branch in continuation.hpp).
#include "continuation/locate.hpp"
#include "hbf/post_processing.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hbf/error.hpp"

namespace hbf::detail {

namespace {

/// f(), a location's solve: an exception of the solver (not bad input) makes it a failed
/// location, counted in result.location_errors, the first such message kept in `error`.
template <class F>
bool guarded(F&& f, std::string& error, BranchResult& result) {
    try {
        return f();
    } catch (const InvalidInput&) {
        throw;
    } catch (const std::exception& e) {
        if (error.empty()) error = e.what();
        ++result.location_errors;
        return false;
    }
}

/// Appends "; <what> failed in the solver: <error>" to the result's message when `error` is set.
void say_solver_error(BranchResult& result, const std::string& what, const std::string& error) {
    if (error.empty()) return;
    result.message += (result.message.empty() ? "" : "; ") + what + " failed in the solver: " + error;
}

/// The regime of contact `contact` at a point (stick_pattern).
std::string regime_at(HarmonicBalance& hb, const SolutionPoint& p, int contact) {
    return stick_pattern(hb.stick_indicator(p.x, p.omega, contact),
                         stick_phase_samples(hb.harmonics(), hb.time_samples()))
        .regime;
}
/// Every contact's regime at a point.
std::vector<std::string> regimes_at(HarmonicBalance& hb, const SolutionPoint& p) {
    std::vector<std::string> r;
    for (int c = 0; c < static_cast<int>(hb.system().contacts.size()); ++c) r.push_back(regime_at(hb, p, c));
    return r;
}

/// Whether the point lies on the stick side of the boundary (stick|stick-slip: in full
/// stick; stick-slip|slip: not in full slip).
bool stick_side(Boundary boundary, const std::string& regime) {
    return boundary == Boundary::stick_stick_slip ? regime == "stick" : regime != "slip";
}

/// The unit chord from a to b in the scaled coordinates (x / x_scale, omega / omega_scale), with
/// x_scale the larger of the two points' unknown scales; length 0 when a and b coincide.
struct Chord {
    double x_scale = 1.0, length = 0.0;
    Eigen::VectorXd direction;
};
Chord chord_between(HarmonicBalance& hb, const SolutionPoint& a, const SolutionPoint& b, double omega_scale) {
    const int n = hb.unknowns();
    Chord c;
    c.x_scale = std::max(hb.unknown_scale(a.x), hb.unknown_scale(b.x));
    c.direction.resize(n + 1);
    c.direction.head(n) = (b.x - a.x) / c.x_scale;
    c.direction(n) = (b.omega - a.omega) / omega_scale;
    c.length = c.direction.norm();
    if (c.length > 0.0) c.direction /= c.length;
    return c;
}

/// Locates, between successive points a and b of a branch, where contact `contact`'s g(u) (max
/// phi for stick|stick-slip, min phi for stick-slip|slip) changes sign, by bisection along the
/// chord (see continue_branch). Returns false if a correction fails.
bool bisect_transition(HarmonicBalance& hb, Corrector& corrector, Corrector& patient, const SolutionPoint& a,
                       const SolutionPoint& b, Boundary boundary, int contact, double omega_scale,
                       SolutionPoint& out) {
    const Chord c = chord_between(hb, a, b, omega_scale);
    if (!(c.length > 0.0)) return false;
    const double x_scale = c.x_scale, length = c.length;
    const Eigen::VectorXd& chord = c.direction;
    auto side = [&](const SolutionPoint& p) { return stick_side(boundary, regime_at(hb, p, contact)); };
    const bool side_a = side(a);
    SolutionPoint lo = a, hi = b;  // lo on a's side, hi on b's
    double t_lo = 0.0, t_hi = 1.0;
    while ((t_hi - t_lo) * length > 1e-10) {
        // The midpoint, or off-centre points when the correction fails there: a nonsmooth
        // law's residual may not be solvable to the tolerance at one spot but is beside it.
        SolutionPoint m = a;
        double t = 0.0;
        bool corrected = false;
        // Then, as the continuation retries, with five times the iterations (measured: the
        // 200-DOF beam's stick-slip|slip boundary near 103 rad/s needs them).
        for (Corrector* c : {&corrector, &patient}) {
            for (const double fraction : {0.5, 0.382, 0.618}) {
                t = t_lo + fraction * (t_hi - t_lo);
                m.x = a.x + t * (b.x - a.x);
                m.omega = a.omega + t * (b.omega - a.omega);
                if ((corrected = c->correct(m.x, m.omega, chord, x_scale, m.iterations, m.residual, omega_scale)))
                    break;
            }
            if (corrected) break;
        }
        if (!corrected) {
            // A bracket already within 1 % of the step is located (its stick-side end is a
            // converged point; HB's own transitions are O(1/H) misplaced anyway, measured on
            // chain3_exact.toml at --tolerance 1e-11: the corrector stalls at 0.5 % of the step);
            // a wider one is not.
            if (t_hi - t_lo > 1e-2) return false;
            break;
        }
        if (side(m) == side_a) {
            lo = m;
            t_lo = t;
        } else {
            hi = m;
            t_hi = t;
        }
    }
    // The stick-side point of the boundary.
    out = side_a ? lo : hi;
    out.kind = PointKind::transition;
    out.boundary = boundary;
    out.contact = contact;
    out.step = 0.0;
    return true;
}

/// Locates the fold marked at b (the tangent's omega-component changed sign between a and b)
/// on the chord between them: the test function is g = t_omega, the omega-component of the unit
/// tangent, i.e. the last unknown of the bordered system [dR/dX, dR/domega; chord^T] t = e
/// (branch_tangent), oriented along the chord; it is zero exactly where dR/dX is singular. Each
/// trial point is corrected onto the branch on the hyperplane normal to the chord; the bracket
/// shrinks by regula falsi (Illinois), to 1e-12 of the chord or 1e-10 of arclength. On a piecewise-smooth branch g
/// may jump through zero at a corner instead (a fold of the HB equations at a kink: Dahl's |v|
/// at a sample, a stick/slip switch): the bracket then closes on the corner, which is the fold.
/// Returns false when a correction fails, or when the turn is not real: omega at the located
/// point must exceed (or fall below) omega at both a and b by more than 1e-10 omega, not just
/// by rounding (on nearly vertical segments, where omega is constant to ~1e-12, the sign of
/// t_omega is noise).
bool locate_fold(HarmonicBalance& hb, Corrector& corrector, Corrector& patient, const SolutionPoint& a,
                 const SolutionPoint& b, double omega_scale, SolutionPoint& out,
                 const std::function<std::string()>& stop) {
    const int n = hb.unknowns();
    const Chord c = chord_between(hb, a, b, omega_scale);
    if (!(c.length > 0.0)) return false;
    const double x_scale = c.x_scale;
    const Eigen::VectorXd& chord = c.direction;
    auto g = [&](const SolutionPoint& p) { return branch_tangent(hb, p.x, p.omega, x_scale, chord, omega_scale)(n); };
    double t_lo = 0.0, t_hi = 1.0, g_lo = g(a), g_hi = g(b);
    if (!(g_lo * g_hi < 0.0)) return false;
    const bool towards_larger = g_lo > 0.0;  // omega grows from a: a turn at a largest omega
    SolutionPoint lo = a, hi = b;
    SolutionPoint best = std::abs(g_lo) < std::abs(g_hi) ? a : b;
    double g_best = std::min(std::abs(g_lo), std::abs(g_hi));
    int kept = 0;  // Illinois: +1 after moving the low end, -1 after the high end
    // To 1e-12 of the chord, or 1e-10 of arclength (the transitions' bisection's tolerance): a
    // fold at a corner of the branch (below) closes its bracket only linearly, and on an
    // interface of 99 nodes with many such folds the last decades cost more Jacobians than the
    // branch itself.
    for (int iteration = 0; iteration < 60 && (t_hi - t_lo) > 1e-12 && (t_hi - t_lo) * c.length > 1e-10;
         ++iteration) {
        if (stop && !stop().empty()) return false;  // an interrupt or the time limit: asked each step
        double t = (t_lo * g_hi - t_hi * g_lo) / (g_hi - g_lo);
        if (!(t > t_lo && t < t_hi)) t = 0.5 * (t_lo + t_hi);
        SolutionPoint m = a;
        bool corrected = false;
        for (Corrector* c : {&corrector, &patient}) {
            m.x = a.x + t * (b.x - a.x);
            m.omega = a.omega + t * (b.omega - a.omega);
            if ((corrected = c->correct(m.x, m.omega, chord, x_scale, m.iterations, m.residual, omega_scale))) break;
        }
        if (!corrected) return false;
        const double gm = g(m);
        if (std::abs(gm) < g_best) {
            g_best = std::abs(gm);
            best = m;
        }
        if (gm == 0.0) break;
        if ((gm < 0.0) == (g_hi < 0.0)) {
            t_hi = t;
            g_hi = gm;
            hi = m;
            if (kept == -1) g_lo *= 0.5;  // the low end kept twice: halve its value
            kept = -1;
        } else {
            t_lo = t;
            g_lo = gm;
            lo = m;
            if (kept == 1) g_hi *= 0.5;
            kept = 1;
        }
        // A corner: g does not fall with the bracket (|g| above 1e4 times its arclength once that
        // is below 1e-7; a smooth fold's g falls like the curvature times the distance). Its
        // bracket closes only by halving (some 40 corrections and tangents on the block's
        // interface); 1e-7 of arclength places it well within any use of a fold.
        const double arclength = (t_hi - t_lo) * c.length;
        if (arclength < 1e-7 && g_best > 1e4 * arclength) break;
    }
    // A corner: g jumps through zero (a time sample's |v| or stick/slip switching makes the HB
    // residual piecewise smooth) and the bracket closed on it without a small g: the turn is
    // at the corner, the end of the final bracket with the extreme omega.
    if (g_best > 1e-9) best = (hi.omega > lo.omega) == towards_larger ? hi : lo;
    const double up_a = best.omega - a.omega, up_b = best.omega - b.omega;
    const bool extremal = (up_a > 0.0 && up_b > 0.0) || (up_a < 0.0 && up_b < 0.0);
    if (!extremal || std::max(std::abs(up_a), std::abs(up_b)) <= 1e-10 * std::abs(best.omega)) return false;
    out = best;
    out.kind = PointKind::fold;
    out.step = 0.0;
    out.branch = a.branch;
    return true;
}

}  // namespace

bool stop_location(const std::function<std::string()>& stop, std::string& why, BranchResult& result,
                   const std::string& left) {
    if (!why.empty()) return true;
    if (!stop) return false;
    why = stop();
    if (why.empty()) return false;
    const bool already = result.status == ContinuationStatus::stopped;  // the trace said why
    if (result.status < ContinuationStatus::stopped) result.status = ContinuationStatus::stopped;
    result.message += (result.message.empty() ? "" : "; ") + left + (already ? std::string() : " (stopped: " + why + ")");
    return true;
}

void insert_transitions(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options,
                        double omega_scale, BranchResult& result, const std::function<std::string()>& stop) {
    if (hb.system().contacts.empty() || result.points.size() < 2) return;
    CorrectorOptions patient_options = options;
    patient_options.max_iterations = std::max(100, 5 * patient_options.max_iterations);
    Corrector patient(hb, patient_options);
    std::vector<SolutionPoint> points;
    points.reserve(result.points.size() + 8);
    std::vector<std::string> previous = regimes_at(hb, result.points.front());
    points.push_back(result.points.front());
    const bool several = previous.size() > 1;
    int lost = 0;
    std::string where, stopped, solver_error;
    for (std::size_t k = 1; k < result.points.size(); ++k) {
        const SolutionPoint &a = result.points[k - 1], &b = result.points[k];
        const std::vector<std::string> current = regimes_at(hb, b);
        if (a.branch == b.branch && !stop_location(stop, stopped, result, "stick-slip transitions not located")) {
            std::vector<SolutionPoint> found;
            for (int c = 0; c < static_cast<int>(current.size()); ++c) {
                const auto i = static_cast<std::size_t>(c);
                for (const Boundary boundary : {Boundary::stick_stick_slip, Boundary::stick_slip_slip}) {
                    if (stick_side(boundary, previous[i]) == stick_side(boundary, current[i])) continue;
                    SolutionPoint t;
                    if (guarded([&] { return bisect_transition(hb, corrector, patient, a, b, boundary, c, omega_scale, t); },
                                solver_error, result)) {
                        found.push_back(std::move(t));
                    } else {
                        ++lost;
                        where += (where.empty() ? "" : ", ") + to_string(boundary) +
                                 (several ? " of contact " + std::to_string(c + 1) : std::string()) +
                                 " between w = " + format_number(a.omega) + " and " + format_number(b.omega);
                    }
                }
            }
            // In branch order: by the distance from a along the chord.
            std::sort(found.begin(), found.end(), [&](const SolutionPoint& p, const SolutionPoint& q) {
                return (p.x - a.x).squaredNorm() + std::pow(p.omega - a.omega, 2) <
                       (q.x - a.x).squaredNorm() + std::pow(q.omega - a.omega, 2);
            });
            for (SolutionPoint& t : found) points.push_back(std::move(t));
        }
        points.push_back(b);
        previous = current;
    }
    result.transitions = static_cast<int>(points.size() - result.points.size());
    result.contact_transitions = transitions_per_contact(points, static_cast<int>(hb.system().contacts.size()));
    result.points = std::move(points);
    result.unlocated_transitions += lost;
    if (lost > 0)
        result.message += (result.message.empty() ? "" : "; ") + std::to_string(lost) +
                          " stick-slip transition(s) not located (correction failed): " + where;
    say_solver_error(result, "a transition's location", solver_error);
}

void insert_folds(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options, double omega_scale,
                  BranchResult& result, const std::function<void(int done, int total)>& progress,
                  const std::function<std::string()>& stop) {
    CorrectorOptions patient_options = options;
    patient_options.max_iterations = std::max(100, 5 * patient_options.max_iterations);
    Corrector patient(hb, patient_options);
    std::vector<SolutionPoint> points;
    points.reserve(result.points.size() + 8);
    const int marked = static_cast<int>(std::count_if(result.points.begin(), result.points.end(),
                                                      [](const SolutionPoint& p) { return p.kind == PointKind::fold; }));
    int done = 0;
    std::string stopped, solver_error;
    for (std::size_t k = 0; k < result.points.size(); ++k) {
        SolutionPoint b = result.points[k];
        // The last point of a capped trace keeps its mark (the cap stopped it there).
        const bool last = k + 1 == result.points.size() || result.points[k + 1].branch != b.branch;
        if (b.kind == PointKind::fold && !last && k > 0 && result.points[k - 1].branch == b.branch) {
            if (stop_location(stop, stopped, result, std::to_string(marked - done) + " fold(s) not located")) {
                b.kind = PointKind::regular;  // a mark, not a located fold
                points.push_back(std::move(b));
                continue;
            }
            SolutionPoint fold;
            if (progress) progress(done++, marked);
            b.kind = PointKind::regular;
            if (guarded([&] { return locate_fold(hb, corrector, patient, result.points[k - 1], b, omega_scale, fold, stop); },
                        solver_error, result)) {
                points.push_back(std::move(fold));
                ++result.located_folds;
            } else if (!stop_location(stop, stopped, result, std::to_string(marked - done + 1) + " fold(s) not located")) {
                ++result.unconfirmed_folds;
            }
        }
        points.push_back(std::move(b));
    }
    result.points = std::move(points);
    say_solver_error(result, "a fold's location", solver_error);
}

}  // namespace hbf::detail
