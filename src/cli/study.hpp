// hbf command line — the parameter of a design study (hbf map, hbf optimize): which value of
// the system it changes, and the grids of values.
#pragma once

#include <string>
#include <vector>

#include "arguments.hpp"
#include "hbf/absorber.hpp"

namespace hbf::cli {

/// One parameter of the chosen system, set to any value by system(). For the paper's
/// absorber: fe, mu, wa, r, wb (dahl, lugre, jenkins), xi (lugre). With --config: mu, the
/// friction limit F_c of one contact, or fe, a factor on the file's excitation vector.
class StudyParameter {
public:
    /// `flag` names the option that chose the parameter (for messages); `contact` is the
    /// --contact text (1-based; --config only). Throws UsageError for a parameter that does not
    /// apply to the system.
    StudyParameter(const std::string& flag, const std::string& name, const ChosenSystem& chosen,
                   const std::string& contact_flag, const std::string& contact);
    const std::string& name() const { return name_; }
    /// What the parameter is, with its units (for --help-like texts and JSON).
    std::string meaning() const;
    /// The value in the chosen system (the flag's or the file's).
    double current() const { return current_; }
    /// The system with the parameter set to `value`; throws InvalidInput for a value out of
    /// range (the message names the parameter).
    System system(double value) const;
    bool preset() const { return !chosen_.config.has_value(); }
    /// Whether the parameter belongs to the contact --contact (mu, contact.KEY of --config).
    bool uses_contact() const { return uses_contact_; }
    /// Whether it takes integer values only (cyclic.engine_order): a grid's (hbf map), not a
    /// continuous study's (hbf track, hbf optimize).
    bool integer() const { return integer_; }
    /// The same parameter on the preset with its tuning ratio set to wa (the joint search of
    /// hbf optimize --param mu,wa). Preset only.
    StudyParameter with_tuning(double wa) const;
    const ChosenSystem& chosen() const { return chosen_; }
    /// The checks of a study's --contact and of a preset flag the study sets itself (UsageError):
    /// --contact needs a --config parameter of a contact (mu, contact.KEY); the preset's flag of
    /// the parameter (e.g. --mu with --param mu) is set by `values` (e.g. "the map's values").
    void check_flags(const CLI::App& command, const std::string& values) const;

private:
    std::string name_;
    ChosenSystem chosen_;
    FrictionLaw law_ = FrictionLaw::coulomb;
    int contact_ = 0;
    bool uses_contact_ = false;
    bool integer_ = false;
    double current_ = 0;
};

/// The preset's parameters with the one named (fe, mu, wa, r, wb or xi; anything else: xi)
/// set to `value`, unvalidated.
AbsorberParameters with_parameter(AbsorberParameters p, const std::string& name, double value);

/// Values of a study: "V1,V2,...", "START:STOP:N" (N values, evenly spaced) or
/// "log:START:STOP:N" (N values, evenly spaced in log; START, STOP > 0). 1..100000 values,
/// finite. Throws UsageError naming `flag`.
std::vector<double> parse_values(const std::string& flag, const std::string& text);

/// Parses a positive integer flag in lo..hi (UsageError naming the flag otherwise).
int parse_count(const std::string& flag, const std::string& text, long long lo, long long hi);

}  // namespace hbf::cli
