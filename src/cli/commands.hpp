// hbf command line — the subcommands. Each registers its flags on the app and returns a
// runner that is called after parsing if the subcommand was chosen.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

namespace hbf::cli {

using Runner = std::function<int()>;

/// Registers a command: the subcommand `name` (with `description`), an options object that
/// lives as long as the runner, `add_flags` on both, and a runner that calls `run` with them.
template <class Options>
Runner register_command(CLI::App& app, const char* name, const std::string& description,
                        void (*add_flags)(CLI::App&, Options&), int (*run)(const CLI::App&, const Options&)) {
    auto options = std::make_shared<Options>();
    CLI::App* command = app.add_subcommand(name, description);
    add_flags(*command, *options);
    return [command, options, run]() { return run(*command, *options); };
}

Runner add_analytic_command(CLI::App& app);
Runner add_frf_command(CLI::App& app);
Runner add_loop_command(CLI::App& app);
Runner add_map_command(CLI::App& app);
Runner add_modes_command(CLI::App& app);
Runner add_nodal_diameters_command(CLI::App& app);
Runner add_optimize_command(CLI::App& app);
Runner add_timeint_command(CLI::App& app);
Runner add_track_command(CLI::App& app);
/// `hbf reference`: the whole command line (every command added before it), the laws and the
/// system-file keys as JSON.
Runner add_reference_command(CLI::App& app);

/// The whole command line: parses argv, runs the chosen command, returns the exit code
/// (hbf/verdict.hpp: ExitCode). main() calls it after setting up the process.
int run_program(int argc, char** argv);

}  // namespace hbf::cli
