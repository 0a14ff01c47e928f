// Verification: periodic orbits of law elastic (contacts with a normal direction and mass at the
// nodes, e.g. the block example's Craig-Bampton model) and their stability, two ways: from the
// time integrator alone (its event-driven CVODE flow, the stick, slip and separation events
// located, as the period map P, and Newton with a Jacobian built here), and by the library's
// periodic-orbit solver (elastic_exact.hpp) from the same saved states:
//   1. --periods N integrates N periods from rest (the static state under the preloads), one at
//      a time, and prints per period the mean of each output over the period (zero on a
//      half-wave symmetric orbit, y(t + T/2) = -y(t), for the outputs the symmetry turns over),
//      its first harmonic and the Poincare change; the state after the periods in --save-at
//      is written to STEM_<k>.txt (--save-stem STEM);
//   2. --shoot FILE solves P(x) = x by Newton's method from the state in FILE: the Jacobian of
//      P by forward differences (steps of --step times the state's scale: displacements and
//      sliders max |y|, velocities omega max |y|; one period per coordinate; the contacts'
//      discrete modes taken from the period's end), at most --newton iterations, and prints the
//      eigenvalues of the last Jacobian: the orbit's Floquet multipliers to the differences'
//      accuracy (the integrator's tolerance over the step: about 1e-4 with the defaults). Each
//      iterate is written to --save-orbit;
//   3. --orbit FILE runs elastic_periodic_orbit from the state in FILE (Newton-Krylov beyond 64
//      continuous states, the dominant multipliers by Arnoldi) and prints its status, the
//      multipliers and each output's mean, max and first harmonic on the orbit; --time-limit
//      bounds it (a stop is reported, exit 1).
#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/output_file.hpp"
#include "hbf/time_integration.hpp"
#include "state_file.hpp"

using namespace hbf;
using bench::read_state;
using bench::write_state;

namespace {
using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point start) { return std::chrono::duration<double>(clock_type::now() - start).count(); }
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"law elastic: periods from rest, Newton shooting on the integrator's period map, multipliers"};
    std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/block/block.toml", shoot, save_stem, save_orbit,
                orbit_from;
    double omega = 17900.0, step = 1e-6, orbit_tolerance = 1e-9, time_limit = 3600.0;
    int periods = 0, newton = 6;
    std::vector<int> save_at;
    app.add_option("--config", file, "a system file of law elastic contacts");
    app.add_option("--w", omega, "the frequency [rad/s]");
    app.add_option("--periods", periods, "periods from rest, each printed");
    app.add_option("--save-at", save_at, "periods after which the state is written")->delimiter(',');
    app.add_option("--save-stem", save_stem, "the states' file stem (STEM_<period>.txt)");
    app.add_option("--shoot", shoot, "Newton shooting from the state in this file");
    app.add_option("--newton", newton, "Newton iterations at most");
    app.add_option("--step", step, "the differences' step, relative to the state's scale");
    app.add_option("--save-orbit", save_orbit, "the last Newton iterate");
    app.add_option("--orbit", orbit_from, "the library's periodic-orbit solver from the state in this file");
    app.add_option("--orbit-tolerance", orbit_tolerance, "its Newton tolerance (relative residual)");
    app.add_option("--time-limit", time_limit, "seconds the library's solver may take");
    CLI11_PARSE(app, argc, argv);
    try {
        std::vector<io::OutputTarget> targets;
        if (!save_orbit.empty()) targets.push_back({"--save-orbit", save_orbit, true, false, false});
        for (int k : save_at) targets.push_back({"--save-at", save_stem + "_" + std::to_string(k) + ".txt", true, false, false});
        io::check_outputs(targets, {{"--shoot", shoot}, {"--orbit", orbit_from}, {"--config", file}});
        if (!save_at.empty() && save_stem.empty()) throw std::runtime_error("--save-at needs --save-stem");
        if (!(omega > 0.0) || periods < 0 || newton < 0 || !(step > 0.0) || !(time_limit > 0.0))
            throw std::runtime_error("--w, --step, --time-limit > 0 and --periods, --newton >= 0");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "elastic_shooting: %s\n", e.what());
        return 2;
    }
    const io::SystemConfig config = io::read_system_config(file);
    const System& system = config.system;
    const std::vector<Output>& outputs = config.outputs;
    const int n = system.dofs(), size = state_size(system), nc = static_cast<int>(system.contacts.size());
    const int continuous = size - nc;  // y, y', the sliders; then one discrete mode per contact
    std::printf("%s: %d DOFs, state %d (%d continuous), w = %g\n", file.c_str(), n, size, continuous, omega);
    const auto start = clock_type::now();

    // 1. periods from rest, each printed
    TimeIntegrationOptions o;
    o.min_periods = o.max_periods = 1;
    o.steady_tolerance = TimeIntegrationOptions::largest_steady_tolerance;  // a period is recorded once below it
    o.shooting = false;
    o.stick_restart = false;
    o.outputs = outputs;
    Eigen::VectorXd x;
    for (int k = 1; k <= periods; ++k) {
        const PeriodicResponse r = integrate_steady_state(system, omega, o, x.size() > 0 ? &x : nullptr);
        if (r.state.size() != size) {
            std::printf("period %d: %s\n", k, r.message.c_str());
            return 1;
        }
        x = r.state;
        if (std::find(save_at.begin(), save_at.end(), k) != save_at.end())
            write_state("--save-at", save_stem + "_" + std::to_string(k) + ".txt", x);
        std::printf("period %d:", k);
        if (r.converged) {  // the next period's signals (change below 1e-2)
            for (std::size_t j = 0; j < outputs.size(); ++j)
                std::printf(" %s mean %+.5e amp1 %.5e;", outputs[j].name().c_str(),
                            outputs[j].combine(r.displacement).mean(), r.output_amp1[j]);
        }
        std::printf(" change %.3e (%.0f s)\n", r.poincare_change, seconds_since(start));
        std::fflush(stdout);
    }
    if (!orbit_from.empty()) {
        // 3. the library's solver from a saved state
        const Eigen::VectorXd from = read_state("--orbit", orbit_from);
        ExactOptions e;
        e.tolerance = orbit_tolerance;
        e.outputs = outputs;
        e.samples = 512;
        e.dof_maxima = false;
        e.stop = [&]() { return seconds_since(start) > time_limit ? std::string("--time-limit") : std::string(); };
        const ExactOrbit r = elastic_periodic_orbit(system, omega, from, e);
        std::printf("elastic_periodic_orbit from %s: %s%s; %d periods, %d Newton iterations (%.0f s)\n",
                    orbit_from.c_str(), r.converged ? "" : "NOT converged: ", r.message.c_str(), r.periods,
                    r.iterations, seconds_since(start));
        if (!r.converged) return 1;
        std::vector<std::complex<double>> sorted(r.multipliers.data(), r.multipliers.data() + r.multipliers.size());
        std::sort(sorted.begin(), sorted.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
        std::printf("  multipliers, largest |mu| (arg):");
        for (std::size_t k = 0; k < std::min<std::size_t>(sorted.size(), 10); ++k)
            std::printf(" %.6f (%+.4f)", std::abs(sorted[k]), std::arg(sorted[k]));
        std::printf("\n  %s\n", r.stable                   ? "stable"
                                 : r.stability_unresolved() ? "stability uncertain (within the differences' accuracy of 1)"
                                                            : "UNSTABLE");
        for (std::size_t j = 0; j < outputs.size(); ++j)
            std::printf("  %s: mean %+.6e max %.6e amp1 %.6e\n", outputs[j].name().c_str(),
                        outputs[j].combine(r.displacement).mean(), r.output_max[j], r.output_amp1[j]);
        if (!save_orbit.empty()) write_state("--save-orbit", save_orbit, r.state);
        return 0;
    }
    if (shoot.empty()) return 0;

    // 2. Newton shooting on P with a forward-difference Jacobian
    x = read_state("--shoot", shoot);
    if (x.size() != size) {
        std::fprintf(stderr, "elastic_shooting: --shoot %s has %ld numbers, the state %d\n", shoot.c_str(),
                     static_cast<long>(x.size()), size);
        return 2;
    }
    TimeIntegrationOptions one = o;
    one.steady_tolerance = TimeIntegrationOptions::smallest_steady_tolerance;  // one period, not recorded
    auto period = [&](const Eigen::VectorXd& a) {
        const PeriodicResponse r = integrate_steady_state(system, omega, one, &a);
        if (r.state.size() != size) throw std::runtime_error("the period failed: " + r.message);
        return Eigen::VectorXd(r.state);
    };
    const double ys = x.head(n).cwiseAbs().maxCoeff();
    Eigen::VectorXd scale(continuous);
    for (int i = 0; i < continuous; ++i) scale(i) = i >= n && i < 2 * n ? ys * omega : ys;
    Eigen::MatrixXd jacobian(continuous, continuous);
    for (int it = 0; it <= newton; ++it) {
        const Eigen::VectorXd p = period(x);
        const Eigen::VectorXd residual = (p.head(continuous) - x.head(continuous)).cwiseQuotient(scale);
        int changed = 0;
        for (int c = 0; c < nc; ++c) changed += p(continuous + c) != x(continuous + c);
        std::printf("Newton %d: |P(x) - x| / scale %.3e (modes that differ at the period's end: %d) (%.0f s)\n", it,
                    residual.cwiseAbs().maxCoeff(), changed, seconds_since(start));
        std::fflush(stdout);
        if (it == newton) break;
        for (int j = 0; j < continuous; ++j) {
            Eigen::VectorXd a = x;
            a(j) += step * scale(j);
            jacobian.col(j) = (period(a).head(continuous) - p.head(continuous)).cwiseQuotient(scale) / step;
        }
        const Eigen::VectorXcd mu = Eigen::EigenSolver<Eigen::MatrixXd>(jacobian, false).eigenvalues();
        std::vector<std::complex<double>> sorted(mu.data(), mu.data() + mu.size());
        std::sort(sorted.begin(), sorted.end(), [](auto a, auto b) { return std::abs(a) > std::abs(b); });
        std::printf("  the Jacobian's eigenvalues, largest |mu| (arg):");
        for (std::size_t k = 0; k < std::min<std::size_t>(sorted.size(), 10); ++k)
            std::printf(" %.6f (%+.4f)", std::abs(sorted[k]), std::arg(sorted[k]));
        const Eigen::VectorXd dz =
            (jacobian - Eigen::MatrixXd::Identity(continuous, continuous)).fullPivLu().solve(-residual);
        std::printf("; Newton step %.3e (%.0f s)\n", dz.cwiseAbs().maxCoeff(), seconds_since(start));
        std::fflush(stdout);
        x.head(continuous) += dz.cwiseProduct(scale);
        x.tail(nc) = p.tail(nc);
        if (!save_orbit.empty()) write_state("--save-orbit", save_orbit, x);
    }
    // the orbit's outputs: two periods from the last iterate, the second recorded
    TimeIntegrationOptions two = o;
    two.min_periods = two.max_periods = 1;
    const PeriodicResponse r = integrate_steady_state(system, omega, two, &x);
    if (r.converged)
        for (std::size_t j = 0; j < outputs.size(); ++j)
            std::printf("  %s: mean %+.6e max %.6e amp1 %.6e\n", outputs[j].name().c_str(),
                        outputs[j].combine(r.displacement).mean(), r.output_max[j], r.output_amp1[j]);
    return 0;
}
