// hbfriction — internal to the library: the names of an enum's values, one table per enum, for
// its to_string and its parse (the pattern of Ceres' types.cc). One policy for a value or a name
// outside the table: InvalidInput naming what was given and the allowed set.
#pragma once

#include <cstddef>
#include <string>

#include "hbf/error.hpp"

namespace hbf::detail {

/// One value of an enum and its name (in files, flags, CSV cells and messages).
template <class Enum>
struct EnumName {
    Enum value;
    const char* name;
};

/// The names of a table joined by ", " (for "allowed ..." in messages).
template <class Enum, std::size_t N>
std::string enum_names(const EnumName<Enum> (&table)[N]) {
    std::string out;
    for (const EnumName<Enum>& e : table) out += (out.empty() ? "" : ", ") + std::string(e.name);
    return out;
}

/// The name of `value`. A value outside the table (a cast integer) is an InvalidInput naming
/// `what`, the value and the allowed names.
template <class Enum, std::size_t N>
std::string enum_name(const EnumName<Enum> (&table)[N], Enum value, const char* what) {
    for (const EnumName<Enum>& e : table)
        if (e.value == value) return e.name;
    throw InvalidInput(std::string(what) + " = " + std::to_string(static_cast<long long>(value)) +
                       " is not a known value: allowed " + enum_names(table));
}

/// The value named `name`. An unknown name is an InvalidInput "<what> = '<name>' is not known:
/// allowed <names>".
template <class Enum, std::size_t N>
Enum parse_enum(const EnumName<Enum> (&table)[N], const std::string& name, const std::string& what) {
    for (const EnumName<Enum>& e : table)
        if (name == e.name) return e.value;
    throw InvalidInput(what + " = '" + name + "' is not known: allowed " + enum_names(table));
}

}  // namespace hbf::detail
