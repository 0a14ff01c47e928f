// hbfriction — the largest-margin centre of a stuck 3D contact: the point s minimising
// max_j (|s - u_j| - r_j) over planar points u_j with radii r_j (the centre of the smallest circle
// enclosing the circles of radius -r_j about u_j), by Welzl's algorithm, and its derivative.
//
// A 3D contact stuck all period leaves its slider free within {s : |s - u_j| <= r_j for all j}
// (law elastic: u_j the tangential displacements, r_j = mu N_j / k_t; law unilateral: u_j the
// forces' oscillating part reversed, r_j = mu N_j); the centre keeps the largest margin to the
// cone at every sample, and is rotation-equivariant. The optimum is fixed by one, two or three
// of the constraints (its basis): the circle of one point, the tangent point of two, or the circle
// tangent to three, whose derivative with respect to the basis' u_i and r_i follows from its tight
// constraints |s - u_i| - r_i = R.
#pragma once

#include <Eigen/Dense>
#include <array>

namespace hbf::detail {

struct EnclosingCircle {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double value = 0;                       ///< max_j (|centre - u_j| - r_j)
    std::array<int, 3> member = {-1, -1, -1};  ///< the basis: sample indices
    int size = 0;                           ///< 1, 2 or 3
};

/// The optimum for the points u (rows, N x 2) and radii r (N), N >= 1; `scale` (> 0) the size
/// of the points and radii, for the tolerances (1e-12 of it). Reproducible: a fixed pseudo-random
/// order. Throws std::runtime_error where no basis is found (degenerate data).
EnclosingCircle smallest_enclosing_circle(const Eigen::MatrixXd& u, const Eigen::VectorXd& r, double scale);

/// d centre / d u_i (2 x 2) and d centre / d r_i (2) for each basis member k = 0 .. size - 1.
struct EnclosingDerivative {
    std::array<Eigen::Matrix2d, 3> du;
    std::array<Eigen::Vector2d, 3> dr;
};
EnclosingDerivative enclosing_circle_derivative(const Eigen::MatrixXd& u, const Eigen::VectorXd& r,
                                                const EnclosingCircle& circle);

}  // namespace hbf::detail
