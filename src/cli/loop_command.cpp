// `hbf loop`: the time signals of one harmonic-balance solution (friction force against
// relative velocity: the friction loop), as CSV and optionally a plot.
#include <iostream>
#include <cmath>
#include <memory>

#include "arguments.hpp"
#include "outputs.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/table.hpp"

namespace hbf::cli {

namespace {
struct LoopOptions {
    AbsorberFlags absorber;
    std::string w, wmin = "0.5", harmonics = "0", time_samples = "0", contact = "1";
    OutputFlags output;
    std::string config;
};

/// The columns for a system of `dofs` DOFs and a contact with `signals` directions (law
/// elastic: 2 or 3, the normal last).
std::vector<io::Column> loop_columns(int dofs, int signals) {
    std::vector<io::Column> columns = {{"t", "time over one period, t = theta / w (theta = w t from 0 to 2 pi)"}};
    for (int i = 1; i <= dofs; ++i)
        columns.push_back({"y" + std::to_string(i), "displacement y" + std::to_string(i) + "(t)"});
    const std::vector<io::Column> rest = {
        {"q", "relative displacement of the contact, q = w_c^T y (absorber: y1 - y2)"},
        {"v", "relative velocity dq/dt"},
        {"f", "friction force of the contact by its law, in time (acts as -f on its first DOF; coulomb: the "
              "dynamic Lagrangian's multiplier projected on [-mu, mu], so |f| <= mu; jenkins: the marched force)"},
        {"stick", "1 where the contact sticks by its law's definition (hbf frf --help: stick_fraction), else 0"},
        {"f_series", "f's Fourier series truncated to the H harmonics: the force the harmonic-balance equations "
                     "see (it overshoots mu near a discontinuity: Gibbs)"}};
    columns.insert(columns.end(), rest.begin(), rest.end());
    if (signals == 3) {
        columns.push_back({"q2", "laws elastic, unilateral, 3D: relative displacement along the second tangential direction"});
        columns.push_back({"f2", "laws elastic, unilateral, 3D: tangential force along the second direction (|(f, f2)| <= mu fn)"});
    }
    if (signals >= 2) {
        columns.push_back({"qn", "laws elastic, unilateral: normal relative displacement v = n^T y (positive closing)"});
        columns.push_back({"fn", "laws elastic, unilateral: normal force N (elastic: max(0, N_0 - k_n g_0 + k_n v); unilateral: the obstacle's reaction)"});
        columns.push_back({"open", "laws elastic, unilateral: 1 where the contact is separated (N = 0), else 0"});
    }
    return columns;
}

int run(const CLI::App& command, const LoopOptions& o) {
    o.output.check_plot();  // before any work
    const ChosenSystem chosen = choose_system(command, o.absorber, o.config);
    o.output.check(command, chosen.inputs());
    if (o.w.empty()) throw UsageError("--w is required: the frequency of the solution");
    const double w = parse_double("--w", o.w);
    if (!(w > 0.0)) throw UsageError("--w = " + o.w + " is out of range: allowed > 0");
    double wmin = parse_double("--wmin", o.wmin);
    if (!(wmin > 0.0)) throw UsageError("--wmin = " + o.wmin + " is out of range: allowed > 0");
    if (chosen.config && chosen.config->choices.omega_start && command.count("--wmin") == 0) wmin = *chosen.config->choices.omega_start;
    const long long contact = parse_integer("--contact", o.contact);
    const auto contacts = static_cast<long long>(chosen.system.contacts.size());
    if (contact < 1 || contact > contacts)
        throw UsageError("--contact = " + o.contact + " is out of range: allowed 1.." + std::to_string(contacts));
    const HarmonicBalanceOptions hbo = harmonic_balance_options(command, o.harmonics, o.time_samples, chosen, o.config, false);

    // The solution at w: the branch followed from wmin (from 0.9 w when w <= wmin).
    ContinuationOptions co;
    if (o.output.dry_run) {  // the same checks, without building the Fourier matrices
        HarmonicBalance::validate(chosen.system, hbo);
        co.omega_start = w > wmin ? wmin : 0.9 * w;
        co.omega_end = w;
        validate(co);
        return o.output.dry_run_done("loop");
    }
    HarmonicBalance hb(chosen.system, hbo);
    MessageCollector messages;  // what Ceres reports while the solution is found
    const SolutionAt solution = solve_at(hb, w, wmin, co);
    if (!solution.found)
        throw std::runtime_error("no solution at w = " + format_number(w) + ": the branch from w = " +
                                 format_number(w > wmin ? wmin : 0.9 * w) +
                                 " stopped: " + solution.branch.summary());
    const SolutionPoint* at = &solution.point;
    const PointSignals s = point_signals(hb, *at, static_cast<int>(contact - 1));

    io::OutputFile out(o.output.out);
    const auto signals = s.q_directions.cols();
    const auto columns = loop_columns(hb.system().dofs(), static_cast<int>(signals));
    for (std::size_t k = 0; k < columns.size(); ++k) out.stream() << (k ? "," : "") << columns[k].name;
    out.stream() << '\n';
    for (Eigen::Index j = 0; j < s.time.size(); ++j) {
        out.stream() << io::csv_field(s.time(j));
        for (Eigen::Index i = 0; i < s.y.cols(); ++i) out.stream() << ',' << io::csv_field(s.y(j, i));
        out.stream() << ',' << io::csv_field(s.q(j)) << ',' << io::csv_field(s.v(j)) << ',' << io::csv_field(s.f(j))
                     << ',' << (s.phi(j) < 0.0 ? 1 : 0) << ',' << io::csv_field(s.f_series(j));
        for (Eigen::Index a = 1; a < signals; ++a)
            out.stream() << ',' << io::csv_field(s.q_directions(j, a)) << ',' << io::csv_field(s.f_directions(j, a));
        if (signals >= 2) out.stream() << ',' << (s.f_directions(j, signals - 1) > 0.0 ? 0 : 1);
        out.stream() << '\n';
    }
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = "hbf loop: " + chosen.law_name + ", w = " + format_number(w) + ", H = " + std::to_string(hb.harmonics());
        spec.xlabel = "v = relative velocity dq/dt";
        spec.ylabel = "f = friction force";
        io::PlotCurve loop{"friction loop (one period)", {}, {}, io::PlotCurve::Style::line, 7};
        for (Eigen::Index j = 0; j <= s.time.size(); ++j) {  // closed: back to the first sample
            const Eigen::Index k = j % s.time.size();
            loop.x.push_back(s.v(k));
            loop.y.push_back(s.f(k));
        }
        spec.curves = {loop};
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    Verdict verdict;
    Analyser analyse(hb, {0});
    const double imbalance = analyse(*at).energy_error;
    if (imbalance > energy_balance_limit(co.corrector.tolerance))
        verdict.warning("the solution at w = " + format_number(w) + " fails the energy balance (relative error " +
                        format_number(imbalance) + ", allowed " +
                        format_number(energy_balance_limit(co.corrector.tolerance)) + "; hbf frf --help: energy_error)");
    verdict.add(messages.messages());
    return finish("loop", verdict);
}
/// The flags of hbf loop.
void add_flags(CLI::App& command, LoopOptions& o) {
    o.absorber.add_system_flags(command);
    command.add_option("--w", o.w, "frequency w of the solution, > 0 (required)")->type_name("NUMBER");
    command.add_option("--wmin", o.wmin,
                        "the solution is the one reached by following the branch from wmin (from 0.9 w when "
                        "w <= wmin), > 0")
        ->capture_default_str()->type_name("NUMBER");
    add_discretisation_flags(command, o.harmonics, o.time_samples, "the largest of the contacts' laws' own");
    command.add_option("--contact", o.contact, "which contact's q, v, f and stick to write (1-based)")
        ->capture_default_str()->type_name("INT");
    command.add_option("--config", o.config, "the structure from a TOML system file (as hbf frf --config)")
        ->option_text("FILE.toml");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output", "", "FILE",
                                      "draw f against v through gnuplot (.png or .svg)", ""});
    describe_output(command, {
        R"(Output: CSV with a header row, one row per time sample of one period (the AFT grid). Nondimensional
for the preset (t in 1/omega1, y in x_s = N/k1, f in N).
Columns:)",
        loop_columns(2, 3),
        R"((y1, y2: one column per DOF of the system; q2, f2 for a 3D contact of laws elastic and unilateral, qn, fn, open for every such contact.) Exit code 1 when the branch does not reach w.)"});
}
}  // namespace

Runner add_loop_command(CLI::App& app) {
    return register_command<LoopOptions>(app, "loop", "Time signals of one harmonic-balance solution at frequency w: displacements, the contact's "
                "relative motion and friction force (the friction loop f against v, paper Figs. 5-6).", add_flags, run);
}

}  // namespace hbf::cli
