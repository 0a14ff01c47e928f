// hbfriction — the linear structure per harmonic, condensed onto the contacts: the
// receptance of harmonic balance's condensed formulation.
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
// singular at k = 0) is a status with a message, never NaN. The one exception (direct solve):
// an undamped resonance hit exactly of a part no contact sees (W^T v = 0 for its mode v).
// G_k and W^T Z_k^-1 F are regular through it and are given (the limit); the entries of the
// F column's solution and output_load that the mode moves, when F excites it, are +infinity
// (the linear response there is unbounded).
//
// Modal option (use_modes): the m lowest modes of K phi = lambda M phi (Spectra, shift-invert
// Lanczos; a dense solver for small models), M-normalised, and the static residual flexibility
// R = K^-1 - Phi Lambda^-1 Phi^T (one sparse LDL^T of K), so that for B_k = K - (k w)^2 M +
// i k w C
//     W^T B_k^-1 W = P^T diag(1 / (lambda_j - (k w)^2 + i k w c_j)) P + W^T R W,  P = Phi^T W,
// a closed-form sum whose cost does not grow with N (exact at k = 0; truncation error ~ (k w /
// w_{m+1})^2 of the dynamic part). C must be diagonal in the modal basis (c_j = phi_j^T C
// phi_j: Rayleigh or modal damping). Contact springs and dampers added along the directions,
// Z'_k = B_k + W diag(kappa_c + i k w delta_c) W^T, enter exactly by the small identity
// W^T Z'^-1 W = G_B (I + D G_B)^-1 (Woodbury), D = diag(kappa + i k w delta).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <complex>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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
        /// The modal receptance solved without forming G_k (solve's `explicit_contact` false):
        /// G_k = G_B (I + S G_B)^-1 with G_B = W^T B_k^-1 W (the closed-form modal sum) and S the
        /// contacts' shift diag(kappa + i k w delta): one LU of n_c x n_c instead of its inverse
        /// and five products of that size. `contact` and `contact_omega` are then empty; apply
        /// and apply_omega give their products, materialize forms them.
        struct Factored {
            Eigen::MatrixXcd g_b, g_b_omega;
            Eigen::VectorXcd shift, shift_omega;
            Eigen::PartialPivLU<Eigen::MatrixXcd> lu;  ///< of I + S G_B
        };
        std::shared_ptr<const Factored> factored;
        /// G_k z and dG_k/domega z, from `contact` or from `factored`.
        Eigen::VectorXcd apply(const Eigen::VectorXcd& z) const;
        Eigen::VectorXcd apply_omega(const Eigen::VectorXcd& z) const;
        /// Forms `contact` and `contact_omega` from `factored` (no-op when formed).
        void materialize();
    };
    /// Models up to this many DOFs are solved by a dense LU, larger ones by a sparse LU (its
    /// symbolic analysis done once: Z_k has the pattern of K + M + C for every k), but for
    /// dense_fill_limit.
    static constexpr int dense_limit = 16;
    /// Models up to this many DOFs whose Z_k has more than a quarter of its entries nonzero (a
    /// reduced model's full matrices) are solved by a dense LU too.
    static constexpr int dense_fill_limit = 4000;
    /// k >= 0, omega > 0 (throws InvalidInput otherwise; omega is not used at k = 0). With `load` false the F terms are
    /// left empty (harmonics the excitation does not drive). Not thread-safe: one Receptance
    /// per thread (it keeps the sparse factorisation's workspace). The N-long `solution` is
    /// always filled by the direct solve; the modal one fills it only when `solution` is true
    /// (its cost grows with N).
    /// `explicit_contact` false: the modal receptance leaves G_k factored (Harmonic::Factored);
    /// the direct solve always forms it.
    Harmonic solve(int k, double omega, bool load = true, bool solution = true, bool explicit_contact = true);

    /// Switches to the modal basis of the comment above with `modes` modes (fewer when the
    /// model has fewer DOFs), and contact springs kappa and dampers delta (one per direction)
    /// added to the structure. Throws InvalidInput naming the reason: modes < 1, M not positive
    /// definite, K not positive definite, C not diagonal in the modal basis, the eigensolver
    /// failing.
    void use_modes(int modes, const Eigen::VectorXd& contact_stiffness, const Eigen::VectorXd& contact_damping);
    /// Modal receptance only: an upper bound of max_i |Y_i| for Y = Z'_k^-1 (F [load] - W
    /// lambda), from the modal coordinates and the largest entries of the modes and of the
    /// residual flexibility (cost independent of N). +infinity where Z'_k is singular.
    double response_bound(int k, double omega, const Eigen::VectorXcd& lambda, bool load) const;
    /// Modal receptance only: Y = Z'_k^-1 (F [load] - W lambda), the N-long response to the
    /// contacts' forces lambda (one per direction), in O(N (m + n_c)): what
    /// solve(k, omega, load, true).solution gives applied to (-lambda, 1), without forming that
    /// N x n_c matrix (n_c times the work). NaN where Z'_k is singular.
    Eigen::VectorXcd modal_response(int k, double omega, const Eigen::VectorXcd& lambda, bool load) const;
    /// Replaces C by C - xi M from now on (the extended periodic motion concept's artificial
    /// damping, modes.hpp; xi = 0 restores C): the direct solve's Z_k exactly, the modal
    /// receptance's c_j by c_j - xi (M-normalised modes); the static residual flexibility keeps
    /// its own damping (its modes' -xi M, like their inertia, is left out: relative size
    /// k w xi / lambda_{m+1}).
    void set_mass_damping(double xi);
    double mass_damping() const { return mass_damping_; }
    /// dG_k/dxi z: the derivative of G_k in the mass damping xi (set_mass_damping) applied to
    /// z (one per contact direction), at h's k and omega (h from solve at the present xi,
    /// explicit or factored). Modal: G_k = G_B A^-1 (A = I + S G_B) with dG_B/dxi =
    /// P^T diag(i k w d_j^2) P, so dG_k/dxi z = (I - G_k S) dG_B (z - S G_k z), matrix-vector
    /// products only. Direct solve of symmetric K, M, C: i k w (Z_k^-1 W)^T M (Z_k^-1 W) z from
    /// h's solution. Empty where neither applies (non-symmetric matrices, no solution in h, a
    /// mode a contact sees hit exactly): differences in xi are the caller's fallback.
    Eigen::VectorXcd apply_mass_damping(const Harmonic& h, const Eigen::VectorXcd& z) const;
    /// A sector model (cyclic.hpp): each pair (dependent DOF, master) moves as its master turned
    /// by k phi at harmonic k, Y_d = e^{-i k phi} Y_m, and the equations solved are the sector's
    /// own DOFs' (the dependent rows folded onto their masters): Z_k becomes T_k^H Z_k T_k on the
    /// own DOFs (factorised at each solve), and every quantity of Harmonic keeps its meaning on all
    /// DOFs: G_k = W^T T_k (T_k^H Z_k T_k)^-1 T_k^H W, the solution T_k (...)^-1 T_k^H [W, F].
    /// The direct solve only (use_modes refuses a sector); apply_mass_damping gives nothing.
    void set_cyclic(std::vector<std::pair<int, int>> neighbours, double phase);
    /// Modes in use (0: the direct sparse solve).
    int modes() const { return static_cast<int>(modal_.lambda.size()); }
    /// Natural frequencies sqrt(lambda_j) of the modes in use, ascending.
    Eigen::VectorXd natural_frequencies() const { return modal_.lambda.cwiseSqrt(); }
    /// The modal basis in use (after use_modes): what a time-domain modal model of the
    /// structure is built from (event_exact.hpp's ModalExactModel).
    struct ModalBasis {
        Eigen::VectorXd lambda, damping;  ///< lambda_j ascending, c_j = phi_j^T C phi_j
        Eigen::MatrixXd phi;              ///< N x m, M-normalised
        Eigen::MatrixXd residual_w;       ///< R W (N x n_c), R = K^-1 - Phi Lambda^-1 Phi^T
        Eigen::VectorXd residual_load;    ///< R F
        double residual_damping = 0;      ///< b of Rayleigh damping, else 0 (use_modes)
    };
    ModalBasis modal_basis() const {
        return {modal_.lambda, modal_.damping, modal_.phi, modal_.residual_w, modal_.residual_load,
                modal_.residual_damping};
    }

private:
    using SparseComplex = Eigen::SparseMatrix<std::complex<double>>;
    /// b - Z_k x in double-double, the products with K, M and C exact (iterative refinement).
    Eigen::MatrixXcd precise_residual(int k, double omega, const Eigen::MatrixXcd& rhs, const Eigen::MatrixXcd& x) const;
    /// dZ_k/domega x, formed as precisely (C x cancels like K x when C holds a multiple of K).
    Eigen::MatrixXcd precise_derivative_product(int k, double omega, const Eigen::MatrixXcd& x) const;
    /// rhs - (a_K K + a_M M + i a_C C) x, a_M and a_C in double-double (first + second).
    Eigen::MatrixXcd precise_combination(double k_coefficient, std::pair<double, double> m_coefficient,
                                         std::pair<double, double> c_coefficient, const Eigen::MatrixXcd& rhs,
                                         const Eigen::MatrixXcd& x) const;
    /// x = Z_k^-1 rhs (refined) and w_dx = W^T dx/domega (n_c x columns); rhs's first n_c columns
    /// are W. False where Z_k is (numerically) singular.
    bool direct_solve(int k, double omega, const Eigen::MatrixXcd& rhs, Eigen::MatrixXcd& x, Eigen::MatrixXcd& w_dx);
    Eigen::SparseMatrix<double> mass_, damping_, stiffness_;
    Eigen::MatrixXd directions_, outputs_;
    Eigen::VectorXd excitation_;
    // Z_k = K - (k w)^2 M + i k w C on the union pattern of K, M, C: the values of K, M, C at
    // the pattern's entries (zeros where a matrix has none), and the matrix whose values are set.
    SparseComplex z_;
    Eigen::VectorXd k_values_, m_values_, c_values_;
    Eigen::VectorXd c_values_given_;  // C's own values (c_values_ = them - xi M's: set_mass_damping)
    double mass_damping_ = 0;
    bool symmetric_ = false;  // K, M, C all symmetric: W^T Z_k^-1 = (Z_k^-1 W)^T
    bool dense_ = false;      // a dense LU (dense_limit, dense_fill_limit), else the sparse one
    std::unique_ptr<Eigen::SparseLU<SparseComplex>> lu_;  // analysed once (large models)
    std::vector<std::pair<int, int>> cyclic_;  // set_cyclic's pairs (dependent, master); empty: not a sector
    double cyclic_phase_ = 0;
    /// T_k (N x own DOFs) of set_cyclic at harmonic k.
    SparseComplex cyclic_basis(int k) const;
    Harmonic solve_modal(int k, double omega, bool load, bool solution, bool explicit_contact = true) const;
    struct Modal {
        Eigen::VectorXd lambda, damping;         // lambda_j, c_j (minus xi: set_mass_damping)
        Eigen::VectorXd damping_given;           // c_j = phi_j^T C phi_j
        Eigen::MatrixXd phi;                     // N x m
        Eigen::MatrixXd p;                       // Phi^T W (m x n_c)
        Eigen::VectorXd p_load;                  // Phi^T F
        Eigen::MatrixXd t_phi;                   // T Phi (n_o x m)
        Eigen::MatrixXd residual_w;              // R W (N x n_c)
        Eigen::VectorXd residual_load;           // R F
        Eigen::VectorXd kappa, delta;            // contact springs and dampers
        double residual_damping = 0;             // b of Rayleigh damping (the truncated modes'), else 0
        Eigen::VectorXd phi_max, residual_w_max;  // max_i |phi_ij| per mode, max_i |(R W)_ic| per contact
        double residual_load_max = 0;             // max_i |(R F)_i|
        // W^T R W, W^T R F, T R W, T R F (small: formed once, not per harmonic)
        Eigen::MatrixXd w_r_w, t_r_w;
        Eigen::VectorXd w_r_f, t_r_f;
    } modal_;
    /// What response_bound and modal_response share: Y = Phi eta + r_factor (R W g + R F [load]).
    struct ModalResponse {
        bool regular = true;     ///< false: a mode a contact sees is hit exactly (take a limit)
        bool unbounded = false;  ///< a mode no contact sees is hit exactly under the load
        Eigen::VectorXcd g, eta;
        std::complex<double> r_factor;
    };
    ModalResponse modal_response_terms(int k, double omega, const Eigen::VectorXcd& lambda, bool load) const;
    /// What solve_modal and response_bound share at harmonic k: the modal factors d_j, the
    /// residual's factor, G_B = W^T B_k^-1 W, u_B = W^T B_k^-1 F and the contact shift.
    struct ModalTerms {
        /// 1 / (lambda_j - (k w)^2 + i k w c_j); 0 for a mode in `hidden`.
        Eigen::VectorXcd d;
        /// Undamped modes hit exactly (d_j infinite) that no contact sees (their row of P zero):
        /// they add nothing to what the contacts see, and make the DOFs they move unbounded
        /// under the load (Receptance::solve's limit in the direct solve).
        std::vector<Eigen::Index> hidden;
        std::complex<double> r_factor;
        Eigen::MatrixXcd g_b;
        Eigen::VectorXcd u_b, shift;
    };
    ModalTerms modal_terms(int k, double omega) const;
};

}  // namespace hbf
