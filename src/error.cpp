#include "hbf/error.hpp"

#include <charconv>
#include <cmath>

namespace hbf {

std::string format_number(double value) {
    char buffer[64];
    const auto result =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 15);
    return std::string(buffer, result.ptr);
}

namespace {
[[noreturn]] void out_of_range(double value, const char* name, const char* meaning,
                               const char* allowed) {
    throw InvalidInput(std::string(name) + " (" + meaning + ") = " + format_number(value) +
                       " is out of range: allowed " + allowed);
}
}  // namespace

void require_finite(double value, const char* name, const char* meaning) {
    if (!std::isfinite(value)) out_of_range(value, name, meaning, "a finite number");
}

void require_positive(double value, const char* name, const char* meaning) {
    if (!(std::isfinite(value) && value > 0.0)) out_of_range(value, name, meaning, "finite and > 0");
}

void require_non_negative(double value, const char* name, const char* meaning) {
    if (!(std::isfinite(value) && value >= 0.0))
        out_of_range(value, name, meaning, "finite and >= 0");
}

}  // namespace hbf
