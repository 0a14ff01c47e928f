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

class Dahl final : public ContactLaw {
public:
    FrictionLaw id() const override { return FrictionLaw::dahl; }
    const char* name() const override { return "dahl"; }
    const char* definition() const override { return "Dahl: f = sigma0 z, z' = v - sigma0 |v| z / F_c"; }
    std::vector<LawParameter> parameters() const override {
        return {{"stiffness", &Contact::stiffness, "contact (bristle) stiffness sigma0", LawParameter::Range::positive}};
    }
    int default_harmonics() const override { return 10; }
    bool smooth() const override { return true; }
    bool exact_stick() const override { return false; }
    TimeState time_state() const override { return TimeState::bristle; }
    StuckElement stuck(const Contact& contact) const override { return {false, contact.stiffness, 0.0}; }
    /// sigma0 = r wb^2 (paper eqs. 18-19).
    std::vector<std::string> preset_parameters() const override { return {"wb"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.stiffness = p.contact_stiffness();
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return detail::bristle_model(contact, 0.0, 0.0);
    }
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override {
        detail::bristle_static_force(contact, contact.friction_limit, q(0), out);
        return true;
    }
    LocalLinearization linearize(const Contact& contact, double v, double z) const override {
        return detail::bristle_linearization(contact, 0.0, 0.0, v, z);
    }
    double time_force(const Contact& contact, double v, double z, double& rate) const override {
        return detail::bristle_time_force(contact, 0.0, 0.0, v, z, rate);
    }
    double time_margin(const Contact& contact, double v, double z) const override {
        return detail::bristle_time_margin(contact, v, z);
    }
    void guess_state(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                     const Eigen::VectorXcd&, const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd> z) const override {
        detail::bristle_guess(contact, sliding, q, cos_row, z);
    }
};

}  // namespace

const ContactLaw& dahl_law() {
    static const Dahl law;
    return law;
}

}  // namespace hbf
