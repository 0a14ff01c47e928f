// hbfriction — the registry of contact laws: one line a law (contact.hpp). A new law is its
// file in this folder, the accessor it defines declared below, and its line in the table.
#include <algorithm>

#include "hbf/contact.hpp"
#include "hbf/error.hpp"

namespace hbf {

const ContactLaw& coulomb_law();
const ContactLaw& dahl_law();
const ContactLaw& lugre_law();
const ContactLaw& coulomb_regularized_law();
const ContactLaw& jenkins_law();

const std::vector<const ContactLaw*>& contact_laws() {
    static const std::vector<const ContactLaw*> laws = {
        &coulomb_law(),
        &dahl_law(),
        &lugre_law(),
        &coulomb_regularized_law(),
        &jenkins_law(),
    };
    return laws;
}

// ---- lookups ------------------------------------------------------------------------------

const ContactLaw& contact_law(FrictionLaw law) {
    for (const ContactLaw* l : contact_laws())
        if (l->id() == law) return *l;
    throw InvalidInput("law = " + std::to_string(static_cast<int>(law)) + " is not in the registry of contact laws");
}

std::string to_string(FrictionLaw law) { return contact_law(law).name(); }

FrictionLaw parse_friction_law(const std::string& name) {
    for (const ContactLaw* l : contact_laws())
        if (name == l->name()) return l->id();
    throw InvalidInput("law = '" + name + "' is not a known friction law: allowed " + contact_law_names());
}

std::string contact_law_names(const std::string& separator) {
    std::string names;
    for (const ContactLaw* l : contact_laws()) names += (names.empty() ? "" : separator) + l->name();
    return names;
}

std::string laws_with_parameter(const std::string& key) {
    std::string names;
    for (const ContactLaw* l : contact_laws()) {
        const std::vector<LawParameter> p = l->parameters();
        if (std::any_of(p.begin(), p.end(), [&](const LawParameter& q) { return key == q.key; }))
            names += (names.empty() ? "" : ", ") + std::string(l->name());
    }
    return names;
}

std::string laws_reading(const std::string& symbol) {
    std::string names;
    for (const ContactLaw* law : contact_laws())
        if (law_reads(law->id(), symbol)) names += (names.empty() ? "" : ", ") + std::string(law->name());
    return names;
}

bool law_reads(FrictionLaw law, const std::string& symbol) {
    const std::vector<std::string> read = contact_law(law).preset_parameters();
    return std::find(read.begin(), read.end(), symbol) != read.end();
}

// ---- the defaults of the interface --------------------------------------------------------

std::string LawParameter::allowed() const { return range == Range::positive ? "finite and > 0" : "finite and >= 0"; }

LocalLinearization ContactLaw::linearize(const Contact&, double, double) const {
    std::string smooth;
    for (const ContactLaw* l : contact_laws())
        if (l->smooth()) smooth += (smooth.empty() ? "" : ", ") + std::string(l->name());
    throw InvalidInput("law = " + std::string(name()) + " has no local linearisation: allowed " + smooth +
                       " (smooth laws)");
}

void ContactLaw::guess_state(const Contact&, bool, const Eigen::VectorXd&, int, std::complex<double>,
                             Eigen::Ref<Eigen::VectorXd>) const {}

void ContactLaw::complete(Contact&, const DirectionScale&, const std::string&) const {}

void ContactLaw::validate(const Contact& contact, const std::string& where) const {
    for (const LawParameter& p : parameters()) {
        const std::string name = where + p.key;
        const std::string meaning = std::string(p.meaning);
        if (p.range == LawParameter::Range::positive)
            require_positive(contact.*(p.field), name.c_str(), meaning.c_str());
        else
            require_non_negative(contact.*(p.field), name.c_str(), meaning.c_str());
    }
}

// ---- friction.hpp's entry points ----------------------------------------------------------

std::unique_ptr<FrictionModel> make_friction_model(const Contact& contact) {
    return contact_law(contact.law).periodic_model(contact);
}

LocalLinearization linearize(const Contact& contact, double v, double z) {
    return contact_law(contact.law).linearize(contact, v, z);
}

}  // namespace hbf
