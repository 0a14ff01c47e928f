// Benchmark: the cost of the exact polish against harmonic balance alone (issue 30). The chain of
// hb_scaling (a fixed-free bar of N masses 1/N and springs N, first mode at w1 = pi/2,
// stiffness-proportional damping of 1 % at w1, the force cos(w t) at the free end) with one exact
// Coulomb contact to the ground at the free end (friction limit 0.5), over w in [1.0, 2.2].
// Per N, in one process: the default FRF (hbf frf without flags: the exact polish, H = 10), the
// same with the polish off at the same H, and harmonic balance alone at its own default H (20);
// then the default FRF of the same chain in other consistent units (mass x 1e-6, stiffness x 1e9,
// so time x sqrt(1e-15): frequencies, damping, force and friction limit scaled with them; the
// displacements are the same numbers).
//
// Printed per N: seconds of each run, the ratios polished / HB (same H) and polished / HB
// (default H), the ratio of the polished FRF's time in the other units to its time in these,
// and the largest peak of y_N in both unit systems (equal to rounding: the same physics). The
// last line is one JSON object with every case.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "chain.hpp"
#include "hbf/frf.hpp"

using namespace hbf;

namespace {

struct Run {
    double seconds = 0, peak = 0;
    std::string status;
    int points = 0;
};

Run run(const System& system, double time_unit, std::optional<bool> exact, std::optional<int> harmonics) {
    FrfChoices choices;
    choices.omega_start = 1.0 / time_unit;
    choices.omega_end = 2.2 / time_unit;
    choices.exact = exact;
    choices.harmonics = harmonics;
    const FrfSettings settings = frf_settings(system, {Output::dof(system.dofs() - 1)}, choices);
    const FrfResult frf = compute_frf(system, settings);
    Run r;
    r.seconds = frf.seconds;
    r.peak = frf.peak.value;
    r.status = frf.status();
    r.points = static_cast<int>(frf.points.size());
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Cost of the exact polish against harmonic balance on chains of N masses (issue 30)"};
    std::vector<int> sizes{10, 30, 50, 64};
    app.add_option("--dofs", sizes, "chain sizes N (the exact solver covers at most 64 DOFs)");
    CLI11_PARSE(app, argc, argv);
    nlohmann::json all = nlohmann::json::array();
    std::printf("%5s %10s %10s %10s %12s %12s %12s %12s %14s %14s\n", "N", "exact [s]", "HB10 [s]", "HB20 [s]",
                "exact/HB10", "exact/HB20", "units [s]", "units/exact", "peak", "peak (units)");
    const double mass_unit = 1e-6, stiffness_unit = 1e9, time_unit = std::sqrt(mass_unit / stiffness_unit);
    for (int n : sizes) {
        const System reference = bench::chain(n, 1), other = bench::chain(n, 1, mass_unit, stiffness_unit);
        const Run polished = run(reference, 1.0, std::nullopt, std::nullopt);
        const Run same_h = run(reference, 1.0, false, 10);
        const Run hb = run(reference, 1.0, false, std::nullopt);
        const Run units = run(other, time_unit, std::nullopt, std::nullopt);
        std::printf("%5d %10.3f %10.3f %10.3f %12.2f %12.2f %12.3f %12.2f %14.10g %14.10g\n", n, polished.seconds,
                    same_h.seconds, hb.seconds, polished.seconds / same_h.seconds, polished.seconds / hb.seconds,
                    units.seconds, units.seconds / polished.seconds, polished.peak, units.peak);
        std::fflush(stdout);
        all.push_back({{"dofs", n},
                       {"exact_seconds", polished.seconds},
                       {"exact_status", polished.status},
                       {"exact_points", polished.points},
                       {"hb10_seconds", same_h.seconds},
                       {"hb20_seconds", hb.seconds},
                       {"units_seconds", units.seconds},
                       {"units_status", units.status},
                       {"peak", polished.peak},
                       {"peak_units", units.peak}});
    }
    std::cout << all.dump() << "\n";
    return 0;
}
