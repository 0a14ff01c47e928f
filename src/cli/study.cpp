// hbf command line — the parameter of a design study (study.hpp): the system value it changes
// and its grids of values.
#include "study.hpp"

#include <algorithm>
#include <cmath>

#include "hbf/contact_law.hpp"
#include "frf_flags.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"

namespace hbf::cli {

namespace {
/// The --param names of the absorber preset: the laws' preset parameters wb and xi with the laws
/// that read them (contact_law.hpp).
std::string preset_names() {
    return "fe, mu, wa, r, wb (" + laws_reading("wb") + "), xi (" + laws_reading("xi") + ")";
}
/// The --param names of a --config system: the contact's keys come from the registry of laws
/// (contact_law.hpp), each with the laws it applies to.
std::string config_names() {
    std::string keys = "contact.friction_limit";
    std::vector<std::string> seen;
    for (const ContactLaw* law : contact_laws())
        for (const LawParameter& p : law->parameters()) {
            if (std::find(seen.begin(), seen.end(), p.key) != seen.end()) continue;
            seen.emplace_back(p.key);
            keys += ", contact." + std::string(p.key) + " (" + laws_with_parameter(p.key) + ")";
        }
    return "mu (the friction limit F_c of the contact --contact), fe (a factor on the file's excitation vector), "
           "structure.damping (a factor on the file's damping matrix C), cyclic.engine_order (a sector's engine "
           "order, integers: hbf map), or a key of the contact --contact: " +
           keys;
}

/// A contact's scalar key of a --config file: friction_limit (every law) or a law's parameter;
/// `field` is null when the name is none of them.
struct ContactKey {
    std::string name;
    bool found = false;
    LawParameter parameter{"friction_limit", &Contact::friction_limit, "slip force mu N", LawParameter::Range::positive};
};
ContactKey find_contact_key(const std::string& name) {
    if (name == "mu") return {"friction_limit", true};
    if (name.rfind("contact.", 0) != 0) return {};
    const std::string key = name.substr(8);
    if (key == "friction_limit") return {key, true};
    for (const ContactLaw* law : contact_laws())
        for (const LawParameter& p : law->parameters())
            if (key == p.key && p.scalar())
                return {key, true, p};
    return {};
}
/// "> 0", ">= 0", or the parameter's interval.
std::string bound(const LawParameter& p) {
    using R = LawParameter::Range;
    if (p.kind == LawParameter::Kind::number && p.range != R::interval) return p.range == R::positive ? "> 0" : ">= 0";
    return p.allowed();
}
/// Whether `key` applies to `law` (friction_limit to every law that has it).
bool applies(const ContactKey& key, FrictionLaw law) {
    if (key.name == "friction_limit") return contact_law(law).has_friction_limit();
    const std::vector<LawParameter> p = contact_law(law).parameters();
    return std::any_of(p.begin(), p.end(), [&](const LawParameter& q) { return key.name == q.key; });
}
}  // namespace

StudyParameter::StudyParameter(const std::string& flag, const std::string& name, const ChosenSystem& chosen,
                               const std::string& contact_flag, const std::string& contact)
    : name_(name), chosen_(chosen) {
    if (name.empty()) throw UsageError(flag + " is empty: allowed " + preset_names());
    if (chosen.config) {
        if (name == "cyclic.engine_order") {
            if (!chosen.system.cyclic.active())
                throw UsageError(flag + " = cyclic.engine_order: the system is not a sector (allowed with a [cyclic] table)");
            current_ = chosen.system.cyclic.engine_order;
            integer_ = true;
            return;
        }
        const ContactKey key = find_contact_key(name);
        if (!key.found && name != "fe" && name != "structure.damping")
            throw UsageError(flag + " = '" + name + "' is not a parameter of a --config system: allowed " +
                             config_names());
        if (!key.found) {
            current_ = 1.0;
            return;
        }
        const long long n = parse_integer(contact_flag, contact);
        const auto contacts = static_cast<long long>(chosen.system.contacts.size());
        if (n < 1 || n > contacts)
            throw UsageError(contact_flag + " = " + contact + " is out of range: allowed 1.." + std::to_string(contacts) +
                             (contacts == 0 ? " (the system has no contact)" : ""));
        contact_ = static_cast<int>(n - 1);
        uses_contact_ = true;
        const Contact& c = chosen.system.contacts[static_cast<std::size_t>(contact_)];
        if (!applies(key, c.law))
            throw UsageError(flag + " = " + name + " does not apply to contact " + std::to_string(n) + " (law " +
                             to_string(c.law) + "): allowed " + config_names());
        current_ = key.parameter.get(c);
        return;
    }
    law_ = chosen.system.contacts.front().law;
    const AbsorberParameters& p = chosen.absorber;
    if (name == "fe") current_ = p.excitation;
    else if (name == "mu") current_ = p.friction_coefficient;
    else if (name == "wa") current_ = p.tuning_ratio;
    else if (name == "r") current_ = p.mass_ratio;
    else if (name == "wb" && law_reads(law_, "wb")) current_ = p.contact_stiffness_ratio;
    else if (name == "xi" && law_reads(law_, "xi")) current_ = p.contact_damping_ratio;
    else if (name == "wb" || name == "xi")
        throw UsageError(flag + " = " + name + " does not apply to --law " + to_string(law_) + ": allowed " +
                         preset_names());
    else
        throw UsageError(flag + " = '" + name + "' is not known: allowed " + preset_names());
}

void StudyParameter::check_flags(const CLI::App& command, const std::string& values) const {
    if (given(command, "--contact") && preset())
        throw UsageError("--contact chooses a contact of a --config system: the preset has one");
    if (given(command, "--contact") && !preset() && !uses_contact())
        throw UsageError("--contact chooses the contact of --param mu or contact.KEY: --param " + name_ +
                         " belongs to the structure");
    if (preset() && command.get_option_no_throw("--" + name_) != nullptr && given(command, ("--" + name_).c_str()))
        throw UsageError("--" + name_ + " is set by --param " + name_ + " (" + values + "): drop it");
}

AbsorberParameters with_parameter(AbsorberParameters p, const std::string& name, double value) {
    if (name == "fe") p.excitation = value;
    else if (name == "mu") p.friction_coefficient = value;
    else if (name == "wa") p.tuning_ratio = value;
    else if (name == "r") p.mass_ratio = value;
    else if (name == "wb") p.contact_stiffness_ratio = value;
    else p.contact_damping_ratio = value;
    return p;
}

StudyParameter StudyParameter::with_tuning(double wa) const {
    StudyParameter copy = *this;
    copy.chosen_.absorber.tuning_ratio = wa;
    return copy;
}

std::string StudyParameter::meaning() const {
    if (chosen_.config) {
        const std::string contact = " of contact " + std::to_string(contact_ + 1);
        if (name_ == "mu") return "friction limit F_c" + contact + " (the file's force units)";
        if (name_ == "fe") return "factor on the file's excitation vector (1: as in the file)";
        if (name_ == "structure.damping") return "factor on the file's damping matrix C (1: as in the file)";
        if (name_ == "cyclic.engine_order")
            return "engine order of the travelling-wave excitation (an integer 0.." +
                   std::to_string(chosen_.system.cyclic.sectors - 1) + " on " +
                   std::to_string(chosen_.system.cyclic.sectors) + " sectors)";
        return "the key " + name_.substr(8) + contact + " (the file's units)";
    }
    if (name_ == "fe") return "excitation amplitude F0/N (nondimensional)";
    if (name_ == "mu") return "friction coefficient";
    if (name_ == "wa") return "tuning ratio omega2/omega1";
    if (name_ == "r") return "mass ratio m2/m1";
    if (name_ == "wb") return "contact stiffness ratio omega3/omega1";
    return "contact damping ratio";
}

System StudyParameter::system(double value) const {
    if (chosen_.config) {
        System s = chosen_.system;
        if (const ContactKey key = find_contact_key(name_); key.found) {
            if (!key.parameter.allows(value))
                throw InvalidInput(name_ + " (" + meaning() + ") = " + format_number(value) +
                                   " is out of range: allowed " + bound(key.parameter));
            key.parameter.set(s.contacts[static_cast<std::size_t>(contact_)], value);
        } else if (name_ == "cyclic.engine_order") {
            const double n = s.cyclic.sectors, rounded = std::round(value);
            if (!(std::abs(value - rounded) <= 1e-9 * std::max(1.0, n) && rounded >= 0.0 && rounded <= n - 1.0))
                throw InvalidInput("cyclic.engine_order = " + format_number(value) + " is out of range: allowed an integer 0.." +
                                   std::to_string(s.cyclic.sectors - 1));
            s.cyclic.engine_order = static_cast<int>(rounded);
        } else if (name_ == "fe") {
            if (!(std::isfinite(value) && value > 0.0))
                throw InvalidInput("fe (factor on the excitation) = " + format_number(value) + " is out of range: allowed > 0");
            s.excitation *= value;
        } else {
            if (!(std::isfinite(value) && value >= 0.0))
                throw InvalidInput("structure.damping (factor on C) = " + format_number(value) +
                                   " is out of range: allowed >= 0");
            s.damping *= value;
        }
        s.validate();
        return s;
    }
    System s = friction_absorber(with_parameter(chosen_.absorber, name_, value), law_);
    s.excitation_harmonic = chosen_.system.excitation_harmonic;
    return s;
}

std::vector<double> parse_values(const std::string& flag, const std::string& text) {
    if (text.empty()) throw UsageError(flag + " is empty: allowed V1,V2,..., START:STOP:N or log:START:STOP:N");
    const bool log = text.rfind("log:", 0) == 0;
    const std::string body = log ? text.substr(4) : text;
    std::vector<double> values;
    if (log || body.find(':') != std::string::npos) {
        const std::size_t c1 = body.find(':'), c2 = body.find(':', c1 + 1);
        if (c1 == std::string::npos || c2 == std::string::npos || body.find(':', c2 + 1) != std::string::npos)
            throw UsageError(flag + " = '" + text + "' is not a grid: allowed START:STOP:N or log:START:STOP:N");
        const double a = parse_double(flag, body.substr(0, c1)), b = parse_double(flag, body.substr(c1 + 1, c2 - c1 - 1));
        const int n = parse_count(flag, body.substr(c2 + 1), 1, 100000);
        if (n > 1 && a == b) throw UsageError(flag + " = '" + text + "': START equals STOP with N > 1");
        if (log && !(a > 0.0 && b > 0.0))
            throw UsageError(flag + " = '" + text + "' is out of range: a log grid needs START, STOP > 0");
        for (int k = 0; k < n; ++k) {
            const double t = n == 1 ? 0.0 : static_cast<double>(k) / (n - 1);
            values.push_back(log ? std::exp(std::log(a) + t * (std::log(b) - std::log(a))) : a + t * (b - a));
        }
        values.back() = n == 1 ? a : b;  // exact ends
        return values;
    }
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        values.push_back(parse_double(flag, text.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (values.size() > 100000) throw UsageError(flag + ": more than 100000 values");
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return values;
}

int parse_count(const std::string& flag, const std::string& text, long long lo, long long hi) {
    const long long n = parse_integer(flag, text);
    if (n < lo || n > hi)
        throw UsageError(flag + " = " + text + " is out of range: allowed " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(n);
}

}  // namespace hbf::cli
