// hbf command line — strict parsing of flag values and the shared absorber flags.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/continuation.hpp"
#include "hbf/frf.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/verdict.hpp"

namespace hbf::cli {

/// Prints the verdict's errors, warnings and notes on standard error, one line each ("hbf
/// <command>: error: ...", "...: warning: ...", "...: note: ...") after the outputs are
/// committed, and returns its exit code (verdict.hpp: Verdict::exit_code).
int finish(const std::string& command, const Verdict& verdict);

/// A flag value that cannot be used; the message names the flag.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Parses the whole text as a finite decimal number (hbf::parse_decimal: the Fortran D
/// exponent is accepted); throws UsageError naming `flag` for an empty value, a non-number,
/// trailing characters, NaN, infinity, overflow or underflow.
double parse_double(const std::string& flag, const std::string& text);
/// Parses the whole text as a decimal integer; throws UsageError like parse_double.
long long parse_integer(const std::string& flag, const std::string& text);

/// The paper absorber's parameter flags --r --wa --mu --fe --wb --xi (values kept as text so
/// that they are parsed strictly), shared by every subcommand that works on the preset.
struct AbsorberFlags {
    std::string r, wa, mu, fe;
    /// The laws' own preset parameters (model.hpp: preset_parameters) by flag ("--wb").
    std::map<std::string, std::string> law_values;
    std::string law;
    std::string excitation_harmonic;  ///< --excitation-harmonic (preset and --config alike)
    std::string force_scale;          ///< --force-scale (--config systems)

    /// Adds --excitation-harmonic h (the force F cos(h w t)), which applies to the preset and
    /// to --config systems alike (it overrides the file's structure.excitation_harmonic).
    void add_excitation_harmonic(CLI::App& command);
    /// Adds the flags; `laws_help` is the help of --law (empty: every law of the registry with
    /// its definition, laws_help()), `law_default` the default --law; `with_smooth_options` adds
    /// the preset parameters only harmonic balance reads (--eps, --mu-static,
    /// --stribeck-velocity, --viscous, --dlft-eps: the harmonic-balance commands).
    void add_to(CLI::App& command, const std::string& laws_help, const std::string& law_default,
                bool with_smooth_options);
    /// The system flags of the commands that compute (frf, loop, map, optimize, timeint): every
    /// law of the registry (default coulomb), every preset parameter, --excitation-harmonic and
    /// --force-scale (a factor on a --config file's excitation vector).
    void add_system_flags(CLI::App& command);
    /// "friction law: coulomb (...), dahl (...), ... or jenkins (...)", from the registry.
    static std::string laws_help();
    /// The chosen law; throws UsageError for an unknown name.
    FrictionLaw friction_law() const;
    /// Parameters with defaults for flags not given. Throws UsageError for a flag that does
    /// not apply to the chosen law (e.g. --wb for coulomb, --xi for coulomb and dahl).
    AbsorberParameters parameters(const CLI::App& command) const;
    /// The preset's parameter flags given on the command line (all but --law), e.g. to reject
    /// them where the system comes from a file.
    std::vector<std::string> given(const CLI::App& command) const;
};

/// The system a command works on: the paper's absorber from its flags, or any structure from
/// a --config file (the preset's parameter flags are then rejected; a given --law replaces
/// every contact's law).
struct ChosenSystem {
    System system;
    std::string law_name;             ///< the law, or the contacts' laws joined by ','
    std::vector<Output> outputs = {Output::dof(0), Output::dof(1)};  ///< reported (preset: y1, y2)
    std::optional<io::SystemConfig> config;
    AbsorberParameters absorber;      ///< the preset's parameters (without --config)
    std::optional<double> force_scale;  ///< --force-scale where given, applied to system.excitation
    /// The files the run reads (the config and its Matrix Market files): no output may be one.
    std::vector<io::InputFile> inputs() const { return config ? config->inputs : std::vector<io::InputFile>{}; }
};
ChosenSystem choose_system(const CLI::App& command, const AbsorberFlags& flags, const std::string& config_path);

/// A library default or bound as --help and messages show it: format_number without an
/// exponent's leading zeros ("1e-9", not "1e-09").
std::string default_text(double value);

/// The FRF's choices (frf.hpp: FrfChoices): the --config file's [frequency] and [solver]
/// (io::SystemConfig::choices), with --harmonics (H; 0 = automatic; odd, odd:H) and
/// --time-samples over them where given (texts as given). Throws UsageError naming the flag.
FrfChoices frf_choices(const CLI::App& command, const std::string& harmonics, const std::string& time_samples,
                       const ChosenSystem& chosen);
/// An integer flag that fits an int (its range is the library's: validate()); throws UsageError
/// naming `flag` otherwise.
int parse_int(const std::string& flag, const std::string& text);
/// Runs `check`, a library validate() (InvalidInput "<field> = <value> ..."). Where the field
/// was not given as its flag (--field, '_' as '-') but comes from the --config file (a key
/// <section>.<field>), the error is a UsageError naming the file, the line and the key, as the
/// file reader names its own errors; otherwise the InvalidInput goes on (hbf names the flag).
void check_naming_source(const std::function<void()>& check, const CLI::App& command, const ChosenSystem& chosen,
                         const std::string& config_path);
/// Harmonic-balance options of frf_choices with the exact polish as given (frf_settings: the
/// automatic H), checked (hbo.validate, the file's values named by check_naming_source).
HarmonicBalanceOptions harmonic_balance_options(const CLI::App& command, const std::string& harmonics,
                                                const std::string& time_samples, const ChosenSystem& chosen,
                                                const std::string& config_path, bool exact);

}  // namespace hbf::cli
