// Benchmark: the same FRF of the paper's absorber by harmonic balance + continuation and by
// time integration (a CVODE sweep), in this process, for each friction law and excitation:
//   - HB: everything a user waits for — the HarmonicBalance set-up, continue_branch over
//     [wmin, wmax], sample_branch at the grid frequencies (every solution of the branch
//     there) and the Analyser's y_max of each sample;
//   - TI: sweep() up the same uniform grid, each point starting from the previous steady state,
//     with tolerances per law that keep it well more accurate than HB (default_time_integration);
//   - each side is run `--repeats` times and the fastest run is reported;
//   - the largest relative difference in y1_max (relative to the TI value) over the grid
//     points where both converged; where the HB branch has several solutions at a frequency
//     (folds) the one nearest to the TI value is compared. Grid points without a converged
//     counterpart on either side (e.g. between two unbounded resonances, where the HB branch
//     stops at its amplitude cap) are excluded and counted, with the reason;
//   - the accuracy of the TI itself: at every compared point (`--check-every K`: every K-th)
//     the steady state is recomputed with tight tolerances (rtol 1e-12, atol 1e-14, steady-tol
//     1e-10) from the TI's own final state, so on the same attractor, untimed; the largest
//     relative change of y1_max is reported; against the same tight TI the largest errors of HB
//     and of the exact polish are reported too;
//   - for the laws the event-exact solver covers (coulomb, jenkins), a third side: HB + exact
//     polish as `hbf frf` runs it by default (H = 10, HB's own transitions off, every grid sample
//     polished by exact_polish.hpp), timed like HB, with its speed-up over the TI sweep.
// With `--config FILE --at W1,W2,...` (a finite-element system, e.g. the 200-DOF beam) it
// times instead the whole FRF by HB over the file's frequency range (its harmonics; condensed)
// against BDF time integration at the given frequencies only, compares y_max of the first
// reported DOF there, and reports the ratio of a TI sweep as fine as the HB branch
// (TI seconds per frequency x branch points) to the HB FRF. It times as well the FRF that
// `hbf frf --config FILE --at W1,...` computes by default (frf.hpp: frf_settings; with the
// exact polish where the exact solver covers the model), compares its samples with the TI and
// reports the same ratio for it.
// The last line is one JSON object with all figures. Run by hand: `build/benchmarks/hb_vs_timeint`.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/time_integration.hpp"

using namespace hbf;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}


/// The TI tolerances of this benchmark by default, measured (README, Benchmarks): per law the
/// fastest set on the ladder rtol 1e-10..1e-4 (atol = rtol / 100, steady-tol 1e-8..1e-4) whose
/// y1_max stays within 1/10 of the HB-TI difference against a tight TI in every case, so that
/// the difference measures HB, not the TI.
/// Exact Coulomb (event-driven): rtol 1e-6, atol 1e-8, steady-tol 1e-5: |TI - tight TI| <=
/// 7e-5 relative (HB at H = 20 differs by 1e-2), in 0.4 of the time of hbf timeint's
/// defaults; rtol 1e-5 / steady-tol 1e-4 reaches 1.3e-3.
/// Dahl and LuGre: rtol 1e-9, atol 1e-11, steady-tol 1e-7: <= 2e-6 (HB at H = 10 differs by
/// 7e-5..3e-4), 20% faster than hbf timeint's defaults. Looser does not pay for them: at rtol
/// 1e-8 or 1e-7 the sweeps take up to 4x longer (the Poincare iteration and its shooting
/// steps stall on the integration noise), with errors up to 3e-5 and an unconverged point.
TimeIntegrationOptions default_time_integration(FrictionLaw law) {
    TimeIntegrationOptions o;
    if (law == FrictionLaw::coulomb) {
        o.relative_tolerance = 1e-6;
        o.absolute_tolerance = 1e-8;
        o.steady_tolerance = 1e-5;
    } else {
        o.relative_tolerance = 1e-9;
        o.absolute_tolerance = 1e-11;
        o.steady_tolerance = 1e-7;
    }
    return o;
}

/// One grid point: the TI value and the HB solutions there.
struct GridPoint {
    double omega = 0;
    bool ti_converged = false;
    double ti_y1_max = 0, ti_seconds = 0;
    int ti_periods = 0;
    std::string ti_regime;
    std::vector<double> hb_y1_max;  ///< every HB solution at omega (several where the branch folds)
    std::vector<double> exact_y1_max;  ///< every polished solution at omega (coulomb, jenkins)
    double hb_nearest = std::numeric_limits<double>::quiet_NaN();
    double rel_diff = std::numeric_limits<double>::quiet_NaN();
    double ti_error = std::numeric_limits<double>::quiet_NaN();  ///< vs the tight TI (checked points)
    std::string excluded;  ///< reason, empty if compared
};

struct Case {
    std::string law;
    double fe = 0;
    int harmonics = 0, time_samples = 0, points = 0, branch_points = 0;
    std::string branch_status, branch_message;
    double hb_seconds = 0, continuation_seconds = 0, timeint_seconds = 0;
    long ti_periods = 0;
    int compared = 0, excluded = 0, multiple = 0, checked = 0, unchecked = 0;
    double max_rel_diff = 0, max_rel_diff_omega = 0;
    double ti_error = 0;  ///< largest relative change of y1_max vs the tight TI
    double hb_error = 0;  ///< largest relative error of HB (nearest solution) vs the tight TI
    // HB + exact polish (coulomb, jenkins; exact_harmonics = 0: not run)
    int exact_harmonics = 0, exact_failed = 0;
    double exact_seconds = 0, exact_error = 0;
    double tight_seconds = 0;  ///< a TI sweep with the tight tolerances (the exact side's accuracy class)
    std::map<std::string, int> reasons;
    std::vector<GridPoint> grid;
};

Case run_case(const AbsorberParameters& p, FrictionLaw law, int harmonics, const std::vector<double>& grid,
              const ContinuationOptions& co, const TimeIntegrationOptions& tio,
              const TimeIntegrationOptions& tight, int check_every, int repeats) {
    Case c;
    c.law = to_string(law);
    c.fe = p.excitation;
    c.harmonics = harmonics;
    c.points = static_cast<int>(grid.size());
    c.grid.resize(grid.size());
    const System system = friction_absorber(p, law);

    // ---- harmonic balance: set-up, continuation, samples at the grid, y_max (fastest of `repeats`) ----
    BranchResult branch;
    std::vector<SolutionPoint> samples;
    std::vector<double> sample_y1;
    int time_samples = 0;
    for (int repeat = 0; repeat < repeats; ++repeat) {
        const auto hb_start = std::chrono::steady_clock::now();
        HarmonicBalance hb(system, HarmonicBalanceOptions{harmonics, 0});
        branch = continue_branch(hb, co);
        samples = sample_branch(hb, branch, grid, co.corrector);
        Analyser analyse(hb);
        sample_y1.resize(samples.size());
        for (std::size_t k = 0; k < samples.size(); ++k) sample_y1[k] = analyse(samples[k]).y_max[0];
        const double elapsed = seconds_since(hb_start);
        if (repeat == 0 || elapsed < c.hb_seconds) c.hb_seconds = elapsed;
        time_samples = hb.time_samples();
    }
    c.continuation_seconds = branch.seconds;
    c.time_samples = time_samples;
    c.branch_points = static_cast<int>(branch.points.size());
    c.branch_status = to_string(branch.status);
    c.branch_message = branch.message;
    // sample_branch returns the samples frequency by frequency, in the order of `grid`.
    for (std::size_t k = 0, g = 0; k < samples.size(); ++k) {
        while (g < grid.size() && grid[g] != samples[k].omega) ++g;
        if (g < grid.size()) c.grid[g].hb_y1_max.push_back(sample_y1[k]);
    }

    // ---- time integration: a sweep up the grid (fastest of `repeats`) ----
    std::vector<PeriodicResponse> ti;
    for (int repeat = 0; repeat < repeats; ++repeat) {
        const auto ti_start = std::chrono::steady_clock::now();
        ti = sweep(system, grid, tio);
        const double elapsed = seconds_since(ti_start);
        if (repeat == 0 || elapsed < c.timeint_seconds) c.timeint_seconds = elapsed;
    }

    // ---- HB + exact polish, as hbf frf by default (fastest of `repeats`) ----
    if (exact_solver_supports(system)) {
        c.exact_harmonics = 10;
        PolishedBranch polished;
        for (int repeat = 0; repeat < repeats; ++repeat) {
            const auto start = std::chrono::steady_clock::now();
            HarmonicBalance hb(system, HarmonicBalanceOptions{c.exact_harmonics, 0});
            ContinuationOptions pco = co;
            pco.locate_transitions = false;
            const BranchResult b = continue_branch(hb, pco);
            const std::vector<SolutionPoint> at = sample_branch(hb, b, grid, co.corrector);
            Analyser analyse(hb);
            std::vector<PointMetrics> metrics;
            for (const SolutionPoint& q : at) metrics.push_back(analyse(q));
            PolishOptions po;
            po.transitions = false;
            po.peaks = false;
            polished = polish_branch(hb, at, metrics, po, co.corrector);
            const double elapsed = seconds_since(start);
            if (repeat == 0 || elapsed < c.exact_seconds) c.exact_seconds = elapsed;
        }
        c.exact_failed = polished.failed;
        // The CVODE sweep at the tight tolerances of the reference: what a TI needs to come
        // near the exact polish's accuracy (1e-10 and better).
        for (int repeat = 0; repeat < repeats; ++repeat) {
            const auto start = std::chrono::steady_clock::now();
            (void)sweep(system, grid, tight);
            const double elapsed = seconds_since(start);
            if (repeat == 0 || elapsed < c.tight_seconds) c.tight_seconds = elapsed;
        }
        for (std::size_t k = 0, g = 0; k < polished.points.size(); ++k) {
            while (g < grid.size() && grid[g] != polished.points[k].omega) ++g;
            if (g < grid.size() && polished.exact[k].status == PolishStatus::exact)
                c.grid[g].exact_y1_max.push_back(polished.metrics[k].y_max[0]);
        }
    }

    // ---- comparison ----
    for (std::size_t g = 0; g < grid.size(); ++g) {
        GridPoint& gp = c.grid[g];
        const PeriodicResponse& r = ti[g];
        gp.omega = grid[g];
        gp.ti_converged = r.converged;
        gp.ti_y1_max = r.y_max[0];
        gp.ti_seconds = r.seconds;
        gp.ti_periods = r.periods;
        gp.ti_regime = r.regime;
        c.ti_periods += r.periods;
        if (!gp.hb_y1_max.empty()) {
            gp.hb_nearest = *std::min_element(gp.hb_y1_max.begin(), gp.hb_y1_max.end(), [&](double a, double b) {
                return std::abs(a - gp.ti_y1_max) < std::abs(b - gp.ti_y1_max);
            });
        }
        if (gp.hb_y1_max.empty() && !r.converged)
            gp.excluded = "neither HB nor TI";
        else if (gp.hb_y1_max.empty())
            gp.excluded = branch.status == ContinuationStatus::amplitude_cap
                              ? "no HB solution (between the branch ends at the amplitude cap)"
                              : "no HB solution (branch " + c.branch_status + ")";
        else if (!r.converged)
            gp.excluded = "TI not converged";
        if (!gp.excluded.empty()) {
            ++c.excluded;
            ++c.reasons[gp.excluded];
            continue;
        }
        ++c.compared;
        if (gp.hb_y1_max.size() > 1) ++c.multiple;
        gp.rel_diff = std::abs(gp.hb_nearest - gp.ti_y1_max) / gp.ti_y1_max;
        if (gp.rel_diff > c.max_rel_diff) {
            c.max_rel_diff = gp.rel_diff;
            c.max_rel_diff_omega = gp.omega;
        }
    }

    // ---- accuracy of the TI (untimed): tight tolerances from the TI's own final state, at
    // every check_every-th compared point (those that enter max_rel_diff) ----
    if (check_every > 0) {
        int counter = 0;
        for (std::size_t g = 0; g < grid.size(); ++g) {
            if (!c.grid[g].excluded.empty() || counter++ % check_every != 0) continue;
            const PeriodicResponse ref = integrate_steady_state(system, grid[g], tight, &ti[g].state);
            if (!ref.converged) {
                ++c.unchecked;
                continue;
            }
            const double y = ref.y_max[0];
            c.grid[g].ti_error = std::abs(ti[g].y_max[0] - y) / y;
            c.ti_error = std::max(c.ti_error, c.grid[g].ti_error);
            auto nearest_error = [&](const std::vector<double>& values) {
                double best = std::numeric_limits<double>::infinity();
                for (double v : values) best = std::min(best, std::abs(v - y) / y);
                return best;
            };
            c.hb_error = std::max(c.hb_error, nearest_error(c.grid[g].hb_y1_max));
            if (c.exact_harmonics > 0) c.exact_error = std::max(c.exact_error, nearest_error(c.grid[g].exact_y1_max));
            ++c.checked;
        }
    }
    return c;
}

std::string format_reasons(const std::map<std::string, int>& reasons) {
    std::string text;
    for (const auto& [reason, count] : reasons) text += (text.empty() ? "" : "; ") + std::to_string(count) + " " + reason;
    return text;
}

}  // namespace

/// The finite-element mode (--config): see the header comment.
int run_config(const std::string& path, const std::vector<double>& omegas, double rtol, double steady_tol) {
    const io::SystemConfig config = io::read_system_config(path);
    const Output& output = config.outputs.front();
    HarmonicBalanceOptions ho;
    ho.harmonics = config.choices.harmonics.value_or(20);
    ho.time_samples = config.choices.time_samples.value_or(0);
    ContinuationOptions co;
    co.omega_start = config.choices.omega_start.value_or(omegas.front());
    co.omega_end = config.choices.omega_end.value_or(omegas.back());
    for (double w : omegas)
        if (!(w >= co.omega_start && w <= co.omega_end))
            throw InvalidInput("--at w = " + std::to_string(w) + " is outside the file's range [" +
                               std::to_string(co.omega_start) + ", " + std::to_string(co.omega_end) + "]");
    const auto hb_start = std::chrono::steady_clock::now();
    HarmonicBalance hb(config.system, ho);
    const BranchResult branch = continue_branch(hb, co);
    const std::vector<SolutionPoint> samples = sample_branch(hb, branch, omegas, co.corrector);
    Analyser analyse(hb, {}, {output});
    std::vector<std::vector<double>> hb_y(omegas.size());
    for (const SolutionPoint& p : samples)
        for (std::size_t i = 0; i < omegas.size(); ++i)
            if (p.omega == omegas[i]) hb_y[i].push_back(analyse(p).output_max.front());
    const double hb_seconds = seconds_since(hb_start);
    const int branch_points = static_cast<int>(branch.points.size());
    std::printf("%s: N = %d DOFs, %zu contact(s), H = %d (%s): HB FRF over [%g, %g]: %d branch points in %.3f s (%s)\n",
                path.c_str(), config.system.dofs(), config.system.contacts.size(), hb.harmonics(),
                to_string(hb.formulation()).c_str(), co.omega_start, co.omega_end, branch_points, hb_seconds,
                to_string(branch.status).c_str());
    // The default FRF, as hbf frf --config FILE --at ... computes it.
    FrfSettings settings = frf_settings(config.system, {output}, config.choices);
    settings.at = omegas;
    const auto default_start = std::chrono::steady_clock::now();
    const FrfResult frf = compute_frf(config.system, settings);
    const double default_seconds = seconds_since(default_start);
    std::vector<double> default_y(omegas.size(), std::numeric_limits<double>::quiet_NaN());
    int default_points = 0;
    for (std::size_t k = 0; k < frf.points.size(); ++k) {
        if (frf.points[k].kind != PointKind::sample) {
            ++default_points;
            continue;
        }
        for (std::size_t i = 0; i < omegas.size(); ++i)
            if (frf.points[k].omega == omegas[i]) default_y[i] = frf.metrics[k].output_max.front();
    }
    const bool polished = frf.polish.has_value();
    std::printf("default FRF (hbf frf --config, %s, H = %d): %d branch points in %.3f s (%s)%s\n",
                polished ? "exact polish" : "harmonic balance", settings.harmonic_balance.harmonics, default_points,
                default_seconds, frf.status().c_str(),
                polished ? (": " + frf.polish->summary()).c_str() : "");
    std::printf("TI: BDF, rtol %g, atol 1e-10 (relative to the response scale), steady-tol %g; y = max over one period of |%s(t)|\n\n", rtol, steady_tol,
                output.name().c_str());
    std::fflush(stdout);
    std::printf("%10s %14s %14s %10s %14s %10s %10s %8s %10s\n", "w", "y TI", "y HB", "rel. diff", "y default",
                "rel. diff", "TI [s]", "periods", "regime TI");
    TimeIntegrationOptions to;
    to.method = IntegrationMethod::bdf;
    to.relative_tolerance = rtol;
    // relative to the response scale (the default; on the beam 1e-10 s = 1.8e-13 m; 1e-12 s made
    // the 40 rad/s point 3.3x slower for y_max changes of 1e-9)
    to.absolute_tolerance = 1e-10;
    to.steady_tolerance = steady_tol;
    to.outputs = {output};
    to.validate();
    nlohmann::json points = nlohmann::json::array();
    double ti_total = 0, worst = 0, default_worst = 0;
    for (std::size_t i = 0; i < omegas.size(); ++i) {
        const PeriodicResponse r = integrate_steady_state(config.system, omegas[i], to);
        ti_total += r.seconds;
        const double y_ti = r.output_max.front();
        double y_hb = std::numeric_limits<double>::quiet_NaN(), diff = y_hb;
        for (double y : hb_y[i])
            if (!(std::abs(y - y_ti) >= std::abs(y_hb - y_ti))) y_hb = y;
        diff = std::abs(y_hb - y_ti) / y_ti;
        const double default_diff = std::abs(default_y[i] - y_ti) / y_ti;
        if (r.converged) {
            worst = std::max(worst, diff);
            if (!(default_diff <= default_worst)) default_worst = default_diff;  // NaN propagates
        }
        std::printf("%10g %14.8e %14.8e %10.2e %14.8e %10.2e %10.2f %8d %10s%s\n", omegas[i], y_ti, y_hb, diff,
                    default_y[i], default_diff, r.seconds, r.periods, r.regime.c_str(),
                    r.converged ? "" : "  (TI not converged)");
        std::fflush(stdout);
        points.push_back({{"w", omegas[i]}, {"y_max_timeint", y_ti}, {"y_max_hb", y_hb}, {"rel_diff", diff},
                          {"y_max_default", default_y[i]}, {"default_rel_diff", default_diff},
                          {"timeint_seconds", r.seconds}, {"timeint_periods", r.periods},
                          {"timeint_converged", r.converged}, {"timeint_regime", r.regime}});
    }
    const double per_frequency = ti_total / static_cast<double>(omegas.size());
    const double ratio = per_frequency * branch_points / hb_seconds;
    const double default_ratio = per_frequency * default_points / default_seconds;
    std::printf("\nTI %.2f s per frequency; a TI sweep with as many frequencies as the HB branch (%d) would take "
                "%.0f s: %.0f times the HB FRF (%.3f s)\n",
                per_frequency, branch_points, per_frequency * branch_points, ratio, hb_seconds);
    std::printf("default FRF: a TI sweep as fine as its branch (%d) would take %.0f s: %.0f times the default FRF "
                "(%.3f s); largest difference from the TI %.2e\n",
                default_points, per_frequency * default_points, default_ratio, default_seconds, default_worst);
    std::cout << nlohmann::json{{"config", path},
                                {"dofs", config.system.dofs()},
                                {"harmonics", hb.harmonics()},
                                {"hb_seconds", hb_seconds},
                                {"hb_branch_points", branch_points},
                                {"hb_status", to_string(branch.status)},
                                {"timeint_seconds_per_frequency", per_frequency},
                                {"sweep_ratio", ratio},
                                {"default_seconds", default_seconds},
                                {"default_branch_points", default_points},
                                {"default_polished", polished},
                                {"default_sweep_ratio", default_ratio},
                                {"default_max_rel_diff", default_worst},
                                {"max_rel_diff", worst},
                                {"points", points}}
                     .dump()
              << std::endl;
    return 0;
}

int main(int argc, char** argv) {
    CLI::App app{"Times the FRF of the paper's absorber by harmonic balance + continuation and by a time-integration "
                 "sweep on the same grid, and compares their y1_max."};
    std::vector<std::string> law_names = {"coulomb", "jenkins", "dahl", "lugre"};
    std::vector<double> excitations = {0.5, 1.0};
    AbsorberParameters p;  // r = 0.1, wa = 1, mu = 0.2, wb = 0.4, xi = 0.01
    ContinuationOptions co;
    double rtol = 0, atol = 0, steady_tol = 0;  // 0: default_time_integration(law)
    TimeIntegrationOptions tight;
    tight.relative_tolerance = 1e-12;
    tight.absolute_tolerance = 1e-14;
    tight.steady_tolerance = 1e-10;  // rounding floor of the Poincare change at rtol 1e-12: ~1e-10
    tight.max_periods = 1000;
    int points = 111, harmonics = 0, check_every = 1, repeats = 3;
    std::string csv;
    app.add_option("--law", law_names,
                   "friction laws: coulomb (exact), jenkins, dahl, lugre, coulomb-reg (coulomb and jenkins also "
                   "with the exact polish)")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--fe", excitations, "excitation amplitudes fe")->delimiter(',')->capture_default_str();
    app.add_option("--wmin", co.omega_start, "first frequency")->capture_default_str();
    app.add_option("--wmax", co.omega_end, "last frequency")->capture_default_str();
    app.add_option("--points", points, "uniform grid of the TI sweep and of the HB samples")
        ->check(CLI::Range(2, 10000))
        ->capture_default_str();
    app.add_option("--harmonics", harmonics, "H for every law; 0 = hbf frf's automatic H without the polish (frf.hpp: automatic_harmonics)")
        ->check(CLI::Range(0, 200))
        ->capture_default_str();
    app.add_option("--rtol", rtol,
                   "CVODE relative tolerance of the TI for every law; 0 = per law: 1e-6 coulomb, 1e-9 others")
        ->capture_default_str();
    app.add_option("--atol", atol,
                   "CVODE absolute tolerance of the TI for every law; 0 = per law: 1e-8 coulomb, 1e-11 others")
        ->capture_default_str();
    app.add_option("--steady-tol", steady_tol,
                   "Poincare convergence tolerance of the TI for every law; 0 = per law: 1e-5 coulomb, 1e-7 "
                   "others")
        ->capture_default_str();
    app.add_option("--repeats", repeats, "runs of each side per case; the fastest is reported")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    app.add_option("--check-every", check_every,
                   "accuracy of the TI: recompute every K-th compared grid point with rtol 1e-12, atol 1e-14, "
                   "steady-tol 1e-10 (untimed); 0 = off")
        ->check(CLI::Range(0, 10000))
        ->capture_default_str();
    app.add_option("--csv", csv, "write every grid point (w, TI and HB y1_max, ...) of every case to this file");
    std::string config_path;
    std::vector<double> config_at;
    app.add_option("--config", config_path,
                   "instead of the absorber: a TOML system (e.g. examples/systems/beam/beam200.toml): the HB FRF over "
                   "its range against BDF time integration at --at");
    app.add_option("--at", config_at, "frequencies of the --config comparison")->delimiter(',');
    CLI11_PARSE(app, argc, argv);
    try {
        if (!config_path.empty()) {
            if (config_at.empty()) throw InvalidInput("--config needs --at W1,W2,...: allowed frequencies in the file's range");
            return run_config(config_path, config_at, rtol != 0 ? rtol : 1e-10, steady_tol != 0 ? steady_tol : 1e-7);
        }
        const auto time_integration = [&](FrictionLaw law) {
            TimeIntegrationOptions o = default_time_integration(law);
            if (rtol != 0) o.relative_tolerance = rtol;
            if (atol != 0) o.absolute_tolerance = atol;
            if (steady_tol != 0) o.steady_tolerance = steady_tol;
            o.validate();
            return o;
        };
        std::vector<FrictionLaw> laws;
        for (const std::string& name : law_names) {
            laws.push_back(parse_friction_law(name));
            time_integration(laws.back());  // validates the tolerances up front
        }
        const std::vector<double> grid = analytic::uniform_grid(co.omega_start, co.omega_end, points);

        std::printf("FRF of the absorber by HB + continuation and by a TI sweep: w in [%g, %g], %d grid points, "
                    "r = %g, wa = %g, mu = %g, wb = %g, xi = %g\n",
                    co.omega_start, co.omega_end, points, p.mass_ratio, p.tuning_ratio, p.friction_coefficient,
                    p.contact_stiffness_ratio, p.contact_damping_ratio);
        std::printf("HB: set-up + continuation + samples at the grid + y_max (corrector tolerance %g, amplitude cap "
                    "%g); TI: a CVODE sweep up the grid\n(%s; tolerances per case below). Fastest of %d runs each.\n",
                    co.corrector.tolerance, co.max_amplitude, to_string(TimeIntegrationOptions{}.method).c_str(),
                    repeats);
        std::printf("rel. diff = max |y1_max HB - y1_max TI| / y1_max TI over the compared points (nearest HB "
                    "solution where several);\nTI error = max |y1_max TI - y1_max tight TI| / y1_max tight TI "
                    "(rtol 1e-12, atol 1e-14, steady-tol 1e-10),\n"
                    "from the TI's final state, untimed, %s\n\n",
                    check_every == 0   ? "not checked (--check-every 0)"
                    : check_every == 1 ? "at every compared point"
                                       : ("at every " + std::to_string(check_every) + "th compared point").c_str());
        std::printf("HB err / exact err = the same for plain HB and for HB + exact polish (H = 10, coulomb and "
                    "jenkins: hbf frf's default);\nexact [s] and its speedup = TI [s] / exact [s]; tight TI [s] = the "
                    "sweep at the tight tolerances, and x tight = tight TI [s] / exact [s].\n\n");
        std::printf("%-8s %4s %3s %6s %9s %9s %8s %8s %8s %10s %7s %10s %9s %9s %8s %9s %9s %7s  %s\n", "law", "fe", "H",
                    "points", "HB [s]", "TI [s]", "speedup", "compared", "excluded", "rel. diff", "at w", "TI error",
                    "HB err", "exact [s]", "speedup", "exact err", "tight TI", "x tight", "TI rtol/atol/steady-tol");
        std::ofstream csv_file;
        if (!csv.empty()) {
            csv_file.open(csv);
            csv_file << "law,fe,w,ti_y1_max,ti_converged,ti_regime,ti_periods,ti_seconds,hb_solutions,hb_y1_max,"
                        "rel_diff,ti_error,excluded\n";
            csv_file.precision(12);
        }
        const auto total_start = std::chrono::steady_clock::now();
        nlohmann::json cases = nlohmann::json::array();
        for (FrictionLaw law : laws) {
            for (double fe : excitations) {
                AbsorberParameters q = p;
                q.excitation = fe;
                // hbf frf's automatic H without the polish (frf.hpp: the one home of it)
                const int h = harmonics > 0 ? harmonics : automatic_harmonics(friction_absorber(q, law), false);
                const TimeIntegrationOptions law_tio = time_integration(law);
                const Case c = run_case(q, law, h, grid, co, law_tio, tight, check_every, repeats);
                const double speedup = c.timeint_seconds / c.hb_seconds;
                const bool exact = c.exact_harmonics > 0;
                const std::string exact_seconds = exact ? std::to_string(c.exact_seconds).substr(0, 5) : "-";
                char exact_speedup[32] = "-", exact_error[32] = "-", tight_seconds[32] = "-", tight_ratio[32] = "-";
                if (exact) {
                    std::snprintf(tight_seconds, sizeof tight_seconds, "%.3f", c.tight_seconds);
                    std::snprintf(tight_ratio, sizeof tight_ratio, "%.1f", c.tight_seconds / c.exact_seconds);
                    std::snprintf(exact_speedup, sizeof exact_speedup, "%.1f", c.timeint_seconds / c.exact_seconds);
                    std::snprintf(exact_error, sizeof exact_error, "%.1e", c.exact_error);
                }
                std::printf("%-8s %4g %3d %6d %9.3f %9.3f %8.1f %8d %8d %10.2e %7.3f %10.1e %9.1e %9s %8s %9s %9s %7s  %g/%g/%g\n",
                            c.law.c_str(), c.fe, c.harmonics, c.points, c.hb_seconds, c.timeint_seconds, speedup,
                            c.compared, c.excluded, c.max_rel_diff, c.max_rel_diff_omega, c.ti_error, c.hb_error,
                            exact_seconds.c_str(), exact_speedup, exact_error, tight_seconds, tight_ratio,
                            law_tio.relative_tolerance,
                            law_tio.absolute_tolerance, law_tio.steady_tolerance);
                if (exact && c.exact_failed > 0)
                    std::printf("         %d grid samples whose exact polish failed (left out of exact err)\n",
                                c.exact_failed);
                if (c.multiple > 0)
                    std::printf("         %d compared points with several HB solutions (the nearest compared)\n",
                                c.multiple);
                if (c.unchecked > 0)
                    std::printf("         %d checked points whose tight TI did not converge (left out of TI error)\n",
                                c.unchecked);
                if (c.branch_status != "completed")
                    std::printf("         HB branch: %s: %s\n", c.branch_status.c_str(), c.branch_message.c_str());
                if (c.excluded > 0) std::printf("         excluded: %s\n", format_reasons(c.reasons).c_str());
                std::fflush(stdout);
                nlohmann::json reasons = nlohmann::json::object();
                for (const auto& [reason, count] : c.reasons) reasons[reason] = count;
                cases.push_back({{"law", c.law},
                                 {"fe", c.fe},
                                 {"harmonics", c.harmonics},
                                 {"time_samples", c.time_samples},
                                 {"points", c.points},
                                 {"hb_seconds", c.hb_seconds},
                                 {"continuation_seconds", c.continuation_seconds},
                                 {"timeint_seconds", c.timeint_seconds},
                                 {"speedup", speedup},
                                 {"max_rel_diff_y1_max", c.max_rel_diff},
                                 {"max_rel_diff_w", c.max_rel_diff_omega},
                                 {"compared", c.compared},
                                 {"excluded", c.excluded},
                                 {"excluded_reasons", reasons},
                                 {"hb_branch_points", c.branch_points},
                                 {"hb_branch_status", c.branch_status},
                                 {"timeint_periods", c.ti_periods},
                                 {"hb_multiple_solutions", c.multiple},
                                 {"timeint_rtol", law_tio.relative_tolerance},
                                 {"timeint_atol", law_tio.absolute_tolerance},
                                 {"timeint_steady_tol", law_tio.steady_tolerance},
                                 {"timeint_checked", c.checked},
                                 {"timeint_unchecked", c.unchecked},
                                 {"timeint_error_y1_max", c.ti_error},
                                 {"hb_error_y1_max", c.hb_error},
                                 {"exact_harmonics", c.exact_harmonics},
                                 {"exact_seconds", c.exact_seconds},
                                 {"exact_speedup", c.exact_harmonics > 0 ? c.timeint_seconds / c.exact_seconds : 0.0},
                                 {"exact_error_y1_max", c.exact_error},
                                 {"exact_failed", c.exact_failed},
                                 {"timeint_tight_seconds", c.tight_seconds}});
                if (csv_file.is_open()) {
                    for (const GridPoint& gp : c.grid)
                        csv_file << c.law << ',' << c.fe << ',' << gp.omega << ',' << gp.ti_y1_max << ','
                                 << (gp.ti_converged ? "true" : "false") << ',' << gp.ti_regime << ','
                                 << gp.ti_periods << ',' << gp.ti_seconds << ',' << gp.hb_y1_max.size() << ','
                                 << gp.hb_nearest << ',' << gp.rel_diff << ',' << gp.ti_error << ','
                                 << gp.excluded << '\n';
                }
            }
        }
        std::printf("\ntotal %.1f s (the TI accuracy checks included)\n", seconds_since(total_start));
        std::cout << nlohmann::json{{"cases", cases}}.dump() << std::endl;
    } catch (const InvalidInput& e) {
        std::cerr << "hb_vs_timeint: " << e.what() << '\n';
        return 2;
    }
    return 0;
}
