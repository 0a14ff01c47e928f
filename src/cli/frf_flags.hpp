// hbf command line — the flags of one FRF (frequency range, harmonic balance, continuation,
// exact polish, --config), shared by frf, map and optimize.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "arguments.hpp"
#include "hbf/frf.hpp"

namespace hbf::cli {

/// The defaults shown and parsed are the library's (ContinuationOptions, CorrectorOptions); 0
/// for H, N_t and modes means automatic (H, N_t) or the direct solve (modes), as in the library.
struct FrfFlags {
    std::string wmin = default_text(ContinuationOptions{}.omega_start), wmax = default_text(ContinuationOptions{}.omega_end),
                harmonics = "0", time_samples = "0", max_amplitude = default_text(ContinuationOptions{}.max_amplitude),
                max_step = default_text(ContinuationOptions{}.max_step),
                tolerance = default_text(CorrectorOptions{}.tolerance), formulation = "automatic", modes = "0",
                error_points = std::to_string(FrfSettings{}.error_points), error_limit = default_text(FrfSettings{}.error_limit),
                start_harmonics = "0";
    std::string jacobian;  ///< --jacobian (empty: the --config file's, else automatic)
    std::string exact, config, stability = "off";

    /// Adds --wmin --wmax --harmonics --modes --formulation --time-samples --max-amplitude
    /// --max-step --tolerance --config --exact --stability --error-points --error-limit
    /// --start-harmonics.
    void add_to(CLI::App& command);
    /// The settings of one FRF of the chosen system, every flag checked (UsageError names it);
    /// a --config file's range and [solver] apply where the flags are not given. With the exact
    /// polish, the automatic H is 10 and harmonic balance does not locate transitions. `made`:
    /// the command's own choices of the peaks (FrfChoices::peaks, peaks_of_every_output; the
    /// latter unset: the first output's peaks only, a design study's objective).
    FrfSettings settings(const CLI::App& command, ChosenSystem& chosen, const FrfChoices& made = {}) const;
};

/// --harmonics and --time-samples into `harmonics` and `time_samples` (hbf frf's and hbf loop's
/// help); `automatic` says what the automatic H is, before the laws' own counts.
void add_discretisation_flags(CLI::App& command, std::string& harmonics, std::string& time_samples,
                              const std::string& automatic);

/// A comma-separated list of frequencies > 0 (--at); throws UsageError naming `flag`.
std::vector<double> parse_frequencies(const std::string& flag, const std::string& text);

/// Whether a flag was given on the command line.
bool given(const CLI::App& command, const char* flag);

}  // namespace hbf::cli
