// hbfriction — contact law `coulomb`: exact (set-valued) Coulomb friction.
//
// Definition (paper eq. 3): f = F_c sign(v) in slip, |f| <= F_c in stick (v = q' = 0).
// Parameters: friction_limit F_c = mu N (> 0); lagrangian_penalty eps (>= 0, 0 = automatic:
// the contact direction's impedance sqrt((w^T K w)(w^T M w)), capped at 30 times the impedance of
// the structure's static deflection under the contact: see complete()).
// While stuck: rigid (w^T y is held; the force is the constraint's multiplier).
//
// Harmonic balance by the dynamic Lagrangian: the contact force lambda itself is the unknown
// signal (coefficients Lambda) and the law is written as the fixed point
//     lambda = proj_[-F_c, F_c](lambda + eps v),
// which holds, for any eps > 0, iff v = 0 and |lambda| <= F_c (stick), or lambda = F_c
// sign(v) (slip). Balanced like the equations of motion: r = Lambda - P proj(E Lambda + eps v),
// with the force f = lambda. Samples with |lambda + eps v| < F_c stick; its Jacobian is
// exact on each stick/slip pattern (semi-smooth). In permanent stick the mean force is not
// determined (any offset keeping |lambda| <= F_c solves the equations); the c0 row is then
// replaced by max lambda + min lambda = 0: the force is centred in the friction cone, which
// for a system without static load is the symmetric solution (mean force and mean
// displacement zero).
//
// Not smooth; its stick is exact (the event-exact solver and time integration's modes); no
// internal state in time (stick is a mode); default H 20 (the DLFT converges like 1/H: about
// 1 % at the peak).
#include <algorithm>
#include <cmath>

#include "hbf/contact_law.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

/// Exact Coulomb friction by the dynamic Lagrangian (see the top of this file).
class DynamicLagrangianCoulomb final : public FrictionModel {
public:
    explicit DynamicLagrangianCoulomb(const Contact& c) : limit_(c.friction_limit), eps_(c.lagrangian_penalty) {}
    int state_signals() const override { return 1; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                  FrictionEvaluation& out, bool jacobian) const override {
        const Eigen::MatrixXd& D1 = fourier.derivative();
        const int nt = fourier.time_samples(), n = fourier.size();
        Eigen::VectorXd v(nt), lambda(nt);
        fourier.to_time(omega * (D1 * q), v);
        fourier.to_time(z, lambda);
        const Eigen::ArrayXd u = lambda.array() + eps_ * v.array();
        Eigen::VectorXd projected(n);
        fourier.to_coefficients(u.max(-limit_).min(limit_).matrix(), projected);
        out.state_residual = z - projected;
        out.force = z;
        const Eigen::ArrayXd stick = (u.abs() < limit_).cast<double>();
        const bool permanent_stick = stick.minCoeff() == 1.0;
        Eigen::Index highest = 0, lowest = 0;
        if (permanent_stick) {
            // The mean force is free in permanent stick: centre it in the friction cone.
            out.state_residual(0) = 0.5 * (lambda.maxCoeff(&highest) + lambda.minCoeff(&lowest));
        }
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        Eigen::MatrixXd m(n, n);
        fourier.multiplication_matrix(stick.matrix(), m);  // P diag(stick) E
        out.state_z = Eigen::MatrixXd::Identity(n, n) - m;
        out.state_q = -eps_ * omega * fourier.times_derivative(m);
        out.state_omega = -eps_ * (m * (D1 * q));
        if (permanent_stick) {
            const Eigen::MatrixXd& E = fourier.synthesis();
            out.state_z.row(0) = 0.5 * (E.row(highest) + E.row(lowest));
            out.state_q.row(0).setZero();
            out.state_omega(0) = 0.0;
        }
        out.force_q = Eigen::MatrixXd::Zero(n, n);
        out.force_z = Eigen::MatrixXd::Identity(n, n);
        out.force_omega = Eigen::VectorXd::Zero(n);
        out.jacobian_seconds = watch.lap();
    }

    /// The law's own force: lambda + eps v projected on [-F_c, F_c] (|f| <= F_c at every
    /// sample). At a solution its H-harmonic series is z, the force the balance sees.
    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& z) const override {
        return trial(fourier, omega, q, z).max(-limit_).min(limit_).matrix();
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& z) const override {
        return (trial(fourier, omega, q, z).abs() / limit_ - 1.0).matrix();
    }

private:
    /// The trial force lambda + eps v at the time samples.
    Eigen::ArrayXd trial(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd& z) const {
        const int nt = fourier.time_samples();
        Eigen::VectorXd v(nt), lambda(nt);
        fourier.to_time(omega * (fourier.derivative() * q), v);
        fourier.to_time(z, lambda);
        return lambda.array() + eps_ * v.array();
    }
    double limit_, eps_;
};

class Coulomb final : public ContactLaw {
public:
    Coulomb()
        : ContactLaw(FrictionLaw::coulomb, "coulomb",
              "exact Coulomb: f = F_c sign(v) in slip, |f| <= F_c in stick (v = 0)") {}
    std::vector<LawParameter> parameters() const override {
        return {{"lagrangian_penalty", &Contact::lagrangian_penalty, "dynamic Lagrangian epsilon (0 = automatic)",
                 LawParameter::Range::non_negative, "automatic: the contact's impedance sqrt(k m), at most 30 times the structure's static one"}};
    }
    int default_harmonics() const override { return 20; }
    bool smooth() const override { return false; }
    bool exact_stick() const override { return true; }
    TimeState time_state() const override { return TimeState::none; }
    StuckElement stuck(const Contact&) const override { return {true, 0.0, 0.0}; }
    std::vector<std::string> preset_parameters() const override { return {"lagrangian_penalty"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.lagrangian_penalty = p.lagrangian_penalty;
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        if (!(contact.lagrangian_penalty > 0.0))
            throw InvalidInput("lagrangian_penalty = " + format_number(contact.lagrangian_penalty) +
                               " is out of range: allowed > 0 (HarmonicBalance chooses it when 0)");
        return std::make_unique<DynamicLagrangianCoulomb>(contact);
    }
    /// eps = the contact direction's impedance sqrt(k m), lambda and eps v of the same order,
    /// capped at 30 times the impedance of the structure's static deflection shape (below).
    void complete(Contact& c, const std::vector<DirectionScale>& scales, const std::string& where) const override {
        const DirectionScale& scale = scales.front();
        const double k = scale.stiffness, m = scale.mass;
        double automatic = k > 0.0 ? std::sqrt(k * m) : m;
        if (!(automatic > 0.0))  // a massless contact on a massless, unsprung direction
            automatic = std::sqrt(std::max(k, 0.0) * scale.largest_mass);
        // On a discretised continuum w^T K w and w^T M w are the contact node's own (~N^3 and
        // ~1/N for a beam): sqrt(k m) grows like N with mesh refinement (9.9e3 on the 100-element
        // beam, 9.9e4 on 1000 elements, where the start fails). The static deflection shape's
        // impedance sqrt(kappa m_s) (DirectionScale) converges instead (39.4 N s/m on both). The
        // cap 30 sqrt(kappa m_s) leaves the lumped models alone (sqrt(k m) is 12 times it on the
        // paper's absorber, 6 times on the reduced beam) and was measured best on the beam at
        // w = 40.6, H = 20: y_max of mid-span against BDF time integration -0.53 % at 1 times,
        // +0.17 % at 30 times, -0.4 % at sqrt(k m) (250 times).
        const double structure = std::sqrt(scale.static_stiffness * scale.static_mass);
        if (structure > 0.0) automatic = std::min(automatic, 30.0 * structure);
        // A chosen eps must stay within a range measured to converge (the paper's absorber,
        // H = 20, eps / automatic from 1e-4 to 1e4: the same branch from 0.04 to 4 times the
        // automatic value; spurious folds and stalls below 0.01, stalls above 8).
        const double low = automatic / 30.0, high = 4.0 * automatic;
        if (c.lagrangian_penalty != 0.0 && automatic > 0.0 &&
            !(c.lagrangian_penalty >= low && c.lagrangian_penalty <= high))
            throw InvalidInput(where + "lagrangian_penalty (--dlft-eps) = " + format_number(c.lagrangian_penalty) +
                               " is out of range: allowed " + format_number(low) + ".." + format_number(high) +
                               " (1/30 to 4 times the automatic value " + format_number(automatic) +
                               ", the contact's impedance; outside it the dynamic Lagrangian was measured to "
                               "stall or to follow spurious branches)");
        if (c.lagrangian_penalty == 0.0) c.lagrangian_penalty = automatic;
    }
    /// The state is the force lambda: sliding, (4/pi) F_c in phase with the velocity (harmonic h
    /// of F_c sign(v) for v on harmonic h); stuck, the stuck response's constraint force.
    void guess_state(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                     const Eigen::VectorXcd& stuck_forces, const Eigen::VectorXd&,
                     Eigen::Ref<Eigen::VectorXd> z) const override {
        const std::complex<double> stuck_force = stuck_forces(0);
        const double speed = std::hypot(q(cos_row), q(cos_row + 1));
        if (sliding && speed > 0.0) {
            const double limit = 4.0 / M_PI * contact.friction_limit;
            z(cos_row) = limit * q(cos_row + 1) / speed;
            z(cos_row + 1) = -limit * q(cos_row) / speed;
        } else if (!sliding && std::isfinite(std::abs(stuck_force))) {
            z(cos_row) = stuck_force.real();
            z(cos_row + 1) = -stuck_force.imag();
        }
    }
};

}  // namespace

const ContactLaw& coulomb_law() {
    static const Coulomb law;
    return law;
}

}  // namespace hbf
