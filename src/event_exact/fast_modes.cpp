// hbfriction — the fast modes of a contact pattern (fast_modes.hpp) and the pattern's exponential.
#include "event_exact/fast_modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <vector>

#include "event_exact/polynomial.hpp"

namespace hbf::detail::exact {

namespace {

/// Eigenvalues above this multiple of w are candidates for the fast modes (the cut is placed
/// in the first gap of at least kFastGap above it).
constexpr double kFastFactor = 4.0;
constexpr double kFastGap = 1.5;

/// The eigen-decomposition of a pattern's balanced dynamic block: it does not depend on w (the
/// forcing enters through the input columns only), so it is computed once per block and kept
/// for the next frequencies (a few per thread, most recent first).
struct Spectrum {
    Eigen::MatrixXd block;  ///< the dynamic block as given (the key, with dofs)
    int dofs = 0;
    Eigen::VectorXd d;      ///< balance
    double size = 0;        ///< largest entry of the balanced block
    bool ok = false;
    Eigen::VectorXcd lambda, lambda_left;
    Eigen::MatrixXcd right, left;  ///< eigenvectors of d^-1 az d and of its transpose
};

/// The block is first scaled physically (velocities by w_ref = sqrt(max |K / M|): the same
/// numbers in any consistent units), then balanced: balancing alone stops at different
/// matrices in different units, and so would the rounding of the eigenvectors.
std::shared_ptr<const Spectrum> spectrum_of(const Eigen::MatrixXd& az, int dofs) {
    thread_local std::vector<std::shared_ptr<const Spectrum>> cache;
    for (std::size_t k = 0; k < cache.size(); ++k)
        if (cache[k]->dofs == dofs && cache[k]->block.rows() == az.rows() && cache[k]->block == az) {
            std::rotate(cache.begin(), cache.begin() + static_cast<std::ptrdiff_t>(k), cache.begin() + static_cast<std::ptrdiff_t>(k) + 1);
            return cache.front();
        }
    auto s = std::make_shared<Spectrum>();
    s->block = az;
    s->dofs = dofs;
    Eigen::VectorXd physical = Eigen::VectorXd::Ones(az.rows());
    const double stiffness = az.block(dofs, 0, dofs, dofs).cwiseAbs().maxCoeff();
    if (stiffness > 0.0) physical.segment(dofs, dofs).setConstant(std::sqrt(stiffness));
    Eigen::MatrixXd balanced = physical.cwiseInverse().asDiagonal() * az * physical.asDiagonal();
    // Entries at the rounding level of the scaled block are residues of cancellations (a stuck
    // contact's row after the constraint's projection: exactly zero in some units, 1e-16 of the
    // block in others). Balancing reads them as couplings and scales their coordinates by up to
    // 1e-7, which left the split's bases ill-conditioned and its period maps noisy at 1e-10
    // (Newton then stalled, in some units only). They are zero here.
    const double largest = balanced.cwiseAbs().maxCoeff();
    balanced = (balanced.array().abs() <= 1e-13 * largest).select(0.0, balanced);
    s->d = physical.cwiseProduct(balance(balanced));
    s->size = balanced.cwiseAbs().maxCoeff();
    Eigen::EigenSolver<Eigen::MatrixXd> right_solver(balanced, true);
    Eigen::EigenSolver<Eigen::MatrixXd> left_solver(balanced.transpose(), true);
    s->ok = right_solver.info() == Eigen::Success && left_solver.info() == Eigen::Success;
    if (s->ok) {
        s->lambda = right_solver.eigenvalues();
        s->right = right_solver.eigenvectors();
        s->lambda_left = left_solver.eigenvalues();
        s->left = left_solver.eigenvectors();
    }
    constexpr std::size_t kept = 16;
    cache.insert(cache.begin(), s);
    if (cache.size() > kept) cache.pop_back();
    return s;
}

}  // namespace

bool split_fast_modes(const Eigen::MatrixXd& a, int nz, int dofs, double omega, ModeData& m, double& slow_radius) {
    slow_radius = omega;
    if (nz == 0 || dofs == 0) return false;
    const std::shared_ptr<const Spectrum> spectrum = spectrum_of(a.topLeftCorner(nz, nz), dofs);
    const Eigen::VectorXd& d = spectrum->d;
    if (!spectrum->ok) {
        slow_radius = std::max(omega, a.topLeftCorner(nz, nz).cwiseAbs().rowwise().sum().maxCoeff());
        return false;
    }
    const Eigen::VectorXcd& lambda = spectrum->lambda;
    std::vector<double> sizes(static_cast<std::size_t>(nz));
    for (int i = 0; i < nz; ++i) sizes[static_cast<std::size_t>(i)] = std::abs(lambda(i));
    std::sort(sizes.begin(), sizes.end());
    slow_radius = std::max(omega, sizes.back());
    double cut = -1.0, below_cut = omega;
    for (std::size_t k = 0; k < sizes.size(); ++k) {
        if (sizes[k] <= kFastFactor * omega) continue;
        const double below = k > 0 ? sizes[k - 1] : 0.0;
        if (sizes[k] >= kFastGap * below) {
            cut = k > 0 ? std::max(kFastFactor * omega, std::sqrt(below * sizes[k]))
                        : std::max(kFastFactor * omega, sizes[k] / kFastGap);
            below_cut = std::max(omega, below);
            break;
        }
    }
    if (cut < 0.0) return false;
    std::vector<Eigen::Index> fast_right, fast_left;
    for (Eigen::Index i = 0; i < nz; ++i) {
        if (std::abs(lambda(i)) > cut) fast_right.push_back(i);
        if (std::abs(spectrum->lambda_left(i)) > cut) fast_left.push_back(i);
    }
    const Eigen::Index nf = static_cast<Eigen::Index>(fast_right.size());
    if (nf == 0 || fast_left.size() != fast_right.size()) return false;
    Eigen::MatrixXcd v(nz, nf), w(nz, nf);
    Eigen::VectorXcd mu(nf);
    for (Eigen::Index j = 0; j < nf; ++j) {
        v.col(j) = spectrum->right.col(fast_right[static_cast<std::size_t>(j)]);
        w.col(j) = spectrum->left.col(fast_left[static_cast<std::size_t>(j)]);
        mu(j) = spectrum->lambda_left(fast_left[static_cast<std::size_t>(j)]);
    }
    const Eigen::MatrixXcd g = w.transpose() * v;
    const Eigen::FullPivLU<Eigen::MatrixXcd> lu(g);
    if (!lu.isInvertible() || lu.rcond() < 1e-10) return false;
    // In balanced coordinates (zhat_b = dhat^-1 zhat, dhat = diag(d, 1, 1, 1)). (Scaling the
    // forcing's states too, to the size of their columns, made the period maps of a stiff
    // appendage noisy at 1e-9: measured, left out.)
    const int n = static_cast<int>(a.rows());
    Eigen::VectorXd dhat = Eigen::VectorXd::Ones(n);
    dhat.head(nz) = d;
    const Eigen::MatrixXd ab = dhat.cwiseInverse().asDiagonal() * a * dhat.asDiagonal();
    Eigen::MatrixXcd right = Eigen::MatrixXcd::Zero(n, nf), left(nf, n);
    right.topRows(nz) = v * lu.inverse();
    const Eigen::MatrixXcd b = ab.block(0, nz, nz, n - nz).cast<std::complex<double>>();
    const Eigen::MatrixXcd rotation = ab.block(nz, nz, n - nz, n - nz).cast<std::complex<double>>();
    for (Eigen::Index j = 0; j < nf; ++j) {
        left.row(j).head(nz) = w.col(j).transpose();
        const Eigen::MatrixXcd shifted = mu(j) * Eigen::MatrixXcd::Identity(n - nz, n - nz) - rotation;
        left.row(j).tail(n - nz) =
            shifted.transpose().partialPivLu().solve((w.col(j).transpose() * b).transpose()).transpose();
    }
    // Checks: ab right = right diag(lambda), left ab = diag(lambda) left, left right = I.
    const Eigen::MatrixXcd ac = ab.cast<std::complex<double>>();
    const double a_size = ab.cwiseAbs().maxCoeff();
    const double r_error = (ac * right - right * mu.asDiagonal()).cwiseAbs().maxCoeff() /
                           (a_size * right.cwiseAbs().maxCoeff());
    const double l_error = (left * ac - mu.asDiagonal() * left).cwiseAbs().maxCoeff() /
                           (a_size * left.cwiseAbs().maxCoeff());
    const double i_error = (left * right - Eigen::MatrixXcd::Identity(nf, nf)).cwiseAbs().maxCoeff();
    if (!(r_error < 1e-9 && l_error < 1e-9 && i_error < 1e-9)) return false;
    // The slow subspace: the kernel of the fast left eigenvectors (real and imaginary parts),
    // orthonormal in balanced coordinates from a QR of their transpose.
    Eigen::MatrixXd rows(n, 2 * nf);
    rows << left.real().transpose(), left.imag().transpose();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(rows);
    const Eigen::Index rank = qr.rank();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd basis = q.rightCols(n - rank);
    const Eigen::MatrixXd projector_b = (right * left).real();
    m.a_slow = basis.transpose() * ab * basis;
    m.slow_basis = dhat.asDiagonal() * basis;
    m.slow_coordinates = basis.transpose() * dhat.cwiseInverse().asDiagonal();
    m.slow_restrict = basis.transpose() * (Eigen::MatrixXd::Identity(n, n) - projector_b) * dhat.cwiseInverse().asDiagonal();
    FastModes& fast = m.fast;
    fast.lambda = mu;
    fast.right = dhat.asDiagonal() * right;
    fast.left = left * dhat.cwiseInverse().asDiagonal();
    fast.right_size = fast.right.cwiseAbs().colwise().maxCoeff().transpose();
    slow_radius = below_cut;
    return true;
}
Eigen::MatrixXd ModeData::exponential(double t) const {
    if (fast.size() == 0) return taylor_exp(a_slow, t);
    const Eigen::VectorXcd growth = (fast.lambda * t).array().exp();
    Eigen::MatrixXd e = slow_basis * (taylor_exp(a_slow, t) * slow_restrict);
    e.noalias() += (fast.right * growth.asDiagonal() * fast.left).real();
    // The forcing's states (cos, sin, 1) depend on themselves only: their rows exactly, not
    // through the split's bases (rounding scaled by the forcing's size would leak into them).
    const Eigen::Index n = e.rows();
    const double w = a(n - 2, n - 3);  // sin' = w cos
    e.bottomRows(3).setZero();
    e(n - 3, n - 3) = e(n - 2, n - 2) = std::cos(w * t);
    e(n - 3, n - 2) = -std::sin(w * t);
    e(n - 2, n - 3) = std::sin(w * t);
    e(n - 1, n - 1) = 1.0;
    return e;
}

}  // namespace hbf::detail::exact
