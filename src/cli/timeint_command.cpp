// `hbf timeint`: periodic steady states of the paper's absorber by time integration (CVODE),
// at one frequency or along a sweep, as CSV.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "arguments.hpp"
#include "stop_request.hpp"
#include "outputs.hpp"
#include "progress.hpp"
#include "commands.hpp"
#include "hbf/analytic.hpp"
#include "hbf/error.hpp"
#include "hbf/config.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_branch.hpp"
#include "hbf/table.hpp"
#include "hbf/time_integration.hpp"
#include "hbf/timeint_sweep.hpp"
#include "hbf/rigid_exact.hpp"

namespace hbf::cli {

namespace {
constexpr long long max_points = 10000;


struct TimeintOptions {
    AbsorberFlags absorber;
    std::string w, wmin, wmax, points, sweep = "up", method = "adams";
    // the library's defaults (time_integration.hpp)
    std::string rtol = default_text(TimeIntegrationOptions{}.relative_tolerance),
                atol = default_text(TimeIntegrationOptions{}.absolute_tolerance),
                steady_tol = default_text(TimeIntegrationOptions{}.steady_tolerance),
                max_periods = std::to_string(TimeIntegrationOptions{}.max_periods),
                min_periods = std::to_string(TimeIntegrationOptions{}.min_periods);
    OutputFlags output;
    std::string config, time_limit = "0", symmetric = "off";
};

bool given(const CLI::App& command, const char* flag) { return command.count(flag) > 0; }

double positive_frequency(const std::string& flag, const std::string& text) {
    const double w = parse_double(flag, text);
    if (!(w > 0.0)) throw UsageError(flag + " = '" + text + "' is out of range: allowed frequencies > 0");
    return w;
}

/// "low..high" of a library range, as the help and the messages show it.
std::string range_text(double low, double high) { return default_text(low) + ".." + default_text(high); }

using Tio = TimeIntegrationOptions;  // the ranges' home

double tolerance(const std::string& flag, const std::string& text, double low, double high) {
    const double value = parse_double(flag, text);
    if (!(value >= low && value <= high))
        throw UsageError(flag + " = '" + text + "' is out of range: allowed " + range_text(low, high));
    return value;
}

std::vector<double> frequencies(const CLI::App& command, const TimeintOptions& o) {
    const bool single = given(command, "--w");
    const bool range = given(command, "--wmin") || given(command, "--wmax") || given(command, "--points");
    if (single && range) throw UsageError("--w cannot be combined with --wmin, --wmax or --points: give one or the other");
    if (!single && !range) throw UsageError("no frequency: give --w W, or --wmin A --wmax B --points K");
    if (single) {
        if (given(command, "--sweep")) throw UsageError("--sweep applies to --wmin/--wmax/--points only, not to --w");
        return {positive_frequency("--w", o.w)};
    }
    for (const char* flag : {"--wmin", "--wmax", "--points"})
        if (!given(command, flag))
            throw UsageError(std::string(flag) + " is missing: a sweep needs --wmin, --wmax and --points");
    const double wmin = positive_frequency("--wmin", o.wmin);
    const double wmax = positive_frequency("--wmax", o.wmax);
    if (!(wmax > wmin))
        throw UsageError("--wmax = '" + o.wmax + "' is out of range: allowed > --wmin = " + format_number(wmin));
    const long long points = parse_integer("--points", o.points);
    if (points < 2 || points > max_points)
        throw UsageError("--points = '" + o.points + "' is out of range: allowed 2.." + std::to_string(max_points));
    if (o.sweep != "up" && o.sweep != "down" && o.sweep != "branch")
        throw UsageError("--sweep = '" + o.sweep + "' is not allowed: allowed up, down, branch");
    std::vector<double> grid = analytic::uniform_grid(wmin, wmax, points);
    if (o.sweep == "down") std::reverse(grid.begin(), grid.end());
    return grid;
}

/// The steady state by the event-exact solver (--method exact), as a time-integration row:
/// Newton from `start`; if that fails, again after plain exact periods (the exact flow
/// integrates the motion) up to max_periods.
int run(const CLI::App& command, const TimeintOptions& o) {
    o.output.check_plot();  // before any work
    const ChosenSystem chosen = choose_system(command, o.absorber, o.config);
    o.output.check(command, chosen.inputs());
    const System& system = chosen.system;
    const std::string title = "hbf timeint: " + (o.config.empty() ? chosen.law_name + " (sweep " + o.sweep + ")" : o.config);
    const std::vector<double> omegas = frequencies(command, o);
    TimeIntegrationOptions tio;
    tio.relative_tolerance =
        tolerance("--rtol", o.rtol, Tio::smallest_relative_tolerance, Tio::largest_relative_tolerance);
    tio.absolute_tolerance =
        tolerance("--atol", o.atol, Tio::smallest_absolute_tolerance, Tio::largest_absolute_tolerance);
    tio.steady_tolerance =
        tolerance("--steady-tol", o.steady_tol, Tio::smallest_steady_tolerance, Tio::largest_steady_tolerance);
    const long long max_periods = parse_integer("--max-periods", o.max_periods);
    if (max_periods < 1 || max_periods > Tio::largest_max_periods)
        throw UsageError("--max-periods = '" + o.max_periods + "' is out of range: allowed 1.." +
                         std::to_string(Tio::largest_max_periods));
    const long long min_periods = parse_integer("--min-periods", o.min_periods);
    if (min_periods > max_periods && given(command, "--max-periods") && !given(command, "--min-periods"))
        throw UsageError("--max-periods = '" + o.max_periods + "' is below --min-periods (" + o.min_periods +
                         " by default): allowed --max-periods >= --min-periods");
    if (min_periods < 1 || min_periods > max_periods)
        throw UsageError("--min-periods = '" + o.min_periods + "' is out of range: allowed 1..--max-periods (" +
                         std::to_string(max_periods) + ")");
    tio.max_periods = static_cast<int>(max_periods);
    tio.min_periods = static_cast<int>(min_periods);
    if (o.method != "adams" && o.method != "bdf" && o.method != "exact")
        throw UsageError("--method = '" + o.method + "' is not allowed: allowed adams, bdf, exact");
    tio.method = o.method == "bdf" ? IntegrationMethod::bdf : IntegrationMethod::adams;
    const bool exact = o.method == "exact";
    const bool branch = o.sweep == "branch";
    if (branch && !exact)
        throw UsageError("--sweep branch follows the branch of exact orbits through its folds: it needs --method exact "
                         "(time integration sweeps up or down)");
    if (exact) {  // at the lowest w, a period costs the most Taylor steps (exact_cost_refusal)
        const std::string refusal = exact_sweep_refusal(system, *std::min_element(omegas.begin(), omegas.end()));
        if (!refusal.empty()) throw UsageError("--method exact: " + refusal + " (use adams or bdf)");
    }
    if (o.symmetric != "on" && o.symmetric != "off")
        throw UsageError("--symmetric = '" + o.symmetric + "' is not allowed: allowed on, off");
    const bool symmetric = o.symmetric == "on";
    if (symmetric) {  // refused where it would do nothing, before the work
        if (!exact) throw UsageError("--symmetric on applies to --method exact: allowed off here");
        if (const std::string why = mirror_symmetric_refusal(system); !why.empty())
            throw UsageError("--symmetric on: " + why + ": allowed off here");
    }
    tio.outputs = chosen.outputs;
    ExactOptions eo;
    eo.outputs = chosen.outputs;
    eo.tolerance = given(command, "--steady-tol") ? tio.steady_tolerance : 1e-12;
    eo.mirror_symmetric = symmetric;

    const double time_limit = parse_time_limit(o.time_limit);
    if (o.output.dry_run) return o.output.dry_run_done("timeint");
    io::OutputFile out(o.output.out);  // opened before the work: an unwritable path fails fast
    MessageCollector messages;  // what CVODE reports during the sweep
    // An interrupt or the time limit ends the sweep: the frequencies done are written (exit 3);
    // the integration under way stops after its current period and is not written.
    StopRequest stop("timeint", time_limit);
    // The progress line: the point under way and the periods it has taken (asked after every
    // period: an exact cold start on a meshed interface takes thousands).
    ProgressLine progress(o.output.progress(), "timeint");
    std::string where;
    long long periods = 0;
    tio.stop = [&stop, &progress, &where, &periods] {
        ++periods;
        progress.update(where + ", " + std::to_string(periods) + (periods == 1 ? " period" : " periods"));
        return stop.why();
    };
    eo.stop = tio.stop;
    std::string stopped;
    std::vector<PeriodicResponse> responses;
    Verdict verdict;
    if (branch) {
        Eigen::VectorXd state = linear_stuck_state(system, omegas.front());
        ExactBranchOptions bo =
            exact_branch_options(omegas.front(), omegas.back(), static_cast<long long>(omegas.size()));
        bo.exact = eo;
        bo.max_periods = tio.max_periods;
        where = "branch from w = " + format_number(omegas.front());
        int done = 0;
        bo.progress = [&where, &periods, &done](const PeriodicResponse& r, double step) {
            char text[96];
            std::snprintf(text, sizeof text, "branch point %d at w = %.9g (step %.3g), next", ++done, r.omega, step);
            where = text;
            periods = 0;
        };
        ExactBranch b = exact_branch(system, bo, state);
        responses = std::move(b.points);
        if (b.status == "failed")
            verdict.error(b.message);
        else if (b.status != "completed")
            verdict.warning(b.message + " (" + std::to_string(responses.size()) + " points written)");
        for (const ExactFold& fold : b.folds)
            verdict.note("a fold at w = " + format_number(fold.omega) + " (branch point " + std::to_string(fold.point + 1) +
                         ": the parabola's vertex through the exact orbits about the turn)");
        for (const double w : b.corners)
            verdict.note("a corner of the branch at w = " + format_number(w) +
                         " (not smooth there: a contact's regime changes, e.g. stick to stick-slip)");
        verdict.note(std::to_string(responses.size()) + " branch points, " + std::to_string(b.folds.size()) + " fold(s), " +
                     std::to_string(b.corners.size()) + " corner(s), " +
                     std::to_string(b.rejected) + " solve(s) not taken (the step halved)");
    }
    if (!branch) {
        SteadySweep sweep = sweep_steady_states(
            system, omegas, tio, exact ? &eo : nullptr, [&stop] { return stop.why(); },
            [&](std::size_t k) {
                char text[96];
                std::snprintf(text, sizeof text, "point %zu of %zu, w = %.9g", k + 1, omegas.size(), omegas[k]);
                where = text;
                periods = 0;
            });
        responses = std::move(sweep.responses);
        stopped = std::move(sweep.stopped);
    }
    progress.clear();
    io::write_timeint_csv(out.stream(), responses, chosen.outputs,
                          chosen.config ? chosen.config->interfaces : std::vector<InterfaceContacts>());
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = title;
        spec.xlabel = "w";
        const std::string& name = chosen.outputs.front().name();
        spec.ylabel = name + "_max = max over one period of |" + name + "(t)|";
        io::PlotCurve line{exact ? (branch ? "exact orbits (branch order)" : "exact orbits (sweep order)")
                                 : "time integration (sweep order)",
                           {}, {}, io::PlotCurve::Style::line, 7};
        io::PlotCurve converged{exact ? "stable" : "converged", {}, {}, io::PlotCurve::Style::markers, 4};
        io::PlotCurve unstable{"unstable (a Floquet multiplier above 1)", {}, {}, io::PlotCurve::Style::markers, 1};
        io::PlotCurve failed{"not converged", {}, {}, io::PlotCurve::Style::markers, 3};
        io::PlotCurve unknown{"stability unknown (multipliers not computed)", {}, {}, io::PlotCurve::Style::markers, 12};
        io::PlotCurve uncertain{"stability uncertain (a multiplier at 1 within the differences' accuracy)", {}, {},
                                io::PlotCurve::Style::markers, 10};
        for (const PeriodicResponse& r : responses) {
            line.x.push_back(r.omega);
            line.y.push_back(r.output_max.front());
            io::PlotCurve& marks = !r.converged                                                    ? failed
                                   : exact && !std::isfinite(r.max_multiplier)                     ? unknown
                                   : r.stability_unresolved(eo.stability_tolerance)                ? uncertain
                                   : r.max_multiplier > 1.0 + eo.stability_tolerance               ? unstable
                                                                                                   : converged;
            marks.x.push_back(r.omega);
            marks.y.push_back(r.output_max.front());
        }
        spec.curves = {line, converged, unstable, unknown, uncertain, failed};
        io::write_plot(o.output.plot, spec);  // before the CSV is committed: a failed plot leaves no output
    }
    out.commit();
    // Points that did not converge (errors) and converged points out of energy balance
    // (warnings): judge_sweep, frf.hpp.
    verdict.add(judge_sweep(system, responses, tio, exact ? &eo : nullptr));
    if (symmetric) {  // the points --symmetric on could not solve among the symmetric states
        std::string where_not;
        int count = 0;
        for (const PeriodicResponse& r : responses)
            if (r.converged && r.message.find("(not among the mirror-symmetric states") != std::string::npos) {
                if (++count <= 5) where_not += (count > 1 ? ", " : "") + format_number(r.omega);
            }
        if (count > 0)
            verdict.note("--symmetric on: " + std::to_string(count) + " of " + std::to_string(responses.size()) +
                         " orbits were solved as with off, their contact patterns at the section not their own mirror "
                         "image (w = " + where_not + (count > 5 ? ", ..." : "") + ")");
    }
    verdict.add(messages.messages());
    if (!stopped.empty())
        verdict.warning(stopped + " (" + std::to_string(responses.size()) + " of " + std::to_string(omegas.size()) +
                        " frequencies written)");
    return finish("timeint", verdict);
}
/// The flags of hbf timeint.
void add_flags(CLI::App& command, TimeintOptions& o) {
    o.absorber.add_system_flags(command);
    command.remove_option(command.get_option("--dlft-eps"));  // harmonic balance only
    command.add_option("--w", o.w, "a single frequency w, > 0")->type_name("NUMBER");
    command.add_option("--wmin", o.wmin, "first frequency of the sweep grid, > 0")->type_name("NUMBER");
    command.add_option("--wmax", o.wmax, "last frequency of the sweep grid, > wmin")->type_name("NUMBER");
    command.add_option("--points", o.points, "number of frequencies of the uniform sweep grid, 2..10000")
        ->type_name("INT");
    command.add_option("--sweep", o.sweep,
                        "sweep: up (wmin to wmax), down (wmax to wmin), or branch (--method exact: the exact orbits "
                        "through the folds)\nsweep direction: up (wmin to wmax) or down (wmax to wmin); each point "
                        "starts from the previous point's steady state; or branch (--method exact): the branch of exact "
                        "orbits from wmin "
                        "followed by its arclength through its folds until it leaves [wmin, wmax], each point solved at "
                        "the w predicted along the branch (steps at most those of --points on a flat branch, adapted; at "
                        "most 20 --points points), the folds located")
        ->capture_default_str()->type_name("up|down|branch");
    command.add_option("--rtol", o.rtol,
                       "CVODE relative tolerance, " +
                           range_text(Tio::smallest_relative_tolerance, Tio::largest_relative_tolerance))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--atol", o.atol,
                        "CVODE absolute tolerance relative to the response's scale\nCVODE absolute tolerance relative to the response's scale s (displacements atol s, velocities "
                        "atol h w s; s = min(|K^-1 F|, |M^-1 F| / (h w)^2): the same in any units and at any w), " +
                            range_text(Tio::smallest_absolute_tolerance, Tio::largest_absolute_tolerance))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--steady-tol", o.steady_tol,
                        "Poincare convergence: the relative change of the state over one period\nPoincare convergence: the state at the start of consecutive periods changes by <= "
                        "steady-tol relative to the displacement scale max(|y|_inf, |y'|_inf / w) (velocities divided by w: "
                        "the same in any units), " +
                            range_text(Tio::smallest_steady_tolerance, Tio::largest_steady_tolerance))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-periods", o.max_periods,
                       "periods per frequency at most, 1.." + std::to_string(Tio::largest_max_periods))
        ->capture_default_str()->type_name("INT");
    command.add_option("--min-periods", o.min_periods, "periods per frequency at least, 1..max-periods")
        ->capture_default_str()->type_name("INT");
    command.add_option("--method", o.method,
                        "CVODE method: adams or bdf\nCVODE method: adams (fixed-point iteration; fastest here) or bdf (Newton, dense "
                        "difference-quotient Jacobian; for stiff contacts); or exact (coulomb, jenkins, law unilateral on "
                        "massless contact nodes, law elastic): the event-exact solver, flows between stick/slip/lift-off events "
                        "and Newton shooting on the period map, each point from the previous point's orbit (steady "
                        "state to --steady-tol, default 1e-12 with it; --rtol and --atol do not apply; periods counts "
                        "the period maps evaluated; law elastic: its event-driven flow at a tolerance of 1e-11 with the "
                        "flow's derivative, converged at 1e-9 where that is its accuracy). With laws unilateral and "
                        "elastic, orbits on which some nodes stick all period "
                        "form a family (any held position inside the friction cones): the sweep keeps the member its "
                        "history leads to, as a slow sweep of the structure would")
        ->capture_default_str()->type_name("adams|bdf|exact");
    command.add_option("--symmetric", o.symmetric,
                       "on: each exact orbit among the mirror-symmetric states (--method exact, law unilateral in "
                       "3D)\non: each exact orbit is solved among the states of a mirror-symmetric structure that are "
                       "their own mirror images (--method exact, law unilateral's 3D contacts; refused where the "
                       "structure has no mirror symmetry). Where nodes stick all period the orbits form a family (any "
                       "held position inside the friction cones), and this is the symmetric member Newton reaches "
                       "from the start projected onto the symmetric states (not unique either: a sweep's history can "
                       "still move the held positions, but not sideways); where the "
                       "orbit's contact patterns at its section are not their own mirror image the point is solved "
                       "as with off, and its message says so. off: the orbit the sweep's history leads to, "
                       "symmetric or not")
        ->capture_default_str()->type_name("on|off");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output", "", "FILE",
                                      "draw y1_max against w (sweep order, non-converged points marked) through gnuplot "
                                      "(.png or .svg)",
                                      "no progress on standard error"});
    command.add_option("--time-limit", o.time_limit,
                       "stop after SECONDS and write the frequencies done so far (exit 3); 0: none\n"
                       "stop the sweep after SECONDS of wall time (0: no limit) and write the frequencies whose "
                       "steady state was done (exit code 3); the integration under way stops after its current "
                       "period and is not written. An interrupt (Ctrl-C, SIGTERM, SIGHUP) does the same; a second "
                       "one ends the process without output")
        ->option_text("SECONDS");
    command.add_option("--config", o.config,
                        "integrate the structure of a TOML system file (as hbf frf --config)\nintegrate the structure of a TOML system file (as hbf frf --config; its frequency range "
                        "and solver settings are not used: give --w or --wmin/--wmax/--points)")
        ->option_text("FILE.toml");
    describe_output(command, {
        R"(Each frequency is integrated period by period until the Poincare map converges (with Newton shooting
steps when it contracts slowly). The first frequency starts from the linear steady state with the
contact stuck, the next ones from the previous steady state (a sweep follows one branch: hysteresis
between up and down sweeps; --sweep branch with --method exact follows the branch of exact orbits
through its folds, the folds in notes). Output: CSV with a header row, one row per frequency in
sweep (or branch) order.
Nondimensional as in the paper: y = x / x_s, x_s = N / k1, w = Omega / omega1.
Columns:)",
        io::timeint_columns({Output::dof(0), Output::dof(1)}, 1, {0}, {InterfaceContacts{}}),  // with law elastic's and an interface's columns
        R"(converged = true needs the Poincare map converged and the final period's physics: energy balance
(input work = dissipated energy per period), contacts stuck for the whole period moving together,
and permanent stick on the centred linear stuck state (as --method exact), each to max(1e-6, 100
max(rtol, steady-tol)). A point that did not converge is written with converged = false and reported
on standard error, and the exit code is 1 (like a stalled hbf frf branch: what was computed is
written). --time-limit or an interrupt ends the sweep early: the frequencies done are written and
the exit code is 3.)"});
}
}  // namespace

Runner add_timeint_command(CLI::App& app) {
    return register_command<TimeintOptions>(app, "timeint", "Periodic steady states of a structure with friction and contact (--config FILE, or the paper's "
                   "friction absorber) by time integration (SUNDIALS CVODE; law unilateral: velocity Verlet with a "
                   "complementarity solve per step): the reference for harmonic balance. One frequency (--w) or a sweep (--wmin --wmax --points).", add_flags, run);
}

}  // namespace hbf::cli
