#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "hbf/error.hpp"
#include "stopwatch.hpp"

namespace hbf {

EvaluationStatistics operator-(const EvaluationStatistics& later, const EvaluationStatistics& earlier) {
    return {later.residuals - earlier.residuals, later.jacobians - earlier.jacobians,
            later.aft_seconds - earlier.aft_seconds, later.jacobian_seconds - earlier.jacobian_seconds,
            later.structure_seconds - earlier.structure_seconds};
}

HarmonicBalance::HarmonicBalance(System system, HarmonicBalanceOptions options)
    : system_(std::move(system)),
      fourier_(options.harmonics,
               options.time_samples > 0 ? options.time_samples : Fourier::default_time_samples(options.harmonics)) {
    if (options.harmonics < 1)
        throw InvalidInput("harmonics = " + std::to_string(options.harmonics) + " is out of range: allowed >= 1");
    if (options.time_samples < 0)
        throw InvalidInput("time_samples = " + std::to_string(options.time_samples) +
                           " is out of range: allowed 0 (automatic) or > 2 harmonics");
    system_.validate();
    const int n = coefficients();
    unknowns_ = system_.dofs() * n;
    force_scale_ = system_.excitation.cwiseAbs().maxCoeff();
    if (!(force_scale_ > 0.0)) throw InvalidInput("excitation vector is zero: allowed a non-zero force amplitude");
    for (Contact& c : system_.contacts) {
        if (c.law == FrictionLaw::coulomb && c.lagrangian_penalty == 0.0) {
            // The contact direction's impedance sqrt(k m): lambda and eps v of the same order.
            const Eigen::VectorXd w = system_.contact_direction(c);
            const double k = w.dot(system_.stiffness * w), m = w.dot(system_.mass * w);
            c.lagrangian_penalty = k > 0.0 ? std::sqrt(k * m) : m;
        }
        models_.push_back(make_friction_model(c));
        directions_.push_back(system_.contact_direction(c));
        state_offset_.push_back(models_.back()->state_signals() > 0 ? unknowns_ : -1);
        unknowns_ += models_.back()->state_signals() * n;
    }
}

Eigen::VectorXd HarmonicBalance::dof(const Eigen::VectorXd& x, int i) const {
    return x.segment(i * coefficients(), coefficients());
}

Eigen::VectorXd HarmonicBalance::relative(const Eigen::VectorXd& x, int contact) const {
    const int n = coefficients();
    const Eigen::Map<const Eigen::MatrixXd> y(x.data(), n, system_.dofs());
    return y * directions_[static_cast<std::size_t>(contact)];
}

Eigen::VectorXd HarmonicBalance::state(const Eigen::VectorXd& x, int contact) const {
    const int offset = state_offset_[static_cast<std::size_t>(contact)];
    return offset < 0 ? Eigen::VectorXd() : Eigen::VectorXd(x.segment(offset, coefficients()));
}

Eigen::VectorXd HarmonicBalance::force_samples(const Eigen::VectorXd& x, double omega, int contact) {
    return models_[static_cast<std::size_t>(contact)]->force_samples(fourier_, omega, relative(x, contact),
                                                                     state(x, contact));
}

Eigen::VectorXd HarmonicBalance::stick_indicator(const Eigen::VectorXd& x, double omega, int contact) {
    return models_[static_cast<std::size_t>(contact)]->stick_indicator(fourier_, omega, relative(x, contact),
                                                                       state(x, contact));
}

void HarmonicBalance::evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                               Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega) {
    detail::Stopwatch watch;
    ++statistics_.residuals;
    if (jacobian) ++statistics_.jacobians;
    const int n = coefficients(), dofs = system_.dofs();
    const Eigen::MatrixXd& D1 = fourier_.derivative();
    const Eigen::MatrixXd& M = system_.mass;
    const Eigen::MatrixXd& C = system_.damping;
    const Eigen::MatrixXd& K = system_.stiffness;
    const Eigen::Map<const Eigen::MatrixXd> Y(x.data(), n, dofs);
    residual.resize(unknowns_);
    Eigen::Map<Eigen::MatrixXd> RY(residual.data(), n, dofs);

    // Linear structure: D^2 Y M + D Y C + Y K - e_cos1 F^T.
    const Eigen::MatrixXd D1Y = D1 * Y;
    const Eigen::MatrixXd D2Y = D1 * D1Y;
    RY = omega * omega * D2Y * M + omega * D1Y * C + Y * K;
    RY.row(1) -= system_.excitation.transpose();
    statistics_.structure_seconds += watch.lap();
    const bool want_jacobian = jacobian != nullptr || jacobian_omega != nullptr;
    if (jacobian) {
        jacobian->setZero(unknowns_, unknowns_);
        const Eigen::MatrixXd D2 = D1 * D1;
        const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
        for (int i = 0; i < dofs; ++i)
            for (int j = 0; j < dofs; ++j)
                jacobian->block(i * n, j * n, n, n) = K(i, j) * I + omega * C(i, j) * D1 + omega * omega * M(i, j) * D2;
    }
    if (jacobian_omega) {
        jacobian_omega->setZero(unknowns_);
        Eigen::Map<Eigen::MatrixXd>(jacobian_omega->data(), n, dofs) = 2.0 * omega * D2Y * M + D1Y * C;
    }

    statistics_.jacobian_seconds += watch.lap();

    // Friction contacts through the AFT.
    for (std::size_t c = 0; c < models_.size(); ++c) {
        const Eigen::VectorXd& w = directions_[c];
        const Eigen::VectorXd q = Y * w;
        const int offset = state_offset_[c];
        const Eigen::VectorXd z = offset < 0 ? Eigen::VectorXd() : Eigen::VectorXd(x.segment(offset, n));
        FrictionEvaluation& e = scratch_;
        models_[c]->evaluate(fourier_, omega, q, z, e, want_jacobian);
        const double model_seconds = watch.lap();
        statistics_.aft_seconds += model_seconds - e.jacobian_seconds;
        statistics_.jacobian_seconds += e.jacobian_seconds;
        RY += e.force * w.transpose();
        if (offset >= 0) residual.segment(offset, n) = e.state_residual;
        if (jacobian) {
            for (int i = 0; i < dofs; ++i) {
                if (w(i) == 0.0) continue;
                for (int j = 0; j < dofs; ++j)
                    if (w(j) != 0.0) jacobian->block(i * n, j * n, n, n) += w(i) * w(j) * e.force_q;
                if (offset >= 0) {
                    jacobian->block(i * n, offset, n, n) += w(i) * e.force_z;
                    jacobian->block(offset, i * n, n, n) += w(i) * e.state_q;
                }
            }
            if (offset >= 0) jacobian->block(offset, offset, n, n) += e.state_z;
        }
        if (jacobian_omega) {
            Eigen::Map<Eigen::MatrixXd>(jacobian_omega->data(), n, dofs) += e.force_omega * w.transpose();
            if (offset >= 0) jacobian_omega->segment(offset, n) += e.state_omega;
        }
        statistics_.jacobian_seconds += watch.lap();  // residual/Jacobian assembly of this contact
    }
}

Eigen::VectorXd HarmonicBalance::linear_guess(double omega, bool sliding) const {
    const int n = coefficients(), dofs = system_.dofs();
    Eigen::MatrixXd C = system_.damping, K = system_.stiffness;
    std::vector<std::size_t> stuck;  // exact Coulomb contacts held rigid (pre-sliding guess)
    for (std::size_t c = 0; c < system_.contacts.size() && !sliding; ++c) {
        const Contact& k = system_.contacts[c];
        const Eigen::MatrixXd ww = directions_[c] * directions_[c].transpose();
        if (k.law == FrictionLaw::dahl || k.law == FrictionLaw::lugre || k.law == FrictionLaw::jenkins) {
            K += k.stiffness * ww;  // pre-sliding bristle / tangential spring
            C += (k.law == FrictionLaw::lugre ? k.damping + k.viscous : 0.0) * ww;
        }
        if (k.law == FrictionLaw::coulomb_regularized) C += k.friction_limit / k.regularization * ww;  // tanh'(0)
        if (k.law == FrictionLaw::coulomb) stuck.push_back(c);
    }
    // First harmonic of (K - w^2 M + i w C) Y + W Lambda = F with W^T Y = 0 for the stuck
    // contacts (Lambda: their complex force amplitudes).
    const auto m = static_cast<Eigen::Index>(stuck.size());
    Eigen::MatrixXcd A = Eigen::MatrixXcd::Zero(dofs + m, dofs + m);
    A.topLeftCorner(dofs, dofs) = dynamic_stiffness(system_.mass, C, K, omega);
    for (Eigen::Index j = 0; j < m; ++j) {
        A.block(0, dofs + j, dofs, 1) = directions_[stuck[static_cast<std::size_t>(j)]].cast<std::complex<double>>();
        A.block(dofs + j, 0, 1, dofs) = directions_[stuck[static_cast<std::size_t>(j)]].cast<std::complex<double>>().transpose();
    }
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(dofs + m);
    rhs.head(dofs) = system_.excitation.cast<std::complex<double>>();
    const Eigen::VectorXcd amplitude = A.fullPivLu().solve(rhs);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(unknowns_);
    auto put = [&](Eigen::Index offset, std::complex<double> a) {
        if (!std::isfinite(std::abs(a))) return;  // exact resonance: start from rest
        x(offset + 1) = a.real();  // y = Re(Y e^{i theta}) = Re Y cos - Im Y sin
        x(offset + 2) = -a.imag();
    };
    for (int d = 0; d < dofs; ++d) put(d * n, amplitude(d));
    for (std::size_t c = 0; c < system_.contacts.size(); ++c) {
        if (state_offset_[c] < 0) continue;
        const Contact& k = system_.contacts[c];
        const Eigen::VectorXd q = relative(x, static_cast<int>(c));
        const double speed = std::hypot(q(1), q(2));
        auto z = x.segment(state_offset_[c], n);  // zero so far
        if (sliding && speed > 0.0) {
            // The friction force sits at its limit, in phase with the velocity: the first
            // harmonic of F_c sign(v) is (4/pi) F_c v / |v|, v ~ (s1 cos - c1 sin).
            const double limit = 4.0 / M_PI * k.friction_limit / (k.law == FrictionLaw::coulomb ? 1.0 : k.stiffness);
            z(1) = limit * q(2) / speed;
            z(2) = -limit * q(1) / speed;
        } else if (k.law == FrictionLaw::coulomb) {
            const auto j = std::find(stuck.begin(), stuck.end(), c) - stuck.begin();
            const std::complex<double> force = amplitude(dofs + j);
            if (std::isfinite(std::abs(force))) {
                z(1) = force.real();
                z(2) = -force.imag();
            }
        } else if (!sliding) {
            z = q;  // pre-sliding bristle: z = q
        }
    }
    return x;
}

}  // namespace hbf
