// hbfriction — periodic orbits of law elastic by Newton shooting on the event-driven flow with
// its own derivative (elastic_exact.hpp).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <memory>
#include <string>

#include "event_exact/metrics.hpp"
#include "numerics/krylov.hpp"
#include "time_integration/elastic_contacts.hpp"
#include "time_integration/elastic_integrator.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"
#include "hbf/time_integration.hpp"

namespace hbf {

namespace {

/// Below this residual a Newton step that no longer lowers it has reached the flow's accuracy.
constexpr double newton_floor = 1e-9;
/// Samples of the recorded period (the maxima refined by a parabola).
constexpr int record_samples = 4096;
/// The central differences' step, of the state's size.
constexpr double difference_step = 1e-5;

/// At most this many Krylov vectors (GMRES, and Arnoldi for the multipliers).
constexpr int krylov_max_steps = 120;

using detail::ElasticIntegrator;
using detail::ElasticRoute;
using detail::KrylovOperator;
using detail::arnoldi_count;
using detail::arnoldi_dominant;
using Operator = KrylovOperator;

}  // namespace

bool elastic_contacts_only(const System& system) {
    return !system.contacts.empty() &&
           std::all_of(system.contacts.begin(), system.contacts.end(), [](const Contact& c) {
               return contact_law(c.law).time_integrator() == TimeIntegrator::elastic_contacts;
           });
}

int elastic_continuous_states(const System& system) {
    return detail::elastic_state_size(system) - static_cast<int>(system.contacts.size());
}

std::string elastic_solver_refusal(const System& system) {
    if (!elastic_contacts_only(system))
        return "the elastic-contact exact solver takes systems whose contacts are all of law elastic";
    if (system.cyclic.active()) return "the elastic-contact exact solver does not take a sector model (cyclic symmetry)";
    if (!system.has_positive_definite_mass())
        return "the mass matrix is singular (massless DOFs): law elastic's flow needs M positive definite";
    const int states = elastic_continuous_states(system);
    if (states > elastic_solver_max_states)
        return "the model has " + std::to_string(states) + " continuous states (2 N + the sliders), the elastic-contact "
               "exact solver at most " + std::to_string(elastic_solver_max_states) +
               " (each Newton step and the multipliers take up to " + std::to_string(2 * krylov_max_steps) +
               " periods of the flow)";
    return "";
}

ExactOrbit elastic_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                  const ExactOptions& options) {
    return detail::elastic_orbit(system, omega, initial_state, options, ElasticRoute::automatic);
}

ExactOrbit detail::elastic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                 const ExactOptions& options, ElasticRoute route) {
    options.validate();
    if (const std::string why = elastic_solver_refusal(system); !why.empty()) throw InvalidInput(why);
    if (!(omega > 0.0) || !std::isfinite(omega))
        throw InvalidInput("omega = " + format_number(omega) + " is out of range: allowed > 0");
    const int size = detail::elastic_state_size(system), n = system.dofs();
    if (initial_state.size() != 0 && (initial_state.size() != size || !initial_state.allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state.size()) +
                           " entries or non-finite values: allowed " + std::to_string(size) +
                           " finite values (2 N + the contacts' sliders and modes), or none (from rest)");
    TimeIntegrationOptions flow;
    flow.relative_tolerance = flow.absolute_tolerance = elastic_flow_tolerance;
    // per contact: a meshed interface's nodes each close, open, stick and slip every period
    flow.max_events_per_period =
        options.max_events_per_period * std::max(1, static_cast<int>(system.contacts.size()));
    flow.samples_per_period = options.samples > 0 ? options.samples : 256;
    flow.outputs = options.outputs;
    const double scale = response_scale(system, omega);
    ElasticIntegrator plain(system, omega, flow, scale);
    const int k = plain.continuous();
    const bool krylov =
        route == ElasticRoute::krylov || (route == ElasticRoute::automatic && k > elastic_variational_max_states);
    std::unique_ptr<ElasticIntegrator> variational_flow;
    if (route == ElasticRoute::variational || (route == ElasticRoute::automatic && k <= elastic_variational_max_states))
        variational_flow = std::make_unique<ElasticIntegrator>(system, omega, flow, scale, true);

    ExactOrbit out;
    out.omega = omega;
    // the max norm with velocities divided by omega (event_exact.hpp's convention)
    auto norm = [&](const Eigen::VectorXd& v) {
        double largest = 0.0;
        for (int i = 0; i < k; ++i) largest = std::max(largest, std::abs(v(i)) * (i >= n && i < 2 * n ? 1.0 / omega : 1.0));
        return largest;
    };
    Eigen::VectorXd x = initial_state.size() > 0 ? initial_state : detail::elastic_rest_state(system);
    plain.settle(x);
    const double start_size = norm(x);
    auto relative = [&](const Eigen::VectorXd& end, const Eigen::VectorXd& at) {
        const double size_of = std::max({norm(at), start_size, 1e-300});
        return norm(end.head(k) - at.head(k)) / size_of;
    };
    auto fail = [&](const std::string& why) {
        out.converged = false;
        out.message = why;
        out.state = x;
        return out;
    };
    long plain_steps = 0;  // of the last plain period
    auto plain_periods = [&](int count) -> std::string {  // "" or why they stopped
        for (int p = 0; p < count; ++p) {
            if (std::string why = options.stop_reason(); !why.empty()) {
                out.stopped = why;
                return "stopped: " + why;
            }
            const ElasticIntegrator::Record r = plain.period(x, 0);
            ++out.periods;
            if (!r.ok) return "the flow failed: " + r.failure;
            plain_steps = r.steps;
            x = r.end;
            plain.settle(x);
        }
        return "";
    };
    if (std::string why = plain_periods(options.warmup_periods); !why.empty()) return fail(why);

    // Newton on P(z) - z with the flow's derivative, in units where velocities are divided by
    // omega; least-squares steps (a contact slipping or open all period conserves its slider's
    // distance from the constraint: a multiplier at 1 without a residual along it).
    Eigen::VectorXd unit = Eigen::VectorXd::Ones(k);
    unit.segment(n, n).setConstant(omega);
    // The period from z with the flow's derivative: the variational equation (up to
    // elastic_variational_max_states), or where that is stiff (more than 20 times a plain
    // period's steps: in 3D a slip next to an opening or a closing, where the slip direction
    // turns as fast as the normal force vanishes) or larger central differences of the period
    // map; after two stiff periods in a row, differences from then on.
    bool differences = false;  // the last derivative was by differences
    int stiff = variational_flow ? 0 : 2;
    // Newton-Krylov: the derivative along v by central differences of the period map (two
    // periods, the perturbed states' modes settled).
    std::string krylov_failure;
    long krylov_periods = 0;
    auto along = [&](const Eigen::VectorXd& z, const Eigen::VectorXd& v, Eigen::VectorXd& derivative) {
        if (std::string why = options.stop_reason(); !why.empty()) {
            out.stopped = why;
            krylov_failure = "stopped: " + why;
            return false;
        }
        const double length = norm(v);
        if (!(length > 0.0)) {
            derivative = Eigen::VectorXd::Zero(k);
            return true;
        }
        const double h = difference_step * std::max(norm(z), 1e-300) / length;
        Eigen::VectorXd plus = z, minus = z;
        plus.head(k) += h * v;
        minus.head(k) -= h * v;
        plain.settle(plus);
        plain.settle(minus);
        const ElasticIntegrator::Record a = plain.period(plus, 0), b = plain.period(minus, 0);
        out.periods += 2;
        krylov_periods += 2;
        if (!a.ok || !b.ok) {
            krylov_failure = "the flow failed in a period of the differences: " + (a.ok ? b.failure : a.failure);
            return false;
        }
        derivative = (a.end.head(k) - b.end.head(k)) / (2.0 * h);
        return true;
    };
    // The monodromy in scaled units (velocities divided by omega) at z, as an operator.
    auto monodromy_at = [&](const Eigen::VectorXd& z) -> Operator {
        return [&, z](const Eigen::VectorXd& u, Eigen::VectorXd& y) {
            Eigen::VectorXd d;
            if (!along(z, unit.cwiseProduct(u), d)) return false;
            y = d.cwiseQuotient(unit);
            return true;
        };
    };
    auto with_derivative = [&](const Eigen::VectorXd& z) {
        if (krylov) {  // the period alone: Newton's steps and the multipliers come from `along`
            ElasticIntegrator::Record r = plain.period(z, 0);
            ++out.periods;
            if (r.ok) plain_steps = r.steps;
            return r;
        }
        if (stiff < 2) {
            ElasticIntegrator::Record r = variational_flow->period(z, 0, std::max<long>(20000, 20 * plain_steps));
            ++out.periods;
            if (r.ok) {
                differences = false;
                stiff = 0;
                return r;
            }
            ++stiff;
        }
        differences = true;
        ElasticIntegrator::Record r = plain.period(z, 0);
        ++out.periods;
        if (!r.ok) return r;
        plain_steps = r.steps;
        r.monodromy.resize(k, k);
        const double size = std::max(norm(z), 1e-300);
        for (int j = 0; j < k; ++j) {
            const double h = difference_step * size * unit(j);
            Eigen::VectorXd plus = z, minus = z;
            plus(j) += h;
            minus(j) -= h;
            plain.settle(plus);  // the modes where the step moves a contact across its cone or gap
            plain.settle(minus);
            const ElasticIntegrator::Record a = plain.period(plus, 0), b = plain.period(minus, 0);
            out.periods += 2;
            if (!a.ok || !b.ok) {
                r.ok = false;
                r.failure = "a period of the differences failed: " + (a.ok ? b.failure : a.failure);
                return r;
            }
            r.monodromy.col(j) = (a.end.head(k) - b.end.head(k)) / (2.0 * h);
        }
        return r;
    };
    ElasticIntegrator::Record at;  // the variational period from x
    bool have = false, converged = false;
    double residual = 0.0;
    int restart = 0;
    std::string how;
    while (!converged) {
        if (std::string why = options.stop_reason(); !why.empty()) {
            out.stopped = why;
            return fail("stopped: " + why);
        }
        if (!have) {
            at = with_derivative(x);
            if (!at.ok) return fail("the flow failed: " + at.failure);
            have = true;
        }
        residual = relative(at.end, x);
        if (residual <= options.tolerance) {
            converged = true;
            how = "converged";
            break;
        }
        if (out.iterations >= options.max_iterations) break;
        ++out.iterations;
        const Eigen::VectorXd rhs = -(at.end.head(k) - x.head(k)).cwiseQuotient(unit);
        Eigen::VectorXd step;
        if (krylov) {  // GMRES on (M - I) u = rhs, M's products by differences at x
            const Operator m = monodromy_at(x);
            const Operator a = [&](const Eigen::VectorXd& u, Eigen::VectorXd& y) {
                if (!m(u, y)) return false;
                y -= u;
                return true;
            };
            Eigen::VectorXd u;
            int steps = 0;
            if (!gmres(a, rhs, detail::newton_forcing, std::min(k, krylov_max_steps), u, steps)) return fail(krylov_failure);
            step = unit.cwiseProduct(u);
        } else {
            const Eigen::MatrixXd matrix = unit.cwiseInverse().asDiagonal() *
                                           (at.monodromy - Eigen::MatrixXd::Identity(k, k)) * unit.asDiagonal();
            // The threshold before the decomposition: the rank it finds decides which
            // Householder factors of Z are formed, and solve() applies those of the rank the
            // threshold gives (set after, a smaller rank applies factors never formed).
            Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> decomposition(matrix.rows(), matrix.cols());
            decomposition.setThreshold(1e-12);
            decomposition.compute(matrix);
            step = unit.cwiseProduct(decomposition.solve(rhs));
        }
        bool moved = false;
        double length = 1.0;
        for (int trial = 0; trial < 5 && !moved; ++trial, length *= 0.5) {
            Eigen::VectorXd z = x;
            z.head(k) += length * step;
            plain.settle(z);
            ElasticIntegrator::Record r = trial == 0 ? with_derivative(z) : plain.period(z, 0);
            if (trial > 0) ++out.periods;
            if (!r.ok || !(relative(r.end, z) < residual)) continue;
            x = z;
            have = trial == 0;
            if (have) at = std::move(r);
            moved = true;
        }
        if (moved) continue;
        if (residual <= newton_floor) {  // the flow's accuracy
            converged = true;
            how = "converged to the flow's accuracy (no Newton step lowers the residual)";
            break;
        }
        if (restart >= options.restarts) break;
        // the contact pattern of the iterate is not the orbit's: plain periods, then Newton again
        const int count = 8 << (2 * restart++);
        if (std::string why = plain_periods(count); !why.empty()) return fail(why);
        have = false;
    }
    out.residual = residual;
    out.converged = converged;
    out.message = converged ? how + " after " + std::to_string(out.iterations) + " Newton iterations (residual " +
                                  format_number(residual) + ")"
                            : "Newton did not converge after " + std::to_string(out.iterations) + " iterations and " +
                                  std::to_string(restart) + " restarts (residual " + format_number(residual) + ")";
    out.state = x;
    if (!have) {  // the multipliers at the final iterate
        at = with_derivative(x);
        if (!at.ok) return fail("the flow failed: " + at.failure);
    }
    if (differences)
        out.message += std::string("; Newton's matrix and the multipliers by central differences of the period map (") +
                       (route == ElasticRoute::differences ? "as asked"
                        : k <= elastic_variational_max_states ? "the variational equation was stiff"
                                                              : "a model beyond the variational equation's size") +
                       "; accuracy about 1e-5)";
    if (krylov) {
        // the dominant multipliers: Arnoldi on the monodromy's products at the orbit, from a
        // fixed start that excites every component
        const Eigen::VectorXd start = detail::arnoldi_start(k);
        double largest = 0.0;
        int unconverged = 0, steps = 0;
        const long newton_periods = krylov_periods;
        if (!dominant_eigenvalues(monodromy_at(x), start, std::min(k, krylov_max_steps), out.multipliers, largest,
                                  unconverged, steps))
            return fail(krylov_failure);
        out.max_multiplier = largest;
        out.stable = largest <= 1.0 + options.stability_tolerance;
        out.multiplier_accuracy = difference_multiplier_accuracy;
        out.message += "; Newton-Krylov (GMRES on central differences of the period map, " +
                       std::to_string(newton_periods) + " periods) and the dominant multipliers by Arnoldi (" +
                       std::to_string(out.multipliers.size()) + " converged to about 1e-5 in " + std::to_string(steps) +
                       " steps" +
                       (unconverged > 0 ? ", " + std::to_string(unconverged) + " of modulus >= " +
                                              format_number(arnoldi_dominant) + " among the " +
                                              std::to_string(arnoldi_count) + " largest not converged: the verdict takes "
                                              "the largest Ritz value, " + format_number(largest)
                                        : std::string()) +
                       ")";
    } else {
        out.multipliers = Eigen::EigenSolver<Eigen::MatrixXd>(at.monodromy, false).eigenvalues();
        out.max_multiplier = out.multipliers.size() > 0 ? out.multipliers.cwiseAbs().maxCoeff() : 0.0;
        out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
        if (differences) out.multiplier_accuracy = difference_multiplier_accuracy;
    }
    detail::exact::note_unresolved_stability(out);

    // the orbit's metrics: one recorded period
    const ElasticIntegrator::Record f = plain.period(x, std::max(16 * flow.samples_per_period, record_samples));
    ++out.periods;
    if (!f.ok) return fail("the flow failed on the recorded period: " + f.failure);
    PeriodicResponse m;
    detail::elastic_metrics(system, omega, f, flow, m);
    out.y_max = m.y_max;
    out.y_amp1 = m.y_amp1;
    out.harmonic1 = m.harmonic1;
    out.output_max = m.output_max;
    out.output_amp1 = m.output_amp1;
    out.stick_fraction = m.stick_fraction;
    out.regime = m.regime;
    out.contacts = m.contacts;
    out.energy = m.energy;
    out.input_energy = m.input_energy;
    out.events = f.events;
    out.switches = f.switches;
    out.stick_margin_min = m.stick_margin_min;
    out.stick_margin_max = m.stick_margin_max;
    out.permanent_stick = std::all_of(f.stuck_time.begin(), f.stuck_time.end(),
                                      [&](double t) { return t >= (1.0 - 1e-12) * 2.0 * M_PI / omega; });
    if (options.samples > 0) {
        const int every = static_cast<int>(f.time.size()) / options.samples;
        out.time = m.time;
        out.displacement = m.displacement;
        out.velocity = m.velocity;
        out.friction_force.resize(options.samples, f.friction_force.cols());
        for (int j = 0; j < options.samples; ++j) out.friction_force.row(j) = f.friction_force.row(j * every);
    }
    return out;
}

Eigen::VectorXd elastic_start_state(const System& system, const Eigen::MatrixXd& displacement,
                                    const Eigen::VectorXd& velocity) {
    const int n = system.dofs(), size = detail::elastic_state_size(system);
    const auto nc = static_cast<Eigen::Index>(system.contacts.size());
    if (displacement.cols() != n || velocity.size() != n || displacement.rows() < 2)
        throw InvalidInput("elastic start: displacement samples " + std::to_string(displacement.rows()) + " x " +
                           std::to_string(displacement.cols()) + " and velocity " + std::to_string(velocity.size()) +
                           ": allowed at least 2 samples of the " + std::to_string(n) + " DOFs");
    Eigen::VectorXd state(size);
    state.head(n) = displacement.row(0).transpose();
    state.segment(n, n) = velocity;
    int at = 2 * n;
    for (Eigen::Index c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        const Eigen::MatrixXd w = system.contact_directions(contact);
        const Eigen::Index d = w.cols() - 1;
        const ElasticContact element = elastic_element(contact);
        const NormalContactCycle cycle = march(element, displacement * w.leftCols(d), displacement * w.col(d));
        state.segment(at, d) = cycle.slider;
        const ContactState first = cycle.state.front();
        state(size - nc + c) = first == ContactState::separated ? 0.0 : first == ContactState::stuck ? 1.0 : 2.0;
        at += static_cast<int>(d);
    }
    return state;
}

}  // namespace hbf
