// hbfriction — the seed paper's friction absorber as a preset: its nondimensional parameters,
// the table of the law-specific ones (which the front ends' flags and keywords come from), the
// System it builds, and its physical units.
//
// Below the contact laws (src/README.md): each law maps the preset's parameters onto its own in
// its file (contact_law.hpp: ContactLaw::from_preset), so that a law is added in one file.
#pragma once

#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

// ---------------------------------------------------------------------------------------
// The paper's friction absorber (2 DOF), in the paper's nondimensional variables (eq. 2):
//   time tau = omega1 t, displacements y = x / x_s with x_s = N / k1, forces in units of N.
//   (Jenkins: k_t = r wb^2, the same tangential stiffness as Dahl's sigma0.)
//
//   y1'' + (1 + r wa^2) y1 - r wa^2 y2 + f = fe cos(omega tau)
//   r y2'' - r wa^2 (y1 - y2)          - f = 0          (paper eq. 2, second row times r)
//
// so M = diag(1, r), K = [[1 + r wa^2, -r wa^2], [-r wa^2, r wa^2]], C = 0, F = (fe, 0),
// and one contact between DOF 1 and DOF 2 (q = y1 - y2) with F_c = mu. For Dahl and LuGre
// the contact stiffness and damping are sigma0 = r wb^2 and sigma1 = 2 xi r wb (paper
// eqs. 18-19 / B.4: f = r wb^2 y3 + 2 xi r wb y3').
// ---------------------------------------------------------------------------------------
struct AbsorberParameters {
    double mass_ratio = 0.1;               ///< r  = m2 / m1
    double tuning_ratio = 1.0;             ///< wa = omega2 / omega1, omega2 = sqrt(k2/m2)
    double friction_coefficient = 0.2;     ///< mu = mu_c (the slip force is mu N)
    double excitation = 0.5;               ///< fe = F0 / N
    double contact_stiffness_ratio = 0.4;  ///< wb = omega3 / omega1, omega3 = sqrt(sigma0/m2)
    double contact_damping_ratio = 0.01;   ///< xi = sigma1 / (2 m2 omega3)
    double regularization = 0.05;          ///< eps, velocity of the tanh (coulomb-reg)
    double static_friction_coefficient = 0;  ///< mu_s (LuGre Stribeck; 0 means mu_s = mu)
    double stribeck_velocity = 0;          ///< v_s, nondimensional (LuGre; 0 means none)
    double viscous_coefficient = 0;        ///< sigma2 / (m1 omega1) (LuGre viscous term)
    double lagrangian_penalty = 0;         ///< dynamic Lagrangian eps (coulomb in HB; 0 = automatic)

    /// The contact's stiffness sigma0 = k_t = r wb^2 and damping sigma1 = 2 xi r wb, in units of
    /// k1 and sqrt(k1 m1) (paper eqs. 18-19 / B.4: f = r wb^2 y3 + 2 xi r wb y3').
    double contact_stiffness() const { return mass_ratio * contact_stiffness_ratio * contact_stiffness_ratio; }
    double contact_damping() const { return 2.0 * contact_damping_ratio * mass_ratio * contact_stiffness_ratio; }

    /// Throws InvalidInput naming the first parameter out of range: r, wa, mu, fe > 0;
    /// for Dahl, LuGre and Jenkins also wb > 0; for LuGre xi >= 0 (wb, xi are unused by Coulomb).
    void validate(FrictionLaw law) const;
};

/// The paper's absorber as a System (see the block comment above): the contact's friction_limit
/// is mu, its law's own parameters come from the law's preset parameters (contact_law.hpp:
/// ContactLaw::from_preset).
System friction_absorber(const AbsorberParameters& parameters, FrictionLaw law);

/// A law-specific parameter of the absorber preset (beyond r, wa, mu, fe, which every law has):
/// its symbol (in messages), the `hbf` flag, the Python keyword of absorber(), the field of
/// AbsorberParameters with its C++ name, what it is and its range. Each law lists the symbols it
/// reads (contact_law.hpp: ContactLaw::preset_parameters); the front ends' flags, their help and
/// which law each applies to come from this table and those lists.
struct PresetParameter {
    const char* symbol;      ///< "wb"
    const char* flag;        ///< "--wb"
    const char* keyword;     ///< "wb" (Python: absorber(wb=...))
    const char* field_name;  ///< "contact_stiffness_ratio"
    double AbsorberParameters::*field;
    const char* meaning;     ///< "contact stiffness ratio omega3/omega1"
    const char* help;        ///< the flag's help: definition, range and what 0 means
    bool zero_allowed;       ///< >= 0 (else > 0)
    /// Only harmonic balance reads it (not the closed forms of `hbf analytic`).
    bool harmonic_balance_only;
    /// 0 is only the default (automatic): a value given explicitly must be > 0.
    bool zero_only_by_default;
};
/// The preset's law-specific parameters: wb, xi, eps, mu_s, vs, sigma2, lagrangian_penalty.
const std::vector<PresetParameter>& preset_parameters();
/// The checks on preset parameters a front end was given explicitly (named by their
/// PresetParameter::keyword; the paper's r, wa, mu, fe are always read), for `law`, before
/// AbsorberParameters::validate: one the law does not read ("xi does not apply to law
/// coulomb: allowed with lugre (contact damping ratio)"), and an explicit 0 where 0 is only
/// the automatic default. Throws InvalidInput whose message starts with the keyword; hbf and
/// Python both call it, so that they refuse the same inputs with the same words.
void check_given_preset_parameters(FrictionLaw law, const AbsorberParameters& p,
                                   const std::vector<std::string>& keywords);

/// Physical parameters of the absorber (any consistent unit system, e.g. SI).
struct PhysicalAbsorber {
    double m1 = 0;                    ///< main mass
    double k1 = 0;                    ///< main stiffness
    double m2 = 0;                    ///< absorber mass
    double k2 = 0;                    ///< absorber stiffness
    double normal_force = 0;          ///< N, normal load in the contact
    double force_amplitude = 0;       ///< F0, amplitude of F0 cos(Omega t) on m1
    double friction_coefficient = 0;  ///< mu_c (dimensionless)
    double sigma0 = 0;                ///< contact stiffness (Dahl, LuGre)
    double sigma1 = 0;                ///< contact damping (LuGre)

    void validate() const;
};

/// Scales between physical and nondimensional quantities:
/// t = tau * time, Omega = omega * frequency, x = y * displacement, F_nl = f_nl * force.
struct Scales {
    double frequency = 1;     ///< omega1 = sqrt(k1 / m1)    [rad / time]
    double time = 1;          ///< 1 / omega1                [time]
    double displacement = 1;  ///< x_s = N / k1              [length]
    double force = 1;         ///< N                         [force]
};

/// Paper section 2 and Appendix B: r = m2/m1, wa = sqrt(k2/m2)/omega1, fe = F0/N,
/// wb = sqrt(sigma0/m2)/omega1, xi = sigma1 / (2 m2 sqrt(sigma0/m2)); mu unchanged.
/// sigma0 = 0 is allowed (Coulomb only); then wb = 0 and xi = 0.
AbsorberParameters to_nondimensional(const PhysicalAbsorber& physical);
Scales scales_of(const PhysicalAbsorber& physical);
/// Inverse of to_nondimensional, given the three reference quantities m1, k1 and N.
PhysicalAbsorber to_physical(const AbsorberParameters& parameters, double m1, double k1,
                             double normal_force);

}  // namespace hbf
