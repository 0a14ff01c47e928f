// Benchmark: one sector against the whole wheel (cyclic.hpp), in one process. The lumped bladed
// disk of benchmarks/lumped_wheel.hpp with N sectors, engine order 3, H harmonics: the cost of
// one Newton step of harmonic balance (residual, dense Jacobian, LU solve) on the sector and on
// the whole wheel assembled by hand, at a stick-slip point of the sector's FRF (the wheel at the
// sector's solution placed on every sector). A continuation makes the same number of steps
// either way, so the ratio is the cost ratio of the FRF. Also the sector's whole FRF time.
// The last line is one JSON object with every case.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "hbf/cyclic.hpp"
#include "hbf/frf.hpp"
#include "hbf/harmonic_balance.hpp"
#include "lumped_wheel.hpp"

using namespace hbf;

namespace {

/// Seconds per call of fn, over enough repetitions for about 0.3 s (at least 3).
template <typename F>
double per_call(F&& fn) {
    using clock = std::chrono::steady_clock;
    int repetitions = 3;
    while (true) {
        const auto start = clock::now();
        for (int r = 0; r < repetitions; ++r) fn();
        const double seconds = std::chrono::duration<double>(clock::now() - start).count();
        if (seconds > 0.3) return seconds / repetitions;
        repetitions *= 2;
    }
}

/// One Newton step: residual, Jacobian, LU solve.
double newton_step(HarmonicBalance& hb, const Eigen::VectorXd& x, double omega) {
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    return per_call([&] {
        hb.evaluate(x, omega, r, &j);
        const Eigen::VectorXd dx = j.partialPivLu().solve(r);
        if (!dx.allFinite()) std::cerr << "cyclic: a singular Jacobian\n";
    });
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("One sector against the whole wheel: the cost of a harmonic-balance Newton step");
    std::vector<int> sectors = {6, 12, 24};
    int harmonics = 5;
    app.add_option("--sectors", sectors, "numbers of sectors N")->capture_default_str();
    app.add_option("--harmonics", harmonics, "H")->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    nlohmann::json cases = nlohmann::json::array();
    std::printf("%8s %10s %14s %14s %10s %12s\n", "sectors", "unknowns", "sector step s", "wheel step s", "ratio",
                "sector FRF s");
    for (const int n : sectors) {
        const System s = bench::lumped_sector(n, 3 % n, 0.05);
        const NodalDiameterFamily released = nodal_diameter_family(s, false), stuck = nodal_diameter_family(s, true);
        const int d = nodal_diameter(s.cyclic, 1);
        FrfChoices choices;
        choices.omega_start = 0.8 * released.frequencies(d, 0);
        choices.omega_end = 1.2 * stuck.frequencies(d, 0);
        choices.harmonics = harmonics;
        FrfSettings settings = frf_settings(s, {Output::dof(2)}, choices);
        settings.error_points = 0;
        const auto start = std::chrono::steady_clock::now();
        const FrfResult frf = compute_frf(s, settings);
        const double frf_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // a stick-slip point (else the middle one)
        std::size_t p = frf.points.size() / 2;
        for (std::size_t k = 0; k < frf.points.size(); ++k)
            if (frf.metrics[k].regime == "stick-slip") p = k;
        const double omega = frf.points[p].omega;
        HarmonicBalanceOptions o;
        o.harmonics = harmonics;
        o.formulation = Formulation::full;
        HarmonicBalance sector_hb(s, o);
        const System w = bench::lumped_wheel(s);
        HarmonicBalance wheel_hb(w, o);
        const Eigen::MatrixXd y = sector_hb.dofs(frf.points[p].x, omega);
        const Eigen::VectorXd x = bench::placed_on_wheel(s, y);
        const double sector_step = newton_step(sector_hb, frf.points[p].x, omega);
        const double wheel_step = newton_step(wheel_hb, x, omega);
        std::printf("%8d %4d/%5d %14.3e %14.3e %10.1f %12.3f\n", n, sector_hb.unknowns(), wheel_hb.unknowns(),
                    sector_step, wheel_step, wheel_step / sector_step, frf_seconds);
        cases.push_back({{"sectors", n},
                         {"harmonics", harmonics},
                         {"sector_unknowns", sector_hb.unknowns()},
                         {"wheel_unknowns", wheel_hb.unknowns()},
                         {"sector_step_seconds", sector_step},
                         {"wheel_step_seconds", wheel_step},
                         {"ratio", wheel_step / sector_step},
                         {"sector_frf_seconds", frf_seconds},
                         {"sector_frf_points", frf.points.size()}});
    }
    std::cout << cases.dump() << "\n";
    return 0;
}
