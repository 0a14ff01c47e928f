// hbfriction — law `damper`: a nonlinear (power-law) damper, e.g. the quadratic damper of a
// fluid or a squeeze film.
//
// Definition: f = c |v|^a sign(v) with v = q' the relative velocity, acting as -w f on the
// structure: a = 1 is a linear dashpot, a = 2 the quadratic damper c |v| v.
// Parameters: coefficient c (> 0), exponent a (in [1, 10], default 2; below 1 the slope
// c a |v|^(a - 1) is infinite at rest and the equations of motion are not Lipschitz).
// While stuck (the linear limits, the first guess): the dashpot c where a = 1, else none.
//
// Harmonic balance: f = P f(omega E D1 q), the exact Jacobian omega P diag(f'(v)) E D1. For an
// odd integer a the force is a polynomial of v, alias-free when N_t > (a + 1) H
// (time_samples_needed); otherwise (|v| v) it has every harmonic and no N_t is alias-free: the
// automatic N_t (16 H + 8 or more) keeps the error at the truncation's size. Smooth: time
// integration, stability (f_v = c a |v|^(a - 1)); no stick (regime "none"). Default H 10.
#include <cmath>
#include <string>

#include "contact/force_element.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

double exponent_of(const Contact& contact) {
    const auto a = contact.values.find("exponent");
    return a == contact.values.end() ? 2.0 : a->second;
}

class PowerDamper final : public detail::PointwiseForce {
public:
    explicit PowerDamper(const Contact& c) : coefficient_(c.values.at("coefficient")), exponent_(exponent_of(c)) {}
    detail::PointForce at(double, double v) const override {
        detail::PointForce f;
        const double speed = std::abs(v);
        if (exponent_ == 1.0) {
            f.force = coefficient_ * v;
            f.slope_v = coefficient_;
        } else if (exponent_ == 2.0) {
            f.force = coefficient_ * speed * v;
            f.slope_v = 2.0 * coefficient_ * speed;
        } else {
            const double power = std::pow(speed, exponent_ - 1.0);  // |v|^(a - 1)
            f.force = coefficient_ * power * v;
            f.slope_v = coefficient_ * exponent_ * power;
        }
        return f;
    }
    bool uses_velocity() const override { return true; }
    bool odd_integer() const { return exponent_ == std::floor(exponent_) && std::fmod(exponent_, 2.0) == 1.0; }
    double samples_needed(int harmonics) const override {
        return odd_integer() ? (exponent_ + 1.0) * harmonics + 1.0 : 0.0;
    }
    std::string samples_reason() const override {
        return "is a polynomial of the velocity of degree " + std::to_string(static_cast<int>(exponent_)) +
               ", alias-free when N_t > (a + 1) H";
    }

private:
    double coefficient_, exponent_;
};

class DamperLaw final : public detail::ForceElementLaw {
public:
    DamperLaw() : ForceElementLaw(FrictionLaw::damper, "damper", "power-law damper: f = c |v|^a sign(v)") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        LawParameter exponent{"exponent", nullptr, "damper exponent a (a = 2: the quadratic damper c v^2 sign v)", R::interval};
        exponent.low = 1.0;
        exponent.high = 10.0;
        exponent.default_value = 2.0;
        return {{"coefficient", nullptr, "damper coefficient c", R::positive}, exponent};
    }
    int default_harmonics() const override { return 10; }
    StuckElement stuck(const Contact& contact) const override {
        return {false, 0.0, exponent_of(contact) == 1.0 ? contact.values.at("coefficient") : 0.0};
    }
    void validate(const Contact& contact, const std::string& where) const override {
        if (!contact.values.count("coefficient"))
            throw InvalidInput(where + "coefficient is missing: law damper needs it (c > 0)");
        ContactLaw::validate(contact, where);
    }
    /// A velocity law: at rest it carries no force.
    bool static_force(const Contact&, const Eigen::VectorXd&, StaticForce& out) const override {
        out.force = Eigen::VectorXd::Zero(1);
        out.jacobian = Eigen::MatrixXd::Zero(1, 1);
        out.state = "elastic";
        return true;
    }
    std::shared_ptr<const detail::PointwiseForce> force(const Contact& contact) const override {
        return std::make_shared<PowerDamper>(contact);
    }
};

}  // namespace

const ContactLaw& damper_law() {
    static const DamperLaw law;
    return law;
}

}  // namespace hbf
