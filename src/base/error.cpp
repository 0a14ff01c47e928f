// hbfriction — InvalidInput and the range checks that name a parameter, its value and its
// allowed range; numbers formatted for messages (error.hpp).
#include "hbf/error.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace hbf {

std::string format_number(double value) {
    char buffer[64];
    const auto result =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 15);
    return std::string(buffer, result.ptr);
}

namespace {
bool digit(char c) { return c >= '0' && c <= '9'; }

std::string lower(std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}
}  // namespace

bool parse_decimal(const std::string& text, double& value, std::string& why) {
    // [+-] (digits [. digits*] | . digits) [(e|E|d|D) [+-] digits]
    std::string normal = text;
    std::size_t i = 0;
    const std::size_t n = text.size();
    if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
    std::size_t mantissa_digits = 0;
    while (i < n && digit(text[i])) ++i, ++mantissa_digits;
    if (i < n && text[i] == '.') {
        ++i;
        while (i < n && digit(text[i])) ++i, ++mantissa_digits;
    }
    bool good = mantissa_digits > 0;
    if (good && i < n && (text[i] == 'e' || text[i] == 'E' || text[i] == 'd' || text[i] == 'D')) {
        normal[i] = 'e';
        ++i;
        if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
        std::size_t exponent_digits = 0;
        while (i < n && digit(text[i])) ++i, ++exponent_digits;
        good = exponent_digits > 0;
    }
    if (!good || i != n) {
        const std::string word = lower(text);
        const std::string bare = word.empty() || word[0] == '+' || word[0] == '-' ? word.substr(word.empty() ? 0 : 1) : word;
        if (bare == "nan" || bare == "inf" || bare == "infinity")
            why = "is not finite: a finite number is required";
        else if (text.empty())
            why = "is empty: a number is required";
        else
            why = "is not a decimal number: allowed [+-]digits[.digits][(e|E|d|D)[+-]digits], e.g. 0.1, 1e-3, 1.0D-1 "
                  "(no spaces, decimal commas, hexadecimal or trailing characters)";
        return false;
    }
    errno = 0;
    value = std::strtod(normal.c_str(), nullptr);
    if (std::isinf(value)) {
        why = "is not finite (it overflows a double): a finite number is required";
        return false;
    }
    if (errno == ERANGE) {
        why = "underflows a double: use 0 or a larger magnitude";
        return false;
    }
    return true;
}

bool parse_whole_number(const std::string& text, long long& value, std::string& why) {
    std::size_t i = 0;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    const bool digits = i < text.size() && std::all_of(text.begin() + static_cast<std::ptrdiff_t>(i), text.end(), digit);
    if (!digits) {
        why = text.empty() ? "is empty: an integer is required" : "is not an integer: allowed [+-]digits";
        return false;
    }
    errno = 0;
    value = std::strtoll(text.c_str(), nullptr, 10);
    if (errno == ERANGE) {
        why = "is out of the range of integers";
        return false;
    }
    return true;
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
