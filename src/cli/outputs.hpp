// hbf command line — the output flags every command shares, as one group: --out (the CSV),
// --summary (JSON), --plot (gnuplot), --quiet and --dry-run, their checks under the output
// policy before any work, and the dry-run stop.
#pragma once

#include <CLI/CLI.hpp>
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

/// A command's --help footer: `intro` (ending with what introduces the columns), one line per
/// column ("  name: meaning"), then `outro` (the exit codes, what a failure leaves).
std::string columns_footer(const std::string& intro, const std::vector<io::Column>& columns, const std::string& outro);

}  // namespace hbf::cli
