// hbfriction — contact law `dahl`: the Dahl bristle model (paper eq. 16).
//
// Definition: f = sigma0 z, z' = v - sigma0 |v| z / F_c (z the bristle deflection, the paper's
// y3; v = q'). LuGre without bristle damping, viscous friction and Stribeck curve (bristle.cpp
// evaluates both).
// Parameters: friction_limit F_c (> 0), stiffness sigma0 (> 0).
// While stuck (pre-sliding): the spring sigma0.
// Smooth (stick is pre-sliding: |sigma0 z| < stick_force_ratio F_c); its state in time is the
// bristle deflection; default H 10 (the peak within 6e-5 of H = 40).
#include "contact/bristle.hpp"
#include "hbf/absorber.hpp"

namespace hbf {

namespace {

class Dahl final : public detail::BristleLaw {
public:
    Dahl()
        : BristleLaw(FrictionLaw::dahl, "dahl",
              "Dahl: f = sigma0 z, z' = v - sigma0 |v| z / F_c") {}
    std::vector<LawParameter> parameters() const override {
        return {{"stiffness", &Contact::stiffness, "contact (bristle) stiffness sigma0", LawParameter::Range::positive}};
    }
    StuckElement stuck(const Contact& contact) const override { return {false, contact.stiffness, 0.0}; }
    /// sigma0 = r wb^2 (paper eqs. 18-19).
    std::vector<std::string> preset_parameters() const override { return {"wb"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.stiffness = p.contact_stiffness();
    }
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override {
        detail::bristle_static_force(contact, contact.friction_limit, q(0), out);
        return true;
    }

private:
    double sigma1(const Contact&) const override { return 0.0; }
    double sigma2(const Contact&) const override { return 0.0; }
};

}  // namespace

const ContactLaw& dahl_law() {
    static const Dahl law;
    return law;
}

}  // namespace hbf
