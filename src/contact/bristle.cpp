// hbfriction — the bristle model of `dahl` and `lugre` (bristle.hpp; the law files hold the
// definitions).
//
// Harmonic balance: the bristle deflection z is one more harmonic unknown signal, balanced like
// the equations of motion; the law returns the residual of its ODE z' = v - sigma0 |v| z / g(v),
//     r_z = sigma0 [ D z - D q + P( sigma0 |v| z / g(v) ) ],
// (multiplied by sigma0 so that it is in force / time units like the structure's rows), with
// the force f = sigma0 z + sigma1 D z + sigma2 D q, linear in the coefficients. E and P are the
// synthesis/analysis matrices of Fourier and D = omega D1 the derivative with respect to tau;
// the Jacobians are exact: the chain rule through E and P.
#include "contact/bristle.hpp"

#include <cmath>

#include "base/stopwatch.hpp"

namespace hbf {

double sliding_limit(const Contact& contact, double v, double* slope) {
    const double kinetic = contact.friction_limit;
    const double stat = contact.static_limit > 0.0 ? contact.static_limit : kinetic;
    if (contact.law == FrictionLaw::lugre && contact.stribeck_velocity > 0.0 && stat != kinetic) {
        const double x = v / contact.stribeck_velocity, e = std::exp(-x * x);
        if (slope) *slope = (stat - kinetic) * e * (-2.0 * x / contact.stribeck_velocity);
        return kinetic + (stat - kinetic) * e;
    }
    if (slope) *slope = 0.0;
    return kinetic;
}

namespace detail {

namespace {

class Bristle final : public FrictionModel {
public:
    Bristle(const Contact& c, double sigma1, double sigma2)
        : contact_(c), sigma0_(c.stiffness), sigma1_(sigma1), sigma2_(sigma2),
          constant_(sliding_limit(c, 0.0) == c.friction_limit) {}  // g(0) = F_s: F_c without a curve
    int state_signals() const override { return 1; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                  FrictionEvaluation& out, bool jacobian) const override {
        const Eigen::MatrixXd& D1 = fourier.derivative();
        const int nt = fourier.time_samples();
        const Eigen::VectorXd dq = D1 * q, dz = D1 * z;  // d/dtheta
        Eigen::VectorXd v(nt), zt(nt);
        fourier.to_time(omega * dq, v);
        fourier.to_time(z, zt);
        Eigen::ArrayXd g(nt), dg(nt);
        curve(v.array(), g, dg);
        // h = sigma0 |v| z / g(v): the bristle relaxation term.
        const Eigen::ArrayXd h = sigma0_ * v.array().abs() * zt.array() / g;
        Eigen::VectorXd h_coefficients(fourier.size());
        fourier.to_coefficients(h.matrix(), h_coefficients);
        out.state_residual = sigma0_ * (omega * (dz - dq) + h_coefficients);
        out.force = sigma0_ * z + sigma1_ * omega * dz + sigma2_ * omega * dq;
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        const Eigen::ArrayXd sign = v.array().sign();
        // dh/dv = sigma0 z (sign(v) g - |v| g') / g^2 ; dh/dz = sigma0 |v| / g.
        const Eigen::ArrayXd dh_dv = sigma0_ * zt.array() * (sign * g - v.array().abs() * dg) / g.square();
        const Eigen::ArrayXd dh_dz = sigma0_ * v.array().abs() / g;
        // With v = omega E D1 q and P diag(d) E the multiplication matrix of d:
        // dr_z/dq = sigma0 omega (-D1 + [dh/dv] D1), dr_z/dz = sigma0 (omega D1 + [dh/dz]),
        // dr_z/domega = sigma0 (D1 z - D1 q + [dh/dv] D1 q).
        const int n = fourier.size();
        Eigen::MatrixXd p_dv(n, n), p_dz(n, n);
        fourier.multiplication_matrix(dh_dv.matrix(), p_dv);
        fourier.multiplication_matrix(dh_dz.matrix(), p_dz);
        out.state_q = sigma0_ * omega * (fourier.times_derivative(p_dv) - D1);
        out.state_z = sigma0_ * (omega * D1 + p_dz);
        out.state_omega = sigma0_ * (dz - dq + p_dv * dq);
        out.force_q = sigma2_ * omega * D1;
        out.force_z = sigma0_ * Eigen::MatrixXd::Identity(n, n) + sigma1_ * omega * D1;
        out.force_omega = sigma1_ * dz + sigma2_ * dq;
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& z) const override {
        Eigen::VectorXd f(fourier.time_samples());
        const Eigen::VectorXd dq = fourier.derivative() * q, dz = fourier.derivative() * z;
        fourier.to_time(sigma0_ * z + sigma1_ * omega * dz + sigma2_ * omega * dq, f);
        return f;
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& z) const override {
        const int nt = fourier.time_samples();
        Eigen::VectorXd v(nt), zt(nt);
        fourier.to_time(omega * (fourier.derivative() * q), v);
        fourier.to_time(z, zt);
        Eigen::ArrayXd g(nt), dg(nt);
        curve(v.array(), g, dg);
        return (sigma0_ * zt.array().abs() / (stick_force_ratio * g) - 1.0).matrix();
    }

private:
    /// g(v) and its derivative on the samples (constant without a Stribeck curve).
    void curve(const Eigen::ArrayXd& v, Eigen::ArrayXd& g, Eigen::ArrayXd& dg) const {
        if (constant_) {
            g.setConstant(contact_.friction_limit);
            dg.setZero();
            return;
        }
        for (Eigen::Index j = 0; j < v.size(); ++j) g(j) = sliding_limit(contact_, v(j), &dg(j));
    }

    Contact contact_;
    double sigma0_, sigma1_, sigma2_;
    bool constant_;  ///< g = F_c (Dahl, LuGre without a Stribeck curve)
};

}  // namespace

std::unique_ptr<FrictionModel> bristle_model(const Contact& contact, double sigma1, double sigma2) {
    return std::make_unique<Bristle>(contact, sigma1, sigma2);
}

LocalLinearization bristle_linearization(const Contact& contact, double sigma1, double sigma2, double v, double z) {
    LocalLinearization l;
    const double s0 = contact.stiffness;
    double dg = 0.0;
    const double g = sliding_limit(contact, v, &dg);
    const double sign = v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0;
    l.g_v = 1.0 - s0 * z * (sign * g - std::abs(v) * dg) / (g * g);
    l.g_z = -s0 * std::abs(v) / g;
    l.f_v = sigma1 * l.g_v + sigma2;
    l.f_z = s0 + sigma1 * l.g_z;
    return l;
}

void bristle_guess(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                   Eigen::Ref<Eigen::VectorXd> z) {
    const double speed = std::hypot(q(cos_row), q(cos_row + 1));
    if (sliding && speed > 0.0) {
        const double limit = 4.0 / M_PI * contact.friction_limit / contact.stiffness;
        z(cos_row) = limit * q(cos_row + 1) / speed;
        z(cos_row + 1) = -limit * q(cos_row) / speed;
    } else if (!sliding) {
        z = q;  // pre-sliding bristle: z = q
    }
}

double bristle_time_force(const Contact& contact, double sigma1, double sigma2, double v, double z, double& rate) {
    const double sigma0 = contact.stiffness;
    rate = v - sigma0 * std::abs(v) * z / sliding_limit(contact, v);
    return sigma0 * z + sigma1 * rate + sigma2 * v;
}

void bristle_static_force(const Contact& contact, double limit, double q, StaticForce& out) {
    const double decay = std::exp(-contact.stiffness * std::abs(q) / limit);
    out.force = Eigen::VectorXd::Constant(1, std::copysign(limit * (1.0 - decay), q));
    out.jacobian = Eigen::MatrixXd::Constant(1, 1, contact.stiffness * decay);
    out.state = "presliding";
}

double bristle_time_margin(const Contact& contact, double v, double z) {
    return std::abs(contact.stiffness * z) / (stick_force_ratio * sliding_limit(contact, v)) - 1.0;
}

}  // namespace detail

}  // namespace hbf
