// hbf — the command line as a function (main.cpp calls it; the fuzz target too).

#include <algorithm>
#include <iostream>
#include <map>
#include <string>

#include "arguments.hpp"
#include "commands.hpp"
#include "hbf/diagnostics.hpp"
#include "hbf/error.hpp"
#include "hbf/version.hpp"

namespace hbf::cli {

namespace {

/// --help shows each flag's summary: its description's first line. The lines after it are the
/// details, which the command-line reference gives (hbf reference).
class BriefFormatter : public CLI::Formatter {
public:
    std::string make_option_desc(const CLI::Option* option) const override {
        const std::string& text = option->get_description();
        return text.substr(0, text.find('\n'));
    }
};

}  // namespace

int run_program(int argc, char** argv) {
    CLI::App app("hbf: periodic responses of vibrating structures with friction and contact (harmonic "
                 "balance, an event-exact solver, stability, nonlinear modes, parameter studies, time integration).",
                 "hbf");
    app.set_version_flag("--version", std::string("hbf ") + hbf::version());
    app.formatter(std::make_shared<BriefFormatter>());
    app.require_subcommand(1);
    app.footer(R"(Exit codes: 0 success; 2 bad input (an invalid flag or value, or an output path that cannot be used,
found before any work: the message names it, no output file is written); 1 failure (a solver that
did not converge or stalled, a failed exact polish, an --at frequency without a solution, a write
that fails: what was computed is written and stderr says where and why); 3 written but incomplete or
doubtful (a capped, truncated or partial branch, an unlocated transition, a point failing the energy
balance, warnings of the numerical libraries: each a warning line on stderr and in the JSON
summary). A note on stderr (e.g. a peak not refined, flagged in the JSON) leaves the exit code as it
is.
Outputs: '-' is standard output; a regular file (or a symlink to one, which stays a symlink) is
replaced atomically when the command succeeds; a character device or FIFO (e.g. /dev/null) is
written in place, never replaced; no two outputs may name the same file.
Run 'hbf <command> --help' for a command's flags and output columns; the details of every flag are
in the documentation's command-line reference (docs/reference/cli.md; 'hbf reference' as JSON).)");

    std::map<std::string, Runner> runners;
    runners["analytic"] = add_analytic_command(app);
    runners["frf"] = add_frf_command(app);
    runners["loop"] = add_loop_command(app);
    runners["map"] = add_map_command(app);
    runners["modes"] = add_modes_command(app);
    runners["nodal-diameters"] = add_nodal_diameters_command(app);
    runners["optimize"] = add_optimize_command(app);
    runners["timeint"] = add_timeint_command(app);
    runners["track"] = add_track_command(app);
    runners["reference"] = add_reference_command(app);

    const std::string program = "hbf";
    if (argc > 1 && argv[1][0] != '-' && runners.count(argv[1]) == 0) {
        std::string known;
        for (const auto& entry : runners) known += (known.empty() ? "" : ", ") + entry.first;
        std::cerr << program << ": error: unknown command '" << argv[1] << "': allowed " << known << "\n"
                  << "Run 'hbf --help' for usage.\n";
        return exit_bad_input;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::Success&) {  // --columns: printed
        return 0;
    } catch (const CLI::ParseError& e) {
        std::string what = e.what();
        if (what.find("disallowed flag override") != std::string::npos)  // --dry-run=0: a flag takes no value
            what = "--" + what.substr(0, what.find(' ')) + " takes no value: give it alone (--" +
                   what.substr(0, what.find(' ')) + "=VALUE is not allowed; omit the flag to run)";
        std::cerr << program << ": error: " << what << "\n"
                  << "Run 'hbf --help' or 'hbf <command> --help' for usage.\n";
        return exit_bad_input;
    }

    std::string name;
    for (const CLI::App* sub : app.get_subcommands()) name = sub->get_name();
    try {
        return runners.at(name)();
    } catch (const UsageError& e) {
        std::cerr << program << " " << name << ": error: " << e.what() << "\n";
        return exit_bad_input;
    } catch (const hbf::InvalidInput& e) {
        // The library names its own parameter (wmin, harmonics, ...): where the user gave it as
        // a flag, name the flag as well.
        const std::string what = e.what();
        const std::string word = what.substr(0, what.find_first_of(" :("));
        std::string flag = "--" + word;  // the field's flag: its name with '-' for '_'
        std::replace(flag.begin(), flag.end(), '_', '-');
        const CLI::App* sub = app.get_subcommands().empty() ? nullptr : app.get_subcommands().front();
        const std::string next = what.substr(word.size(), 2);  // "<field> = ", "<field>: ", "<field> (..."
        const bool named = (next == " =" || next == ": " || next == " (") && sub != nullptr &&
                           sub->get_option_no_throw(flag) != nullptr && sub->count(flag) > 0;
        std::cerr << program << " " << name << ": error: " << (named ? flag + ": " : "") << what << "\n";
        return exit_bad_input;
    } catch (const std::exception& e) {
        std::cerr << program << " " << name << ": error: " << e.what() << "\n";
        return exit_failure;
    }
}

}  // namespace hbf::cli
