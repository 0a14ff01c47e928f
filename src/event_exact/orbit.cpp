// hbfriction — exact periodic orbits: Newton on the period map from a Poincare section, the
// permanent-stick convention, the Floquet multipliers, and systems with massless DOFs solved on
// their static condensation (event_exact.hpp).
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <string>
#include <utility>

#include "event_exact/engine.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/linear_limits.hpp"
#include "event_exact/metrics.hpp"
#include "event_exact/polynomial.hpp"
#include "event_exact/validation.hpp"

namespace hbf::detail::exact {

namespace {

/// The linear stuck steady state (convention of event_exact.hpp): z at t = 0 and the load
/// max_c |f_c| / F_c; infinity where the stuck structure is singular at omega.
double stuck_steady_state(const System& system, double omega, Eigen::VectorXd& z) {
    const StuckResponse stuck = stuck_linear_response(system, omega);
    if (!stuck.ok) return std::numeric_limits<double>::infinity();
    const int nd = system.dofs(), nc = static_cast<int>(system.contacts.size());
    double load = 0.0;
    for (int c = 0; c < nc; ++c)
        load = std::max(load, std::abs(stuck.force(c)) / system.contacts[static_cast<std::size_t>(c)].friction_limit);
    z = Eigen::VectorXd::Zero(2 * nd + nc);
    z.head(nd) = stuck.amplitude.real();
    z.segment(nd, nd) = -omega * stuck.amplitude.imag();  // Re(i omega Y)
    return load;
}

/// The permanent-stick orbit's state, or false when it does not hold every contact.
bool permanent_stick_state(const System& system, double omega, Eigen::VectorXd& z) {
    return stuck_steady_state(system, omega, z) <= 1.0;
}

/// Basis B of the states allowed at the section with `modes`, its left inverse C (C B = I: the
/// projection onto them is z_p + B C (z - z_p)), and the particular
/// state z_p: z = z_p + B xi (coulomb sliders fixed at 0; coulomb stuck: v_c = 0; jenkins
/// slipping: s_c = q_c + p_c cos(omega t) - mode F_c / k_t, p_c its base motion, t the
/// section's time).
/// B is orthonormal in the scaled state S z (velocities divided by w, as SectionNorm's): the
/// Newton matrix C (Psi - I) B and the multipliers' C Psi B are then the same numbers in any
/// units (in raw units y and y' differ by w, and the rank threshold of the Newton solve would
/// cut the wrong singular values).
void section_manifold(const Engine& e, const Modes& modes, double t, Eigen::MatrixXd& basis,
                      Eigen::MatrixXd& cobasis, Eigen::VectorXd& particular) {
    const int nd = e.dofs(), nz = e.nz();
    std::vector<Eigen::RowVectorXd> rows;
    std::vector<double> values;
    for (int c = 0; c < e.contacts(); ++c) {
        const int mode = modes[static_cast<std::size_t>(c)];
        Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(nz);
        if (e.coulomb(c)) {
            row(2 * nd + c) = 1.0;
            rows.push_back(row);
            values.push_back(0.0);
            if (mode == 0) {
                Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(nz);
                v.segment(nd, nd) = e.direction(c).transpose();
                rows.push_back(v);
                values.push_back(0.0);
            }
        } else if (mode != 0) {
            row.head(nd) = e.direction(c).transpose();
            row(2 * nd + c) = -1.0;
            rows.push_back(row);
            // the spring's far end is at q + p cos(omega t) (Contact::base_motion)
            values.push_back(mode * e.contact(c).friction_limit / e.contact(c).stiffness -
                             e.contact(c).base_motion * std::cos(e.omega() * t));
        }
    }
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(nz);  // S
    scale.segment(nd, nd).setConstant(1.0 / e.omega());
    if (rows.empty()) {
        basis = Eigen::MatrixXd::Identity(nz, nz);
        cobasis = basis;
        particular = Eigen::VectorXd::Zero(nz);
        return;
    }
    Eigen::MatrixXd constraints(static_cast<Eigen::Index>(rows.size()), nz);
    Eigen::VectorXd d(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) {
        constraints.row(static_cast<Eigen::Index>(k)) = rows[k];
        d(static_cast<Eigen::Index>(k)) = values[k];
    }
    const Eigen::MatrixXd scaled = constraints * scale.cwiseInverse().asDiagonal();  // on S z
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(scaled.transpose());
    const Eigen::Index rank = qr.rank();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(nz, nz);
    const Eigen::MatrixXd orthonormal = q.rightCols(nz - rank);
    basis = scale.cwiseInverse().asDiagonal() * orthonormal;
    cobasis = orthonormal.transpose() * scale.asDiagonal();
    particular = scale.cwiseInverse().asDiagonal() * scaled.completeOrthogonalDecomposition().solve(d);
}

void fill_stability(const Eigen::MatrixXd& psi, const Eigen::MatrixXd& basis, const Eigen::MatrixXd& cobasis, int nz,
                    const ExactOptions& options, ExactOrbit& out) {
    const Eigen::MatrixXd reduced = cobasis * psi.topLeftCorner(nz, nz) * basis;
    if (reduced.rows() == 0) {
        out.multipliers.resize(0);
        out.max_multiplier = 0;
        out.stable = true;
        return;
    }
    out.multipliers = balanced_eigenvalues(reduced);
    out.max_multiplier = out.multipliers.cwiseAbs().maxCoeff();
    out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
}

/// exact_periodic_orbit on a system with M > 0 (validated); with `probes`, their metrics from
/// the orbit's period instead of the DOFs' maxima (fill_metrics).
ExactOrbit orbit_of(const System& system, double omega, const Eigen::VectorXd& initial_state,
                    const ExactOptions& options, Probes* probes = nullptr, bool split = true) {
    Engine e(system, omega, split);
    const double period = e.period();
    ExactOrbit out;
    out.omega = omega;
    SectionNorm norm{e.dofs(), omega, 0.0};
    norm.reference = norm.size(initial_state.head(e.nz()));

    // Plain periods from zhat (at t = 0) with modes; the last one recorded (with its monodromy
    // if asked).
    Engine::Flow warm;
    auto plain_periods = [&](Eigen::VectorXd zhat, Modes modes, int periods, bool monodromy = false) {
        for (int p = 0; p < periods; ++p) {
            zhat(e.cos_index()) = 1.0;
            zhat(e.sin_index()) = 0.0;
            warm = e.flow(zhat, modes, 0.0, period, monodromy && p + 1 == periods, p + 1 == periods,
                          options.max_events_per_period);
            ++out.periods;
            if (!warm.ok) return false;
            zhat = warm.zhat;
            modes = warm.modes;
        }
        return true;
    };
    Eigen::VectorXd zhat = e.augment(initial_state.head(e.nz()), 0.0);
    for (int c = 0; c < e.contacts(); ++c)
        if (e.coulomb(c)) zhat(2 * e.dofs() + c) = 0.0;
    Modes hints(static_cast<std::size_t>(e.contacts()));
    for (int c = 0; c < e.contacts(); ++c)
        hints[static_cast<std::size_t>(c)] = static_cast<int>(std::lround(initial_state(e.nz() + c)));
    const Modes modes = e.initial_modes(zhat, hints);
    // A single warm-up period starts on the section manifold at t = 0 and carries its monodromy:
    // where no event falls near t = 0 it is the first period map of Newton on the section t = 0
    // (one period less per orbit; from a start close to the orbit, the common case in a
    // continuation, a third to a fifth of the periods).
    Eigen::VectorXd first_z;
    const bool first_map = options.warmup_periods == 1;
    if (first_map) {
        Eigen::MatrixXd b0, c0;
        Eigen::VectorXd p0;
        section_manifold(e, modes, 0.0, b0, c0, p0);
        first_z = p0 + b0 * (c0 * (zhat.head(e.nz()) - p0));
        zhat = e.augment(first_z, 0.0);
    }
    const Modes start_modes = first_map ? e.initial_modes(zhat, modes) : modes;
    if (!plain_periods(zhat, start_modes, options.warmup_periods, first_map)) {
        out.message = "warm-up: " + warm.message;
        if (!warm.steps.empty()) fill_metrics(e, warm, 0.0, options, out, probes);  // the period as far as it went
        out.state = initial_state;
        return out;
    }

    Eigen::VectorXd stuck;
    const bool stuck_holds = permanent_stick_state(system, omega, stuck);
    // The permanent-stick orbit (the convention of event_exact.hpp), into `orbit`.
    auto permanent = [&](ExactOrbit& orbit) {
        const Modes stick(static_cast<std::size_t>(e.contacts()), 0);
        Engine::Flow f = e.flow(e.augment(stuck, 0.0), stick, 0.0, period, true, true, options.max_events_per_period);
        ++orbit.periods;
        orbit.permanent_stick = true;
        orbit.residual = norm.relative_change(f.zhat.head(e.nz()), stuck);
        orbit.converged = f.ok && f.events.empty() && orbit.residual <= std::max(options.tolerance, 1e-10);
        orbit.message = orbit.converged ? "permanent stick: the linear stuck steady state with zero mean friction "
                                          "force (convention for the undetermined offset)"
                                        : "the permanent-stick state left stick within the period";
        fill_metrics(e, f, 0.0, options, orbit, probes);
        Eigen::MatrixXd basis, cobasis;
        Eigen::VectorXd particular;
        section_manifold(e, stick, 0.0, basis, cobasis, particular);
        fill_stability(f.psi, basis, cobasis, e.nz(), options, orbit);
    };

    Engine::Flow f;
    double t_s = 0.0;
    Eigen::MatrixXd basis, cobasis;
    int restart_periods = 8;
    for (int attempt = 0;; ++attempt) {
        // Permanent stick: no event and every contact stuck over the last plain period.
        bool all_stuck = warm.events.empty();
        for (const Step& st : warm.steps)
            for (int mode : st.modes) all_stuck = all_stuck && mode == 0;
        if (all_stuck && stuck_holds) {
            const int periods = out.periods, iterations = out.iterations;
            out = ExactOrbit{};
            out.omega = omega;
            out.periods = periods;
            out.iterations = iterations;
            permanent(out);
            return out;
        }
        // The section: the middle of the longest event-free stretch of the last plain period;
        // t = 0 on the first attempt when the warm-up was its period map there, the start was
        // close to periodic (|P(z) - z| <= 1e-2 |z|: a far start, e.g. a linear guess, takes the
        // plain period to settle its stick/slip pattern first) and no event lies within 1/50 of a
        // period of t = 0 (Newton's steps do not move events across it).
        t_s = 0.0;
        Modes section_modes = warm.steps.front().modes;
        bool reuse = attempt == 0 && first_map && warm.psi.size() > 0 && section_modes == start_modes &&
                     norm.relative_change(warm.zhat.head(e.nz()), first_z) <= 1e-2;
        for (const ExactEvent& ev : warm.events) {
            const double phase = std::fmod(ev.time, period);
            if (std::min(phase, period - phase) < period / 50.0) reuse = false;
        }
        Eigen::VectorXd z, particular;
        if (reuse) {
            section_manifold(e, section_modes, 0.0, basis, cobasis, particular);
            z = first_z;
            f = std::move(warm);
            warm = Engine::Flow{};
        } else {
            if (!warm.events.empty()) {
                std::vector<double> times;
                for (const ExactEvent& ev : warm.events) times.push_back(ev.time);
                std::sort(times.begin(), times.end());
                double best_gap = -1.0;
                for (std::size_t k = 0; k < times.size(); ++k) {
                    const double next = k + 1 < times.size() ? times[k + 1] : times.front() + period;
                    if (next - times[k] > best_gap) {
                        best_gap = next - times[k];
                        t_s = times[k] + 0.5 * (next - times[k]);
                    }
                }
                t_s = std::fmod(t_s, period);
                section_modes = step_at(warm.steps, t_s).modes;
            }
            z = t_s == 0.0 ? Eigen::VectorXd(warm.steps.front().state(0.0).head(e.nz()))
                           : Eigen::VectorXd(state_at(warm.steps, t_s).head(e.nz()));
            section_manifold(e, section_modes, t_s, basis, cobasis, particular);
            z = particular + basis * (cobasis * (z - particular));
        }

        auto map = [&](const Eigen::VectorXd& start) {
            Eigen::VectorXd zh = e.augment(start, t_s);
            const Modes m = e.initial_modes(zh, section_modes);
            ++out.periods;
            return e.flow(zh, m, t_s, period, true, true, options.max_events_per_period);
        };
        // Newton on B^T (P(z) - z) = 0 from z (f = map(z) on entry); returns whether a restart
        // may help. A singular Jacobian (a multiplier at 1: the undetermined offset of a contact
        // stuck all period, or a fold) takes the minimum-norm step.
        auto newton = [&]() {
            for (int iteration = 0;; ++iteration, ++out.iterations) {
                if (!f.ok) {
                    out.message = "Newton iteration " + std::to_string(iteration) + ": " + f.message;
                    return false;
                }
                const Eigen::VectorXd r = f.zhat.head(e.nz()) - z;
                out.residual = norm.relative_change(f.zhat.head(e.nz()), z);
                if (out.residual <= options.tolerance) {
                    out.converged = true;
                    out.message = "Newton on the period map converged" + std::string(f.grazing ? " (a grazing event)" : "");
                    return false;
                }
                if (out.iterations >= options.max_iterations) {
                    out.message = "Newton reached " + std::to_string(options.max_iterations) + " iterations, residual " +
                                  format_number(out.residual);
                    return false;
                }
                const Eigen::MatrixXd jacobian =
                    cobasis *
                    (f.psi.topLeftCorner(e.nz(), e.nz()) - Eigen::MatrixXd::Identity(e.nz(), e.nz())) * basis;
                Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver;
                solver.setThreshold(1e-11);
                solver.compute(jacobian);
                const Eigen::VectorXd step = -(basis * solver.solve(cobasis * r));
                double alpha = 1.0;
                for (int trial = 0; trial < 12; ++trial, alpha *= 0.5) {
                    const Eigen::VectorXd trial_z = z + alpha * step;
                    Engine::Flow g = map(trial_z);
                    if (!g.ok) continue;
                    const double residual = norm.relative_change(g.zhat.head(e.nz()), trial_z);
                    if (residual < out.residual * (1.0 - 1e-4 * alpha) || residual <= options.tolerance) {
                        z = trial_z;
                        f = std::move(g);
                        alpha = -1.0;
                        break;
                    }
                }
                if (alpha > 0.0) {
                    out.message = "Newton stalled (no decrease along the step) at residual " +
                                  format_number(out.residual) +
                                  ": the stick/slip pattern changes near this frequency, or the start is too far";
                    return true;
                }
            }
        };
        if (!reuse) f = map(z);
        bool retry = newton();
        if (out.converged) {
            // Contacts stuck over the whole period (others slipping) have an undetermined offset:
            // the convention of event_exact.hpp, zero mean force. A static shift of the structure
            // K dy = sum_c w_c fbar_c (and of the Jenkins sliders, s_c += w_c^T dy + fbar_c / k_t)
            // removes each such contact's mean force fbar_c and leaves the others' forces and
            // every velocity unchanged; Newton then polishes the shifted orbit.
            Eigen::VectorXd mean = mean_forces(e, f);
            const Eigen::VectorXd work = slip_work(e, f);
            std::vector<int> stuck_all;
            for (int c = 0; c < e.contacts(); ++c) {
                bool stuck_throughout = true;
                for (const Step& st : f.steps)
                    if (st.s_end > 0.0 && st.modes[static_cast<std::size_t>(c)] != 0) stuck_throughout = false;
                // A member of that family at the edge of the friction cone grazes it: slips of
                // vanishing length (measured 2e-13 of the orbit's friction energy on a two-contact
                // chain) that leave the offset undetermined too; it is centred the same way.
                const bool grazing = work(c) <= 1e-9 * work.sum();
                if ((stuck_throughout || grazing) && std::abs(mean(c)) > 1e-12 * e.contact(c).friction_limit)
                    stuck_all.push_back(c);
            }
            if (!stuck_all.empty() && static_cast<int>(stuck_all.size()) < e.contacts()) {
                Eigen::VectorXd load = Eigen::VectorXd::Zero(e.dofs());
                for (int c : stuck_all) load += e.direction(c) * mean(c);
                const Eigen::VectorXd dy = Eigen::MatrixXd(system.stiffness).completeOrthogonalDecomposition().solve(load);
                Eigen::VectorXd shifted = z;
                shifted.head(e.dofs()) += dy;
                for (int c : stuck_all)
                    if (!e.coulomb(c))
                        shifted(2 * e.dofs() + c) += e.direction(c).dot(dy) + mean(c) / e.contact(c).stiffness;
                const Eigen::VectorXd kept = z;
                Engine::Flow kept_flow = f;
                z = particular + basis * (cobasis * (shifted - particular));
                f = map(z);
                out.converged = false;
                newton();
                if (!out.converged) {  // keep the orbit found, with its offset, and say so
                    z = kept;
                    f = std::move(kept_flow);
                    out.converged = true;
                    out.residual = norm.relative_change(f.zhat.head(e.nz()), z);
                    out.message = "Newton on the period map converged; a contact stuck all period keeps a nonzero "
                                  "mean force (centring it failed)";
                }
            }
        }
        if (out.converged || !retry || attempt >= options.restarts || out.iterations >= options.max_iterations) break;
        // Restart: plain periods from the last iterate (the exact flow integrates the motion and
        // settles the stick/slip pattern), then a new section and Newton.
        const Eigen::VectorXd at_zero = t_s > 0.0 ? state_at(f.steps, period) : f.zhat;
        const Modes modes_zero = t_s > 0.0 ? step_at(f.steps, period).modes : f.modes;
        if (!plain_periods(at_zero, modes_zero, restart_periods)) {
            out.message += "; restart: " + warm.message;
            break;
        }
        restart_periods *= 4;
    }
    if (!out.converged && stuck_holds) {
        // Newton found no orbit with slip from this start, and the permanent-stick state holds:
        // that is the orbit (the start's slip was a transient).
        ExactOrbit orbit;
        orbit.omega = omega;
        orbit.periods = out.periods;
        orbit.iterations = out.iterations;
        permanent(orbit);
        if (orbit.converged) {
            orbit.message += "; Newton from the start failed: " + out.message;
            return orbit;
        }
    }
    fill_metrics(e, f, t_s, options, out, probes);
    fill_stability(f.psi, basis, cobasis, e.nz(), options, out);
    // A member of the permanent-stick family with another offset (no slip, or slips of
    // vanishing length at the edge of the friction cone, dissipating nothing) where the
    // conventional one holds: the convention instead.
    double scale = 0.0;
    for (int c = 0; c < e.contacts(); ++c) scale += e.contact(c).friction_limit;
    double largest = 0.0;  // NaN where the DOF maxima are not computed
    for (double y : out.y_max)
        if (std::isfinite(y)) largest = std::max(largest, y);
    scale *= 1.0 + largest;
    if (out.converged && stuck_holds && out.energy <= 1e-9 * scale) {
        ExactOrbit orbit;
        orbit.omega = omega;
        orbit.periods = out.periods;
        orbit.iterations = out.iterations;
        permanent(orbit);
        if (orbit.converged) return orbit;
    }
    return out;
}

/// The orbit of a system with massless DOFs: solved on its static condensation (exact: the
/// massless DOFs follow the massive ones, the load and the sliders linearly), then expressed
/// in the original DOFs. The massless DOFs and the outputs are functions of the reduced
/// state, p = L zhat, whose maxima and harmonics come from the orbit's period (Probes).
ExactOrbit massless_orbit(const System& system, const detail::MasslessCondensation& condensation, double omega,
                          const Eigen::VectorXd& initial_state, const ExactOptions& options, bool split) {
    const System& reduced = condensation.reduced();
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size()), nr = reduced.dofs();
    ExactOptions reduced_options = options;
    reduced_options.outputs.clear();
    // Rows over zhat = [y_R, y_R', s, cos, sin, 1]: every original DOF, then every output.
    const int cos_index = 2 * nr + nc;
    const detail::MasslessCondensation::MasslessMap map = condensation.massless_map();
    Probes probes;
    probes.rows = Eigen::MatrixXd::Zero(n + static_cast<Eigen::Index>(options.outputs.size()), cos_index + 3);
    for (int i = 0; i < n; ++i) {
        const int p = condensation.position(i);
        if (!condensation.massless(i)) {
            probes.rows(i, p) = 1.0;
            continue;
        }
        probes.rows.row(i).head(nr) = map.from_massive.row(p);
        probes.rows.row(i).segment(2 * nr, nc) = map.from_sliders.row(p);
        probes.rows(i, cos_index) = map.load(p);
    }
    for (std::size_t o = 0; o < options.outputs.size(); ++o)
        for (const auto& [i, c] : options.outputs[o].terms())
            probes.rows.row(n + static_cast<Eigen::Index>(o)) += c * probes.rows.row(i);
    if (!options.dof_maxima) probes.first_max = n;  // the outputs' maxima only
    ExactOrbit out = orbit_of(reduced, omega, condensation.reduce_state(initial_state), reduced_options, &probes, split);
    if (probes.max.size() != static_cast<std::size_t>(probes.rows.rows())) {
        out.converged = false;
        out.message += "; no period of the massless DOFs was integrated";
        return out;
    }
    // The original's metrics and state.
    out.y_max.assign(probes.max.begin(), probes.max.begin() + n);
    out.y_amp1.resize(static_cast<std::size_t>(n));
    out.harmonic1.resize(n);
    for (int i = 0; i < n; ++i) {
        out.y_amp1[static_cast<std::size_t>(i)] = std::hypot(probes.c1(i), probes.s1(i));
        out.harmonic1(i) = std::complex<double>(probes.c1(i), -probes.s1(i));
    }
    // The force's work on the original DOFs (the load on the massless DOFs included: in the
    // reduced system it works through the sliders' base motion).
    out.input_energy = pi * system.excitation.dot(probes.s1.head(n));
    out.output_max.assign(probes.max.begin() + n, probes.max.end());
    out.output_amp1.clear();
    for (std::size_t o = 0; o < options.outputs.size(); ++o) {
        const Eigen::Index row = n + static_cast<Eigen::Index>(o);
        out.output_amp1.push_back(std::hypot(probes.c1(row), probes.s1(row)));
    }
    Eigen::VectorXd state = Eigen::VectorXd::Zero(2 * n + 2 * nc);
    state.head(n) = probes.value.head(n);
    state.segment(n, n) = probes.rate.head(n);
    for (int c = 0; c < nc; ++c) {
        // A Coulomb contact's internal state is 0 by convention (its slider is q itself).
        const bool coulomb = rigid_slider(system.contacts[static_cast<std::size_t>(c)]);
        state(2 * n + c) = coulomb ? 0.0 : out.state(2 * nr + c);
        state(2 * n + nc + c) = out.state(2 * nr + nc + c);
    }
    out.state = state;
    if (options.samples > 0) {
        out.displacement = probes.samples.leftCols(n);
        out.velocity = probes.sample_rates.leftCols(n);
    }
    return out;
}

}  // namespace

}  // namespace hbf::detail::exact

namespace hbf {

double permanent_stick_load(const System& given, double omega, int contact) {
    using namespace detail::exact;
    given.validate();
    const TimeDomainView view(given);  // the contacts as time-domain elements (contact_law.hpp)
    const System& system = view.system();
    validate_system(system, omega);
    if (contact < 0) {
        Eigen::VectorXd z;
        return stuck_steady_state(system, omega, z);
    }
    if (contact >= static_cast<int>(given.contacts.size()))
        throw InvalidInput("contact " + std::to_string(contact + 1) + " is out of range: allowed 1.." +
                           std::to_string(given.contacts.size()));
    const StuckResponse stuck = stuck_linear_response(system, omega);
    if (!stuck.ok) return std::numeric_limits<double>::infinity();
    // The contact's elements (time_domain_system's order).
    std::size_t first = 0;
    for (int c = 0; c < contact; ++c)
        first += contact_law(given.contacts[static_cast<std::size_t>(c)].law).time_elements(given.contacts[static_cast<std::size_t>(c)]).size();
    const std::size_t count =
        contact_law(given.contacts[static_cast<std::size_t>(contact)].law).time_elements(given.contacts[static_cast<std::size_t>(contact)]).size();
    double load = 0.0;
    for (std::size_t e = first; e < first + count; ++e)
        load = std::max(load, std::abs(stuck.force(static_cast<Eigen::Index>(e))) / system.contacts[e].friction_limit);
    return load;
}

ExactOrbit exact_periodic_orbit(const System& given, double omega, const Eigen::VectorXd& initial_state,
                                const ExactOptions& options) {
    using namespace detail::exact;
    given.validate();
    const TimeDomainView view(given);  // the contacts as time-domain elements (contact_law.hpp)
    const System& system = view.system();
    const auto condensation = validate_system(system, omega);
    check_state_size(system, initial_state);
    options.validate();
    for (const Output& o : options.outputs) o.validate(system.dofs());
    auto solve = [&](bool split) {
        return condensation ? massless_orbit(system, *condensation, omega, initial_state, options, split)
                            : orbit_of(system, omega, initial_state, options, nullptr, split);
    };
    ExactOrbit orbit = solve(true);
    if (!orbit.converged && orbit.residual < 1e-8) {
        // The split flows (fast modes in closed form) can leave a residual floor near 1e-11 (seen
        // in some units on a 10-DOF chain); the plain Taylor flows do not. They are tried, for an
        // orbit that stalled that close (not a start that led nowhere), when their steps against
        // the fastest mode stay within the cost bound.
        Engine plain(condensation ? condensation->reduced() : system, omega, false);
        if (period_cost(plain) <= exact_max_steps_per_period(plain.n())) {
            ExactOrbit retry = solve(false);
            if (retry.converged) {
                retry.iterations += orbit.iterations;
                retry.periods += orbit.periods;
                retry.message += " (plain Taylor flows: with the fast modes split off, " + orbit.message + ")";
                orbit = std::move(retry);
            }
        }
    }
    if (!orbit.contacts.empty()) {
        orbit.contacts = contact_regimes(given, orbit.contacts);
        orbit.stick_fraction = orbit.contacts.front().stick_fraction;
        orbit.regime = orbit.contacts.front().regime;
    }
    return orbit;
}

}  // namespace hbf
