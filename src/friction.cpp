#include "hbf/friction.hpp"

#include <cmath>
#include <vector>

#include "hbf/error.hpp"
#include "stopwatch.hpp"

namespace hbf {

namespace {

/// f = F_c tanh(v / eps).
class RegularizedCoulomb final : public FrictionModel {
public:
    explicit RegularizedCoulomb(const Contact& c) : limit_(c.friction_limit), eps_(c.regularization) {}
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd&,
                  FrictionEvaluation& out, bool jacobian) const override {
        const Eigen::MatrixXd& D1 = fourier.derivative();
        const Eigen::VectorXd v_coefficients = omega * (D1 * q);
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(v_coefficients, v);
        const Eigen::ArrayXd t = (v.array() / eps_).tanh();
        out.force.resize(fourier.size());
        fourier.to_coefficients((limit_ * t).matrix(), out.force);
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        const Eigen::ArrayXd slope = limit_ / eps_ * (1.0 - t.square());  // df/dv
        // f = P f(v), v = omega E D1 q: df/dq = omega P diag(f') E D1, df/domega = P (f' v / omega).
        const int n = fourier.size();
        Eigen::MatrixXd p_slope(n, n);
        fourier.multiplication_matrix(slope.matrix(), p_slope);
        out.force_q = omega * fourier.times_derivative(p_slope);
        out.force_omega = p_slope * (D1 * q);
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(omega * (fourier.derivative() * q), v);
        return (limit_ * (v.array() / eps_).tanh()).matrix();
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd&) const override {
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(omega * (fourier.derivative() * q), v);
        return ((v.array() / eps_).tanh().abs() / stick_force_ratio - 1.0).matrix();
    }

private:
    double limit_, eps_;
};

/// LuGre (Dahl when sigma1 = sigma2 = 0 and no Stribeck curve).
class LuGre final : public FrictionModel {
public:
    explicit LuGre(const Contact& c)
        : sigma0_(c.stiffness), sigma1_(c.damping), sigma2_(c.viscous), kinetic_(c.friction_limit),
          static_(c.static_limit > 0.0 ? c.static_limit : c.friction_limit), stribeck_(c.stribeck_velocity) {}
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
    /// g(v) = F_c + (F_s - F_c) exp(-(v/v_s)^2) and its derivative.
    void curve(const Eigen::ArrayXd& v, Eigen::ArrayXd& g, Eigen::ArrayXd& dg) const {
        if (stribeck_ > 0.0 && static_ != kinetic_) {
            const Eigen::ArrayXd e = (-(v / stribeck_).square()).exp();
            g = kinetic_ + (static_ - kinetic_) * e;
            dg = (static_ - kinetic_) * e * (-2.0 * v / (stribeck_ * stribeck_));
        } else {
            g.setConstant(kinetic_);
            dg.setZero();
        }
    }

    double sigma0_, sigma1_, sigma2_, kinetic_, static_, stribeck_;
};

/// Exact Coulomb friction by the dynamic Lagrangian (see friction.hpp).
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
        const int nt = fourier.time_samples();
        Eigen::VectorXd v(nt), lambda(nt);
        fourier.to_time(omega * (fourier.derivative() * q), v);
        fourier.to_time(z, lambda);
        return (lambda.array() + eps_ * v.array()).max(-limit_).min(limit_).matrix();
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& z) const override {
        const int nt = fourier.time_samples();
        Eigen::VectorXd v(nt), lambda(nt);
        fourier.to_time(omega * (fourier.derivative() * q), v);
        fourier.to_time(z, lambda);
        return ((lambda.array() + eps_ * v.array()).abs() / limit_ - 1.0).matrix();
    }

private:
    double limit_, eps_;
};

/// Jenkins element: spring k_t in series with a Coulomb slider, marched over the period (see
/// friction.hpp).
class Jenkins final : public FrictionModel {
public:
    explicit Jenkins(const Contact& c) : limit_(c.friction_limit), stiffness_(c.stiffness) {}
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double, const Eigen::VectorXd& q, const Eigen::VectorXd&,
                  FrictionEvaluation& out, bool jacobian) const override {
        const int nt = fourier.time_samples(), n = fourier.size();
        Eigen::VectorXd qt(nt);
        fourier.to_time(q, qt);
        const Cycle cycle = march(qt);
        out.force.resize(n);
        fourier.to_coefficients(cycle.force, out.force);
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        // f_j = k_t (q_j - sum_k W_jk q_k) + const on stick samples, constant on slip samples:
        // df/dq = k_t P (diag(stick) - W) E, W the anchor weights of each stick sample.
        Eigen::MatrixXd m(n, n);
        fourier.multiplication_matrix(cycle.stick, m);
        const Eigen::MatrixXd& E = fourier.synthesis();
        const Eigen::MatrixXd& P = fourier.analysis();
        Eigen::MatrixXd anchored = Eigen::MatrixXd::Zero(n, nt);  // P W, column k: sum of P's
        for (int j = 0; j < nt; ++j) {                             // columns anchored at k
            if (cycle.stick(j) == 0.0) continue;
            if (cycle.anchor[j] >= 0) {
                anchored.col(cycle.anchor[j]) += P.col(j);
            } else {  // permanent stick: s = (q_max + q_min) / 2
                anchored.col(cycle.highest) += 0.5 * P.col(j);
                anchored.col(cycle.lowest) += 0.5 * P.col(j);
            }
        }
        out.force_q = stiffness_ * (m - anchored * E);
        out.force_omega = Eigen::VectorXd::Zero(n);
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        Eigen::VectorXd qt(fourier.time_samples());
        fourier.to_time(q, qt);
        return march(qt).force;
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd&) const override {
        Eigen::VectorXd qt(fourier.time_samples());
        fourier.to_time(q, qt);
        const Cycle cycle = march(qt);
        return (cycle.stick.array() * (cycle.force.array().abs() / limit_ - 1.0)).matrix();
    }

private:
    /// The periodic slider cycle on the samples q_j.
    struct Cycle {
        Eigen::VectorXd force;    ///< f_j
        Eigen::VectorXd stick;    ///< 1 where the slider rests at sample j, 0 where it moves
        std::vector<int> anchor;  ///< stick samples: the last slip sample (-1: permanent stick)
        Eigen::Index highest = 0, lowest = 0;
    };

    Cycle march(const Eigen::VectorXd& qt) const {
        const int nt = static_cast<int>(qt.size());
        Cycle c;
        c.force.resize(nt);
        c.stick.resize(nt);
        c.anchor.assign(static_cast<std::size_t>(nt), -1);
        double slider = 0.5 * (qt.maxCoeff(&c.highest) + qt.minCoeff(&c.lowest));
        int last_slip = -1;
        // Two periods settle the cycle (the first slip forgets the start); more are marched
        // only while the slider's position at the period's end still changes. The samples of
        // the last period before its first slip hang on the previous period's last slip,
        // which is the same sample once the cycle repeats.
        constexpr int max_periods = 8;
        for (int period = 0; period < max_periods; ++period) {
            const double start = slider;
            for (int j = 0; j < nt; ++j) {
                const double trial = stiffness_ * (qt(j) - slider);
                if (std::abs(trial) > limit_) {
                    const double sign = trial > 0.0 ? 1.0 : -1.0;
                    slider = qt(j) - sign * limit_ / stiffness_;
                    c.force(j) = sign * limit_;
                    c.stick(j) = 0.0;
                    last_slip = j;
                } else {
                    c.force(j) = trial;
                    c.stick(j) = 1.0;
                }
                c.anchor[static_cast<std::size_t>(j)] = last_slip;
            }
            if (last_slip < 0 || (period > 0 && slider == start)) break;
        }
        return c;
    }

    double limit_, stiffness_;
};

}  // namespace

LocalLinearization linearize(const Contact& contact, double v, double z) {
    LocalLinearization l;
    switch (contact.law) {
        case FrictionLaw::coulomb_regularized: {
            const double t = std::tanh(v / contact.regularization);
            l.f_v = contact.friction_limit * (1.0 - t * t) / contact.regularization;
            return l;
        }
        case FrictionLaw::dahl:
        case FrictionLaw::lugre: {
            const bool lugre = contact.law == FrictionLaw::lugre;
            const double s0 = contact.stiffness, s1 = lugre ? contact.damping : 0.0, s2 = lugre ? contact.viscous : 0.0;
            double g = contact.friction_limit, dg = 0.0;
            if (lugre && contact.stribeck_velocity > 0.0 && contact.static_limit > 0.0 &&
                contact.static_limit != contact.friction_limit) {
                const double x = v / contact.stribeck_velocity, e = std::exp(-x * x);
                g += (contact.static_limit - contact.friction_limit) * e;
                dg = (contact.static_limit - contact.friction_limit) * e * (-2.0 * x / contact.stribeck_velocity);
            }
            const double sign = v > 0.0 ? 1.0 : v < 0.0 ? -1.0 : 0.0;
            l.g_v = 1.0 - s0 * z * (sign * g - std::abs(v) * dg) / (g * g);
            l.g_z = -s0 * std::abs(v) / g;
            l.f_v = s1 * l.g_v + s2;
            l.f_z = s0 + s1 * l.g_z;
            return l;
        }
        case FrictionLaw::coulomb:
        case FrictionLaw::jenkins: break;
    }
    throw InvalidInput("law = " + to_string(contact.law) +
                       " has no local linearisation: allowed dahl, lugre, coulomb-reg (smooth laws)");
}

std::unique_ptr<FrictionModel> make_friction_model(const Contact& contact) {
    switch (contact.law) {
        case FrictionLaw::coulomb_regularized: return std::make_unique<RegularizedCoulomb>(contact);
        case FrictionLaw::dahl: {
            Contact dahl = contact;
            dahl.damping = dahl.viscous = dahl.stribeck_velocity = 0.0;
            return std::make_unique<LuGre>(dahl);
        }
        case FrictionLaw::lugre: return std::make_unique<LuGre>(contact);
        case FrictionLaw::coulomb:
            if (!(contact.lagrangian_penalty > 0.0))
                throw InvalidInput("lagrangian_penalty = " + format_number(contact.lagrangian_penalty) +
                                   " is out of range: allowed > 0 (HarmonicBalance chooses it when 0)");
            return std::make_unique<DynamicLagrangianCoulomb>(contact);
        case FrictionLaw::jenkins: return std::make_unique<Jenkins>(contact);
    }
    throw InvalidInput("unknown friction law");
}

}  // namespace hbf
