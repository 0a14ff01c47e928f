// `hbf analytic`: the paper's closed forms on a frequency grid, as CSV.
#include <iostream>
#include <cmath>
#include <memory>

#include "arguments.hpp"
#include "outputs.hpp"
#include "commands.hpp"
#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"
#include "study.hpp"

#include <nlohmann/json.hpp>

namespace hbf::cli {

namespace {
struct AnalyticOptions {
    AbsorberFlags absorber;
    std::string wmin = "0.5", wmax = "1.6", points = "221";
    OutputFlags output;
    std::string sweep, values;
};

/// --sweep: one row per value, the band's largest mu_limit.
int run_sweep(const CLI::App& command, const AnalyticOptions& o, FrictionLaw law, const AbsorberParameters& p,
              double wmin, double wmax) {
    const std::string& name = o.sweep;
    const bool contact = law == FrictionLaw::dahl || law == FrictionLaw::lugre;
    if (!(name == "fe" || name == "mu" || name == "wa" || name == "r" || (name == "wb" && contact) ||
          (name == "xi" && law == FrictionLaw::lugre)))
        throw UsageError("--sweep = '" + name + "' is not a parameter of --law " + to_string(law) +
                         ": allowed fe, mu, wa, r" + (contact ? ", wb" : "") + (law == FrictionLaw::lugre ? ", xi" : ""));
    if (command.count("--" + name) > 0)
        throw UsageError("--" + name + " is what --sweep varies: drop it (its values are --values)");
    for (const char* flag : {"--points", "--plot", "--summary"})
        if (command.count(flag) > 0)
            throw UsageError(std::string(flag) + " does not apply with --sweep (one row per value, not per frequency)");
    const std::vector<double> values = parse_values("--values", o.values);
    std::vector<analytic::LimitFrictionMaximum> rows;
    for (double v : values) {
        try {
            rows.push_back(analytic::limit_friction_maximum(with_parameter(p, name, v), law, wmin, wmax));
        } catch (const InvalidInput& e) {
            throw UsageError("--values: " + name + " = " + format_number(v) + ": " + e.what());
        }
    }
    if (o.output.dry_run) return o.output.dry_run_done("analytic");
    io::OutputFile out(o.output.out);
    out.stream() << name << ",w_at_max,mu_limit_max\n";
    for (std::size_t k = 0; k < values.size(); ++k)
        out.stream() << io::csv_field(values[k]) << ',' << io::csv_field(rows[k].omega) << ','
                     << (rows[k].bounded ? io::csv_field(rows[k].value) : "") << '\n';
    out.commit();
    return exit_success;
}

using nlohmann::json;

json summary_json(const AbsorberParameters& p, FrictionLaw law, double wmin, double wmax) {
    const analytic::LimitFrictionMaximum m = analytic::limit_friction_maximum(p, law, wmin, wmax);
    json resonances = json::array();
    for (double w : analytic::stuck_resonances(p, law))
        resonances.push_back({{"w", w}, {"in_band", w >= wmin && w <= wmax}});
    json j;
    j["law"] = to_string(law);
    j["parameters"] = {{"r", p.mass_ratio},          {"wa", p.tuning_ratio},
                       {"mu", p.friction_coefficient}, {"fe", p.excitation},
                       {"wb", p.contact_stiffness_ratio}, {"xi", p.contact_damping_ratio}};
    j["band"] = {{"wmin", wmin}, {"wmax", wmax}};
    j["mu_limit_max"] = {{"w", m.omega},
                         {"value", m.bounded ? json(m.value) : json(nullptr)},
                         {"bounded", m.bounded},
                         {"meaning", "max over wmin <= w <= wmax of mu_limit: mu >= value sticks (pre-slides) "
                                     "at every frequency of the band; value null = infinite (an undamped stuck "
                                     "resonance lies in the band, at w)"}};
    j["stuck_resonances"] = resonances;
    return j;
}

OutputHelp output_help_of_analytic() {
    return {
        R"(Output: CSV with a header row, one row per frequency of the uniform grid wmin..wmax (both ends
included). All quantities are nondimensional (paper eq. 2): y = x / x_s with x_s = N / k1,
w = Omega / omega1, omega1 = sqrt(k1/m1). An empty field means no finite value exists there (no slipping
solution, or an exact undamped resonance).
Columns:)",
        io::analytic_columns(),
        R"(For dahl and lugre, y*_stick is the pre-sliding (linear contact) response and y*_slip is the same
equivalent-viscous solution as coulomb's (the laws coincide in full slip).)"};
}

int run(const CLI::App& command, const AnalyticOptions& o) {
    const FrictionLaw law = o.absorber.friction_law();
    // the paper's closed forms exist for these three laws only (analytic.hpp); every other law,
    // including those added later, is refused rather than answered with Coulomb's
    if (law != FrictionLaw::coulomb && law != FrictionLaw::dahl && law != FrictionLaw::lugre)
        throw UsageError("--law = '" + o.absorber.law + "' has no closed form: allowed coulomb, dahl, lugre");
    const AbsorberParameters p = o.absorber.parameters(command);
    o.output.check(command);  // before any work
    const double wmin = parse_double("--wmin", o.wmin), wmax = parse_double("--wmax", o.wmax);
    if (command.count("--sweep") != command.count("--values"))
        throw UsageError(command.count("--sweep") ? "--sweep needs --values (the values of the parameter)"
                                                  : "--values needs --sweep (the parameter they are values of)");
    if (command.count("--sweep")) {
        (void)analytic::uniform_grid(wmin, wmax, 2);  // checks the band
        return run_sweep(command, o, law, p, wmin, wmax);
    }
    const std::vector<double> grid = analytic::uniform_grid(wmin, wmax, parse_integer("--points", o.points));
    if (o.output.dry_run) return o.output.dry_run_done("analytic");
    const std::vector<analytic::Row> rows = analytic::table(p, law, grid);
    io::OutputFile out(o.output.out);
    io::write_analytic_csv(out.stream(), rows);
    std::unique_ptr<io::OutputFile> summary;
    if (!o.output.summary.empty()) {
        summary = std::make_unique<io::OutputFile>(o.output.summary);
        summary->stream() << summary_json(p, law, wmin, wmax).dump(2) << '\n';
    }
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = "hbf analytic: " + to_string(law) + ", fe = " + format_number(p.excitation) + ", mu = " +
                     format_number(p.friction_coefficient);
        spec.xlabel = "w";
        spec.ylabel = "|Y1|, first-harmonic amplitude of y1";
        io::PlotCurve stick{"y1_stick (full stick)", {}, {}, io::PlotCurve::Style::line, 7};
        io::PlotCurve slip{"y1_slip (full slip, equivalent viscous)", {}, {}, io::PlotCurve::Style::dashed, 7};
        for (const analytic::Row& row : rows) {  // no value: a gap in the line
            stick.x.push_back(row.omega);
            stick.y.push_back(row.y1_stick ? *row.y1_stick : std::nan(""));
            slip.x.push_back(row.omega);
            slip.y.push_back(row.y1_slip ? *row.y1_slip : std::nan(""));
        }
        spec.curves = {stick, slip};
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    if (summary) summary->commit();
    return exit_success;
}
/// The flags of hbf analytic.
void add_flags(CLI::App& command, AnalyticOptions& o) {
    o.absorber.add_to(command, "friction law: coulomb, dahl or lugre", "coulomb", false);
    command.add_option("--wmin", o.wmin, "lowest frequency w, > 0")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--wmax", o.wmax, "highest frequency w, > wmin")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--points", o.points, "number of frequencies, 2..1000000")
        ->capture_default_str()->type_name("INT");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output",
                                      "write a JSON summary (the band's largest mu_limit, the parameters) to FILE\nwrite a JSON summary to FILE: mu_limit_max = the largest mu_limit over wmin..wmax (w "
                                      "and value, refined beyond the grid, null if infinite: mu >= value sticks at every "
                                      "frequency of the band) and the stuck system's undamped resonances",
                                      "FILE.json", "draw y1_stick and y1_slip against w through gnuplot (.png or .svg)", ""});
    command.add_option("--sweep", o.sweep,
                        "with --values: the band's largest mu_limit for each value of this parameter\nwith --values: the band's largest mu_limit for each value of this parameter (fe, mu, wa, r; "
                        "wb for dahl and lugre; xi for lugre) instead of the frequency table; the CSV is then "
                        "NAME,w_at_max,mu_limit_max (as mu_limit_max of --summary; empty = infinite)")
        ->type_name("NAME");
    command.add_option("--values", o.values,
                        "the values of --sweep: V1,V2,..., START:STOP:N or log:START:STOP:N (as hbf map)")
        ->type_name("LIST");
    describe_output(command, output_help_of_analytic());
}
}  // namespace

Runner add_analytic_command(CLI::App& app) {
    return register_command<AnalyticOptions>(app, "analytic", "Closed-form stick and slip responses, limit and optimal friction coefficients "
                    "of the paper's friction absorber (nondimensional).", add_flags, run);
}

}  // namespace hbf::cli
