// Benchmark: one full FRF branch of the paper's absorber by harmonic balance + continuation,
// for several harmonic counts H. Prints, per H,
//   - points per second and Ceres iterations per point of the whole continuation,
//   - where the time goes: AFT (transforms + friction law on the samples), Jacobian (chain
//     rule through the AFT and assembly), Ceres' own work (Solve minus our evaluations),
//     predictor (tangent LU solves) and the rest,
//   - the same corrections (same predictions, same scaled system, same tolerance) done once
//     with our Ceres Corrector and once with a bare Newton iteration with a dense LU, in this
//     process: their time ratio is the price of Ceres.
// With --allocator-check H, at the end: the exact-Coulomb branch at H harmonics (N_t = 2048)
// with glibc's default allocator settings and with hbf::retain_freed_memory() (memory.hpp):
// page faults, kernel time and the time ratio. Each variant runs in a fresh process (this
// program, re-executed): glibc adapts its thresholds to the blocks a process has freed, so a
// second branch in the same process is already fast (measured: 444,000 faults and 8.5 s for
// the first branch of a process, 1,500 and 2.6 s for the next one).
// For the smooth laws (dahl, lugre, coulomb-reg), per H: the cost of stability per branch
// point (stability.hpp), a bare Hill eigenproblem (d (2H + 1) square, the sorted selection)
// against the monodromy route (the variational equation over one period by CVODE), each as a
// ratio to the branch's own time per point, all in this process.
// The last line is one JSON object with all figures. Run by hand: `build/benchmarks/hb_branch`.
#include <CLI/CLI.hpp>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "hbf/continuation.hpp"
#include "hbf/absorber.hpp"
#include "hbf/memory.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/stability.hpp"

using namespace hbf;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Bare Newton on [R / |F|; t . (p - p_predicted)] = 0 in the corrector's scaled unknowns
/// p = (x / x_scale, omega), with a partially pivoted LU of the exact Jacobian; the same
/// acceptance test as the Corrector (|R|_inf / |F| <= tolerance).
bool newton_lu(HarmonicBalance& hb, Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent,
               double x_scale, double tolerance, int max_iterations, int& iterations) {
    const int n = hb.unknowns();
    const double f = hb.force_scale();
    Eigen::VectorXd p(n + 1);
    p.head(n) = x / x_scale;
    p(n) = omega;
    const Eigen::VectorXd predicted = p;
    Eigen::VectorXd r, r_omega, rhs(n + 1);
    Eigen::MatrixXd J, A(n + 1, n + 1);
    for (iterations = 0; iterations <= max_iterations; ++iterations) {
        hb.evaluate(p.head(n) * x_scale, p(n), r, &J, &r_omega);
        if (!r.allFinite()) return false;
        if (r.cwiseAbs().maxCoeff() <= tolerance * f) {
            x = p.head(n) * x_scale;
            omega = p(n);
            return true;
        }
        if (iterations == max_iterations) break;
        A.topLeftCorner(n, n) = J * (x_scale / f);
        A.topRightCorner(n, 1) = r_omega / f;
        A.row(n) = tangent.transpose();
        rhs.head(n) = -r / f;
        rhs(n) = -tangent.dot(p - predicted);
        p += A.partialPivLu().solve(rhs);
    }
    return false;
}

struct Figures {
    int harmonics = 0, time_samples = 0, unknowns = 0, points = 0;
    double seconds = 0, points_per_second = 0, iterations_per_point = 0;
    double aft = 0, jacobian = 0, ceres = 0, predictor = 0, other = 0;  // shares of `seconds`
    int corrections = 0, ceres_iterations = 0, newton_iterations = 0, disagreements = 0;
    double ceres_seconds = 0, newton_seconds = 0;
    double peak_omega = 0, peak_y1_max = 0;  // the largest y1_max on the branch (accuracy in H)
};

Figures measure(const AbsorberParameters& p, FrictionLaw law, int harmonics, const ContinuationOptions& o,
                int repeats) {
    HarmonicBalance hb(friction_absorber(p, law), HarmonicBalanceOptions{harmonics, 0});
    Figures fig;
    fig.harmonics = harmonics;
    fig.time_samples = hb.time_samples();
    fig.unknowns = hb.unknowns();
    BranchResult best;
    for (int k = 0; k < repeats; ++k) {  // the fastest of `repeats` runs: least disturbed
        BranchResult b = continue_branch(hb, o);
        if (k == 0 || b.seconds < best.seconds) best = std::move(b);
    }
    if (best.status != ContinuationStatus::completed)
        std::cerr << "warning: H = " << harmonics << ": " << best.summary() << '\n';
    fig.points = static_cast<int>(best.points.size());
    fig.seconds = best.seconds;
    fig.points_per_second = fig.points / best.seconds;
    fig.iterations_per_point = static_cast<double>(best.corrector.iterations) / fig.points;
    const EvaluationStatistics& e = best.evaluation;
    const double ceres_own = best.corrector.seconds - best.corrector.evaluation_seconds;
    // Tangent evaluations are counted in e (AFT, Jacobian); predictor = its LU and the rest.
    const double predictor_evaluations = e.aft_seconds + e.jacobian_seconds + e.structure_seconds -
                                         best.corrector.evaluation_seconds;
    fig.aft = e.aft_seconds / best.seconds;
    fig.jacobian = (e.jacobian_seconds + e.structure_seconds) / best.seconds;
    fig.ceres = ceres_own / best.seconds;
    fig.predictor = std::max(0.0, best.predictor_seconds - predictor_evaluations) / best.seconds;
    fig.other = std::max(0.0, 1.0 - fig.aft - fig.jacobian - fig.ceres - fig.predictor);
    for (const Peak& peak : find_peaks(hb, best, 0, o.corrector)) {
        if (peak.y_max > fig.peak_y1_max) {
            fig.peak_y1_max = peak.y_max;
            fig.peak_omega = peak.omega;
        }
    }

    // The same corrections by Ceres and by Newton-LU: from each accepted point, predict the
    // next one along the tangent with the step the continuation took.
    const int n = hb.unknowns();
    const double x_scale = hb.unknown_scale(best.points.front().x);
    struct Prediction {
        Eigen::VectorXd x, tangent;
        double omega;
    };
    std::vector<Prediction> predictions;
    for (std::size_t k = 0; k + 1 < best.points.size(); ++k) {
        const SolutionPoint &a = best.points[k], &b = best.points[k + 1];
        if (a.branch != b.branch) continue;
        Eigen::VectorXd chord(n + 1);
        chord.head(n) = (b.x - a.x) / x_scale;
        chord(n) = b.omega - a.omega;
        const Eigen::VectorXd t = branch_tangent(hb, a.x, a.omega, x_scale, chord);
        predictions.push_back({a.x + b.step * x_scale * t.head(n), t, a.omega + b.step * t(n)});
    }
    Corrector corrector(hb, o.corrector);
    std::vector<Eigen::VectorXd> by_ceres;
    for (int repeat = 0; repeat < repeats; ++repeat) {
        by_ceres.clear();
        int iterations_total = 0;
        const auto start = std::chrono::steady_clock::now();
        for (const Prediction& pr : predictions) {
            Eigen::VectorXd x = pr.x;
            double omega = pr.omega, residual = 0;
            int iterations = 0;
            corrector.correct(x, omega, pr.tangent, x_scale, iterations, residual);
            iterations_total += iterations;
            by_ceres.push_back(x);
        }
        const double elapsed = seconds_since(start);
        if (repeat == 0 || elapsed < fig.ceres_seconds) fig.ceres_seconds = elapsed;
        fig.ceres_iterations = iterations_total;
    }
    for (int repeat = 0; repeat < repeats; ++repeat) {
        int iterations_total = 0, disagreements = 0;
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t k = 0; k < predictions.size(); ++k) {
            const Prediction& pr = predictions[k];
            Eigen::VectorXd x = pr.x;
            double omega = pr.omega;
            int iterations = 0;
            const bool ok = newton_lu(hb, x, omega, pr.tangent, x_scale, o.corrector.tolerance,
                                      o.corrector.max_iterations, iterations);
            iterations_total += iterations;
            if (!ok || (x - by_ceres[k]).cwiseAbs().maxCoeff() > 1e-6 * x_scale) ++disagreements;
        }
        const double elapsed = seconds_since(start);
        if (repeat == 0 || elapsed < fig.newton_seconds) fig.newton_seconds = elapsed;
        fig.newton_iterations = iterations_total;
        fig.disagreements = disagreements;
    }
    fig.corrections = static_cast<int>(predictions.size());
    return fig;
}

/// One exact-Coulomb branch of the absorber at H harmonics and 2048 samples: seconds, minor
/// page faults and kernel seconds of this process while it ran.
struct AllocatorRun {
    double seconds = 0, kernel_seconds = 0;
    long faults = 0;
    std::size_t points = 0;
};
AllocatorRun allocator_run(const AbsorberParameters& p, int harmonics, const ContinuationOptions& o, bool retain) {
    if (retain && !retain_freed_memory()) throw std::runtime_error("retain_freed_memory: not glibc");
    auto usage = [] {
        rusage u{};
        getrusage(RUSAGE_SELF, &u);
        return u;
    };
    const rusage before = usage();
    const auto start = std::chrono::steady_clock::now();
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{harmonics, 2048});
    const BranchResult b = continue_branch(hb, o);
    AllocatorRun r;
    r.seconds = seconds_since(start);
    const rusage after = usage();
    r.faults = after.ru_minflt - before.ru_minflt;
    r.kernel_seconds = static_cast<double>(after.ru_stime.tv_sec - before.ru_stime.tv_sec) +
                       1e-6 * static_cast<double>(after.ru_stime.tv_usec - before.ru_stime.tv_usec);
    r.points = b.points.size();
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Times one FRF branch of the paper's absorber by harmonic balance for several H, "
                 "and compares the Ceres corrector with a bare Newton-LU on the same corrections."};
    std::vector<int> harmonics = {5, 10, 20, 40};
    std::string law_name = "lugre";
    AbsorberParameters p;
    ContinuationOptions o;
    int repeats = 3;
    int allocator_harmonics = 0;
    std::string allocator_variant;  // internal: one variant in a fresh process
    // Defaults: the library's own choice.
    std::string strategy = o.corrector.trust_region == TrustRegion::dogleg ? "dogleg" : "lm";
    std::string solver = o.corrector.dense_solver == DenseSolver::qr ? "qr" : "cholesky";
    std::string library = o.corrector.dense_library == DenseLibrary::lapack ? "lapack" : "eigen";
    app.add_option("--harmonics", harmonics, "harmonic counts H to time")->delimiter(',')->capture_default_str();
    app.add_option("--law", law_name, "friction law: lugre, dahl, coulomb-reg, coulomb (exact) or jenkins")->capture_default_str();
    app.add_option("--fe", p.excitation, "excitation amplitude fe (paper's nondimensional)")->capture_default_str();
    app.add_option("--wmin", o.omega_start, "first frequency")->capture_default_str();
    app.add_option("--wmax", o.omega_end, "last frequency")->capture_default_str();
    app.add_option("--repeats", repeats, "runs per measurement; the fastest is reported")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    app.add_option("--ceres-strategy", strategy, "trust region: lm (Levenberg-Marquardt) or dogleg")
        ->check(CLI::IsMember({"lm", "dogleg"}))
        ->capture_default_str();
    app.add_option("--ceres-solver", solver, "dense linear solver: qr or cholesky (normal equations)")
        ->check(CLI::IsMember({"qr", "cholesky"}))
        ->capture_default_str();
    app.add_option("--ceres-library", library, "dense linear algebra: eigen or lapack")
        ->check(CLI::IsMember({"eigen", "lapack"}))
        ->capture_default_str();
    app.add_option("--allocator-check", allocator_harmonics,
                   "H > 0: at the end, time the exact-Coulomb branch at H harmonics and N_t = 2048 with glibc's "
                   "default allocator settings and then with hbf::retain_freed_memory() [default 0: off]")
        ->check(CLI::Range(0, 200));
    app.add_option("--allocator-variant", allocator_variant, "internal (--allocator-check): default or retained")
        ->check(CLI::IsMember({"default", "retained"}))
        ->group("");
    CLI11_PARSE(app, argc, argv);
    if (!allocator_variant.empty()) {  // the child of --allocator-check: one branch, one line
        const AllocatorRun r = allocator_run(p, allocator_harmonics, o, allocator_variant == "retained");
        std::printf("%.6f %ld %.6f %zu\n", r.seconds, r.faults, r.kernel_seconds, r.points);
        return 0;
    }
    o.corrector.trust_region = strategy == "dogleg" ? TrustRegion::dogleg : TrustRegion::levenberg_marquardt;
    o.corrector.dense_solver = solver == "cholesky" ? DenseSolver::normal_cholesky : DenseSolver::qr;
    o.corrector.dense_library = library == "lapack" ? DenseLibrary::lapack : DenseLibrary::eigen;
    const FrictionLaw law = parse_friction_law(law_name);
    for (int h : harmonics)
        if (h < 1 || h > 200) {
            std::cerr << "--harmonics: H = " << h << " is out of range: allowed 1..200\n";
            return 2;
        }

    std::printf("FRF branch of the absorber: law %s, fe = %g, w in [%g, %g], r = %g, wa = %g, mu = %g, wb = %g, "
                "xi = %g; fastest of %d runs\nCeres: %s, dense %s, %s\n",
                law_name.c_str(), p.excitation, o.omega_start, o.omega_end, p.mass_ratio, p.tuning_ratio,
                p.friction_coefficient, p.contact_stiffness_ratio, p.contact_damping_ratio, repeats, strategy.c_str(),
                solver.c_str(), library.c_str());
    std::printf("shares of the branch time: AFT = transforms + friction law on the samples; Jacobian = chain rule "
                "+ assembly;\nCeres = inside Solve but not in our evaluations; predictor = tangent LU solves.\n\n");
    std::printf("%4s %5s %8s %7s %9s %9s %8s | %5s %5s %5s %5s %5s | %12s %12s %8s\n", "H", "N_t", "unknowns",
                "points", "seconds", "points/s", "it/point", "AFT", "Jac", "Ceres", "pred", "other",
                "Ceres [s]", "Newton-LU [s]", "ratio");
    nlohmann::json cases = nlohmann::json::array();
    std::vector<Figures> all;
    for (int h : harmonics) {
        const Figures f = measure(p, law, h, o, repeats);
        all.push_back(f);
        std::printf("%4d %5d %8d %7d %9.4f %9.0f %8.2f | %4.0f%% %4.0f%% %4.0f%% %4.0f%% %4.0f%% | %12.4f %13.4f %8.2f\n",
                    f.harmonics, f.time_samples, f.unknowns, f.points, f.seconds, f.points_per_second,
                    f.iterations_per_point, 100 * f.aft, 100 * f.jacobian, 100 * f.ceres, 100 * f.predictor,
                    100 * f.other, f.ceres_seconds, f.newton_seconds, f.ceres_seconds / f.newton_seconds);
        if (f.disagreements > 0)
            std::printf("     warning: Newton-LU failed or disagreed with Ceres on %d of %d corrections\n",
                        f.disagreements, f.corrections);
        cases.push_back({{"law", law_name},
                         {"fe", p.excitation},
                         {"harmonics", f.harmonics},
                         {"time_samples", f.time_samples},
                         {"points", f.points},
                         {"seconds", f.seconds},
                         {"points_per_second", f.points_per_second},
                         {"iterations_per_point", f.iterations_per_point},
                         {"share_aft", f.aft},
                         {"share_jacobian", f.jacobian},
                         {"share_ceres", f.ceres},
                         {"share_predictor", f.predictor},
                         {"corrections", f.corrections},
                         {"ceres_seconds", f.ceres_seconds},
                         {"newton_lu_seconds", f.newton_seconds},
                         {"ceres_over_newton_lu", f.ceres_seconds / f.newton_seconds},
                         {"ceres_iterations", f.ceres_iterations},
                         {"newton_lu_iterations", f.newton_iterations},
                         {"disagreements", f.disagreements},
                         {"peak_w", f.peak_omega},
                         {"peak_y1_max", f.peak_y1_max}});
    }
    // Accuracy in H: the highest peak of y1_max (refined by find_peaks) against the largest H.
    const Figures& finest = *std::max_element(all.begin(), all.end(), [](const Figures& a, const Figures& b) {
        return a.harmonics < b.harmonics;
    });
    std::printf("\naccuracy in H: highest y1_max on the branch (max over one period of |y1|)\n%4s %10s %12s %22s\n", "H",
                "w", "y1_max", ("rel. diff vs H = " + std::to_string(finest.harmonics)).c_str());
    for (const Figures& f : all)
        std::printf("%4d %10.5f %12.6f %22.2e\n", f.harmonics, f.peak_omega, f.peak_y1_max,
                    std::abs(f.peak_y1_max - finest.peak_y1_max) / finest.peak_y1_max);
    std::printf("\n(ratio = Ceres corrector time / bare Newton-LU time on the same %s corrections)\n",
                "predicted");
    nlohmann::json result{{"cases", cases}};
    if (law == FrictionLaw::dahl || law == FrictionLaw::lugre || law == FrictionLaw::coulomb_regularized) {
        std::printf("\nstability per branch point (every point of the branch; fastest of %d runs):\n%4s %6s %7s %12s "
                    "%12s %12s %10s %10s %9s\n",
                    repeats, "H", "d(2H+1)", "points", "branch [ms]", "Hill [ms]", "monodromy [ms]", "Hill/pt",
                    "mono/pt", "mono/Hill");
        nlohmann::json stability = nlohmann::json::array();
        for (int h : harmonics) {
            HarmonicBalance hb(friction_absorber(p, law), {h, 0});
            double branch_s = 1e300, hill_s = 1e300, mono_s = 1e300;
            BranchResult b;
            for (int k = 0; k < repeats; ++k) {
                const auto t0 = std::chrono::steady_clock::now();
                b = continue_branch(hb, o);
                branch_s = std::min(branch_s, seconds_since(t0));
            }
            StabilityAnalyser analyse(hb);
            int size = 0;
            for (int k = 0; k < repeats; ++k) {
                auto t0 = std::chrono::steady_clock::now();
                for (const SolutionPoint& q : b.points) size = static_cast<int>(analyse.hill(q).size());
                hill_s = std::min(hill_s, seconds_since(t0));
                t0 = std::chrono::steady_clock::now();
                for (const SolutionPoint& q : b.points) analyse.monodromy(q);
                mono_s = std::min(mono_s, seconds_since(t0));
            }
            const double n = static_cast<double>(b.points.size());
            const int hill_size = size * (2 * h + 1);
            std::printf("%4d %6d %7zu %12.3f %12.3f %12.3f %10.2f %10.2f %9.2f\n", h, hill_size, b.points.size(),
                        1e3 * branch_s / n, 1e3 * hill_s / n, 1e3 * mono_s / n, hill_s / branch_s, mono_s / branch_s,
                        mono_s / hill_s);
            stability.push_back({{"harmonics", h},
                                 {"hill_size", hill_size},
                                 {"points", b.points.size()},
                                 {"branch_ms_per_point", 1e3 * branch_s / n},
                                 {"hill_ms_per_point", 1e3 * hill_s / n},
                                 {"monodromy_ms_per_point", 1e3 * mono_s / n},
                                 {"monodromy_over_hill", mono_s / hill_s}});
        }
        std::printf("(Hill/pt, mono/pt: stability time over the branch's own time, i.e. the factor it adds to an FRF)\n");
        result["stability"] = stability;
    }
    if (allocator_harmonics > 0) {
        // Each variant in a fresh process: this program with the same branch options.
        auto fresh = [&](const std::string& variant) {
            const std::string command = "'" + std::filesystem::read_symlink("/proc/self/exe").string() + "' --allocator-check " + std::to_string(allocator_harmonics) +
                                        " --allocator-variant " + variant + " --fe " + std::to_string(p.excitation) +
                                        " --wmin " + std::to_string(o.omega_start) + " --wmax " +
                                        std::to_string(o.omega_end);
            AllocatorRun r;
            FILE* child = popen(command.c_str(), "r");
            if (child == nullptr || std::fscanf(child, "%lf %ld %lf %zu", &r.seconds, &r.faults, &r.kernel_seconds,
                                                &r.points) != 4 || pclose(child) != 0)
                throw std::runtime_error("--allocator-check: the " + variant + " run failed");
            return r;
        };
        const AllocatorRun plain = fresh("default"), kept = fresh("retained");
        std::printf("\nallocator, exact coulomb, H = %d, N_t = 2048 (%zu points):\n%24s %9s %12s %9s\n"
                    "%24s %9.3f %12ld %9.3f\n%24s %9.3f %12ld %9.3f\nratio default / retained: %.2f\n",
                    allocator_harmonics, kept.points, "", "seconds", "page faults", "kernel s", "glibc defaults",
                    plain.seconds, plain.faults, plain.kernel_seconds, "retain_freed_memory()", kept.seconds,
                    kept.faults, kept.kernel_seconds, plain.seconds / kept.seconds);
        result["allocator"] = {{"harmonics", allocator_harmonics},    {"points", kept.points},
                               {"default_seconds", plain.seconds},    {"default_faults", plain.faults},
                               {"retained_seconds", kept.seconds},    {"retained_faults", kept.faults},
                               {"ratio", plain.seconds / kept.seconds}};
    }
    std::cout << result.dump() << std::endl;
    return 0;
}
