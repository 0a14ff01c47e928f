// hbfriction — the registry of contact laws (contact_law.hpp): one line a law, the lookups by
// name and parameter. A new law is its
// file in this folder, the accessor it defines declared below, and its line in the table.
#include "hbf/contact_law.hpp"

#include <algorithm>
#include <cmath>

#include "hbf/error.hpp"
#include "hbf/cyclic.hpp"

#include <stdexcept>

namespace hbf {

const ContactLaw& coulomb_law();
const ContactLaw& dahl_law();
const ContactLaw& lugre_law();
const ContactLaw& coulomb_regularized_law();
const ContactLaw& jenkins_law();
const ContactLaw& iwan_law();
const ContactLaw& elastic_law();
const ContactLaw& unilateral_law();
const ContactLaw& polynomial_law();
const ContactLaw& gap_law();
const ContactLaw& damper_law();

const std::vector<const ContactLaw*>& contact_laws() {
    static const std::vector<const ContactLaw*> laws = {
        &coulomb_law(),
        &dahl_law(),
        &lugre_law(),
        &coulomb_regularized_law(),
        &jenkins_law(),
        &iwan_law(),
        &elastic_law(),
        &unilateral_law(),
        &polynomial_law(),
        &gap_law(),
        &damper_law(),
    };
    static const bool unique = [] {
        for (std::size_t a = 0; a < laws.size(); ++a)
            for (std::size_t b = a + 1; b < laws.size(); ++b)
                if (laws[a]->id() == laws[b]->id() || std::string(laws[a]->name()) == laws[b]->name())
                    throw std::logic_error(std::string("the contact laws ") + laws[a]->name() + " and " +
                                           laws[b]->name() + " share an id or a name");
        return true;
    }();
    (void)unique;
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

double LawParameter::get(const Contact& contact) const {
    if (field) return contact.*field;
    const auto at = contact.values.find(key);
    return at == contact.values.end() ? default_value : at->second;
}

void LawParameter::set(Contact& contact, double value) const {
    if (field)
        contact.*field = value;
    else
        contact.values[key] = value;
}

bool LawParameter::allows(double value) const {
    if (!std::isfinite(value)) return false;
    if (kind == Kind::integer && value != std::floor(value)) return false;
    switch (range) {
        case Range::positive: return value > 0.0;
        case Range::non_negative: return value >= 0.0;
        case Range::finite: return true;
        case Range::interval:
            return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
    }
    return false;
}

std::string LawParameter::allowed() const {
    if (range == Range::finite) return kind == Kind::integer ? "an integer" : "finite";
    if (range != Range::interval) {
        const std::string bound = range == Range::positive ? "> 0" : ">= 0";
        return kind == Kind::integer ? "an integer " + bound : "finite and " + bound;
    }
    if (kind == Kind::integer) return "an integer in " + format_number(low) + ".." + format_number(high);
    return std::string("in ") + (low_open ? "(" : "[") + format_number(low) + ", " + format_number(high) +
           (high_open ? ")" : "]");
}

bool rigid_slider(const Contact& element) {
    const ContactLaw& law = contact_law(element.law);
    return law.exact_stick() && law.stuck(element).rigid;
}

bool elastic_slider(const Contact& element) {
    const ContactLaw& law = contact_law(element.law);
    if (!law.exact_stick() || law.stuck(element).rigid || law.time_state() != TimeState::slider) return false;
    const std::vector<Contact> elements = law.time_elements(element);  // not split into several
    return elements.size() == 1 && elements.front().law == element.law;
}

LocalLinearization ContactLaw::linearize(const Contact&, double, double, double) const {
    std::string smooth;
    for (const ContactLaw* l : contact_laws())
        if (l->smooth()) smooth += (smooth.empty() ? "" : ", ") + std::string(l->name());
    throw InvalidInput("law = " + std::string(name()) + " has no local linearisation: allowed " + smooth +
                       " (smooth laws)");
}

void ContactLaw::guess_state(const Contact&, bool, const Eigen::VectorXd&, int, const Eigen::VectorXcd&,
                             const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd>) const {}

bool ContactLaw::static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const {
    if (!exact_stick() || time_state() != TimeState::slider || q.size() != 1) return false;
    // Monotonic loading from s = 0: each slider's spring k q until k |q| reaches its slip force.
    double force = 0.0, slope = 0.0;
    bool stuck = true;
    for (const Contact& e : time_elements(contact)) {
        if (!elastic_slider(e)) return false;
        const double trial = e.stiffness * q(0);
        if (std::abs(trial) <= e.friction_limit) {
            force += trial;
            slope += e.stiffness;
        } else {
            force += std::copysign(e.friction_limit, trial);
            stuck = false;
        }
    }
    out.force = Eigen::VectorXd::Constant(1, force);
    out.jacobian = Eigen::MatrixXd::Constant(1, 1, slope);
    out.state = stuck ? "stuck" : "slipping";
    return true;
}

void BoundLaw::forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& f, Eigen::MatrixXd* f_q,
                      Eigen::MatrixXd* f_v) const {
    double rate = 0.0;
    f.resize(1);
    f(0) = force(q(0), v(0), 0.0, rate);
    if (!f_q && !f_v) return;
    const LocalLinearization l = linearize(q(0), v(0), 0.0);
    if (f_q) *f_q = Eigen::MatrixXd::Constant(1, 1, l.f_q);
    if (f_v) *f_v = Eigen::MatrixXd::Constant(1, 1, l.f_v);
}

void ContactLaw::complete(Contact&, const std::vector<DirectionScale>&, const std::string&) const {}

void ContactLaw::validate(const Contact& contact, const std::string& where) const {
    for (const LawParameter& p : parameters()) {
        if (!p.scalar()) continue;  // the law's own validate (directions: also System::validate)
        const double value = p.get(contact);
        if (!p.allows(value))
            throw InvalidInput(where + p.key + " (" + p.meaning + ") = " + format_number(value) +
                               " is out of range: allowed " + p.allowed());
    }
}

namespace {

/// ContactLaw::bind's default: the law's own functions at a copy of the contact.
class ForwardingLaw final : public BoundLaw {
public:
    ForwardingLaw(const ContactLaw& law, const Contact& contact) : law_(law), contact_(contact) {}
    double force(double q, double v, double z, double& rate) const override {
        return law_.time_force(contact_, q, v, z, rate);
    }
    double margin(double q, double v, double z) const override { return law_.time_margin(contact_, q, v, z); }
    LocalLinearization linearize(double q, double v, double z) const override {
        return law_.linearize(contact_, q, v, z);
    }

private:
    const ContactLaw& law_;
    Contact contact_;
};

}  // namespace

std::unique_ptr<BoundLaw> ContactLaw::bind(const Contact& contact) const {
    return std::make_unique<ForwardingLaw>(*this, contact);
}

double ContactLaw::time_force(const Contact&, double, double, double, double&) const {
    throw InvalidInput("law = " + std::string(name()) + " has no smooth time-domain force (its stick is exact: it "
                       "is integrated by the modes of its elements)");
}

double ContactLaw::time_margin(const Contact&, double, double, double) const {
    throw InvalidInput("law = " + std::string(name()) + " has no smooth stick margin (its stick is exact)");
}

// ---- the time domain's elements -----------------------------------------------------------

bool splits_contacts(const System& system) {
    for (const Contact& c : system.contacts) {
        const std::vector<Contact> elements = contact_law(c.law).time_elements(c);
        if (elements.size() != 1 || elements.front().law != c.law) return true;  // not the contact itself
    }
    return false;
}

int time_domain_elements(const System& system) {
    std::size_t count = 0;
    for (const Contact& c : system.contacts) count += contact_law(c.law).time_elements(c).size();
    return static_cast<int>(count);
}

std::vector<ContactRegime> contact_regimes(const System& system, const std::vector<ContactRegime>& elements) {
    std::vector<ContactRegime> out;
    std::size_t e = 0;
    for (const Contact& c : system.contacts) {
        const std::size_t count = contact_law(c.law).time_elements(c).size();
        if (e + count > elements.size())
            throw std::logic_error("contact_regimes: fewer element regimes than time-domain elements");
        ContactRegime r = elements[e];
        for (std::size_t k = 1; k < count; ++k) {
            const ContactRegime& o = elements[e + k];
            r.stick_fraction = std::min(r.stick_fraction, o.stick_fraction);
            if (o.regime == "slip" || (o.regime == "stick-slip" && r.regime == "stick")) r.regime = o.regime;
        }
        out.push_back(std::move(r));
        e += count;
    }
    return out;
}

System time_domain_system(const System& system) {
    System lowered = system;
    lowered.contacts.clear();
    for (const Contact& c : system.contacts)
        for (const Contact& e : contact_law(c.law).time_elements(c)) {
            const ContactLaw& law = contact_law(e.law);
            if (law.exact_stick() ? !rigid_slider(e) && !elastic_slider(e) : law.time_elements(e).size() != 1)
                throw InvalidInput("law = " + std::string(contact_law(c.law).name()) +
                                   ": its time-domain elements must be smooth laws, rigid or elastic sliders");
            lowered.contacts.push_back(e);
        }
    return lowered;
}

void mark_force_elements(const System& system, std::vector<ContactRegime>& contacts, std::string& regime,
                         double& stick_fraction) {
    bool found = false;
    for (std::size_t c = 0; c < system.contacts.size() && c < contacts.size(); ++c) {
        if (!contact_law(system.contacts[c].law).friction()) {
            contacts[c].regime = "none";
            contacts[c].stick_fraction = 0.0;
        } else if (!found) {
            found = true;
            regime = contacts[c].regime;
            stick_fraction = contacts[c].stick_fraction;
        }
    }
    if (!found) {
        regime = "none";
        stick_fraction = 0.0;
    }
}

bool without_friction(const System& system) {
    return std::none_of(system.contacts.begin(), system.contacts.end(),
                        [](const Contact& c) { return contact_law(c.law).friction(); });
}

void refuse_time_domain(const System& system, const std::string& what) {
    refuse_cyclic(system, what);
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const ContactLaw& law = contact_law(system.contacts[c].law);
        if (law.time_domain()) continue;
        std::string covered;
        for (const ContactLaw* l : contact_laws())
            if (l->time_domain()) covered += (covered.empty() ? "" : ", ") + std::string(l->name());
        throw InvalidInput("contact " + std::to_string(c + 1) + ": law = " + law.name() + " is outside " + what +
                           " (harmonic balance and time integration take it): allowed " + covered);
    }
}

TimeDomainView::TimeDomainView(const System& system) : original_(system), split_(false) {
    refuse_cyclic(system, "time integration and the exact solver");
    refuse_time_domain(system, "the event-exact solver and the time-domain elements of the general integrator");
    if (system.has_static_load())
        throw InvalidInput("static load: the event-exact solver and the general time integrator do not carry one "
                           "(harmonic balance does, and the time integration of laws elastic and unilateral): allowed no static_load");
    split_ = splits_contacts(system);
    if (split_) lowered_ = time_domain_system(system);
}

// ---- contact_force.hpp's entry points ----------------------------------------------------------

}  // namespace hbf
