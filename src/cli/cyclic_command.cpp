// `hbf nodal-diameters`: the linear nodal-diameter families of a cyclically symmetric wheel
// given by one sector (a [cyclic] system file), released and stuck, and which of them the
// engine order's harmonics excite: CSV, a plot, a line on standard error.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "commands.hpp"
#include "frf_flags.hpp"
#include "outputs.hpp"
#include "hbf/config.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"
#include "hbf/output_file.hpp"
#include "hbf/plot.hpp"
#include "hbf/table.hpp"

namespace hbf::cli {

namespace {
struct NodalDiameterOptions {
    std::string config, harmonics = "10", modes;
    OutputFlags output;
};

int run(const CLI::App& command, const NodalDiameterOptions& o) {
    o.output.check_plot();
    if (o.config.empty()) throw UsageError("--config is required: a system file with a [cyclic] table");
    const long long harmonics = parse_integer("--harmonics", o.harmonics);
    if (harmonics < 1 || harmonics > 100)
        throw UsageError("--harmonics = " + o.harmonics + " is out of range: allowed 1..100");
    const io::SystemConfig config = io::read_system_config(o.config);
    std::vector<io::InputFile> inputs = config.inputs;
    o.output.check(command, inputs);
    if (!config.cyclic_note.empty()) std::cerr << "hbf nodal-diameters: note: " << config.cyclic_note << "\n";
    const System& system = config.system;
    if (!system.cyclic.active())
        throw UsageError("--config " + o.config + ": the model is not a sector (no [cyclic] table)");
    const auto own = static_cast<long long>(independent_dofs(system).size());
    long long kept = own;
    if (given(command, "--modes")) {
        kept = parse_integer("--modes", o.modes);
        if (kept < 1 || kept > own)
            throw UsageError("--modes = " + o.modes + " is out of range: allowed 1.." + std::to_string(own) +
                             " (the sector's own DOFs)");
    }
    if (o.output.dry_run) return o.output.dry_run_done("nodal-diameters");
    NodalDiameterFamily released = nodal_diameter_family(system, false);
    NodalDiameterFamily stuck = nodal_diameter_family(system, true);
    released.frequencies = released.frequencies.leftCols(kept).eval();
    stuck.frequencies = stuck.frequencies.leftCols(kept).eval();
    const io::Table table = io::nodal_diameter_table(system.cyclic, released, stuck, static_cast<int>(harmonics));
    const Eigen::Index diameters = released.frequencies.rows(), modes = released.frequencies.cols();
    io::OutputFile out(o.output.out);
    io::write_csv(out.stream(), table);
    if (!o.output.plot.empty()) {
        io::PlotSpec spec;
        spec.title = "hbf nodal-diameters: " + std::to_string(system.cyclic.sectors) + " sectors, engine order " +
                     std::to_string(system.cyclic.engine_order);
        spec.xlabel = "nodal diameter";
        spec.ylabel = "natural frequency";
        const double nan = std::numeric_limits<double>::quiet_NaN();
        io::PlotCurve r{"released", {}, {}, io::PlotCurve::Style::line, 7}, s{"stuck", {}, {}, io::PlotCurve::Style::dashed, 7};
        double top = 0.0;
        for (Eigen::Index j = 0; j < modes; ++j) {  // one line per mode family, broken between them
            for (Eigen::Index d = 0; d < diameters; ++d) {
                r.x.push_back(static_cast<double>(d));
                r.y.push_back(released.frequencies(d, j));
                s.x.push_back(static_cast<double>(d));
                s.y.push_back(stuck.frequencies(d, j));
                top = std::max(top, std::isfinite(stuck.frequencies(d, j)) ? stuck.frequencies(d, j) : 0.0);
                top = std::max(top, released.frequencies(d, j));
            }
            r.x.push_back(nan);
            r.y.push_back(nan);
            s.x.push_back(nan);
            s.y.push_back(nan);
        }
        const double d1 = nodal_diameter(system.cyclic, 1);
        io::PlotCurve eo{"engine order " + std::to_string(system.cyclic.engine_order) + " (harmonic 1)",
                         {d1, d1}, {0.0, 1.05 * top}, io::PlotCurve::Style::dashed, 7};
        spec.curves = {r, s, eo};
        io::write_plot(o.output.plot, spec);
    }
    out.commit();
    if (o.output.verbose()) {
        const int d = nodal_diameter(system.cyclic, 1);
        std::cerr << "hbf nodal-diameters: engine order " << system.cyclic.engine_order << " of "
                  << system.cyclic.sectors << " sectors excites nodal diameter " << d
                  << " at harmonic 1: its first mode released at " << format_number(released.frequencies(d, 0))
                  << ", stuck at "
                  << (std::isfinite(stuck.frequencies(d, 0)) ? format_number(stuck.frequencies(d, 0)) : std::string("none"))
                  << "\n";
    }
    return finish("nodal-diameters", Verdict{});
}

void add_flags(CLI::App& command, NodalDiameterOptions& o) {
    command.add_option("--config", o.config, "the sector: a TOML system file with a [cyclic] table (required)")
        ->option_text("FILE.toml");
    command.add_option("--harmonics", o.harmonics,
                       "the response's harmonics k whose nodal diameters the column excited_by lists, 1..100")
        ->capture_default_str()->type_name("INT");
    command.add_option("--modes", o.modes,
                       "the lowest modes of each nodal diameter written and drawn, 1..the sector's own DOFs (default: every one)")
        ->type_name("INT");
    o.output.add_to(command, {"write the CSV to FILE instead of standard output", "",
                              "FILE", "draw the families against the nodal diameter through gnuplot (.png or .svg)",
                              "no summary line on standard error"});
    describe_output(command, {"Output: CSV with a header row, one row per nodal diameter and mode (in the system "
                              "file's units).\nColumns:",
                              io::nodal_diameter_columns(), "Exit code 2 for a file without [cyclic] or a sector whose mass matrix is "
                                         "singular on its own DOFs."});
}
}  // namespace

Runner add_nodal_diameters_command(CLI::App& app) {
    return register_command<NodalDiameterOptions>(
        app, "nodal-diameters",
        "Linear nodal-diameter families of a cyclically symmetric wheel from one sector ([cyclic] system file): "
        "natural frequencies against nodal diameter, released and stuck, and those the engine order excites.",
        add_flags, run);
}

}  // namespace hbf::cli
