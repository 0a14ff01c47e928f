#include "study.hpp"

#include <algorithm>
#include <cmath>

#include "hbf/error.hpp"

namespace hbf::cli {

namespace {
const char* preset_names = "fe, mu, wa, r, wb (dahl, lugre, jenkins), xi (lugre)";
const char* config_names =
    "mu (the friction limit F_c of the contact --contact), fe (a factor on the file's excitation vector), "
    "structure.damping (a factor on the file's damping matrix C), or a key of the contact --contact: "
    "contact.friction_limit, contact.stiffness (dahl, lugre, jenkins), contact.damping, contact.viscous, "
    "contact.static_limit, contact.stribeck_velocity (lugre), contact.regularization (coulomb-reg), "
    "contact.lagrangian_penalty (coulomb)";

/// The contact's scalar keys of a --config file (config.hpp), the laws each applies to, whether
/// 0 is allowed, and the field.
struct ContactKey {
    const char* name;
    std::vector<FrictionLaw> laws;  ///< empty: every law
    bool zero_allowed;
    double Contact::*field;
};
const std::vector<ContactKey>& contact_keys() {
    using L = FrictionLaw;
    static const std::vector<ContactKey> keys = {
        {"friction_limit", {}, false, &Contact::friction_limit},
        {"stiffness", {L::dahl, L::lugre, L::jenkins}, false, &Contact::stiffness},
        {"damping", {L::lugre}, true, &Contact::damping},
        {"viscous", {L::lugre}, true, &Contact::viscous},
        {"static_limit", {L::lugre}, true, &Contact::static_limit},
        {"stribeck_velocity", {L::lugre}, true, &Contact::stribeck_velocity},
        {"regularization", {L::coulomb_regularized}, false, &Contact::regularization},
        {"lagrangian_penalty", {L::coulomb}, true, &Contact::lagrangian_penalty}};
    return keys;
}
const ContactKey* find_contact_key(const std::string& name) {
    if (name == "mu") return &contact_keys().front();
    if (name.rfind("contact.", 0) != 0) return nullptr;
    for (const ContactKey& k : contact_keys())
        if (name.substr(8) == k.name) return &k;
    return nullptr;
}
}  // namespace

StudyParameter::StudyParameter(const std::string& flag, const std::string& name, const ChosenSystem& chosen,
                               const std::string& contact_flag, const std::string& contact)
    : name_(name), chosen_(chosen) {
    if (name.empty()) throw UsageError(flag + " is empty: allowed " + std::string(preset_names));
    if (chosen.config) {
        const ContactKey* key = find_contact_key(name);
        if (!key && name != "fe" && name != "structure.damping")
            throw UsageError(flag + " = '" + name + "' is not a parameter of a --config system: allowed " +
                             std::string(config_names));
        if (!key) {
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
        if (!key->laws.empty() && std::find(key->laws.begin(), key->laws.end(), c.law) == key->laws.end())
            throw UsageError(flag + " = " + name + " does not apply to contact " + std::to_string(n) + " (law " +
                             to_string(c.law) + "): allowed " + std::string(config_names));
        current_ = c.*(key->field);
        return;
    }
    law_ = chosen.system.contacts.front().law;
    const AbsorberParameters& p = chosen.absorber;
    const bool bristles = law_ == FrictionLaw::dahl || law_ == FrictionLaw::lugre || law_ == FrictionLaw::jenkins;
    if (name == "fe") current_ = p.excitation;
    else if (name == "mu") current_ = p.friction_coefficient;
    else if (name == "wa") current_ = p.tuning_ratio;
    else if (name == "r") current_ = p.mass_ratio;
    else if (name == "wb" && bristles) current_ = p.contact_stiffness_ratio;
    else if (name == "xi" && law_ == FrictionLaw::lugre) current_ = p.contact_damping_ratio;
    else if (name == "wb" || name == "xi")
        throw UsageError(flag + " = " + name + " does not apply to --law " + to_string(law_) + ": allowed " +
                         std::string(preset_names));
    else
        throw UsageError(flag + " = '" + name + "' is not known: allowed " + std::string(preset_names));
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
        if (const ContactKey* key = find_contact_key(name_)) {
            if (!(std::isfinite(value) && (value > 0.0 || (key->zero_allowed && value == 0.0))))
                throw InvalidInput(name_ + " (" + meaning() + ") = " + format_number(value) +
                                   " is out of range: allowed " + (key->zero_allowed ? ">= 0" : "> 0"));
            s.contacts[static_cast<std::size_t>(contact_)].*(key->field) = value;
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
