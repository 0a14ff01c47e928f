// hbfriction — steady states over a frequency sweep (hbf timeint): the event-exact orbit as a
// time-integration result, and the verdict on a sweep's points (time_integration.hpp).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "time_integration/law_orbit.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"

namespace hbf {

ExactOrbit detail::law_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& start,
                                      const ExactOptions& options) {
    if (rigid_contacts_only(system)) return rigid_periodic_orbit(system, omega, start, options);
    if (elastic_contacts_only(system)) return elastic_periodic_orbit(system, omega, start, options);
    return exact_periodic_orbit(system, omega, start, options);
}

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
    if (orbit.converged) r.max_multiplier = orbit.max_multiplier;
    if (!orbit.stopped.empty()) r.stop_after(periods, orbit.stopped);
    return r;
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
    if (done.size() < 2 || !rigid_contacts_only(system)) return last.state;
    const PeriodicResponse& before = done[done.size() - 2];
    const double step = last.omega - before.omega;
    if (!last.converged || !before.converged || last.state.size() != before.state.size() || step == 0.0 ||
        (omega - last.omega) / step <= 0.0)
        return last.state;
    return last.state + (last.state - before.state) * ((omega - last.omega) / step);
}

Verdict judge_sweep(const System& system, const std::vector<PeriodicResponse>& responses,
                       const TimeIntegrationOptions& options, bool exact) {
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
        int unstable = 0;
        double largest = 0.0, largest_w = 0.0;
        for (const PeriodicResponse& r : responses)
            if (r.converged && r.max_multiplier > 1.0 + ExactOptions{}.stability_tolerance) {
                ++unstable;
                if (r.max_multiplier > largest) {
                    largest = r.max_multiplier;
                    largest_w = r.omega;
                }
            }
        if (unstable > 0)
            v.note(std::to_string(unstable) + " of " + std::to_string(responses.size()) +
                   " exact orbits are unstable (a Floquet multiplier above 1; the largest, " + format_number(largest) +
                   ", at w = " + format_number(largest_w) +
                   "): periodic solutions the structure leaves, where a time integration goes to another response");
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

}  // namespace hbf
