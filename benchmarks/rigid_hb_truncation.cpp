// Benchmark and verification: where harmonic balance's error on a rigid contact comes from.
// examples/systems/liftoff3_rigid.toml (law unilateral on massless nodes) at chosen frequencies.
// Per frequency: the exact periodic orbit (rigid_exact.hpp) sampled finely, and for each H
//  - the truncation error: the exact orbit's own Fourier series cut at H, its max |y| against
//    the exact one's (relative) and its largest deviation from the exact signal (relative to
//    max |y|): the best harmonic balance with H harmonics could do in its representation;
//  - harmonic balance's error: the FRF point at w (hbf frf --at w, the branch from wmin) against
//    the exact orbit solved from its state (the polish), in max |y| and the first harmonic;
//  - the same at 4 and 16 times the AFT's time samples: an event-aware quadrature of the
//    contact forces would be the limit of these.
// An error that does not move with the samples is not the AFT grid's; one far above the
// truncation's is not the representation's but the projection's (the Galerkin residual of the
// contact forces). The last line is one JSON array.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/rigid_exact.hpp"

using namespace hbf;

namespace {

constexpr double pi = 3.14159265358979323846;

/// The signal y (equally spaced over a period) cut to its harmonics 0..H, at the same samples.
Eigen::VectorXd truncated(const Eigen::VectorXd& y, int harmonics) {
    const Eigen::Index n = y.size();
    Eigen::VectorXd z = Eigen::VectorXd::Constant(n, y.mean());
    for (int h = 1; h <= harmonics; ++h) {
        double a = 0.0, b = 0.0;
        for (Eigen::Index j = 0; j < n; ++j) {
            const double phase = 2.0 * pi * h * static_cast<double>(j) / static_cast<double>(n);
            a += y(j) * std::cos(phase);
            b += y(j) * std::sin(phase);
        }
        a *= 2.0 / static_cast<double>(n);
        b *= 2.0 / static_cast<double>(n);
        for (Eigen::Index j = 0; j < n; ++j) {
            const double phase = 2.0 * pi * h * static_cast<double>(j) / static_cast<double>(n);
            z(j) += a * std::cos(phase) + b * std::sin(phase);
        }
    }
    return z;
}

/// The FRF row at omega of the first output: (max, amp1), and the exact orbit's with the polish.
struct AtRow {
    bool found = false;
    double max = 0.0, amp1 = 0.0;
    bool exact = false;  // with the polish: the row is the exact orbit
    int time_samples = 0;  // the AFT's N_t
};

AtRow frf_at(const io::SystemConfig& config, double omega, int harmonics, int time_samples, bool exact) {
    FrfChoices choices = config.choices;  // the file's band and solver settings
    choices.harmonics = harmonics;
    choices.exact = exact;
    if (time_samples > 0) choices.time_samples = time_samples;
    choices.peaks = false;
    choices.peaks_of_every_output = false;
    FrfSettings settings = frf_settings(config.system, config.outputs, choices);
    settings.at = {omega};
    settings.error_points = 0;
    const FrfResult r = compute_frf(config.system, settings);
    AtRow row;
    for (std::size_t k = 0; k < r.points.size(); ++k) {
        if (r.points[k].kind != PointKind::sample || std::abs(r.points[k].omega - omega) > 1e-12 * omega) continue;
        row.found = true;
        row.max = r.metrics[k].output_max[0];
        row.amp1 = r.metrics[k].output_amp1[0];
        row.exact = exact && k < r.exact.size() && r.exact[k].status == PolishStatus::exact;
        break;
    }
    row.time_samples = r.time_samples;
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"harmonic balance's error on a rigid contact: truncation, projection and the AFT grid"};
    std::vector<double> omegas = {1.2, 2.8};
    std::vector<int> harmonics_list = {5, 10, 20, 40};
    std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";
    int samples = 16384, warmup = 200;
    app.add_option("--w", omegas, "frequencies, > 0")->delimiter(',')->check(CLI::PositiveNumber);
    app.add_option("--harmonics", harmonics_list, "H, 1..200")->delimiter(',')->check(CLI::Range(1, 200));
    app.add_option("--config", file, "the system file (law unilateral on massless nodes)");
    app.add_option("--samples", samples, "the exact orbit's samples a period")->check(CLI::Range(256, 1 << 20));
    app.add_option("--warmup", warmup, "exact periods from rest before Newton")->check(CLI::Range(1, 100000));
    CLI11_PARSE(app, argc, argv);
    io::SystemConfig config;
    try {
        config = io::read_system_config(file);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rigid_hb_truncation: %s\n", e.what());
        return 2;
    }
    nlohmann::json all = nlohmann::json::array();
    for (double omega : omegas) {
        ExactOptions eo;
        eo.samples = samples;
        eo.outputs = config.outputs;
        eo.warmup_periods = warmup;
        const ExactOrbit orbit = rigid_periodic_orbit(config.system, omega, Eigen::VectorXd(), eo);
        if (!orbit.converged) {
            std::printf("w = %g: the exact orbit from rest did not converge (%s)\n", omega, orbit.message.c_str());
            continue;
        }
        // the first output's signal (a reported DOF: io::SystemConfig outputs)
        Eigen::VectorXd y = Eigen::VectorXd::Zero(samples);
        for (int j = 0; j < samples; ++j) y(j) = config.outputs[0].of(orbit.displacement.row(j).transpose());
        const double y_max = y.cwiseAbs().maxCoeff();
        std::printf("w = %g: exact orbit %s, %s max %.12g (on %d samples %.12g), amp1 %.12g\n", omega, orbit.regime.c_str(),
                    config.outputs[0].name().c_str(), orbit.output_max[0], samples, y_max, orbit.output_amp1[0]);
        std::printf("  %4s  %-28s  %-34s  %s\n", "H", "truncation: max, deviation", "HB against its exact orbit: max, amp1",
                    "HB max at 4x, 16x the AFT samples N_t");
        for (int h : harmonics_list) {
            const Eigen::VectorXd z = truncated(y, h);
            const double cut_max = (z.cwiseAbs().maxCoeff() - y_max) / y_max, deviation = (z - y).cwiseAbs().maxCoeff() / y_max;
            nlohmann::json row = {{"w", omega}, {"H", h}, {"truncation_max", cut_max}, {"truncation_deviation", deviation}};
            const AtRow hb = frf_at(config, omega, h, 0, false), ex = frf_at(config, omega, h, 0, true);
            std::printf("  %4d  %+.2e, %.2e", h, cut_max, deviation);
            if (!hb.found || !ex.found || !ex.exact) {
                std::printf("           no comparison (%s)\n", !hb.found || !ex.found ? "the FRF has no point at w" : "the polish failed at w");
                all.push_back(row);
                continue;
            }
            const double e_max = (hb.max - ex.max) / ex.max, e_amp1 = (hb.amp1 - ex.amp1) / ex.amp1;
            row["hb_max"] = e_max;
            row["hb_amp1"] = e_amp1;
            std::printf("           %+.2e, %+.2e", e_max, e_amp1);
            // the AFT's samples raised: N_t as chosen for H, times 4 and 16
            const int base = hb.time_samples;
            for (int factor : {4, 16}) {
                const AtRow finer = frf_at(config, omega, h, factor * base, false);
                if (finer.found) {
                    std::printf("   %+.2e", (finer.max - ex.max) / ex.max);
                    row["hb_max_samples_x" + std::to_string(factor)] = (finer.max - ex.max) / ex.max;
                } else {
                    std::printf("   -");
                }
            }
            std::printf("\n");
            std::fflush(stdout);
            all.push_back(row);
        }
    }
    std::printf("%s\n", all.dump().c_str());
    return 0;
}
