// Benchmark: the exact periodic orbit of rigid unilateral contacts on massless nodes
// (rigid_exact.hpp) against law unilateral's time integrator to its steady state
// (time_integration.hpp: velocity Verlet with a complementarity solve a step), at the same
// frequencies, in one process. Two models: examples/systems/liftoff3_rigid.toml (one contact,
// stick-slip at w = 1.2 and 2.0, lift-off at 2.5) and chains of n masses each pressing a
// massless node onto a wall (contact_chain.hpp), whose contacts stick, slip and open at
// different times.
// The chains are taken at the first frequency of a scan where their orbit is stable and has
// events; the 3D chain (contact_chain_3d: forces along both tangential directions, slip along
// curved paths; Taylor flows and a differenced period map) at w = 0.6 and 2.0, where it is. Per case: the integrator's seconds to its steady state (from rest, 1024 samples a period,
// steady tolerance 1e-10), the exact solver's from rest and from the integrator's final state,
// their ratios, and how far the two answers are apart (relative, first harmonic of output 1).
// The last line is one JSON object with every case.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"

#include "contact_chain.hpp"

using namespace hbf;

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point start) {
    return std::chrono::duration<double>(clock_type::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Exact orbits of rigid unilateral contacts against law unilateral's time integrator"};
    std::string source = HBF_SOURCE_DIR;
    app.add_option("--source", source, "the repository (for examples/systems/liftoff3_rigid.toml)");
    CLI11_PARSE(app, argc, argv);
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each case's line as it is measured
    struct Case {
        std::string name;
        System system;
        std::vector<Output> outputs;
        double omega;
    };
    const io::SystemConfig liftoff = io::read_system_config(source + "/examples/systems/liftoff3_rigid.toml");
    std::vector<Case> cases;
    for (double w : {1.2, 2.0, 2.5}) cases.push_back({"liftoff3_rigid", liftoff.system, liftoff.outputs, w});
    // the chains at the first frequency of a scan whose orbit (from rest) is stable: an unstable
    // one has no steady state for the integrator to reach
    for (int n : {3, 8}) {
        const System chain = bench::contact_chain(n, 0.3);
        for (double w : {1.0, 1.3, 1.6, 2.0, 0.8, 2.5}) {
            const ExactOrbit probe = rigid_periodic_orbit(chain, w, Eigen::VectorXd());
            if (probe.converged && probe.stable && probe.switches > 2) {
                cases.push_back({"chain" + std::to_string(n), chain, {Output::dof(0)}, w});
                break;
            }
        }
    }
    const System chain_3d = bench::contact_chain_3d(3, 1.0, 0.8);
    for (double w : {0.6, 2.0}) cases.push_back({"chain3_3d", chain_3d, {Output::dof(0)}, w});
    nlohmann::json all = nlohmann::json::array();
    std::printf("%-16s %6s %8s %10s %10s %10s %10s %10s %10s\n", "model", "w", "events", "TI s", "exact s",
                "cold s", "TI/exact", "TI/cold", "gap");
    for (const Case& c : cases) {
        TimeIntegrationOptions ti;
        ti.samples_per_period = 1024;
        ti.steady_tolerance = 1e-10;
        ti.max_periods = 3000;
        ti.outputs = c.outputs;
        auto start = clock_type::now();
        const PeriodicResponse r = integrate_steady_state(c.system, c.omega, ti);
        const double ti_seconds = seconds_since(start);
        ExactOptions options;
        options.outputs = c.outputs;
        start = clock_type::now();
        int repetitions = 0;
        ExactOrbit warm;
        do {
            warm = rigid_periodic_orbit(c.system, c.omega, r.state, options);
            ++repetitions;
        } while (seconds_since(start) < 0.2);
        const double exact_seconds = seconds_since(start) / repetitions;
        start = clock_type::now();
        const ExactOrbit cold = rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), options);
        const double cold_seconds = seconds_since(start);
        const double gap = r.converged && warm.converged
                               ? std::abs(r.output_amp1[0] - warm.output_amp1[0]) / warm.output_amp1[0]
                               : NAN;
        std::printf("%-16s %6.3g %8d %10.4g %10.4g %10.4g %10.4g %10.4g %10.3g%s%s\n", c.name.c_str(), c.omega,
                    warm.switches, ti_seconds, exact_seconds, cold_seconds, ti_seconds / exact_seconds,
                    ti_seconds / cold_seconds, gap, warm.converged ? "" : "  (exact: not converged)",
                    cold.converged ? "" : "  (cold: not converged)");
        all.push_back({{"model", c.name},
                       {"omega", c.omega},
                       {"events", warm.switches},
                       {"time_integration_seconds", ti_seconds},
                       {"time_integration_converged", r.converged},
                       {"exact_seconds", exact_seconds},
                       {"exact_converged", warm.converged},
                       {"cold_seconds", cold_seconds},
                       {"cold_converged", cold.converged},
                       {"cold_stable", cold.stable},
                       {"ratio", ti_seconds / exact_seconds},
                       {"amp1_gap", gap}});
    }
    std::printf("%s\n", all.dump().c_str());
    return 0;
}
