// hbfriction — contact law `lugre`: the LuGre bristle model (paper eq. 17).
//
// Definition: f = sigma0 z + sigma1 z' + sigma2 v, z' = v - sigma0 |v| z / g(v),
// g(v) = F_c + (F_s - F_c) exp(-(v / v_s)^2) (contact_law.hpp: sliding_limit; the paper has
// v_s = 0, F_s = F_c, sigma2 = 0, so g = F_c).
// Parameters: friction_limit F_c (> 0), stiffness sigma0 (> 0), damping sigma1 (>= 0), viscous
// sigma2 (>= 0), static_limit F_s (>= 0; 0 means F_s = F_c), stribeck_velocity v_s (>= 0; 0
// means no Stribeck curve).
// While stuck (pre-sliding): the spring sigma0 and the damper sigma1 + sigma2.
// Smooth (stick is pre-sliding: |sigma0 z| < stick_force_ratio g(v)); its state in time is the
// bristle deflection; default H 10.
#include "contact/bristle.hpp"
#include "hbf/absorber.hpp"

namespace hbf {

namespace {

class LuGre final : public detail::BristleLaw {
public:
    LuGre()
        : BristleLaw(FrictionLaw::lugre, "lugre",
              "LuGre: f = sigma0 z + sigma1 z' + sigma2 v, z' = v - sigma0 |v| z / g(v), "
              "g(v) = F_c + (F_s - F_c) exp(-(v / v_s)^2)") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        return {{"stiffness", &Contact::stiffness, "contact (bristle) stiffness sigma0", R::positive},
                {"damping", &Contact::damping, "contact (bristle) damping sigma1", R::non_negative},
                {"viscous", &Contact::viscous, "viscous friction sigma2", R::non_negative},
                {"static_limit", &Contact::static_limit, "static friction force F_s", R::non_negative, "F_s = F_c"},
                {"stribeck_velocity", &Contact::stribeck_velocity, "Stribeck velocity v_s", R::non_negative,
                 "no Stribeck curve"}};
    }
    StuckElement stuck(const Contact& contact) const override {
        return {false, contact.stiffness, contact.damping + contact.viscous};
    }
    /// sigma0 = r wb^2, sigma1 = 2 xi r wb (paper eqs. 18-19 / B.4: f = r wb^2 y3 + 2 xi r wb y3');
    /// sigma2, F_s = mu_s and v_s as given (in units of N, x_s omega1).
    std::vector<std::string> preset_parameters() const override { return {"wb", "xi", "mu_s", "vs", "sigma2"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.stiffness = p.contact_stiffness();
        contact.damping = p.contact_damping();
        contact.viscous = p.viscous_coefficient;
        contact.static_limit = p.static_friction_coefficient;
        contact.stribeck_velocity = p.stribeck_velocity;
    }
    /// At a vanishing velocity the bristle's limit is g(0): F_s with a Stribeck curve, else F_c.
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override {
        const double g0 = contact.stribeck_velocity > 0.0 && contact.static_limit > 0.0 ? contact.static_limit
                                                                                         : contact.friction_limit;
        detail::bristle_static_force(contact, g0, q(0), out);
        return true;
    }

private:
    double sigma1(const Contact& contact) const override { return contact.damping; }
    double sigma2(const Contact& contact) const override { return contact.viscous; }
};

}  // namespace

const ContactLaw& lugre_law() {
    static const LuGre law;
    return law;
}

}  // namespace hbf
