// hbfriction — internal to event_exact: the Radau IIA collocation table of s stages (the
// implicit steps of stiff slip-direction flows, cone_collocation.cpp).
//
// Nodes c_1 < ... < c_s = 1, the roots of P_s(2c - 1) - P_{s-1}(2c - 1) (Legendre); the
// collocation polynomial v of degree s through v(0) = v_0 with v'(t_0 + c_i h) = f(v(t_0 + c_i
// h)) has the stage values V_i = v_0 + h sum_j a_ij f(V_j), a_ij = int_0^{c_i} l_j (l_j the
// Lagrange basis on the nodes). At the step's end it is of order 2s - 1, inside it of order
// s + 1; stiffly accurate and L-stable (Hairer and Wanner, Solving ODEs II, IV.5).
#pragma once

#include <Eigen/Dense>

namespace hbf::detail::exact {

struct RadauTable {
    int stages = 0;
    Eigen::VectorXd c;  ///< the nodes, c(s - 1) = 1
    Eigen::MatrixXd a;  ///< s x s
    /// (s + 1) x (s + 1): the monomial coefficients (in sigma in [0, 1]) of the polynomial through
    /// the values at sigma = 0, c_1, ..., c_s are to_monomial * values.
    Eigen::MatrixXd to_monomial;
    /// A^-1 = V diag(lambda) V^-1 (complex; a real A's eigenvalues come in conjugate pairs, each
    /// pair consecutive with conjugate vectors): the simplified Newton system of the stages,
    /// (I - h A (x) J) dZ = -G (dZ, G: m x s, a column a stage), splits into s systems
    /// (lambda_k I - h J) dW_k = R_k with R = -G right, right = (V^-1 A^-1)^T, and dZ = Re(dW V^T);
    /// of a conjugate pair only the first is solved, the second is its conjugate.
    Eigen::VectorXcd lambda;
    Eigen::MatrixXcd vectors;  ///< V
    Eigen::MatrixXcd right;    ///< (V^-1 A^-1)^T
    /// partner(k): the column whose conjugate column k is (-1: column k is solved).
    Eigen::VectorXi partner;
};

/// The table of `stages` stages (2..12), computed in long double once and kept.
const RadauTable& radau_table(int stages);

}  // namespace hbf::detail::exact
