// hbf command line — strict parsing of flag values and the shared absorber flags.
#pragma once

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf::cli {

/// Exit codes of every `hbf` command (documented in `hbf --help`).
enum ExitCode : int { exit_success = 0, exit_failure = 1, exit_bad_input = 2 };

/// A flag value that cannot be used; the message names the flag.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Parses the whole text as a finite double; throws UsageError naming `flag` for an empty
/// value, a non-number, trailing characters, NaN, infinity, overflow or underflow.
double parse_double(const std::string& flag, const std::string& text);
/// Parses the whole text as a decimal integer; throws UsageError like parse_double.
long long parse_integer(const std::string& flag, const std::string& text);

/// The paper absorber's parameter flags --r --wa --mu --fe --wb --xi (values kept as text so
/// that they are parsed strictly), shared by every subcommand that works on the preset.
struct AbsorberFlags {
    std::string r, wa, mu, fe, wb, xi, eps, mu_static, stribeck_velocity, viscous, dlft_eps;
    std::string law;

    /// Adds the flags; `law_default` is the default --law, `with_smooth_options` adds --eps,
    /// --mu-static, --stribeck-velocity, --viscous and --dlft-eps (harmonic-balance commands).
    void add_to(CLI::App& command, const std::string& laws_help, const std::string& law_default,
                bool with_smooth_options);
    /// The chosen law; throws UsageError for an unknown name.
    FrictionLaw friction_law() const;
    /// Parameters with defaults for flags not given. Throws UsageError for a flag that does
    /// not apply to the chosen law (e.g. --wb for coulomb, --xi for coulomb and dahl).
    AbsorberParameters parameters(const CLI::App& command) const;
    /// The preset's parameter flags given on the command line (all but --law), e.g. to reject
    /// them where the system comes from a file.
    std::vector<std::string> given(const CLI::App& command) const;
};

}  // namespace hbf::cli
