// hbfriction — internal: the bristle model shared by the laws `dahl` and `lugre` (Dahl is
// LuGre without bristle damping, viscous friction and Stribeck curve). Not installed.
#pragma once

#include <memory>

#include "hbf/contact_law.hpp"

namespace hbf::detail {

/// The bristle force by AFT (see lugre.cpp): sigma0, sigma1, sigma2 as given (Dahl: 0 for the
/// last two), g(v) = sliding_limit(contact, v).
std::unique_ptr<FrictionModel> bristle_model(const Contact& contact, double sigma1, double sigma2);
/// The local linearisation of the bristle law with sigma1, sigma2 as given.
LocalLinearization bristle_linearization(const Contact& contact, double sigma1, double sigma2, double v, double z);
/// Harmonic balance's first guess of the bristle deflection z: sliding, (4/pi) F_c / sigma0 in
/// phase with the velocity; stuck (pre-sliding), z = q.
void bristle_guess(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                   Eigen::Ref<Eigen::VectorXd> z);

/// Time integration of the bristle law (contact_law.hpp: ContactLaw::time_force, time_margin):
/// z' = v - sigma0 |v| z / g(v), f = sigma0 z + sigma1 z' + sigma2 v (Dahl: g = F_c, sigma1 =
/// sigma2 = 0); the margin |sigma0 z| / (stick_force_ratio g(v)) - 1.
double bristle_time_force(const Contact& contact, double sigma1, double sigma2, double v, double z, double& rate);
double bristle_time_margin(const Contact& contact, double v, double z);
/// The static force of a bristle loaded monotonically from z = 0 at a vanishing velocity
/// (ContactLaw::static_force): dz/dq = 1 - sigma0 z / g for q growing, so
/// f = sigma0 z = g (1 - exp(-sigma0 |q| / g)) sign(q), g = `limit` (Dahl: F_c; LuGre: g(0) = F_s).
void bristle_static_force(const Contact& contact, double limit, double q, StaticForce& out);

/// What the laws dahl and lugre share as contact laws: smooth, the bristle deflection as their
/// state, default H 10, and the bristle model's AFT force, linearisation, time-domain force and
/// first guess with their own sigma1 and sigma2 (Dahl: 0 and 0).
class BristleLaw : public ContactLaw {
public:
    using ContactLaw::ContactLaw;
    int default_harmonics() const override { return 10; }
    bool smooth() const override { return true; }
    bool exact_stick() const override { return false; }
    TimeState time_state() const override { return TimeState::bristle; }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return bristle_model(contact, sigma1(contact), sigma2(contact));
    }
    LocalLinearization linearize(const Contact& contact, double, double v, double z) const override {
        return bristle_linearization(contact, sigma1(contact), sigma2(contact), v, z);
    }
    double time_force(const Contact& contact, double, double v, double z, double& rate) const override {
        return bristle_time_force(contact, sigma1(contact), sigma2(contact), v, z, rate);
    }
    double time_margin(const Contact& contact, double, double v, double z) const override {
        return bristle_time_margin(contact, v, z);
    }
    void guess_state(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                     const Eigen::VectorXcd&, const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd> z) const override {
        bristle_guess(contact, sliding, q, cos_row, z);
    }

protected:
    /// The bristle damping sigma1 and the viscous coefficient sigma2 of `contact`.
    virtual double sigma1(const Contact& contact) const = 0;
    virtual double sigma2(const Contact& contact) const = 0;
};

}  // namespace hbf::detail
