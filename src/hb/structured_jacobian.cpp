// The condensed Jacobian in its structure and its Krylov solver (structured_jacobian.hpp).
#include "hbf/structured_jacobian.hpp"

#include <algorithm>
#include <cmath>

namespace hbf {

Eigen::VectorXcd harmonic_amplitudes(const Eigen::Ref<const Eigen::MatrixXd>& v, int k) {
    if (k == 0) return v.row(0).transpose().cast<std::complex<double>>();
    Eigen::VectorXcd y(v.cols());
    y.real() = v.row(2 * k - 1).transpose();
    y.imag() = -v.row(2 * k).transpose();
    return y;
}
void add_harmonic_amplitudes(const Eigen::VectorXcd& y, int k, Eigen::Ref<Eigen::MatrixXd> v) {
    if (k == 0) {
        v.row(0) += y.real().transpose();
        return;
    }
    v.row(2 * k - 1) += y.real().transpose();
    v.row(2 * k) -= y.imag().transpose();
}

void StructuredJacobian::apply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
    const int n = coefficients_, top = n * signals_;
    work_.resize(n, signals_);
    out.resize(size());
    // u = Df v_q + Fz v_z, contact by contact (each one's directions are consecutive signals,
    // its states consecutive states, so their coefficients are consecutive segments of v);
    // the states' rows Rq v_q + Rz v_z likewise.
    for (std::size_t d = 0; d < df_.size(); ++d) {
        const int length = count_[d] * n, start = first_[d] * n;
        Eigen::Map<Eigen::VectorXd> u(work_.data() + start, length);
        u.noalias() = df_[d] * v.segment(start, length);
        if (state_count_[d] == 0) continue;
        const int states = state_count_[d] * n, at = top + state_first_[d] * n;
        u.noalias() += fz_[d] * v.segment(at, states);
        out.segment(at, states).noalias() = rq_[d] * v.segment(start, length);
        out.segment(at, states).noalias() += rz_[d] * v.segment(at, states);
    }
    // v_q + Gr u, harmonic by harmonic.
    out.head(top) = v.head(top);
    Eigen::Map<Eigen::MatrixXd> o(out.data(), n, signals_);
    const auto& g = *receptance_;
    for (int k = 0; k <= harmonics_; ++k)
        add_harmonic_amplitudes(g[static_cast<std::size_t>(k)].apply(harmonic_amplitudes(work_, k)), k, o);
}

Eigen::VectorXd StructuredJacobian::abs_row_sums() const {
    const int n = coefficients_, top = n * signals_;
    Eigen::MatrixXd u(n, signals_);
    Eigen::VectorXd all = Eigen::VectorXd::Zero(size());
    for (std::size_t d = 0; d < df_.size(); ++d) {
        const int length = count_[d] * n, start = first_[d] * n;
        Eigen::Map<Eigen::VectorXd> row(u.data() + start, length);
        row = df_[d].cwiseAbs().rowwise().sum();
        if (state_count_[d] == 0) continue;
        const int states = state_count_[d] * n, at = top + state_first_[d] * n;
        row += fz_[d].cwiseAbs().rowwise().sum();
        all.segment(at, states) = rq_[d].cwiseAbs().rowwise().sum() + rz_[d].cwiseAbs().rowwise().sum();
    }
    Eigen::Map<Eigen::MatrixXd> sums(all.data(), n, signals_);
    sums.setOnes();
    const auto& g = *receptance_;
    for (int k = 0; k <= harmonics_; ++k) {
        // G_k factored: formed here, on a copy of its factors (rarely asked: the corrector's
        // noise test); formed already: used as it is.
        const Receptance::Harmonic& held = g[static_cast<std::size_t>(k)];
        Receptance::Harmonic formed;
        if (held.contact.size() == 0) {
            formed.factored = held.factored;
            formed.materialize();
        }
        const Eigen::MatrixXcd& gk = held.contact.size() > 0 ? held.contact : formed.contact;
        // |a c + b s| <= |G| sqrt2 max(|c|, |s|): an upper bound per row of the real 2 x 2 form.
        const Eigen::VectorXd larger = k == 0 ? Eigen::VectorXd(u.row(0).transpose())
                                              : Eigen::VectorXd(u.row(2 * k - 1).cwiseMax(u.row(2 * k)).transpose());
        const Eigen::VectorXd bound = (k == 0 ? 1.0 : std::sqrt(2.0)) * (gk.cwiseAbs() * larger);
        if (k == 0) {
            sums.row(0) += bound.transpose();
        } else {
            sums.row(2 * k - 1) += bound.transpose();
            sums.row(2 * k) += bound.transpose();
        }
    }
    return row_scale_.cwiseProduct(all);
}

Eigen::MatrixXd StructuredJacobian::dense() const {
    Eigen::MatrixXd j(size(), size());
    Eigen::VectorXd e = Eigen::VectorXd::Zero(size()), column;
    for (int i = 0; i < size(); ++i) {
        e(i) = 1.0;
        apply(e, column);
        j.col(i) = row_scale_.cwiseProduct(column);
        e(i) = 0.0;
    }
    return j;
}

double StructuredJacobian::bytes() const {
    double b = 8.0 * (row_scale_.size() + work_.size());
    for (const auto* blocks : {&df_, &fz_, &rq_, &rz_})
        for (const auto& d : *blocks) b += 8.0 * static_cast<double>(d.size());
    return b;
}

namespace {
/// Harmonic k of the block between signal i and signal j of a per-contact block B (n
/// coefficients a signal) in complex form: k = 0 its constant entry; k > 0 the
/// rotation-invariant part p + i q of the (cos k, sin k) block [[al, be], [ga, de]], p = (al +
/// de) / 2, q = (be - ga) / 2 (acting on Y = c - i s as [[p, q], [-q, p]]).
std::complex<double> harmonic_entry(const Eigen::MatrixXd& block, int i, int j, int k, int n) {
    if (k == 0) return block(i * n, j * n);
    const int ci = i * n + 2 * k - 1, cj = j * n + 2 * k - 1;
    return {0.5 * (block(ci, cj) + block(ci + 1, cj + 1)), 0.5 * (block(ci, cj + 1) - block(ci + 1, cj))};
}
/// Writes harmonic k of a complex vector y into the rows of v (k = 0: the real parts).
void set_harmonic_amplitudes(const Eigen::Ref<const Eigen::VectorXcd>& y, int k, Eigen::Ref<Eigen::MatrixXd> v) {
    if (k == 0) {
        v.row(0) = y.real().transpose();
        return;
    }
    v.row(2 * k - 1) = y.real().transpose();
    v.row(2 * k) = -y.imag().transpose();
}
}  // namespace

BlockPreconditioner::BlockPreconditioner(const StructuredJacobian& jacobian)
    : coefficients_(jacobian.coefficients_),
      signals_(jacobian.signals_),
      states_(jacobian.states_),
      harmonics_(jacobian.harmonics_) {
    const int n = coefficients_, ns = signals_, nz = states_;
    const auto& g = *jacobian.receptance_;
    lu_.resize(static_cast<std::size_t>(harmonics_ + 1));
    factored_.resize(static_cast<std::size_t>(harmonics_ + 1));
    Eigen::MatrixXcd dbar(ns, ns), fzbar = Eigen::MatrixXcd::Zero(ns, nz);
    Eigen::MatrixXcd pk(ns + nz, ns + nz);
    for (int k = 0; k <= harmonics_; ++k) {
        const Receptance::Harmonic& h = g[static_cast<std::size_t>(k)];
        const auto& factored = h.factored;
        // The bars, block-diagonal by contact: Dbar and Fzbar (the signals' rows), Rqbar and
        // Rzbar (the states' rows, straight into P_k's bottom rows).
        dbar.setZero();
        pk.setZero();
        for (std::size_t d = 0; d < jacobian.df_.size(); ++d) {
            const int first = jacobian.first_[d], count = jacobian.count_[d];
            for (int i = 0; i < count; ++i)
                for (int j = 0; j < count; ++j)
                    dbar(first + i, first + j) = harmonic_entry(jacobian.df_[d], i, j, k, n);
            const int sfirst = jacobian.state_first_[d], scount = jacobian.state_count_[d];
            for (int i = 0; i < scount; ++i) {
                for (int j = 0; j < count; ++j) {
                    fzbar(first + j, sfirst + i) = harmonic_entry(jacobian.fz_[d], j, i, k, n);
                    pk(ns + sfirst + i, first + j) = harmonic_entry(jacobian.rq_[d], i, j, k, n);
                }
                for (int j = 0; j < scount; ++j)
                    pk(ns + sfirst + i, ns + sfirst + j) = harmonic_entry(jacobian.rz_[d], i, j, k, n);
            }
        }
        // P_k's signal rows [I + G_k Dbar, G_k Fzbar], Dbar and Fzbar block-diagonal: column
        // block by column block. With G_k factored (G_B (I + S G_B)^-1 = (I + G_B S)^-1 G_B)
        // those rows are (I + G_B S)^-1 [I + G_B (S + Dbar), G_B Fzbar]: P_k^-1 [v; w] = M^-1
        // [v + G_B S v; w], M the matrix with those rows: one LU, no inverse.
        if (factored) dbar.diagonal() += factored->shift;
        const Eigen::MatrixXcd& gk = factored ? factored->g_b : h.contact;
        pk.topLeftCorner(ns, ns).setIdentity();
        for (std::size_t d = 0; d < jacobian.df_.size(); ++d) {
            const int first = jacobian.first_[d], count = jacobian.count_[d];
            pk.block(0, first, ns, count).noalias() += gk.middleCols(first, count) * dbar.block(first, first, count, count);
            const int sfirst = jacobian.state_first_[d], scount = jacobian.state_count_[d];
            if (scount > 0)
                pk.block(0, ns + sfirst, ns, scount).noalias() =
                    gk.middleCols(first, count) * fzbar.block(first, sfirst, count, scount);
        }
        lu_[static_cast<std::size_t>(k)].compute(pk);
        factored_[static_cast<std::size_t>(k)] = factored;
    }
}

void BlockPreconditioner::apply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
    const int n = coefficients_, ns = signals_, nz = states_;
    out = v;  // harmonics not balanced: identity
    const Eigen::Map<const Eigen::MatrixXd> in(v.data(), n, ns), in_z(v.data() + n * ns, n, nz);
    Eigen::Map<Eigen::MatrixXd> o(out.data(), n, ns), o_z(out.data() + n * ns, n, nz);
    Eigen::VectorXcd z(ns + nz);
    for (int k = 0; k <= harmonics_; ++k) {
        const auto& lu = lu_[static_cast<std::size_t>(k)];
        if (lu.rows() == 0) continue;
        z.head(ns) = harmonic_amplitudes(in, k);
        if (nz > 0) z.tail(nz) = harmonic_amplitudes(in_z, k);
        if (const auto& f = factored_[static_cast<std::size_t>(k)]) z.head(ns) += f->g_b * f->shift.cwiseProduct(z.head(ns));
        const Eigen::VectorXcd y = lu.solve(z);
        set_harmonic_amplitudes(y.head(ns), k, o);  // replace harmonic k of out by y
        if (nz > 0) set_harmonic_amplitudes(y.tail(nz), k, o_z);
    }
}

double BlockPreconditioner::bytes() const {
    double b = 0;
    for (const auto& lu : lu_) b += 16.0 * static_cast<double>(lu.rows()) * static_cast<double>(lu.cols());
    return b;
}

KrylovReport gmres(const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& op,
                   const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& prec,
                   const Eigen::VectorXd& rhs, Eigen::VectorXd& x, double tolerance, int max_iterations,
                   int restart) {
    KrylovReport report;
    const Eigen::Index size = rhs.size();
    x = Eigen::VectorXd::Zero(size);
    const double target = tolerance * rhs.norm();
    if (!(rhs.norm() > 0.0)) {
        report.converged = rhs.allFinite();
        return report;
    }
    const int m = std::max(1, std::min<int>(restart, static_cast<int>(size)));
    Eigen::MatrixXd v(size, m + 1), h = Eigen::MatrixXd::Zero(m + 1, m);
    Eigen::VectorXd cs(m), sn(m), g(m + 1), w, z, r;
    r = rhs;  // x = 0
    double beta = r.norm();
    while (true) {
        v.col(0) = r / beta;
        g.setZero();
        g(0) = beta;
        int j = 0;
        for (; j < m && report.iterations < max_iterations; ++j) {
            prec(v.col(j), z);
            op(z, w);
            ++report.iterations;
            for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
                h(i, j) = w.dot(v.col(i));
                w -= h(i, j) * v.col(i);
            }
            h(j + 1, j) = w.norm();
            for (int i = 0; i < j; ++i) {  // the earlier rotations on the new column
                const double t = cs(i) * h(i, j) + sn(i) * h(i + 1, j);
                h(i + 1, j) = -sn(i) * h(i, j) + cs(i) * h(i + 1, j);
                h(i, j) = t;
            }
            const double rho = std::hypot(h(j, j), h(j + 1, j));
            cs(j) = rho > 0.0 ? h(j, j) / rho : 1.0;
            sn(j) = rho > 0.0 ? h(j + 1, j) / rho : 0.0;
            h(j, j) = rho;
            h(j + 1, j) = 0.0;
            g(j + 1) = -sn(j) * g(j);
            g(j) = cs(j) * g(j);
            const double estimate = std::abs(g(j + 1));
            if (estimate <= target || !(rho > 0.0)) {
                ++j;
                break;
            }
            v.col(j + 1) = w / (w.norm() > 0.0 ? w.norm() : 1.0);
        }
        // x += M^-1 V_j y, H_j y = g_j (upper triangular)
        if (j > 0) {
            const Eigen::VectorXd y =
                h.topLeftCorner(j, j).triangularView<Eigen::Upper>().solve(g.head(j));
            prec(v.leftCols(j) * y, z);
            x += z;
        }
        op(x, w);  // the true residual (the estimate drifts in rounding)
        r = rhs - w;
        beta = r.norm();
        report.residual = beta / rhs.norm();
        if (!std::isfinite(beta)) return report;
        if (beta <= target) {
            report.converged = true;
            return report;
        }
        if (report.iterations >= max_iterations) return report;
    }
}

KrylovReport solve_bordered(const StructuredJacobian& a, const BlockPreconditioner& p, const Eigen::VectorXd& c,
                            const Eigen::VectorXd& b, double d, const Eigen::VectorXd& r, double rho,
                            Eigen::VectorXd& u, double& mu, double tolerance, int max_iterations) {
    const Eigen::Index n = a.size();
    // The bordered preconditioner by block elimination: with P u_c = c, [P c; b^T d]^-1 [s; t]
    // = [v - m u_c; m], P v = s, m = (t - b.v) / (d - b.u_c). Where d - b.u_c vanishes (P
    // itself singular along the border) the border is left unpreconditioned.
    Eigen::VectorXd u_c;
    p.apply(c, u_c);
    const double schur = d - b.dot(u_c);
    const bool bordered = std::abs(schur) > 1e-13 * (std::abs(d) + b.norm() * u_c.norm());
    Eigen::VectorXd top;
    auto prec = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        p.apply(in.head(n), top);
        out.resize(n + 1);
        if (bordered) {
            const double m = (in(n) - b.dot(top)) / schur;
            out.head(n) = top - m * u_c;
            out(n) = m;
        } else {
            out.head(n) = top;
            out(n) = in(n);
        }
    };
    Eigen::VectorXd product;
    auto op = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        a.apply(in.head(n), product);
        out.resize(n + 1);
        out.head(n) = product + c * in(n);
        out(n) = b.dot(in.head(n)) + d * in(n);
    };
    Eigen::VectorXd rhs(n + 1), solution;
    rhs << r, rho;
    const KrylovReport report = gmres(op, prec, rhs, solution, tolerance, max_iterations);
    u = solution.head(n);
    mu = solution(n);
    return report;
}

}  // namespace hbf
