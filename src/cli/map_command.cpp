// `hbf map`: FRFs over a grid of one parameter (fe, mu, wa, ...; a --config contact's friction
// limit or excitation factor), crossed with the frequency: a tidy CSV, a JSON summary and a
// picture. One FRF per task, on threads, and on MPI ranks under mpirun (rank 0 gathers and
// writes): the CSV is the same whatever the split.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "arguments.hpp"
#include "outputs.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"
#include "mpi_session.hpp"
#include "progress.hpp"
#include "stop_request.hpp"
#include "study.hpp"

namespace hbf::cli {

namespace {
struct MapOptions {
    AbsorberFlags absorber;
    FrfFlags frf;
    std::string param, values, threads = "0", contact = "1", at, style = "auto", overlay, time_limit = "0";
    OutputFlags output;
};

using nlohmann::json;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
double number_from(const json& j) { return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN(); }

/// One FRF of the map, as it travels from a rank to rank 0: the CSV rows (without the header
/// and the two leading columns), the summary, and the curve of outputs[0] for the picture.
json record(int index, double value, const FrfResult& r, const std::vector<Output>& outputs) {
    std::ostringstream csv;
    if (!r.points.empty())
        io::write_frf_csv(csv, r.points, r.metrics, outputs, r.exact, r.stability ? &*r.stability : nullptr);
    std::string rows = csv.str();
    rows = rows.substr(std::min(rows.size(), rows.find('\n') == std::string::npos ? rows.size() : rows.find('\n') + 1));
    json w = json::array(), y = json::array();
    int branch = 0;
    for (std::size_t k = 0; k < r.points.size(); ++k) {
        const SolutionPoint& p = r.points[k];
        if (p.kind == PointKind::sample) continue;
        if (branch != 0 && p.branch != branch) {  // a gap between branches
            w.push_back(nullptr);
            y.push_back(nullptr);
        }
        branch = p.branch;
        w.push_back(number_or_null(p.omega));
        y.push_back(number_or_null(r.metrics[k].output_max.empty() ? NAN : r.metrics[k].output_max.front()));
    }
    return {{"index", index},
            {"value", value},
            {"status", to_string(r.branch.status)},
            {"message", r.branch.message},
            {"coverage", r.branch.coverage},
            {"points", r.points.size()},
            {"peak", number_or_null(r.peak.value)},
            {"peak_w", number_or_null(r.peak.omega)},
            {"peak_state", to_string(r.peak.state)},
            {"polish_failed", r.polish ? r.polish->failed : 0},
            {"missed_at", r.missed},
            {"library_warnings", r.messages.count},
            {"library_first_warning", r.messages.first},
            {"hb_error", number_or_null(r.hb_error)},
            {"seconds", r.seconds},
            {"rows", rows},
            {"w", w},
            {"y", y}};
}

/// The curves of an hbf track CSV (columns curve, PARAM, w) as overlays of the heat map (x = w,
/// y = the parameter), one per curve. UsageError naming --overlay for a file that cannot be read
/// or lacks a column.
std::vector<io::PlotCurve> read_overlay(const std::string& path, const std::string& param) {
    io::check_input_file("--overlay", path, std::uintmax_t{256} << 20);  // 256 MB: a CSV of hbf track
    std::ifstream in(path);
    if (!in) throw UsageError("--overlay = '" + path + "' cannot be read");
    std::string line;
    if (!std::getline(in, line)) throw UsageError("--overlay = '" + path + "' is empty: allowed a CSV of hbf track");
    std::vector<std::string> header;
    {
        std::istringstream cells(line);
        for (std::string c; std::getline(cells, c, ',');) header.push_back(c);
    }
    const auto column = [&](const std::string& name) {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end())
            throw UsageError("--overlay = '" + path + "' has no column '" + name + "': allowed a CSV of hbf track --param " +
                             param + " (columns curve, " + param + ", w)");
        return static_cast<std::size_t>(it - header.begin());
    };
    const std::size_t c_curve = column("curve"), c_p = column(param), c_w = column("w");
    std::vector<io::PlotCurve> curves;
    std::string current;
    int row = 1;
    while (std::getline(in, line)) {
        ++row;
        std::vector<std::string> f;
        std::istringstream cells(line);
        for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
        if (f.size() <= std::max({c_curve, c_p, c_w}))
            throw UsageError("--overlay = '" + path + "', line " + std::to_string(row) + ": too few fields");
        if (curves.empty() || f[c_curve] != current) {
            current = f[c_curve];
            curves.push_back({"tracked curve " + current, {}, {}, io::PlotCurve::Style::line, 7});
        }
        curves.back().x.push_back(parse_double("--overlay (line " + std::to_string(row) + ", w)", f[c_w]));
        curves.back().y.push_back(parse_double("--overlay (line " + std::to_string(row) + ", " + param + ")", f[c_p]));
    }
    return curves;
}

int run(const CLI::App& command, const MapOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    MpiSession mpi;
    const bool root = mpi.rank() == 0;
    o.output.check_plot();
    if (o.style != "auto" && o.style != "curves" && o.style != "heatmap")
        throw UsageError("--plot-style = '" + o.style + "' is not known: allowed auto, curves, heatmap");
    if (!given(command, "--param")) throw UsageError("--param is required: the parameter of the map (e.g. --param fe)");
    if (!given(command, "--values")) throw UsageError("--values is required: V1,V2,..., START:STOP:N or log:START:STOP:N");
    ChosenSystem chosen = choose_system(command, o.absorber, o.frf.config);
    if (given(command, "--overlay") && o.overlay.empty()) throw UsageError("--overlay is empty: allowed a CSV of hbf track");
    std::vector<io::InputFile> inputs = chosen.inputs();
    if (!o.overlay.empty()) inputs.push_back({"--overlay", o.overlay});
    if (root)
        o.output.check(command, inputs);
    if (!o.overlay.empty() && o.output.plot.empty())
        throw UsageError("--overlay = '" + o.overlay + "' draws the tracked curves on the --plot, which is not given: add --plot FILE");
    const StudyParameter parameter("--param", o.param, chosen, "--contact", o.contact);
    parameter.check_flags(command, "the map's values");
    FrfSettings settings = o.frf.settings(command, chosen);
    settings.peaks = true;  // the largest peak per FRF (JSON)
    if (given(command, "--at") && o.at.empty()) throw UsageError("--at is empty: allowed a comma-separated list of frequencies > 0");
    if (!o.at.empty()) settings.at = parse_frequencies("--at", o.at);
    const std::vector<double> values = parse_values("--values", o.values);
    const std::vector<io::PlotCurve> overlays = o.overlay.empty() ? std::vector<io::PlotCurve>{} : read_overlay(o.overlay, o.param);
    for (double v : values) {  // every value checked before the work
        try {
            (void)parameter.system(v);
        } catch (const InvalidInput& e) {
            throw UsageError("--values: " + o.param + " = " + format_number(v) + ": " + e.what());
        }
    }
    const int threads = parse_count("--threads", o.threads, 0, 4096);
    const double time_limit = parse_time_limit(o.time_limit);
    HarmonicBalance::validate(parameter.system(values.front()), settings.harmonic_balance);
    if (o.output.dry_run) return root ? o.output.dry_run_done("map") : exit_success;

    // This rank's share: FRFs k with k mod ranks = rank.
    std::vector<int> mine;
    for (int k = mpi.rank(); k < static_cast<int>(values.size()); k += mpi.size()) mine.push_back(k);
    ProgressLine progress(root ? o.output.progress() : ProgressLine::Mode::off, "map");
    const auto draw = [&](int finished, int total) {
        const int width = 30, filled = total > 0 ? width * finished / total : width;
        progress.update("[" + std::string(static_cast<std::size_t>(filled), '#') +
                            std::string(static_cast<std::size_t>(width - filled), '.') + "] " + std::to_string(finished) +
                            "/" + std::to_string(total) + " FRFs" + (mpi.size() > 1 ? " on rank 0" : ""),
                        finished == total);
    };
    // An interrupt or the time limit stops the FRFs running (their points so far are kept) and
    // leaves the others uncomputed; everything is written (exit 3). Asked from every thread: the
    // request's state alone (no crawl watch).
    StopRequest stop("map", time_limit);
    settings.continuation.stop = [&stop] { return stop.why(); };
    // Under MPI one thread per rank unless --threads says otherwise (the ranks fill the cores).
    const int workers = mpi.size() > 1 && !given(command, "--threads") ? 1 : threads;
    const std::vector<FrfResult> results = compute_frfs(
        static_cast<int>(mine.size()),
        [&](int k) { return parameter.system(values[static_cast<std::size_t>(mine[static_cast<std::size_t>(k)])]); },
        settings, workers, draw);
    progress.clear();
    json part = json::array();
    for (std::size_t k = 0; k < mine.size(); ++k)
        part.push_back(record(mine[k], values[static_cast<std::size_t>(mine[k])], results[k], chosen.outputs));
    const std::vector<std::string> parts = mpi.gather(part.dump());
    if (!root) return mpi.broadcast(0);

    std::vector<json> frfs(values.size());
    for (const std::string& text : parts)
        for (json& r : json::parse(text)) {
            const auto index = r.at("index").get<std::size_t>();  // before r is moved from
            frfs.at(index) = std::move(r);
        }

    // The tidy CSV: the parameter and the FRF's status, then hbf frf's columns, one row per
    // point; an FRF without points is one row of empty fields.
    const std::vector<io::Column> columns =
        io::frf_columns(chosen.outputs, static_cast<int>(parameter.system(values.front()).contacts.size()),
                        io::normal_contacts(parameter.system(values.front())));
    io::OutputFile out(o.output.out);
    out.stream() << o.param << ",frf_status";
    for (const io::Column& c : columns) out.stream() << ',' << c.name;
    out.stream() << '\n';
    const std::string empty_row(columns.size(), ',');
    for (std::size_t k = 0; k < values.size(); ++k) {
        const std::string prefix = io::csv_field(values[k]) + "," + frfs[k].at("status").get<std::string>() + ",";
        const std::string rows = frfs[k].at("rows").get<std::string>();
        if (rows.empty()) {
            out.stream() << prefix << empty_row.substr(1) << '\n';
            continue;
        }
        std::istringstream lines(rows);
        for (std::string line; std::getline(lines, line);) out.stream() << prefix << line << '\n';
    }

    MapTally tally;  // each FRF's record, from every rank (frf.hpp)
    for (const json& r : frfs) {
        tally.add(r.at("peak_state").get<std::string>(), static_cast<int>(r.at("missed_at").size()),
                  {r.at("library_warnings").get<long long>(), r.at("library_first_warning").get<std::string>()});
        tally.add_error(r.at("hb_error").is_number() ? r.at("hb_error").get<double>() : NAN, settings.error_limit);
    }
    const Verdict verdict = tally.verdict();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

    std::unique_ptr<io::OutputFile> summary;
    if (!o.output.summary.empty()) {
        json j;
        j["command"] = "map";
        j["law"] = chosen.law_name;
        if (chosen.force_scale) j["force_scale"] = *chosen.force_scale;
        j["parameter"] = {{"name", o.param}, {"meaning", parameter.meaning()}, {"values", values}};
        j["output"] = columns.size() > 1 ? columns[1].name : "";
        j["ranks"] = mpi.size();
        j["threads"] = workers == 0 ? static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) : workers;
        j["wall_time_seconds"] = seconds;
        json list = json::array();
        for (json r : frfs) {
            r.erase("rows");
            r.erase("w");
            r.erase("y");
            r.erase("index");
            list.push_back(r);
        }
        j["frfs"] = list;
        j["outcome"] = !verdict.errors.empty() ? "failed" : verdict.warnings.empty() ? "completed" : "incomplete";
        j["errors"] = verdict.errors;
        j["warnings"] = verdict.warnings;
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        summary->stream() << j.dump(2) << '\n';
    }
    if (!o.output.plot.empty()) {
        const std::string y_name = columns.size() > 1 ? columns[1].name : "y1_max";
        io::PlotSpec spec;
        spec.title = "hbf map: " + chosen.law_name + ", " + y_name + " over (w, " + o.param + ")";
        spec.xlabel = "w";
        const bool heatmap = o.style == "heatmap" || (o.style == "auto" && values.size() > 8);
        if (heatmap) {
            spec.ylabel = o.param;
            spec.colorbar = y_name + " (max over one period)";
            spec.log_colorbar = true;
            io::PlotCurve capped{"unbounded resonance (capped)", {}, {}, io::PlotCurve::Style::markers, 2};
            for (std::size_t k = 0; k < values.size(); ++k) {
                const json& r = frfs[k];
                for (std::size_t i = 0; i < r.at("w").size(); ++i) {
                    const double w = number_from(r.at("w")[i]), y = number_from(r.at("y")[i]);
                    if (!std::isfinite(w) || !(y > 0.0)) continue;
                    spec.heat_x.push_back(w);
                    spec.heat_y.push_back(values[k]);
                    spec.heat_z.push_back(y);
                }
                if (r.at("peak_state") == "unbounded") {
                    capped.x.push_back(number_from(r.at("peak_w")));  // the largest point before the cap
                    capped.y.push_back(values[k]);
                }
            }
            spec.curves = {capped};
            spec.curves.insert(spec.curves.end(), overlays.begin(), overlays.end());
        } else {
            spec.ylabel = y_name + " (max over one period)";
            for (std::size_t k = 0; k < values.size(); ++k) {
                const json& r = frfs[k];
                const std::string diameter =
                    parameter.integer() ? " (nodal diameter " +
                                              std::to_string(nodal_diameter(parameter.system(values[k]).cyclic, 1)) + ")"
                                        : std::string();
                io::PlotCurve c{o.param + " = " + format_number(values[k]) + diameter +
                                    (r.at("peak_state") == "unbounded" ? " (unbounded: capped)"
                                     : r.at("peak_state") == "bounded" ? ""
                                                                       : " (" + r.at("status").get<std::string>() + ")"),
                                {}, {}, io::PlotCurve::Style::line, 7};
                for (std::size_t i = 0; i < r.at("w").size(); ++i) {
                    c.x.push_back(number_from(r.at("w")[i]));
                    c.y.push_back(number_from(r.at("y")[i]));
                }
                spec.curves.push_back(c);
            }
        }
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    if (summary) summary->commit();
    if (o.output.verbose())
        std::cerr << "hbf map: " << values.size() << " FRFs in " << format_number(seconds) << " s\n";
    return mpi.broadcast(finish("map", verdict));
}
/// The flags of hbf map.
void add_flags(CLI::App& command, MapOptions& o) {
    o.absorber.add_system_flags(command);
    o.frf.add_to(command);
    command.add_option("--param", o.param,
                        "the parameter varied: fe, mu, wa, r, wb, xi (preset) or a --config parameter\nthe parameter of the map: for the paper's absorber fe, mu, wa, r, wb (dahl, lugre, jenkins) "
                        "or xi (lugre); for a --config system mu (the friction limit F_c of the contact --contact, "
                        "in the file's force units), fe (a factor on the file's excitation vector), structure.damping "
                        "(a factor on its damping matrix), cyclic.engine_order (a sector's engine order: integer values, "
                        "one FRF per engine order) or a scalar key of the contact --contact as in the file "
                        "(contact.friction_limit, contact.stiffness, contact.damping, contact.viscous, "
                        "contact.static_limit, contact.stribeck_velocity, contact.regularization, "
                        "contact.lagrangian_penalty; the keys of its law only)")
        ->type_name("NAME");
    command.add_option("--values", o.values,
                        "the parameter's values: V1,V2,..., START:STOP:N or log:START:STOP:N\nthe parameter's values: V1,V2,..., START:STOP:N (N evenly spaced) or log:START:STOP:N "
                        "(evenly spaced in log); 1..100000 values")
        ->type_name("LIST|GRID");
    command.add_option("--at", o.at,
                        "comma-separated frequencies at which every FRF's solutions are written as extra rows\ncomma-separated frequencies W1,W2,...: on every FRF, every solution there is solved exactly "
                        "and written as extra rows with point = sample (as hbf frf --at)")
        ->type_name("LIST");
    command.add_option("--contact", o.contact, "--config: the contact whose friction limit (--param mu) or key (--param contact.KEY) the map sets (1-based)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--threads", o.threads,
                        "FRFs computed at once, 0..4096; 0 = every core\nFRFs computed at once, 0..4096; 0 = every core. Under mpirun: per rank [default 1]. The CSV "
                        "is the same for any number of threads and ranks")
        ->capture_default_str()->type_name("INT");
    command.add_option("--time-limit", o.time_limit,
                       "stop after SECONDS and write the FRFs computed so far (exit 3, status stopped); 0: none\n"
                       "stop the run after SECONDS of wall time (0: no limit; under mpirun: on every rank) and write what "
                       "it has computed: the FRFs done, those running up to where they stopped (frf_status stopped), "
                       "those not started without points (stopped, \"not computed\" in the JSON); exit code 3. An "
                       "interrupt (Ctrl-C, SIGTERM, SIGHUP) does the same; a second one ends the process without output")
        ->option_text("SECONDS");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output",
                                      "write a JSON summary to FILE: per value the FRF's status, coverage, largest "
                                      "peak (peak, peak_w, peak_state) and time",
                                      "FILE",
                                      "draw the map: curves, or a heat map over (w, parameter)\ndraw the first output's max over one period against w: one curve per value, or "
                                      "a heat map over (w, parameter) with the colour on a log scale (.png or .svg)",
                                      "no progress bar (on a terminal; otherwise one line a minute) or summary line on standard error"});
    command.add_option("--overlay", o.overlay,
                        "draw the curves of an hbf track CSV over the heat map\ndraw the curves of an hbf track CSV of the same --param (its columns curve, PARAM, w) over the "
                        "heat map: the tracked peaks, boundaries or folds in the (w, parameter) plane")
        ->type_name("FILE.csv");
    command.add_option("--plot-style", o.style,
                        "curves, heatmap, or auto (curves for up to 8 values, else a heat map)")
        ->capture_default_str()->type_name("auto|curves|heatmap");
    describe_output(command, {
        R"(Output: a tidy CSV, one row per FRF point: the parameter's value (column named after it), frf_status
(the FRF's continuation status: completed, amplitude_cap, left_range, point_budget, stopped, min_step,
solver_error, start_failed), then the columns of hbf frf:)",
        io::frf_columns(2),
        R"(An FRF that fails is one row with its status and empty fields, and the map goes on. Exit code 3 when
any FRF failed, is incomplete (also stopped by --time-limit or an interrupt) or has an unbounded
resonance (counted on standard error).
MPI: mpirun -n K hbf map ... splits the values over K ranks (value k on rank k mod K); rank 0
gathers and writes.)"});
}
}  // namespace

Runner add_map_command(CLI::App& app) {
    return register_command<MapOptions>(app, "map", "FRFs over a grid of one parameter, crossed with the frequency: one FRF (hbf frf) per value, on "
               "threads and, under mpirun, on MPI ranks; a tidy CSV, a JSON summary and a picture.", add_flags, run);
}

}  // namespace hbf::cli
