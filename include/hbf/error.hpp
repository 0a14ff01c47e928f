// hbfriction — error types shared by every layer.
#pragma once

#include <stdexcept>
#include <string>

namespace hbf {

/// Thrown by the library when a caller passes a value outside its allowed range.
/// The message names the parameter, the offending value and the allowed range, e.g.
/// "r (mass ratio) = -1 is out of range: allowed 0 < r < inf".
/// Non-convergence of a solver is never an exception: it is a status in the result.
class InvalidInput : public std::invalid_argument {
public:
    explicit InvalidInput(const std::string& message) : std::invalid_argument(message) {}
};

/// Helpers that throw InvalidInput with a uniform message. `name` is the short (paper)
/// symbol, `meaning` a few words saying what it is.
void require_positive(double value, const char* name, const char* meaning);
void require_non_negative(double value, const char* name, const char* meaning);
void require_finite(double value, const char* name, const char* meaning);

/// Parses the whole of `text` as a finite decimal number: an optional sign, digits with an
/// optional decimal point (at least one digit), and an optional exponent introduced by e, E or,
/// as Fortran and the finite-element codes print it, d or D (1.0D-1 = 0.1). Nothing else is a
/// number: no space, no decimal comma, no hexadecimal, no trailing characters, no nan or inf.
/// Returns false with `why` saying what is wrong ("is not a decimal number ...", "is not
/// finite", "overflows a double", "underflows a double") for the caller to put after the
/// field's name.
bool parse_decimal(const std::string& text, double& value, std::string& why);
/// Parses the whole of `text` as a decimal integer (optional sign, digits only); false with
/// `why` as parse_decimal.
bool parse_whole_number(const std::string& text, long long& value, std::string& why);

/// Formats a double with 15 significant digits (trailing zeros dropped), e.g. 1.2, 0.0172413793103448.
std::string format_number(double value);

}  // namespace hbf
