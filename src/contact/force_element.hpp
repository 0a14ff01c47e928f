// hbfriction — internal to contact/: what the force elements without friction share (laws
// polynomial, gap and damper): a force f(q, v) of the relative displacement and velocity alone,
// evaluated pointwise on the time samples. Not installed.
//
// Harmonic balance: with u = E q and v = omega E D1 q the samples of the displacement and the
// velocity, f = P f(u, v), and the exact Jacobians
//     df/dq = P diag(f_q) E + omega P diag(f_v) E D1,   df/domega = P (f_v v / omega)
// (E, P, D1: fourier.hpp). Time integration and the stability analysis take f, f_q and f_v
// at one instant (ContactLaw::time_force, linearize). No regime: friction() is false.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"

namespace hbf::detail {

/// One instant of a force element: its force and its slopes.
struct PointForce {
    double force = 0, slope_q = 0, slope_v = 0;
};

/// A force element's force as a function of one instant's displacement q and velocity v.
class PointwiseForce {
public:
    virtual ~PointwiseForce() = default;
    virtual PointForce at(double q, double v) const = 0;
    /// Whether the force depends on v (the velocity samples are formed only then).
    virtual bool uses_velocity() const = 0;
    /// N_t the AFT needs (FrictionModel::time_samples_needed) at H harmonics, and why.
    virtual double samples_needed(int harmonics) const = 0;
    virtual std::string samples_reason() const = 0;
    /// Time integration's margin (ContactLaw::time_margin): a positive constant (no event), or
    /// where the force has a corner a function whose sign changes there (the gap's closing).
    virtual double margin(double) const { return 1.0; }
};

/// The AFT model of a pointwise force (the equations at the top of this file).
std::unique_ptr<FrictionModel> pointwise_model(std::shared_ptr<const PointwiseForce> force);

/// What the force elements share as contact laws; a law gives its parameters, its pointwise
/// force (`force`), its linear part at rest (`stuck`) and its default H.
class ForceElementLaw : public ContactLaw {
public:
    using ContactLaw::ContactLaw;
    bool smooth() const override { return true; }
    bool exact_stick() const override { return false; }
    bool has_friction_limit() const override { return false; }
    bool has_preset() const override { return false; }
    bool friction() const override { return false; }
    TimeState time_state() const override { return TimeState::none; }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return pointwise_model(force(contact));
    }
    LocalLinearization linearize(const Contact& contact, double q, double v, double z) const override {
        return bind(contact)->linearize(q, v, z);
    }
    double time_force(const Contact& contact, double q, double v, double z, double& rate) const override {
        return bind(contact)->force(q, v, z, rate);
    }
    /// No stick: a positive constant (no event), unless the law has a corner (gap).
    double time_margin(const Contact& contact, double q, double v, double z) const override {
        return bind(contact)->margin(q, v, z);
    }
    /// The pointwise force built once (its parameters read from the contact's tables).
    std::unique_ptr<BoundLaw> bind(const Contact& contact) const override;
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override;
    /// The pointwise force of the contact's parameters.
    virtual std::shared_ptr<const PointwiseForce> force(const Contact& contact) const = 0;
};

}  // namespace hbf::detail
