// hbf command line — the output flags every command shares (outputs.hpp) and their checks under
// the output policy before any work.
#include "outputs.hpp"

#include <unistd.h>

#include <iostream>

#include "hbf/plot.hpp"

namespace hbf::cli {

void OutputFlags::add_to(CLI::App& command, const Help& help) {
    command.add_flag("--dry-run", dry_run,
                     "check every flag, input and output, then stop before computing: exit 0 when the run would start\ncheck every flag, input file and output path as for a run, then stop before the computation: "
                     "exit 0 and nothing written when the run would start (2 and the reason otherwise)")
        ->disable_flag_override();  // --dry-run=0 must not turn it off (found by the fuzz harness)
    command.add_option("--out", out, help.out)->option_text("FILE");
    if (!help.summary.empty()) command.add_option("--summary", summary, help.summary)->option_text(help.summary_type);
    if (!help.plot.empty()) command.add_option("--plot", plot, help.plot)->option_text("FILE.png|FILE.svg");
    if (!help.quiet.empty()) command.add_flag("--quiet", quiet, help.quiet);
}

void OutputFlags::check_plot() const { io::check_plot("--plot", plot); }

void OutputFlags::check(const CLI::App& command, const std::vector<io::InputFile>& inputs,
                        std::vector<io::OutputTarget> extra) const {
    check_plot();
    auto given = [&command](const char* flag) {
        return command.get_option_no_throw(flag) != nullptr && command.count(flag) > 0;
    };
    std::vector<io::OutputTarget> targets = {{"--out", out, given("--out"), true},
                                             {"--summary", summary, given("--summary")},
                                             {"--plot", plot, given("--plot"), false, true}};
    targets.insert(targets.end(), extra.begin(), extra.end());
    io::check_outputs(targets, inputs);
}

bool OutputFlags::verbose() const { return !quiet && isatty(STDERR_FILENO); }

ProgressLine::Mode OutputFlags::progress() const {
    if (quiet) return ProgressLine::Mode::off;
    return isatty(STDERR_FILENO) ? ProgressLine::Mode::terminal : ProgressLine::Mode::log;
}

namespace {
std::map<std::string, OutputHelp>& described() {
    static std::map<std::string, OutputHelp> help;
    return help;
}
}  // namespace

void describe_output(CLI::App& command, const OutputHelp& help) {
    std::string text = help.intro + "\n";
    for (const auto& c : help.columns) text += "  " + c.name + ": " + c.meaning + "\n";
    command.footer(text + help.outro);
    described()[command.get_name()] = help;
    const std::vector<io::Column> columns = help.columns;
    command
        .add_flag_callback(
            "--columns",
            [columns]() {
                for (const auto& c : columns) std::cout << c.name << ": " << c.meaning << "\n";
                throw CLI::Success();
            },
            "list the output columns with their meaning, then exit")
        ->trigger_on_parse();
}

const std::map<std::string, OutputHelp>& output_help() { return described(); }

int OutputFlags::dry_run_done(const std::string& command) const {
    std::cerr << "hbf " << command << ": dry run: every input and output is valid; nothing computed, nothing written\n";
    return 0;
}

}  // namespace hbf::cli
