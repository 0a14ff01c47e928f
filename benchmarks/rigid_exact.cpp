// Benchmark: the exact periodic orbit of rigid unilateral contacts on massless nodes
// (rigid_exact.hpp) against law unilateral's time integrator to its steady state
// (time_integration.hpp: velocity Verlet with a complementarity solve a step), at the same
// frequencies, in one process. Two models: examples/systems/liftoff3_rigid.toml (one contact,
// stick-slip at w = 1.2 and 2.0, lift-off at 2.5) and a chain of n masses, each pressing a
// massless node onto a wall (the node of contact c tied to mass c along the wall and to mass
// c + 1 across it, preloads differing), whose contacts stick, slip and open at different times.
// Per case: the integrator's seconds to its steady state (from rest, 1024 samples a period,
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

using namespace hbf;

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point start) {
    return std::chrono::duration<double>(clock_type::now() - start).count();
}

/// n masses in a chain (grounded at both ends), each pressing a massless contact node onto a wall.
System contact_chain(int n, double force) {
    const int size = 3 * n;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size), K = M, C = M;
    auto spring = [&K](int a, int b, double k) {
        K(a, a) += k;
        K(b, b) += k;
        K(a, b) -= k;
        K(b, a) -= k;
    };
    Eigen::VectorXd F = Eigen::VectorXd::Zero(size), S = Eigen::VectorXd::Zero(size);
    System s;
    for (int i = 0; i < n; ++i) {
        M(i, i) = 1.0 - 0.5 * i / n;
        C(i, i) = 0.02 * M(i, i);
        if (i + 1 < n) spring(i, i + 1, 1.5);
        F(i) = force * std::cos(2.0 * i);
    }
    K(0, 0) += 2.0;
    K(n - 1, n - 1) += 0.5;
    for (int c = 0; c < n; ++c) {
        const int t = n + 2 * c, v = t + 1, across = (c + 1) % n;
        spring(c, t, 3.0 + (c % 3));
        spring(across, v, 5.0 - (c % 2));
        const double preload = 0.6 + 0.4 * ((c * 7) % 5) / 4.0;
        S(v) += preload;
        S(across) -= preload;
        Contact k;
        k.law = parse_friction_law("unilateral");
        k.dof = t;
        k.values["friction_coefficient"] = 0.3;
        k.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(size), 0.0);
        k.lists["normal_direction"][static_cast<std::size_t>(v)] = 1.0;
        s.contacts.push_back(k);
    }
    s.mass = M.sparseView();
    s.stiffness = K.sparseView();
    s.damping = C.sparseView();
    s.excitation = F;
    s.static_load = S;
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Exact orbits of rigid unilateral contacts against law unilateral's time integrator"};
    std::string source = HBF_SOURCE_DIR;
    app.add_option("--source", source, "the repository (for examples/systems/liftoff3_rigid.toml)");
    CLI11_PARSE(app, argc, argv);
    struct Case {
        std::string name;
        System system;
        std::vector<Output> outputs;
        double omega;
    };
    const io::SystemConfig liftoff = io::read_system_config(source + "/examples/systems/liftoff3_rigid.toml");
    std::vector<Case> cases;
    for (double w : {1.2, 2.0, 2.5}) cases.push_back({"liftoff3_rigid", liftoff.system, liftoff.outputs, w});
    for (int n : {3, 8}) cases.push_back({"chain" + std::to_string(n), contact_chain(n, 0.3), {Output::dof(0)}, 1.0});
    nlohmann::json all = nlohmann::json::array();
    std::printf("%-16s %6s %8s %10s %10s %10s %10s %10s %10s\n", "model", "w", "events", "TI s", "exact s",
                "cold s", "TI/exact", "TI/cold", "gap");
    for (const Case& c : cases) {
        TimeIntegrationOptions ti;
        ti.samples_per_period = 1024;
        ti.steady_tolerance = 1e-10;
        ti.max_periods = 20000;
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
