// hbfriction — the linear structure per harmonic, condensed onto the contacts (issue 12, first
// step: the unit under harmonic_balance that a condensed residual will use).
//
// For harmonic k of the excitation frequency omega the linear part of
//     M y'' + C y' + K y + W f = F cos(omega t)
// is exact: with Y_k the complex amplitude of harmonic k (y = Re(Y_k e^{i k omega t})),
//     Z_k Y_k = F_k - W Lambda_k,   Z_k = K - (k omega)^2 M + i k omega C,
// so the contacts' relative motion Q_k = W^T Y_k and any outputs T Y_k follow from the friction
// forces Lambda_k alone:
//     Q_k = W^T Z_k^-1 F_k - G_k Lambda_k,   G_k = W^T Z_k^-1 W  (the receptance, n_c x n_c).
// Each Z_k is factorised once by a sparse LU (Eigen::SparseLU), so the cost grows with the
// model's sparse factorisation, not with (N (2H+1))^2 as the dense all-DOF formulation.
// The derivative in omega is exact: dZ_k/domega = -2 k^2 omega M + i k C and
// dG_k/domega = -W^T Z_k^-1 (dZ_k/domega) Z_k^-1 W.
// M may be singular (massless DOFs of a reduced model) wherever Z_k stays invertible; a
// singular Z_k (an undamped resonance hit exactly, a rigid-body mode no contact holds, K
// singular at k = 0) is a status with a message, never NaN.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <complex>
#include <memory>
#include <string>

namespace hbf {

class Receptance {
public:
    /// mass, damping, stiffness: N x N (sparse, symmetric is not required); directions: N x n_c
    /// (column c is w_c); excitation: N; outputs: n_o x N (row o is an output's vector, e.g. a
    /// unit row for a DOF). Throws InvalidInput naming the mismatched argument.
    Receptance(Eigen::SparseMatrix<double> mass, Eigen::SparseMatrix<double> damping,
               Eigen::SparseMatrix<double> stiffness, Eigen::MatrixXd directions, Eigen::VectorXd excitation,
               Eigen::MatrixXd outputs);

    int dofs() const { return static_cast<int>(stiffness_.rows()); }
    int contacts() const { return static_cast<int>(directions_.cols()); }
    int outputs() const { return static_cast<int>(outputs_.rows()); }

    /// Harmonic k at omega, everything the condensed residual needs.
    struct Harmonic {
        int k = 0;
        double omega = 0;
        bool ok = false;
        std::string message;                ///< why not (a singular Z_k)
        Eigen::MatrixXcd contact;           ///< G_k = W^T Z_k^-1 W
        Eigen::MatrixXcd contact_omega;     ///< dG_k / domega
        Eigen::VectorXcd contact_load;      ///< W^T Z_k^-1 F (the contacts' motion without friction)
        Eigen::VectorXcd contact_load_omega;  ///< its derivative in omega
        Eigen::MatrixXcd output;            ///< T Z_k^-1 W (n_o x n_c)
        Eigen::VectorXcd output_load;       ///< T Z_k^-1 F
        Eigen::MatrixXcd solution;          ///< Z_k^-1 [W, F] (N x (n_c + 1), F only with load)
    };
    /// Models up to this many DOFs are solved by a dense LU, larger ones by a sparse LU (its
    /// symbolic analysis done once: Z_k has the pattern of K + M + C for every k).
    static constexpr int dense_limit = 16;
    /// k >= 0, omega > 0 (throws InvalidInput otherwise; omega is not used at k = 0). With `load` false the F terms are
    /// left empty (harmonics the excitation does not drive). Not thread-safe: one Receptance
    /// per thread (it keeps the sparse factorisation's workspace).
    Harmonic solve(int k, double omega, bool load = true);

private:
    using SparseComplex = Eigen::SparseMatrix<std::complex<double>>;
    /// b - Z_k x, with Z_k's entries and the products in long double (iterative refinement).
    Eigen::MatrixXcd precise_residual(int k, double omega, const Eigen::MatrixXcd& rhs, const Eigen::MatrixXcd& x) const;
    Eigen::SparseMatrix<double> mass_, damping_, stiffness_;
    Eigen::MatrixXd directions_, outputs_;
    Eigen::VectorXd excitation_;
    // Z_k = K - (k w)^2 M + i k w C on the union pattern of K, M, C: the values of K, M, C at
    // the pattern's entries (zeros where a matrix has none), and the matrix whose values are set.
    SparseComplex z_, dz_;
    Eigen::VectorXd k_values_, m_values_, c_values_;
    std::unique_ptr<Eigen::SparseLU<SparseComplex>> lu_;  // analysed once (large models)
};

}  // namespace hbf
