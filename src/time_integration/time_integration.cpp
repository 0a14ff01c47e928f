// Periodic steady state by time integration with CVODE (see time_integration.hpp for the
// model of each law, the events and the state convention).
#include "hbf/time_integration.hpp"

#include "hbf/contact_law.hpp"
#include "hbf/linear_limits.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hbf/error.hpp"
#include "hbf/cyclic.hpp"
#include "base/enum_table.hpp"
#include "base/stopwatch.hpp"
#include "time_integration/elastic_contacts.hpp"
#include "time_integration/unilateral_contacts.hpp"
#include "time_integration/integrator.hpp"
#include "time_integration/massless.hpp"

namespace hbf {

namespace {
/// Solves A s = b by GMRES without restarts, A given as a product v -> A v that may fail
/// (false: a period failed). Stops at |A s - b| <= relative_tolerance |b| or after
/// max_products products; false if a product failed or s is not finite.
bool gmres(const std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)>& product, const Eigen::VectorXd& b,
           int max_products, double relative_tolerance, Eigen::VectorXd& solution) {
    const double beta = b.norm();
    solution = Eigen::VectorXd::Zero(b.size());
    if (!(beta > 0.0)) return std::isfinite(beta);
    // Arnoldi with modified Gram-Schmidt; the small least-squares problem is solved afresh
    // by QR after every product (max_products is tens, the cost is the periods).
    std::vector<Eigen::VectorXd> basis{b / beta};
    Eigen::MatrixXd hessenberg = Eigen::MatrixXd::Zero(max_products + 1, max_products);
    Eigen::VectorXd coefficients;
    for (int j = 0; j < max_products; ++j) {
        Eigen::VectorXd w;
        if (!product(basis[static_cast<std::size_t>(j)], w)) return false;
        for (int i = 0; i <= j; ++i) {
            hessenberg(i, j) = basis[static_cast<std::size_t>(i)].dot(w);
            w -= hessenberg(i, j) * basis[static_cast<std::size_t>(i)];
        }
        hessenberg(j + 1, j) = w.norm();
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(j + 2);
        rhs(0) = beta;
        const Eigen::MatrixXd block = hessenberg.topLeftCorner(j + 2, j + 1);
        coefficients = block.colPivHouseholderQr().solve(rhs);
        const double residual = (block * coefficients - rhs).norm();
        const bool breakdown = !(hessenberg(j + 1, j) > 1e-14 * beta);
        if (residual <= relative_tolerance * beta || breakdown || j + 1 == max_products) break;
        basis.push_back(w / hessenberg(j + 1, j));
    }
    for (Eigen::Index i = 0; i < coefficients.size(); ++i) solution += coefficients(i) * basis[static_cast<std::size_t>(i)];
    return solution.allFinite();
}
}  // namespace

constexpr detail::EnumName<IntegrationMethod> integration_method_names[] = {
    {IntegrationMethod::adams, "adams"}, {IntegrationMethod::bdf, "bdf"}};

std::string to_string(IntegrationMethod method) {
    return detail::enum_name(integration_method_names, method, "integration method");
}

IntegrationMethod parse_integration_method(const std::string& name) {
    return detail::parse_enum(integration_method_names, name, "method");
}

namespace {
/// An integer option's lower bound: InvalidInput naming it otherwise.
void at_least(const char* name, int value, int lowest) {
    if (value < lowest)
        throw InvalidInput(std::string(name) + " = " + std::to_string(value) + " is out of range: allowed >= " +
                           std::to_string(lowest));
}
}  // namespace

void TimeIntegrationOptions::validate() const {
    auto in_range = [](double value, double low, double high, const char* name, const char* meaning) {
        if (!(value >= low && value <= high))
            throw InvalidInput(std::string(name) + " (" + meaning + ") = " + format_number(value) +
                               " is out of range: allowed " + format_number(low) + ".." + format_number(high));
    };
    in_range(relative_tolerance, smallest_relative_tolerance, largest_relative_tolerance, "relative_tolerance",
             "CVODE relative tolerance");
    in_range(absolute_tolerance, smallest_absolute_tolerance, largest_absolute_tolerance, "absolute_tolerance",
             "CVODE absolute tolerance");
    in_range(steady_tolerance, smallest_steady_tolerance, largest_steady_tolerance, "steady_tolerance",
             "Poincare convergence tolerance");
    if (!(displacement_scale >= 0.0 && std::isfinite(displacement_scale)))
        throw InvalidInput("displacement_scale (scale of the absolute tolerances) = " + format_number(displacement_scale) +
                           " is out of range: allowed finite >= 0 (0 = automatic)");
    at_least("min_periods", min_periods, 1);
    if (max_periods < min_periods || max_periods > largest_max_periods)
        throw InvalidInput("max_periods = " + std::to_string(max_periods) + " is out of range: allowed min_periods = " +
                           std::to_string(min_periods) + ".." + std::to_string(largest_max_periods));
    at_least("samples_per_period", samples_per_period, 8);
    at_least("max_events_per_period", max_events_per_period, 1);
    at_least("max_steps_per_period", max_steps_per_period, 10);
    at_least("stick_restart_periods", stick_restart_periods, 1);
    at_least("shooting_interval", shooting_interval, 1);
    at_least("dense_newton_max_dofs", dense_newton_max_dofs, 0);
    at_least("shooting_dense_max_states", shooting_dense_max_states, 0);
    at_least("shooting_krylov_max", shooting_krylov_max, 1);
}

double TimeIntegrationOptions::physics_tolerance() const {
    return std::max(1e-6, 100.0 * std::max(relative_tolerance, steady_tolerance));
}

std::string PeriodicResponse::summary() const {
    std::ostringstream s;
    s << "w = " << format_number(omega) << ": " << (converged ? "converged" : "not converged") << " after "
      << periods << " periods";
    if (!y_max.empty()) s << ", y1_max = " << format_number(y_max[0]);
    if (!regime.empty()) s << ", " << regime;
    if (!message.empty()) s << "; " << message;
    return s.str();
}

void PeriodicResponse::stop_after(int periods_done, const std::string& why) {
    converged = false;
    stopped = true;
    periods = periods_done;
    message = "stopped after " + std::to_string(periods_done) + " periods (w = " + format_number(omega) + "): " + why;
}

int state_size(const System& system) {
    if (detail::has_elastic_contacts(system)) return detail::elastic_state_size(system);
    if (detail::has_unilateral_contacts(system)) return 2 * system.dofs();
    return 2 * system.dofs() + 2 * time_domain_elements(system);
}

double response_scale(const System& system, double omega) {
    system.validate();
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    const auto usable = [](double x) { return std::isfinite(x) && x > 0.0; };
    const auto largest = [](const Eigen::VectorXd& y) { return y.size() > 0 ? y.cwiseAbs().maxCoeff() : 0.0; };
    double quasi_static = 0.0, mass_line = 0.0;
    Eigen::SparseLU<SparseMatrix> stiffness;
    stiffness.compute(system.stiffness);
    if (stiffness.info() == Eigen::Success) quasi_static = largest(stiffness.solve(system.excitation));
    if (!usable(quasi_static) && !system.contacts.empty()) {
        // K singular: a part held only by its contacts (a massless shoe sliding on the ground).
        // The quasi-static response with each contact held by a spring of K's largest diagonal.
        double spring = 0.0;
        for (int i = 0; i < system.dofs(); ++i) spring = std::max(spring, std::abs(system.stiffness.coeff(i, i)));
        if (!(spring > 0.0)) spring = 1.0;
        std::vector<Eigen::Triplet<double>> held;
        for (const Contact& contact : system.contacts) {
            const Eigen::VectorXd w = system.contact_direction(contact);
            std::vector<int> support;
            for (int i = 0; i < w.size(); ++i)
                if (w(i) != 0.0) support.push_back(i);
            for (int i : support)
                for (int j : support) held.emplace_back(i, j, spring * w(i) * w(j));
        }
        SparseMatrix k(system.dofs(), system.dofs());
        k.setFromTriplets(held.begin(), held.end());
        k += system.stiffness;
        stiffness.compute(k);
        if (stiffness.info() == Eigen::Success) quasi_static = largest(stiffness.solve(system.excitation));
    }
    if (system.has_positive_definite_mass()) {
        Eigen::SimplicialLDLT<SparseMatrix> mass(system.mass);
        const double drive = system.excitation_harmonic * omega;
        if (mass.info() == Eigen::Success) mass_line = largest(mass.solve(system.excitation)) / (drive * drive);
    }
    if (usable(quasi_static) && usable(mass_line)) return std::min(quasi_static, mass_line);
    if (usable(quasi_static)) return quasi_static;
    if (usable(mass_line)) return mass_line;
    return 1.0;
}

namespace {

constexpr double pi = 3.14159265358979323846;
using detail::Integrator;
using detail::PeriodRecord;

double poincare_change(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int dofs, int continuous, double omega) {
    // Relative and unit-consistent: displacements (and internal states, also lengths) against
    // the displacement scale, velocities against omega times it.
    const double y_scale = std::max(a.head(dofs).cwiseAbs().maxCoeff(), a.segment(dofs, dofs).cwiseAbs().maxCoeff() / omega);
    const Eigen::VectorXd d = (a.head(continuous) - b.head(continuous)).cwiseAbs();
    const double dy = std::max(d.head(dofs).maxCoeff(), d.size() > 2 * dofs ? d.tail(continuous - 2 * dofs).maxCoeff() : 0.0);
    const double dv = d.segment(dofs, dofs).maxCoeff() / omega;
    const double change = std::max(dy, dv);
    return y_scale > 0.0 ? change / y_scale : (change > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
}

/// integrate_steady_state for M > 0 (validated by the caller).
PeriodicResponse integrate_with_mass(const System& system, double omega, const TimeIntegrationOptions& options,
                                     const Eigen::VectorXd* initial_state);

void fill_metrics(PeriodicResponse& out, const PeriodRecord& r, const Eigen::VectorXd& start, double period,
                  const std::vector<Output>& outputs) {
    out.state = start;
    out.y_max = r.y_max;
    out.harmonic1 = r.harmonic1;
    out.y_amp1.resize(static_cast<std::size_t>(r.harmonic1.size()));
    for (Eigen::Index i = 0; i < r.harmonic1.size(); ++i) out.y_amp1[static_cast<std::size_t>(i)] = std::abs(r.harmonic1(i));
    out.output_max = r.output_max;
    out.output_amp1.clear();
    for (const Output& o : outputs) {
        std::complex<double> h = 0.0;
        for (const auto& [i, c] : o.terms()) h += c * r.harmonic1(i);
        out.output_amp1.push_back(std::abs(h));
    }
    if (r.stick_time.empty()) {
        out.stick_fraction = 0.0;
        out.regime = "none";
        out.stick_margin_min = out.stick_margin_max = 0.0;
    } else {
        // Per time-domain element here; integrate_steady_state regroups them by contact.
        out.contacts.clear();
        for (std::size_t c = 0; c < r.stick_time.size(); ++c)
            out.contacts.push_back(contact_regime(r.always_stuck[c] ? period : r.never_stuck[c] ? 0.0 : r.stick_time[c], period));
        out.stick_fraction = out.contacts.front().stick_fraction;
        out.regime = out.contacts.front().regime;
        out.stick_margin_min = std::isfinite(r.margin_min) ? r.margin_min : 0.0;
        out.stick_margin_max = std::isfinite(r.margin_max) ? r.margin_max : 0.0;
    }
    out.switches = r.switches;
    out.energy = r.energy;
    out.viscous_energy = r.viscous_energy;
    out.input_energy = r.input_energy;
    out.time = r.time;
    out.displacement = r.displacement;
    out.velocity = r.velocity;
    out.friction_force = r.friction_force;
}

/// The physics checks of a converged final period (integrate_steady_state): fills
/// out.energy_error and out.stick_error from `r` (the period that starts at out.state).
struct PhysicsCheck {
    std::string failure;          ///< empty: every check passed
    bool off_convention = false;  ///< permanent stick on another member of the stuck family
};
PhysicsCheck check_physics(const System& system, double omega, const PeriodRecord& r, PeriodicResponse& out,
                           double scale, double tolerance) {
    PhysicsCheck check;
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    // energy balance, relative to the work the force could do on the first harmonic (on a
    // harmonic of the size of y_max for a force at h omega, h > 1: its harmonic h is not
    // integrated)
    double amplitude = 0.0;
    for (double a : system.excitation_harmonic == 1 ? out.y_amp1 : out.y_max) amplitude += a * a;
    // (not below the work on 1e-9 of the scale s: a response held at zero by a stuck contact has
    // no meaningful relative imbalance, as response_floor in harmonic balance)
    const double reach = pi * system.excitation.norm() * std::max(std::sqrt(amplitude), 1e-9 * scale);
    out.energy_error = energy_imbalance(out.input_energy, out.viscous_energy, out.energy, reach);
    // stick kinematics, relative to the scale s (not to the integrated response: a wrong one
    // must not set its own yardstick)
    out.stick_error = 0.0;
    bool permanent = nc > 0;
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        const ContactLaw& law = contact_law(contact.law);
        const bool stuck = law.exact_stick() && r.always_stuck[static_cast<std::size_t>(c)];
        permanent = permanent && stuck;
        if (!stuck || !law.stuck(contact).rigid || out.displacement.rows() == 0) continue;
        const Eigen::VectorXd q = out.displacement * system.contact_direction(contact);
        out.stick_error = std::max(out.stick_error, (q.maxCoeff() - q.minCoeff()) / scale);
    }
    if (permanent) {  // the convention of event_exact.hpp: the centred (linear stuck) state
        const Eigen::VectorXd centred = linear_stuck_state(system, omega);
        const double drive = system.excitation_harmonic * omega;
        const Eigen::VectorXd d = (out.state - centred).head(2 * n + nc).cwiseAbs();
        double distance = std::max(d.head(n).maxCoeff(), d.segment(n, n).maxCoeff() / drive);
        if (nc > 0) distance = std::max(distance, d.tail(nc).maxCoeff());
        // relative to the centred state's size (not below s)
        const double size = std::max({scale, centred.head(n).cwiseAbs().maxCoeff(),
                                      centred.segment(n, n).cwiseAbs().maxCoeff() / drive});
        distance /= size;
        check.off_convention = distance > tolerance;
        out.stick_error = std::max(out.stick_error, distance);
    }
    if (out.energy_error > tolerance)
        check.failure = "the energy balance fails: input work - viscous - friction energy per period is " +
                        format_number(out.energy_error) + " of the work scale, allowed " + format_number(tolerance);
    else if (check.off_convention)
        check.failure = "in permanent stick the state is " + format_number(out.stick_error) +
                        " (relative) from the centred linear stuck steady state, allowed " + format_number(tolerance);
    else if (out.stick_error > tolerance)
        check.failure = "a contact stuck for the whole period moves: q varies by " + format_number(out.stick_error) +
                        " of the response, allowed " + format_number(tolerance);
    return check;
}

}  // namespace

Eigen::VectorXd linear_stuck_state(const System& given, double omega) {
    given.validate();
    if (detail::has_elastic_contacts(given)) return detail::elastic_linear_stuck_state(given, omega);
    if (detail::has_unilateral_contacts(given)) return Eigen::VectorXd::Zero(2 * given.dofs());  // at rest
    const TimeDomainView view(given);  // the state is per time-domain element (contact_law.hpp)
    const System& system = view.system();
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    const StuckResponse stuck = stuck_linear_response(system, omega);
    const Eigen::VectorXcd y = stuck.ok ? stuck.amplitude : Eigen::VectorXcd::Zero(n);
    Eigen::VectorXd state = Eigen::VectorXd::Zero(state_size(system));
    state.head(n) = y.real();
    state.segment(n, n) = -system.excitation_harmonic * omega * y.imag();  // Re(i h omega Y)
    for (int c = 0; c < nc; ++c) {
        const Contact& k = system.contacts[static_cast<std::size_t>(c)];
        if (contact_law(k.law).time_state() == TimeState::bristle)
            state(2 * n + c) = system.contact_direction(k).dot(state.head(n));  // z = q
    }
    return state;
}

PeriodicResponse integrate_steady_state(const System& given, double omega, const TimeIntegrationOptions& options,
                                        const Eigen::VectorXd* initial_state) {
    given.validate();
    refuse_cyclic(given, "time integration");
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    options.validate();
    for (const Output& o : options.outputs) o.validate(given.dofs());
    if (detail::has_elastic_contacts(given)) {  // contacts with a normal direction: their own integrator
        detail::Stopwatch clock;
        PeriodicResponse r = detail::integrate_elastic_contacts(given, omega, options, initial_state);
        r.seconds = clock.lap();
        return r;
    }
    if (detail::has_unilateral_contacts(given)) {  // rigid contacts on massless nodes: their own integrator
        detail::Stopwatch clock;
        PeriodicResponse r = detail::integrate_unilateral_contacts(given, omega, options, initial_state);
        r.seconds = clock.lap();
        return r;
    }
    const TimeDomainView view(given);  // the contacts as time-domain elements (contact_law.hpp)
    const System& system = view.system();
    const int size = state_size(system);
    if (initial_state && (initial_state->size() != size || !initial_state->allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state->size()) +
                           " entries or non-finite values: allowed " + std::to_string(size) +
                           " finite values (2 N + 2 n_e, n_e the contacts' time-domain elements)");
    PeriodicResponse r;
    if (system.has_positive_definite_mass()) {
        r = integrate_with_mass(system, omega, options, initial_state);
    } else {
        // Massless DOFs: condensed statically (exact), integrated, expanded.
        const detail::MasslessCondensation condensation(system);
        const TimeIntegrationOptions reduced_options = detail::reduced_options(condensation, options);
        Eigen::VectorXd reduced_start;
        if (initial_state) reduced_start = condensation.reduce_state(*initial_state);
        r = integrate_with_mass(condensation.reduced(), omega, reduced_options, initial_state ? &reduced_start : nullptr);
        detail::expand(condensation, r, options);
    }
    if (!r.contacts.empty()) {
        r.contacts = contact_regimes(given, r.contacts);
        // A unilateral force element's margin is negative while closed (ContactLaw::time_margin):
        // its "stick" time is the closed time.
        for (std::size_t c = 0; c < given.contacts.size() && c < r.contacts.size(); ++c)
            if (contact_law(given.contacts[c].law).unilateral())
                r.contacts[c].separated_fraction = 1.0 - r.contacts[c].stick_fraction;
        mark_force_elements(given, r.contacts, r.regime, r.stick_fraction);
    }
    return r;
}

namespace {

PeriodicResponse integrate_with_mass(const System& system, double omega, const TimeIntegrationOptions& options,
                                     const Eigen::VectorXd* initial_state) {
    const int size = state_size(system);
    detail::Stopwatch clock;
    const int continuous = 2 * system.dofs() + static_cast<int>(system.contacts.size());
    const double period = 2.0 * pi / omega;
    PeriodicResponse out;
    out.omega = omega;
    const double scale = options.displacement_scale > 0.0 ? options.displacement_scale : response_scale(system, omega);
    out.displacement_scale = scale;
    const double physics_tolerance = options.physics_tolerance();
    std::string physics_failure;
    bool recentred = false;
    Integrator integrator(system, omega, options, scale);
    Eigen::VectorXd x = initial_state ? *initial_state : Eigen::VectorXd::Zero(size);
    integrator.settle_initial(x);
    bool restarted = false, have_metrics = false;
    int stuck_periods = 0;
    std::string note;
    // Newton (shooting) acceleration of the Poincare map: see TimeIntegrationOptions::shooting.
    int next_shooting = options.shooting_interval, shooting_interval = options.shooting_interval;
    int newton_steps = 0, newton_rejected = 0;
    bool pending_check = false, candidate_is_linear = false;
    int linear_tried_at = 0;
    Eigen::VectorXd saved;  // P(x) before a Newton step, to revert to
    double saved_change = 0, previous_change = std::numeric_limits<double>::infinity();
    int k = 0;
    while (k < options.max_periods) {
        if (const std::string why = k > 0 ? options.stop_reason() : std::string(); !why.empty()) {
            out.stop_after(k, why);
            if (!have_metrics) out.state = x;
            break;
        }
        PeriodRecord record = integrator.period(x);
        ++k;
        out.periods = k;
        if (!record.ok) {
            out.converged = false;
            out.message = record.failure + " (period " + std::to_string(k) + ", w = " + format_number(omega) + ")";
            if (!have_metrics) out.state = x;
            break;
        }
        const double change = poincare_change(record.end_state, x, system.dofs(), continuous, omega);
        if (pending_check) {  // the first period from a candidate start: keep it only if it helped
            pending_check = false;
            if (change > saved_change) {
                if (candidate_is_linear) {
                    note += "; the linear stuck start was tried after " + std::to_string(linear_tried_at) +
                            " periods and rejected";
                } else {
                    ++newton_rejected;
                    shooting_interval *= 2;
                    next_shooting = k + shooting_interval;
                }
                x = saved;
                previous_change = saved_change;
                continue;
            }
            if (candidate_is_linear)
                note += "; restarted from the linear stuck steady state after " + std::to_string(linear_tried_at) +
                        " periods";
            else {
                ++newton_steps;
                next_shooting = k;  // Newton converges fast: go on with it while it helps
            }
        }
        out.poincare_change = change;
        fill_metrics(out, record, x, period, options.outputs);
        have_metrics = true;
        if (k >= options.min_periods && change <= options.steady_tolerance) {
            const PhysicsCheck check = check_physics(system, omega, record, out, scale, physics_tolerance);
            if (check.failure.empty()) {
                out.converged = true;
                break;
            }
            if (check.off_convention && options.stick_restart && !recentred) {
                // permanent stick elsewhere in the stuck family: the centred member, integrated
                recentred = restarted = true;
                note += "; permanent stick moved to the centred linear stuck steady state after " +
                        std::to_string(k) + " periods";
                x = linear_stuck_state(system, omega);
                integrator.settle_initial(x);
                previous_change = std::numeric_limits<double>::infinity();
                continue;
            }
            physics_failure = check.failure;
            break;
        }
        const bool all_stuck = !record.always_stuck.empty() &&
                               std::all_of(record.always_stuck.begin(), record.always_stuck.end(), [](bool b) { return b; });
        stuck_periods = all_stuck ? stuck_periods + 1 : 0;
        const Eigen::VectorXd start = x;
        x = record.end_state;
        const bool shooting_due = options.shooting && k >= next_shooting && change > 0.2 * previous_change;
        if (options.stick_restart && !restarted && (stuck_periods >= options.stick_restart_periods || shooting_due)) {
            // candidate start: the linear stuck steady state (kept only if its first period
            // changes less than the current one)
            restarted = true;
            candidate_is_linear = true;
            linear_tried_at = k;
            saved = x;
            saved_change = change;
            pending_check = true;
            x = linear_stuck_state(system, omega);
            integrator.settle_initial(x);
        } else if (shooting_due && k + std::min(continuous, options.shooting_krylov_max) + 1 < options.max_periods) {
            // Newton step of the map: x <- x + (I - J)^-1 (P(x) - x)
            next_shooting = k + shooting_interval;
            bool ok = true;
            Eigen::VectorXd step;
            const Eigen::VectorXd difference = x.head(continuous) - start.head(continuous);
            if (continuous <= options.shooting_dense_max_states) {
                // J by forward differences, one period per continuous state
                const double size = start.head(continuous).cwiseAbs().maxCoeff();
                const double h = 1e-6 * (size > 0.0 ? size : 1.0);  // relative: independent of the units
                Eigen::MatrixXd jacobian(continuous, continuous);
                for (int j = 0; j < continuous && ok; ++j) {
                    Eigen::VectorXd perturbed = start;
                    perturbed(j) += h;
                    integrator.settle_initial(perturbed);
                    const PeriodRecord column = integrator.period(perturbed);
                    ++k;
                    ok = column.ok;
                    if (ok) jacobian.col(j) = (column.end_state.head(continuous) - x.head(continuous)) / h;
                }
                if (ok) step = (Eigen::MatrixXd::Identity(continuous, continuous) - jacobian).fullPivLu().solve(difference);
            } else {
                // matrix-free: J v = (P(start + h v) - P(start)) / h for |v| = 1
                const double norm = start.head(continuous).norm();
                const double h = 1e-7 * (norm > 0.0 ? norm : 1.0);
                const auto map_product = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) {
                    Eigen::VectorXd perturbed = start;
                    perturbed.head(continuous) += h * v;
                    integrator.settle_initial(perturbed);
                    const PeriodRecord column = integrator.period(perturbed);
                    ++k;
                    if (!column.ok) return false;
                    out = v - (column.end_state.head(continuous) - x.head(continuous)) / h;  // (I - J) v
                    return true;
                };
                ok = gmres(map_product, difference, options.shooting_krylov_max, 1e-4, step);
            }
            if (ok && step.allFinite()) {
                saved = x;
                saved_change = change;
                pending_check = true;
                candidate_is_linear = false;
                x.head(continuous) = start.head(continuous) + step;
                integrator.settle_initial(x);
            }
            out.periods = k;
        }
        previous_change = change;
    }
    if (!physics_failure.empty())
        out.message = "Poincare change " + format_number(out.poincare_change) + " <= " +
                      format_number(options.steady_tolerance) + " but the period fails its physics check: " +
                      physics_failure + " (w = " + format_number(omega) + "; tighter integration tolerances may help)";
    else if (!out.converged && out.message.empty())
        out.message = "Poincare map not converged after " + std::to_string(out.periods) + " periods: change " +
                      format_number(out.poincare_change) + " > " + format_number(options.steady_tolerance) +
                      " (w = " + format_number(omega) + "; a change that stalls is the integration's error per "
                      "period: tighter absolute/relative tolerances, or a looser steady tolerance, help)";
    else if (out.converged)
        out.message = "Poincare change " + format_number(out.poincare_change) + " <= " +
                      format_number(options.steady_tolerance);
    if (newton_steps + newton_rejected > 0)
        note += "; " + std::to_string(newton_steps) + " Newton (shooting) steps accepted, " +
                std::to_string(newton_rejected) + " rejected";
    out.message += note;
    out.steps = integrator.steps();
    out.rhs_evaluations = integrator.rhs_evaluations();
    out.seconds = clock.lap();
    return out;
}

}  // namespace

std::vector<PeriodicResponse> sweep(const System& system, const std::vector<double>& omegas,
                                    const TimeIntegrationOptions& options, const Eigen::VectorXd* initial_state) {
    std::vector<PeriodicResponse> responses;
    responses.reserve(omegas.size());
    Eigen::VectorXd state;
    if (initial_state) state = *initial_state;
    for (double omega : omegas) {
        responses.push_back(integrate_steady_state(system, omega, options, state.size() ? &state : nullptr));
        state = responses.back().state;
        if (responses.back().stopped) break;
    }
    return responses;
}

}  // namespace hbf
