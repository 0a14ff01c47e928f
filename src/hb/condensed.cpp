// hbfriction — the condensed formulation of harmonic balance (harmonic_balance.hpp): the
// structure solved per harmonic by the receptance, the residual on the contacts' relative
// displacements with its dense and structured Jacobians, the DOFs recovered from a solution,
// and the free motions of nonlinear modes.
#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {
/// Scales the residual's rows of signal a and harmonic k by scale(k, a) (rows a n + row, k =
/// (row + 1) / 2, n = 2H + 1 rows a signal) and its omega-derivative accordingly (d(s r)/dw = s
/// dr/dw + ds/dw r); `each(i, s)` does the Jacobian's part of row i.
template <class Each>
void scale_rows(int ns, int n, const Eigen::MatrixXd& scale, const Eigen::MatrixXd& scale_omega,
                Eigen::VectorXd& residual, Eigen::VectorXd* jacobian_omega, Each each) {
    for (int a = 0; a < ns; ++a)
        for (int row = 0; row < n; ++row) {
            const int k = (row + 1) / 2;
            const double s = scale(k, a);
            const int i = a * n + row;
            if (jacobian_omega) (*jacobian_omega)(i) = s * (*jacobian_omega)(i) + scale_omega(k, a) * residual(i);
            residual(i) *= s;
            each(i, s);
        }
}
}  // namespace

bool HarmonicBalance::prepare_receptance(double omega) {
    if (omega == receptance_omega_) return structure_failure_.empty();
    receptance_omega_ = omega;
    structure_failure_.clear();
    if (!(omega > 0.0) || !std::isfinite(omega)) {
        structure_failure_ = "w = " + format_number(omega) + " is not a positive frequency";
        return false;
    }
    const int ns = signals_;
    if (harmonic_.use_count() > 1) {  // a structured Jacobian holds the old receptances
        auto fresh = std::make_shared<std::vector<Receptance::Harmonic>>(static_cast<std::size_t>(harmonics() + 1));
        (*fresh)[0] = (*harmonic_)[0];
        harmonic_ = std::move(fresh);
    }
    row_scale_.resize(harmonics() + 1, ns);
    row_scale_omega_.resize(harmonics() + 1, ns);
    for (int k = 0; k <= harmonics(); ++k) {
        if (skipped(k)) {  // odd harmonics only: the even ones are never balanced nor solved
            row_scale_.row(k).setOnes();
            row_scale_omega_.row(k).setZero();
            continue;
        }
        Receptance::Harmonic& h = (*harmonic_)[static_cast<std::size_t>(k)];
        // The N-long solution: in dofs(). Structured with the modal receptance: G_k factored.
        if (k > 0) h = receptance_->solve(k, omega, carries_load(k), false, !structured_);
        if (!h.ok) {
            structure_failure_ = h.message;
            return false;
        }
        // Row scale 1 / min(|G_k,cc|, G_0,cc) (bounded near an antiresonance, where G_k,cc -> 0)
        // and its omega-derivative -Re(conj(g) g') / |g|^3. With G_k factored (G_B (I + S
        // G_B)^-1) its diagonal is not formed: the contact's own part g = G_B,cc / (1 + s_c
        // G_B,cc) stands for it (exact for one contact; a scale of the same size for many).
        const Receptance::Harmonic::Factored* f = h.factored.get();
        for (int c = 0; c < ns; ++c) {
            std::complex<double> g, g_omega;
            if (f) {
                const std::complex<double> b = f->g_b(c, c), b_omega = f->g_b_omega(c, c), s = f->shift(c);
                const std::complex<double> denominator = 1.0 + s * b;
                g = b / denominator;
                g_omega = (b_omega - f->shift_omega(c) * b * b) / (denominator * denominator);
            } else {
                g = h.contact(c, c);
                g_omega = k > 0 ? h.contact_omega(c, c) : 0.0;
            }
            // A free motion (set_free_motion) sits where G_1,cc -> 0 (an exact Coulomb contact
            // stuck: the mode is G's antiresonance, G_1's entries a cancellation), so its rows
            // keep the static scale 1 / G_0,cc: constant in omega and xi, and G_1's rounding not
            // magnified (a floor of 1e-3 G_0 left 3e-8 of the beam's stuck mode unconverged).
            const double floor = (free_ ? 1.0 : 1e-10) * static_flexibility_(c), size = std::abs(g);
            const bool dynamic = size < static_flexibility_(c) && size > floor && k > 0;
            row_scale_(k, c) = 1.0 / std::max(std::min(size, static_flexibility_(c)), floor);
            row_scale_omega_(k, c) =
                dynamic ? -std::real(std::conj(g) * g_omega) / (size * size * size) : 0.0;
        }
    }
    return true;
}

void HarmonicBalance::add_receptance(int c, int d, const Eigen::Ref<const Eigen::MatrixXd>& in,
                                     Eigen::Ref<Eigen::MatrixXd> out, bool omega_derivative) const {
    // G_0 is real; harmonic k: G_k = a + i b maps (c_k, s_k) to (a c_k + b s_k, -b c_k + a s_k),
    // since y = Re(Y e^{i k theta}) = c cos + s sin with Y = c - i s.
    if (!omega_derivative) out.row(0) += (*harmonic_)[0].contact(c, d).real() * in.row(0);
    for (int k = 1; k <= harmonics(); ++k) {
        if (skipped(k)) continue;
        const Receptance::Harmonic& h = (*harmonic_)[static_cast<std::size_t>(k)];
        const std::complex<double> g = omega_derivative ? h.contact_omega(c, d) : h.contact(c, d);
        const double a = g.real(), b = g.imag();
        out.row(2 * k - 1) += a * in.row(2 * k - 1) + b * in.row(2 * k);
        out.row(2 * k) += -b * in.row(2 * k - 1) + a * in.row(2 * k);
    }
}

bool HarmonicBalance::hold_switches(bool on) {
    bool any = false;
    for (const auto& model : models_) any = model->hold_switch(on) || any;
    return any;
}

void HarmonicBalance::set_free_motion(double xi) {
    if (!condensed_)
        throw InvalidInput("set_free_motion: the condensed formulation's (the full formulation adds -xi w (D1 Y) M itself)");
    if (odd_) throw InvalidInput("set_free_motion: not with odd harmonics only (a free motion may have even harmonics)");
    if (free_ && xi == receptance_->mass_damping()) return;
    receptance_->set_mass_damping(xi);
    free_ = true;
    receptance_omega_ = -1.0;  // every receptance k >= 1 again at the next evaluation
}

Eigen::MatrixXcd HarmonicBalance::contact_response(int k, double omega) {
    if (!condensed_) throw InvalidInput("contact_response: the condensed formulation's");
    if (k < 1 || k > harmonics())
        throw InvalidInput("contact_response: harmonic k = " + std::to_string(k) + " is out of range: allowed 1.." +
                           std::to_string(harmonics()));
    const Receptance::Harmonic h = receptance_->solve(k, omega, false, true, true);
    if (!h.ok || !h.solution.allFinite()) return {};
    return h.solution.leftCols(signals_);
}

Eigen::VectorXcd HarmonicBalance::free_response(int k, double omega, const Eigen::VectorXcd& lambda) {
    if (!free_) throw InvalidInput("free_response: after set_free_motion");
    if (lambda.size() != signals_) throw InvalidInput("free_response: one force per signal is needed");
    if (receptance_->modes() > 0) {
        if (k < 1 || k > harmonics())
            throw InvalidInput("free_response: harmonic k = " + std::to_string(k) + " is out of range: allowed 1.." +
                               std::to_string(harmonics()));
        Eigen::VectorXcd y = receptance_->modal_response(k, omega, lambda, false);
        if (!y.allFinite()) return {};
        return y;
    }
    const Eigen::MatrixXcd response = contact_response(k, omega);
    if (response.size() == 0) return {};
    return -(response * lambda);
}

bool HarmonicBalance::free_motion_xi_derivative(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& d_xi) {
    if (!free_) throw InvalidInput("free_motion_xi_derivative: after set_free_motion");
    if (!prepare_receptance(omega)) return false;
    const int n = coefficients(), ns = signals_;
    const Eigen::MatrixXd forces = shifted_forces(x, omega);
    d_xi.setZero(all_unknowns_);
    Eigen::Map<Eigen::MatrixXd> rows(d_xi.data(), n, ns);
    for (int k = 1; k <= harmonics(); ++k) {
        const Receptance::Harmonic& h = (*harmonic_)[static_cast<std::size_t>(k)];
        const Eigen::VectorXcd y = receptance_->apply_mass_damping(h, harmonic_amplitudes(forces, k));
        if (y.size() != ns || !y.allFinite()) return false;
        add_harmonic_amplitudes(y, k, rows);
    }
    for (int a = 0; a < ns; ++a)
        for (int row = 0; row < n; ++row) rows(row, a) *= row_scale_((row + 1) / 2, a);
    return true;
}

Eigen::VectorXcd HarmonicBalance::shifted_force_harmonic(const Eigen::VectorXd& x, double omega, int k,
                                                         Eigen::MatrixXcd* d_x) {
    if (!condensed_ || odd_) throw InvalidInput("shifted_force_harmonic: the condensed formulation's, every harmonic");
    if (k < 1 || k > harmonics())
        throw InvalidInput("shifted_force_harmonic: harmonic k = " + std::to_string(k) + " is out of range: allowed 1.." +
                           std::to_string(harmonics()));
    using Complex = std::complex<double>;
    const int n = coefficients(), nc = static_cast<int>(models_.size());
    Eigen::VectorXcd lambda(signals_);
    if (d_x) d_x->setZero(signals_, unknowns_);
    for (int c = 0; c < nc; ++c) {
        const auto cc = static_cast<std::size_t>(c);
        const int offset = state_offset_[cc], first = signal_first_[cc], count = signal_count_[cc];
        const int states = state_count_[cc] * n;
        const FrictionEvaluation& e = evaluate_contact(x, omega, c, d_x != nullptr);
        for (int j = 0; j < count; ++j) {
            const int a = first + j, cos_row = j * n + 2 * k - 1, sin_row = cos_row + 1;
            lambda(a) = Complex(e.force(cos_row), -e.force(sin_row));  // c - i s
            if (!d_x) continue;
            for (int col = 0; col < count * n; ++col)
                (*d_x)(a, first * n + col) = Complex(e.force_q(cos_row, col), -e.force_q(sin_row, col));
            for (int col = 0; offset >= 0 && col < states; ++col)
                (*d_x)(a, offset + col) = Complex(e.force_z(cos_row, col), -e.force_z(sin_row, col));
        }
    }
    return lambda;
}

Eigen::MatrixXd HarmonicBalance::dofs(const Eigen::VectorXd& unknowns, double omega) {
    const int n = coefficients(), dofs = system_.dofs();
    const Eigen::VectorXd x = all_harmonics(unknowns);
    if (!condensed_) return Eigen::Map<const Eigen::MatrixXd>(x.data(), n, dofs);
    Eigen::MatrixXd y = Eigen::MatrixXd::Constant(n, dofs, std::numeric_limits<double>::quiet_NaN());
    if (!prepare_receptance(omega)) return y;
    // Y_k = Z_k^-1 (F_k - W Lambda_k), F on harmonic h only; in the real layout (c, s) with
    // Y = c - i s, as in add_receptance.
    const int ns = signals_;
    const Eigen::MatrixXd forces = shifted_forces(x, omega);
    // Z_k^-1 [W, F]: kept by the direct solve (the modal one applies Z_k^-1 to the forces below).
    auto solved = [&](int k) -> const Receptance::Harmonic& {
        Receptance::Harmonic& h = (*harmonic_)[static_cast<std::size_t>(k)];
        if (h.solution.size() == 0) h = receptance_->solve(k, omega, carries_load(k), true);
        return h;
    };
    if (odd_)
        y.row(0).setZero();  // no mean by the half-wave symmetry
    else if (modes_ > 0)  // the modal receptance applied to the mean forces (no N x signals matrix)
        y.row(0) = receptance_->modal_response(0, omega, forces.row(0).transpose().cast<std::complex<double>>(), false)
                       .real()
                       .transpose();
    else
        y.row(0) = -(solved(0).solution.leftCols(ns).real() * forces.row(0).transpose()).transpose();
    if (static_deflection_.size() > 0) y.row(0) += static_deflection_.transpose();
    for (int k = 1; k <= harmonics(); ++k) {
        if (skipped(k)) {  // zero by the half-wave symmetry
            y.row(2 * k - 1).setZero();
            y.row(2 * k).setZero();
            continue;
        }
        const Eigen::VectorXcd lambda = forces.row(2 * k - 1).transpose().cast<std::complex<double>>() -
                                        std::complex<double>(0.0, 1.0) * forces.row(2 * k).transpose();
        Eigen::VectorXcd amplitude;
        const Receptance::Harmonic& kept = (*harmonic_)[static_cast<std::size_t>(k)];
        if (modes_ > 0 && kept.solution.size() == 0) {
            // The modal receptance applies Z'_k^-1 to this one right-hand side: O(N (m + n_c))
            // instead of forming Z'_k^-1 W (N x n_c; 90 % of a 99-node interface's FRF).
            amplitude = receptance_->modal_response(k, omega, lambda, carries_load(k));
        } else {
            const Receptance::Harmonic& h = solved(k);
            amplitude = -h.solution.leftCols(ns) * lambda;
            if (carries_load(k)) amplitude += h.solution.col(ns);
        }
        y.row(2 * k - 1) = amplitude.real().transpose();
        y.row(2 * k) = -amplitude.imag().transpose();
    }
    return y;
}

double HarmonicBalance::amplitude_bound(const Eigen::VectorXd& x, double omega) {
    if (condensed_ && modes_ > 0) {
        if (!prepare_receptance(omega)) return std::numeric_limits<double>::infinity();
        const Eigen::MatrixXd forces = shifted_forces(all_harmonics(x), omega);
        double bound = 0.0;
        for (int k = 0; k <= harmonics(); ++k) {
            if (skipped(k)) continue;
            const Eigen::VectorXcd lambda =
                k == 0 ? Eigen::VectorXcd(forces.row(0).transpose().cast<std::complex<double>>())
                       : Eigen::VectorXcd(forces.row(2 * k - 1).transpose().cast<std::complex<double>>() -
                                          std::complex<double>(0.0, 1.0) * forces.row(2 * k).transpose());
            bound += receptance_->response_bound(k, omega, lambda, carries_load(k));
        }
        // the static load's deflection K'^-1 F_s on harmonic 0 (dofs() adds it)
        if (static_deflection_.size() > 0) bound += static_deflection_.cwiseAbs().maxCoeff();
        return bound;
    }
    const Eigen::MatrixXd y = dofs(x, omega);
    if (!y.allFinite()) return std::numeric_limits<double>::infinity();
    double bound = 0.0;
    for (int i = 0; i < system_.dofs(); ++i) {
        const auto c = y.col(i);
        double b = std::abs(c(0));
        for (int k = 1; k <= harmonics(); ++k) b += std::hypot(c(2 * k - 1), c(2 * k));
        bound = std::max(bound, b);
    }
    return bound;
}

void HarmonicBalance::evaluate_structured(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                                          StructuredJacobian* jacobian, Eigen::VectorXd* jacobian_omega) {
    detail::Stopwatch watch;
    const int n = coefficients(), ns = signals_, nc = static_cast<int>(models_.size());
    residual.resize(all_unknowns_);
    if (jacobian_omega) jacobian_omega->setZero(all_unknowns_);
    if (!prepare_receptance(omega)) {
        residual.setConstant(std::numeric_limits<double>::quiet_NaN());
        statistics_.structure_seconds += watch.lap();
        return;
    }
    const bool want_jacobian = jacobian != nullptr || jacobian_omega != nullptr;
    // q - q0 (q0 on harmonic h, and the static load's share on harmonic 0), as evaluate_condensed.
    Eigen::Map<Eigen::MatrixXd> rq(residual.data(), n, ns);
    rq = Eigen::Map<const Eigen::MatrixXd>(x.data(), n, ns);
    const Receptance::Harmonic& loaded = (*harmonic_)[static_cast<std::size_t>(load_harmonic())];
    if (!free_) add_harmonic_amplitudes(-loaded.contact_load, load_harmonic(), rq);
    if (static_contact_.size() > 0) rq.row(0) -= static_contact_.transpose();
    Eigen::Map<Eigen::MatrixXd> rw(jacobian_omega ? jacobian_omega->data() : nullptr, jacobian_omega ? n : 0,
                                   jacobian_omega ? ns : 0);
    if (jacobian_omega && !free_) add_harmonic_amplitudes(-loaded.contact_load_omega, load_harmonic(), rw);
    if (jacobian) {
        jacobian->coefficients_ = n;
        jacobian->signals_ = ns;
        jacobian->harmonics_ = harmonics_;
        jacobian->first_ = signal_first_;
        jacobian->count_ = signal_count_;
        jacobian->states_ = (all_unknowns_ - ns * n) / n;
        jacobian->state_count_ = state_count_;
        jacobian->state_first_.resize(static_cast<std::size_t>(nc));
        for (int d = 0; d < nc; ++d) {
            const int offset = state_offset_[static_cast<std::size_t>(d)];
            jacobian->state_first_[static_cast<std::size_t>(d)] = offset < 0 ? 0 : (offset - ns * n) / n;
        }
        jacobian->df_.resize(static_cast<std::size_t>(nc));
        jacobian->fz_.resize(static_cast<std::size_t>(nc));
        jacobian->rq_.resize(static_cast<std::size_t>(nc));
        jacobian->rz_.resize(static_cast<std::size_t>(nc));
    }
    statistics_.structure_seconds += watch.lap();
    // Every contact's forces (and their blocks) through the AFT.
    forces_.resize(n, ns);
    if (jacobian_omega) forces_omega_.resize(n, ns);
    for (int d = 0; d < nc; ++d) {
        const auto dd = static_cast<std::size_t>(d);
        const int first = signal_first_[dd], count = signal_count_[dd];
        const FrictionEvaluation& e = evaluate_contact(x, omega, d, want_jacobian);
        const double model_seconds = watch.lap();
        statistics_.aft_seconds += model_seconds - e.jacobian_seconds;
        statistics_.jacobian_seconds += e.jacobian_seconds;
        Eigen::Map<Eigen::VectorXd>(forces_.col(first).data(), count * n) = e.force;
        if (jacobian_omega) Eigen::Map<Eigen::VectorXd>(forces_omega_.col(first).data(), count * n) = e.force_omega;
        if (jacobian) jacobian->df_[dd] = e.force_q;
        const int offset = state_offset_[dd];
        if (offset >= 0) {  // the states' rows (unscaled) and their blocks
            const int states = state_count_[dd] * n;
            residual.segment(offset, states) = e.state_residual;
            if (jacobian) {
                jacobian->fz_[dd] = e.force_z;
                jacobian->rq_[dd] = e.state_q;
                jacobian->rz_[dd] = e.state_z;
            }
            if (jacobian_omega) jacobian_omega->segment(offset, states) = e.state_omega;
        }
        statistics_.jacobian_seconds += watch.lap();
    }
    // + Gr f, all contacts at once per harmonic; d/domega: Gr f_omega + Gr' f.
    for (int k = 0; k <= harmonics_; ++k) {
        const Receptance::Harmonic& h = (*harmonic_)[static_cast<std::size_t>(k)];
        const Eigen::VectorXcd f = harmonic_amplitudes(forces_, k);
        add_harmonic_amplitudes(h.apply(f), k, rq);
        if (!jacobian_omega) continue;
        Eigen::VectorXcd y = h.apply(harmonic_amplitudes(forces_omega_, k));
        if (k > 0) y += h.apply_omega(f);
        add_harmonic_amplitudes(y, k, rw);
    }
    statistics_.structure_seconds += watch.lap();
    // Rows scaled by S (evaluate_condensed); the scale depends on omega.
    if (jacobian) jacobian->row_scale_.setOnes(all_unknowns_);
    scale_rows(ns, n, row_scale_, row_scale_omega_, residual, jacobian_omega, [jacobian](int i, double scale) {
        if (jacobian) jacobian->row_scale_(i) = scale;
    });
    if (jacobian) jacobian->receptance_ = harmonic_;
    statistics_.jacobian_seconds += watch.lap();
}

void HarmonicBalance::evaluate_condensed(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                                         Eigen::MatrixXd* jacobian, Eigen::VectorXd* jacobian_omega) {
    detail::Stopwatch watch;
    const int n = coefficients(), ns = signals_, nc = static_cast<int>(models_.size());
    residual.resize(all_unknowns_);
    if (!prepare_receptance(omega)) {
        residual.setConstant(std::numeric_limits<double>::quiet_NaN());
        if (jacobian) jacobian->setZero(all_unknowns_, all_unknowns_);
        if (jacobian_omega) jacobian_omega->setZero(all_unknowns_);
        statistics_.structure_seconds += watch.lap();
        return;
    }
    for (auto& h : *harmonic_) h.materialize();  // structured HB asked for a dense Jacobian (tests)
    const bool want_jacobian = jacobian != nullptr || jacobian_omega != nullptr;
    // The rows of every signal a before scaling: q_a - q0_a + sum_b Gr_ab f_b (q0 on harmonic h
    // only).
    Eigen::Map<Eigen::MatrixXd> rq(residual.data(), n, ns);
    rq = Eigen::Map<const Eigen::MatrixXd>(x.data(), n, ns);
    const int cos_row = 2 * load_harmonic() - 1, sin_row = cos_row + 1;
    const Receptance::Harmonic& loaded = (*harmonic_)[static_cast<std::size_t>(load_harmonic())];
    for (int a = 0; a < ns && !free_; ++a) {
        rq(cos_row, a) -= loaded.contact_load(a).real();
        rq(sin_row, a) += loaded.contact_load(a).imag();  // s = -Im
    }
    if (static_contact_.size() > 0) rq.row(0) -= static_contact_.transpose();
    if (jacobian) {
        jacobian->setZero(all_unknowns_, all_unknowns_);
        jacobian->topLeftCorner(ns * n, ns * n).setIdentity();
    }
    if (jacobian_omega) {
        jacobian_omega->setZero(all_unknowns_);
        for (int a = 0; a < ns && !free_; ++a) {
            (*jacobian_omega)(a * n + cos_row) = -loaded.contact_load_omega(a).real();
            (*jacobian_omega)(a * n + sin_row) = loaded.contact_load_omega(a).imag();
        }
    }
    statistics_.structure_seconds += watch.lap();
    for (int d = 0; d < nc; ++d) {
        const auto dd = static_cast<std::size_t>(d);
        const int offset = state_offset_[dd], first = signal_first_[dd], count = signal_count_[dd];
        const int states = state_count_[dd] * n;
        const FrictionEvaluation& e = evaluate_contact(x, omega, d, want_jacobian);
        const double model_seconds = watch.lap();
        statistics_.aft_seconds += model_seconds - e.jacobian_seconds;
        statistics_.jacobian_seconds += e.jacobian_seconds;
        for (int a = 0; a < ns; ++a)
            for (int j = 0; j < count; ++j) {  // the force along direction b = first + j
                const int b = first + j;
                add_receptance(a, b, e.force.segment(j * n, n), rq.col(a));
                if (jacobian) {
                    add_receptance(a, b, e.force_q.middleRows(j * n, n), jacobian->block(a * n, first * n, n, count * n));
                    if (offset >= 0)
                        add_receptance(a, b, e.force_z.middleRows(j * n, n), jacobian->block(a * n, offset, n, states));
                }
                if (jacobian_omega) {
                    auto column = jacobian_omega->segment(a * n, n);
                    add_receptance(a, b, e.force_omega.segment(j * n, n), column);
                    add_receptance(a, b, e.force.segment(j * n, n), column, true);
                }
            }
        if (offset >= 0) {
            residual.segment(offset, states) = e.state_residual;
            if (jacobian) {
                jacobian->block(offset, first * n, states, count * n) = e.state_q;
                jacobian->block(offset, offset, states, states) = e.state_z;
            }
            if (jacobian_omega) jacobian_omega->segment(offset, states) = e.state_omega;
        }
        statistics_.jacobian_seconds += watch.lap();
    }
    // Scale signal a's rows of harmonic k by 1 / |G_k,aa|: a force, and for one contact on one
    // DOF the full formulation's row up to its sign. The scale depends on omega (row_scale_omega_).
    scale_rows(ns, n, row_scale_, row_scale_omega_, residual, jacobian_omega, [jacobian](int i, double scale) {
        if (jacobian) jacobian->row(i) *= scale;
    });
    statistics_.jacobian_seconds += watch.lap();
}

}  // namespace hbf
