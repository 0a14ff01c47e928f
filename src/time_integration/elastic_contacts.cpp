// hbfriction — time integration of contacts with a normal direction (elastic_contacts.hpp).
#include "time_integration/elastic_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "time_integration/elastic_integrator.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/linear_limits.hpp"
#include "hbf/normal_contact.hpp"
#include "hbf/static_state.hpp"

namespace hbf::detail {

namespace {
constexpr double pi = 3.14159265358979323846;
}  // namespace

void summarise_contacts(PeriodicResponse& out) {
    if (out.contacts.empty()) {
        out.regime = "none";
        return;
    }
    out.stick_fraction = out.contacts.front().stick_fraction;
    out.regime = out.contacts.front().regime;
}

double refined_max(const Eigen::VectorXd& y) {
    const Eigen::Index n = y.size();
    Eigen::Index j = 0;
    y.cwiseAbs().maxCoeff(&j);
    const double a = std::abs(y((j + n - 1) % n)), b = std::abs(y(j)), c = std::abs(y((j + 1) % n));
    const double curvature = a - 2.0 * b + c;
    if (!(curvature < 0.0)) return b;
    const double offset = 0.5 * (a - c) / curvature;
    return b - 0.25 * (a - c) * offset;
}


bool has_elastic_contacts(const System& system) {
    return std::any_of(system.contacts.begin(), system.contacts.end(),
                       [](const Contact& c) { return contact_law(c.law).time_integrator() == TimeIntegrator::elastic_contacts; });
}

int elastic_state_size(const System& system) {
    int size = 2 * system.dofs();
    for (const Contact& c : system.contacts) size += static_cast<int>(system.contact_directions(c).cols());
    return size;
}

Eigen::VectorXd elastic_linear_stuck_state(const System& system, double omega) {
    const int n = system.dofs();
    Eigen::VectorXd state = Eigen::VectorXd::Zero(elastic_state_size(system));
    Eigen::MatrixXd k(system.stiffness);
    Eigen::VectorXd load = Eigen::VectorXd::Zero(n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    for (std::size_t i = 0; i < system.contacts.size(); ++i) {
        const Contact& c = system.contacts[i];
        const StuckElement normal = elements[i].back();
        const Eigen::VectorXd w = system.contact_directions(c).rightCols(1);
        k += normal.stiffness * w * w.transpose();
        load -= normal.offset * w;
    }
    if (system.static_load.size() > 0) load += system.static_load;
    const Eigen::VectorXd rest = k.fullPivLu().solve(load);
    const StuckResponse stuck = stuck_linear_response(system, omega);
    const Eigen::VectorXcd y = stuck.ok ? stuck.amplitude : Eigen::VectorXcd::Zero(n);
    state.head(n) = rest.allFinite() ? rest : Eigen::VectorXd::Zero(n);
    // The sliders where the static state puts no tangential force: centred, the stuck force
    // k_t (u - s) is the linear response's alone, of zero mean (not zero at t = 0).
    int at = 2 * n;
    for (const Contact& c : system.contacts) {
        const Eigen::MatrixXd w = system.contact_directions(c);
        const Eigen::VectorXd s = w.leftCols(w.cols() - 1).transpose() * state.head(n);
        state.segment(at, s.size()) = s;
        at += static_cast<int>(s.size());
    }
    state.head(n) += y.real();
    state.segment(n, n) = -system.excitation_harmonic * omega * y.imag();
    state.tail(static_cast<Eigen::Index>(system.contacts.size())).setConstant(1.0);  // stuck
    return state;
}

PeriodicResponse integrate_elastic_contacts(const System& system, double omega, const TimeIntegrationOptions& options,
                                            const Eigen::VectorXd* initial_state) {
    check_elastic_system(system);
    const int size = elastic_state_size(system);
    if (initial_state && (initial_state->size() != size || !initial_state->allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state->size()) +
                           " entries or non-finite values: allowed " + std::to_string(size) +
                           " finite values (2 N + the contacts' sliders and modes)");
    const double scale = options.displacement_scale > 0.0 ? options.displacement_scale : response_scale(system, omega);
    ElasticIntegrator integrator(system, omega, options, scale);
    Eigen::VectorXd x = initial_state ? *initial_state : elastic_rest_state(system);
    integrator.settle(x);
    PeriodicResponse out;
    out.omega = omega;
    out.displacement_scale = scale;
    const int n = system.dofs();
    const int samples = std::max(16 * options.samples_per_period, 4096);
    for (int k = 1; k <= options.max_periods; ++k) {
        if (const std::string why = k > 1 ? options.stop_reason() : std::string(); !why.empty()) {
            out.stop_after(k - 1, why);
            out.state = x;
            return out;
        }
        ElasticIntegrator::Record r = integrator.period(x, 0);
        out.periods = k;
        if (!r.ok) {
            out.message = r.failure + " (period " + std::to_string(k) + ", w = " + format_number(omega) + ")";
            out.state = x;
            return out;
        }
        // the Poincare change: displacements, sliders and velocities / omega, relative
        const Eigen::VectorXd& e = r.end;
        const int continuous = 2 * n + (size - 2 * n - static_cast<int>(system.contacts.size()));
        double size_now = 0.0, change = 0.0;
        for (int i = 0; i < continuous; ++i) {
            const double w = i >= n && i < 2 * n ? 1.0 / omega : 1.0;
            size_now = std::max(size_now, w * std::abs(e(i)));
            change = std::max(change, w * std::abs(e(i) - x(i)));
        }
        out.poincare_change = size_now > 0.0 ? change / size_now : change;
        x = e;
        if (k < options.min_periods || out.poincare_change > options.steady_tolerance) continue;
        // converged: the final period again, with its samples and metrics
        ElasticIntegrator::Record f = integrator.period(x, samples);
        if (!f.ok) {
            out.message = f.failure + " (the final period, w = " + format_number(omega) + ")";
            out.state = x;
            return out;
        }
        out.converged = true;
        out.state = x;
        out.message = "converged after " + std::to_string(k) + " periods (Poincare change " +
                      format_number(out.poincare_change) + ")";
        elastic_metrics(system, omega, f, options, out);
        if (out.energy_error > options.physics_tolerance()) {
            out.converged = false;
            out.message += "; but the energy balance fails: " + format_number(out.energy_error) + " > " +
                           format_number(options.physics_tolerance());
        }
        return out;
    }
    out.state = x;
    out.message = "no steady state within " + std::to_string(options.max_periods) + " periods (Poincare change " +
                  format_number(out.poincare_change) + ")";
    return out;
}

}  // namespace hbf::detail
