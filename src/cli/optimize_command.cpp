// `hbf optimize`: the friction coefficient (or another parameter) that minimises the largest
// peak of the main mass's FRF over [wmin, wmax] (paper Section 4), from full branches with
// refined peaks; compared with the Den Hartog formula, the minimum-displacement rule and the
// viscous Den Hartog absorber.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "arguments.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "hbf/analytic.hpp"
#include "hbf/design.hpp"
#include "hbf/error.hpp"
#include "hbf/io.hpp"
#include "hbf/plot.hpp"
#include "study.hpp"

namespace hbf::cli {

namespace {
struct OptimizeOptions_ {
    AbsorberFlags absorber;
    FrfFlags frf;
    std::string param = "mu", range, scan = "13", param_tolerance = "1e-4", max_frfs = "200", threads = "0",
                contact = "1", out, summary, plot;
    bool quiet = false;
};

using nlohmann::json;
json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::vector<io::Column> trace_columns(const std::string& param) {
    return {{"evaluation", "1-based order of the FRF in the search"},
               {"phase", "scan (the first, log-spaced, on threads) or golden (the golden-section search in log " + param + ")"},
               {param, "the parameter's value of this FRF"},
               {"peak", "largest max over one period of |o(t)| of the first output (y1 for the absorber) over the FRF: "
                        "the objective; empty when unbounded or failed"},
               {"peak_w", "frequency w of that peak"},
               {"peak_state", "bounded (the branch spans [wmin, wmax]), unbounded (amplitude_cap: a resonance grows "
                              "past --max-amplitude), incomplete (left_range, point_budget) or failed (a stall or a "
                              "failed exact polish): only bounded values can be the optimum"},
               {"frf_status", "the FRF's continuation status"},
               {"peaks", "number of refined peaks of the first output on the FRF"},
               {"seconds", "wall time of the FRF"}};
}

/// The largest stuck (minimum-displacement design) response of the preset over [wmin, wmax]:
/// the rule mu = mu_limit(w) keeps the contact stuck at every w, so the main mass follows the
/// stuck linear system. Unbounded where the stuck system has no damping.
double stuck_peak(const AbsorberParameters& p, FrictionLaw law, double wmin, double wmax) {
    if (law == FrictionLaw::lugre && p.contact_damping_ratio > 0.0) {
        double best = 0.0;
        const int n = 20001;
        for (int k = 0; k < n; ++k) {
            const double w = wmin + (wmax - wmin) * k / (n - 1);
            best = std::max(best, std::abs(analytic::stick(p, w, law).y1));
        }
        return best;
    }
    return std::numeric_limits<double>::infinity();
}

int run(const CLI::App& command, const OptimizeOptions_& o) {
    io::check_plot("--plot", o.plot);
    io::check_outputs({{"--out", o.out, given(command, "--out"), true},
                       {"--summary", o.summary, given(command, "--summary")},
                       {"--plot", o.plot, given(command, "--plot"), false, true}});
    ChosenSystem chosen = choose_system(command, o.absorber, o.frf.config);
    if (o.param != "mu" && o.param != "wa")
        throw UsageError("--param = '" + o.param + "' is not allowed: allowed mu (the friction coefficient; with "
                         "--config the friction limit of --contact) or wa (the absorber's tuning, preset only)");
    const StudyParameter parameter("--param", o.param, chosen, "--contact", o.contact);
    if (given(command, "--contact") && parameter.preset())
        throw UsageError("--contact chooses a contact of a --config system: the preset has one");
    if (parameter.preset() && given(command, ("--" + o.param).c_str()))
        throw UsageError("--" + o.param + " is what hbf optimize finds: drop it (its range is --range)");
    FrfSettings settings = o.frf.settings(command, chosen);
    settings.peaks = true;
    OptimizeOptions oo;
    // The default range: the friction force from 1 % to 10 times the force amplitude (the
    // optimum of a Coulomb damper scales with it), the tuning from 0.5 to 2.
    const double force = chosen.system.excitation.cwiseAbs().maxCoeff();
    if (o.range.empty()) {
        if (given(command, "--range")) throw UsageError("--range is empty: allowed LOWER:UPPER, 0 < LOWER < UPPER");
        oo.lower = o.param == "mu" ? 0.01 * force : 0.5;
        oo.upper = o.param == "mu" ? 10.0 * force : 2.0;
    } else {
        const std::size_t colon = o.range.find(':');
        if (colon == std::string::npos)
            throw UsageError("--range = '" + o.range + "' is not LOWER:UPPER (allowed 0 < LOWER < UPPER)");
        oo.lower = parse_double("--range", o.range.substr(0, colon));
        oo.upper = parse_double("--range", o.range.substr(colon + 1));
        if (!(oo.lower > 0.0 && oo.upper > oo.lower * (1.0 + 1e-9)))
            throw UsageError("--range = '" + o.range + "' is out of range: allowed 0 < LOWER < UPPER");
    }
    for (double v : {oo.lower, oo.upper}) {
        try {
            (void)parameter.system(v);
        } catch (const InvalidInput& e) {
            throw UsageError("--range: " + o.param + " = " + format_number(v) + ": " + e.what());
        }
    }
    oo.scan_points = parse_count("--scan", o.scan, 3, 1000);
    oo.tolerance = parse_double("--param-tolerance", o.param_tolerance);
    if (!(oo.tolerance >= 1e-12 && oo.tolerance <= 0.1))
        throw UsageError("--param-tolerance = " + o.param_tolerance + " is out of range: allowed 1e-12..0.1");
    oo.max_evaluations = parse_count("--max-frfs", o.max_frfs, oo.scan_points + 1, 100000);
    oo.threads = parse_count("--threads", o.threads, 0, 4096);
    HarmonicBalance::validate(parameter.system(oo.lower), settings.harmonic_balance);
    validate(settings.continuation);
    if (dry_run()) {
        std::cerr << "hbf optimize: dry run: every input and output is valid; nothing computed, nothing written\n";
        return exit_success;
    }

    const OptimizeResult result = optimize_parameter([&](double v) { return parameter.system(v); }, settings, oo);

    // Comparisons (the preset's friction coefficient only): the Den Hartog friction (paper
    // eq. 32 as derived in analytic.hpp: its largest value over [wmin, wmax], as the paper's
    // Fig. 16), the minimum-displacement rule (stuck at every w) and the viscous Den Hartog
    // absorber, whose fixed points put the peak at fe sqrt(1 + 2/r).
    json comparisons = json::object();
    const ContinuationOptions& co = settings.continuation;
    if (parameter.preset() && o.param == "mu") {
        const AbsorberParameters& p = chosen.absorber;
        const FrictionLaw law = chosen.system.contacts.front().law;
        double mu_dh = 0.0;
        for (int k = 0; k <= 2000; ++k)
            mu_dh = std::max(mu_dh, analytic::den_hartog_friction(p, co.omega_start + (co.omega_end - co.omega_start) * k / 2000));
        FrfResult dh;
        try {
            dh = compute_frf(parameter.system(mu_dh), settings);
        } catch (const InvalidInput&) {
            dh.peak.state = PeakState::failed;
        }
        const double viscous = p.excitation * std::sqrt(1.0 + 2.0 / p.mass_ratio);
        const double stuck = stuck_peak(p, law, co.omega_start, co.omega_end);
        const double best = result.peak.objective();
        auto ratio = [best](double other) {
            return number_or_null(std::isfinite(other) && std::isfinite(best) && best > 0 ? other / best : NAN);
        };
        comparisons["den_hartog"] = {
            {"mu", mu_dh},
            {"peak", number_or_null(dh.peak.value)},
            {"peak_w", number_or_null(dh.peak.omega)},
            {"peak_state", to_string(dh.peak.state)},
            {"peak_ratio", ratio(dh.peak.objective())},
            {"meaning", "the paper's Den Hartog friction coefficient (Section 4.1, eq. 32 as derived): the largest "
                        "mu_op(w) over [wmin, wmax]; its FRF at this system's wa"}};
        comparisons["min_displacement"] = {
            {"peak", number_or_null(stuck)},
            {"peak_ratio", ratio(stuck)},
            {"meaning", "the paper's minimum-displacement rule (Section 4.2): mu = mu_limit(w) at every w keeps the "
                        "contact stuck, so the main mass follows the stuck linear system; its largest response over "
                        "[wmin, wmax] (null: unbounded, the stuck system has no damping)"}};
        comparisons["viscous_den_hartog"] = {
            {"peak", viscous},
            {"peak_ratio", ratio(viscous)},
            {"meaning", "the optimal viscous absorber of the same mass ratio (Den Hartog): peak y1 = fe sqrt(1 + 2/r) "
                        "at its two fixed points"}};
    }

    Verdict verdict("optimize");
    switch (result.status) {
        case OptimizeStatus::converged: break;
        case OptimizeStatus::at_bound:
        case OptimizeStatus::budget: verdict.warning(result.summary()); break;
        case OptimizeStatus::unbounded:
        case OptimizeStatus::failed: verdict.error(result.summary()); break;
    }
    if (result.failed_in_bracket > 0)
        verdict.warning(std::to_string(result.failed_in_bracket) + " FRF(s) inside the final bracket " +
                        format_number(result.bracket_lower) + ".." + format_number(result.bracket_upper) +
                        " failed or stayed incomplete: the optimum is doubtful there (the trace CSV has them)");
    else if (result.failed > 0)
        verdict.note(std::to_string(result.failed) + " FRF(s) of the search failed or stayed incomplete, all outside "
                     "the final bracket (peak_state in the trace)");
    verdict.add_library_messages();

    io::OutputFile out(o.out);
    const std::vector<io::Column> columns = trace_columns(o.param);
    for (std::size_t c = 0; c < columns.size(); ++c) out.stream() << (c ? "," : "") << columns[c].name;
    out.stream() << '\n';
    for (std::size_t k = 0; k < result.trace.size(); ++k) {
        const OptimizeEvaluation& e = result.trace[k];
        const bool bounded = e.peak.state == PeakState::bounded;
        out.stream() << k + 1 << ',' << e.phase << ',' << io::csv_field(e.parameter) << ','
                     << (bounded ? io::csv_field(e.peak.value) : "") << ','
                     << (bounded ? io::csv_field(e.peak.omega) : "") << ',' << to_string(e.peak.state) << ','
                     << to_string(e.status) << ',' << e.peaks.size() << ',' << io::csv_field(e.seconds) << '\n';
    }
    std::unique_ptr<io::OutputFile> summary;
    if (!o.summary.empty()) {
        json peaks = json::array();
        for (const Peak& p : result.peaks)
            peaks.push_back({{"w", p.omega}, {"y_max", p.y_max}, {"branch", p.branch}, {"refined", p.refined}});
        json j;
        j["command"] = "optimize";
        j["law"] = chosen.law_name;
        j["parameter"] = {{"name", o.param}, {"meaning", parameter.meaning()}, {"range", {oo.lower, oo.upper}}};
        j["status"] = to_string(result.status);
        j["message"] = result.message;
        j["optimum"] = {{"value", result.parameter},
                        {"peak", number_or_null(result.peak.value)},
                        {"peak_w", number_or_null(result.peak.omega)},
                        {"peak_state", to_string(result.peak.state)},
                        {"peaks", peaks},
                        {"bracket", {result.bracket_lower, result.bracket_upper}}};
        j["frfs"] = result.trace.size();
        j["failed_frfs"] = result.failed;
        j["scan_points"] = oo.scan_points;
        j["param_tolerance"] = oo.tolerance;
        j["comparisons"] = comparisons;
        j["wall_time_seconds"] = result.seconds;
        j["outcome"] = !verdict.errors().empty() ? "failed" : verdict.warnings().empty() ? "completed" : "incomplete";
        j["errors"] = verdict.errors();
        j["warnings"] = verdict.warnings();
        j["notes"] = verdict.notes();
        summary = std::make_unique<io::OutputFile>(o.summary);
        summary->stream() << j.dump(2) << '\n';
    }
    if (!o.plot.empty()) {
        io::PlotSpec spec;
        spec.title = "hbf optimize: " + chosen.law_name + ", largest peak against " + o.param;
        spec.xlabel = o.param;
        spec.ylabel = "largest peak of " + (io::frf_columns(chosen.outputs).size() > 1 ? io::frf_columns(chosen.outputs)[1].name
                                                                                         : std::string("y1_max"));
        spec.log_x = true;
        std::vector<const OptimizeEvaluation*> sorted;
        double top = 0.0;
        for (const OptimizeEvaluation& e : result.trace) {
            sorted.push_back(&e);
            if (e.peak.state == PeakState::bounded) top = std::max(top, e.peak.value);
        }
        std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->parameter < b->parameter; });
        io::PlotCurve curve{"FRFs (bounded)", {}, {}, io::PlotCurve::Style::line, 7};
        io::PlotCurve dots{"", {}, {}, io::PlotCurve::Style::points, 7};
        io::PlotCurve capped{"unbounded (capped), drawn at the top", {}, {}, io::PlotCurve::Style::markers, 9};
        io::PlotCurve failed{"failed or incomplete, drawn at the top", {}, {}, io::PlotCurve::Style::markers, 2};
        for (const OptimizeEvaluation* e : sorted) {
            if (e->peak.state == PeakState::bounded) {
                curve.x.push_back(e->parameter);
                curve.y.push_back(e->peak.value);
                dots.x.push_back(e->parameter);
                dots.y.push_back(e->peak.value);
            } else {
                curve.x.push_back(NAN);  // a gap
                curve.y.push_back(NAN);
                io::PlotCurve& c = e->peak.state == PeakState::unbounded ? capped : failed;
                c.x.push_back(e->parameter);
                c.y.push_back(top > 0.0 ? 1.1 * top : 1.0);
            }
        }
        spec.curves = {curve, dots, capped, failed};
        if (result.peak.state == PeakState::bounded)
            spec.curves.push_back({"optimum " + o.param + " = " + format_number(result.parameter),
                                   {result.parameter}, {result.peak.value}, io::PlotCurve::Style::markers, 6});
        if (comparisons.contains("den_hartog") && comparisons["den_hartog"]["peak_state"] == "bounded")
            spec.curves.push_back({"Den Hartog mu", {comparisons["den_hartog"]["mu"].get<double>()},
                                   {comparisons["den_hartog"]["peak"].get<double>()}, io::PlotCurve::Style::markers, 4});
        io::write_plot(o.plot, spec);
    }
    out.commit();
    if (summary) summary->commit();
    if (!o.quiet && isatty(STDERR_FILENO)) std::cerr << "hbf optimize: " << result.summary() << "\n";
    return verdict.finish();
}
}  // namespace

Runner add_optimize_command(CLI::App& app) {
    auto options = std::make_shared<OptimizeOptions_>();
    CLI::App* command = app.add_subcommand(
        "optimize", "The friction coefficient (or the tuning wa) that minimises the largest peak of the main mass's "
                    "FRF over [wmin, wmax] (paper Section 4): a log-spaced scan on threads, then a golden-section "
                    "search in log of the parameter, every FRF a full branch with refined peaks.");
    add_dry_run(*command);
    options->absorber.add_to(*command,
                             "friction law: coulomb (exact), jenkins, dahl, lugre or coulomb-reg (as hbf frf)", "coulomb",
                             true);
    options->absorber.add_excitation_harmonic(*command);
    options->frf.add_to(*command);
    command->add_option("--param", options->param,
                        "what is optimised: mu (the friction coefficient; with --config the friction limit F_c of the "
                        "contact --contact) or wa (the preset's tuning ratio, at the --mu given)")
        ->capture_default_str()->type_name("mu|wa");
    command->add_option("--range", options->range,
                        "the search range LOWER:UPPER (0 < LOWER < UPPER) [default: mu from 0.01 to 10 times the "
                        "largest force amplitude |F|_inf (fe for the preset); wa from 0.5 to 2]")
        ->type_name("LOWER:UPPER");
    command->add_option("--contact", options->contact, "--config: the contact whose friction limit is optimised (1-based)")
        ->capture_default_str()->type_name("INT");
    command->add_option("--scan", options->scan,
                        "FRFs of the first, log-spaced scan over the range, 3..1000: it brackets the optimum (the "
                        "peak is unbounded at both ends for a friction damper without viscous damping)")
        ->capture_default_str()->type_name("INT");
    command->add_option("--param-tolerance", options->param_tolerance,
                        "the search stops when the bracket is narrower than this fraction of the parameter, 1e-12..0.1")
        ->capture_default_str()->type_name("NUMBER");
    command->add_option("--max-frfs", options->max_frfs, "largest number of FRFs (scan included)")
        ->capture_default_str()->type_name("INT");
    command->add_option("--threads", options->threads, "FRFs of the scan computed at once; 0 = every core")
        ->capture_default_str()->type_name("INT");
    command->add_option("--out", options->out,
                        "write the convergence trace (CSV, one row per FRF) to FILE instead of standard output")
        ->option_text("FILE");
    command->add_option("--summary", options->summary,
                        "write a JSON summary to FILE: the optimum (value, largest peak and its w, every peak), the "
                        "final bracket, the number of FRFs, and the comparisons with the Den Hartog friction, the "
                        "minimum-displacement rule and the viscous Den Hartog absorber (peak ratios to the optimum)")
        ->option_text("FILE");
    command->add_option("--plot", options->plot, "draw the largest peak against the parameter, the optimum marked")
        ->option_text("FILE.png|FILE.svg");
    command->add_flag("--quiet", options->quiet, "no summary line on standard error");
    std::string footer = "Output: the convergence trace, one row per FRF in the order computed. Columns:\n";
    for (const auto& c : trace_columns("mu")) footer += "  " + c.name + ": " + c.meaning + "\n";
    footer += "The objective is the largest max over one period of |y1(t)| (the first output with --config) over the "
              "whole FRF, every branch and fold included (nondimensional for the preset). Exit code 0 when the search "
              "converged; 3 when the optimum lies at an end of the range, the FRF budget ran out, or an FRF near the "
              "optimum failed; 1 when no value of the range gives a bounded response.";
    command->footer(footer);
    return [command, options]() { return run(*command, *options); };
}

}  // namespace hbf::cli
