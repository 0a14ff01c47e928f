// `hbf modes`: a nonlinear mode of the structure (EPMC, modes.hpp): backbone and modal damping
// against the modal amplitude, as CSV, JSON summary and plots.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "arguments.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "outputs.hpp"
#include "stop_request.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/modes.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"

namespace hbf::cli {

namespace {

struct ModesOptions {
    AbsorberFlags absorber;
    std::string mode = "1", near, start_frequency, amin, amax, harmonics = "0", time_samples = "0",
                tolerance = default_text(ModeOptions{}.tolerance), max_step = default_text(ModeOptions{}.max_step),
                max_points = std::to_string(ModeOptions{}.max_points), formulation = "automatic", modes;
    std::string plot_damping, synthesis_out, plot_synthesis, time_limit = "0";
    bool exact_check = false;
    OutputFlags output;
    std::string config;
};

double number_in(const std::string& flag, const std::string& text, double low, double high, bool open_low) {
    const double v = parse_double(flag, text);
    if (!(open_low ? v > low : v >= low) || !(v <= high))
        throw UsageError(flag + " = " + text + " is out of range: allowed " + (open_low ? "(" : "[") + default_text(low) +
                         ", " + default_text(high) + "]");
    return v;
}

int run(const CLI::App& command, const ModesOptions& o) {
    o.output.check_plot();  // before any work
    if (given(command, "--plot-damping") && o.plot_damping.empty())
        throw UsageError("--plot-damping is empty: allowed FILE.png|FILE.svg");
    io::check_plot("--plot-damping", o.plot_damping);
    const ChosenSystem chosen = choose_system(command, o.absorber, o.config);
    if (given(command, "--synthesis-out") && o.synthesis_out.empty())
        throw UsageError("--synthesis-out is empty: allowed FILE.csv");
    if (given(command, "--plot-synthesis") && o.plot_synthesis.empty())
        throw UsageError("--plot-synthesis is empty: allowed FILE.png|FILE.svg");
    io::check_plot("--plot-synthesis", o.plot_synthesis);
    o.output.check(command, chosen.inputs(),
                   {{"--plot-damping", o.plot_damping, !o.plot_damping.empty(), false, true},
                    {"--synthesis-out", o.synthesis_out, given(command, "--synthesis-out")},
                    {"--plot-synthesis", o.plot_synthesis, !o.plot_synthesis.empty(), false, true}});
    const bool synthesise = !o.synthesis_out.empty() || !o.plot_synthesis.empty();
    if (synthesise && chosen.system.excitation_harmonic != 1)
        throw UsageError("--synthesis-out and --plot-synthesis synthesise the response to F cos(w t): the system's "
                         "excitation harmonic is " + std::to_string(chosen.system.excitation_harmonic) + " (allowed 1)");
    ModeOptions mo;
    if (given(command, "--near") && given(command, "--mode"))
        throw UsageError("--near cannot be combined with --mode: give the mode by its index or by a frequency");
    if (given(command, "--near")) {
        mo.near_frequency = parse_double("--near", o.near);
        if (!(mo.near_frequency > 0.0)) throw UsageError("--near = " + o.near + " is out of range: allowed > 0");
    } else {
        const long long mode = parse_integer("--mode", o.mode);
        if (mode < 1 || mode > 1000000) throw UsageError("--mode = " + o.mode + " is out of range: allowed >= 1");
        mo.mode = static_cast<int>(mode);
    }
    if (given(command, "--start-frequency")) {
        mo.start_frequency = parse_double("--start-frequency", o.start_frequency);
        if (!(mo.start_frequency > 0.0 && std::isfinite(mo.start_frequency)))
            throw UsageError("--start-frequency = " + o.start_frequency + " is out of range: allowed > 0");
    }
    const bool range_given = !o.amin.empty() || !o.amax.empty();
    if (range_given && (o.amin.empty() || o.amax.empty()))
        throw UsageError(std::string(o.amin.empty() ? "--amin" : "--amax") + " is missing: give --amin and --amax "
                         "together, or neither (the range is then chosen from the contacts' slip onset)");
    if (range_given) {
        mo.amplitude_min = parse_double("--amin", o.amin);
        if (!(mo.amplitude_min > 0.0)) throw UsageError("--amin = " + o.amin + " is out of range: allowed > 0");
        mo.amplitude_max = parse_double("--amax", o.amax);
        if (!(mo.amplitude_max > mo.amplitude_min))
            throw UsageError("--amax = " + o.amax + " is out of range: allowed > --amin = " + format_number(mo.amplitude_min));
        const double decades = std::log10(mo.amplitude_max) - std::log10(mo.amplitude_min);  // no overflow
        if (decades > 12.0)
            throw UsageError("--amax / --amin spans " + format_number(std::round(decades * 100.0) / 100.0) +
                             " decades: allowed up to 12 (--amax <= 1e12 --amin)");
    }
    mo.tolerance = number_in("--tolerance", o.tolerance, CorrectorOptions::smallest_tolerance,
                             CorrectorOptions::largest_tolerance, false);
    mo.max_step = number_in("--max-step", o.max_step, 0.0, 1.0, true);
    mo.initial_step = std::min(mo.initial_step, mo.max_step);
    mo.min_step = std::min(mo.min_step, mo.initial_step);
    const long long max_points = parse_integer("--max-points", o.max_points);
    if (max_points < 2 || max_points > 100000)
        throw UsageError("--max-points = " + o.max_points + " is out of range: allowed 2..100000");
    mo.max_points = static_cast<int>(max_points);
    HarmonicBalanceOptions hbo = harmonic_balance_options(command, o.harmonics, o.time_samples, chosen, o.config, false);
    const HarmonicBalanceOptions forced = hbo;  // the full FRF of --plot-synthesis: as hbf frf would solve it
    hbo.formulation = parse_formulation(o.formulation);  // hbf names the flag
    if (given(command, "--modes")) {
        hbo.modes = parse_int("--modes", o.modes);
        hbo.validate();  // its range; hbf names the flag
    }
    if (hbo.modes > 0 && hbo.formulation == Formulation::full)
        throw UsageError("--modes " + std::to_string(hbo.modes) +
                         " (the modal receptance) needs the condensed formulation: allowed --formulation condensed or "
                         "automatic, or --modes 0");
    if (hbo.odd_harmonics) throw UsageError("--harmonics odd: hbf modes balances every harmonic (a mode may have a mean)");

    const double time_limit = parse_time_limit(o.time_limit);
    ProgressLine progress(o.output.progress(), "modes");
    mo.progress = [&progress](double a, int points) {
        progress.update("a = " + format_number(a) + ", " + std::to_string(points) + " points");
    };
    if (!range_given) {  // from the slip onset of the stuck mode followed
        const SlipOnset onset = slip_onset(chosen.system, hbo, mo);
        if (!onset.found)
            throw UsageError("--amin and --amax are required here: no default range of the modal amplitude (" + onset.why +
                             ")");
        mo.amplitude_min = onset.amplitude_min;
        mo.amplitude_max = onset.amplitude_max;
        std::cerr << "hbf modes: note: the range a = " << format_number(mo.amplitude_min) << " .. "
                  << format_number(mo.amplitude_max) << " (a tenth to a hundred times the slip onset of stuck mode "
                  << onset.mode << ", a* = " << format_number(onset.amplitude)
                  << ": no stuck motion above it, contact " << onset.contact + 1
                  << (onset.opens ? " opens there" : " slips there");
        if (onset.static_amplitude < onset.amplitude * (1.0 - 1e-9))
            std::cerr << "; with the sliders where the static load leaves them contact " << onset.static_contact + 1
                      << " reaches its limit at a = " << format_number(onset.static_amplitude);
        std::cerr << "); --amin and --amax choose another\n";
    }
    // Every check of the run (a mode out of range, a rigid-body mode: InvalidInput) before any output.
    const NonlinearModes checked(chosen.system, hbo, mo);
    if (o.output.dry_run) return o.output.dry_run_done("modes");
    io::OutputFile out(o.output.out);
    std::unique_ptr<io::OutputFile> synthesis;
    if (!o.synthesis_out.empty()) synthesis = std::make_unique<io::OutputFile>(o.synthesis_out);
    // An interrupt or the time limit stops the run; the points computed are written (exit 3).
    StopRequest stop("modes", time_limit);
    mo.stop = stop.function();
    const ModeRun run = compute_mode(chosen.system, hbo, mo, chosen.outputs, synthesise, o.exact_check);
    progress.clear();
    const Backbone& b = run.backbone;
    const std::vector<ModeMetrics>& metrics = run.metrics;
    const std::vector<SynthesisPoint>& curve = run.synthesis;
    const int harmonics = run.harmonics;
    io::write_csv(out.stream(), run.table);
    const std::string title = "hbf modes: " + (o.config.empty() ? chosen.law_name : o.config) + ", mode " +
                              std::to_string(b.linear.index) + cyclic_label(chosen.system.cyclic) + ", H = " +
                              std::to_string(harmonics);
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = title + " (backbone)";
        spec.xlabel = "w = frequency of the nonlinear mode";
        spec.ylabel = "a = modal amplitude";
        spec.log_y = true;
        io::PlotCurve line{"backbone", {}, {}, io::PlotCurve::Style::line, 7};
        for (const ModePoint& p : b.points) {
            line.x.push_back(p.omega);
            line.y.push_back(p.amplitude);
        }
        spec.curves = {line};
        io::write_plot(o.output.plot, spec);
    }
    if (!o.plot_damping.empty()) {
        io::PlotSpec spec;
        spec.title = title + " (modal damping)";
        spec.xlabel = "a = modal amplitude";
        spec.ylabel = "damping ratio";
        spec.log_x = true;
        spec.log_y = true;
        io::PlotCurve zeta{"zeta = xi / (2 w)", {}, {}, io::PlotCurve::Style::line, 7};
        io::PlotCurve energy{"zeta_energy = E / (2 pi w^2 a^2)", {}, {}, io::PlotCurve::Style::dashed, 7};
        // A log axis: damping ratios at the solver's resolution (100 x the tolerance: the
        // rounding of an undamped stuck mode, of either sign) are left out.
        const double resolution = 100.0 * mo.tolerance;
        for (std::size_t k = 0; k < b.points.size(); ++k) {
            if (!(b.points[k].zeta() > resolution)) continue;
            zeta.x.push_back(b.points[k].amplitude);
            zeta.y.push_back(b.points[k].zeta());
            if (metrics[k].zeta_energy > resolution) {
                energy.x.push_back(b.points[k].amplitude);
                energy.y.push_back(metrics[k].zeta_energy);
            }
        }
        spec.curves = {zeta, energy};
        io::write_plot(o.plot_damping, spec);
    }
    std::unique_ptr<io::OutputFile> summary;
    double worst_energy = 0.0;
    for (const ModeMetrics& m : metrics) worst_energy = std::max(worst_energy, m.energy_error);
    if (!o.output.summary.empty()) {
        using nlohmann::json;
        json j;
        j["command"] = "modes";
        j["system"] = o.config.empty() ? chosen.law_name : o.config;
        if (chosen.force_scale) j["force_scale"] = *chosen.force_scale;
        j["mode"] = b.linear.index;
        if (chosen.system.cyclic.active()) {
            j["sectors"] = chosen.system.cyclic.sectors;
            j["engine_order"] = chosen.system.cyclic.engine_order;
            j["nodal_diameter"] = nodal_diameter(chosen.system.cyclic, 1);
        }
        j["linear"] = {{"omega", b.linear.omega}, {"zeta", b.linear.zeta}};
        j["harmonics"] = harmonics;
        j["time_samples"] = run.time_samples;
        j["formulation"] = to_string(run.formulation);
        j["modes"] = run.modes;
        j["amplitude_range"] = {mo.amplitude_min, mo.amplitude_max};
        j["status"] = to_string(b.status);
        j["message"] = b.message;
        j["points"] = b.points.size();
        j["failed_steps"] = b.failed_steps;
        j["evaluations"] = b.evaluations;
        j["seconds"] = b.seconds;
        j["largest_energy_error"] = worst_energy;
        if (o.exact_check) {
            double largest = 0.0;
            std::size_t checked = 0;
            for (const ExactModeCheck& c : run.exact)
                if (c.checked) {
                    ++checked;
                    largest = std::max(largest, c.gap);
                }
            j["exact_check"] = {{"checked", checked}, {"points", run.exact.size()},
                                {"largest_exact_gap", checked ? nlohmann::json(largest) : nlohmann::json()}};
        }
        if (!b.points.empty()) {
            j["first"] = {{"a", b.points.front().amplitude}, {"w", b.points.front().omega}, {"zeta", b.points.front().zeta()}};
            j["last"] = {{"a", b.points.back().amplitude}, {"w", b.points.back().omega}, {"zeta", b.points.back().zeta()}};
        }
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        summary->stream() << j.dump(2) << '\n';
    }
    Verdict frf_verdict;
    if (!o.plot_synthesis.empty()) {
        // The synthesis over the full harmonic-balance FRF of the same system and force (hbf frf
        // over the synthesised band), the first output's first harmonic, and the two peaks.
        const std::string& name = chosen.outputs.front().name();
        io::PlotSpec spec;
        spec.xlabel = "w = excitation frequency";
        spec.ylabel = name + "_amp1 = first-harmonic amplitude of " + name + "(t)";
        io::PlotCurve full{"harmonic balance (hbf frf)", {}, {}, io::PlotCurve::Style::line, 7};
        io::PlotCurve synthesised{"synthesised from the mode", {}, {}, io::PlotCurve::Style::dashed, 7};
        double w_low = std::numeric_limits<double>::infinity(), w_high = 0.0, s_peak = 0.0, s_w = 0.0;
        for (const SynthesisPoint& q : curve)
            if (q.output_amp1.front() > s_peak) {
                s_peak = q.output_amp1.front();
                s_w = q.omega;
            }
        // The resonance's band, where the synthesis means something: down to 10 % of its peak.
        for (const SynthesisPoint& q : curve) {
            if (!(q.output_amp1.front() >= 0.1 * s_peak)) continue;
            synthesised.x.push_back(q.omega);
            synthesised.y.push_back(q.output_amp1.front());
            w_low = std::min(w_low, q.omega);
            w_high = std::max(w_high, q.omega);
        }
        std::string difference = "no synthesised response (the force sustains no backbone point)";
        if (w_high > w_low) {
            FrfSettings fs;
            fs.harmonic_balance = forced;
            fs.continuation.omega_start = w_low;
            fs.continuation.omega_end = w_high;
            fs.outputs = {chosen.outputs.front()};
            fs.peaks = false;
            fs.continuation.stop = stop.function();
            const FrfResult frf = compute_frf(chosen.system, fs);
            double f_peak = 0.0, f_w = 0.0;
            for (std::size_t k = 0; k < frf.points.size(); ++k) {
                const double y = frf.metrics[k].output_amp1.front();
                full.x.push_back(frf.points[k].omega);
                full.y.push_back(y);
                if (y > f_peak) {
                    f_peak = y;
                    f_w = frf.points[k].omega;
                }
            }
            for (const std::string& w : frf.verdict.warnings) frf_verdict.note("--plot-synthesis: the full FRF: " + w);
            for (const std::string& e : frf.verdict.errors) frf_verdict.note("--plot-synthesis: the full FRF: " + e);
            difference = "peak: synthesis w = " + format_number(s_w) + ", " + format_number(s_peak) + "; harmonic balance w = " +
                         format_number(f_w) + ", " + format_number(f_peak) + " (" +
                         format_number(std::abs(s_w - f_w) / f_w) + " and " +
                         format_number(std::abs(s_peak - f_peak) / f_peak) + " relative)";
            char title[200];
            std::snprintf(title, sizeof title, "mode %d synthesised: peak w %.4g vs %.4g, %s %.4g vs %.4g (HB)",
                          b.linear.index, s_w, f_w, (name + "_amp1").c_str(), s_peak, f_peak);
            spec.title = title;
        } else {
            spec.title = "mode " + std::to_string(b.linear.index) + ": " + difference;
        }
        spec.curves = {full, synthesised};
        io::write_plot(o.plot_synthesis, spec);
        frf_verdict.note("--plot-synthesis: " + difference);
    }
    if (synthesis) io::write_csv(synthesis->stream(), io::synthesis_table(curve, chosen.outputs));
    out.commit();
    if (summary) summary->commit();
    if (synthesis) synthesis->commit();
    if (o.output.verbose())
        std::cerr << "hbf modes: mode " << b.linear.index << " (stuck: w = " << format_number(b.linear.omega)
                  << ", zeta = " << format_number(b.linear.zeta) << "): " << to_string(b.status) << ", "
                  << b.points.size() << " points in " << format_number(b.seconds) << " s\n";
    Verdict verdict = run.verdict;
    verdict.add(frf_verdict);
    return finish("modes", verdict);
}

void add_flags(CLI::App& command, ModesOptions& o) {
    o.absorber.add_system_flags(command);
    // A nonlinear mode is a free motion: the excitation enters only --synthesis-out (harmonic 1).
    command.remove_option(command.get_option("--excitation-harmonic"));
    command.add_option("--mode", o.mode,
                       "the stuck structure's mode followed, 1-based by ascending frequency\nthe linear mode of the stuck structure followed, 1-based by ascending frequency (stuck: every "
                       "contact's stuck spring, exact Coulomb contacts held rigid; a sector model: the modes of the nodal "
                       "diameter its engine order excites)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--near", o.near, "instead of --mode: the stuck mode nearest this frequency, > 0")
        ->type_name("NUMBER");
    command.add_option("--start-frequency", o.start_frequency,
                       "the first point's frequency guess, > 0, instead of the automatic start\nthe first point's frequency guess at --amin, > 0, instead of the automatic start (the linear "
                       "limit: the stuck mode, or where the stuck structure is damped its damped mode; where --amin is "
                       "beyond the linear regime, the backbone followed up to --amin from it); a given start is not "
                       "checked against the linear limit (a note)")
        ->type_name("NUMBER");
    command.add_option("--amin", o.amin,
                       "smallest modal amplitude a, > 0 (default: a tenth of the slip onset)\nsmallest modal amplitude a (first point), > 0: a = the M-norm of y's first harmonic "
                       "(c1 cos + s1 sin), sqrt(c1^T M c1 + s1^T M s1); the modal coordinate's amplitude in the linear "
                       "limit. Without --amin and --amax the range is a tenth to a hundred times the slip onset (the "
                       "amplitude where the stuck mode's first contact reaches its friction limit or opens), said on standard "
                       "error")
        ->type_name("NUMBER");
    command.add_option("--amax", o.amax, "largest modal amplitude a, > amin, at most 1e12 amin (given with --amin)")
        ->type_name("NUMBER");
    add_discretisation_flags(command, o.harmonics, o.time_samples, "the largest of the contacts' laws' own");
    command.add_option("--formulation", o.formulation,
                       "how the structure enters: full, condensed or automatic\nhow the structure enters: full (every DOF's harmonics are unknowns: a dense Jacobian of N (2H + 1) "
                       "rows), condensed (the contacts' relative displacements only, the structure with C - xi M "
                       "solved per harmonic: the direct sparse LU, or --modes), automatic (full up to " +
                           std::to_string(mode_full_limit) +
                           " unknowns N (2H + 1), and with --modes 0, else condensed where K is invertible)")
        ->capture_default_str()->type_name("automatic|condensed|full");
    command.add_option("--modes", o.modes,
                       "condensed formulation: 0 solves the structure directly, m > 0 by its m lowest modes\ncondensed formulation: 0 (default, or a --config file's [solver] modes) solves the structure "
                       "directly; m > 0 by its m lowest modes plus the static residual flexibility (as hbf frf "
                       "--modes: cost independent of N; needs M > 0, K > 0 and C diagonal in the modes)")
        ->type_name("INT");
    command.add_option("--tolerance", o.tolerance,
                       "Newton's acceptance on the scaled residual\nNewton's acceptance: max |residual|, the structure's rows relative to the mode's inertial force "
                       "a w0^2 |M phi|_inf, the amplitude and phase rows relative to a; " +
                           default_text(CorrectorOptions::smallest_tolerance) + ".." +
                           default_text(CorrectorOptions::largest_tolerance))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-step", o.max_step, "largest pseudo-arclength step in the scaled coordinates (x / (a |phi|), w / w0, xi / w0, log10 a: decades), (0, 1]")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-points", o.max_points, "point budget, 2..100000 (exit 3 when reached)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--time-limit", o.time_limit,
                       "stop after SECONDS and write the points computed so far (exit 3, status stopped); 0: none\n"
                       "stop the run after SECONDS of wall time (0: no limit) and write what it has computed: the "
                       "backbone's points so far (status stopped, exit code 3; --exact-check leaves the points after "
                       "the stop unchecked, and --plot-synthesis's FRF stops too). An interrupt (Ctrl-C, SIGTERM, "
                       "SIGHUP) does the same; a second one ends the process without output")
        ->option_text("SECONDS");
    command.add_option("--config", o.config, "the structure from a TOML system file (as hbf frf --config; its "
                                             "excitation and frequency range are not used)")
        ->option_text("FILE.toml");
    command.add_option("--synthesis-out", o.synthesis_out,
                       "write the forced response synthesised from the mode to FILE (CSV)\nwrite the forced response to the system's excitation F cos(w t) (the preset: --fe) "
                       "synthesised from the mode (single-nonlinear-mode synthesis, Krack et al. 2014: "
                       "(w_mode^2 - w^2 + i w xi) a = psi^H F at each backbone point, psi its first harmonic per "
                       "unit a) as CSV: w, a, w_mode, flank and the outputs' _amp1; valid near the resonance of a "
                       "mode well separated from the others")
        ->type_name("FILE.csv");
    command.add_option("--plot-synthesis", o.plot_synthesis,
                       "draw the synthesised response over the harmonic-balance FRF (.png or .svg)\ndraw the synthesised response (as --synthesis-out) over the full harmonic-balance FRF of the same "
                       "system and force (hbf frf over the synthesised band), the first output's first harmonic, "
                       "with both peaks and their difference in the title (and a note on standard error) "
                       "through gnuplot (.png or .svg)")
        ->type_name("FILE.png|FILE.svg");
    command.add_flag("--exact-check", o.exact_check,
                     "check every point against the event-exact solver (exact Coulomb and Jenkins)\ncheck every point against the event-exact solver (exact Coulomb and Jenkins contacts along one "
                     "direction, M > 0, at most 64 DOFs): the free orbit with C - xi M by shooting with exact "
                     "events, compared at the same modal displacement and velocity at a section where every contact "
                     "slips; adds the columns exact_w, exact_xi, exact_gap (empty where not checked: permanent stick "
                     "is the linear mode) and a note with the largest gap");
    command.add_option("--plot-damping", o.plot_damping,
                       "draw the modal damping ratios against the amplitude (.png or .svg)\ndraw zeta and zeta_energy against a (log-log; values below 100 x --tolerance, rounding, left out) "
                       "through gnuplot (.png or .svg)")
        ->type_name("FILE.png|FILE.svg");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output",
                              "write a JSON summary (mode, linear limit, status, points, seconds, largest energy error)",
                              "FILE", "draw the backbone, a (log) against w, through gnuplot (.png or .svg)",
                              "no progress on standard error"});
    describe_output(command, {
        R"(The extended periodic motion concept (Krack 2015): the periodic free motions of
M y'' + (C - xi M) y' + K y + f_contacts = F_s, xi the artificial damping that makes them
periodic, by harmonic balance (--formulation) with the amplitude and phase of the first
harmonic c1 cos + s1 sin fixed (sqrt(c1^T M c1 + s1^T M s1) = a, phi^T M s1 = 0, phi the stuck
mode), followed from --amin to --amax by pseudo-arclength in log a (the backbone may turn back in
a) from the stuck structure's linear mode. The system's excitation (the preset: --fe) is used
only by --synthesis-out and --plot-synthesis. Nondimensional for the preset (y in x_s = N/k1, w
in omega1).
Columns:)",
        io::backbone_columns({Output::dof(0), Output::dof(1)}, {false}, 1),
        R"((y1, y2: the system's outputs; one stick_fraction/regime pair per contact, separated_fraction for
contacts with a normal direction; h0..hH for the H harmonics.) Exit code 0 when the backbone spans
[amin, amax]; 3 when it stops early (Newton fails at the smallest step, the point budget, --time-limit
or an interrupt) or a point
fails the energy balance, or the synthesised response (--synthesis-out, --plot-synthesis) is cut at
the backbone's last point (its peak lies beyond --amax) or empty, with every point computed written; 1 when the first point fails; 2 for
bad input (a mode out of range, a rigid-body mode, an empty amplitude range).)"});
}

}  // namespace

Runner add_modes_command(CLI::App& app) {
    return register_command<ModesOptions>(
        app, "modes",
        "Nonlinear mode of the structure (extended periodic motion concept): frequency and modal damping ratio against "
        "the modal amplitude (backbone), from the stuck structure's linear mode.",
        add_flags, run);
}

}  // namespace hbf::cli
