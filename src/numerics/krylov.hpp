// hbfriction — internal: matrix-free Krylov methods on an operator whose products cost a
// period of a flow each (differences of a period map): GMRES for Newton's steps and Arnoldi
// for the dominant eigenvalues (Floquet multipliers). Used by the exact orbits of law elastic
// (time_integration/elastic_orbit.cpp) and of rigid 3D contacts (event_exact/rigid_orbit.cpp).
#pragma once

#include <Eigen/Dense>
#include <functional>

namespace hbf::detail {

/// y = op(x); false where the product failed (a period of the flow, or a stop request).
using KrylovOperator = std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)>;

/// Arnoldi's Ritz values count as eigenvalues where their residual estimate is below this
/// (relative to max(1, |mu|)): about a central difference's accuracy.
constexpr double arnoldi_tolerance = 1e-5;
/// Arnoldi stops once the arnoldi_count largest Ritz values of at least arnoldi_dominant in
/// modulus have converged (a stability verdict needs the largest; the next ones say how close
/// the others are).
constexpr double arnoldi_dominant = 0.05;
constexpr int arnoldi_count = 10;

/// Newton-Krylov: GMRES stops at this residual relative to Newton's (an inexact Newton step).
constexpr double newton_forcing = 1e-3;

/// A start for Arnoldi of `size` entries, all of one size and without symmetry (every
/// component excited).
Eigen::VectorXd arnoldi_start(Eigen::Index size);

/// GMRES on op u = b from u = 0 until |b - op u| <= eta |b|, a breakdown or `most` steps; u the
/// minimum-norm least-squares solution on the Krylov space (op may be singular: a family of
/// orbits). `steps`: the products taken. False where op failed.
bool gmres(const KrylovOperator& op, const Eigen::VectorXd& b, double eta, int most, Eigen::VectorXd& u, int& steps);

/// The dominant eigenvalues of op by Arnoldi from `start`: stopped once the arnoldi_count
/// largest Ritz values of modulus >= arnoldi_dominant have a residual estimate |h_{m+1,m} y_m|
/// below tolerance max(1, |theta|), at an invariant subspace, or after `most` steps.
/// `values`: the converged Ritz values; `largest`: the largest modulus of all (converged or not);
/// `unconverged`: those among the arnoldi_count largest not converged; `steps`: the products
/// taken. False where op failed.
bool dominant_eigenvalues(const KrylovOperator& op, const Eigen::VectorXd& start, int most, Eigen::VectorXcd& values,
                          double& largest, int& unconverged, int& steps, double tolerance = arnoldi_tolerance);

}  // namespace hbf::detail
