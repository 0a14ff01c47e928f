// hbf command line — the output flags every command shares, as one group: --out (the CSV),
// --summary (JSON), --plot (gnuplot), --quiet and --dry-run, their checks under the output
// policy before any work, and the dry-run stop.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "progress.hpp"
#include "hbf/output_file.hpp"
#include "hbf/table.hpp"

namespace hbf::cli {

struct OutputFlags {
    std::string out, summary, plot;
    bool quiet = false;
    bool dry_run = false;

    /// What the command writes; an empty help leaves that flag out (--out and --dry-run are
    /// always there).
    struct Help {
        std::string out = "write the CSV to FILE instead of standard output";
        std::string summary;                  ///< --summary FILE: the JSON summary
        std::string summary_type = "FILE";
        std::string plot;                     ///< --plot FILE.png|FILE.svg (gnuplot)
        std::string quiet;                    ///< --quiet: what it silences on standard error
    };
    /// Adds the group's flags to `command`.
    void add_to(CLI::App& command, const Help& help);
    /// The plot's format (io::check_plot): callable early, before the inputs are read.
    void check_plot() const;
    /// check_plot, then the output policy (io::check_outputs) on --out, --summary, --plot and
    /// the command's `extra` outputs, against the run's `inputs`: before any work.
    void check(const CLI::App& command, const std::vector<io::InputFile>& inputs = {},
               std::vector<io::OutputTarget> extra = {}) const;
    /// Progress and summary lines: not --quiet, and standard error is a terminal.
    bool verbose() const;
    /// The progress display: off with --quiet, a redrawn line on a terminal, else a line a
    /// minute (progress.hpp).
    ProgressLine::Mode progress() const;
    /// The end of a --dry-run, after its checks: says on standard error that every input and
    /// output is valid and nothing is computed or written; returns exit code 0.
    int dry_run_done(const std::string& command) const;
};

/// What a command writes: `intro` (ending with what introduces the columns), its columns, then
/// `outro` (the exit codes, what a failure leaves).
struct OutputHelp {
    std::string intro;
    std::vector<io::Column> columns;
    std::string outro;
};
/// Describes `command`'s output: its --help footer (intro, one line per column "  name:
/// meaning", outro), the flag --columns (prints the columns and exits 0) and the entry of
/// output_help() under the command's name, from which `hbf reference` documents it.
void describe_output(CLI::App& command, const OutputHelp& help);
/// Every described command's output, by command name.
const std::map<std::string, OutputHelp>& output_help();

}  // namespace hbf::cli
