// hbfriction — exact periodic orbits of rigid unilateral contacts on massless nodes
// (rigid_exact.hpp): Newton shooting on the period map of RigidEngine, and the orbit's metrics.
#include "hbf/rigid_exact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <future>
#include <memory>
#include <optional>
#include <limits>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "event_exact/metrics.hpp"
#include "event_exact/cone_engine.hpp"
#include "event_exact/rigid_engine.hpp"
#include "model/mirror.hpp"
#include "numerics/krylov.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/static_state.hpp"

namespace hbf {

namespace {

using namespace detail::exact;
using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The orbit's metrics from one recorded period [t_s, t_s + T].
template <class E>
void rigid_metrics(E& e, const PatternEngine::Flow& flow, double t_s, const ExactOptions& options,
                   ExactOrbit& out) {
    const System& system = e.system();
    const int N = system.dofs(), nc = e.contacts();
    const double period = e.period();
    const auto& rule = gauss_legendre();
    out.y_max.assign(static_cast<std::size_t>(N), options.dof_maxima ? 0.0 : std::numeric_limits<double>::quiet_NaN());
    out.output_max.assign(options.outputs.size(), 0.0);
    std::vector<double> stick(static_cast<std::size_t>(nc), 0.0), open(stick), energy(stick), normal_mean(stick),
        normal_max(stick), normal_range(stick);
    VectorXd c1 = VectorXd::Zero(N), s1 = VectorXd::Zero(N);
    Maxima maxima;
    for (const Step& st : flow.steps) {
        const double length = st.s_end * st.h;
        if (length <= 0.0) continue;
        const ModeData& m = *st.data;
        if (options.dof_maxima)
            for (int i = 0; i < N; ++i)
                maxima.add(st, st.signal(Eigen::RowVectorXd(m.displacement.row(i))), out.y_max[static_cast<std::size_t>(i)]);
        for (std::size_t o = 0; o < options.outputs.size(); ++o) {
            Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m.displacement.cols());
            for (const auto& [i, c] : options.outputs[o].terms()) row += c * m.displacement.row(i);
            maxima.add(st, st.signal(row), out.output_max[o]);
        }
        // First harmonics by Gauss-Legendre on the polynomial part, the fast part in closed form.
        for (const auto& [node, weight] : rule) {
            const VectorXd z = evaluate(st.u, node * st.s_end);
            const VectorXd y = m.displacement * z;
            c1 += (weight * length * z(e.cos_index())) * y;
            s1 += (weight * length * z(e.sin_index())) * y;
        }
        if (st.fast()) {
            const std::complex<double> phase(st.u(e.cos_index(), 0), st.u(e.sin_index(), 0));
            const Eigen::VectorXcd turned =
                m.displacement.cast<std::complex<double>>() * (phase * st.fast_integral(std::complex<double>(0.0, e.omega())));
            c1 += turned.real();
            s1 += turned.imag();
        }
        // The contacts: times of each pattern, normal force, friction work lambda_T q_T' (on the
        // full state, the fast part included, at Gauss-Legendre nodes of two halves).
        for (int c = 0; c < nc; ++c) {
            const int mode = st.modes[static_cast<std::size_t>(c)];
            if (mode == rigid_open) {
                open[static_cast<std::size_t>(c)] += length;
                continue;
            }
            if (mode == rigid_stuck) stick[static_cast<std::size_t>(c)] += length;
            const Eigen::RowVectorXd normal = m.lambda.row(e.normal(c));
            maxima.add(st, st.signal(normal), normal_max[static_cast<std::size_t>(c)]);
            for (int half = 0; half < 2; ++half)
                for (const auto& [node, weight] : rule) {
                    const double s = st.s_end * 0.5 * (half + node);
                    const VectorXd z = st.state(s);
                    normal_mean[static_cast<std::size_t>(c)] += 0.5 * weight * length * normal.dot(z);
                    if (mode != rigid_stuck) {
                        const VectorXd rate = st.rate(s);
                        for (int j = 0; j < e.directions(c); ++j)
                            energy[static_cast<std::size_t>(c)] += 0.5 * weight * length *
                                                                   m.lambda.row(e.tangential(c) + j).dot(z) *
                                                                   m.relative.row(e.tangential(c) + j).dot(rate);
                    }
                }
        }
    }
    maxima.finish();
    // The normal force's range: max lambda_N - min lambda_N, the minimum as the maximum of
    // (max - lambda_N) >= 0 over the period (0 where the contact opens).
    Maxima ranges;
    for (const Step& st : flow.steps) {
        if (st.s_end * st.h <= 0.0) continue;
        for (int c = 0; c < nc; ++c) {
            Eigen::RowVectorXd row = -st.data->lambda.row(e.normal(c));
            if (st.modes[static_cast<std::size_t>(c)] == rigid_open) row.setZero();
            row(e.one_index()) += normal_max[static_cast<std::size_t>(c)];
            ranges.add(st, st.signal(row), normal_range[static_cast<std::size_t>(c)]);
        }
    }
    ranges.finish();
    c1 *= 2.0 / period;
    s1 *= 2.0 / period;
    out.harmonic1 = c1.cast<std::complex<double>>() - std::complex<double>(0.0, 1.0) * s1.cast<std::complex<double>>();
    out.y_amp1.resize(static_cast<std::size_t>(N));
    for (int i = 0; i < N; ++i) out.y_amp1[static_cast<std::size_t>(i)] = std::hypot(c1(i), s1(i));
    out.output_amp1.clear();
    for (const Output& o : options.outputs) out.output_amp1.push_back(std::hypot(o.of(c1), o.of(s1)));
    out.input_energy = system.excitation.size() ? pi * system.excitation.dot(s1) : 0.0;
    out.contacts.clear();
    out.energy = 0.0;
    for (int c = 0; c < nc; ++c) {
        const auto k = static_cast<std::size_t>(c);
        ContactRegime r = contact_regime(stick[k], period);
        r.separated_fraction = open[k] / period;
        r.normal_mean = normal_mean[k] / period;
        r.normal_amplitude = 0.5 * normal_range[k];
        r.energy = energy[k];
        out.energy += energy[k];
        out.contacts.push_back(r);
    }
    out.stick_fraction = nc > 0 ? out.contacts.front().stick_fraction : 0.0;
    out.regime = nc > 0 ? out.contacts.front().regime : "none";
    // Contact 1's stick indicator (time_integration.hpp's): |lambda_T| / (mu lambda_N) - 1 while
    // stuck, 0 slipping, 1 open; on 64 points a step and at its ends.
    out.stick_margin_min = out.stick_margin_max = 0.0;
    if (nc > 0) {
        const double mu = system.contacts.front().values.at("friction_coefficient");
        double low = std::numeric_limits<double>::infinity(), high = -low;
        for (const Step& st : flow.steps) {
            if (st.s_end * st.h <= 0.0) continue;
            const int mode = st.modes.front();
            if (mode != rigid_stuck) {
                const double margin = mode == rigid_open ? 1.0 : 0.0;
                low = std::min(low, margin);
                high = std::max(high, margin);
                continue;
            }
            const ModeData& m = *st.data;
            for (int k = 0; k <= 64; ++k) {
                const VectorXd z = st.state(st.s_end * k / 64.0);
                const double normal = m.lambda.row(e.normal(0)).dot(z);
                double tangential = 0.0;
                for (int j = 0; j < e.directions(0); ++j) tangential += std::pow(m.lambda.row(e.tangential(0) + j).dot(z), 2);
                const double margin = mu * normal > 0.0 ? std::sqrt(tangential) / (mu * normal) - 1.0 : -1.0;
                low = std::min(low, margin);
                high = std::max(high, margin);
            }
        }
        if (std::isfinite(low)) {
            out.stick_margin_min = low;
            out.stick_margin_max = high;
        }
    }
    period_events(flow.events, period, out);
    auto dof_state_at = [&](double t) {
        const double tt = t < t_s ? t + period : t;
        const Step& st = step_at(flow.steps, tt);
        const double s = std::min(std::max((tt - st.t0) / st.h, 0.0), st.s_end);
        VectorXd x(2 * N);
        x.head(N) = st.data->displacement * st.state(s);
        x.tail(N) = st.data->displacement * st.rate(s);
        return x;
    };
    out.state = dof_state_at(t_s > 0.0 ? period : 0.0);
    if (options.samples > 0) {
        out.time.resize(options.samples);
        out.displacement.resize(options.samples, N);
        out.velocity.resize(options.samples, N);
        out.friction_force.resize(options.samples, nc);
        for (int j = 0; j < options.samples; ++j) {
            const double t = period * j / options.samples;
            const VectorXd x = dof_state_at(t);
            out.time(j) = t;
            out.displacement.row(j) = x.head(N).transpose();
            out.velocity.row(j) = x.tail(N).transpose();
            const double tt = t < t_s ? t + period : t;
            const Step& st = step_at(flow.steps, tt);
            const VectorXd z = st.state(std::min(std::max((tt - st.t0) / st.h, 0.0), st.s_end));
            for (int c = 0; c < nc; ++c) out.friction_force(j, c) = st.data->lambda.row(e.tangential(c)).dot(z);
        }
    }
}

/// Newton's residual below which a stall (no step lowers it) is the rounding of the flow.
constexpr double stall_floor = 1e-9;

/// ConeEngine, before the last restart: Newton on all the unknowns whose residual (above
/// creep_floor) has not fallen by creep_factor over creep_window iterations has a derivative that is off (events of coupled
/// contacts at one instant) and stops: plain periods from its last iterate and a new section (a
/// restart) cost less than creeping on, or GMRES on differences (tens of periods a step). The
/// last attempt goes on, and turns to GMRES where a step with a fresh derivative fails.
constexpr int creep_window = 8;
constexpr double creep_factor = 0.1;
/// Below it Newton is near the orbit and goes on: the last digits fall slowly where the flow's
/// rounding is near (a restart there would throw a nearly converged orbit away).
constexpr double creep_floor = 1e-6;

/// The message's note where a perturbed period has events the orbit lacks.
constexpr const char* grazing_note =
    "; a contact grazes an edge of its friction cone or its gap (a perturbation of 1e-6 adds events there): the "
    "multipliers are those of the orbit's own events";

/// The message of an orbit held where its start holds the nodes (permanent stick's convention).
constexpr const char* permanent_stick_note =
    "permanent stick: the contacts held where the start holds them (convention for the undetermined held position)";

/// Whether every contact is stuck over the whole recorded period.
bool permanently_stuck(const PatternEngine::Flow& flow) {
    if (!flow.events.empty()) return false;
    for (const Step& st : flow.steps)
        for (int mode : st.modes)
            if (mode != rigid_stuck) return false;
    return true;
}

/// Permanent stick is degenerate: any held position of the nodes that keeps them within
/// their friction cones gives a periodic orbit (the same oscillation about another mean).
/// Convention: the nodes held where the start holds them (`where`: the tangential
/// displacements of the caller's start, or of the static state for a start at rest), when the
/// orbit about that position still sticks throughout; x (y, y', the held positions) and the
/// recorded period `last` are then replaced. Otherwise the orbit stays as found (the warm-up
/// period and Newton moved the nodes: they slipped on the way).
template <class E, class Map, class Derivative>
void hold_where_started(E& e, const VectorXd& where, VectorXd& x, PatternEngine::Flow& last, const Map& map,
                        const Derivative& derivative, const ExactOptions& options, ExactOrbit& out) {
    const int nm = e.dofs();
    VectorXd held = x;
    held.tail(where.size()) = where;
    // The stuck structure is linear: Newton on y, y' converges in one step (two for rounding).
    PatternEngine::Flow f;
    for (int iteration = 0; iteration < 3; ++iteration) {
        f = map(held, iteration == 2);
        if (!f.ok || !permanently_stuck(f)) return;
        const VectorXd r = f.zhat.head(2 * nm) - held.head(2 * nm);
        const MatrixXd jacobian =
            MatrixXd(derivative(held, f).topLeftCorner(2 * nm, 2 * nm)) - MatrixXd::Identity(2 * nm, 2 * nm);
        if (iteration < 2) held.head(2 * nm) -= jacobian.partialPivLu().solve(r);
    }
    SectionNorm norm{nm, e.omega(), 0.0};
    if (!(norm.relative_change(f.zhat.head(2 * nm), held.head(2 * nm)) <= std::max(options.tolerance, stall_floor))) return;
    x = held;
    last = std::move(f);
    out.permanent_stick = true;
    out.message = permanent_stick_note;
}

/// Plain periods at most that a start holding every contact stuck may take to shake down (its
/// nodes slip at the new frequency and settle at new held positions) before the stuck
/// structure's orbit is solved about where they settled.
constexpr int max_shakedown_periods = 30;

/// Whether a period's events are those of a shakedown: contacts that slip once, each a single
/// slip phase in it (at most 3 events: one that starts or ends at its ends), and none opens. A
/// contact that slips twice (4 events: both ways, as a node in stick-slip must to come back)
/// or opens is on an orbit that slips or lifts off: no stuck orbit is near.
bool ratchets(const ConeEngine& e, const PatternEngine::Flow& plain) {
    std::vector<int> count(static_cast<std::size_t>(e.contacts()), 0);
    for (const ExactEvent& event : plain.events) {
        if (event.mode_after == rigid_open || ++count[static_cast<std::size_t>(event.contact)] > 3) return false;
    }
    return true;
}

/// ConeEngine, every contact stuck: the rates of y, y' are affine in the state, y'' = A (y, y')
/// + g cos(w t) + h sin(w t) + r0 (r0: the held positions' and the preload's share), so the orbit
/// about zhat's held positions is the stuck structure's forced response, solved in the frequency
/// domain: (y, y')(0) = -A^-1 r0 + Re((i w - A)^-1 (g - i h)). Its multipliers are exp(lambda T)
/// of A's eigenvalues and 1 for each held position (the family). zhat (at t = 0) gets that state.
void stuck_orbit_state(ConeEngine& e, VectorXd& zhat, const Modes& modes, Eigen::VectorXcd& multipliers) {
    const int nm = e.dofs();
    const std::vector<int> dyn = e.moving_entries(modes, {});
    MatrixXd A;
    VectorXd rate;
    e.rates_jacobian(zhat, modes, {}, dyn, A, rate);
    auto rates_at = [&](double c, double s) {
        VectorXd z = zhat;
        z.head(2 * nm).setZero();
        z(e.cos_index()) = c;
        z(e.sin_index()) = s;
        return VectorXd(e.series(z, modes, 0.0, 1).col(1).head(2 * nm));
    };
    const VectorXd r0 = rates_at(0.0, 0.0), g = rates_at(1.0, 0.0) - r0, h = rates_at(0.0, 1.0) - r0;
    const std::complex<double> i(0.0, 1.0);
    const Eigen::MatrixXcd shifted = i * e.omega() * Eigen::MatrixXcd::Identity(2 * nm, 2 * nm) - A.cast<std::complex<double>>();
    const Eigen::VectorXcd response = shifted.partialPivLu().solve(g.cast<std::complex<double>>() - i * h);
    zhat.head(2 * nm) = -A.partialPivLu().solve(r0) + response.real();
    zhat(e.cos_index()) = 1.0;
    zhat(e.sin_index()) = 0.0;
    e.make_consistent(zhat, modes, 0.0);
    const Eigen::VectorXcd lambda = balanced_eigenvalues(A);  // A's entries spread by w^2: balanced
    multipliers = Eigen::VectorXcd::Ones(2 * nm + e.tangential_entries());
    for (int k = 0; k < 2 * nm; ++k) multipliers(k) = std::exp(lambda(k) * e.period());
}

/// A start that holds every contact stuck (the orbit before it in a sweep, an FRF point's state;
/// not rest, whose first period is the preload's and the force's transient):
/// first the stuck structure's orbit about where the start holds the nodes, the convention of
/// hold_where_started, without the warm-up, the section's choice and Newton on the held
/// positions. The first, plain period from the start says whether its nodes stay stuck at the
/// new frequency. RigidEngine: then Newton on y, y' from one period with its derivative (the
/// stuck structure is linear: the derivative is the same at every state), which lands in one
/// step, a second for rounding. ConeEngine: the orbit in closed form (stuck_orbit_state); where
/// nodes slip in the first period, plain periods while they ratchet (ratchets) until one keeps
/// every node stuck (a shakedown, at most max_shakedown_periods), then the orbit about where
/// they settled. Each checked by a recorded period. False where that fails (the general solve
/// then takes over).
template <class E, class Flow>
bool held_start_orbit(E& e, VectorXd zhat, Modes modes, const VectorXd& where, const Flow& flow,
                      const ExactOptions& options, ExactOrbit& out) {
    if (std::any_of(modes.begin(), modes.end(), [](int m) { return m != rigid_stuck; })) return false;
    const int nm = e.dofs();
    const auto held = static_cast<Eigen::Index>(where.size()), nu = 2 * nm + held;
    zhat.segment(2 * nm, held) = where;
    zhat(e.cos_index()) = 1.0;
    zhat(e.sin_index()) = 0.0;
    e.make_consistent(zhat, modes, 0.0);
    // a plain period first: where the start's nodes slip, that is all this costs (a period with
    // the derivative costs many plain ones)
    PatternEngine::Flow plain = flow(zhat, modes, 0.0, e.period(), false, false, options.max_events_per_period);
    ++out.periods;
    SectionNorm norm{nm, e.omega(), 0.0};
    PatternEngine::Flow last;
    if constexpr (std::is_same_v<E, ConeEngine>) {
        norm.reference = norm.size(zhat.head(nu));
        bool tried = false;  // the orbit about the current held positions tried (and slipped)
        int shaken = 0;
        for (;; ++shaken) {
            if (!plain.ok) return false;
            if (!permanently_stuck(plain)) {
                if (!ratchets(e, plain)) return false;
                tried = false;
            } else if (!tried) {
                VectorXd z = zhat;
                stuck_orbit_state(e, z, modes, out.multipliers);
                last = flow(z, modes, 0.0, e.period(), false, true, options.max_events_per_period);
                ++out.periods;
                if (last.ok && permanently_stuck(last)) {
                    zhat = z;
                    break;
                }
                tried = true;
            }
            if (shaken == max_shakedown_periods) return false;
            zhat = plain.zhat;
            modes = plain.modes;
            zhat(e.cos_index()) = 1.0;
            zhat(e.sin_index()) = 0.0;
            plain = flow(zhat, modes, 0.0, e.period(), false, false, options.max_events_per_period);
            ++out.periods;
        }
        out.residual = norm.relative_change(last.zhat.head(nu), zhat.head(nu));
        out.iterations = 0;
        if (shaken > 0)
            out.message = "permanent stick: the contacts held where " + std::to_string(shaken) +
                          " periods of the start's shakedown left them (convention for the undetermined held position)";
    } else {
        if (!plain.ok || !permanently_stuck(plain)) return false;
        const PatternEngine::Flow f = flow(zhat, modes, 0.0, e.period(), true, false, options.max_events_per_period);
        ++out.periods;
        if (!f.ok || f.psi.size() == 0) return false;
        const MatrixXd d = f.psi.topLeftCorner(nu, nu);
        const MatrixXd jacobian = MatrixXd(d.topLeftCorner(2 * nm, 2 * nm)) - MatrixXd::Identity(2 * nm, 2 * nm);
        const Eigen::PartialPivLU<MatrixXd> lu(jacobian);
        norm.reference = norm.size(zhat.head(nu));
        VectorXd end = f.zhat;
        for (int step = 1; step <= 2; ++step) {
            zhat.head(2 * nm) -= lu.solve(end.head(2 * nm) - zhat.head(2 * nm));
            e.make_consistent(zhat, modes, 0.0);
            last = flow(zhat, modes, 0.0, e.period(), false, true, options.max_events_per_period);
            ++out.periods;
            if (!last.ok || !permanently_stuck(last)) return false;
            end = last.zhat;
            out.iterations = step;
            out.residual = norm.relative_change(end.head(nu), zhat.head(nu));
            if (out.residual <= options.tolerance) break;
        }
        out.multipliers = balanced_eigenvalues(d);
    }
    if (!(out.residual <= std::max(options.tolerance, stall_floor))) return false;
    out.converged = true;
    out.permanent_stick = true;
    if (out.message.empty()) out.message = permanent_stick_note;
    rigid_metrics(e, last, 0.0, options, out);
    out.max_multiplier = out.multipliers.cwiseAbs().maxCoeff();
    out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
    if constexpr (std::is_same_v<E, ConeEngine>) {
        // The kink check of the general solve: a perturbation of 1e-6 of y, y' along a fixed
        // direction that adds events (a node whose force touches its cone's edge at an instant).
        VectorXd direction(2 * nm);
        for (int k = 0; k < 2 * nm; ++k)
            direction(k) = std::sin(1.0 + 2.0 * static_cast<double>(k)) * norm.reference * (k >= nm ? e.omega() : 1.0);
        for (const double sign : {1.0, -1.0}) {
            VectorXd z = zhat;
            z.head(2 * nm) += sign * 1e-6 * direction;
            e.make_consistent(z, modes, 0.0);
            const PatternEngine::Flow g = flow(z, modes, 0.0, e.period(), false, false, options.max_events_per_period);
            ++out.periods;
            if (!g.ok || !g.events.empty()) {
                out.message += grazing_note;
                break;
            }
        }
    }
    return true;
}

}  // namespace

MatrixXd detail::exact::end_derivative(ConeEngine& e, const PatternEngine::Flow& f, const std::vector<Eigen::Index>& unknowns) {
    const auto nu = static_cast<Eigen::Index>(unknowns.size());
    const std::vector<int> ends = e.independent(f.modes);
    MatrixXd d(nu, nu);
    MatrixXd relative;  // d q / d x at the end
    for (Eigen::Index k = 0; k < nu; ++k) {
        const auto i = static_cast<int>(unknowns[static_cast<std::size_t>(k)]);
        if (std::find(ends.begin(), ends.end(), i) != ends.end()) {
            for (Eigen::Index l = 0; l < nu; ++l) d(k, l) = f.psi(i, unknowns[static_cast<std::size_t>(l)]);
            continue;
        }
        if (i >= e.theta(0)) {
            d.row(k).setZero();
            continue;
        }
        if (relative.size() == 0) {
            MatrixXd J, from(static_cast<Eigen::Index>(ends.size()), nu);
            VectorXd rate;
            ConeEngine::ContactDerivatives D;
            e.rates_jacobian(f.zhat, f.modes, {}, e.moving_entries(f.modes, {}), ends, J, rate, &D);
            for (std::size_t r = 0; r < ends.size(); ++r)
                for (Eigen::Index l = 0; l < nu; ++l)
                    from(static_cast<Eigen::Index>(r), l) = f.psi(ends[r], unknowns[static_cast<std::size_t>(l)]);
            relative = D.drelative * from;
        }
        const int q = e.slider_contact(i);
        d.row(k) = relative.row(e.tangential(q) + (i - e.slider(q)));
    }
    if (!d.allFinite()) throw std::runtime_error("the flow's derivative is not finite");
    return d;
}

namespace {

/// Candidate sections: the middles of the event-free stretches of a period at least a quarter
/// as long as the longest, as (length, time) in time order.
std::vector<std::pair<double, double>> section_times(const std::vector<ExactEvent>& events, double period) {
    if (events.empty()) return {{period, 0.0}};
    std::vector<double> times;
    for (const ExactEvent& ev : events) times.push_back(std::fmod(ev.time, period));
    std::sort(times.begin(), times.end());
    std::vector<std::pair<double, double>> stretches;  // (length, middle)
    double longest = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
        const double next = k + 1 < times.size() ? times[k + 1] : times.front() + period;
        stretches.emplace_back(next - times[k], std::fmod(times[k] + 0.5 * (next - times[k]), period));
        longest = std::max(longest, next - times[k]);
    }
    std::vector<std::pair<double, double>> out;
    for (const auto& stretch : stretches)
        if (stretch.first >= 0.25 * longest) out.push_back(stretch);
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    return out;
}

}  // namespace

bool rigid_contacts_only(const System& system) {
    return !system.contacts.empty() && std::all_of(system.contacts.begin(), system.contacts.end(), [](const Contact& c) {
               return contact_law(c.law).time_integrator() == TimeIntegrator::unilateral_contacts;
           });
}

bool rigid_contacts_3d(const System& system) {
    return rigid_contacts_only(system) &&
           std::any_of(system.contacts.begin(), system.contacts.end(),
                       [](const Contact& c) { return c.lists.count("second_direction") != 0; });
}

std::string mirror_symmetric_refusal(const System& system) {
    if (!rigid_contacts_3d(system))
        return "mirror-symmetric orbits apply to law unilateral's 3D contacts (a normal and two tangential directions each)";
    if (!detail::find_mirror(system))
        return "the structure has no mirror symmetry (a reflection of its DOFs that leaves M, C, K, the loads and the "
               "contacts unchanged, to 1e-10 of each)";
    return {};
}

namespace {

/// Whether a contact has two tangential directions (3D): the cone engine's systems.
bool cones(const System& system) { return rigid_contacts_3d(system); }

}  // namespace

std::string rigid_solver_refusal(const System& system) {
    try {
        system.validate();
        refuse_cyclic(system, "the exact solver of law unilateral");
        if (system.contacts.size() > static_cast<std::size_t>(rigid_solver_max_contacts))
            return "the model has " + std::to_string(system.contacts.size()) +
                   " contacts: the exact solver of law unilateral allows at most " +
                   std::to_string(rigid_solver_max_contacts) +
                   " (each step solves their equations with a dense LU, whose cost grows as their cube)";
        const int dofs = cones(system) ? ConeEngine(system, 1.0).dofs() : RigidEngine(system, 1.0).dofs();
        if (dofs > exact_solver_max_dofs)
            return "the model has " + std::to_string(dofs) + " DOFs with mass: the exact solver allows at most " +
                   std::to_string(exact_solver_max_dofs) + " (a reduction first)";
    } catch (const InvalidInput& error) {
        return error.what();
    }
    return {};
}

namespace {

/// The flow's derivative (3D) is checked against a central difference of the period map along
/// one direction: a mismatch above this share means the events it passed were not smooth.
constexpr double derivative_check_tolerance = 1e-3;

/// Arnoldi's multipliers converge to this residual (relative to max(1, |mu|)): the period map's
/// central differences (steps of 1e-6) are accurate to about 1e-9, and a family of orbits (nodes
/// stuck all period) has multipliers at 1 that a looser residual would put a few 1e-6 outside
/// the unit circle (unstable by ExactOptions::stability_tolerance).
constexpr double multiplier_tolerance = 1e-8;

/// A converged orbit is taken as mirror-symmetric (its multipliers split by the mirror) where its
/// unknowns are their mirror images' to this, in the differences' units (1e-6 of it is their step).
constexpr double mirror_split_tolerance = 1e-8;
/// The split's check: an antisymmetric change's central difference has a symmetric part of at most
/// this share of the change (the derivative's commutation with the mirror, seen to the differences'
/// accuracy); above it, the multipliers are Arnoldi's on all the free unknowns.
constexpr double mirror_leak_tolerance = 1e-6;

/// Newton's iterations at most with the nodes stuck all period held (shoot's predictor).
constexpr int held_newton_iterations = 12;
/// Held rounds at most after the first (each: a plain period that drags the held nodes that slip
/// to their cones' edges, then Newton with them held there).
constexpr int max_held_rounds = 4;
/// A held round's residual before the check that its nodes stay inside their cones (the last
/// round, where none slips, goes on to the solve's tolerance).
constexpr double held_round_tolerance = 1e-8;

/// The contacts stuck at the section (`modes`) that have no event in the plain period f: stuck
/// all of it. None where f has no events (permanent stick: hold_where_started's convention) or
/// is not a period.
std::vector<char> stuck_all_period(const ConeEngine& e, const PatternEngine::Flow& f, const Modes& modes) {
    if (f.zhat.size() == 0 || !f.ok || f.events.empty()) return {};
    std::vector<char> held(static_cast<std::size_t>(e.contacts()), 0);
    for (int c = 0; c < e.contacts(); ++c) held[static_cast<std::size_t>(c)] = modes[static_cast<std::size_t>(c)] == rigid_stuck;
    for (const ExactEvent& event : f.events) held[static_cast<std::size_t>(event.contact)] = 0;
    return held;
}

/// A mirror symmetry of the structure (model/mirror.hpp) on the ConeEngine's state zhat: each
/// entry's image and sign (y, y', the held positions: (P z)[image[i]] = sign[i] z[i]), and the slip
/// directions, which map as angles: the image contact's is atan2(s_2 sin theta, s_1 cos theta)
/// (s_k: the signs its tangential directions take), of derivative s_1 s_2. The forcing's entries
/// are their own images (the load is symmetric).
struct StateMirror {
    std::vector<int> image;      ///< per entry of zhat (its n_z first)
    std::vector<double> sign;
    std::vector<int> angle_of;   ///< per entry: the contact whose direction it is, or -1
    std::vector<std::array<double, 2>> turn;  ///< per contact: (s_1, s_2) of its tangential directions
    std::vector<int> contact_image;           ///< per contact
    bool valid() const { return !image.empty(); }
    /// theta of contact c seen from its image contact.
    double angle(int c, double theta) const {
        const auto& s = turn[static_cast<std::size_t>(c)];
        return std::atan2(s[1] * std::sin(theta), s[0] * std::cos(theta));
    }
};

/// The mean of two angles (of their unit vectors), near the first.
double mean_angle(double own, double seen) {
    const double mean = std::atan2(std::sin(own) + std::sin(seen), std::cos(own) + std::cos(seen));
    return own + std::remainder(mean - own, 2.0 * pi);
}

StateMirror state_mirror(const detail::Mirror& m, const ConeEngine& e) {
    StateMirror out;
    const detail::MasslessContacts& split = e.split();
    const int nm = e.dofs();
    out.image.resize(static_cast<std::size_t>(e.nz()));
    for (std::size_t i = 0; i < out.image.size(); ++i) out.image[i] = static_cast<int>(i);
    out.sign.assign(static_cast<std::size_t>(e.nz()), 1.0);
    out.angle_of.assign(static_cast<std::size_t>(e.nz()), -1);
    for (int k = 0; k < nm; ++k) {
        const int dof = split.massive[static_cast<std::size_t>(k)];
        const auto at = std::find(split.massive.begin(), split.massive.end(), m.image[static_cast<std::size_t>(dof)]);
        if (at == split.massive.end()) return {};
        const int image = static_cast<int>(at - split.massive.begin());
        for (const int shift : {0, nm}) {
            out.image[static_cast<std::size_t>(k + shift)] = image + shift;
            out.sign[static_cast<std::size_t>(k + shift)] = m.sign[static_cast<std::size_t>(dof)];
        }
    }
    out.turn.assign(static_cast<std::size_t>(e.contacts()), {1.0, 1.0});
    out.contact_image = m.contact_image;
    for (int c = 0; c < e.contacts(); ++c) {
        const int image = m.contact_image[static_cast<std::size_t>(c)];
        const std::vector<double>& signs = m.direction_sign[static_cast<std::size_t>(c)];
        if (e.directions(image) != e.directions(c) || static_cast<int>(signs.size()) < e.directions(c)) return {};
        for (int j = 0; j < e.directions(c); ++j) {
            out.image[static_cast<std::size_t>(e.slider(c) + j)] = e.slider(image) + j;
            out.sign[static_cast<std::size_t>(e.slider(c) + j)] = signs[static_cast<std::size_t>(j)];
        }
        if (e.directions(c) == 2) out.turn[static_cast<std::size_t>(c)] = {signs[0], signs[1]};
        out.image[static_cast<std::size_t>(e.theta(c))] = e.theta(image);
        out.sign[static_cast<std::size_t>(e.theta(c))] = e.directions(c) == 2 ? signs[0] * signs[1] : 1.0;
        out.angle_of[static_cast<std::size_t>(e.theta(c))] = c;
    }
    return out;
}

/// The symmetric state nearest z's pair by pair: (z + P z) / 2 on y, y' and the held positions,
/// each slip direction the mean of its own and its image's seen from it (their unit vectors'
/// mean, near its own value). Every entry of zhat's first n_z.
VectorXd symmetric_state(const StateMirror& q, const VectorXd& z) {
    VectorXd out = z;
    for (std::size_t i = 0; i < q.image.size(); ++i) {
        const auto k = static_cast<Eigen::Index>(i);
        const int image = q.image[i];
        out(k) = q.angle_of[i] < 0 ? 0.5 * (z(k) + q.sign[i] * z(image)) : mean_angle(z(k), q.angle(q.angle_of[i], z(image)));
    }
    return out;
}

/// How far z's y, y' (over omega) and held positions are from their mirror images, relative to
/// their largest entry; infinity where the patterns `modes` are not the mirror's image of
/// themselves (a contact and its image in different patterns).
double section_mirror_offset(const StateMirror& q, const ConeEngine& e, const VectorXd& z, const Modes& modes, double omega) {
    for (int c = 0; c < e.contacts(); ++c)
        if (modes[static_cast<std::size_t>(c)] != modes[static_cast<std::size_t>(q.contact_image[static_cast<std::size_t>(c)])])
            return std::numeric_limits<double>::infinity();
    double offset = 0.0, size = 0.0;
    for (int i = 0; i < e.theta(0); ++i) {
        const double unit = i >= e.dofs() && i < 2 * e.dofs() ? 1.0 / omega : 1.0;
        offset = std::max(offset, unit * std::abs(z(i) - q.sign[static_cast<std::size_t>(i)] * z(q.image[static_cast<std::size_t>(i)])));
        size = std::max(size, unit * std::abs(z(i)));
    }
    return size > 0.0 ? offset / size : offset;
}

/// The mirror on Newton's unknowns (entries `unknowns` of zhat): each one's image among them and
/// its sign (an angle's: the derivative of its map). Empty where an unknown's image is not one
/// (the section's patterns not symmetric).
struct UnknownMirror {
    std::vector<Eigen::Index> image, zhat;  ///< per unknown: its image, and its entry of zhat
    VectorXd sign;
    const StateMirror* state_mirror = nullptr;
    bool valid() const { return !image.empty(); }
    /// The symmetric unknowns nearest x (symmetric_state's rule).
    VectorXd state(const VectorXd& x) const {
        VectorXd out(x.size());
        for (Eigen::Index k = 0; k < x.size(); ++k) {
            const Eigen::Index other = image[static_cast<std::size_t>(k)];
            const int c = state_mirror->angle_of[static_cast<std::size_t>(zhat[static_cast<std::size_t>(k)])];
            out(k) = c < 0 ? 0.5 * (x(k) + sign(k) * x(other)) : mean_angle(x(k), state_mirror->angle(c, x(other)));
        }
        return out;
    }
    /// (v + Q v) / 2 for a change of the unknowns (linear: an angle's by its sign).
    VectorXd symmetric(const VectorXd& v) const {
        VectorXd out(v.size());
        for (Eigen::Index k = 0; k < v.size(); ++k)
            out(k) = 0.5 * (v(k) + sign(k) * v(image[static_cast<std::size_t>(k)]));
        return out;
    }
    /// (D + Q D Q) / 2: the derivative's part that commutes with the mirror.
    MatrixXd symmetric(const MatrixXd& d) const {
        MatrixXd out(d.rows(), d.cols());
        for (Eigen::Index k = 0; k < d.rows(); ++k)
            for (Eigen::Index l = 0; l < d.cols(); ++l)
                out(k, l) = 0.5 * (d(k, l) + sign(k) * sign(l) *
                                                 d(image[static_cast<std::size_t>(k)], image[static_cast<std::size_t>(l)]));
        return out;
    }
};

UnknownMirror unknown_mirror(const StateMirror& q, const std::vector<Eigen::Index>& unknowns) {
    UnknownMirror out;
    out.state_mirror = &q;
    const auto nu = static_cast<Eigen::Index>(unknowns.size());
    out.sign.resize(nu);
    for (Eigen::Index k = 0; k < nu; ++k) {
        const Eigen::Index i = unknowns[static_cast<std::size_t>(k)];
        const int image = q.image[static_cast<std::size_t>(i)];
        const auto at = std::find(unknowns.begin(), unknowns.end(), static_cast<Eigen::Index>(image));
        if (at == unknowns.end()) return {};
        out.image.push_back(at - unknowns.begin());
        out.zhat.push_back(i);
        out.sign(k) = q.sign[static_cast<std::size_t>(i)];
    }
    return out;
}

/// How far unknowns x are from their mirror images (q), in the units `scale` (angles in
/// radians, modulo a turn).
double unknowns_mirror_offset(const UnknownMirror& q, const VectorXd& x, const VectorXd& scale) {
    double offset = 0.0;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
        const Eigen::Index other = q.image[static_cast<std::size_t>(k)];
        const int c = q.state_mirror->angle_of[static_cast<std::size_t>(q.zhat[static_cast<std::size_t>(k)])];
        const double gap = c < 0 ? x(k) - q.sign(k) * x(other) : std::remainder(x(k) - q.state_mirror->angle(c, x(other)), 2.0 * pi);
        offset = std::max(offset, std::abs(gap) / scale(k));
    }
    return offset;
}

/// A mirror-symmetric orbit's changes split by the mirror (q, an involution: its period map's
/// derivative commutes with it): orthonormal bases, in the coordinates of the unknowns `free`
/// (indices into q's), of the symmetric changes (Q v = v) and the antisymmetric ones (Q v = -v).
/// Each pair of images gives one of each, an unknown that is its own image one of either. Both
/// empty where an image of a free unknown is not free.
struct MirrorSplit {
    MatrixXd symmetric, antisymmetric;
    bool valid() const { return symmetric.cols() + antisymmetric.cols() > 0; }
};

MirrorSplit mirror_split(const UnknownMirror& q, const std::vector<Eigen::Index>& free) {
    const auto nf = static_cast<Eigen::Index>(free.size());
    std::vector<VectorXd> even, odd;
    for (Eigen::Index i = 0; i < nf; ++i) {
        const Eigen::Index k = free[static_cast<std::size_t>(i)], image = q.image[static_cast<std::size_t>(k)];
        const auto at = std::find(free.begin(), free.end(), image);
        if (at == free.end()) return {};
        const auto j = static_cast<Eigen::Index>(at - free.begin());
        if (j < i) continue;
        if (j == i) {
            (q.sign(k) > 0.0 ? even : odd).push_back(VectorXd::Unit(nf, i));
            continue;
        }
        VectorXd plus = VectorXd::Zero(nf), minus = VectorXd::Zero(nf);
        plus(i) = minus(i) = std::sqrt(0.5);
        plus(j) = q.sign(k) * std::sqrt(0.5);
        minus(j) = -q.sign(k) * std::sqrt(0.5);
        even.push_back(plus);
        odd.push_back(minus);
    }
    MirrorSplit out;
    out.symmetric.resize(nf, static_cast<Eigen::Index>(even.size()));
    out.antisymmetric.resize(nf, static_cast<Eigen::Index>(odd.size()));
    for (std::size_t c = 0; c < even.size(); ++c) out.symmetric.col(static_cast<Eigen::Index>(c)) = even[c];
    for (std::size_t c = 0; c < odd.size(); ++c) out.antisymmetric.col(static_cast<Eigen::Index>(c)) = odd[c];
    return out;
}

/// Newton shooting on the period map of engine e (RigidEngine: linear patterns, the exact
/// monodromy; ConeEngine: Taylor flows, the period map's derivative by central differences).
template <class E>
ExactOrbit shoot(E& e, const System& system, double omega, const VectorXd& initial_state, const ExactOptions& options,
                 ConeNewton newton = ConeNewton::automatic) {
    constexpr bool exact_monodromy = std::is_same_v<E, RigidEngine>;
    const int N = system.dofs();
    const detail::MasslessContacts& split = e.split();
    const int nm = e.dofs(), nz = e.nz();
    const double period = e.period();
    ExactOrbit out;
    out.omega = omega;

    VectorXd zhat = e.augment(VectorXd::Zero(nz), 0.0);
    if (initial_state.size() > 0) {
        for (int k = 0; k < nm; ++k) {
            zhat(k) = initial_state(split.massive[static_cast<std::size_t>(k)]);
            zhat(nm + k) = initial_state(N + split.massive[static_cast<std::size_t>(k)]);
        }
        const VectorXd q = split.W.transpose() * detail::pick(VectorXd(initial_state.head(N)), split.massless);
        for (int c = 0; c < e.contacts(); ++c)
            for (int j = 0; j < e.directions(c); ++j) zhat(e.slider(c) + j) = q(e.tangential(c) + j);
    }
    // Where the start holds the nodes (permanent stick's convention): its tangential
    // displacements, or the static state's for a start at rest.
    VectorXd start_sliders(e.tangential_entries());
    if (initial_state.size() > 0) {
        start_sliders = zhat.segment(2 * nm, e.tangential_entries());
    } else {
        const StaticState rest = static_state(system);
        for (int c = 0; c < e.contacts(); ++c)
            for (int j = 0; j < e.directions(c); ++j)
                start_sliders(e.slider(c) + j - 2 * nm) = rest.ok ? rest.contacts[static_cast<std::size_t>(c)].relative(j) : 0.0;
    }
    SectionNorm norm{nm, omega, 0.0};
    PatternEngine::Flow f;
    // A mirror-symmetric structure (ConeEngine): its symmetric orbits are solved among the
    // symmetric states (below).
    // Without the option, the structure's mirror splits a symmetric orbit's multipliers (below).
    StateMirror mirror, structure_mirror;
    std::string no_mirror;  // why ExactOptions::mirror_symmetric finds no symmetric states to solve in
    if constexpr (exact_monodromy) {
        if (options.mirror_symmetric) no_mirror = "the option is for 3D contacts";
    } else if (const std::optional<detail::Mirror> m = detail::find_mirror(system)) {
        structure_mirror = state_mirror(*m, e);
        if (!structure_mirror.valid()) no_mirror = "the structure's mirror does not map its DOFs with mass onto each other";
    } else {
        no_mirror = "the structure has no mirror symmetry";
    }
    if (options.mirror_symmetric) mirror = structure_mirror;
    // Every flow, then the stop request (ExactOptions::stop): a period of a meshed 3D interface
    // can take seconds, a solve hundreds of periods.
    struct StopRequested {
        std::string why;
    };
    auto flow = [&](const VectorXd& z, const Modes& m, double t0, double span, bool derivative, bool record, int events) {
        PatternEngine::Flow g = e.flow(z, m, t0, span, derivative, record, events);
        if (std::string why = options.stop_reason(); !why.empty()) throw StopRequested{std::move(why)};
        return g;
    };
    // ExactOptions::threads: the second engine of central differences (created at the first).
    const bool parallel = options.threads == 2 || (options.threads == 0 && std::thread::hardware_concurrency() >= 2);
    std::unique_ptr<ConeEngine> twin;
    try {
        Modes modes = e.initial_modes(zhat);
        if (initial_state.size() > 0) {  // a start that holds every contact stuck: the stuck structure's orbit first
            ExactOrbit held = out;
            if (held_start_orbit(e, zhat, modes, start_sliders, flow, options, held)) return held;
            out.periods = held.periods;
        }

        // Plain periods from (zhat, modes) at t = 0; the last one's events kept in f.
        // (a start for Newton: the engine's looser start flows, restored however they end)
        auto plain_periods = [&](int periods) {
            struct Start {
                PatternEngine& engine;
                explicit Start(PatternEngine& e) : engine(e) { engine.set_start_flows(true); }
                ~Start() { engine.set_start_flows(false); }
                Start(const Start&) = delete;
                Start& operator=(const Start&) = delete;
            } start_flows(e);
            for (int p = 0; p < periods; ++p) {
                zhat(e.cos_index()) = 1.0;
                zhat(e.sin_index()) = 0.0;
                f = flow(zhat, modes, 0.0, period, false, false, options.max_events_per_period);
                ++out.periods;
                if (!f.ok) return false;
                zhat = f.zhat;
                modes = f.modes;
            }
            return true;
        };
        if (!plain_periods(options.warmup_periods)) {
            out.message = "warm-up: " + f.message;
            return out;
        }
        int restart_periods = 8;
        int whole_iterations = 0;  // Newton's on all the unknowns, over all attempts (held rounds apart)
        for (int attempt = 0;; ++attempt) {
            // The section: the middle of a long event-free stretch of the last period, where the
            // fewest 3D contacts slip (their directions are unknowns, and a slow slip's direction
            // turns fast), and where a period from it ends in the pattern it started in: in a
            // transient (or near an orbit with a phase that touches a limit) a short phase can
            // come and go at a stretch's middle, and a section there changes its unknowns from one
            // period to the next.
            struct Section {
                double t = 0.0, length = 0.0;
                VectorXd z;
                Modes modes;
                int angles = 0;
            };
            std::vector<Section> sections;
            {
                VectorXd z = zhat;
                Modes m = modes;
                z(e.cos_index()) = 1.0;
                z(e.sin_index()) = 0.0;
                double t = 0.0;
                for (const auto& [length, t_k] : section_times(f.events, period)) {
                    if (t_k > t) {
                        const PatternEngine::Flow to = flow(z, m, t, t_k - t, false, false, options.max_events_per_period);
                        if (!to.ok) {
                            out.message = to.message;
                            return out;
                        }
                        z = to.zhat;
                        m = to.modes;
                        t = t_k;
                    }
                    Section section{t_k, length, z, m, 0};
                    if constexpr (!exact_monodromy)
                        for (int c = 0; c < e.contacts(); ++c)
                            section.angles += m[static_cast<std::size_t>(c)] == rigid_slip_positive && e.directions(c) == 2;
                    sections.push_back(std::move(section));
                }
            }
            std::stable_sort(sections.begin(), sections.end(), [](const Section& a, const Section& b) {
                return a.angles != b.angles ? a.angles < b.angles : a.length > b.length;
            });
            std::size_t chosen = 0;
            constexpr std::size_t tried_sections = 4;
            for (std::size_t k = 0; sections.size() > 1 && k < std::min(sections.size(), tried_sections); ++k) {
                const PatternEngine::Flow once = flow(sections[k].z, sections[k].modes, sections[k].t, period, false, false,
                                                        options.max_events_per_period);
                ++out.periods;
                if (once.ok && once.modes == sections[k].modes) {
                    chosen = k;
                    break;
                }
            }
            const double t_s = sections[chosen].t;
            VectorXd zs = sections[chosen].z;  // a held round's start moves it (below)
            const Modes ms = sections[chosen].modes;
            // ExactOptions::mirror_symmetric: the section's state projected onto the symmetric
            // ones, where its patterns are their own mirror image.
            bool symmetric = false;
            double section_offset = 0.0;
            auto project_section = [&]() {
                if constexpr (!exact_monodromy) {
                    zs.head(e.nz()) = symmetric_state(mirror, zs.head(e.nz()));
                    e.make_consistent(zs, ms, t_s);
                }
            };
            if constexpr (!exact_monodromy)
                if (mirror.valid()) {
                    section_offset = section_mirror_offset(mirror, e, zs, ms, omega);
                    symmetric = std::isfinite(section_offset);
                    if (symmetric) project_section();
                }
            // Nodes stuck all of the last period (ConeEngine; a sweep's shakedown leaves them on
            // their cones' edges): Newton first on the orbit with them held stuck (hold_stuck) at
            // the section's held positions, which are then not unknowns. That map is smooth where
            // the whole one has a kink (a Newton iterate that pushes such a node's force past its
            // cone's edge makes it slip for an instant, and Newton creeps). Held rounds solve to
            // held_round_tolerance; the period without the hold then drags the held nodes that
            // slip in it to their cones' edges and starts the next round (max_held_rounds), and
            // where none slips a last round goes to the tolerance. Then Newton on all the
            // unknowns from that orbit: where the held nodes stay inside their cones without the
            // hold it is the orbit at once (a period); otherwise it is the start. Where a held
            // round does not converge, the whole Newton starts from the section (as dragged).
            std::vector<char> held;
            if constexpr (!exact_monodromy) held = stuck_all_period(e, f, ms);
            VectorXd carried;       // the held phase's orbit at the section (zhat), where it converged
            VectorXd restart_from;  // a restart's start (zhat at the section)
            int held_iterations = 0;
            int held_rounds = 0;
            bool loose_round = true;  // a held round to held_round_tolerance (not the last one)
            MatrixXd held_jacobian;   // Newton's matrix of the held rounds, kept from one to the next
            VectorXd held_unit;
            for (bool holding = std::find(held.begin(), held.end(), 1) != held.end();;) {
                std::vector<Eigen::Index> fixed;  // held sliders: zhat entries kept at zs's
                if constexpr (!exact_monodromy) {
                    e.hold_stuck(holding ? held : std::vector<char>());
                    if (holding)
                        for (int c = 0; c < e.contacts(); ++c)
                            if (held[static_cast<std::size_t>(c)])
                                for (int j = 0; j < e.directions(c); ++j) fixed.push_back(e.slider(c) + j);
                }
                const int first_iteration = out.iterations;
                // The unknowns: y, y', the sliders of the contacts stuck at the section and the slip
                // directions of 3D contacts slipping there; the other sliders are their contacts'
                // tangential displacements (rows of the pattern, or its contact problem's solution).
                // The directions (angles) last: the norm compares them modulo 2 pi.
                std::vector<Eigen::Index> unknowns;
                for (int k = 0; k < 2 * nm; ++k) unknowns.push_back(k);
                for (int c = 0; c < e.contacts(); ++c)
                    if (ms[static_cast<std::size_t>(c)] == rigid_stuck && !(holding && held[static_cast<std::size_t>(c)]))
                        for (int j = 0; j < e.directions(c); ++j) unknowns.push_back(e.slider(c) + j);
                norm.angles = 0;
                std::vector<int> angle_contacts;  // the contact of each angle unknown
                if constexpr (!exact_monodromy)
                    for (int c = 0; c < e.contacts(); ++c)
                        if (ms[static_cast<std::size_t>(c)] == rigid_slip_positive && e.directions(c) == 2) {
                            unknowns.push_back(e.theta(c));
                            angle_contacts.push_back(c);
                            ++norm.angles;
                        }
                const auto nu = static_cast<Eigen::Index>(unknowns.size());
                const UnknownMirror qx = symmetric ? unknown_mirror(mirror, unknowns) : UnknownMirror();
                auto on_mirror = [&](const VectorXd& v) { return qx.valid() ? qx.state(v) : v; };
                MatrixXd lift = MatrixXd::Zero(e.n(), nu);  // d zhat / d x
                if constexpr (exact_monodromy) {
                    const ModeData& section = e.mode(ms);
                    for (Eigen::Index k = 0; k < nu; ++k) lift(unknowns[static_cast<std::size_t>(k)], k) = 1.0;
                    for (int c = 0; c < e.contacts(); ++c)
                        if (ms[static_cast<std::size_t>(c)] != rigid_stuck)
                            for (Eigen::Index k = 0; k < nu; ++k)
                                lift(e.slider(c), k) = section.relative(e.tangential(c), unknowns[static_cast<std::size_t>(k)]);
                }
                auto start = [&](const VectorXd& x) {
                    VectorXd zh = e.augment(VectorXd::Zero(nz), t_s);
                    for (Eigen::Index k = 0; k < nu; ++k) zh(unknowns[static_cast<std::size_t>(k)]) = x(k);
                    for (const Eigen::Index i : fixed) zh(i) = zs(i);
                    e.make_consistent(zh, ms, t_s);
                    return zh;
                };
                auto pick = [&](const VectorXd& zh) {
                    VectorXd x(nu);
                    for (Eigen::Index k = 0; k < nu; ++k) x(k) = zh(unknowns[static_cast<std::size_t>(k)]);
                    return x;
                };
                // The unknowns at a flow's end. A contact that slipped at the section but does not
                // slip at the end (far from the orbit: the patterns differ) has no direction there
                // (the one it stopped with is stale): its angle is not compared, and Newton does
                // not move it by that stale value (end_derivative's row for it is zero).
                auto pick_end = [&](const PatternEngine::Flow& g, const VectorXd& from) {
                    VectorXd x_end = pick(g.zhat);
                    for (std::size_t a = 0; a < angle_contacts.size(); ++a) {
                        const auto k = nu - norm.angles + static_cast<Eigen::Index>(a);
                        if (g.modes[static_cast<std::size_t>(angle_contacts[a])] != rigid_slip_positive) x_end(k) = from(k);
                    }
                    return x_end;
                };
                VectorXd x = on_mirror(pick(carried.size() > 0 ? carried : zs));
                // Newton's residual |P(x) - x|; among the symmetric states its symmetric part (the
                // other is the flow's own asymmetry over a period, its rounding and local errors
                // on mirror-image nodes: the message gives it).
                auto residual_of = [&](const VectorXd& end, const VectorXd& from) {
                    if (!qx.valid()) return norm.relative_change(end, from);
                    return norm.relative_change(VectorXd(from + qx.symmetric(norm.difference(end, from))), from);
                };
                norm.reference = std::max(norm.reference, norm.size(x));
                auto map = [&](const VectorXd& from, bool record) {
                    ++out.periods;
                    return flow(start(from), ms, t_s, period, exact_monodromy, record, options.max_events_per_period);
                };
                // The periods from a and b (a central difference's two): on two threads where
                // options.threads allows (ConeEngine), b on the twin, which first follows the
                // engine's run state; the engine then keeps the larger of the scales both met.
                // The stop request is asked on this thread only.
                auto map_pair = [&](const VectorXd& a, const VectorXd& b, PatternEngine::Flow& fa, PatternEngine::Flow& fb) {
                    if constexpr (!exact_monodromy) {
                        if (parallel) {
                            if (!twin) {
                                twin = std::make_unique<ConeEngine>(system, omega);
                            }
                            twin->follow(e);
                            const VectorXd zb = start(b);
                            std::future<PatternEngine::Flow> other = std::async(std::launch::async, [&, zb]() {
                                return twin->flow(zb, ms, t_s, period, false, false, options.max_events_per_period);
                            });
                            try {
                                fa = map(a, false);
                            } catch (...) {
                                other.wait();
                                throw;
                            }
                            fb = other.get();
                            e.merge_scales(*twin);
                            ++out.periods;
                            if (std::string why = options.stop_reason(); !why.empty()) throw StopRequested{std::move(why)};
                            return;
                        }
                    }
                    fa = map(a, false);
                    fb = map(b, false);
                };
                // d x_end / d x: the monodromy (RigidEngine); ConeEngine: the flow's own derivative (a
                // period with the variational equation and the saltations; end_derivative where the
                // period ends in another pattern), checked against central differences of the map
                // with steps of 1e-6 of the state's size (velocities over omega, directions in
                // radians), which take over where it is missing or fails (below).
                // The unknowns' units at `size` (the state's): displacements and held positions in
                // it, velocities in it times omega, directions (last) in radians.
                auto units = [&](double size) {
                    VectorXd u(nu);
                    for (Eigen::Index k = 0; k < nu; ++k)
                        u(k) = k >= nu - norm.angles ? 1.0 : (k >= nm && k < 2 * nm ? omega : 1.0) * size;
                    return u;
                };
                // The size the differences' steps are measured in at `at`.
                auto difference_size = [&](const VectorXd& at) {
                    return std::max({norm.reference, at.head(nm).cwiseAbs().maxCoeff(),
                                     at.segment(nm, nm).cwiseAbs().maxCoeff() / omega});
                };
                // The period map's central difference along `direction` (in the unknowns' own
                // units) at `at`, steps of 1e-6 of it: d x_end / d x times direction. False where a
                // perturbed period failed (`failure` says why).
                std::string failure;
                // `events`: the perturbed periods' events, where given.
                auto difference_along = [&](const VectorXd& at, const VectorXd& direction, VectorXd& out_difference,
                                            std::vector<ExactEvent>* events = nullptr, double delta = 1e-6) {
                    const VectorXd plus = at + delta * direction, minus = at - delta * direction;
                    PatternEngine::Flow fp, fm;
                    map_pair(plus, minus, fp, fm);
                    if (!fp.ok || !fm.ok) {
                        failure = (fp.ok ? fm : fp).message;
                        return false;
                    }
                    out_difference = (pick_end(fp, plus) - pick_end(fm, minus)) / (2.0 * delta);
                    if (events) {
                        events[0] = std::move(fp.events);
                        events[1] = std::move(fm.events);
                    }
                    return true;
                };
                // The same for the Krylov products (GMRES's and Arnoldi's), where one failed period
                // would end the whole iteration: a perturbed period that fails (events that repeat
                // without time passing where a perturbation of 1e-6 puts two nodes' events at one
                // instant) is taken again at 1e-7.
                auto krylov_difference = [&](const VectorXd& at, const VectorXd& direction, VectorXd& out_difference) {
                    return difference_along(at, direction, out_difference) ||
                           difference_along(at, direction, out_difference, nullptr, 1e-7);
                };
                // The period map's whole derivative by central differences (two periods per unknown).
                auto differences_matrix = [&](const VectorXd& at) {
                    MatrixXd d(nu, nu);
                    const VectorXd scale = units(difference_size(at));
                    for (Eigen::Index k = 0; k < nu; ++k) {
                        VectorXd column;
                        if (!difference_along(at, scale(k) * VectorXd::Unit(nu, k), column))
                            throw std::runtime_error("the period map's derivative: " + failure);
                        d.col(k) = column / scale(k);
                    }
                    return d;
                };
                // d x_end / d x from the flow: the monodromy (RigidEngine), or a period with the
                // variational equation and the saltations (ConeEngine); empty where that is missing
                // (a pattern's equations singular on the way or at the end).
                auto flow_derivative = [&](const VectorXd& at, const PatternEngine::Flow& fx) {
                    if constexpr (exact_monodromy) {
                        MatrixXd d(nu, nu);
                        for (Eigen::Index k = 0; k < nu; ++k) d.row(k) = fx.psi.row(unknowns[static_cast<std::size_t>(k)]) * lift;
                        return d;
                    } else {
                        const PatternEngine::Flow fv = flow(start(at), ms, t_s, period, true, false, options.max_events_per_period);
                        ++out.periods;
                        if (fv.ok && fv.psi.size() > 0) {
                            try {
                                return end_derivative(e, fv, unknowns);
                            } catch (const std::runtime_error&) {  // a singular pattern at the end
                            }
                        }
                        return MatrixXd();
                    }
                };
                // The flow's derivative, or the differences' where it is missing.
                auto derivative = [&](const VectorXd& at, const PatternEngine::Flow& fx) {
                    MatrixXd d = flow_derivative(at, fx);
                    return d.size() > 0 ? d : differences_matrix(at);
                };
                // The largest difference, in the unknowns' units, between d x_end / d x along a fixed
                // direction and a central difference of the period map along it (steps of 1e-6 of the
                // unknowns' units), relative to the larger of the two and the direction; and whether
                // a perturbed period has another number of events at some contact than `orbit` (the
                // orbit's events): a contact that touches an edge of its cone or gap without crossing it.
                struct Mismatch {
                    double share = 0.0;
                    bool kink = false;
                };
                // A perturbation of 1e-6 that adds events (a node within it of an edge of its cone or
                // its gap) is tried again at 1e-8: where the events stay the orbit's there, that
                // decides (the flow's derivative is the period map's, a kink or not further out).
                // `kept`: unknowns d was not differentiated with respect to (the direction leaves them).
                // `mirrored`: the direction's symmetric part (a symmetric orbit's symmetric changes).
                auto derivative_mismatch = [&](const VectorXd& at, const MatrixXd& d, const std::vector<ExactEvent>& orbit,
                                               const std::vector<Eigen::Index>& kept, const UnknownMirror* mirrored = nullptr) {
                    const VectorXd scale = units(difference_size(at));
                    VectorXd pattern(nu);  // entries of one size and no symmetry
                    for (Eigen::Index k = 0; k < nu; ++k) pattern(k) = std::sin(1.0 + 2.0 * static_cast<double>(k));
                    if (mirrored) pattern = mirrored->symmetric(pattern);
                    for (const Eigen::Index k : kept) pattern(k) = 0.0;
                    const VectorXd direction = scale.cwiseProduct(pattern);
                    const VectorXd predicted = (d * direction).cwiseQuotient(scale);
                    auto counts = [&](const std::vector<ExactEvent>& events) {
                        std::vector<int> n(static_cast<std::size_t>(e.contacts()), 0);
                        for (const ExactEvent& event : events) ++n[static_cast<std::size_t>(event.contact)];
                        return n;
                    };
                    const std::vector<int> own = counts(orbit);
                    Mismatch result;
                    for (const double delta : {1e-6, 1e-8}) {
                        VectorXd differences;
                        std::vector<ExactEvent> perturbed[2];
                        if (!difference_along(at, direction, differences, perturbed, delta))
                            return Mismatch{std::numeric_limits<double>::infinity(), false};
                        differences = differences.cwiseQuotient(scale);
                        const double size_of = std::max({differences.cwiseAbs().maxCoeff(), predicted.cwiseAbs().maxCoeff(),
                                                         pattern.cwiseAbs().maxCoeff()});
                        result = Mismatch{(differences - predicted).cwiseAbs().maxCoeff() / size_of,
                                          counts(perturbed[0]) != own || counts(perturbed[1]) != own};
                        if (!(result.share > derivative_check_tolerance && result.kink)) break;
                    }
                    return result;
                };
                // Newton works on the unknowns in their units (the state's size, velocities times
                // omega, angles in radians): its matrix and steps in those units, so that the rank
                // threshold below and Broyden's update do not mix metres, metres per second and radians.
                VectorXd unit(nu);
                // Newton's matrix d(x_end - x)/dx from the flow's derivative; empty where that is missing.
                auto newton_matrix = [&](const VectorXd& at, const PatternEngine::Flow& fx) {
                    unit = units(std::max(norm.reference, norm.size(at)));
                    MatrixXd d = flow_derivative(at, fx);
                    if (d.size() == 0) return MatrixXd();
                    if (qx.valid()) d = qx.symmetric(d);
                    return MatrixXd(unit.cwiseInverse().asDiagonal() * (d - MatrixXd::Identity(nu, nu)) * unit.asDiagonal());
                };
                // The minimum-norm solve: a contact stuck all period leaves its held position free (a
                // multiplier at 1, a singular Jacobian), and Newton does not move it.
                auto decompose = [](const MatrixXd& m) {
                    Eigen::CompleteOrthogonalDecomposition<MatrixXd> decomposition(m.rows(), m.cols());
                    decomposition.setThreshold(1e-9);  // a multiplier within 1e-9 of 1: its direction is free
                    decomposition.compute(m);
                    return decomposition;
                };
                // ConeEngine, where the flow's derivative is missing or a step with it failed (events
                // of coupled contacts at one instant: it follows the order rounding puts them in):
                // Newton's step by GMRES on central differences of the period map (two periods a
                // product), right-preconditioned by the flow's last Newton matrix where there is one
                // (off along the few directions those events touch: a few products, not two periods
                // per unknown).
                bool krylov = !exact_monodromy && newton == ConeNewton::differences, preconditioned = false;
                Eigen::CompleteOrthogonalDecomposition<MatrixXd> preconditioner;
                int products = 0;
                auto krylov_step = [&](const VectorXd& at, const VectorXd& rhs) {
                    const VectorXd scale = units(difference_size(at));
                    auto precondition = [&](const VectorXd& w) { return preconditioned ? VectorXd(preconditioner.solve(w)) : w; };
                    const detail::KrylovOperator op = [&](const VectorXd& w, VectorXd& y) {
                        const VectorXd u = precondition(w), d = unit.cwiseProduct(u);
                        const double length = d.cwiseQuotient(scale).cwiseAbs().maxCoeff();
                        if (!(length > 0.0)) {
                            y = VectorXd::Zero(nu);
                            return true;
                        }
                        VectorXd difference;
                        if (!krylov_difference(at, d / length, difference)) return false;
                        y = (length * difference).cwiseQuotient(unit) - u;
                        return true;
                    };
                    VectorXd w;
                    int steps = 0;
                    if (!detail::gmres(op, rhs, detail::newton_forcing, static_cast<int>(nu), w, steps))
                        throw std::runtime_error("Newton's step by central differences: " + failure);
                    products += steps;
                    return VectorXd(unit.cwiseProduct(precondition(w)));
                };
                f = map(x, false);
                // The held orbit's period without the hold: where a held node slips in it (the
                // new frequency pushes its force past its cone's edge), the period's end drags it
                // to the edge; from there another held round (the nodes held at their new places).
                // Where none slips but the period is not the orbit to the tolerance (the rounds
                // stop at held_round_tolerance), a last held round to the tolerance.
                if (!holding && carried.size() > 0 && held_rounds < max_held_rounds && f.ok && f.modes == ms &&
                    residual_of(pick_end(f, x), x) > options.tolerance) {
                    const bool slipped = std::any_of(f.events.begin(), f.events.end(), [&](const ExactEvent& event) {
                        return held[static_cast<std::size_t>(event.contact)] != 0;
                    });
                    if (slipped || loose_round) {
                        if (slipped) {
                            zs = f.zhat;
                            if (symmetric) project_section();
                            carried.resize(0);
                        }
                        loose_round = slipped;
                        ++held_rounds;
                        holding = true;
                        continue;
                    }
                }
                bool stalled = false;
                // Newton's matrix: the monodromy's at every step (RigidEngine); ConeEngine: the flow's
                // derivative once, then updated by Broyden's rank-one formula, again where an updated
                // step fails, and GMRES on differences (above) once a step with a fresh one failed.
                MatrixXd jacobian;
                bool fresh = false;  // computed at the current x
                if (holding && held_jacobian.size() > 0) {
                    jacobian = held_jacobian;
                    unit = held_unit;
                }
                auto refresh = [&]() {
                    jacobian = newton_matrix(x, f);
                    fresh = true;
                    krylov = krylov || jacobian.size() == 0;
                };
                const bool last_attempt = attempt >= options.restarts;
                std::vector<double> residuals;  // this Newton's, one an iteration
                for (int iteration = 0;; ++iteration) {
                    if (!f.ok) {
                        out.message = "Newton iteration " + std::to_string(iteration) + ": " + f.message;
                        stalled = true;
                        break;
                    }
                    const VectorXd end = pick_end(f, x);
                    out.residual = residual_of(end, x);
                    if (out.residual <= (holding && loose_round ? std::max(options.tolerance, held_round_tolerance)
                                                                : options.tolerance)) {
                        out.converged = true;
                        out.message = "Newton on the period map converged" + std::string(f.grazing ? " (a grazing event)" : "") +
                                      (f.modes == ms ? "" : " (a contact's event at the section)");
                        break;
                    }
                    // A held round's iterations, or the whole Newton's over all attempts.
                    const int budget = holding ? held_newton_iterations : options.max_iterations;
                    if ((holding ? out.iterations - first_iteration : whole_iterations) >= budget) {
                        out.message = "Newton reached " + std::to_string(budget) + (budget == 1 ? " iteration" : " iterations") + ", residual " +
                                      format_number(out.residual);
                        stalled = true;
                        break;
                    }
                    residuals.push_back(out.residual);
                    if (!exact_monodromy && !holding && !last_attempt && !krylov && residuals.size() > creep_window &&
                        out.residual > creep_floor && out.residual > creep_factor * residuals[residuals.size() - 1 - creep_window]) {
                        out.message = "Newton crept from residual " + format_number(residuals[residuals.size() - 1 - creep_window]) +
                                      " to " + format_number(out.residual) + " in " + std::to_string(creep_window) + " iterations";
                        stalled = true;
                        break;
                    }
                    ++out.iterations;
                    if (!holding) ++whole_iterations;
                    if (!krylov && (exact_monodromy || jacobian.size() == 0)) refresh();
                    VectorXd dx;
                    if (krylov) {
                        unit = units(std::max(norm.reference, norm.size(x)));
                        dx = krylov_step(x, norm.difference(x, end).cwiseQuotient(unit));
                        if (qx.valid()) dx = qx.symmetric(dx);
                    } else {
                        dx = unit.cwiseProduct(decompose(jacobian).solve(norm.difference(x, end).cwiseQuotient(unit)));
                    }
                    // Halving steps until the residual falls.
                    bool moved = false;
                    for (double alpha = 1.0; alpha >= 1.0 / 256; alpha *= 0.5) {
                        const VectorXd trial = on_mirror(x + alpha * dx);
                        PatternEngine::Flow g = map(trial, false);
                        if (g.ok && residual_of(pick_end(g, trial), trial) < out.residual) {
                            if (!exact_monodromy && !krylov) {  // Broyden: the secant through the step
                                const VectorXd step = (trial - x).cwiseQuotient(unit),
                                               change = (norm.difference(pick_end(g, trial), trial) - norm.difference(end, x))
                                                            .cwiseQuotient(unit);
                                jacobian += (change - jacobian * step) * step.transpose() / step.squaredNorm();
                                if (qx.valid()) jacobian = qx.symmetric(jacobian);
                                fresh = false;
                            }
                            x = trial;
                            f = std::move(g);
                            moved = true;
                            break;
                        }
                    }
                    if (!moved && !krylov && !fresh) {  // an updated matrix that failed: the flow's derivative again
                        refresh();
                        continue;
                    }
                    if (!moved && holding) {  // a predictor: no steps by differences
                        out.message = "Newton with the held nodes stalled at residual " + format_number(out.residual);
                        stalled = true;
                        break;
                    }
                    if (!moved && !exact_monodromy && !krylov && out.residual > stall_floor && last_attempt) {
                        krylov = true;  // the flow's derivative failed: GMRES on differences from here on
                        preconditioner = decompose(jacobian);
                        preconditioned = true;
                        continue;
                    }
                    if (!moved) {
                        // No step lowers the residual: the rounding of the flow over one period.
                        // Below stall_floor that is the orbit (converged, the residual says how close).
                        if (out.residual <= stall_floor) {
                            out.converged = true;
                            out.message = "Newton on the period map converged to its rounding (residual " +
                                          format_number(out.residual) + ")";
                        } else {
                            out.message = "Newton stalled at residual " + format_number(out.residual);
                            stalled = true;
                        }
                        break;
                    }
                }
                if (holding) {
                    held_iterations += out.iterations - first_iteration;
                    held_jacobian = jacobian;
                    held_unit = unit;
                    if (out.converged) carried = start(x);
                    out.converged = false;
                    holding = false;
                    continue;
                }
                if (held_iterations > 0)
                    out.message += carried.size() > 0 ? " (from the orbit with the nodes stuck all period held, " +
                                                             std::to_string(held_iterations) + " Newton iterations in " +
                                                             std::to_string(held_rounds + 1) + " rounds)"
                                                       : " (Newton with the nodes stuck all period held did not converge in " +
                                                             std::to_string(held_iterations) + " iterations)";
                if (options.mirror_symmetric) {
                    if (qx.valid() && f.ok) {
                        const VectorXd r = norm.difference(pick_end(f, x), x);
                        out.message += " (among the mirror-symmetric states: the section's start " + format_number(section_offset) +
                                       " off them, relative to its size; the period's own asymmetry " +
                                       format_number(norm.size(VectorXd(r - qx.symmetric(r))) /
                                                     std::max(norm.reference, norm.size(x))) +
                                       ")";
                    } else {
                        out.message += " (not among the mirror-symmetric states: " +
                                       (no_mirror.empty() ? std::string("the section's contact patterns are not their own mirror image")
                                                          : no_mirror) +
                                       ")";
                    }
                }
                if (products > 0)
                    out.message += " (Newton's steps by GMRES on central differences of the period map: " +
                                   std::to_string(products) + " products)";
                if (out.converged || !stalled || attempt >= options.restarts || whole_iterations >= options.max_iterations) {
                    // The recorded period of the last iterate: metrics and multipliers.
                    PatternEngine::Flow last = map(x, true);
                    if (!last.ok) {
                        out.converged = false;
                        out.message = last.message;
                        return out;
                    }
                    if (out.converged && permanently_stuck(last)) hold_where_started(e, start_sliders, x, last, map, derivative, options, out);
                    rigid_metrics(e, last, t_s, options, out);
                    // The multipliers. ConeEngine: the contacts stuck all of the orbit's period are
                    // held over the period with the derivative, which then leaves out their held
                    // positions (a node stuck all period keeps its held position: its rows are
                    // the identity's, and the multipliers are those of the other unknowns and 1 for
                    // each of them; their columns, the other entries' dependence on them, are not
                    // needed for those): fewer columns through every step.
                    std::vector<Eigen::Index> kept;
                    std::vector<char> still;
                    if constexpr (!exact_monodromy) {
                        still = stuck_all_period(e, last, ms);
                        for (Eigen::Index k = 2 * nm; k < nu - norm.angles && !still.empty(); ++k)
                            if (still[static_cast<std::size_t>(e.slider_contact(static_cast<int>(unknowns[static_cast<std::size_t>(k)])))])
                                kept.push_back(k);
                        if (!kept.empty()) e.hold_stuck(still);
                    }
                    // ConeNewton::differences: the multipliers by Arnoldi too (below), without the flow's derivative.
                    const bool by_request = !exact_monodromy && newton == ConeNewton::differences;
                    MatrixXd reduced = by_request ? MatrixXd() : flow_derivative(x, last);
                    if (reduced.size() > 0 && qx.valid()) reduced = qx.symmetric(reduced);
                    if constexpr (!exact_monodromy) e.hold_stuck({});
                    if (reduced.size() > 0)
                        for (const Eigen::Index k : kept) {
                            reduced.row(k).setZero();
                            reduced.col(k).setZero();
                            reduced(k, k) = 1.0;
                        }
                    if constexpr (!exact_monodromy) {
                        // The flow's derivative checked along one direction against a central
                        // difference of the period map: where coupled contacts change pattern at one
                        // instant (mirror-image nodes of a symmetric interface) it follows the order
                        // rounding puts their events in and can be far off; the multipliers are then
                        // the differences' (two periods per unknown).
                        // Where a perturbed period has another number of events at a contact than the
                        // orbit (it touches an edge of its cone or its gap without crossing it: a node
                        // stuck all period after a shakedown, whose friction force reaches the limit at
                        // an instant, or a slipping node that touches lift-off), the period map has a
                        // kink at the orbit: the differences straddle it and are not its derivative
                        // either. The multipliers are then the orbit's own sequence of events' (the
                        // side the orbit is on), and the message says so.
                        // Not where events of two contacts coincide independently (mirror-image
                        // nodes: PatternEngine::Flow::simultaneous): the flow's derivative may then
                        // follow rounding's order, and the check decides. A cascade (a node's event
                        // making another stick or slip at its instant) is settled in its causal order
                        // and does not count: a node closing into slip as another sticks is common on
                        // a meshed interface whose stuck nodes graze their cones.
                        const bool coincident = last.simultaneous;
                        // Where the flow's derivative is missing: Arnoldi's multipliers.
                        const Mismatch mismatch = reduced.size() == 0
                                                      ? Mismatch{std::numeric_limits<double>::infinity(), false}
                                                      : derivative_mismatch(x, reduced, last.events, kept);
                        if (mismatch.share > derivative_check_tolerance && mismatch.kink && !coincident) {
                            out.message += grazing_note;
                        } else if (mismatch.share > derivative_check_tolerance) {
                            // The dominant multipliers by Arnoldi on central differences of the
                            // period map (two periods a product), in the unknowns' units: a few
                            // tens of periods where the whole matrix takes two per unknown. The
                            // contacts stuck all period are held through them and their held
                            // positions left out (the map is block triangular in them, with the
                            // identity's rows: their multipliers are 1, a cluster Arnoldi would
                            // otherwise have to resolve): Arnoldi works on the other unknowns.
                            std::vector<Eigen::Index> free;
                            for (Eigen::Index k = 0, next = 0; k < nu; ++k) {
                                if (next < static_cast<Eigen::Index>(kept.size()) && kept[static_cast<std::size_t>(next)] == k) {
                                    ++next;
                                    continue;
                                }
                                free.push_back(k);
                            }
                            const auto nf = static_cast<Eigen::Index>(free.size());
                            const VectorXd scale = units(difference_size(x));
                            // A symmetric orbit of a mirror-symmetric structure: its period map's
                            // derivative commutes with the mirror, and its multipliers are those of
                            // the symmetric changes and those of the antisymmetric ones. The
                            // symmetric changes keep mirror-image events at one instant, and the
                            // flow's derivative is theirs where a central difference along a
                            // symmetric direction confirms it: Arnoldi then works on the
                            // antisymmetric changes only (about half the free unknowns). The
                            // products' symmetric parts (the commutation's defect) are measured;
                            // where one exceeds mirror_leak_tolerance, Arnoldi works on all of them.
                            MirrorSplit halves;
                            Eigen::VectorXcd symmetric_values;
                            double symmetric_share = 0.0;
                            std::string unsplit;  // why a symmetric orbit's multipliers are not split
                            if (reduced.size() > 0 && structure_mirror.valid() && nf > 0) {
                                const UnknownMirror qs = qx.valid() ? qx : unknown_mirror(structure_mirror, unknowns);
                                if (qs.valid() && std::isfinite(section_mirror_offset(structure_mirror, e, start(x), ms, omega)) &&
                                    unknowns_mirror_offset(qs, x, scale) <= mirror_split_tolerance) {
                                    halves = mirror_split(qs, free);
                                    if (!halves.valid())
                                        unsplit = "; the orbit is mirror-symmetric, but its nodes stuck all period are not their mirror "
                                                  "images' (the multipliers not split by the mirror)";
                                }
                                if (halves.valid() && halves.antisymmetric.cols() > 0) {
                                    symmetric_share = derivative_mismatch(x, reduced, last.events, kept, &qs).share;
                                    if (symmetric_share <= derivative_check_tolerance) {
                                        MatrixXd scaled(nf, nf);
                                        for (Eigen::Index i = 0; i < nf; ++i)
                                            for (Eigen::Index j = 0; j < nf; ++j) {
                                                const Eigen::Index a = free[static_cast<std::size_t>(i)], b = free[static_cast<std::size_t>(j)];
                                                scaled(i, j) = reduced(a, b) * scale(b) / scale(a);
                                            }
                                        symmetric_values =
                                            balanced_eigenvalues(halves.symmetric.transpose() * scaled * halves.symmetric);
                                    } else {
                                        unsplit = "; the orbit is mirror-symmetric, but the flow's derivative differs from a central "
                                                  "difference along a symmetric direction by " +
                                                  format_number(symmetric_share) + " (the multipliers not split by the mirror)";
                                        halves = MirrorSplit();
                                    }
                                } else {
                                    halves = MirrorSplit();
                                }
                            }
                            // Arnoldi on the changes basis * u (columns orthonormal in the free
                            // unknowns, in their units).
                            // `failed`: a perturbed period failed at both steps (`failure` says
                            // why): the orbit stands, its multipliers are unknown.
                            struct Ritz {
                                Eigen::VectorXcd values;
                                double largest = 0.0, leak = 0.0;
                                int unconverged = 0, steps = 0;
                                bool failed = false;
                            };
                            auto arnoldi = [&](const MatrixXd& basis) {
                                Ritz r;
                                const Eigen::Index nb = basis.cols();
                                const detail::KrylovOperator product = [&](const VectorXd& u, VectorXd& y) {
                                    const VectorXd v = basis * u;
                                    const double length = v.cwiseAbs().maxCoeff();
                                    if (!(length > 0.0)) {
                                        y = VectorXd::Zero(nb);
                                        return true;
                                    }
                                    VectorXd direction = VectorXd::Zero(nu), whole;
                                    for (Eigen::Index k = 0; k < nf; ++k)
                                        direction(free[static_cast<std::size_t>(k)]) = scale(free[static_cast<std::size_t>(k)]) * v(k) / length;
                                    if (!krylov_difference(x, direction, whole)) return false;
                                    VectorXd image(nf);
                                    for (Eigen::Index k = 0; k < nf; ++k)
                                        image(k) = length * whole(free[static_cast<std::size_t>(k)]) / scale(free[static_cast<std::size_t>(k)]);
                                    y = basis.transpose() * image;
                                    r.leak = std::max(r.leak, (image - basis * y).norm() / u.norm());
                                    return true;
                                };
                                if constexpr (!exact_monodromy)
                                    if (!kept.empty()) e.hold_stuck(still);
                                const bool done = nb == 0 || detail::dominant_eigenvalues(product, detail::arnoldi_start(nb), static_cast<int>(nb),
                                                                                          r.values, r.largest, r.unconverged, r.steps,
                                                                                          multiplier_tolerance);
                                if constexpr (!exact_monodromy) e.hold_stuck({});
                                r.failed = !done;
                                return r;
                            };
                            Ritz ritz;
                            if (halves.valid()) {
                                ritz = arnoldi(halves.antisymmetric);
                                if (!ritz.failed && ritz.leak > mirror_leak_tolerance) {
                                    unsplit = "; the orbit is mirror-symmetric, but a product's symmetric part was " +
                                              format_number(ritz.leak) +
                                              " of its direction (the multipliers not split by the mirror)";
                                    halves = MirrorSplit();
                                    symmetric_values.resize(0);
                                }
                            }
                            if (!halves.valid()) ritz = arnoldi(MatrixXd::Identity(nf, nf));
                            if (ritz.failed) {
                                // The orbit is converged: it stands, with its stability unknown.
                                out.multipliers.resize(0);
                                out.max_multiplier = std::numeric_limits<double>::quiet_NaN();
                                out.stable = false;
                                out.message += "; the multipliers are unknown (a perturbed period of their central "
                                               "differences failed: " +
                                               failure + ")";
                                return out;
                            }
                            const Eigen::Index ns = symmetric_values.size(), na = ritz.values.size();
                            out.multipliers = Eigen::VectorXcd::Ones(ns + na + static_cast<Eigen::Index>(kept.size()));
                            out.multipliers.head(ns) = symmetric_values;
                            out.multipliers.segment(ns, na) = ritz.values;
                            const double symmetric_largest = ns > 0 ? symmetric_values.cwiseAbs().maxCoeff() : 0.0;
                            out.max_multiplier = std::max({ritz.largest, symmetric_largest, kept.empty() ? 0.0 : 1.0});
                            out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
                            out.multiplier_accuracy = difference_multiplier_accuracy;
                            // The tolerance bounds the Ritz residuals of the differences' map, not the
                            // multipliers' error: where events part at the orbit (mirror-image nodes,
                            // grazing ones) the period map is only piecewise smooth there, and
                            // differences along other directions give other values.
                            const std::string counted = std::to_string(na) + " with Ritz residuals below about " +
                                                        format_number(multiplier_tolerance) + " in " + std::to_string(ritz.steps) +
                                                        " products";
                            const std::string residual_note =
                                "; the residuals are the differences' map's, not the multipliers' accuracy, which is the differences'";
                            const std::string held_note =
                                kept.empty() ? std::string()
                                             : ", with the " + std::to_string(kept.size()) + " held positions of the nodes stuck all period held: 1 each";
                            const std::string unconverged_note =
                                ritz.unconverged > 0 ? ", " + std::to_string(ritz.unconverged) + " of modulus >= " +
                                                           format_number(detail::arnoldi_dominant) +
                                                           " not converged: the verdict takes the largest Ritz value"
                                                     : std::string();
                            if (halves.valid())
                                out.message += "; the multipliers of the mirror-symmetric orbit by halves: the symmetric changes' " +
                                               std::to_string(ns) +
                                               " from the flow's derivative (it matches a central difference along a symmetric direction to " +
                                               format_number(symmetric_share) +
                                               "), the antisymmetric changes' dominant ones by Arnoldi on central differences of the period map (" +
                                               counted + held_note + unconverged_note + residual_note + "; the products' symmetric parts at most " +
                                               format_number(ritz.leak) + " of their directions; the flow's derivative differs from them by " +
                                               format_number(mismatch.share) + " along a test direction)";
                            else
                                out.message += "; the dominant multipliers by Arnoldi on central differences of the period map (" + counted +
                                               held_note + unconverged_note + residual_note +
                                               (by_request            ? std::string("; by differences as asked)")
                                                : reduced.size() == 0 ? std::string("; the flow's derivative is missing)")
                                                                      : "; the flow's derivative differs from them by " +
                                                                            format_number(mismatch.share) + " along a test direction)") +
                                               unsplit;
                            detail::exact::note_unresolved_stability(out);
                            return out;
                        }
                    }
                    out.multipliers = balanced_eigenvalues(reduced);
                    out.max_multiplier = nu > 0 ? out.multipliers.cwiseAbs().maxCoeff() : 0.0;
                    out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
                    return out;
                }
                restart_from = start(x);
                break;
            }
            // A restart: plain periods from the last iterate, then a new section.
            zhat = restart_from;
            modes = ms;
            // back to t = 0: flow the rest of the period
            if (t_s > 0.0) {
                const PatternEngine::Flow rest = flow(zhat, modes, t_s, period - t_s, false, false,
                                                        options.max_events_per_period);
                if (!rest.ok) {
                    out.message = rest.message;
                    return out;
                }
                zhat = rest.zhat;
                modes = rest.modes;
            }
            if (!plain_periods(restart_periods)) {
                out.message = "restart: " + f.message;
                return out;
            }
            restart_periods *= 4;
        }
    } catch (const StopRequested& stop) {
        if constexpr (!exact_monodromy) e.hold_stuck({});
        out.converged = false;
        out.stopped = stop.why;
        out.message = "stopped after " + std::to_string(out.periods) + " periods: " + stop.why;
    } catch (const std::runtime_error& error) {
        if constexpr (!exact_monodromy) e.hold_stuck({});
        out.converged = false;
        out.message = error.what();
    }
    return out;
}

}  // namespace

ExactOrbit rigid_periodic_orbit(const System& system, double omega, const VectorXd& initial_state,
                                const ExactOptions& options) {
    return rigid_periodic_orbit(system, omega, initial_state, options, ConeStepping::automatic);
}

ExactOrbit rigid_periodic_orbit(const System& system, double omega, const VectorXd& initial_state,
                                const ExactOptions& options, ConeStepping stepping, ConeNewton newton) {
    system.validate();
    refuse_cyclic(system, "the exact solver of law unilateral");
    options.validate();
    if (!(omega > 0.0) || !std::isfinite(omega))
        throw InvalidInput("omega = " + format_number(omega) + " is out of range: allowed > 0");
    const int N = system.dofs();
    if (initial_state.size() != 0 && (initial_state.size() != 2 * N || !initial_state.allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state.size()) +
                           " entries or non-finite values: allowed none (a start at rest) or " + std::to_string(2 * N) +
                           " finite values (y and y' of every DOF)");
    if (system.contacts.size() > static_cast<std::size_t>(rigid_solver_max_contacts))
        throw InvalidInput(rigid_solver_refusal(system));
    if (cones(system)) {
        ConeEngine e(system, omega);
        e.set_stepping(stepping == ConeStepping::taylor        ? ConeEngine::Stepping::taylor
                       : stepping == ConeStepping::collocation ? ConeEngine::Stepping::collocation
                                                               : ConeEngine::Stepping::automatic);
        if (e.dofs() > exact_solver_max_dofs) throw InvalidInput(rigid_solver_refusal(system));
        return shoot(e, system, omega, initial_state, options, newton);
    }
    RigidEngine e(system, omega);
    if (e.dofs() > exact_solver_max_dofs) throw InvalidInput(rigid_solver_refusal(system));
    return shoot(e, system, omega, initial_state, options);
}

}  // namespace hbf