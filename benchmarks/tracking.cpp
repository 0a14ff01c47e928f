// Benchmark: following peaks through a parameter (tracking.hpp) against computing whole FRFs, in
// one process, single-threaded (ratios of wall times on the same machine and load):
//  1. the absorber's exact Coulomb peak curve (fe = 1, mu 0.3..1, 40 values): hbf track with
//     --at against 40 FRFs with refined peaks (what hbf map computes); the largest differences
//     of the largest peak in w and y_max;
//  2. the friction coefficient that minimises the largest peak (fe = 0.5, mu in 0.005..5, scan
//     of 13): tracking against the golden-section search at its default tolerance 1e-4 and at
//     1e-8, for wa = 1 and wa = 1/(1 + r); the optima's differences.
// Usage: tracking [--threads N] (FRFs of the scans on N threads; default 1).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "hbf/tracking.hpp"
#include "hbf/absorber.hpp"

namespace {
using namespace hbf;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

int main(int argc, char** argv) {
    CLI::App app("tracking against whole FRFs");
    int threads = 1;
    app.add_option("--threads", threads, "FRFs of the scans at once")->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    // 1. The peak curve.
    AbsorberParameters p1;
    p1.excitation = 1.0;
    const auto absorber = [&](double mu) {
        AbsorberParameters p = p1;
        p.friction_coefficient = mu;
        return friction_absorber(p, FrictionLaw::coulomb);
    };
    const FrfSettings settings = default_frf_settings(absorber(0.3), {});
    std::vector<double> values;
    for (int k = 0; k < 40; ++k) values.push_back(0.3 + 0.7 * k / 39.0);
    values.back() = 1.0;
    auto t0 = Clock::now();
    const std::vector<FrfResult> frfs =
        compute_frfs(40, [&](int k) { return absorber(values[static_cast<std::size_t>(k)]); }, settings, 1);
    const double map_seconds = since(t0);
    TrackOptions o;
    o.p_start = 0.3;
    o.p_end = 1.0;
    o.at = values;
    t0 = Clock::now();
    const TrackResult r = track(absorber, settings, o);
    const double track_seconds = since(t0);
    double dw = 0.0, dy = 0.0;
    for (std::size_t k = 0; k < values.size(); ++k) {
        double w = 0.0, y = -1.0;
        for (const TrackCurve& c : r.curves)
            for (const TrackPoint& q : c.points)
                if (std::abs(q.p - values[k]) <= 1e-12 && (q.kind == "at" || q.kind == "start") && q.value > y) {
                    y = q.value;
                    w = q.omega;
                }
        dw = std::max(dw, std::abs(w - frfs[k].peak.omega) / w);
        dy = std::max(dy, std::abs(y - frfs[k].peak.value) / y);
    }
    std::printf("1. peak curve, exact Coulomb absorber, fe = 1, mu 0.3..1 at 40 values\n");
    std::printf("   40 FRFs (hbf map, 1 thread): %.2f s; tracking: %.2f s (%lld exact solves, %d FRFs); ratio %.2f\n",
                map_seconds, track_seconds, r.solves, r.frfs, map_seconds / track_seconds);
    std::printf("   largest peak: max |dw|/w = %.1e, max |dy|/y = %.1e; %s\n", dw, dy, r.summary().c_str());

    // 2. The optimum friction coefficient.
    std::printf("2. optimum mu (fe = 0.5, mu in 0.005..5, scan 13)\n");
    for (double wa : {1.0, 1.0 / 1.1}) {
        AbsorberParameters p2;
        p2.tuning_ratio = wa;
        const auto tuned = [&](double mu) {
            AbsorberParameters p = p2;
            p.friction_coefficient = mu;
            return friction_absorber(p, FrictionLaw::coulomb);
        };
        const FrfSettings s2 = default_frf_settings(tuned(0.2), {});
        OptimizeOptions oo;
        oo.lower = 0.005;
        oo.upper = 5.0;
        oo.threads = threads;
        t0 = Clock::now();
        const TrackOptimum tr = optimize_by_tracking(tuned, s2, oo);
        const double tracking_seconds = since(t0);
        t0 = Clock::now();
        const OptimizeResult g4 = optimize_parameter(tuned, s2, oo);
        const double golden4 = since(t0);
        oo.tolerance = 1e-8;
        t0 = Clock::now();
        const OptimizeResult g8 = optimize_parameter(tuned, s2, oo);
        const double golden8 = since(t0);
        std::printf("   wa = %.6f: tracking mu = %.12f (%s, %d FRFs, %lld solves) %.2f s\n", wa, tr.parameter,
                    tr.kind.c_str(), tr.frfs, tr.solves, tracking_seconds);
        std::printf("     golden 1e-4: mu = %.12f (%zu FRFs) %.2f s: |dmu|/mu = %.1e, time ratio golden/tracking %.2f\n",
                    g4.parameter, g4.trace.size(), golden4, std::abs(g4.parameter - tr.parameter) / tr.parameter,
                    golden4 / tracking_seconds);
        std::printf("     golden 1e-8: mu = %.12f (%zu FRFs) %.2f s: |dmu|/mu = %.1e, time ratio golden/tracking %.2f\n",
                    g8.parameter, g8.trace.size(), golden8, std::abs(g8.parameter - tr.parameter) / tr.parameter,
                    golden8 / tracking_seconds);
    }
    return 0;
}
