// `hbf track`: a resonance peak or a stick-slip boundary followed through a second parameter
// (fe, mu, wa, ...; a --config contact's key): the curves in the (p, w) plane, their events
// (equal peaks, a peak that ends), a CSV, a JSON summary and a picture (tracking.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "arguments.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "hbf/error.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"
#include "hbf/tracking.hpp"
#include "outputs.hpp"
#include "progress.hpp"
#include "stop_request.hpp"
#include "study.hpp"

namespace hbf::cli {

namespace {
struct TrackFlags {
    AbsorberFlags absorber;
    FrfFlags frf;
    std::string feature = "peak", param, range, omega, at, contact = "1", of_contact, max_step = "0.05",
                min_step = "1e-7", max_points = "5000", plot_of = "w", output_name, time_limit = "0";
    OutputFlags output;
};

using nlohmann::json;

std::vector<io::Column> track_columns(const std::string& param, const std::string& value) {
    return {{"curve", "1-based number of the tracked curve (the JSON's curves[k].label says which feature)"},
            {param, "the parameter's value"},
            {"w", "frequency of the feature at that value (nondimensional for the preset)"},
            {value, "peak: the peak's value, max over one period of |o(t)| of the first output; boundary: that "
                    "output's max over one period on the boundary (its stick side); fold: at the fold"},
            {"kind", "start (the FRF at the first value), step (a continuation step), at (an --at value), exchange "
                     "(two peaks equal: an equal-peak design), cusp (folds: two folds merge), search (locating where "
                     "a curve ends), end (the curve's last point: its status in the JSON)",
             io::ColumnType::text},
            {"regime", "peak: contact 1's regime at the peak; boundary: the tracked contact's on the boundary's stick "
                       "side (stick, stick-slip, slip)",
             io::ColumnType::text},
            {"curvature", "peak: Y'' w^2 / Y at the peak (< 0; tends to 0 where the peak ends); empty for a corner or a "
                          "boundary"},
            {"corner", "peak: true where the peak sits on a stick/slip corner of Y (located as the transition)",
             io::ColumnType::text}};
}

/// START:END (any order, distinct): UsageError naming the flag.
std::pair<double, double> parse_span(const std::string& flag, const std::string& text) {
    const std::size_t colon = text.find(':');
    if (text.empty() || colon == std::string::npos || text.find(':', colon + 1) != std::string::npos)
        throw UsageError(flag + " = '" + text + "' is not START:END (the parameter's first and last values)");
    const double a = parse_double(flag, text.substr(0, colon)), b = parse_double(flag, text.substr(colon + 1));
    if (!(a != b)) throw UsageError(flag + " = '" + text + "' is out of range: START must differ from END");
    return {a, b};
}

int run(const CLI::App& command, const TrackFlags& o) {
    o.output.check_plot();
    if (o.feature != "peak" && o.feature != "boundary" && o.feature != "fold")
        throw UsageError("--feature = '" + o.feature + "' is not known: allowed peak (a resonance peak of the first "
                         "output), boundary (a stick-slip boundary of a contact) or fold (a limit point of the "
                         "harmonic-balance FRF)");
    if (o.plot_of != "w" && o.plot_of != "value")
        throw UsageError("--plot-of = '" + o.plot_of + "' is not known: allowed w or value");
    if (!given(command, "--param")) throw UsageError("--param is required: the parameter followed (e.g. --param mu)");
    if (!given(command, "--range")) throw UsageError("--range is required: START:END, the parameter's first and last values");
    ChosenSystem chosen = choose_system(command, o.absorber, o.frf.config);
    o.output.check(command, chosen.inputs());
    const StudyParameter parameter("--param", o.param, chosen, "--contact", o.contact);
    if (parameter.integer())
        throw UsageError("--param " + parameter.name() + " takes integer values: hbf track follows a continuous parameter; allowed: hbf map --param " +
                         parameter.name() + " --values V1,V2,...");
    parameter.check_flags(command, "the tracked range");
    if (given(command, "--stability") && o.frf.stability != "off")
        throw UsageError("--stability applies to hbf frf and hbf map: hbf track follows peaks and boundaries");
    FrfSettings settings = o.frf.settings(command, chosen);
    if (given(command, "--output")) {  // the tracked output first
        std::string names;
        auto it = settings.outputs.end();
        for (auto k = settings.outputs.begin(); k != settings.outputs.end(); ++k) {
            names += (names.empty() ? "" : ", ") + k->name();
            if (k->name() == o.output_name) it = k;
        }
        if (it == settings.outputs.end())
            throw UsageError("--output = '" + o.output_name + "' is not an output of the system: allowed " + names);
        std::rotate(settings.outputs.begin(), it, it + 1);
    }
    TrackOptions t;
    t.feature = o.feature == "peak" ? TrackFeature::peak : o.feature == "boundary" ? TrackFeature::boundary : TrackFeature::fold;
    std::tie(t.p_start, t.p_end) = parse_span("--range", o.range);
    for (double v : {t.p_start, t.p_end}) {
        try {
            (void)parameter.system(v);
        } catch (const InvalidInput& e) {
            throw UsageError("--range: " + o.param + " = " + format_number(v) + ": " + e.what());
        }
    }
    if (given(command, "--omega")) {
        t.omega = parse_double("--omega", o.omega);
        if (!(t.omega > 0.0)) throw UsageError("--omega = " + o.omega + " is out of range: allowed > 0");
        const double lo = std::min(settings.continuation.omega_start, settings.continuation.omega_end),
                     hi = std::max(settings.continuation.omega_start, settings.continuation.omega_end);
        if (t.omega < lo || t.omega > hi)
            throw UsageError("--omega = " + o.omega + " is out of range: allowed inside [wmin, wmax] = " +
                             format_number(lo) + ".." + format_number(hi));
    }
    if (given(command, "--at")) {
        if (o.at.empty()) throw UsageError("--at is empty: allowed V1,V2,..., START:STOP:N or log:START:STOP:N");
        t.at = parse_values("--at", o.at);
        const double lo = std::min(t.p_start, t.p_end), hi = std::max(t.p_start, t.p_end);
        for (double v : t.at)
            if (v < lo || v > hi)
                throw UsageError("--at: " + o.param + " = " + format_number(v) + " is out of range: allowed inside --range " +
                                 format_number(lo) + ".." + format_number(hi));
    }
    if (given(command, "--of-contact")) {
        if (t.feature != TrackFeature::boundary)
            throw UsageError("--of-contact chooses the contact whose boundaries --feature boundary follows");
        t.contact = parse_count("--of-contact", o.of_contact, 1, static_cast<long long>(chosen.system.contacts.size())) - 1;
    }
    t.max_step = parse_double("--max-step-p", o.max_step);
    if (!(t.max_step >= 1e-6 && t.max_step <= 0.5))
        throw UsageError("--max-step-p = " + o.max_step + " is out of range: allowed 1e-6..0.5 (relative to the range)");
    t.min_step = parse_double("--min-step-p", o.min_step);
    if (!(t.min_step >= 1e-12 && t.min_step <= t.max_step))
        throw UsageError("--min-step-p = " + o.min_step + " is out of range: allowed 1e-12..--max-step-p");
    t.max_points = parse_count("--max-points", o.max_points, 10, 1000000);
    if (t.feature == TrackFeature::boundary && chosen.system.contacts.empty())
        throw UsageError("--feature boundary: the system has no contact");
    HarmonicBalance::validate(parameter.system(t.p_start), settings.harmonic_balance);
    const double time_limit = parse_time_limit(o.time_limit);
    if (o.output.dry_run) return o.output.dry_run_done("track");
    // An interrupt or the time limit stops the curves where they are; they are written (exit 3).
    StopRequest stop("track", time_limit);
    t.stop = stop.function();
    settings.continuation.stop = t.stop;

    ProgressLine progress(o.output.progress(), "track");
    t.progress = [&](double p) { progress.update(o.param + " = " + format_number(p), false); };
    TrackResult r;
    try {
        r = track([&](double v) { return parameter.system(v); }, settings, t);
    } catch (const InvalidInput& e) {
        progress.clear();
        throw UsageError(e.what());
    }
    progress.clear();

    const Output& output = settings.outputs.empty() ? Output::dof(0) : settings.outputs.front();
    const std::string value_name = output.name() + "_max";
    const std::vector<io::Column> columns = track_columns(o.param, value_name);
    io::OutputFile out(o.output.out);
    for (std::size_t c = 0; c < columns.size(); ++c) out.stream() << (c ? "," : "") << columns[c].name;
    out.stream() << '\n';
    for (const TrackCurve& c : r.curves)
        for (const TrackPoint& q : c.points)
            out.stream() << c.id << ',' << io::csv_field(q.p) << ',' << io::csv_field(q.omega) << ','
                         << io::csv_field(q.value) << ',' << q.kind << ',' << q.regime << ','
                         << (std::isfinite(q.curvature) ? io::csv_field(q.curvature) : "") << ','
                         << (q.corner ? "true" : "false") << '\n';

    std::unique_ptr<io::OutputFile> summary;
    if (!o.output.summary.empty()) {
        json j;
        j["command"] = "track";
        j["law"] = chosen.law_name;
        if (chosen.force_scale) j["force_scale"] = *chosen.force_scale;
        j["feature"] = to_string(r.feature);
        j["output"] = value_name;
        j["parameter"] = {{"name", o.param}, {"meaning", parameter.meaning()}, {"range", {t.p_start, t.p_end}}};
        j["solver"] = r.exact ? "exact" : "harmonic balance";
        j["harmonics"] = r.harmonics;
        json curves = json::array();
        for (const TrackCurve& c : r.curves) {
            json cj = {{"curve", c.id},
                       {"label", c.label},
                       {"status", to_string(c.status)},
                       {"message", c.message},
                       {"points", c.points.size()}};
            if (!c.points.empty()) {
                cj["first"] = {{"p", c.points.front().p}, {"w", c.points.front().omega}, {"value", c.points.front().value}};
                cj["last"] = {{"p", c.points.back().p}, {"w", c.points.back().omega}, {"value", c.points.back().value}};
            }
            if (r.feature == TrackFeature::boundary) {
                cj["contact"] = c.contact + 1;
                cj["boundary"] = to_string(c.boundary);
            }
            curves.push_back(cj);
        }
        j["curves"] = curves;
        json events = json::array();
        for (const TrackEvent& e : r.events) {
            json ej = {{"kind", e.kind}, {"p", e.p}, {"w", e.omega}, {"value", e.value}, {"curve", e.curve}};
            if (e.kind == "exchange") {
                ej["other"] = e.other;
                ej["other_w"] = e.other_omega;
            }
            events.push_back(ej);
        }
        j["events"] = events;
        json largest = json::array();
        for (const TrackResult::Largest& l : r.largest)
            if (l.kind == "at") largest.push_back({{"p", l.p}, {"w", l.omega}, {"value", l.value}, {"curve", l.curve}});
        j["largest_at"] = largest;
        j["solves"] = r.solves;
        j["frfs"] = r.frfs;
        j["wall_time_seconds"] = r.seconds;
        j["outcome"] = r.status();
        j["errors"] = r.verdict.errors;
        j["warnings"] = r.verdict.warnings;
        j["notes"] = r.verdict.notes;
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        summary->stream() << j.dump(2) << '\n';
    }
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        const bool of_w = o.plot_of == "w";
        spec.title = "hbf track: " + chosen.law_name + ", " + to_string(r.feature) + (r.feature == TrackFeature::peak ? " of " + output.name() : "") +
                     " over " + o.param;
        spec.xlabel = o.param;
        spec.ylabel = of_w ? "w" : value_name + " (max over one period)";
        for (const TrackCurve& c : r.curves) {
            io::PlotCurve curve{std::to_string(c.id) + ": " + c.label + (c.status == TrackStatus::completed ? "" : " (" + to_string(c.status) + ")"),
                                {}, {}, io::PlotCurve::Style::line, 7};
            for (const TrackPoint& q : c.points) {
                curve.x.push_back(q.p);
                curve.y.push_back(of_w ? q.omega : q.value);
            }
            spec.curves.push_back(curve);
        }
        io::PlotCurve marks{"exchanges (equal peaks)", {}, {}, io::PlotCurve::Style::markers, 7};
        for (const TrackEvent& e : r.events)
            if (e.kind == "exchange") {
                marks.x.insert(marks.x.end(), {e.p, e.p});
                marks.y.insert(marks.y.end(), {of_w ? e.omega : e.value, of_w ? e.other_omega : e.value});
            }
        if (!marks.x.empty()) spec.curves.push_back(marks);
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    if (summary) summary->commit();
    if (o.output.verbose()) std::cerr << "hbf track: " << r.summary() << '\n';
    return finish("track", r.verdict);
}

void add_flags(CLI::App& command, TrackFlags& o) {
    o.absorber.add_system_flags(command);
    o.frf.add_to(command);
    command.add_option("--feature", o.feature,
                        "what is followed: peak, boundary (stick-slip) or fold\nwhat is followed: peak (every resonance peak of the first output over [wmin, wmax] at the "
                        "first value, or the one nearest --omega), boundary (the stick-slip boundaries of the contacts: "
                        "where a stick phase appears or vanishes) or fold (the folds of the harmonic-balance FRF, "
                        "through the cusps where two of them merge)")
        ->capture_default_str()->type_name("peak|boundary|fold");
    command.add_option("--param", o.param,
                        "the parameter followed: fe, mu, wa, r, wb, xi (preset) or a --config parameter\nthe parameter followed, as hbf map's --param: for the paper's absorber fe, mu, wa, r, wb, xi; "
                        "for a --config system mu, fe, structure.damping or contact.KEY of --contact")
        ->type_name("NAME");
    command.add_option("--range", o.range, "the parameter's first and last values (either order): the features are found "
                                           "on an FRF at START and followed to END")
        ->type_name("START:END");
    command.add_option("--omega", o.omega, "follow only the feature nearest to this frequency at START (within 10 %; "
                                           "otherwise an error listing the features found)")
        ->type_name("W");
    command.add_option("--at", o.at, "values of the parameter where every curve gets a point\nvalues of the parameter where every curve gets a point (kind at): V1,V2,..., "
                                     "START:STOP:N or log:START:STOP:N, inside --range")
        ->type_name("LIST|GRID");
    command.add_option("--contact", o.contact, "--config: the contact whose friction limit (--param mu) or key (--param "
                                               "contact.KEY) is the parameter (1-based)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--of-contact", o.of_contact, "--feature boundary: follow this contact's boundaries only "
                                                     "(1-based) [default: every contact's]")
        ->type_name("INT");
    command.add_option("--max-step-p", o.max_step, "largest step in the parameter, relative to the range, 1e-6..0.5")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--min-step-p", o.min_step, "smallest step in the parameter, relative to the range\nsmallest step, relative to the range: a curve that cannot go on "
                                                   "below it ends there (the peak or boundary vanished, or the solves "
                                                   "failed), 1e-12..--max-step-p")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-points", o.max_points, "accepted points over all curves, 10..1000000")
        ->capture_default_str()->type_name("INT");
    command.add_option("--time-limit", o.time_limit,
                       "stop after SECONDS and write the curves so far (exit 3, status stopped); 0: none\n"
                       "stop the run after SECONDS of wall time (0: no limit) and write what it has computed: every "
                       "curve up to the parameter it reached (status stopped, exit code 3; the check FRF at END is "
                       "not computed, a note says so; a stop in the starting FRF starts from its points so far). An "
                       "interrupt (Ctrl-C, SIGTERM, SIGHUP) does the same; a second one ends the process without output")
        ->option_text("SECONDS");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output",
                              "write a JSON summary (the curves, the events) to FILE\nwrite a JSON summary to FILE: the curves (label, status, why they ended), the events "
                              "(exchanges: equal peaks; vanished peaks; peaks born inside the range), the largest peak "
                              "at each --at value, solves and time",
                              "FILE",
                              "draw the curves in the (parameter, w) plane (.png or .svg)\ndraw the curves in the (parameter, w) plane (or (parameter, value) with --plot-of value), "
                              "the exchanges marked (.png or .svg)",
                              "no progress line or summary line on standard error"});
    command.add_option("--output", o.output_name, "the output whose peaks are followed (a name of the system's outputs)\nthe output whose peaks are followed (and whose value the CSV "
                                                  "reports): a name of the system's outputs (the preset: y1, y2; "
                                                  "--config: its [[output]] names) [default: the first]")
        ->type_name("NAME");
    command.add_option("--plot-of", o.plot_of, "what --plot draws against the parameter: w or value")
        ->capture_default_str()->type_name("w|value");
    describe_output(command, {
        R"(How: an FRF at START (hbf frf's, with the same flags) gives the features: its refined peaks of
the first output, or its located stick-slip transitions. Each is followed in the parameter with a
secant predictor; at each value the peak is re-located by Newton on dY/dw = 0 (Y = max over one
period of |o(t)|; derivatives by central differences, to about 1e-11 w with the exact solver), a
boundary by bisection on the regime (exact solver: to 1e-12 w; from full stick on the closed-form
permanent-stick load). Exact Coulomb and Jenkins contacts are solved by the event-exact solver
(--exact), the other laws by harmonic balance. Folds (harmonic balance): a pair of the FRF's folds
re-located on local branches until they merge in a cusp (located by bisection in the parameter).
An FRF at END checks that no peak was born inside the range. hbf map --overlay draws the CSV over
a heat map. Output: a CSV, one row per point of each curve:)",
        track_columns("PARAM", "OUTPUT_max"),
        R"(Exit code 3 when a curve leaves [wmin, wmax], exceeds --max-amplitude (an unbounded resonance) or
runs out of points or time (--time-limit, an interrupt), when a peak at END is on no curve, or when
the starting FRF is incomplete;
1 when a curve's solves fail; 2 for bad input (a parameter the system lacks, --omega with no feature
near it: nothing written). A peak that ends inside the range (it merged with a valley) and a cusp
are notes.)"});
}
}  // namespace

Runner add_track_command(CLI::App& app) {
    return register_command<TrackFlags>(app, "track",
                                        "Follow resonance peaks, stick-slip boundaries or folds through a parameter (fe, mu, "
                                        "wa, ...): curves in the (parameter, w) plane with their equal-peak points and "
                                        "cusps, from one FRF and a few solves per step.",
                                        add_flags, run);
}

}  // namespace hbf::cli
