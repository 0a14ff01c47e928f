// hbfriction — continuation of a branch: the start, the predictor-corrector trace with its step
// control, the restarts past amplitude caps, and samples of a branch at given frequencies
// (continuation.hpp); folds and transitions are located by locate.cpp.
// Over 600 lines: one loop (predict, correct, control the step, restart) whose parts share the
// trace's state; locate.cpp and corrector.cpp already hold what stands apart.
#include "hbf/continuation.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <memory>
#include <sstream>

#include "hbf/error.hpp"
#include "hbf/linear_limits.hpp"
#include "continuation/locate.hpp"
#include "base/stopwatch.hpp"
#include "base/enum_table.hpp"

namespace hbf {

using detail::insert_folds;
using detail::insert_transitions;

constexpr detail::EnumName<PointKind> point_kind_names[] = {
    {PointKind::regular, "regular"}, {PointKind::fold, "fold"}, {PointKind::sample, "sample"},
    {PointKind::transition, "transition"}, {PointKind::cap, "cap"}, {PointKind::branch_point, "branch-point"},
    {PointKind::period_doubling, "period-doubling"}, {PointKind::neimark_sacker, "neimark-sacker"}};

std::string to_string(PointKind kind) { return detail::enum_name(point_kind_names, kind, "point kind"); }

constexpr detail::EnumName<Boundary> boundary_names[] = {
    {Boundary::none, ""}, {Boundary::stick_stick_slip, "stick|stick-slip"},
    {Boundary::stick_slip_slip, "stick-slip|slip"}, {Boundary::closed_lift_off, "closed|lift-off"}};

std::string to_string(Boundary boundary) { return detail::enum_name(boundary_names, boundary, "boundary"); }

constexpr detail::EnumName<ContinuationStatus> continuation_status_names[] = {
    {ContinuationStatus::completed, "completed"}, {ContinuationStatus::amplitude_cap, "amplitude_cap"},
    {ContinuationStatus::left_range, "left_range"}, {ContinuationStatus::min_step, "min_step"},
    {ContinuationStatus::point_budget, "point_budget"}, {ContinuationStatus::stopped, "stopped"},
    {ContinuationStatus::solver_error, "solver_error"}, {ContinuationStatus::start_failed, "start_failed"}};

std::string to_string(ContinuationStatus status) {
    return detail::enum_name(continuation_status_names, status, "continuation status");
}

std::vector<int> transitions_per_contact(const std::vector<SolutionPoint>& points, int contacts) {
    std::vector<int> counts(static_cast<std::size_t>(std::max(contacts, 0)), 0);
    for (const SolutionPoint& p : points)
        if (p.kind == PointKind::transition && p.contact >= 0 && p.contact < contacts)
            ++counts[static_cast<std::size_t>(p.contact)];
    return counts;
}

std::string per_contact_counts(const std::vector<int>& counts) {
    if (counts.size() < 2) return "";
    std::string s = " (";
    for (std::size_t c = 0; c < counts.size(); ++c)
        s += (c > 0 ? ", contact " : "contact ") + std::to_string(c + 1) + ": " + std::to_string(counts[c]);
    return s + ")";
}

std::string BranchResult::summary() const {
    std::ostringstream s;
    const auto folds = std::count_if(points.begin(), points.end(), [](const SolutionPoint& p) { return p.kind == PointKind::fold; });
    s << to_string(status) << ": " << points.size() << " points, " << folds << " folds, " << transitions
      << " stick-slip transitions" << per_contact_counts(contact_transitions);
    if (unconfirmed_folds > 0)
        s << " (" << unconfirmed_folds << " sign change(s) of dw/ds without a real turn in w not counted as folds)";
    if (!message.empty()) s << "; " << message;
    return s.str();
}

// ---- continuation -----------------------------------------------------------------------

namespace {
/// A converged starting point at omega. Tries the pre-sliding linearisation, then the
/// slipping limit (the structure without its contacts). When the response at omega is
/// stick-slip, far from both, ramps the excitation up from a level lambda0 F at which the
/// pre-sliding guess is accurate: solves at lambda F for increasing lambda, each time from the
/// previous solution scaled by the load ratio (exact while the response is linear), and halves
/// the increment of log(lambda) after a failure.
/// `stop` (ContinuationOptions::stop) is asked before every solve: a non-empty answer ends the
/// search, not found, with `stopped` = that answer. start_harmonics > 0 (ContinuationOptions::
/// start_harmonics): the search at that H first, its solution the start at hb's H; where that
/// fails, `note` says so and the search runs at hb's H.
bool find_start(HarmonicBalance& hb, Corrector& corrector, const CorrectorOptions& options,
                const std::function<std::string()>& stop, double omega, Eigen::VectorXd& x, double& x_scale,
                int& iterations, double& residual, BranchResult& result, std::string& stopped,
                int start_harmonics = 0, std::string* note = nullptr) {
    auto attempt = [&](HarmonicBalance& h, Corrector& c, Eigen::VectorXd& guess) {
        if (stopped.empty() && stop) stopped = stop();
        if (!stopped.empty()) return false;
        x_scale = h.unknown_scale(guess);
        ++result.corrections;
        if (c.solve_at(guess, omega, x_scale, iterations, residual)) return true;
        ++result.failed_corrections;
        return false;
    };
    // The start is one point: let the corrector work longer than on the branch (exact Coulomb
    // with many harmonics may need 30-60 iterations from a linear guess).
    CorrectorOptions patient_options = options;
    patient_options.max_iterations = std::max(options.max_iterations, 100);
    Corrector patient(hb, patient_options);
    // The start searched with `low_harmonics` (automatic there), padded with zero harmonics:
    // Newton's guess at hb's H.
    auto from_fewer_harmonics = [&](int low_harmonics) {
        HarmonicBalanceOptions low_options = hb.options();
        low_options.harmonics = low_harmonics;
        low_options.time_samples = 0;
        HarmonicBalance low(hb.system(), low_options);
        Corrector low_corrector(low, options);
        Eigen::VectorXd low_x;
        double low_scale = 0, low_residual = 0;
        int low_iterations = 0;
        BranchResult low_result;
        const bool found = find_start(low, low_corrector, options, stop, omega, low_x, low_scale, low_iterations,
                                      low_residual, low_result, stopped);
        result.corrections += low_result.corrections;
        result.failed_corrections += low_result.failed_corrections;
        if (!found) {
            residual = low_residual;
            return false;
        }
        x = hb.embed_harmonics(low_x, low.harmonics());
        return attempt(hb, patient, x);
    };
    if (start_harmonics > 0) {
        if (from_fewer_harmonics(start_harmonics)) return true;
        if (!stopped.empty()) return false;
        if (note)
            *note += std::string(note->empty() ? "" : "; ") + "the start at w = " + format_number(omega) + " from H = " +
                     std::to_string(start_harmonics) + " did not converge at H = " + std::to_string(hb.harmonics()) +
                     " (residual " + format_number(residual) + "): searched at H = " + std::to_string(hb.harmonics());
    }
    for (const bool sliding : {false, true}) {
        x = hb.linear_guess(omega, sliding);
        if (attempt(hb, corrector, x)) return true;
    }
    for (const bool sliding : {false, true}) {
        x = hb.linear_guess(omega, sliding);
        if (attempt(hb, patient, x)) return true;
    }
    const double first_residual = residual;
    // Fewer harmonics first: exact Coulomb with many harmonics can fail from a linear guess
    // where half as many converge (measured: the 200-DOF beam at H = 20; its H = 10 start
    // converges). The H/2 solution, padded with zero harmonics, is the guess.
    if (start_harmonics == 0 && hb.harmonics() >= 12 && hb.harmonics() / 2 >= hb.load_harmonic()) {
        if (from_fewer_harmonics(hb.harmonics() / 2)) return true;
        residual = first_residual;
    }
    const HarmonicBalanceOptions layout = hb.options();
    auto scaled = [&](double lambda) {
        System s = hb.system();
        s.excitation *= lambda;
        return HarmonicBalance(std::move(s), layout);
    };
    // Lowest level: the pre-sliding guess must converge there.
    double log_lambda = -3.0;
    Eigen::VectorXd solution;
    for (; log_lambda >= -9.0 && stopped.empty(); log_lambda -= 3.0) {
        HarmonicBalance low = scaled(std::pow(10.0, log_lambda));
        Corrector c(low, options);
        solution = low.linear_guess(omega);
        if (attempt(low, c, solution)) break;
    }
    if (log_lambda < -9.0 || !stopped.empty()) {
        residual = first_residual;
        return false;
    }
    double increment = 0.5;
    while (log_lambda < 0.0) {
        const double next = std::min(0.0, log_lambda + increment);
        Eigen::VectorXd guess = solution * std::pow(10.0, next - log_lambda);
        bool converged = false;
        if (next == 0.0) {
            converged = attempt(hb, corrector, guess);
        } else {
            HarmonicBalance level = scaled(std::pow(10.0, next));
            Corrector c(level, options);
            converged = attempt(level, c, guess);
        }
        if (converged) {
            solution = guess;
            log_lambda = next;
            increment = std::min(1.0, 1.5 * increment);
        } else if (!stopped.empty() || (increment *= 0.5) < 1e-4) {
            residual = first_residual;
            return false;
        }
    }
    x = solution;
    return true;
}

/// Whether a step from (x, omega) to the corrected (xp, wp) crosses no resonance of the
/// linear structure unresolved (ContinuationOptions::resolve_resonances): for each resonance
/// strictly inside the step's frequency interval (clipped at `end`), the solution there is
/// solved from the chord's interpolation (then with five times the iterations); it resolves the
/// resonance when it converges with the amplitude bound within max_amplitude. `unresolved` is
/// set to the first resonance that is not resolved.
bool resonance_resolved(HarmonicBalance& hb, Corrector& corrector, std::unique_ptr<Corrector>& rough,
                        const ContinuationOptions& o, const Eigen::VectorXd& x, double omega,
                        const Eigen::VectorXd& xp, double wp, double end, int direction, double x_scale,
                        const std::vector<LinearResonance>& resonances, double& unresolved) {
    if (!o.resolve_resonances || wp == omega) return true;
    const double reach = (wp - end) * direction >= 0.0 ? end : wp;
    const double low = std::min(omega, reach), high = std::max(omega, reach);
    for (const LinearResonance& r : resonances) {
        if (!(r.omega > low && r.omega < high)) continue;
        const double s = (r.omega - omega) / (wp - omega);
        Eigen::VectorXd at = x + s * (xp - x);
        int iterations = 0;
        double residual = 0.0;
        bool solved = corrector.solve_at(at, r.omega, x_scale, iterations, residual);
        if (!solved) {
            // Only boundedness is asked, not an accurate point: a tight tolerance on a nonsmooth
            // law may not be met at one frequency the branch passes (measured: exact Coulomb at
            // --tolerance 1e-14 stalled at the absorber's rigid resonance, min_step).
            if (!rough) {
                CorrectorOptions options = o.corrector;
                options.max_iterations = std::max(100, 5 * options.max_iterations);
                options.tolerance = std::max(options.tolerance, 1e-6);
                rough = std::make_unique<Corrector>(hb, options);
            }
            at = x + s * (xp - x);
            solved = rough->solve_at(at, r.omega, x_scale, iterations, residual);
        }
        if (!solved || !(hb.amplitude_bound(at, r.omega) <= o.max_amplitude)) {
            unresolved = r.omega;
            return false;
        }
    }
    return true;
}

struct Trace {
    std::vector<SolutionPoint> points;
    ContinuationStatus status = ContinuationStatus::completed;
    std::string message;
};

/// omega_ref of the arclength (see the file comment of continuation.hpp).
double frequency_scale(const ContinuationOptions& o) { return o.omega_scale > 0.0 ? o.omega_scale : o.omega_end; }

/// trace's steps, filling `out` as they go.
void trace_into(Trace& out, HarmonicBalance& hb, Corrector& corrector, const ContinuationOptions& o, Eigen::VectorXd x,
                double omega, int iterations, double residual, int direction, double omega_low, double omega_high,
                double x_scale, int branch, BranchResult& result) {
    int& corrections = result.corrections;
    int& failures = result.failed_corrections;
    const double w_scale = frequency_scale(o);
    auto tangent = [&](const Eigen::VectorXd& at, double w, const Eigen::VectorXd& previous) {
        detail::Stopwatch watch;
        Eigen::VectorXd t = corrector.tangent(at, w, x_scale, previous, w_scale);
        result.predictor_seconds += watch.lap();
        return t;
    };
    const int n = hb.unknowns();
    auto make_point = [branch](double w, const Eigen::VectorXd& coefficients, int it, double res, double step) {
        SolutionPoint p;
        p.omega = w;
        p.x = coefficients;
        p.iterations = it;
        p.residual = res;
        p.step = step;
        p.branch = branch;
        return p;
    };
    out.points.push_back(make_point(omega, x, iterations, residual, 0.0));
    // A start (or, below, an end) on an unbounded linear resonance the contacts do not see: the
    // condensed unknowns are regular there, the recovered DOFs are not.
    auto capped = [&](double w) {
        if (!(hb.amplitude_bound(out.points.back().x, w) > o.max_amplitude)) return false;
        out.status = ContinuationStatus::amplitude_cap;
        if (out.points.back().kind == PointKind::regular) out.points.back().kind = PointKind::cap;
        out.message = "amplitude cap " + format_number(o.max_amplitude) + " reached at w = " + format_number(w);
        return true;
    };
    if (capped(omega)) return;
    Eigen::VectorXd previous = Eigen::VectorXd::Zero(n + 1);
    previous(n) = direction;
    Eigen::VectorXd t = tangent(x, omega, previous);
    double h = o.initial_step;
    double rejected_turn = -1.0;  // turn of the last step rejected for turning too sharply
    int leaps = 0;                // steps over a spot the corrector cannot land on (below)
    // corners crossed at fixed frequencies (below), and the frequency of the last one: each
    // must lie beyond the previous, so that the branch cannot circle one corner
    constexpr int max_corners = 100;
    int corners = 0;
    double corner_omega = direction > 0 ? -std::numeric_limits<double>::infinity()
                                        : std::numeric_limits<double>::infinity();
    std::unique_ptr<Corrector> patient;  // more iterations for small steps that fail (below)
    std::unique_ptr<Corrector> rough;    // resonance_resolved's
    const double end = direction > 0 ? omega_high : omega_low;
    // Moves the trace to an accepted point p with the tangent t_new there. Distances are
    // relative to the current amplitude: a branch that grows by orders of magnitude (a sharp
    // resonance) is not paced by the scale of its starting point. False (status amplitude_cap)
    // when the amplitude cap is reached.
    auto advance = [&](const SolutionPoint& p, const Eigen::VectorXd& t_new) {
        out.points.push_back(p);
        if (o.progress) o.progress(p.omega, static_cast<int>(result.points.size() + out.points.size()));
        x = p.x;
        omega = p.omega;
        t = t_new;
        const double new_scale = hb.unknown_scale(x);
        t.head(n) *= x_scale / new_scale;
        t.normalize();
        x_scale = new_scale;
        if (!(hb.amplitude_bound(x, omega) > o.max_amplitude)) return true;
        out.status = ContinuationStatus::amplitude_cap;
        if (out.points.back().kind == PointKind::regular) out.points.back().kind = PointKind::cap;
        out.message = "amplitude cap " + format_number(o.max_amplitude) + " reached at w = " + format_number(omega);
        return false;
    };
    while (true) {
        if (const std::string why = o.stop ? o.stop() : std::string(); !why.empty()) {
            out.status = ContinuationStatus::stopped;
            out.message = "stopped at w = " + format_number(omega) + ": " + why;
            return;
        }
        if (static_cast<int>(out.points.size()) >= o.max_points) {
            out.status = ContinuationStatus::point_budget;
            out.message = "point budget of " + std::to_string(o.max_points) + " reached at w = " + format_number(omega);
            return;
        }
        Eigen::VectorXd xp = x + h * x_scale * t.head(n);
        double wp = omega + h * w_scale * t(n);
        int it = 0;
        double res = 0;
        ++corrections;
        bool corrected = corrector.correct(xp, wp, t, x_scale, it, res, w_scale);
        if (!corrected) {
            // Retry with five times the iterations: near a stick/slip pattern boundary a
            // nonsmooth law's iteration creeps, slowly but surely (exact Coulomb; measured:
            // a branch that stalled at min_step completes, for 17% more time on the default
            // FRF).
            ++failures;
            if (!patient) {
                CorrectorOptions options = o.corrector;
                options.max_iterations = std::max(100, 5 * options.max_iterations);
                patient = std::make_unique<Corrector>(hb, options);
            }
            ++corrections;
            corrected = patient->correct(xp, wp, t, x_scale, it, res, w_scale);
        }
        if (!corrected) {
            ++failures;
            rejected_turn = -1.0;
            h *= 0.5;
            if (h < o.min_step && leaps < 3) {
                // The corrector cannot land near here (a nonsmooth law's residual is piecewise
                // smooth: at a pattern boundary the iteration may cycle). Step over the spot
                // with 4, 16, 64 times the initial step; each leap is corrected and checked
                // like any step.
                h = o.initial_step * std::pow(4.0, ++leaps);
                continue;
            }
            if (h < o.min_step && t(n) != 0.0 && corners < max_corners && (omega - corner_omega) * t(n) > 0.0) {
                // A corner sharper than a right angle (in the scaled coordinates): the hyperplane
                // of every arclength step misses the branch beyond it, and a tangent oriented by
                // the last one points back into the corner. Cross at fixed frequencies a little
                // further in the direction the branch was moving in w, and orient the tangent
                // there by that direction (measured: examples/systems/liftoff3.toml with
                // excitation [0.05, 0.2, 0] stalled at w = 1.8857, where permanent stick turns
                // into stick-slip). The landing must be near (scaled distance <= 0.1: not another
                // branch) and cross no linear resonance unresolved.
                const double sense = t(n) > 0.0 ? 1.0 : -1.0;
                corner_omega = omega;
                bool crossed = false;
                for (double scaled : {1e-4, 1e-3, 1e-2}) {
                    double wq = omega + sense * scaled * w_scale;
                    if ((wq - end) * direction >= 0.0) break;
                    Eigen::VectorXd xq = x;
                    ++corrections;
                    if (!patient->solve_at(xq, wq, x_scale, it, res)) {
                        ++failures;
                        continue;
                    }
                    const double distance = std::hypot((xq - x).norm() / x_scale, (wq - omega) / w_scale);
                    double unresolved = 0.0;
                    if (distance > 0.1 || !resonance_resolved(hb, corrector, rough, o, x, omega, xq, wq, end, direction,
                                                              x_scale, result.resonances, unresolved))
                        continue;
                    Eigen::VectorXd along = Eigen::VectorXd::Zero(n + 1);
                    along(n) = sense;
                    const Eigen::VectorXd t_new = tangent(xq, wq, along);
                    ++corners;
                    ++result.crossed_corners;
                    h = o.initial_step;
                    leaps = 0;
                    rejected_turn = -1.0;
                    crossed = true;
                    if (!advance(make_point(wq, xq, it, res, distance), t_new)) return;
                    break;
                }
                if (crossed) continue;
            }
            if (h < o.min_step) {
                out.status = ContinuationStatus::min_step;
                out.message = "corrector failed with the minimum step at w = " + format_number(omega) +
                              " (residual " + format_number(res) + " against the tolerance " +
                              format_number(o.corrector.tolerance) +
                              "): the branch is not smooth enough there for the corrector (a sharp stick-slip "
                              "kink: more harmonics or a looser tolerance may pass it), or the solution stops "
                              "existing (an unbounded or singular response)";
                return;
            }
            continue;
        }
        // A step across a resonance of the linear structure is accepted only when the branch is
        // bounded there (ContinuationOptions::resolve_resonances); else it is halved.
        if (h > 2.0 * o.min_step) {
            double unresolved = 0.0;
            if (!resonance_resolved(hb, corrector, rough, o, x, omega, xp, wp, end, direction, x_scale,
                                    result.resonances, unresolved)) {
                ++result.resonance_rejections;
                rejected_turn = -1.0;
                h *= 0.5;
                if (h > 2.0 * o.min_step) continue;
                ++result.unresolved_resonances;
                out.message += std::string(out.message.empty() ? "" : "; ") + "a step crosses the resonance at w = " +
                               format_number(unresolved) + " unresolved at the minimum step";
            }
        }
        // Past the end of the range: land exactly on it and stop.
        if ((wp - end) * direction >= 0.0) {
            Eigen::VectorXd xe = x + (xp - x) * ((end - omega) / (wp - omega));
            ++corrections;
            if (corrector.solve_at(xe, end, x_scale, it, res)) {
                out.points.push_back(make_point(end, xe, it, res, h));
                capped(end);
                return;
            }
            ++failures;
            h *= 0.5;
            if (h < o.min_step) {
                out.status = ContinuationStatus::min_step;
                out.message = "could not land on w = " + format_number(end);
                return;
            }
            continue;
        }
        // The corrector moves on the hyperplane through the predicted point; a correction longer
        // than twice the step (the branch cannot turn that far within one step: a kink of a
        // nonsmooth law moves the point by at most about the step) means it landed on another
        // part of the branch, or another branch: a jump, never accepted while the step can
        // shrink (measured: 1x rejected legitimate kinks of Jenkins branches, 60 % more points).
        const double correction =
            std::hypot(((xp - x) / x_scale - h * t.head(n)).norm(), (wp - omega) / w_scale - h * t(n));
        if (correction > 2.0 * h && h > o.min_step * 2.0) {
            ++result.rejected_jumps;
            h *= 0.5;
            continue;
        }
        if (wp < omega_low || wp > omega_high) {  // turned back out of the range
            out.status = ContinuationStatus::left_range;
            out.message = "branch turned back and left the frequency range at w = " + format_number(wp);
            return;
        }
        const Eigen::VectorXd t_new = tangent(xp, wp, t);
        const double turn = std::acos(std::clamp(t_new.dot(t), -1.0, 1.0));
        // A turn that does not shrink with the step is a kink of the branch (nonsmooth laws:
        // a time sample switching between stick and slip), not curvature: accept it.
        const bool kink = rejected_turn > 0.0 && turn > 0.75 * rejected_turn;
        if (turn > o.max_turn && h > o.min_step * 2.0 && !kink) {  // turned too sharply
            rejected_turn = turn;
            h *= 0.5;
            continue;
        }
        rejected_turn = -1.0;
        leaps = 0;
        SolutionPoint p = make_point(wp, xp, it, res, h);
        if (t_new(n) * t(n) < 0.0) p.kind = PointKind::fold;
        if (!advance(p, t_new)) return;
        // Next step: grow after an easy correction, at most up to where the tangent would
        // turn by about 0.7 max_turn (the turn grows about linearly with the step; not at a
        // kink, whose turn does not depend on the step).
        double factor = it <= 3 ? 1.5 : it <= 6 ? 1.0 : 0.7;
        if (turn > 0.0 && !kink) factor = std::min(factor, std::max(0.5, 0.7 * o.max_turn / turn));
        h = std::clamp(h * factor, o.min_step, o.max_step);
    }
}

/// Follows one branch from the solution (x, omega) in the direction of increasing
/// (direction = +1) or decreasing (-1) omega until it leaves [omega_low, omega_high].
/// An exception of the solver (a contact model that cannot evaluate a point, a broken-down
/// linear solve) ends the trace with status solver_error and the points before it kept; bad
/// input (InvalidInput) is not a solver failure and propagates.
Trace trace(HarmonicBalance& hb, Corrector& corrector, const ContinuationOptions& o, const Eigen::VectorXd& x,
            double omega, int iterations, double residual, int direction, double omega_low, double omega_high,
            double x_scale, int branch, BranchResult& result) {
    Trace out;
    try {
        trace_into(out, hb, corrector, o, x, omega, iterations, residual, direction, omega_low, omega_high, x_scale,
                   branch, result);
    } catch (const InvalidInput&) {
        throw;
    } catch (const std::exception& e) {
        out.status = ContinuationStatus::solver_error;
        const double last = out.points.empty() ? omega : out.points.back().omega;
        out.message = "the solver failed on the step from w = " + format_number(last) + ": " + e.what();
    }
    return out;
}

/// The worse of two statuses (the order of the ContinuationStatus declaration).
ContinuationStatus worse(ContinuationStatus a, ContinuationStatus b) { return a < b ? b : a; }

/// Share of [low, high] spanned by the segments between successive points of one branch.
double branch_coverage(const std::vector<SolutionPoint>& points, double low, double high) {
    std::vector<std::pair<double, double>> spans;
    for (std::size_t k = 0; k + 1 < points.size(); ++k)
        if (points[k].branch == points[k + 1].branch)
            spans.emplace_back(std::max(low, std::min(points[k].omega, points[k + 1].omega)),
                               std::min(high, std::max(points[k].omega, points[k + 1].omega)));
    std::sort(spans.begin(), spans.end());
    double covered = 0.0, reached = low;
    for (const auto& [a, b] : spans) {
        if (b <= reached) continue;
        covered += b - std::max(a, reached);
        reached = b;
    }
    return covered / (high - low);
}

/// Whether o.stop asks to stop before a restart: then the result's status is stopped (unless worse).
bool stop_now(const ContinuationOptions& o, BranchResult& result) {
    const std::string why = o.stop ? o.stop() : std::string();
    if (why.empty()) return false;
    result.status = worse(result.status, ContinuationStatus::stopped);
    result.message += (result.message.empty() ? "" : "; ") + std::string("stopped before the restart: ") + why;
    return true;
}

/// Branch 1 from omega_start and, after an amplitude cap, branch 2 from omega_end; where they
/// are equal, the start alone (one point).
/// `start_note`: where a start from ContinuationOptions::start_harmonics failed.
void follow_branches(HarmonicBalance& hb, Corrector& corrector, const ContinuationOptions& o, BranchResult& result,
                     std::string& start_note) {
    Eigen::VectorXd x;
    double x_scale = 1.0, res = 0.0;
    int it = 0;
    std::string stopped;
    if (!find_start(hb, corrector, o.corrector, o.stop, o.omega_start, x, x_scale, it, res, result, stopped,
                    o.start_harmonics, &start_note)) {
        result.status = stopped.empty() ? ContinuationStatus::start_failed : ContinuationStatus::stopped;
        result.message = stopped.empty() ? "no converged starting point at w = " + format_number(o.omega_start) +
                                               " (residual " + format_number(res) + ")"
                                         : "stopped while searching the starting point at w = " +
                                               format_number(o.omega_start) + ": " + stopped;
        return;
    }
    if (o.omega_end == o.omega_start) {
        SolutionPoint p;
        p.omega = o.omega_start;
        p.x = x;
        p.iterations = it;
        p.residual = res;
        result.points.push_back(p);
        result.status = ContinuationStatus::completed;
        // start_note is non-empty where the start from start_harmonics failed (the search ran at H)
        const std::string from = o.start_harmonics > 0 && start_note.empty()
                                     ? "a cold start at H = " + std::to_string(o.start_harmonics) + ", padded to H = " +
                                           std::to_string(hb.harmonics())
                                     : std::string("a cold start");
        result.message = "one point at w = " + format_number(o.omega_start) + ", solved from " + from +
                         " (no continuation: the folds and other solutions at this w are not searched)";
        return;
    }
    Trace first = trace(hb, corrector, o, x, o.omega_start, it, res, +1, o.omega_start, o.omega_end, x_scale, 1,
                        result);
    result.points = std::move(first.points);
    result.status = first.status;
    result.message = first.message;
    if (first.status != ContinuationStatus::amplitude_cap || !o.restart_past_cap || stop_now(o, result)) return;

    // Restart from the other end, walking down in frequency towards the capped peak.
    const double capped_at = result.points.back().omega;
    Eigen::VectorXd x2;
    double scale2 = 1.0;
    if (!find_start(hb, corrector, o.corrector, o.stop, o.omega_end, x2, scale2, it, res, result, stopped,
                    o.start_harmonics, &start_note)) {
        if (!stopped.empty()) result.status = worse(result.status, ContinuationStatus::stopped);
        result.message += "; restart at w = " + format_number(o.omega_end) + (stopped.empty() ? " failed" : " stopped: " + stopped);
        return;
    }
    Trace second = trace(hb, corrector, o, x2, o.omega_end, it, res, -1, capped_at, o.omega_end, scale2, 2,
                         result);
    const double capped_above = second.points.back().omega;
    std::reverse(second.points.begin(), second.points.end());  // written in increasing w like branch 1
    result.points.insert(result.points.end(), second.points.begin(), second.points.end());
    result.message += "; branch 2 from w = " + format_number(o.omega_end) + ": " +
                      (second.message.empty() ? to_string(second.status) : second.message);
    result.status = worse(result.status, second.status);
    // (Caps less than 2% apart are the two flanks of one resonance: no gap between them.)
    if (second.status != ContinuationStatus::amplitude_cap || !(capped_above > 1.02 * capped_at) || stop_now(o, result))
        return;

    // Two unbounded resonances: the part between them is a separate (bounded) branch. Start
    // in the middle of the gap and follow it both ways, down to the first cap and up to the
    // second.
    const double middle = 0.5 * (capped_at + capped_above);
    Eigen::VectorXd x3;
    double scale3 = 1.0;
    if (!find_start(hb, corrector, o.corrector, o.stop, middle, x3, scale3, it, res, result, stopped,
                    o.start_harmonics, &start_note)) {
        if (!stopped.empty()) result.status = worse(result.status, ContinuationStatus::stopped);
        result.message += "; no start inside the gap at w = " + format_number(middle) +
                          (stopped.empty() ? std::string() : " (stopped: " + stopped + ")");
        return;
    }
    Trace down = trace(hb, corrector, o, x3, middle, it, res, -1, capped_at, middle, scale3, 3, result);
    Trace up = trace(hb, corrector, o, x3, middle, it, res, +1, middle, capped_above, scale3, 3, result);
    std::reverse(down.points.begin(), down.points.end());
    result.points.insert(result.points.end(), down.points.begin(), down.points.end());
    result.points.insert(result.points.end(), up.points.begin() + 1, up.points.end());  // the start once
    result.message += "; branch 3 inside the gap from w = " + format_number(middle) + ": down " +
                      (down.message.empty() ? to_string(down.status) : down.message) + ", up " +
                      (up.message.empty() ? to_string(up.status) : up.message);
    // Branch 3 is bounded by the caps on both sides; turning back past its start is the other
    // half of its own trace, not an escape from [wmin, wmax].
    for (const Trace* part : {&down, &up})
        if (part->status != ContinuationStatus::left_range) result.status = worse(result.status, part->status);
}
}  // namespace

void validate(const ContinuationOptions& o) {
    require_positive(o.omega_start, "wmin", "lowest frequency");
    require_positive(o.omega_end, "wmax", "highest frequency");
    if (!(o.omega_end >= o.omega_start))
        throw InvalidInput("wmax (highest frequency) = " + format_number(o.omega_end) +
                           " is out of range: allowed wmax > wmin = " + format_number(o.omega_start) +
                           " (or wmax = wmin: one point, solved from a cold start)");
    if (!(o.max_step >= o.smallest_max_step && o.max_step <= o.largest_max_step))
        throw InvalidInput("max_step = " + format_number(o.max_step) + " is out of range: allowed " +
                           format_number(o.smallest_max_step) + ".." + format_number(o.largest_max_step));
    require_positive(o.initial_step, "initial_step", "first arclength step");
    require_positive(o.min_step, "min_step", "minimum arclength step");
    require_positive(o.max_amplitude, "max_amplitude", "amplitude cap");
    if (!(o.omega_scale >= 0.0) || !std::isfinite(o.omega_scale))
        throw InvalidInput("omega_scale = " + format_number(o.omega_scale) +
                           " is out of range: allowed >= 0 (0: wmax)");
    const CorrectorOptions& c = o.corrector;
    if (!(c.tolerance >= c.smallest_tolerance && c.tolerance <= c.largest_tolerance))
        throw InvalidInput("tolerance = " + format_number(c.tolerance) + " is out of range: allowed " +
                           format_number(c.smallest_tolerance) + ".." + format_number(c.largest_tolerance));
    if (o.max_points < 2) throw InvalidInput("max_points = " + std::to_string(o.max_points) + " is out of range: allowed >= 2");
    if (o.corrector.max_iterations < 1)
        throw InvalidInput("max_iterations = " + std::to_string(o.corrector.max_iterations) +
                           " is out of range: allowed >= 1 (corrector iterations per correction)");
    check_start_harmonics(o.start_harmonics, 0);
    if (!(o.max_turn > 0.0 && o.max_turn <= M_PI))
        throw InvalidInput("max_turn = " + format_number(o.max_turn) + " is out of range: allowed 0 < max_turn <= pi");

}

void check_start_harmonics(int start_harmonics, int harmonics, int load_harmonic) {
    const int top = harmonics > 0 ? harmonics - 1 : max_harmonics;
    if (start_harmonics == 0 || (start_harmonics >= load_harmonic && start_harmonics <= top)) return;
    throw InvalidInput("start_harmonics = " + std::to_string(start_harmonics) + " is out of range: allowed 0..H - 1" +
                       (harmonics > 0 ? " = " + std::to_string(top) : " (at most " + std::to_string(max_harmonics) + ")") +
                       ", from the excitation's harmonic " + std::to_string(load_harmonic) + " (0: automatic)");
}

BranchResult continue_branch(HarmonicBalance& hb, const ContinuationOptions& options) {
    validate(options);
    // Every correction hears the stop between its iterations, not only between corrections.
    ContinuationOptions o = options;
    if (!o.corrector.stop) o.corrector.stop = o.stop;
    detail::Stopwatch watch;
    const EvaluationStatistics before = hb.statistics();
    Corrector corrector(hb, o.corrector);
    BranchResult result;
    check_start_harmonics(o.start_harmonics, hb.harmonics(), hb.load_harmonic());
    if (o.resolve_resonances) result.resonances = linear_resonances(hb.system(), o.omega_start, o.omega_end);
    std::string start_note;
    follow_branches(hb, corrector, o, result, start_note);
    if (!start_note.empty()) result.message += (result.message.empty() ? "" : "; ") + start_note;
    if (o.locate_folds) insert_folds(hb, corrector, o.corrector, frequency_scale(o), result, o.fold_progress, o.stop);
    if (o.locate_transitions) insert_transitions(hb, corrector, o.corrector, frequency_scale(o), result, o.stop);
    result.coverage = o.omega_end == o.omega_start ? (result.points.empty() ? 0.0 : 1.0)
                                                   : branch_coverage(result.points, o.omega_start, o.omega_end);
    result.corrector = corrector.statistics();
    result.evaluation = hb.statistics() - before;
    result.seconds = watch.lap();
    return result;
}


std::vector<SolutionPoint> sample_branch(HarmonicBalance& hb, const BranchResult& branch,
                                         const std::vector<double>& omegas, const CorrectorOptions& options,
                                         std::vector<double>* missed) {
    Corrector corrector(hb, options);
    CorrectorOptions patient_options = options;
    patient_options.max_iterations = std::max(100, 5 * options.max_iterations);
    Corrector patient(hb, patient_options);
    std::vector<SolutionPoint> samples;
    for (double omega : omegas) {
        std::vector<SolutionPoint> found;
        // A frequency within rounding of a branch end (e.g. 3e-13 below wmin) is on the branch.
        const double slack = 1e-9 * std::abs(omega);
        for (std::size_t k = 0; k + 1 < branch.points.size(); ++k) {
            const SolutionPoint& a = branch.points[k];
            const SolutionPoint& b = branch.points[k + 1];
            if (a.branch != b.branch || std::min(a.omega, b.omega) - slack > omega ||
                std::max(a.omega, b.omega) + slack < omega)
                continue;
            const double s = a.omega == b.omega ? 0.0 : (omega - a.omega) / (b.omega - a.omega);
            Eigen::VectorXd x = a.x + s * (b.x - a.x);
            const double x_scale = hb.unknown_scale(x);
            SolutionPoint p;
            // From the interpolation, then with five times the iterations from the nearer
            // branch point (as the continuation retries a failed correction).
            if (!corrector.solve_at(x, omega, x_scale, p.iterations, p.residual)) {
                x = std::abs(omega - a.omega) <= std::abs(omega - b.omega) ? a.x : b.x;
                if (!patient.solve_at(x, omega, hb.unknown_scale(x), p.iterations, p.residual)) continue;
            }
            const bool duplicate = std::any_of(found.begin(), found.end(), [&](const SolutionPoint& q) {
                return (q.x - x).cwiseAbs().maxCoeff() <= 1e-7 * x_scale;
            });
            if (duplicate) continue;
            p.omega = omega;
            p.x = x;
            p.kind = PointKind::sample;
            p.branch = a.branch;
            found.push_back(p);
        }
        if (found.empty() && missed) missed->push_back(omega);
        samples.insert(samples.end(), found.begin(), found.end());
    }
    return samples;
}

}  // namespace hbf
