// hbfriction — steady states over a frequency sweep (hbf timeint): the event-exact orbit as a
// time-integration result, and the verdict on a sweep's points (time_integration.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "time_integration/law_orbit.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/exact_branch.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"
#include "hbf/timeint_sweep.hpp"

namespace hbf {

ExactOrbit detail::law_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& start,
                                      const ExactOptions& options) {
    if (rigid_contacts_only(system)) return rigid_periodic_orbit(system, omega, start, options);
    if (elastic_contacts_only(system)) return elastic_periodic_orbit(system, omega, start, options);
    return exact_periodic_orbit(system, omega, start, options);
}

namespace {

/// Whether each DOF carries mass (a non-zero entry in its row of M).
std::vector<bool> dofs_with_mass(const System& system) {
    std::vector<bool> massive(static_cast<std::size_t>(system.dofs()), false);
    for (int k = 0; k < system.mass.outerSize(); ++k)
        for (SparseMatrix::InnerIterator it(system.mass, k); it; ++it)
            if (it.value() != 0.0) massive[static_cast<std::size_t>(it.row())] = true;
    return massive;
}

/// An exact orbit as a time-integration row (`periods`: all its solves').
PeriodicResponse orbit_response(const ExactOrbit& orbit, double omega, int periods) {
    PeriodicResponse r;
    r.omega = omega;
    r.converged = orbit.converged;
    r.message = orbit.message;
    r.periods = periods;
    r.poincare_change = orbit.residual;
    r.state = orbit.state;
    r.y_max = orbit.y_max;
    r.y_amp1 = orbit.y_amp1;
    r.output_max = orbit.output_max;
    r.output_amp1 = orbit.output_amp1;
    r.harmonic1 = orbit.harmonic1;
    r.stick_fraction = orbit.stick_fraction;
    r.regime = orbit.regime;
    r.contacts = orbit.contacts;
    r.stick_margin_min = orbit.stick_margin_min;
    r.stick_margin_max = orbit.stick_margin_max;
    r.switches = orbit.switches;
    r.energy = orbit.energy;
    r.input_energy = orbit.input_energy;
    if (orbit.converged) {
        r.max_multiplier = orbit.max_multiplier;
        r.multiplier_accuracy = orbit.multiplier_accuracy;
    }
    if (!orbit.stopped.empty()) r.stop_after(periods, orbit.stopped);
    return r;
}

}  // namespace

PeriodicResponse exact_steady_state(const System& system, double omega, ExactOptions options, int max_periods,
                                    const Eigen::VectorXd& start) {
    // laws unilateral and elastic: their own solvers, from rest where the start is rest (zeros:
    // the static state under the preloads holds the nodes, not y = 0)
    const bool rigid = rigid_contacts_only(system), elastic = elastic_contacts_only(system);
    const Eigen::VectorXd from =
        (rigid || elastic) && start.size() > 0 && start.isZero(0.0) ? Eigen::VectorXd() : start;
    auto solve = [&] { return detail::law_periodic_orbit(system, omega, from, options); };
    ExactOrbit orbit = solve();
    int periods = orbit.periods;
    if (!orbit.converged && orbit.stopped.empty() && max_periods > 1) {
        options.warmup_periods = std::min(max_periods, 200);
        orbit = solve();
        periods += orbit.periods;
    }
    return orbit_response(orbit, omega, periods);
}

std::string exact_sweep_refusal(const System& system, double omega_min) {
    if (rigid_contacts_only(system)) return rigid_solver_refusal(system);
    if (elastic_contacts_only(system)) return elastic_solver_refusal(system);
    return exact_cost_refusal(system, omega_min);
}

Eigen::VectorXd exact_sweep_start(const System& system, double omega, const std::vector<PeriodicResponse>& done,
                                  const Eigen::VectorXd& first) {
    if (done.empty()) return first;
    const PeriodicResponse& last = done.back();
    if (done.size() < 2 || !rigid_contacts_only(system) || rigid_contacts_3d(system)) return last.state;
    const PeriodicResponse& before = done[done.size() - 2];
    const double step = last.omega - before.omega;
    if (!last.converged || !before.converged || last.state.size() != before.state.size() || step == 0.0 ||
        (omega - last.omega) / step <= 0.0)
        return last.state;
    Eigen::VectorXd next = last.state;
    const double share = (omega - last.omega) / step;
    const std::vector<bool> massive = dofs_with_mass(system);
    const int n = system.dofs();
    for (int i = 0; i < n; ++i)
        if (massive[static_cast<std::size_t>(i)])
            for (const int k : {i, n + i}) next(k) += share * (last.state(k) - before.state(k));
    return next;
}

ExactOptions exact_sweep_options(const System& system, ExactOptions options, bool from_orbit) {
    if (from_orbit && rigid_contacts_3d(system))
        options.warmup_periods = std::max(options.warmup_periods, exact_shakedown_periods);
    return options;
}

void ExactBranchOptions::validate() const {
    if (!(omega_min > 0.0) || !std::isfinite(omega_min))
        throw InvalidInput("omega_min = " + format_number(omega_min) + " is out of range: allowed > 0");
    if (!(omega_max > omega_min) || !std::isfinite(omega_max))
        throw InvalidInput("omega_max = " + format_number(omega_max) + " is out of range: allowed > omega_min = " +
                           format_number(omega_min));
    if (!(step > 0.0 && step <= 1.0)) throw InvalidInput("step = " + format_number(step) + " is out of range: allowed (0, 1]");
    if (max_points < 2) throw InvalidInput("max_points = " + std::to_string(max_points) + " is out of range: allowed >= 2");
    if (max_periods < 1) throw InvalidInput("max_periods = " + std::to_string(max_periods) + " is out of range: allowed >= 1");
    exact.validate();
}

ExactBranchOptions exact_branch_options(double omega_min, double omega_max, long long points) {
    if (points < 2 || points > 10000)
        throw InvalidInput("points = " + std::to_string(points) + " is out of range: allowed 2..10000");
    ExactBranchOptions o;
    o.omega_min = omega_min;
    o.omega_max = omega_max;
    o.step = 1.0 / static_cast<double>(points - 1);
    o.max_points = exact_branch_point_factor * static_cast<int>(points);
    return o;
}

namespace {

/// A point of the branch in the predictor's coordinates: w, h = the first harmonics (cosine and
/// sine parts) of the DOFs with mass (smooth in w where an event of the orbit passes t = 0), and
/// the start x = [y, y' / w] of the DOFs with mass at t = 0 (predicted for the solver only).
struct BranchPoint {
    double omega = 0.0;
    Eigen::VectorXd h, x;
};

/// The chord length of exact_branch.hpp between a and b.
double chord(const BranchPoint& a, const BranchPoint& b, double band) {
    const double size = std::max({a.h.cwiseAbs().maxCoeff(), b.h.cwiseAbs().maxCoeff(), 1e-300});
    return std::hypot((a.omega - b.omega) / band, (a.h - b.h).cwiseAbs().maxCoeff() / size);
}

/// A prediction off by at most this many steps whose error does not shrink as the step halves
/// is a corner of the branch.
constexpr double corner_ratio = 3.0;

/// A failed branch whose last vertical_points points lie within vertical_share of w is said to
/// turn vertical.
constexpr std::size_t vertical_points = 8;
constexpr double vertical_share = 1e-9;

/// A turn in w is a fold where both of its steps in w exceed this share of w (not rounding).
constexpr double fold_turn = 1e-11;

/// Lagrange weights at s of the nodes `at` (1, 2 or 3 of them).
std::vector<double> lagrange(const std::vector<double>& at, double s) {
    std::vector<double> w(at.size(), 1.0);
    for (std::size_t i = 0; i < at.size(); ++i)
        for (std::size_t j = 0; j < at.size(); ++j)
            if (j != i) w[i] *= (s - at[j]) / (at[i] - at[j]);
    return w;
}

}  // namespace

ExactBranch exact_branch(const System& system, const ExactBranchOptions& options, const Eigen::VectorXd& start) {
    options.validate();
    if (const std::string why = exact_sweep_refusal(system, options.omega_min); !why.empty()) throw InvalidInput(why);
    const int n = system.dofs();
    const std::vector<bool> massive = dofs_with_mass(system);
    std::vector<int> moving;  // the state's entries the predictor extrapolates
    for (int i = 0; i < n; ++i)
        if (massive[static_cast<std::size_t>(i)]) moving.push_back(i);
    const auto m = static_cast<Eigen::Index>(moving.size());
    const double band = options.omega_max - options.omega_min;
    auto coordinates = [&](const PeriodicResponse& r) {
        BranchPoint p{r.omega, Eigen::VectorXd(2 * m), Eigen::VectorXd(2 * m)};
        for (Eigen::Index k = 0; k < m; ++k) {
            const auto i = moving[static_cast<std::size_t>(k)];
            // (every exact solver fills harmonic1; the state's y, y' / w stand in otherwise)
            const bool harmonics = r.harmonic1.size() == n;
            p.h(k) = harmonics ? r.harmonic1(i).real() : r.state(i);
            p.h(m + k) = harmonics ? r.harmonic1(i).imag() : r.state(n + i) / r.omega;
            p.x(k) = r.state(i);
            p.x(m + k) = r.state(n + i) / r.omega;
        }
        return p;
    };
    ExactBranch out;
    auto stopped = [&](const PeriodicResponse& r) {
        out.status = "stopped";
        out.message = "stopped at w = " + format_number(r.omega) + " (not written): " + r.message;
        return out;
    };
    // The first point: the sweep's solve (with its retry after plain periods).
    const double first_omega = options.up ? options.omega_min : options.omega_max;
    PeriodicResponse first = exact_steady_state(system, first_omega, options.exact, options.max_periods, start);
    if (first.stopped) return stopped(first);
    if (!first.converged) {
        out.status = "failed";
        out.message = "the first point, w = " + format_number(first_omega) + ", did not converge: " + first.message;
        return out;
    }
    // (the shakedown's plain periods only after a point not known unstable: they would leave it)
    const ExactOptions shaken = exact_sweep_options(system, options.exact, true);
    std::vector<BranchPoint> taken{coordinates(first)};
    out.points.push_back(std::move(first));
    if (options.progress) options.progress(out.points.back(), options.step);
    double direction = options.up ? 1.0 : -1.0;  // of the first step, and after a corner
    const double smallest = 1e-4 * options.step;
    double ds = options.step;
    std::string last_failure;
    std::size_t history = 0;  // the predictor's first point (after a corner: the corner)
    double rejected_ratio = std::numeric_limits<double>::quiet_NaN();  // of the last rejection
    while (true) {
        if (static_cast<int>(out.points.size()) >= options.max_points) {
            out.status = "incomplete";
            out.message = "the branch reached " + std::to_string(options.max_points) + " points at w = " +
                          format_number(out.points.back().omega) + " before leaving the band";
            return out;
        }
        if (ds < smallest) {
            out.status = "failed";
            out.message = "the step fell below " + format_number(smallest) + " after w = " +
                          format_number(out.points.back().omega) + " (no orbit near the predicted starts" +
                          (last_failure.empty() ? std::string(")") : "; the last solve: " + last_failure + ")");
            // A branch that stands still in w while the orbit changes: a vertical stretch, which
            // a solver at a fixed w cannot follow.
            const std::size_t k = out.points.size();
            if (k >= vertical_points) {
                double low = out.points.back().omega, high = low;
                for (std::size_t j = k - vertical_points; j < k; ++j) {
                    low = std::min(low, out.points[j].omega);
                    high = std::max(high, out.points[j].omega);
                }
                if (high - low <= vertical_share * high)
                    out.message += "; over its last " + std::to_string(vertical_points) + " points w changed by " +
                                   format_number((high - low) / high) +
                                   " of itself while the orbit changed: the branch turns vertical there, where a "
                                   "solver at a fixed w cannot follow it";
            }
            return out;
        }
        // The prediction: the polynomial through the last (up to) three points in chord length.
        const std::size_t used = std::min<std::size_t>(3, taken.size() - history);
        std::vector<double> s(used, 0.0);
        for (std::size_t k = 1; k < used; ++k)
            s[k] = s[k - 1] + chord(taken[taken.size() - used + k - 1], taken[taken.size() - used + k], band);
        auto predict = [&](double at) {
            BranchPoint p{0.0, Eigen::VectorXd::Zero(2 * m), Eigen::VectorXd::Zero(2 * m)};
            if (used == 1) {
                p = taken.back();
                p.omega += direction * at * band;
                return p;
            }
            const std::vector<double> w = lagrange(s, at);
            for (std::size_t k = 0; k < used; ++k) {
                p.omega += w[k] * taken[taken.size() - used + k].omega;
                p.h += w[k] * taken[taken.size() - used + k].h;
                p.x += w[k] * taken[taken.size() - used + k].x;
            }
            return p;
        };
        double reach = s.back() + ds;
        BranchPoint p = predict(reach);
        // At the band's edge: the step shortened so that the predicted w is on it.
        bool edge = false;
        const double last_omega = taken.back().omega;
        for (const double bound : {options.omega_min, options.omega_max})
            if ((p.omega - bound) * (last_omega - bound) < 0.0 ||
                (p.omega == bound && last_omega != bound)) {
                reach = s.back() + ds * (bound - last_omega) / (p.omega - last_omega);
                p = predict(reach);
                p.omega = bound;
                edge = true;
            }
        if (!(p.omega > 0.0) || !p.x.allFinite() || !p.h.allFinite()) {
            ds *= 0.5;
            continue;
        }
        Eigen::VectorXd from = out.points.back().state;
        for (Eigen::Index k = 0; k < m; ++k) {
            from(moving[static_cast<std::size_t>(k)]) = p.x(k);
            from(n + moving[static_cast<std::size_t>(k)]) = p.x(m + k) * p.omega;
        }
        const bool unstable = out.points.back().max_multiplier > 1.0 + options.exact.stability_tolerance;
        const ExactOrbit orbit = detail::law_periodic_orbit(system, p.omega, from, unstable ? options.exact : shaken);
        PeriodicResponse r = orbit_response(orbit, p.omega, orbit.periods);
        if (r.stopped) return stopped(r);
        bool taken_ok = r.converged;
        double distance = 0.0;
        if (taken_ok) {
            const BranchPoint c = coordinates(r);
            distance = chord(c, p, band);
            const double step_taken = reach - s.back();
            // onwards: the chord from the last point does not turn back along the previous one
            bool onwards = true;
            if (taken.size() >= 2) {
                const BranchPoint& a = taken[taken.size() - 2];
                const BranchPoint& b = taken.back();
                const double size = std::max({a.h.cwiseAbs().maxCoeff(), b.h.cwiseAbs().maxCoeff(),
                                              c.h.cwiseAbs().maxCoeff(), 1e-300});
                const double dot = (b.omega - a.omega) * (c.omega - b.omega) / (band * band) +
                                   (b.h - a.h).dot(c.h - b.h) / (size * size);
                onwards = dot > 0.0;
            } else {
                onwards = direction * (c.omega - taken.back().omega) > 0.0;
            }
            // (the first step predicts the last state at the next w: its distance is the branch's slope)
            taken_ok = (used == 1 || distance <= 0.5 * step_taken) && onwards;
            // A corner (the tangent turns at a point: a contact's state changes): the prediction's
            // error then shrinks like the step, not its square, as the step halves, and stays of
            // the order of the angle.
            const double ratio = distance / step_taken;
            const bool corner = !taken_ok && onwards && ratio <= corner_ratio && step_taken <= options.step / 16.0 &&
                                rejected_ratio <= corner_ratio && ratio >= rejected_ratio / 1.5;
            rejected_ratio = taken_ok || !onwards ? std::numeric_limits<double>::quiet_NaN() : ratio;
            if (corner) {
                taken_ok = true;
                out.corners.push_back(c.omega);
                history = taken.size();  // the corner's index once taken
                direction = c.omega >= taken.back().omega ? 1.0 : -1.0;
            }
            if (!taken_ok)
                last_failure = "at w = " + format_number(p.omega) + " the orbit found lies " +
                               format_number(distance / step_taken) + " steps from its prediction" +
                               (onwards ? "" : ", back along the branch");
            if (taken_ok) {
                taken.push_back(c);
                out.points.push_back(std::move(r));
                if (options.progress) options.progress(out.points.back(), ds);
                // a turn in w: a fold, its w the vertex of the parabola through the three points
                const std::size_t k = out.points.size();
                if (k >= 3) {
                    const double w0 = out.points[k - 3].omega, w1 = out.points[k - 2].omega, w2 = out.points[k - 1].omega;
                    // (a turn by rounding, on a stretch where w stays put, is none)
                    const double rounding = fold_turn * std::abs(w1);
                    if ((w1 - w0) * (w2 - w1) < 0.0 && std::abs(w1 - w0) > rounding && std::abs(w2 - w1) > rounding) {
                        const double s1 = chord(taken[k - 3], taken[k - 2], band), s2 = s1 + chord(taken[k - 2], taken[k - 1], band);
                        // w(s) = w0 + a s + b s^2 through (0, w0), (s1, w1), (s2, w2)
                        const double d1 = (w1 - w0) / s1, d2 = (w2 - w0) / s2;
                        const double b = (d2 - d1) / (s2 - s1), a = d1 - b * s1;
                        double vertex = w1;
                        if (b != 0.0) {
                            const double sv = -a / (2.0 * b);
                            if (sv >= 0.0 && sv <= s2) vertex = w0 + a * sv + b * sv * sv;
                        }
                        out.folds.push_back(ExactFold{vertex, static_cast<int>(k - 2)});
                    }
                }
                if (edge) {
                    out.status = "completed";
                    out.message = "the branch left the band at w = " + format_number(p.omega);
                    return out;
                }
                if (used > 1 && history + 1 < taken.size()) ds = std::min(options.step, ds * std::min(2.0, std::max(0.5, std::sqrt(0.1 * step_taken / std::max(distance, 1e-300)))));
                continue;
            }
        } else {
            last_failure = "at w = " + format_number(p.omega) + ": " + r.message;
            rejected_ratio = std::numeric_limits<double>::quiet_NaN();
        }
        ++out.rejected;
        ds *= 0.5;
    }
}

Verdict judge_sweep(const System& system, const std::vector<PeriodicResponse>& responses,
                    const TimeIntegrationOptions& options, const ExactOptions* exact) {
    Verdict v;
    int failed = 0;
    for (const PeriodicResponse& r : responses)
        if (!r.converged) {
            ++failed;
            v.errors.push_back(r.summary());
        }
    if (failed > 0)
        v.errors.push_back(std::to_string(failed) + " of " + std::to_string(responses.size()) +
                           " points did not converge (converged = false in the output)");
    // An exact orbit that is unstable is a periodic solution the structure would leave: said, by
    // count and the largest multiplier (a time integration there goes elsewhere).
    if (exact) {
        int unstable = 0, unresolved = 0;
        double largest = 0.0, largest_w = 0.0, unresolved_w = 0.0;
        for (const PeriodicResponse& r : responses)
            if (r.stability_unresolved(exact->stability_tolerance)) {
                if (unresolved++ == 0) unresolved_w = r.omega;
            } else if (r.converged && r.max_multiplier > 1.0 + exact->stability_tolerance) {
                ++unstable;
                if (r.max_multiplier > largest) {
                    largest = r.max_multiplier;
                    largest_w = r.omega;
                }
            }
        int unknown = 0;
        const PeriodicResponse* first = nullptr;
        for (const PeriodicResponse& r : responses)
            if (r.converged && !std::isfinite(r.max_multiplier) && unknown++ == 0) first = &r;
        if (first) {
            // the solver's reason, where its message gives one (ExactOrbit::multipliers)
            const std::size_t why = first->message.find("the multipliers are unknown");
            v.note(std::to_string(unknown) + " of " + std::to_string(responses.size()) +
                   " exact orbits have an unknown stability (their multipliers could not be computed: max_multiplier "
                   "empty), the first at w = " +
                   format_number(first->omega) + (why == std::string::npos ? std::string() : ": " + first->message.substr(why)));
        }
        // Orbits Newton left where no step lowered the residual (the flow's rounding over a
        // period, below the solver's floor): converged, with an accuracy their residual states.
        int rounded = 0;
        double loosest = 0.0, loosest_w = 0.0;
        for (const PeriodicResponse& r : responses)
            if (r.converged && r.poincare_change > exact->tolerance) {
                ++rounded;
                if (r.poincare_change > loosest) {
                    loosest = r.poincare_change;
                    loosest_w = r.omega;
                }
            }
        if (rounded > 0)
            v.note(std::to_string(rounded) + " of " + std::to_string(responses.size()) +
                   " exact orbits converged to the flow's rounding, not to the tolerance " +
                   format_number(exact->tolerance) + ": the period map's residual, relative to the state, is up to " +
                   format_number(loosest) + " (at w = " + format_number(loosest_w) + ")");
        if (unstable > 0)
            v.note(std::to_string(unstable) + " of " + std::to_string(responses.size()) +
                   " exact orbits are unstable (a Floquet multiplier above 1; the largest, " + format_number(largest) +
                   ", at w = " + format_number(largest_w) +
                   "): periodic solutions the structure leaves, where a time integration goes to another response");
        if (unresolved > 0)
            v.note(std::to_string(unresolved) + " of " + std::to_string(responses.size()) +
                   " exact orbits have an uncertain stability (the first at w = " + format_number(unresolved_w) +
                   "): their largest multiplier, from central differences of the period map, is above 1 by less than "
                   "the differences' accuracy (" + format_number(difference_multiplier_accuracy) +
                   "): a neutral direction they cannot place");
    }
    // Energy balance of the exact solver's steady states: input work = viscous + friction
    // energy per period, relative to the work the force could do on the first harmonic (it does
    // not integrate the viscous energy: checked only without damping). Time integration checks
    // its own (a converged PeriodicResponse passed it, integrate_steady_state).
    if (exact && system.damping.nonZeros() == 0) {
        const double limit = options.physics_tolerance();
        int unbalanced = 0;
        double worst = 0.0, worst_w = 0.0;
        for (const PeriodicResponse& r : responses) {
            if (!r.converged) continue;
            double amplitude = 0.0;
            for (double a : r.y_amp1) amplitude += a * a;
            const double reach =
                system.excitation_harmonic == 1 ? M_PI * system.excitation.norm() * std::sqrt(amplitude) : 0.0;
            const double error = energy_imbalance(r.input_energy, r.viscous_energy, r.energy, reach);
            if (error > limit) ++unbalanced;
            if (error > worst) {
                worst = error;
                worst_w = r.omega;
            }
        }
        if (unbalanced > 0)
            v.warnings.push_back(std::to_string(unbalanced) + " converged point(s) fail the energy balance (relative " +
                                 "error above " + format_number(limit) +
                                 ", max(1e-6, 100 max(--rtol, --steady-tol)); the largest, " + format_number(worst) +
                                 ", at w = " + format_number(worst_w) + "): a tighter --steady-tol may help");
    }
    return v;
}

SteadySweep sweep_steady_states(const System& system, const std::vector<double>& omegas,
                                const TimeIntegrationOptions& options, const ExactOptions* exact,
                                const std::function<std::string()>& stop,
                                const std::function<void(std::size_t)>& before) {
    SteadySweep out;
    if (omegas.empty()) return out;
    out.responses.reserve(omegas.size());
    Eigen::VectorXd state = linear_stuck_state(system, omegas.front());
    for (std::size_t k = 0; k < omegas.size(); ++k) {
        const double w = omegas[k];
        if (const std::string why = stop ? stop() : std::string(); !why.empty()) {
            out.stopped = "stopped before w = " + format_number(w) + ": " + why;
            break;
        }
        if (before) before(k);
        PeriodicResponse r =
            exact ? exact_steady_state(system, w, exact_sweep_options(system, *exact, !out.responses.empty()),
                                       options.max_periods, exact_sweep_start(system, w, out.responses, state))
                  : integrate_steady_state(system, w, options, &state);
        if (r.stopped) {
            out.stopped = r.message + "; that frequency is not computed";
            break;
        }
        out.responses.push_back(std::move(r));
        state = out.responses.back().state;
    }
    return out;
}

}  // namespace hbf
