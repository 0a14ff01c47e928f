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
#include "outputs.hpp"
#include "progress.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/optimize.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"
#include "hbf/tracking.hpp"
#include "study.hpp"

namespace hbf::cli {

namespace {
struct OptimizeOptions_ {
    AbsorberFlags absorber;
    FrfFlags frf;
    std::string param = "mu", range, scan = "13", param_tolerance = "1e-4", max_frfs = "200", threads = "0",
                contact = "1", wa_range, wa_scan = "7", method = "golden";
    OutputFlags output;
};

using nlohmann::json;
json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::vector<io::Column> trace_columns(const std::string& param, bool joint) {
    std::vector<io::Column> columns = {{"evaluation", "1-based order of the FRF in the search"}};
    if (joint)
        columns.insert(columns.end(),
                       {{"search", "(--param mu,wa only) 1-based order of the search in mu this FRF belongs to (one per value of wa)"},
                        {"wa_phase", "(--param mu,wa only) scan (log-spaced over --wa-range) or golden (the golden-section search in log wa) "
                                     "of that search's wa"},
                        {"wa", "(--param mu,wa only) the tuning ratio of this FRF"}});
    const std::vector<io::Column> rest = {
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
    columns.insert(columns.end(), rest.begin(), rest.end());
    return columns;
}

std::vector<io::Column> tracking_columns(const std::string& param) {
    return {{"track", "--method tracking: down (from the best scan value to its lower neighbour) or up (to its upper "
                      "neighbour)",
             io::ColumnType::text},
            {"curve", "the tracked peak (1-based within its track)"},
            {param, "the parameter's value"},
            {"w", "the peak's frequency"},
            {"peak", "the peak's value: max over one period of |o(t)| of the first output"},
            {"kind", "start, step, at, exchange (two peaks equal), search (locating where a peak ends), end",
             io::ColumnType::text},
            {"regime", "contact 1's regime at the peak", io::ColumnType::text}};
}

/// The tracking optimum as the search result the rest of the command reports.
OptimizeResult as_optimize_result(const TrackOptimum& t) {
    OptimizeResult r;
    r.status = t.status;
    r.parameter = t.parameter;
    r.peak.value = t.value;
    r.peak.omega = t.omega;
    r.peak.state = std::isfinite(t.value) ? PeakState::bounded : PeakState::failed;
    if (std::isfinite(t.value)) {
        r.peaks.push_back({t.omega, t.value, 1, true, 0, {}});
        if (std::isfinite(t.other_omega)) r.peaks.push_back({t.other_omega, t.value, 1, true, 0, {}});
    }
    r.bracket_lower = r.bracket_upper = t.parameter;
    r.message = t.kind + (t.message.empty() ? "" : ": " + t.message);
    r.seconds = t.seconds;
    return r;
}

/// LOWER:UPPER with 0 < LOWER < UPPER (UsageError naming the flag).
std::pair<double, double> parse_range(const std::string& flag, const std::string& text) {
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos)
        throw UsageError(flag + " = '" + text + "' is not LOWER:UPPER (allowed 0 < LOWER < UPPER)");
    const double lower = parse_double(flag, text.substr(0, colon)), upper = parse_double(flag, text.substr(colon + 1));
    if (!(lower > 0.0 && upper > lower * (1.0 + 1e-9)))
        throw UsageError(flag + " = '" + text + "' is out of range: allowed 0 < LOWER < UPPER");
    return {lower, upper};
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
    o.output.check_plot();
    ChosenSystem chosen = choose_system(command, o.absorber, o.frf.config);
    o.output.check(command, chosen.inputs());
    if (o.param != "mu" && o.param != "wa" && o.param != "mu,wa")
        throw UsageError("--param = '" + o.param + "' is not allowed: allowed mu (the friction coefficient; with "
                         "--config the friction limit of --contact), wa (the absorber's tuning, preset only) or mu,wa "
                         "(both, preset only)");
    const bool joint = o.param == "mu,wa";
    if (o.method != "golden" && o.method != "tracking")
        throw UsageError("--method = '" + o.method + "' is not known: allowed golden (a scan, then golden section on "
                         "whole FRFs) or tracking (a scan, then the peaks followed in the parameter)");
    const bool tracking = o.method == "tracking";
    if (tracking && joint)
        throw UsageError("--method tracking follows the peaks in one parameter: allowed --param mu or wa (mu,wa needs "
                         "--method golden)");
    if (tracking && given(command, "--max-frfs"))
        throw UsageError("--max-frfs bounds the golden-section search: --method tracking computes the scan's FRFs and "
                         "a few checks (its cost is in the JSON)");
    if (joint && chosen.config)
        throw UsageError("--param = mu,wa needs the paper's absorber (wa is its tuning): with --config allowed mu");
    for (const char* flag : {"--wa-range", "--wa-scan"})
        if (!joint && given(command, flag))
            throw UsageError(std::string(flag) + " belongs to --param mu,wa: drop it, or search both parameters");
    const StudyParameter parameter("--param", joint ? "mu" : o.param, chosen, "--contact", o.contact);
    if (parameter.integer())
        throw UsageError("--param " + parameter.name() + " takes integer values: hbf optimize searches a continuous parameter; allowed: hbf map --param " +
                         parameter.name() + " --values V1,V2,...");
    if (given(command, "--contact") && parameter.preset())
        throw UsageError("--contact chooses a contact of a --config system: the preset has one");
    for (const std::string name : {"mu", "wa"})
        if (parameter.preset() && (joint || o.param == name) && given(command, ("--" + name).c_str()))
            throw UsageError("--" + name + " is what hbf optimize finds: drop it (its range is " +
                             (name == "wa" && joint ? "--wa-range" : "--range") + ")");
    if (given(command, "--stability") && o.frf.stability != "off")
        throw UsageError("--stability applies to hbf frf and hbf map (their CSV rows): the optimizer reports peaks only");
    FrfSettings settings = o.frf.settings(command, chosen);
    settings.peaks = true;
    OptimizeOptions oo;
    // The default range: the friction force from 1 % to 10 times the force amplitude (the
    // optimum of a Coulomb damper scales with it), the tuning from 0.5 to 2.
    const double force = chosen.system.excitation.cwiseAbs().maxCoeff();
    const bool friction = parameter.name() == "mu";
    if (o.range.empty()) {
        if (given(command, "--range")) throw UsageError("--range is empty: allowed LOWER:UPPER, 0 < LOWER < UPPER");
        oo.lower = friction ? 0.01 * force : 0.5;
        oo.upper = friction ? 10.0 * force : 2.0;
    } else {
        std::tie(oo.lower, oo.upper) = parse_range("--range", o.range);
    }
    for (double v : {oo.lower, oo.upper}) {
        try {
            (void)parameter.system(v);
        } catch (const InvalidInput& e) {
            throw UsageError("--range: " + parameter.name() + " = " + format_number(v) + ": " + e.what());
        }
    }
    OptimizeOptions tuning;  // the search in wa of --param mu,wa
    if (joint) {
        if (o.wa_range.empty() && given(command, "--wa-range"))
            throw UsageError("--wa-range is empty: allowed LOWER:UPPER, 0 < LOWER < UPPER");
        std::tie(tuning.lower, tuning.upper) = o.wa_range.empty() ? std::pair(0.5, 2.0) : parse_range("--wa-range", o.wa_range);
        tuning.scan_points = parse_count("--wa-scan", o.wa_scan, 3, 1000);
        tuning.max_evaluations = 1000;
    }
    oo.scan_points = parse_count("--scan", o.scan, 3, 1000);
    oo.tolerance = parse_double("--param-tolerance", o.param_tolerance);
    if (!(oo.tolerance >= 1e-12 && oo.tolerance <= 0.1))
        throw UsageError("--param-tolerance = " + o.param_tolerance + " is out of range: allowed 1e-12..0.1");
    oo.max_evaluations = parse_count("--max-frfs", o.max_frfs, oo.scan_points + 1, 100000);
    oo.threads = parse_count("--threads", o.threads, 0, 4096);
    tuning.tolerance = oo.tolerance;
    HarmonicBalance::validate(parameter.system(oo.lower), settings.harmonic_balance);
    if (o.output.dry_run) return o.output.dry_run_done("optimize");

    ProgressLine progress(o.output.progress(), "optimize");
    oo.progress = [&progress](const std::string& text) { progress.update(text); };
    JointOptimizeResult joint_result;
    if (joint)
        joint_result = optimize_two_parameters(
            [&](double mu, double wa) { return parameter.with_tuning(wa).system(mu); }, settings, oo, tuning);
    // The search reported: in the parameter, or (joint) in wa, each of its evaluations the best
    // of a search in mu.
    TrackOptimum tracked;
    if (tracking) tracked = optimize_by_tracking([&](double v) { return parameter.system(v); }, settings, oo);
    const OptimizeResult result = joint      ? joint_result.outer
                                  : tracking ? as_optimize_result(tracked)
                                             : optimize_parameter([&](double v) { return parameter.system(v); }, settings, oo);
    progress.clear();
    const double best_mu = joint ? joint_result.parameter : result.parameter;
    const std::string summary_line = joint ? joint_result.summary("mu", "wa") : result.summary(parameter.name());

    // Comparisons (the preset's friction coefficient only): the Den Hartog friction (paper
    // eq. 32 as derived in analytic.hpp: its largest value over [wmin, wmax], as the paper's
    // Fig. 16), the minimum-displacement rule (stuck at every w) and the viscous Den Hartog
    // absorber, whose fixed points put the peak at fe sqrt(1 + 2/r).
    json comparisons = json::object();
    LibraryMessages comparison_messages;  // the Den Hartog FRF's
    const ContinuationOptions& co = settings.continuation;
    if (parameter.preset() && friction) {
        const AbsorberParameters& p = chosen.absorber;
        const FrictionLaw law = chosen.system.contacts.front().law;
        double mu_dh = 0.0;
        for (int k = 0; k <= 2000; ++k)
            mu_dh = std::max(mu_dh, analytic::den_hartog_friction(p, co.omega_start + (co.omega_end - co.omega_start) * k / 2000));
        // Jointly: the Den Hartog design, at its tuning 1/(1 + r); else at this system's wa.
        const double wa_dh = joint ? analytic::den_hartog_tuning(p.mass_ratio) : p.tuning_ratio;
        FrfResult dh;
        try {
            dh = compute_frf(parameter.with_tuning(wa_dh).system(mu_dh), settings);
            comparison_messages = dh.messages;
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
            {"wa", wa_dh},
            {"peak", number_or_null(dh.peak.value)},
            {"peak_w", number_or_null(dh.peak.omega)},
            {"peak_state", to_string(dh.peak.state)},
            {"peak_ratio", ratio(dh.peak.objective())},
            {"meaning", "the paper's Den Hartog friction coefficient (Section 4.1, eq. 32 as derived): the largest "
                        "mu_op(w) over [wmin, wmax]; its FRF at wa (this system's, or with --param mu,wa Den "
                        "Hartog's tuning 1/(1 + r))"}};
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

    // the library's verdict of the search (frf.hpp), with the comparison FRF's messages
    Verdict verdict = joint      ? joint_result.verdict("mu", "wa", comparison_messages)
                      : tracking ? tracked.verdict(parameter.name())
                                 : result.verdict(parameter.name(), comparison_messages);
    if (tracking) verdict.add(comparison_messages);

    io::OutputFile out(o.output.out);
    const std::vector<io::Column> columns =
        tracking ? tracking_columns(parameter.name()) : trace_columns(parameter.name(), joint);
    for (std::size_t c = 0; c < columns.size(); ++c) out.stream() << (c ? "," : "") << columns[c].name;
    out.stream() << '\n';
    std::size_t row = 0;
    auto write_row = [&](const OptimizeEvaluation& e) {
        const bool bounded = e.peak.state == PeakState::bounded;
        out.stream() << e.phase << ',' << io::csv_field(e.parameter) << ','
                     << (bounded ? io::csv_field(e.peak.value) : "") << ','
                     << (bounded ? io::csv_field(e.peak.omega) : "") << ',' << to_string(e.peak.state) << ','
                     << to_string(e.status) << ',' << e.peaks.size() << ',' << io::csv_field(e.seconds) << '\n';
    };
    if (joint) {
        for (std::size_t k = 0; k < joint_result.inner.size(); ++k)
            for (const OptimizeEvaluation& e : joint_result.inner[k].trace) {
                const OptimizeEvaluation& search = result.trace[k];
                out.stream() << ++row << ',' << k + 1 << ',' << search.phase << ',' << io::csv_field(search.parameter)
                             << ',';
                write_row(e);
            }
    } else if (tracking) {
        for (std::size_t t = 0; t < tracked.tracks.size(); ++t)
            for (const TrackCurve& c : tracked.tracks[t].curves)
                for (const TrackPoint& q : c.points)
                    out.stream() << (t == 0 ? "down" : "up") << ',' << c.id << ',' << io::csv_field(q.p) << ','
                                 << io::csv_field(q.omega) << ',' << io::csv_field(q.value) << ',' << q.kind << ','
                                 << q.regime << '\n';
    } else {
        for (const OptimizeEvaluation& e : result.trace) {
            out.stream() << ++row << ',';
            write_row(e);
        }
    }
    std::unique_ptr<io::OutputFile> summary;
    if (!o.output.summary.empty()) {
        json peaks = json::array();
        for (const Peak& p : result.peaks)
            peaks.push_back({{"w", p.omega}, {"y_max", p.y_max}, {"branch", p.branch}, {"refined", p.refined}});
        json j;
        j["command"] = "optimize";
        j["law"] = chosen.law_name;
        if (chosen.force_scale) j["force_scale"] = *chosen.force_scale;
        j["parameter"] = {{"name", o.param}, {"meaning", parameter.meaning()}, {"range", {oo.lower, oo.upper}}};
        if (joint)
            j["parameter"]["wa"] = {{"meaning", "tuning ratio omega2/omega1, searched outside: each value gets a "
                                                "whole search in mu"},
                                    {"range", {tuning.lower, tuning.upper}},
                                    {"scan_points", tuning.scan_points}};
        j["status"] = to_string(result.status);
        j["message"] = result.message;
        j["optimum"] = {{"value", best_mu},
                        {"peak", number_or_null(result.peak.value)},
                        {"peak_w", number_or_null(result.peak.omega)},
                        {"peak_state", to_string(result.peak.state)},
                        {"peaks", peaks},
                        {"bracket", {result.bracket_lower, result.bracket_upper}}};
        if (joint) {
            const OptimizeResult& at_best = joint_result.inner[joint_result.best];
            j["optimum"]["wa"] = result.parameter;
            j["optimum"]["wa_bracket"] = j["optimum"]["bracket"];
            j["optimum"]["bracket"] = {at_best.bracket_lower, at_best.bracket_upper};
            j["optimum"]["status_in_mu"] = to_string(at_best.status);
            j["searches"] = joint_result.inner.size();
            j["searches_not_converged"] = joint_result.inner_not_converged;
            int failed = 0;
            for (const OptimizeResult& r : joint_result.inner) failed += r.failed;
            j["frfs"] = joint_result.frfs();
            j["failed_frfs"] = failed;
        } else if (tracking) {
            j["frfs"] = tracked.frfs;
            j["solves"] = tracked.solves;
            j["optimum"]["kind"] = tracked.kind;
            j["optimum"]["check_peak"] = number_or_null(tracked.check_value);
            j["restarts"] = tracked.restarts;
            j["failed_curves"] = tracked.failed_curves;
        } else {
            j["frfs"] = result.trace.size();
            j["failed_frfs"] = result.failed;
        }
        j["method"] = o.method;
        j["scan_points"] = oo.scan_points;
        j["param_tolerance"] = oo.tolerance;
        j["comparisons"] = comparisons;
        j["wall_time_seconds"] = result.seconds;  // jointly: the search in wa, every search in mu included
        j["outcome"] = !verdict.errors.empty() ? "failed" : verdict.warnings.empty() ? "completed" : "incomplete";
        j["errors"] = verdict.errors;
        j["warnings"] = verdict.warnings;
        j["notes"] = verdict.notes;
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        summary->stream() << j.dump(2) << '\n';
    }
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = "hbf optimize: " + chosen.law_name + ", largest peak against " +
                     (joint ? "wa, each point at its best mu" : o.param);
        spec.xlabel = joint ? "wa" : o.param;
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
        io::PlotCurve curve{joint ? "the best peak of a search in mu (bounded)" : "FRFs (bounded)", {}, {},
                            io::PlotCurve::Style::line, 7};
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
        if (tracking) {  // the scan's FRFs and the tracked peaks
            spec.curves.clear();
            io::PlotCurve scan{"scan FRFs (bounded)", {}, {}, io::PlotCurve::Style::markers, 7};
            for (std::size_t k = 0; k < tracked.scan.size(); ++k)
                if (std::isfinite(tracked.scan_values[k])) {
                    scan.x.push_back(tracked.scan[k]);
                    scan.y.push_back(tracked.scan_values[k]);
                }
            spec.curves.push_back(scan);
            for (std::size_t t = 0; t < tracked.tracks.size(); ++t)
                for (const TrackCurve& c : tracked.tracks[t].curves) {
                    io::PlotCurve line{std::string(t == 0 ? "down" : "up") + ": " + c.label, {}, {},
                                       io::PlotCurve::Style::line, static_cast<int>(2 + 3 * t + c.id)};
                    for (const TrackPoint& q : c.points) {
                        line.x.push_back(q.p);
                        line.y.push_back(q.value);
                    }
                    spec.curves.push_back(line);
                }
        }
        if (result.peak.state == PeakState::bounded)
            spec.curves.push_back({joint ? "optimum wa = " + format_number(result.parameter) + ", mu = " + format_number(best_mu)
                                         : "optimum " + o.param + " = " + format_number(result.parameter),
                                   {result.parameter}, {result.peak.value}, io::PlotCurve::Style::markers, 6});
        if (comparisons.contains("den_hartog") && comparisons["den_hartog"]["peak_state"] == "bounded")
            spec.curves.push_back({joint ? "Den Hartog design (wa = 1/(1 + r), its mu)" : "Den Hartog mu",
                                   {comparisons["den_hartog"][joint ? "wa" : "mu"].get<double>()},
                                   {comparisons["den_hartog"]["peak"].get<double>()}, io::PlotCurve::Style::markers, 4});
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    if (summary) summary->commit();
    if (o.output.verbose())
        std::cerr << "hbf optimize: " << summary_line << "\n";
    return finish("optimize", verdict);
}
/// The flags of hbf optimize.
void add_flags(CLI::App& command, OptimizeOptions_& o) {
    o.absorber.add_system_flags(command);
    o.frf.add_to(command);
    command.add_option("--param", o.param,
                        "what is optimised: mu, wa or both\nwhat is optimised: mu (the friction coefficient; with --config the friction limit F_c of the "
                        "contact --contact), wa (the preset's tuning ratio, at the --mu given) or mu,wa (both: for each "
                        "wa of a search over --wa-range, a whole search in mu; about --wa-scan + 20 times more FRFs)")
        ->capture_default_str()->type_name("mu|wa|mu,wa");
    command.add_option("--range", o.range,
                        "the search range LOWER:UPPER, 0 < LOWER < UPPER\nthe search range LOWER:UPPER (0 < LOWER < UPPER) [default: mu from 0.01 to 10 times the "
                        "largest force amplitude |F|_inf (fe for the preset); wa from 0.5 to 2]")
        ->type_name("LOWER:UPPER");
    command.add_option("--wa-range", o.wa_range,
                        "--param mu,wa: the range of the tuning LOWER:UPPER (0 < LOWER < UPPER) [default: 0.5:2]")
        ->type_name("LOWER:UPPER");
    command.add_option("--wa-scan", o.wa_scan,
                        "--param mu,wa: values of wa of the first, log-spaced scan, 3..1000 (each a search in mu)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--method", o.method,
                        "golden (a scan, then a golden-section search) or tracking (the peaks followed)\ngolden: the scan, then a golden-section search in log of the parameter on whole FRFs (to "
                        "--param-tolerance); tracking: the scan, then the peaks followed from the best scan value to its "
                        "neighbours (hbf track): the optimum is where two peaks are equal (located to 1e-10) or a "
                        "peak's minimum (Brent on located peaks, to 1e-2 --param-tolerance), checked by an FRF there; "
                        "--param mu or wa")
        ->capture_default_str()->type_name("golden|tracking");
    command.add_option("--contact", o.contact, "--config: the contact whose friction limit is optimised (1-based)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--scan", o.scan,
                        "FRFs of the first, log-spaced scan, 3..1000\nFRFs of the first, log-spaced scan over the range, 3..1000: it brackets the optimum (the "
                        "peak is unbounded at both ends for a friction damper without viscous damping)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--param-tolerance", o.param_tolerance,
                        "the search stops when the bracket is narrower than this fraction of the parameter, 1e-12..0.1")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-frfs", o.max_frfs, "largest number of FRFs (scan included); with --param mu,wa of each search in mu")
        ->capture_default_str()->type_name("INT");
    command.add_option("--threads", o.threads, "FRFs of the scan computed at once; 0 = every core")
        ->capture_default_str()->type_name("INT");
    o.output.add_to(command,
                           {"write the convergence trace (CSV, one row per FRF) to FILE instead of standard output",
                            "write a JSON summary (the optimum, the bracket, the trace) to FILE\nwrite a JSON summary to FILE: the optimum (value, largest peak and its w, every peak), the "
                            "final bracket, the number of FRFs, and the comparisons with the Den Hartog friction, the "
                            "minimum-displacement rule and the viscous Den Hartog absorber (peak ratios to the optimum)",
                            "FILE", "draw the largest peak against the parameter, the optimum marked",
                            "no progress line (on a terminal; otherwise one line a minute) or summary line on standard error"});
    describe_output(command, {
        R"(Output: the convergence trace, one row per FRF in the order computed (with --method tracking
instead the tracked peaks, one row per point: track (down or up from the best scan value), curve,
mu, w, peak, kind, regime). Columns:)",
        trace_columns("mu", true),
        R"(The objective is the largest max over one period of |y1(t)| (the first output with --config) over
the whole FRF, every branch and fold included (nondimensional for the preset). Exit code 0 when the
search converged; 3 when the optimum lies at an end of the range, the FRF budget ran out, or an FRF
near the optimum failed; 1 when no value of the range gives a bounded response.)"});
}
}  // namespace

Runner add_optimize_command(CLI::App& app) {
    return register_command<OptimizeOptions_>(app, "optimize", "The friction coefficient (or the tuning wa, or both) that minimises the largest peak of the main mass's "
                    "FRF over [wmin, wmax] (paper Section 4): a log-spaced scan on threads, then a golden-section "
                    "search in log of the parameter, every FRF a full branch with refined peaks (or, --method "
                    "tracking, the peaks followed from the best scan value).", add_flags, run);
}

}  // namespace hbf::cli
