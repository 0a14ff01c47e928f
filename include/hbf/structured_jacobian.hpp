// hbfriction — the condensed Jacobian kept in its structure, for interfaces of many contact
// nodes.
//
// The condensed residual (harmonic_balance.hpp) of signal a, harmonic k, is
//     R = S (q - q0 + Gr f(q, z)),
// S the row scales (one per signal and harmonic), Gr the real form of the receptances G_k
// (block-diagonal by harmonic, dense between signals) and f the contacts' forces (each
// contact's force depends on its own directions and internal states only). Laws with internal
// states z (exact Coulomb's and law unilateral's Lagrange multipliers, the bristle) add their
// own rows r_z(q, z) (unscaled). Its Jacobian is therefore
//     dR/dX = diag(S, I) A,   A = [I + Gr Df   Gr Fz]
//                                 [Rq          Rz   ],
// with Df = df/dq, Fz = df/dz, Rq = dr_z/dq, Rz = dr_z/dz block-diagonal by contact (each
// block: the contact's signals x 2H + 1 coefficients, coupling the harmonics through the AFT).
// Formed densely, A is (n_u (2H + 1))^2 numbers (n_u the signals and states) and its LU costs
// (n_u (2H + 1))^3: 100 nodes in 3D at H = 7 make 4500 unknowns, 160 MB and some 6e10 flops
// per Newton step. Kept in this structure, storing it costs the receptances (already held) and
// the contacts' blocks (linear in the nodes), a product A v costs (H + 1) complex n_s x n_s
// matrix-vector products, and systems with A are solved by GMRES preconditioned with
//     P = [I + Gr Dbar   Gr Fzbar]
//         [Rqbar         Rzbar   ],
// the bars the harmonic-diagonal parts of the blocks in complex form (per contact and harmonic
// k, the rotation-invariant part of each (cos k, sin k) block: the mean of the tangent over the
// period). P is block-diagonal by harmonic: H + 1 complex LUs of (n_s + n_z) x (n_s + n_z). It
// is exact wherever each contact's tangent does not vary over the period (stuck, open, linear
// springs), so GMRES needs a few iterations there and more where contacts slip part of the
// period.
//
// The continuation needs bordered systems [A c; b^T d] (corrector: the arclength row;
// tangent: the previous tangent's row); solve_bordered solves them with the bordered
// preconditioner [P c; b^T d] (block elimination with P).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <memory>
#include <vector>

#include "hbf/receptance.hpp"

namespace hbf {

/// Harmonic k of every column of an n x m coefficient matrix (fourier.hpp's layout) as complex
/// amplitudes Y = c - i s (y = Re(Y e^{i k theta}) = c cos + s sin); k = 0: the constant.
Eigen::VectorXcd harmonic_amplitudes(const Eigen::Ref<const Eigen::MatrixXd>& v, int k);
/// Adds harmonic k given as amplitudes y (one per column) to the rows of v.
void add_harmonic_amplitudes(const Eigen::VectorXcd& y, int k, Eigen::Ref<Eigen::MatrixXd> v);

class StructuredJacobian {
public:
    /// Unknowns ((signals + internal states) x 2H + 1): the signals' coefficients, then the states'.
    int size() const { return coefficients_ * (signals_ + states_); }
    int signals() const { return signals_; }
    /// The contacts' internal-state signals (0 for memoryless laws).
    int states() const { return states_; }
    int coefficients() const { return coefficients_; }
    /// S per unknown (1 on the states' rows): dR/dX = diag(row_scale()) A.
    const Eigen::VectorXd& row_scale() const { return row_scale_; }
    /// out = A v.
    void apply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
    /// An upper bound of the row sums of |dR/dX| (for the corrector's resolution estimate).
    Eigen::VectorXd abs_row_sums() const;
    /// dR/dX formed densely (tests, small systems): size()^2 numbers.
    Eigen::MatrixXd dense() const;
    /// Bytes held beyond the shared receptances (the contacts' blocks).
    double bytes() const;

private:
    friend class HarmonicBalance;
    friend class BlockPreconditioner;
    int coefficients_ = 0, signals_ = 0, states_ = 0, harmonics_ = 0;
    std::shared_ptr<const std::vector<Receptance::Harmonic>> receptance_;  // G_k, k = 0..H
    Eigen::VectorXd row_scale_;
    std::vector<int> first_, count_;     // per contact: its first signal and their number
    std::vector<int> state_first_, state_count_;  // per contact: its first state and their number
    std::vector<Eigen::MatrixXd> df_;    // per contact: d f / d q (count n x count n)
    std::vector<Eigen::MatrixXd> fz_, rq_, rz_;  // per contact with states: d f / d z, d r_z / d q, d r_z / d z
    mutable Eigen::MatrixXd work_;       // apply's n x n_s buffer
};

/// P of a StructuredJacobian (the top of this file), factorised once: it may
/// serve Jacobians of nearby points (a preconditioner need not be exact).
class BlockPreconditioner {
public:
    explicit BlockPreconditioner(const StructuredJacobian& jacobian);
    /// out = P^-1 v.
    void apply(const Eigen::VectorXd& v, Eigen::VectorXd& out) const;
    double bytes() const;

private:
    int coefficients_ = 0, signals_ = 0, states_ = 0, harmonics_ = 0;
    std::vector<Eigen::PartialPivLU<Eigen::MatrixXcd>> lu_;  // per harmonic k = 0..H
    // per harmonic: G_k's factors where it is factored (then lu_ holds M = I + G_B (S + Dbar))
    std::vector<std::shared_ptr<const Receptance::Harmonic::Factored>> factored_;
};

/// What one bordered solve did.
struct KrylovReport {
    int iterations = 0;      ///< GMRES iterations (products with A)
    double residual = 0;     ///< final |[A c; b^T d] u - rhs| / |rhs|
    bool converged = false;  ///< residual <= the tolerance
};

/// Solves [A c; b^T d] [u; mu] = [r; rho] by restarted GMRES, right-preconditioned with
/// [P c; b^T d]; u and mu start from zero. tolerance: relative to |[r; rho]|; at most
/// max_iterations products with A.
KrylovReport solve_bordered(const StructuredJacobian& a, const BlockPreconditioner& p, const Eigen::VectorXd& c,
                            const Eigen::VectorXd& b, double d, const Eigen::VectorXd& r, double rho,
                            Eigen::VectorXd& u, double& mu, double tolerance = 1e-10, int max_iterations = 600);

/// Restarted GMRES (modified Gram-Schmidt, Givens rotations) for op(x) = rhs, right-
/// preconditioned by prec; x starts from zero. For solve_bordered and its tests.
KrylovReport gmres(const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& op,
                   const std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>& prec,
                   const Eigen::VectorXd& rhs, Eigen::VectorXd& x, double tolerance, int max_iterations,
                   int restart = 60);

}  // namespace hbf
