// hbfriction — the paper's friction absorber preset (absorber.hpp): its parameter table and
// checks, the System it builds, and the conversions to and from physical units.
#include "hbf/absorber.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf {

const std::vector<PresetParameter>& preset_parameters() {
    using P = AbsorberParameters;
    static const std::vector<PresetParameter> table = {
        {"wb", "--wb", "wb", "contact_stiffness_ratio", &P::contact_stiffness_ratio,
         "contact stiffness ratio omega3/omega1",
         "contact stiffness ratio wb = sqrt(sigma0/m2)/omega1, > 0; jenkins: k_t = r wb^2", false, false, false},
        {"xi", "--xi", "xi", "contact_damping_ratio", &P::contact_damping_ratio, "contact damping ratio",
         "contact damping ratio xi = sigma1/(2 m2 sqrt(sigma0/m2)), >= 0", true, false, false},
        {"eps", "--eps", "eps", "regularization", &P::regularization, "regularisation velocity of tanh",
         "regularisation velocity of tanh, > 0", false, true, false},
        {"mu_s", "--mu-static", "mu_static", "static_friction_coefficient", &P::static_friction_coefficient,
         "static friction coefficient",
         "static friction coefficient mu_s of the Stribeck curve, >= 0; 0 means mu_s = mu", true, true, false},
        {"vs", "--stribeck-velocity", "stribeck_velocity", "stribeck_velocity", &P::stribeck_velocity,
         "Stribeck velocity",
         "Stribeck velocity v_s (nondimensional: x_s omega1), >= 0; 0 means no Stribeck curve", true, true, false},
        {"sigma2", "--viscous", "viscous", "viscous_coefficient", &P::viscous_coefficient,
         "viscous friction coefficient", "viscous friction coefficient sigma2 / (N / (x_s omega1)), >= 0", true, true, false},
        {"lagrangian_penalty", "--dlft-eps", "dlft_eps", "lagrangian_penalty", &P::lagrangian_penalty,
         "dynamic Lagrangian parameter",
         "dynamic Lagrangian parameter epsilon of exact Coulomb, force per velocity, allowed 1/30 to 4 times the "
         "automatic value (measured to converge; outside it the iteration stalls or follows spurious branches); "
         "within it the results converge to the same solution as H grows; 0 means automatic: sqrt(k m) of the "
         "contact direction, at most 30 times the structure's static impedance; 1.24 for the paper's absorber: "
         "allowed 0.0413..4.96",
         true, true, true},
    };
    return table;
}

void check_given_preset_parameters(FrictionLaw law, const AbsorberParameters& p,
                                   const std::vector<std::string>& keywords) {
    for (const std::string& keyword : keywords)
        for (const PresetParameter& q : preset_parameters()) {
            if (keyword != q.keyword) continue;
            if (!law_reads(law, q.symbol))
                throw InvalidInput(keyword + " does not apply to law " + to_string(law) + ": allowed with " +
                                   laws_reading(q.symbol) + " (" + q.meaning + ")");
            if (q.zero_only_by_default && !(p.*(q.field) > 0.0))
                throw InvalidInput(keyword + " (" + q.meaning + ") = " + format_number(p.*(q.field)) +
                                   " is out of range: allowed > 0 when given (0, the default, means automatic)");
        }
}

void AbsorberParameters::validate(FrictionLaw law) const {
    if (!contact_law(law).has_preset())
        throw InvalidInput("law = " + to_string(law) + " has no preset: the paper's absorber has no normal direction "
                           "(allowed: a system file, --config, with the contact's normal_direction)");
    require_positive(mass_ratio, "r", "mass ratio m2/m1");
    require_positive(tuning_ratio, "wa", "tuning ratio omega2/omega1");
    require_positive(friction_coefficient, "mu", "friction coefficient");
    require_positive(excitation, "fe", "excitation amplitude F0/N");
    // the law's own (contact_law.hpp), in the order it lists them
    for (const std::string& symbol : contact_law(law).preset_parameters())
        for (const PresetParameter& p : preset_parameters()) {
            if (symbol != p.symbol) continue;
            if (p.zero_allowed)
                require_non_negative(this->*(p.field), p.symbol, p.meaning);
            else
                require_positive(this->*(p.field), p.symbol, p.meaning);
        }
    // Nondimensional ratios, of order 0.01..10 in the paper: bounded to 1e-12..1e12, so that
    // products like r wa^2 stay finite and resolvable next to 1 (r = 1e300 overflowed into a
    // non-finite matrix, reported as such; the linear-limit tests use mu = 1e9).
    const std::pair<const char*, double> ratios[] = {
        {"r (mass ratio m2/m1)", mass_ratio},
        {"wa (tuning ratio omega2/omega1)", tuning_ratio},
        {"mu (friction coefficient)", friction_coefficient},
        {"fe (excitation amplitude F0/N)", excitation},
        {"wb (contact stiffness ratio omega3/omega1)", contact_stiffness_ratio},
        {"xi (contact damping ratio)", contact_damping_ratio},
        {"eps (regularisation velocity of tanh)", regularization},
        {"mu_s (static friction coefficient)", static_friction_coefficient},
        {"vs (Stribeck velocity)", stribeck_velocity},
        {"sigma2 (viscous friction coefficient)", viscous_coefficient}};
    for (const auto& [name, value] : ratios)
        if (value > 1e12 || (value > 0.0 && value < 1e-12))
            throw InvalidInput(std::string(name) + " = " + format_number(value) +
                               " is out of range: allowed 1e-12..1e12 (a nondimensional ratio; products of "
                               "two such must stay finite and resolvable next to 1)");
}

System friction_absorber(const AbsorberParameters& p, FrictionLaw law) {
    p.validate(law);
    const double r = p.mass_ratio;
    const double ka = r * p.tuning_ratio * p.tuning_ratio;  // r wa^2: absorber spring
    System system;
    Eigen::Matrix2d stiffness;
    stiffness << 1.0 + ka, -ka, -ka, ka;
    system.mass = sparse(Eigen::Vector2d(1.0, r).asDiagonal());
    system.damping = SparseMatrix(2, 2);
    system.stiffness = sparse(stiffness);
    system.excitation = Eigen::Vector2d(p.excitation, 0.0);
    Contact contact;
    contact.dof = 0;
    contact.other_dof = 1;
    contact.law = law;
    contact.friction_limit = p.friction_coefficient;
    contact_law(law).from_preset(p, contact);
    system.contacts.push_back(contact);
    return system;
}

void PhysicalAbsorber::validate() const {
    require_positive(m1, "m1", "main mass");
    require_positive(k1, "k1", "main stiffness");
    require_positive(m2, "m2", "absorber mass");
    require_positive(k2, "k2", "absorber stiffness");
    require_positive(normal_force, "N", "normal load");
    require_positive(force_amplitude, "F0", "excitation force amplitude");
    require_positive(friction_coefficient, "mu", "friction coefficient");
    require_non_negative(sigma0, "sigma0", "contact stiffness");
    require_non_negative(sigma1, "sigma1", "contact damping");
    if (sigma0 == 0.0 && sigma1 != 0.0)
        throw InvalidInput("sigma1 (contact damping) = " + format_number(sigma1) +
                           " needs a contact stiffness: allowed sigma1 = 0 when sigma0 = 0");
}

Scales scales_of(const PhysicalAbsorber& physical) {
    physical.validate();
    Scales s;
    s.frequency = std::sqrt(physical.k1 / physical.m1);
    s.time = 1.0 / s.frequency;
    s.displacement = physical.normal_force / physical.k1;
    s.force = physical.normal_force;
    return s;
}

AbsorberParameters to_nondimensional(const PhysicalAbsorber& physical) {
    const Scales s = scales_of(physical);  // validates
    AbsorberParameters p;
    p.mass_ratio = physical.m2 / physical.m1;
    p.tuning_ratio = std::sqrt(physical.k2 / physical.m2) / s.frequency;
    p.friction_coefficient = physical.friction_coefficient;
    p.excitation = physical.force_amplitude / physical.normal_force;
    const double omega3 = std::sqrt(physical.sigma0 / physical.m2);
    p.contact_stiffness_ratio = omega3 / s.frequency;
    p.contact_damping_ratio = omega3 > 0.0 ? physical.sigma1 / (2.0 * physical.m2 * omega3) : 0.0;
    return p;
}

PhysicalAbsorber to_physical(const AbsorberParameters& p, double m1, double k1, double normal_force) {
    require_positive(m1, "m1", "main mass");
    require_positive(k1, "k1", "main stiffness");
    require_positive(normal_force, "N", "normal load");
    p.validate(FrictionLaw::coulomb);
    require_non_negative(p.contact_stiffness_ratio, "wb", "contact stiffness ratio");
    require_non_negative(p.contact_damping_ratio, "xi", "contact damping ratio");
    const double omega1 = std::sqrt(k1 / m1);
    PhysicalAbsorber a;
    a.m1 = m1;
    a.k1 = k1;
    a.normal_force = normal_force;
    a.m2 = p.mass_ratio * m1;
    a.k2 = a.m2 * std::pow(p.tuning_ratio * omega1, 2);  // omega2^2 m2
    a.force_amplitude = p.excitation * normal_force;
    a.friction_coefficient = p.friction_coefficient;
    const double omega3 = p.contact_stiffness_ratio * omega1;
    a.sigma0 = a.m2 * omega3 * omega3;
    a.sigma1 = 2.0 * p.contact_damping_ratio * a.m2 * omega3;
    return a;
}

}  // namespace hbf
