// hbfriction — the harmonic-balance residual and its Jacobians (harmonic_balance.hpp): the
// dispatch between the formulations, the full formulation (every DOF's harmonics), and the
// contacts' periodic forces by AFT.
#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

void HarmonicBalance::shift_force(int c, double omega, const Eigen::VectorXd& q, FrictionEvaluation& e,
                                  bool jacobian) const {
    // f'_a = f_a - kappa_a q_a - delta_a q_a' along each direction a of the contact (the springs
    // and dampers the condensed structure carries).
    const int n = coefficients();
    const Eigen::MatrixXd& D1 = fourier_->derivative();
    for (int j = 0; j < signal_count_[static_cast<std::size_t>(c)]; ++j) {
        const int a = signal_first_[static_cast<std::size_t>(c)] + j;
        const double kappa = shift_stiffness_(a), delta = shift_damping_(a);
        const Eigen::VectorXd dq = D1 * q.segment(j * n, n);
        e.force.segment(j * n, n) -= kappa * q.segment(j * n, n) + delta * omega * dq;
        if (!jacobian) continue;
        auto block = e.force_q.block(j * n, j * n, n, n);
        block -= delta * omega * D1;
        block.diagonal().array() -= kappa;
        e.force_omega.segment(j * n, n) -= delta * dq;
    }
}

FrictionEvaluation& HarmonicBalance::evaluate_contact(const Eigen::VectorXd& x, double omega, int c, bool jacobian) {
    const auto cc = static_cast<std::size_t>(c);
    const int n = coefficients(), offset = state_offset_[cc], first = signal_first_[cc];
    const Eigen::VectorXd q = x.segment(first * n, signal_count_[cc] * n);
    const Eigen::VectorXd z =
        offset < 0 ? Eigen::VectorXd() : Eigen::VectorXd(x.segment(offset, state_count_[cc] * n));
    models_[cc]->evaluate(*fourier_, omega, q, z, scratch_, jacobian);
    shift_force(c, omega, q, scratch_, jacobian);
    return scratch_;
}

Eigen::MatrixXd HarmonicBalance::shifted_forces(const Eigen::VectorXd& x, double omega) {
    const int n = coefficients(), nc = static_cast<int>(models_.size());
    Eigen::MatrixXd forces(n, signals_);
    for (int c = 0; c < nc; ++c) {
        const Eigen::VectorXd q = relative_all(x, c);
        models_[static_cast<std::size_t>(c)]->evaluate(*fourier_, omega, q, state_all(x, c), scratch_, false);
        shift_force(c, omega, q, scratch_, false);
        forces.middleCols(signal_first_[static_cast<std::size_t>(c)], signal_count_[static_cast<std::size_t>(c)]) =
            Eigen::Map<const Eigen::MatrixXd>(scratch_.force.data(), n, signal_count_[static_cast<std::size_t>(c)]);
    }
    return forces;
}

void HarmonicBalance::evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                               Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega) {
    ++statistics_.residuals;
    if (jacobian) ++statistics_.jacobians;
    if (cyclic_) {
        // A sector: every DOF's balance at X = P U, folded onto the independent DOFs by P^T.
        evaluate_all(all_harmonics(x), omega, all_residual_, jacobian ? &all_jacobian_ : nullptr,
                     jacobian_omega ? &all_jacobian_omega_ : nullptr);
        residual = cyclic_map_.transpose() * all_residual_;
        if (jacobian_omega) *jacobian_omega = cyclic_map_.transpose() * all_jacobian_omega_;
        if (jacobian) {
            const Eigen::MatrixXd jp = all_jacobian_ * cyclic_map_;
            *jacobian = cyclic_map_.transpose() * jp;
        }
        return;
    }
    if (!odd_) {
        evaluate_all(x, omega, residual, jacobian, jacobian_omega);
        return;
    }
    // Odd harmonics only: the balance of every harmonic at the symmetric x, restricted to the
    // balanced rows and columns (the others vanish by the half-wave symmetry).
    evaluate_all(all_harmonics(x), omega, all_residual_, jacobian ? &all_jacobian_ : nullptr,
                 jacobian_omega ? &all_jacobian_omega_ : nullptr);
    residual.resize(unknowns_);
    if (jacobian) jacobian->resize(unknowns_, unknowns_);
    if (jacobian_omega) jacobian_omega->resize(unknowns_);
    for (int i = 0; i < unknowns_; ++i) {
        const int row = balanced_index_[static_cast<std::size_t>(i)];
        residual(i) = all_residual_(row);
        if (jacobian_omega) (*jacobian_omega)(i) = all_jacobian_omega_(row);
    }
    if (jacobian)
        for (int j = 0; j < unknowns_; ++j) {
            const int column = balanced_index_[static_cast<std::size_t>(j)];
            for (int i = 0; i < unknowns_; ++i)
                (*jacobian)(i, j) = all_jacobian_(balanced_index_[static_cast<std::size_t>(i)], column);
        }
}

void HarmonicBalance::evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                               StructuredJacobian& jacobian, Eigen::VectorXd* jacobian_omega) {
    if (!structured_)
        throw InvalidInput("harmonic balance: the structured Jacobian needs jacobian = structured");
    ++statistics_.residuals;
    ++statistics_.jacobians;
    evaluate_structured(x, omega, residual, &jacobian, jacobian_omega);
}

void HarmonicBalance::evaluate_all(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                                   Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega) {
    if (structured_ && jacobian == nullptr)
        evaluate_structured(x, omega, residual, nullptr, jacobian_omega);
    else if (condensed_)
        evaluate_condensed(x, omega, residual, jacobian, jacobian_omega);
    else
        evaluate_full(x, omega, residual, jacobian, jacobian_omega);
}

void HarmonicBalance::evaluate_full(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                                    Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega) {
    detail::Stopwatch watch;
    const int n = coefficients(), dofs = system_.dofs();
    const Eigen::MatrixXd& D1 = fourier_->derivative();
    const Eigen::MatrixXd M(system_.mass), C(system_.damping), K(system_.stiffness);
    const Eigen::Map<const Eigen::MatrixXd> Y(x.data(), n, dofs);
    residual.resize(all_unknowns_);
    Eigen::Map<Eigen::MatrixXd> RY(residual.data(), n, dofs);

    // Linear structure: D^2 Y M + D Y C + Y K - e_cos_h F^T.
    const Eigen::MatrixXd D1Y = D1 * Y;
    const Eigen::MatrixXd D2Y = D1 * D1Y;
    RY = omega * omega * D2Y * M + omega * D1Y * C + Y * K;
    RY.row(2 * load_harmonic() - 1) -= system_.excitation.transpose();
    if (system_.static_load.size() > 0) RY.row(0) -= system_.static_load.transpose();
    statistics_.structure_seconds += watch.lap();
    const bool want_jacobian = jacobian != nullptr || jacobian_omega != nullptr;
    if (jacobian) {
        jacobian->setZero(all_unknowns_, all_unknowns_);
        const Eigen::MatrixXd D2 = D1 * D1;
        const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
        for (int i = 0; i < dofs; ++i)
            for (int j = 0; j < dofs; ++j)
                jacobian->block(i * n, j * n, n, n) = K(i, j) * I + omega * C(i, j) * D1 + omega * omega * M(i, j) * D2;
    }
    if (jacobian_omega) {
        jacobian_omega->setZero(all_unknowns_);
        Eigen::Map<Eigen::MatrixXd>(jacobian_omega->data(), n, dofs) = 2.0 * omega * D2Y * M + D1Y * C;
    }

    statistics_.jacobian_seconds += watch.lap();

    // Friction contacts through the AFT: contact c's force along each of its directions w_a,
    // sum_a f_a w_a^T, and its Jacobian sum_ab w_a(i) w_b(j) df_a/dq_b.
    for (std::size_t c = 0; c < models_.size(); ++c) {
        const int first = signal_first_[c], count = signal_count_[c];
        const Eigen::VectorXd q = relative_all(x, static_cast<int>(c));
        const int offset = state_offset_[c], states = state_count_[c] * n;
        const Eigen::VectorXd z = offset < 0 ? Eigen::VectorXd() : Eigen::VectorXd(x.segment(offset, states));
        FrictionEvaluation& e = scratch_;
        models_[c]->evaluate(*fourier_, omega, q, z, e, want_jacobian);
        const double model_seconds = watch.lap();
        statistics_.aft_seconds += model_seconds - e.jacobian_seconds;
        statistics_.jacobian_seconds += e.jacobian_seconds;
        for (int a = 0; a < count; ++a) {
            const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(first + a)];
            RY += e.force.segment(a * n, n) * w.transpose();
            if (jacobian_omega)
                Eigen::Map<Eigen::MatrixXd>(jacobian_omega->data(), n, dofs) += e.force_omega.segment(a * n, n) * w.transpose();
            if (!jacobian) continue;
            for (int b = 0; b < count; ++b) {
                const Eigen::VectorXd& v = directions_[static_cast<std::size_t>(first + b)];
                const auto block = e.force_q.block(a * n, b * n, n, n);
                for (int i = 0; i < dofs; ++i) {
                    if (w(i) == 0.0) continue;
                    for (int j = 0; j < dofs; ++j)
                        if (v(j) != 0.0) jacobian->block(i * n, j * n, n, n) += w(i) * v(j) * block;
                }
            }
        }
        if (offset >= 0) {  // the state signals: rows of their own, read by every direction
            residual.segment(offset, states) = e.state_residual;
            if (jacobian) {
                for (int a = 0; a < count; ++a) {
                    const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(first + a)];
                    for (int i = 0; i < dofs; ++i) {
                        if (w(i) == 0.0) continue;
                        jacobian->block(i * n, offset, n, states) += w(i) * e.force_z.middleRows(a * n, n);
                        jacobian->block(offset, i * n, states, n) += w(i) * e.state_q.middleCols(a * n, n);
                    }
                }
                jacobian->block(offset, offset, states, states) += e.state_z;
            }
            if (jacobian_omega) jacobian_omega->segment(offset, states) += e.state_omega;
        }
        statistics_.jacobian_seconds += watch.lap();  // residual/Jacobian assembly of this contact
    }
}

}  // namespace hbf
