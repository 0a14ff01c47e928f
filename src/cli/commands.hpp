// hbf command line — the subcommands. Each registers its flags on the app and returns a
// runner that is called after parsing if the subcommand was chosen.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace hbf::cli {

using Runner = std::function<int()>;

Runner add_analytic_command(CLI::App& app);
Runner add_frf_command(CLI::App& app);
Runner add_loop_command(CLI::App& app);
Runner add_map_command(CLI::App& app);
Runner add_optimize_command(CLI::App& app);
Runner add_timeint_command(CLI::App& app);

/// The whole command line: parses argv, runs the chosen command, returns the exit code
/// (hbf/verdict.hpp: ExitCode). main() calls it after setting up the process.
int run_program(int argc, char** argv);

}  // namespace hbf::cli
