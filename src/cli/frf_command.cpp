// `hbf frf`: frequency-response branch of the paper's absorber by harmonic balance and
// pseudo-arclength continuation, as CSV (+ optional JSON summary).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "arguments.hpp"
#include "outputs.hpp"
#include "frf_flags.hpp"
#include "progress.hpp"
#include "stop_request.hpp"
#include "commands.hpp"
#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/error.hpp"
#include "hbf/analytic.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/table.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::cli {

namespace {
struct FrfOptions {
    AbsorberFlags absorber;
    FrfFlags frf;
    OutputFlags output;
    std::string at, overlay, overlay_out, plot_contacts, time_limit = "0";
};

/// The contact groups of --plot-contacts and the CSV's *_share_i<k> columns: a file's meshed
/// interfaces, else every contact as one group.
std::vector<InterfaceContacts> contact_groups(const System& system, const std::optional<io::SystemConfig>& config) {
    if (config && !config->interfaces.empty()) return config->interfaces;
    return {InterfaceContacts{"every contact", 0, static_cast<int>(system.contacts.size()), 0}};
}

/// --plot-contacts: each group's shares of the period stuck, slipping and open (averaged over its
/// contacts) against w, the branch in order (a break between branches; no --at samples).
io::PlotSpec contact_share_plot(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics,
                                const std::vector<InterfaceContacts>& groups, const std::string& title) {
    io::PlotSpec spec;
    spec.title = title;
    spec.xlabel = "w";
    spec.ylabel = "share of the period, mean over the group's contacts";
    const char* words[] = {"stuck", "slipping", "open"};
    const int types[] = {7, 9, 6};
    for (const InterfaceContacts& g : groups) {
        io::PlotCurve curves[3];
        for (int j = 0; j < 3; ++j)
            curves[j] = {std::string(words[j]) + (groups.size() > 1 ? " (" + g.name + ")" : std::string()), {}, {},
                         io::PlotCurve::Style::line, types[j]};
        int branch = -1;
        for (std::size_t k = 0; k < points.size() && k < metrics.size(); ++k) {
            if (points[k].kind == PointKind::sample) continue;
            const std::optional<io::InterfaceShares> shares = io::interface_shares(metrics[k], g);
            const double nan = std::numeric_limits<double>::quiet_NaN();
            const bool next_branch = branch >= 0 && points[k].branch != branch;
            branch = points[k].branch;
            const double share[3] = {shares ? shares->stuck : nan, shares ? shares->slipping : nan,
                                     shares ? shares->open : nan};
            for (int j = 0; j < 3; ++j) {
                if (next_branch) {
                    curves[j].x.push_back(nan);
                    curves[j].y.push_back(nan);
                }
                curves[j].x.push_back(points[k].omega);
                curves[j].y.push_back(share[j]);
            }
        }
        for (const io::PlotCurve& c : curves) spec.curves.push_back(c);
    }
    return spec;
}


int run(const CLI::App& command, const FrfOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    // Plot options are checked before the work starts.
    long long overlay_points = 0;
    std::string overlay_out = o.overlay_out;
    o.output.check_plot();  // before any work
    if (given(command, "--plot-contacts") && o.plot_contacts.empty())
        throw UsageError("--plot-contacts is empty: allowed FILE.png|FILE.svg");
    io::check_plot("--plot-contacts", o.plot_contacts);
    // An empty value is never "not given" (it would silently change what runs).
    if (given(command, "--at") && o.at.empty())
        throw UsageError("--at is empty: allowed a comma-separated list of frequencies > 0");
    if (given(command, "--overlay-timeint") && o.overlay.empty())
        throw UsageError("--overlay-timeint is empty: allowed 2..10000 points");
    const double time_limit = parse_time_limit(o.time_limit);
    if (!o.overlay.empty()) {
        overlay_points = parse_integer("--overlay-timeint", o.overlay);
        if (overlay_points < 2 || overlay_points > 10000)
            throw UsageError("--overlay-timeint = " + o.overlay + " is out of range: allowed 2..10000 points");
        if (o.output.plot.empty()) throw UsageError("--overlay-timeint draws on the plot: it needs --plot FILE.png|FILE.svg");
        if (overlay_out.empty()) {
            const std::string stem = o.output.plot.substr(0, o.output.plot.size() - 4);  // .png or .svg
            overlay_out = stem + "-timeint.csv";
        }
    } else if (!overlay_out.empty()) {
        throw UsageError("--overlay-out names the CSV of --overlay-timeint, which is not given");
    }
    // The system: the paper's absorber from its flags, or any structure from --config (whose
    // frequency range and solver settings the flags override).
    ChosenSystem chosen = choose_system(command, o.absorber, o.frf.config);
    o.output.check(command, chosen.inputs(), {{"--overlay-out", overlay_out, command.count("--overlay-out") > 0},
                                              {"--plot-contacts", o.plot_contacts, !o.plot_contacts.empty(), false, true}});
    const System& system = chosen.system;
    if (!o.plot_contacts.empty() && system.contacts.empty())
        throw UsageError("--plot-contacts draws the contacts' states: the system has no contact");
    const std::string& law_name = chosen.law_name;
    const std::vector<Output>& outputs = chosen.outputs;
    const std::optional<io::SystemConfig>& config = chosen.config;
    const AbsorberParameters& p = chosen.absorber;
    // The peaks: of every output for the summary that reports them (and of the first output
    // with the exact polish: frf_settings).
    FrfChoices wanted;
    wanted.peaks = wanted.peaks_of_every_output = !o.output.summary.empty();
    FrfSettings settings = o.frf.settings(command, chosen, wanted);
    settings.at = o.at.empty() ? std::vector<double>{} : parse_frequencies("--at", o.at);
    ContinuationOptions& co = settings.continuation;
    if (o.output.dry_run) {  // the same checks, without building the Fourier matrices
        HarmonicBalance::validate(system, settings.harmonic_balance);
        return o.output.dry_run_done("frf");
    }
    // An interrupt or the time limit stops the run; what it has computed is written (exit 3).
    StopRequest stop("frf", time_limit);
    stop.watch_crawl(co.omega_end - co.omega_start);
    co.stop = stop.function();
    HarmonicBalance hb(system, settings.harmonic_balance);
    // The contacts' state under the static load and preloads alone (static_state.hpp).
    const StaticState* rest = hb.rest_state();
    ProgressLine progress(o.output.progress(), "frf");
    co.progress = [&progress, &stop](double omega, int points) {
        stop.reached(omega);
        char text[64];
        std::snprintf(text, sizeof text, "w = %-12.6g %6d points", omega, points);
        progress.update(text);
    };
    co.fold_progress = [&progress, &stop](int done, int total) {
        stop.pause_crawl();  // the branch waits while its folds are located
        char text[64];
        std::snprintf(text, sizeof text, "locating folds %6d of %d", done, total);
        progress.update(text);
    };
    settings.polish_progress = [&progress, &stop](int done, int total) {
        stop.pause_crawl();
        char text[64];
        std::snprintf(text, sizeof text, "exact polish %6d of %d points", done, total);
        progress.update(text);
    };
    settings.stability_options.progress = [&progress, &stop](int done, int total) {
        stop.pause_crawl();
        char text[64];
        std::snprintf(text, sizeof text, "stability %6d of %d points", done, total);
        progress.update(text);
    };
    FrfResult frf = compute_frf(hb, settings);
    progress.clear();
    const BranchResult& branch = frf.branch;
    const std::vector<SolutionPoint>& points = frf.points;
    const std::vector<PointMetrics>& metrics = frf.metrics;
    const std::optional<PolishedBranch>& polish = frf.polish;
    const std::vector<Peak>& peaks = frf.peaks;
    const std::size_t sample_count = static_cast<std::size_t>(std::count_if(
        points.begin(), points.end(), [](const SolutionPoint& x) { return x.kind == PointKind::sample; }));

    // Time-integration check points on a uniform grid, swept up from the stuck linear state.
    std::vector<PeriodicResponse> overlay;
    MessageCollector overlay_messages;  // the overlay's own (the FRF's are frf.messages)
    Verdict overlay_verdict;            // its points that did not converge, its stop
    if (overlay_points > 0) {
        const std::vector<double> grid = analytic::uniform_grid(co.omega_start, co.omega_end, overlay_points);
        const Eigen::VectorXd start = linear_stuck_state(system, grid.front());
        TimeIntegrationOptions tio;
        tio.outputs = outputs;
        stop.pause_crawl();  // the crawl watch is the continuation's
        tio.stop = stop.function();
        overlay = sweep(system, grid, tio, &start);
        // A check that did not converge or was stopped leaves the plot doubtful: said (exit 3).
        const bool stopped = !overlay.empty() && overlay.back().stopped;
        const std::vector<PeriodicResponse> finished(overlay.begin(), overlay.end() - (stopped ? 1 : 0));
        const Verdict judged = judge_sweep(system, finished, tio, nullptr);
        if (!judged.errors.empty())
            overlay_verdict.warning("--overlay-timeint: " + judged.errors.back() + "; the first: " + judged.errors.front());
        for (const std::string& w : judged.warnings) overlay_verdict.warning("--overlay-timeint: " + w);
        for (const std::string& n : judged.notes) overlay_verdict.note("--overlay-timeint: " + n);
        if (stopped)
            overlay_verdict.warning("--overlay-timeint was stopped (" + stop.why() + ") after " +
                                    std::to_string(finished.size()) + " of " + std::to_string(grid.size()) +
                                    " check frequencies");
    }
    io::OutputFile out(o.output.out);
    const BranchStability* stability = frf.stability ? &*frf.stability : nullptr;
    const std::vector<InterfaceContacts> interfaces = config ? config->interfaces : std::vector<InterfaceContacts>();
    io::write_frf_csv(out.stream(), points, metrics, outputs, frf.exact, stability, interfaces);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    // Everything that makes the result failed (exit 1) or incomplete/doubtful (exit 3): said on
    // stderr after the files are committed, and in the JSON summary (judge_frf, frf.hpp).
    Verdict verdict = frf.verdict;
    verdict.add(overlay_messages.messages());
    verdict.add(overlay_verdict);
    for (const std::string& line : stop.crawls()) verdict.note(line);
    std::unique_ptr<io::OutputFile> summary;
    if (!o.output.summary.empty()) {
        auto parameters = io::frf_parameters(system, config ? nullptr : &p, hb, co);
        if (chosen.force_scale) parameters.emplace_back("force_scale", *chosen.force_scale);  // the file's excitation times this
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        io::write_frf_summary(summary->stream(), law_name, parameters, branch, metrics, peaks, sample_count, seconds,
                              outputs, polish ? &*polish : nullptr, verdict.errors, verdict.warnings,
                              verdict.notes, stability, rest);
    }
    std::unique_ptr<io::OutputFile> overlay_file;
    if (!overlay.empty()) {
        overlay_file = std::make_unique<io::OutputFile>(overlay_out);
        io::write_timeint_csv(overlay_file->stream(), overlay, outputs);
    }
    if (!o.output.plot.empty()) {
        io::PlotSpec spec = io::frf_plot(points, metrics, outputs.front(), 0, stability,
                                         "hbf frf: " + law_name + ", H = " + std::to_string(hb.harmonics()) +
                                             (hb.odd_harmonics() ? " (odd only)" : "") +
                                             (hb.load_harmonic() == 1
                                                  ? std::string()
                                                  : ", force at " + std::to_string(hb.load_harmonic()) + " w") +
                                             cyclic_label(hb.system().cyclic) +
                                             (config ? " (" + o.frf.config + ")" : ""));
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
        io::write_plot(o.output.plot, spec);  // before the CSV is committed: a failed plot leaves no output
    }
    if (!o.plot_contacts.empty())
        io::write_plot(o.plot_contacts,
                       contact_share_plot(points, metrics, contact_groups(system, config),
                                          "hbf frf: contact states" + (config ? " (" + o.frf.config + ")" : std::string())));
    out.commit();
    if (summary) summary->commit();
    if (overlay_file) overlay_file->commit();

    const bool verbose = o.output.verbose();
    if (verbose && verdict.errors.empty() && branch.status == ContinuationStatus::completed)
        std::cerr << "hbf frf: " << branch.summary() << " in " << format_number(seconds) << " s\n";
    if (stability && verbose) std::cerr << "hbf frf: " << stability->summary() << "\n";
    if (rest && !o.output.quiet)
        std::cerr << "hbf frf: static state" << (rest->ok ? ": " : " not solved: ") << describe(*rest) << "\n";
    if (polish && polish->failed == 0 && (verbose || branch.status != ContinuationStatus::completed))
        std::cerr << "hbf frf: note: " << polish->summary() << " (the transitions are the exact solver's)\n";
    return finish("frf", verdict);
}
/// The flags of hbf frf.
void add_flags(CLI::App& command, FrfOptions& o) {
    o.absorber.add_system_flags(command);
    o.frf.add_to(command);
    command.add_option("--at", o.at,
                        "comma-separated frequencies at which every solution of the branch is written as extra rows\ncomma-separated frequencies W1,W2,...: every solution of the branch there is solved "
                        "exactly and written as extra rows with point = sample")
        ->type_name("LIST");
    o.output.add_to(
        command, {"write the CSV to FILE instead of standard output",
                   "write a JSON summary (parameters, peaks, folds, transitions, status) to FILE\nwrite a JSON summary (parameters, solver statistics, peaks, folds, per-contact ranges, the "
                   "static contact state under static_load and preloads, status, wall time) to FILE",
                   "FILE",
                   "draw the first output's FRF through gnuplot (.png or .svg)\ndraw max over one period of |o(t)| of the first reported output o against w through gnuplot: the "
                   "branch in order, folds, transitions and samples marked; with --stability unstable parts dashed and "
                   "uncertain points marked (.png or .svg)",
                   "no progress or summary line on standard error\nno progress (w reached, points, elapsed time: on a terminal redrawn 4 times a second, "
                   "otherwise, e.g. into a log file, one line a minute) or summary line on standard error"});
    command.add_option("--time-limit", o.time_limit,
                       "stop after SECONDS and write the points computed so far (exit 3, status stopped); 0: none\n"
                       "stop the run after SECONDS of wall time (0: no limit) and write what it has computed: the "
                       "branch's points so far (status stopped, exit code 3; the phases after the branch, such as "
                       "the exact polish or the error estimate, are skipped and a note names them; a stop during "
                       "the polish keeps the points polished so far, the others harmonic balance's). An interrupt "
                       "(Ctrl-C, SIGTERM, SIGHUP) does the same; a second one ends the process without output")
        ->option_text("SECONDS");
    command.add_option("--overlay-timeint", o.overlay,
                        "also integrate K frequencies in time and draw them on the --plot\nalso integrate K frequencies of a uniform grid over [wmin, wmax] in time (an up-sweep, "
                        "hbf timeint's defaults) and draw them as markers on the --plot; their rows go to "
                        "--overlay-out")
        ->option_text("K");
    command.add_option("--plot-contacts", o.plot_contacts,
                       "draw the shares of the period the contacts stick, slip and are open against w (.png or .svg)\ndraw the contacts' states against w through gnuplot: the shares of the period stuck, "
                       "slipping and open (N = 0), averaged over each [[interface]]'s nodes (columns "
                       "stuck_share_i<k>, slip_share_i<k>, open_share_i<k>), or over every contact of a system "
                       "without interfaces (.png or .svg)")
        ->option_text("FILE.png|FILE.svg");
    command.add_option("--overlay-out", o.overlay_out,
                        "CSV of the --overlay-timeint points (hbf timeint's columns) [default: the plot's name "
                        "with -timeint.csv]")
        ->option_text("FILE");
    describe_output(command, {
        R"(Output: CSV with a header row, one row per continuation point in branch order, then the --at
samples. Nondimensional as in the paper: y = x / x_s, x_s = N / k1, w = Omega / omega1 (with
--config: the file's units).
Columns:)",
        io::frf_columns({Output::dof(0), Output::dof(1)}, 1, {0}, {InterfaceContacts{}}),  // with the normal-contact columns
        R"(Exit code 1 when the continuation could not start, stalled (min step) or its solver failed on a
step (solver_error: a contact model that could not evaluate the point), when the exact polish
failed at some point (those rows keep their HB values, exact = failed), or when an --at frequency
got no row (outside the branch, or its solve failed; named on standard error); the points computed
so far are still written. Exit code 3 when the result is written but incomplete or doubtful: an
amplitude cap (an unbounded resonance), a branch that left the range or used up its points or its
--time-limit, an interrupt (the first Ctrl-C stops the run and writes what it has), an
unlocated transition, a point that fails the energy balance, or a warning of Ceres (each reason one
line on standard error). With --stability, uncertain verdicts (column stable = uncertain: the two
routes disagree, typically at a fold) are a note on standard error, not an exit code: the FRF itself
is complete.)"});
}
}  // namespace

Runner add_frf_command(CLI::App& app) {
    return register_command<FrfOptions>(app, "frf", "Frequency response of a structure with friction and contact (--config FILE, or the paper's "
               "friction absorber by default) by multi-harmonic balance and continuation in w: branches, folds, "
               "stick-slip transitions, peaks, exact polish and stability.", add_flags, run);
}

}  // namespace hbf::cli
