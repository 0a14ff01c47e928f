// Benchmark and verification: the exact periodic orbit of the mitred bar end
// (examples/systems/mitre: 27 rigid 3D contact nodes on a massless-boundary model) against law
// unilateral's time integrator, at chosen frequencies, in one process. Per frequency: the
// integrator's steady state at N and 2N samples a period (its error falls like 1/N where slip
// directions turn: the Richardson value 2 y(2N) - y(N) is its limit), the exact orbit from the
// fine state (rigid_exact.hpp, --stepping automatic: Taylor series where the slip directions
// are not stiff, implicit collocation where they are), each output's max |o(t)| and first
// harmonic by the three, the interface's stuck and open shares, and the seconds of each. The
// last line is one JSON object with every frequency. Where the integrator does not reach a
// steady state (an unstable orbit, or its contact problem failing at 100 N), --no-integrator
// computes the exact orbit alone (from rest after --warmup exact periods, or from --start), and
// --check-samples N integrates two periods from the exact orbit's state at N, 2N and 4N samples
// (the second one's metrics): their differences from the exact orbit, and the change of the state
// over the first, fall with the step where the orbit is a solution. Per-node shares (stuck, open,
// slipping) are compared node by node, the largest difference printed: the integrator counts them
// on its steps, so each transition's instant is off by up to a step.
// --sweep A,B,K first sweeps K equally spaced frequencies from A to B (A > B: down) with exact orbits,
// each from the previous one (the first from --start where given; exact_steady_state: hbf timeint
// --method exact), and prints each point and the seconds per point; the integrator's runs at --w
// then give the ratio of its seconds per frequency (from rest, both step sizes) to the sweep's per
// point (--messages: each point's solve message, the path it took, under its line), and the
// sweep's point at each
// --w against the exact orbit from the integrator's state (the two may be different members of
// a family of orbits where nodes stick all period). --save-sweep F writes the sweep's last
// orbit. Each exact orbit's line ends with its distance from its mirror image (the mitre is
// symmetric about its mid-plane: model/mirror.hpp), where the system has one; --symmetric solves
// the exact orbits among the symmetric states (ExactOptions::mirror_symmetric).
// --fd-multipliers N checks each exact orbit's Floquet multipliers against the eigenvalues of the
// integrator's period map differentiated at that orbit by central differences (N samples a
// period, steps of 1e-6 of the state's size in each displacement of every DOF and velocity of
// each DOF with mass; two periods a direction): the multipliers off the unit circle (those at 1
// are the held positions of stuck nodes, the projected ones 0), largest first, side by side.
// With --no-integrator and neither --start nor --warmup, the exact orbit is the one hbf timeint
// --method exact finds from rest (exact_steady_state), its multipliers from its own state.
#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <complex>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/output_file.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"
#include "integrator_check.hpp"
#include "model/mirror.hpp"
#include "state_file.hpp"

using namespace hbf;
using bench::read_state;
using bench::write_state;

namespace {
using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point start) { return std::chrono::duration<double>(clock_type::now() - start).count(); }

double mean_share(const std::vector<ContactRegime>& contacts, bool open) {
    double sum = 0.0;
    for (const ContactRegime& c : contacts) sum += open ? c.separated_fraction : c.stick_fraction;
    return contacts.empty() ? 0.0 : sum / static_cast<double>(contacts.size());
}

/// The largest difference over the nodes of `a`'s and `b`'s per-node shares of the period
/// stuck, open and slipping (the rest), in that order.
std::array<double, 3> node_share_gaps(const std::vector<ContactRegime>& a, const std::vector<ContactRegime>& b) {
    std::array<double, 3> gap{0.0, 0.0, 0.0};
    for (std::size_t c = 0; c < std::min(a.size(), b.size()); ++c) {
        const double slip_a = 1.0 - a[c].stick_fraction - a[c].separated_fraction;
        const double slip_b = 1.0 - b[c].stick_fraction - b[c].separated_fraction;
        gap[0] = std::max(gap[0], std::abs(a[c].stick_fraction - b[c].stick_fraction));
        gap[1] = std::max(gap[1], std::abs(a[c].separated_fraction - b[c].separated_fraction));
        gap[2] = std::max(gap[2], std::abs(slip_a - slip_b));
    }
    return gap;
}

/// `samples`-step periods of law unilateral's integrator from `state` ([y, y'] of every DOF): the
/// state after `periods` of them.
Eigen::VectorXd integrator_flow(const System& system, double omega, const Eigen::VectorXd& state, int periods,
                                int samples) {
    TimeIntegrationOptions o;
    o.samples_per_period = samples;
    o.min_periods = o.max_periods = periods;  // the state after them starts the recorded period
    o.steady_tolerance = TimeIntegrationOptions::largest_steady_tolerance;
    o.shooting = false;
    o.stick_restart = false;
    const PeriodicResponse r = integrate_steady_state(system, omega, o, &state);
    if (r.periods != periods + 1) throw std::runtime_error("the integrator's flow stopped: " + r.message);
    return r.state.head(2 * system.dofs());
}

/// The eigenvalues of the integrator's period map differentiated at `state` by central
/// differences: in y of every DOF and y' of each DOF with mass (the massless DOFs' velocities
/// are not states of the flow), steps of 1e-6 of max |y| (velocities: times omega).
Eigen::VectorXcd integrator_multipliers(const System& system, double omega, const Eigen::VectorXd& state, int samples) {
    const int n = system.dofs();
    const Eigen::VectorXd mass = Eigen::MatrixXd(system.mass).diagonal();
    std::vector<int> coordinates;
    for (int i = 0; i < n; ++i) coordinates.push_back(i);
    for (int i = 0; i < n; ++i)
        if (mass(i) != 0.0) coordinates.push_back(n + i);
    const auto m = static_cast<Eigen::Index>(coordinates.size());
    const double size = std::max(state.head(n).cwiseAbs().maxCoeff(), 1e-300);
    Eigen::MatrixXd jacobian(m, m);
    for (Eigen::Index j = 0; j < m; ++j) {
        const int c = coordinates[static_cast<std::size_t>(j)];
        const double h = 1e-6 * size * (c >= n ? omega : 1.0);
        Eigen::VectorXd plus = state, minus = state;
        plus(c) += h;
        minus(c) -= h;
        const Eigen::VectorXd a = integrator_flow(system, omega, plus, 1, samples);
        const Eigen::VectorXd b = integrator_flow(system, omega, minus, 1, samples);
        for (Eigen::Index k = 0; k < m; ++k) {
            const int r = coordinates[static_cast<std::size_t>(k)];
            jacobian(k, j) = (a(r) - b(r)) / (2.0 * h);
        }
    }
    return Eigen::EigenSolver<Eigen::MatrixXd>(jacobian, false).eigenvalues();
}

/// The multipliers off the unit circle (| |mu| - 1 | > 1e-3) and above 1e-3, largest |mu| first
/// (a complex pair once, Im >= 0); `unit` counts those on it.
std::vector<std::complex<double>> off_unit(const Eigen::VectorXcd& multipliers, int& unit) {
    std::vector<std::complex<double>> kept;
    unit = 0;
    for (const std::complex<double>& mu : multipliers) {
        if (std::abs(std::abs(mu) - 1.0) <= 1e-3) {
            ++unit;
        } else if (std::abs(mu) > 1e-3 && mu.imag() >= -1e-12 * std::abs(mu)) {
            kept.push_back(mu);
        }
    }
    std::sort(kept.begin(), kept.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
    return kept;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"exact orbits of the mitred bar end against time integration"};
    std::vector<double> omegas = {12000.0};
    int samples = 1024;
    std::string stepping = "automatic", file = std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml";
    double force_scale = 1.0, steady = 1e-8;
    int max_events = 2000, warmup = 2, check_samples = 0, fd_samples = 0;
    bool no_integrator = false;
    bool messages = false;
    bool symmetric = false;
    std::string start_file, save_file, save_sweep_file;
    app.add_option("--w", omegas, "frequencies [rad/s]")->delimiter(',');
    app.add_option("--samples", samples, "the integrator's coarse samples a period (fine: twice)");
    app.add_option("--stepping", stepping, "automatic, taylor or collocation");
    std::string newton = "automatic";
    app.add_option("--newton", newton, "Newton's steps: automatic (the flow's derivative first) or differences (GMRES on central differences)")
        ->check(CLI::IsMember({"automatic", "differences"}));
    app.add_option("--config", file, "the system file");
    app.add_option("--force-scale", force_scale, "a factor on the file's excitation");
    app.add_option("--steady-tol", steady, "the integrator's steady-state tolerance");
    app.add_option("--max-events", max_events, "the exact solver's events a period at most");
    app.add_flag("--no-integrator", no_integrator,
                 "the exact orbit alone, from rest after --warmup exact periods (where the integrator fails)");
    app.add_option("--warmup", warmup, "with --no-integrator: exact periods from rest before Newton")
        ->check(CLI::Range(0, 1000));
    app.add_option("--start", start_file, "with --no-integrator: the exact orbit's start, [y, y'] of every DOF, one a line");
    app.add_option("--save-orbit", save_file, "the last converged exact orbit's state, one number a line");
    app.add_option("--save-sweep", save_sweep_file, "with --sweep: the sweep's last converged orbit's state, one number a line");
    std::vector<double> sweep;
    app.add_option("--sweep", sweep, "A,B,K: first an exact sweep of K frequencies from A to B (up or down), each from the previous orbit")
        ->delimiter(',')
        ->expected(3);
    app.add_flag("--messages", messages, "with --sweep: each point's solve message under its line (the path it took)");
    app.add_flag("--symmetric", symmetric, "exact orbits among the mirror-symmetric states (ExactOptions::mirror_symmetric)");
    app.add_option("--fd-multipliers", fd_samples,
                   "the exact multipliers against the integrator's period map's, by central differences at N samples");
    app.add_option("--check-samples", check_samples,
                   "two periods of the integrator from the exact state at N, 2N, 4N samples: outputs and per-node shares")
        ->check(CLI::Range(0, 1 << 20));
    CLI11_PARSE(app, argc, argv);
    // --save-orbit and --save-sweep may not replace an input of the run (the start, the system
    // file) nor each other: checked first.
    try {
        std::vector<io::OutputTarget> targets;
        if (!save_file.empty()) targets.push_back({"--save-orbit", save_file, true, false, false});
        if (!save_sweep_file.empty()) targets.push_back({"--save-sweep", save_sweep_file, true, false, false});
        if (!targets.empty()) io::check_outputs(targets, {{"--start", start_file}, {"--config", file}});
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mitre_exact: %s\n", e.what());
        return 2;
    }
    Eigen::VectorXd given_start;
    io::SystemConfig config;
    try {
        if (!start_file.empty()) given_start = read_state("--start", start_file);
        config = io::read_system_config(file);
        if (given_start.size() > 0 && given_start.size() != 2 * config.system.dofs())
            throw std::runtime_error("--start " + start_file + " has " + std::to_string(given_start.size()) +
                                     " numbers: the state of " + file + " has " + std::to_string(2 * config.system.dofs()));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mitre_exact: %s\n", e.what());
        return 2;
    }
    System system = config.system;
    system.excitation *= force_scale;
    const std::vector<Output>& outputs = config.outputs;
    const ConeStepping choice = stepping == "taylor"        ? ConeStepping::taylor
                                : stepping == "collocation" ? ConeStepping::collocation
                                                            : ConeStepping::automatic;
    const ConeNewton newton_choice = newton == "differences" ? ConeNewton::differences : ConeNewton::automatic;
    nlohmann::json all = nlohmann::json::array();
    // Where the model is mirror-symmetric (the mitre about its mid-plane): each orbit's distance
    // from its mirror image at t = 0 (the largest |P y - y| over the DOFs; 0 for a symmetric
    // orbit, the held positions' walk for one a sweep pushed sideways).
    const std::optional<hbf::detail::Mirror> mirror = hbf::detail::find_mirror(system);
    auto mirror_note = [&](const Eigen::VectorXd& state) {
        if (!mirror || state.size() < system.dofs()) return std::string();
        char text[64];
        std::snprintf(text, sizeof text, ", mirror offset %.2e", hbf::detail::mirror_offset(*mirror, state.head(system.dofs())));
        return std::string(text);
    };
    // The exact sweep: seconds per point, and its orbits by frequency.
    std::vector<PeriodicResponse> swept;
    double sweep_seconds = 0.0;
    if (!sweep.empty()) {
        const int points = static_cast<int>(sweep[2]);
        if (points < 2 || !(sweep[0] > 0.0) || !(sweep[1] > 0.0) || sweep[0] == sweep[1]) {
            std::fprintf(stderr, "mitre_exact: --sweep A,B,K needs A, B > 0, A != B (A > B: a sweep down) and K >= 2\n");
            return 2;
        }
        ExactOptions eo;
        eo.max_events_per_period = max_events;
        eo.outputs = outputs;
        eo.mirror_symmetric = symmetric;
        eo.dof_maxima = false;
        if (app.count("--warmup") > 0) eo.warmup_periods = std::max(1, warmup);
        const auto start = clock_type::now();
        int failed = 0;
        for (int k = 0; k < points; ++k) {
            const double omega = sweep[0] + (sweep[1] - sweep[0]) * k / (points - 1);
            const auto t0 = clock_type::now();
            PeriodicResponse r = exact_steady_state(system, omega,
                                                    app.count("--warmup") > 0 ? eo : exact_sweep_options(system, eo, !swept.empty() || given_start.size() > 0),
                                                    200, exact_sweep_start(system, omega, swept, given_start));
            const double seconds = seconds_since(t0);
            if (r.converged) {
                std::printf("sweep w = %g: y365 max %.12g amp1 %.12g, stuck %.6f open %.6f, %d periods, %.2f s, |mu| %.6f%s\n", omega,
                            r.output_max[0], r.output_amp1[0], mean_share(r.contacts, false), mean_share(r.contacts, true),
                            r.periods, seconds, r.max_multiplier, mirror_note(r.state).c_str());
                if (messages) std::printf("  %s\n", r.message.c_str());
            } else {
                ++failed;
                std::printf("sweep w = %g: NOT converged (%s), %.2f s\n", omega, r.message.c_str(), seconds);
            }
            std::fflush(stdout);
            swept.push_back(std::move(r));
        }
        sweep_seconds = seconds_since(start);
        for (auto r = swept.rbegin(); r != swept.rend() && !save_sweep_file.empty(); ++r)
            if (r->converged) {
                write_state("--save-sweep", save_sweep_file, r->state);
                break;
            }
        std::printf("sweep: %d points (%d not converged) in %.1f s, %.3f s a point\n", points, failed, sweep_seconds,
                    sweep_seconds / points);
    }
    double ti_total = 0.0;
    int ti_runs = 0;
    for (double omega : omegas) {
        nlohmann::json row;
        row["w"] = omega;
        PeriodicResponse ti[2];
        double ti_seconds[2];
        for (int k = 0; k < 2 && !no_integrator; ++k) {
            TimeIntegrationOptions o;
            o.samples_per_period = samples << k;
            o.steady_tolerance = steady;
            o.max_periods = 20000;
            o.outputs = outputs;
            const auto start = clock_type::now();
            ti[k] = k == 1 && !ti[0].converged ? ti[0] : integrate_steady_state(system, omega, o, k == 1 ? &ti[0].state : nullptr);
            ti_seconds[k] = seconds_since(start);
        }
        for (int k = 0; k < 2 && !no_integrator; ++k)
            if (!ti[k].converged) std::printf("  integrator %d samples: %s\n", samples << k, ti[k].message.c_str());
        if (!no_integrator) {
            ti_total += ti_seconds[0] + ti_seconds[1];
            ++ti_runs;
        }
        ExactOptions eo;
        eo.max_events_per_period = max_events;
        eo.outputs = outputs;
        eo.mirror_symmetric = symmetric;
        eo.dof_maxima = false;
        const auto start = clock_type::now();
        Eigen::VectorXd exact_start = no_integrator ? given_start : ti[1].state;
        if (no_integrator && given_start.size() == 0 && app.count("--warmup") == 0) {
            // hbf timeint --method exact's orbit from rest (its options); the multipliers from its state
            const PeriodicResponse from_rest = exact_steady_state(system, omega, eo, 200, {});
            if (from_rest.converged) exact_start = from_rest.state;
        } else if (no_integrator) {
            eo.warmup_periods = std::max(1, warmup);
        }
        // --check-samples: two periods of the integrator from the exact state at N, 2N and 4N
        // samples, the second one's outputs and per-node shares against the exact orbit's.
        auto check_from_exact = [&](const ExactOrbit& exact, nlohmann::json& row) {
            for (int k = 0; k < 3 && exact.converged && check_samples > 0; ++k) {
                // two periods from the exact state: the second's metrics
                const TimeIntegrationOptions o = bench::two_periods_from_state(check_samples << k, outputs);
                const auto t0 = clock_type::now();
                const PeriodicResponse one = integrate_steady_state(system, omega, o, &exact.state);
                if (!one.converged) {
                    std::printf("  the integrator at %d samples from the exact state: %s\n", check_samples << k,
                                one.message.c_str());
                    continue;
                }
                std::printf("  the integrator at %d samples from the exact state (%.1f s): its change over a period %.3e; "
                            "its second period relative to exact:",
                            check_samples << k, seconds_since(t0), one.poincare_change);
                for (std::size_t j = 0; j < outputs.size(); ++j) {
                    const double m = exact.output_max[j], a = exact.output_amp1[j];
                    std::printf(" %s max %.3e amp1 %.3e;", outputs[j].name().c_str(), (one.output_max[j] - m) / m,
                                a > 1e-9 * m ? (one.output_amp1[j] - a) / a : one.output_amp1[j] / m);
                }
                const std::array<double, 3> gap = node_share_gaps(one.contacts, exact.contacts);
                std::printf(" stuck %.6f open %.6f; per node, largest |share - exact|: stuck %.1e open %.1e slip %.1e\n",
                            mean_share(one.contacts, false), mean_share(one.contacts, true), gap[0], gap[1], gap[2]);
                std::fflush(stdout);
                nlohmann::json check;
                check["samples"] = check_samples << k;
                check["change"] = one.poincare_change;
                for (std::size_t j = 0; j < outputs.size(); ++j) {
                    check[outputs[j].name() + "_max"] = one.output_max[j];
                    check[outputs[j].name() + "_amp1"] = one.output_amp1[j];
                }
                check["stuck_share"] = mean_share(one.contacts, false);
                check["open_share"] = mean_share(one.contacts, true);
                check["node_share_gaps"] = {gap[0], gap[1], gap[2]};
                row["check"].push_back(check);
            }
        };
        const ExactOrbit exact = rigid_periodic_orbit(system, omega, exact_start, eo, choice, newton_choice);
        const double exact_seconds = seconds_since(start);
        if (exact.converged && fd_samples > 0) {
            const auto t0 = clock_type::now();
            const Eigen::VectorXcd fd = integrator_multipliers(system, omega, exact.state, fd_samples);
            int unit_exact = 0, unit_fd = 0;
            const auto a = off_unit(exact.multipliers, unit_exact), b = off_unit(fd, unit_fd);
            std::printf("  multipliers (|mu|, arg) off the unit circle, exact against the integrator's period map at %d "
                        "samples (%.1f s; on it: %d exact, %d integrator; largest |mu| %.9f):\n",
                        fd_samples, seconds_since(t0), unit_exact, unit_fd, exact.max_multiplier);
            double worst = 0.0;
            for (std::size_t k = 0; k < std::min<std::size_t>(a.size(), 10) && !b.empty(); ++k) {
                // the integrator's nearest
                const auto near = *std::min_element(b.begin(), b.end(), [&](auto x, auto y) {
                    return std::abs(x - a[k]) < std::abs(y - a[k]);
                });
                std::printf("    %.7f %+.5f   %.7f %+.5f   |d mu| %.1e\n", std::abs(a[k]), std::arg(a[k]), std::abs(near),
                            std::arg(near), std::abs(a[k] - near));
                worst = std::max(worst, std::abs(a[k] - near));
            }
            if (!b.empty() && (a.empty() || std::abs(b[0]) > std::abs(a[0]) + 1e-3))
                std::printf("    the integrator's largest off the unit circle, %.7f, exceeds the exact one's\n", std::abs(b[0]));
            row["fd_samples"] = fd_samples;
            row["fd_largest_difference"] = worst;
            row["fd_off_unit"] = {a.size(), b.size()};
            if (!a.empty() && !b.empty()) row["fd_largest_off_unit"] = {std::abs(a[0]), std::abs(b[0])};
        }
        if (exact.converged && !save_file.empty()) write_state("--save-orbit", save_file, exact.state);
        if (no_integrator) {
            std::printf("w = %g: exact %s (%s) in %.1f s, %d events, %d Newton iterations, %d periods, residual %.3e%s\n",
                        omega, exact.converged ? "converged" : "NOT converged", exact.message.c_str(), exact_seconds,
                        exact.switches, exact.iterations, exact.periods, exact.residual, mirror_note(exact.state).c_str());
            for (std::size_t j = 0; j < outputs.size() && exact.converged; ++j)
                std::printf("  %s: max %.12g amp1 %.12g\n", outputs[j].name().c_str(), exact.output_max[j],
                            exact.output_amp1[j]);
            if (exact.converged)
                std::printf("  stuck share %.6f, open share %.6f, max multiplier %.6f\n", mean_share(exact.contacts, false),
                            mean_share(exact.contacts, true), exact.max_multiplier);
            check_from_exact(exact, row);
            row["exact_converged"] = exact.converged;
            row["exact_seconds"] = exact_seconds;
            for (std::size_t j = 0; j < outputs.size() && exact.converged; ++j) {
                row[outputs[j].name() + "_max"] = exact.output_max[j];
                row[outputs[j].name() + "_amp1"] = exact.output_amp1[j];
            }
            if (exact.converged) row["max_multiplier"] = exact.max_multiplier;
            std::fflush(stdout);
            all.push_back(row);
            continue;
        }
        std::printf("w = %g: integrator %d/%d samples %s/%s in %.1f/%.1f s; exact %s (%s) in %.1f s, %d events\n", omega,
                    samples, 2 * samples, ti[0].converged ? "converged" : "NOT converged",
                    ti[1].converged ? "converged" : "NOT converged", ti_seconds[0], ti_seconds[1],
                    exact.converged ? "converged" : "NOT converged", exact.message.c_str(), exact_seconds, exact.switches);
        row["exact_converged"] = exact.converged;
        row["exact_seconds"] = exact_seconds;
        row["ti_seconds"] = {ti_seconds[0], ti_seconds[1]};
        for (std::size_t j = 0; j < outputs.size() && exact.converged; ++j) {
            for (int amp = 0; amp < 2; ++amp) {
                const double e = amp ? exact.output_amp1[j] : exact.output_max[j];
                const double c = amp ? ti[0].output_amp1[j] : ti[0].output_max[j];
                const double f = amp ? ti[1].output_amp1[j] : ti[1].output_max[j];
                const double richardson = 2.0 * f - c;
                std::printf("  %s %s: exact %.12g  TI %.3e %.3e  Richardson %.3e (relative to exact)\n",
                            outputs[j].name().c_str(), amp ? "amp1" : "max ", e, (c - e) / e, (f - e) / e,
                            (richardson - e) / e);
                row[outputs[j].name() + (amp ? "_amp1" : "_max")] = {e, c, f};
            }
        }
        if (exact.converged) {
            std::printf("  stuck share %.6f (TI %.6f), open share %.6f (TI %.6f)\n", mean_share(exact.contacts, false),
                        mean_share(ti[1].contacts, false), mean_share(exact.contacts, true), mean_share(ti[1].contacts, true));
            // the integrator counts each node's state on its steps: a share is within a step or
            // two of the period (1/N a transition) of the exact one
            for (int k = 0; k < 2; ++k) {
                const std::array<double, 3> gap = node_share_gaps(ti[k].contacts, exact.contacts);
                std::printf("  per node, largest |TI %d share - exact|: stuck %.1e open %.1e slip %.1e\n", samples << k,
                            gap[0], gap[1], gap[2]);
                row["node_share_gaps_ti" + std::to_string(k)] = {gap[0], gap[1], gap[2]};
            }
            row["stuck_share"] = mean_share(exact.contacts, false);
            row["open_share"] = mean_share(exact.contacts, true);
        }
        check_from_exact(exact, row);
        for (const PeriodicResponse& r : swept)
            if (std::abs(r.omega - omega) <= 1e-9 * omega && r.converged && exact.converged) {
                std::printf("  the sweep's orbit here against the one from the integrator's state: y365 max %.3e, amp1 %.3e, "
                            "stuck share %.2e, open share %.2e\n",
                            (r.output_max[0] - exact.output_max[0]) / exact.output_max[0],
                            (r.output_amp1[0] - exact.output_amp1[0]) / exact.output_amp1[0],
                            mean_share(r.contacts, false) - mean_share(exact.contacts, false),
                            mean_share(r.contacts, true) - mean_share(exact.contacts, true));
                row["sweep_y365_max"] = r.output_max[0];
                row["sweep_y365_amp1"] = r.output_amp1[0];
            }
        std::fflush(stdout);
        all.push_back(row);
    }
    if (!swept.empty() && ti_runs > 0)
        std::printf("the integrator from rest: %.1f s a frequency (both step sizes, %d frequencies); the exact sweep: %.3f s a "
                    "point; ratio %.0f\n",
                    ti_total / ti_runs, ti_runs, sweep_seconds / static_cast<double>(swept.size()),
                    (ti_total / ti_runs) / (sweep_seconds / static_cast<double>(swept.size())));
    std::printf("%s\n", all.dump().c_str());
    return 0;
}
