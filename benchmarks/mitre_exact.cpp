// Benchmark and verification: the exact periodic orbit of the mitred bar end
// (examples/systems/mitre: 27 rigid 3D contact nodes on a massless-boundary model) against law
// unilateral's time integrator, at chosen frequencies, in one process. Per frequency: the
// integrator's steady state at N and 2N samples a period (its error falls like 1/N where slip
// directions turn: the Richardson value 2 y(2N) - y(N) is its limit), the exact orbit from the
// fine state (rigid_exact.hpp, --stepping automatic: Taylor series where the slip directions
// are not stiff, implicit collocation where they are), each output's max |o(t)| and first
// harmonic by the three, the interface's stuck and open shares, and the seconds of each. The
// last line is one JSON object with every frequency.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"

using namespace hbf;

namespace {
using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point start) { return std::chrono::duration<double>(clock_type::now() - start).count(); }

double mean_share(const std::vector<ContactRegime>& contacts, bool open) {
    double sum = 0.0;
    for (const ContactRegime& c : contacts) sum += open ? c.separated_fraction : c.stick_fraction;
    return contacts.empty() ? 0.0 : sum / static_cast<double>(contacts.size());
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"exact orbits of the mitred bar end against time integration"};
    std::vector<double> omegas = {12000.0};
    int samples = 1024;
    std::string stepping = "automatic", file = std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml";
    double force_scale = 1.0, steady = 1e-8;
    int max_events = 2000, warmup = 2;
    bool no_integrator = false;
    app.add_option("--w", omegas, "frequencies [rad/s]")->delimiter(',');
    app.add_option("--samples", samples, "the integrator's coarse samples a period (fine: twice)");
    app.add_option("--stepping", stepping, "automatic, taylor or collocation");
    app.add_option("--config", file, "the system file");
    app.add_option("--force-scale", force_scale, "a factor on the file's excitation");
    app.add_option("--steady-tol", steady, "the integrator's steady-state tolerance");
    app.add_option("--max-events", max_events, "the exact solver's events a period at most");
    app.add_flag("--no-integrator", no_integrator,
                 "the exact orbit alone, from rest after --warmup exact periods (where the integrator fails)");
    app.add_option("--warmup", warmup, "with --no-integrator: exact periods from rest before Newton")
        ->check(CLI::Range(0, 1000));
    CLI11_PARSE(app, argc, argv);
    const io::SystemConfig config = io::read_system_config(file);
    System system = config.system;
    system.excitation *= force_scale;
    const std::vector<Output>& outputs = config.outputs;
    const ConeStepping choice = stepping == "taylor"        ? ConeStepping::taylor
                                : stepping == "collocation" ? ConeStepping::collocation
                                                            : ConeStepping::automatic;
    nlohmann::json all = nlohmann::json::array();
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
        ExactOptions eo;
        eo.max_events_per_period = max_events;
        eo.outputs = outputs;
        eo.dof_maxima = false;
        if (no_integrator) eo.warmup_periods = warmup;
        const auto start = clock_type::now();
        const ExactOrbit exact =
            rigid_periodic_orbit(system, omega, no_integrator ? Eigen::VectorXd() : ti[1].state, eo, choice);
        const double exact_seconds = seconds_since(start);
        if (no_integrator) {
            std::printf("w = %g: exact %s (%s) in %.1f s, %d events, %d Newton iterations, %d periods, residual %.3e\n",
                        omega, exact.converged ? "converged" : "NOT converged", exact.message.c_str(), exact_seconds,
                        exact.switches, exact.iterations, exact.periods, exact.residual);
            for (std::size_t j = 0; j < outputs.size() && exact.converged; ++j)
                std::printf("  %s: max %.12g amp1 %.12g\n", outputs[j].name().c_str(), exact.output_max[j],
                            exact.output_amp1[j]);
            if (exact.converged)
                std::printf("  stuck share %.6f, open share %.6f, max multiplier %.6f\n", mean_share(exact.contacts, false),
                            mean_share(exact.contacts, true), exact.max_multiplier);
            row["exact_converged"] = exact.converged;
            row["exact_seconds"] = exact_seconds;
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
        if (exact.converged)
            std::printf("  stuck share %.6f (TI %.6f), open share %.6f (TI %.6f)\n", mean_share(exact.contacts, false),
                        mean_share(ti[1].contacts, false), mean_share(exact.contacts, true), mean_share(ti[1].contacts, true));
        std::fflush(stdout);
        all.push_back(row);
    }
    std::printf("%s\n", all.dump().c_str());
    return 0;
}
