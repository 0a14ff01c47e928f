// `hbf frf`: frequency-response branch of the paper's absorber by harmonic balance and
// pseudo-arclength continuation, as CSV (+ optional JSON summary).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "arguments.hpp"
#include "commands.hpp"
#include "hbf/config.hpp"
#include "hbf/continuation.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/error.hpp"
#include "hbf/analytic.hpp"
#include "hbf/io.hpp"
#include "hbf/plot.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::cli {

namespace {
struct FrfOptions {
    AbsorberFlags absorber;
    std::string wmin = "0.5", wmax = "1.6", harmonics = "0", time_samples = "0", max_amplitude = "1000", max_step = "1",
                tolerance = "1e-9", formulation = "automatic", modes = "0";
    std::string at, out, summary, config, plot, overlay, overlay_out, exact;
    bool quiet = false;
};

/// A one-line progress display on a terminal's standard error: w reached, points, elapsed
/// time; redrawn at most 4 times a second, erased when done.
class ProgressLine {
public:
    explicit ProgressLine(bool enabled) : enabled_(enabled), start_(std::chrono::steady_clock::now()) {}
    ~ProgressLine() { clear(); }
    void update(double omega, int points) {
        if (!enabled_) return;
        const auto now = std::chrono::steady_clock::now();
        if (shown_ && now - last_ < std::chrono::milliseconds(250)) return;
        last_ = now;
        shown_ = true;
        const double seconds = std::chrono::duration<double>(now - start_).count();
        std::fprintf(stderr, "\rhbf frf: w = %-12.6g %6d points %8.1f s", omega, points, seconds);
        std::fflush(stderr);
    }
    void clear() {
        if (!shown_) return;
        std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
        shown_ = false;
    }

private:
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

std::vector<double> parse_list(const std::string& flag, const std::string& text) {
    std::vector<double> values;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const double w = parse_double(flag, item);
        if (!(w > 0.0)) throw UsageError(flag + " = '" + item + "' is out of range: allowed frequencies > 0");
        values.push_back(w);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return values;
}

bool given(const CLI::App& command, const char* flag) { return command.count(flag) > 0; }

int run(const CLI::App& command, const FrfOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    // Plot options are checked before the work starts.
    long long overlay_points = 0;
    std::string overlay_out = o.overlay_out;
    io::check_plot("--plot", o.plot);  // before any work
    // An empty value is never "not given" (it would silently change what runs).
    if (given(command, "--at") && o.at.empty())
        throw UsageError("--at is empty: allowed a comma-separated list of frequencies > 0");
    if (given(command, "--exact") && o.exact.empty()) throw UsageError("--exact is empty: allowed on, off");
    if (given(command, "--overlay-timeint") && o.overlay.empty())
        throw UsageError("--overlay-timeint is empty: allowed 2..10000 points");
    if (!o.overlay.empty()) {
        overlay_points = parse_integer("--overlay-timeint", o.overlay);
        if (overlay_points < 2 || overlay_points > 10000)
            throw UsageError("--overlay-timeint = " + o.overlay + " is out of range: allowed 2..10000 points");
        if (o.plot.empty()) throw UsageError("--overlay-timeint draws on the plot: it needs --plot FILE.png|FILE.svg");
        if (overlay_out.empty()) {
            const std::string stem = o.plot.substr(0, o.plot.size() - 4);  // .png or .svg
            overlay_out = stem + "-timeint.csv";
        }
    } else if (!overlay_out.empty()) {
        throw UsageError("--overlay-out names the CSV of --overlay-timeint, which is not given");
    }
    io::check_outputs({{"--out", o.out, command.count("--out") > 0, true},
                       {"--summary", o.summary, command.count("--summary") > 0},
                       {"--plot", o.plot, command.count("--plot") > 0, false, true},
                       {"--overlay-out", overlay_out, command.count("--overlay-out") > 0}});
    // The system: the paper's absorber from its flags, or any structure from --config (whose
    // frequency range and solver settings the flags override).
    ChosenSystem chosen = choose_system(command, o.absorber, o.config);
    const System& system = chosen.system;
    const std::string& law_name = chosen.law_name;
    const std::vector<Output>& outputs = chosen.outputs;
    const std::optional<io::SystemConfig>& config = chosen.config;
    const AbsorberParameters& p = chosen.absorber;
    // The exact polish: on by default for the laws it covers (coulomb, jenkins).
    if (!o.exact.empty() && o.exact != "on" && o.exact != "off")
        throw UsageError("--exact = '" + o.exact + "' is not allowed: allowed on, off");
    const bool exact = o.exact.empty() ? exact_solver_supports(system) : o.exact == "on";
    if (exact && !exact_solver_supports(system))
        throw UsageError("--exact on: " + exact_solver_refusal(system) + " (use --exact off)");
    // With the polish, HB only supplies the branch and the starting guesses: H = 10 suffices
    // (measured: the same exact branch, peaks and transitions as H = 20, 3 times faster).
    if (exact) chosen.automatic_harmonics = 10;
    HarmonicBalanceOptions hbo = harmonic_balance_options(command, o.harmonics, o.time_samples, chosen, o.config);
    try {
        hbo.formulation = parse_formulation(o.formulation);
    } catch (const InvalidInput&) {
        throw UsageError("--formulation = '" + o.formulation + "' is not known: allowed automatic, condensed, full");
    }
    const long long modes = parse_integer("--modes", o.modes);
    if (modes < 0 || modes > 100000)
        throw UsageError("--modes = " + o.modes + " is out of range: allowed 0 (direct solve) or 1..100000");
    hbo.modes = static_cast<int>(modes);
    if (config && config->modes && !given(command, "--modes")) hbo.modes = *config->modes;
    ContinuationOptions co;
    co.omega_start = parse_double("--wmin", o.wmin);
    co.omega_end = parse_double("--wmax", o.wmax);
    if (config && config->omega_start && !given(command, "--wmin")) co.omega_start = *config->omega_start;
    if (config && config->omega_end && !given(command, "--wmax")) co.omega_end = *config->omega_end;
    co.max_amplitude = parse_double("--max-amplitude", o.max_amplitude);
    co.max_step = parse_double("--max-step", o.max_step);
    if (!(co.max_step >= 1e-5 && co.max_step <= 10.0))
        throw UsageError("--max-step = " + o.max_step + " is out of range: allowed 1e-5..10");
    co.initial_step = std::min(co.initial_step, co.max_step);
    co.corrector.tolerance = parse_double("--tolerance", o.tolerance);
    if (!(co.corrector.tolerance >= 1e-14 && co.corrector.tolerance <= 1e-2))
        throw UsageError("--tolerance = " + o.tolerance + " is out of range: allowed 1e-14..1e-2");
    const std::vector<double> at = o.at.empty() ? std::vector<double>{} : parse_list("--at", o.at);
    // With the polish, HB's own transitions (O(1/H) misplaced) are not needed: the exact
    // ones replace them.
    if (exact) co.locate_transitions = false;
    if (dry_run()) {  // the same checks, without building the Fourier matrices
        HarmonicBalance::validate(system, hbo);
        validate(co);
        std::cerr << "hbf frf: dry run: every input and output is valid; nothing computed, nothing written\n";
        return exit_success;
    }
    HarmonicBalance hb(system, hbo);
    validate(co);
    ProgressLine progress(!o.quiet && isatty(STDERR_FILENO));
    co.progress = [&progress](double omega, int points) { progress.update(omega, points); };
    BranchResult branch = continue_branch(hb, co);  // validates the range options
    progress.clear();

    std::vector<SolutionPoint> points = branch.points;
    std::vector<double> missed;
    if (!at.empty()) {
        const auto samples = sample_branch(hb, branch, at, co.corrector, &missed);
        points.insert(points.end(), samples.begin(), samples.end());
    }
    const std::size_t sample_count = points.size() - branch.points.size();
    // The reported outputs, and y_max of DOF 1 (the JSON summary's folds and transitions): on
    // a large model only these are synthesised in time.
    Analyser analyse(hb, {0}, outputs);
    std::vector<PointMetrics> metrics;
    metrics.reserve(points.size());
    for (const SolutionPoint& point : points) metrics.push_back(analyse(point));
    std::optional<PolishedBranch> polish;
    std::vector<Peak> peaks;
    if (exact) {
        PolishOptions po;
        po.dof = std::max(0, outputs.front().single_dof());
        po.exact.outputs = outputs;
        // The peaks of every output are refined only for the summary that reports them.
        po.peaks_of_every_output = !o.summary.empty();
        polish = polish_branch(hb, points, metrics, po, co.corrector);
        points = polish->points;
        metrics = polish->metrics;
        peaks = polish->peaks;
    } else if (!o.summary.empty()) {
        peaks = find_peaks(hb, branch, outputs, co.corrector);
    }

    // Time-integration check points on a uniform grid, swept up from the stuck linear state.
    std::vector<PeriodicResponse> overlay;
    if (overlay_points > 0) {
        const std::vector<double> grid = analytic::uniform_grid(co.omega_start, co.omega_end, overlay_points);
        const Eigen::VectorXd start = linear_stuck_state(system, grid.front());
        TimeIntegrationOptions tio;
        tio.outputs = outputs;
        overlay = sweep(system, grid, tio, &start);
    }
    io::OutputFile out(o.out);
    io::write_frf_csv(out.stream(), points, metrics, outputs,
                      polish ? polish->exact : std::vector<ExactPoint>{});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    // Everything that makes the result failed (exit 1) or incomplete/doubtful (exit 3); said on
    // stderr after the files are committed, and in the JSON summary.
    Verdict verdict("frf");
    const bool failed = branch.status == ContinuationStatus::min_step || branch.status == ContinuationStatus::start_failed;
    if (failed)
        verdict.error(branch.summary() + " (the points computed so far are written)");
    else if (branch.status != ContinuationStatus::completed)
        verdict.warning(branch.summary() + "; the branch spans " + format_number(100.0 * branch.coverage) +
                        " % of [wmin, wmax]");
    else if (branch.unlocated_transitions > 0)
        verdict.warning(branch.message + " (the branch points are right; the CSV lacks those transition rows)");
    // A point whose exact polish failed is HB's value, flagged exact = failed: a doubtful result.
    if (polish && polish->failed > 0)
        verdict.error(polish->summary() + "; the failed rows keep their harmonic-balance values (column exact = failed)");
    // The energy balance of every harmonic-balance point (column energy_error).
    std::size_t unbalanced = 0, worst = 0;
    const double energy_limit = energy_balance_limit(co.corrector.tolerance);
    for (std::size_t k = 0; k < metrics.size(); ++k) {
        if (metrics[k].energy_error > energy_limit) ++unbalanced;
        if (metrics[k].energy_error > metrics[worst].energy_error) worst = k;
    }
    if (unbalanced > 0)
        verdict.warning(std::to_string(unbalanced) + " point(s) fail the energy balance (column energy_error > " +
                        format_number(energy_limit) + ", max(1e-6, 100 --tolerance); the largest, " +
                        format_number(metrics[worst].energy_error) + ", at w = " + format_number(points[worst].omega) +
                        "): the residual is small but the solution is not; a tighter --tolerance or more harmonics "
                        "may help");
    const auto unrefined = std::count_if(peaks.begin(), peaks.end(), [](const Peak& p) { return !p.refined; });
    if (unrefined > 0)
        verdict.note(std::to_string(unrefined) + " peak(s) not refined (at a fold, or a solve failed): the JSON "
                     "gives the branch point (refined = false)");
    // An --at frequency without a row is a failure too.
    for (double w : missed)
        verdict.error("--at w = " + format_number(w) + ": no solution written (outside the computed branch, or the "
                      "solve failed from the branch and after a retry)");
    verdict.add_library_messages();
    std::unique_ptr<io::OutputFile> summary;
    if (!o.summary.empty()) {
        std::vector<std::pair<std::string, double>> parameters;
        if (config) {
            parameters = {{"dofs", system.dofs()}, {"contacts", static_cast<double>(system.contacts.size())}};
        } else {
            parameters = {{"r", p.mass_ratio},
                          {"wa", p.tuning_ratio},
                          {"mu", p.friction_coefficient},
                          {"fe", p.excitation},
                          {"wb", p.contact_stiffness_ratio},
                          {"xi", p.contact_damping_ratio},
                          {"eps", p.regularization},
                          {"mu_static", p.static_friction_coefficient},
                          {"stribeck_velocity", p.stribeck_velocity},
                          {"viscous", p.viscous_coefficient}};
        }
        const std::vector<std::pair<std::string, double>> solver = {{"wmin", co.omega_start},
                                                                    {"wmax", co.omega_end},
                                                                    {"harmonics", hb.harmonics()},
                                                                    {"excitation_harmonic", hb.load_harmonic()},
                                                                    {"odd_harmonics", hb.odd_harmonics() ? 1 : 0},
                                                                    {"time_samples", hb.time_samples()},
                                                                    {"condensed", hb.formulation() == Formulation::condensed ? 1 : 0},
                                                                    {"modes", hb.modes()},
                                                                    {"max_amplitude", co.max_amplitude},
                                                                    {"tolerance", co.corrector.tolerance}};
        parameters.insert(parameters.end(), solver.begin(), solver.end());
        summary = std::make_unique<io::OutputFile>(o.summary);
        io::write_frf_summary(summary->stream(), law_name, parameters, branch, metrics, peaks, sample_count, seconds,
                              outputs, polish ? &*polish : nullptr, verdict.errors(), verdict.warnings(),
                              verdict.notes());
    }
    std::unique_ptr<io::OutputFile> overlay_file;
    if (!overlay.empty()) {
        overlay_file = std::make_unique<io::OutputFile>(overlay_out);
        io::write_timeint_csv(overlay_file->stream(), overlay, outputs);
    }
    if (!o.plot.empty()) {
        io::PlotSpec spec = io::frf_plot(points, metrics, outputs.front(), 0,
                                         "hbf frf: " + law_name + ", H = " + std::to_string(hb.harmonics()) +
                                             (hb.odd_harmonics() ? " (odd only)" : "") +
                                             (hb.load_harmonic() == 1
                                                  ? std::string()
                                                  : ", force at " + std::to_string(hb.load_harmonic()) + " w") +
                                             (config ? " (" + o.config + ")" : ""));
        if (!overlay.empty()) {
            io::PlotCurve check{"time integration (converged)", {}, {}, io::PlotCurve::Style::markers, 4};
            io::PlotCurve failed_check{"time integration (not converged)", {}, {}, io::PlotCurve::Style::markers, 3};
            for (const PeriodicResponse& r : overlay) {
                io::PlotCurve& c = r.converged ? check : failed_check;
                c.x.push_back(r.omega);
                c.y.push_back(r.output_max.front());
            }
            spec.curves.push_back(check);
            spec.curves.push_back(failed_check);
        }
        io::write_plot(o.plot, spec);  // before the CSV is committed: a failed plot leaves no output
    }
    out.commit();
    if (summary) summary->commit();
    if (overlay_file) overlay_file->commit();

    const bool verbose = !o.quiet && isatty(STDERR_FILENO);
    if (verbose && verdict.errors().empty() && branch.status == ContinuationStatus::completed)
        std::cerr << "hbf frf: " << branch.summary() << " in " << format_number(seconds) << " s\n";
    if (polish && polish->failed == 0 && (verbose || branch.status != ContinuationStatus::completed))
        std::cerr << "hbf frf: note: " << polish->summary() << " (the transitions are the exact solver's)\n";
    return verdict.finish();
}
}  // namespace

Runner add_frf_command(CLI::App& app) {
    auto options = std::make_shared<FrfOptions>();
    CLI::App* command = app.add_subcommand(
        "frf", "Frequency response of the paper's friction absorber by multi-harmonic balance (AFT) and "
               "pseudo-arclength continuation in w (nondimensional).");
    add_dry_run(*command);
    options->absorber.add_to(*command,
                             "friction law: coulomb (exact, set-valued: true sticking, by the dynamic Lagrangian), "
                             "jenkins (spring k_t = r wb^2 in series with a Coulomb slider), dahl, lugre or "
                             "coulomb-reg (regularised Coulomb)",
                             "coulomb", true);
    options->absorber.add_excitation_harmonic(*command);
    command->add_option("--wmin", options->wmin, "first frequency w of the branch, > 0")->capture_default_str()->type_name("NUMBER");
    command->add_option("--wmax", options->wmax, "last frequency w of the branch, > wmin")->capture_default_str()->type_name("NUMBER");
    command->add_option("--harmonics", options->harmonics,
                        "number of harmonics H, 1..200; 0 = automatic: 10 with the exact polish (coulomb, jenkins: "
                        "HB only supplies the branch and the starting guesses); without it 20 for coulomb (its error "
                        "falls like 1/H) and coulomb-reg (steep tanh), 10 for dahl, lugre and jenkins; times h with "
                        "--excitation-harmonic h. odd or odd:H balances the odd harmonics 1, 3, 5, ... <= H only "
                        "(automatic H with odd): the half-wave symmetric solutions y(t + T/2) = -y(t), which every "
                        "law here admits under a force at an odd harmonic, with half the unknowns; a solution that "
                        "breaks the symmetry is not found")
        ->capture_default_str()->type_name("INT|odd[:H]");
    command->add_option("--modes", options->modes,
                        "condensed formulation: 0 solves the structure per harmonic and frequency by a sparse LU "
                        "(exact; cost linear in N); m > 0 uses its m lowest modes plus the static residual "
                        "flexibility (cost independent of N; truncation error ~ (k w / w_{m+1})^2 of the dynamic "
                        "part; needs M > 0, K > 0 and C diagonal in the modes, e.g. Rayleigh). A --config file's "
                        "[solver] modes applies unless given")
        ->capture_default_str()->type_name("INT");
    command->add_option("--formulation", options->formulation,
                        "how the linear structure enters harmonic balance: condensed (the unknowns are the contacts' "
                        "relative displacements, the structure solved exactly per harmonic by a sparse LU: any model "
                        "size), full (every DOF's coefficients: a dense Jacobian, small models), automatic (condensed "
                        "for damped or larger than 16-DOF models with an invertible K, else full)")
        ->capture_default_str()->type_name("automatic|condensed|full");
    command->add_option("--time-samples", options->time_samples,
                        "AFT time samples per period N_t > 2H; 0 = automatic: the smallest power of two "
                        ">= max(64, 8 (2H + 1))")
        ->capture_default_str()->type_name("INT");
    command->add_option("--at", options->at,
                        "comma-separated frequencies W1,W2,...: every solution of the branch there is solved "
                        "exactly and written as extra rows with point = sample")
        ->type_name("LIST");
    command->add_option("--max-amplitude", options->max_amplitude,
                        "amplitude cap, in the system's displacement units (nondimensional for the preset): the "
                        "branch stops when a bound of max |y_i| exceeds it (unbounded resonance), then restarts "
                        "from wmax as branch 2")
        ->capture_default_str()->type_name("NUMBER");
    command->add_option("--max-step", options->max_step,
                        "largest arclength step, in the continuation's dimensionless coordinates (w / wmax and the "
                        "coefficients relative to the current amplitude: the same for any units); smaller values "
                        "give denser points, e.g. smoother plots of linear stretches, 1e-5..10")
        ->capture_default_str()->type_name("NUMBER");
    command->add_option("--tolerance", options->tolerance,
                        "corrector acceptance: |R|_inf <= tolerance * |F|_inf (the excitation amplitude), 1e-14..1e-2")
        ->capture_default_str()->type_name("NUMBER");
    command->add_option("--config", options->config,
                        "read the structure (any N DOFs: M, C, K, excitation, friction contacts), frequency range, "
                        "solver settings and reported outputs (DOFs or combinations of DOFs) from a TOML file (format: include/hbf/config.hpp, "
                        "examples/systems/); --wmin, --wmax, --harmonics, --time-samples and --law override the "
                        "file; the preset's parameter flags (--r, --mu, ...) are then rejected")
        ->option_text("FILE.toml");
    command->add_option("--out", options->out, "write the CSV to FILE instead of standard output")->option_text("FILE");
    command->add_option("--summary", options->summary, "write a JSON summary (parameters, solver statistics, "
                                                       "peaks, folds, status, wall time) to FILE")
        ->option_text("FILE");
    command->add_option("--plot", options->plot,
                        "draw max over one period of |o(t)| of the first reported output o against w through gnuplot: the branch in order, "
                        "folds, transitions and samples marked (.png or .svg)")
        ->option_text("FILE.png|FILE.svg");
    command->add_option("--overlay-timeint", options->overlay,
                        "also integrate K frequencies of a uniform grid over [wmin, wmax] in time (an up-sweep, "
                        "hbf timeint's defaults) and draw them as markers on the --plot; their rows go to "
                        "--overlay-out")
        ->option_text("K");
    command->add_option("--overlay-out", options->overlay_out,
                        "CSV of the --overlay-timeint points (hbf timeint's columns) [default: the plot's name "
                        "with -timeint.csv]")
        ->option_text("FILE");
    command->add_option("--exact", options->exact,
                        "polish every branch point, sample, transition and peak by the event-exact periodic solver "
                        "(exact Coulomb and Jenkins: Newton shooting on closed-form flows between stick/slip events, "
                        "Floquet stability), on or off [default: on for coulomb and jenkins contacts on models of at most "
                        "64 DOFs with mass (massless DOFs are condensed statically: a contact on them becomes a "
                        "Jenkins element) and a force at harmonic 1, off otherwise (the exact solver is dense); on "
                        "where it does not apply is an error naming why]")
        ->type_name("on|off");
    command->add_flag("--quiet", options->quiet,
                      "no progress (on a terminal: w reached, points, elapsed time, redrawn 4 times a second) or "
                      "summary line on standard error");
    std::string footer = "Output: CSV with a header row, one row per continuation point in branch order, then the "
                         "--at samples. Nondimensional as in the paper: y = x / x_s, x_s = N / k1, w = Omega / omega1 (with "
                         "--config: the file's units).\n"
                         "Columns:\n";
    for (const auto& c : io::frf_columns(2)) footer += "  " + c.name + ": " + c.meaning + "\n";
    footer += "Exit code 1 when the continuation could not start or stalled (min step), when the exact polish failed "
              "at some point (those rows keep their HB values, exact = failed), or when an --at frequency got no row "
              "(outside the branch, or its solve failed; named on standard error); the points computed so far are "
              "still written. An amplitude cap is reported on standard error and is not a failure.";
    command->footer(footer);
    return [command, options]() { return run(*command, *options); };
}

}  // namespace hbf::cli
