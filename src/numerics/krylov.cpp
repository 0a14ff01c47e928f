// hbfriction — matrix-free GMRES and Arnoldi (krylov.hpp).
#include "numerics/krylov.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

namespace hbf::detail {

namespace {

/// Arnoldi step j: op(v_j) orthogonalised (modified Gram-Schmidt, twice) against v_0..v_j into
/// column j of h (zero on entry), v_{j+1} its direction; breakdown where nothing is left.
bool arnoldi_step(const KrylovOperator& op, Eigen::MatrixXd& v, Eigen::MatrixXd& h, int j, bool& breakdown) {
    Eigen::VectorXd w;
    if (!op(v.col(j), w)) return false;
    const double before = w.norm();
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i <= j; ++i) {
            const double c = v.col(i).dot(w);
            h(i, j) += c;
            w -= c * v.col(i);
        }
    h(j + 1, j) = w.norm();
    breakdown = !(h(j + 1, j) > 1e-14 * std::max(before, 1e-300));
    if (!breakdown) v.col(j + 1) = w / h(j + 1, j);
    return true;
}

}  // namespace

Eigen::VectorXd arnoldi_start(Eigen::Index size) {
    Eigen::VectorXd start(size);
    for (Eigen::Index i = 0; i < size; ++i) start(i) = 1.0 + 0.5 * std::sin(1.0 + 0.7 * static_cast<double>(i));
    return start;
}

bool gmres(const KrylovOperator& op, const Eigen::VectorXd& b, double eta, int most, Eigen::VectorXd& u, int& steps) {
    const double beta = b.norm();
    u = Eigen::VectorXd::Zero(b.size());
    steps = 0;
    if (!(beta > 0.0)) return true;
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(b.size(), most + 1), h = Eigen::MatrixXd::Zero(most + 1, most);
    v.col(0) = b / beta;
    Eigen::VectorXd y;
    for (int j = 0; j < most; ++j) {
        bool breakdown = false;
        if (!arnoldi_step(op, v, h, j, breakdown)) return false;
        steps = j + 1;
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(j + 2);
        rhs(0) = beta;
        const Eigen::MatrixXd hj = h.topLeftCorner(j + 2, j + 1);
        // The threshold before the decomposition (set after it, solve() would apply Householder
        // factors of Z the decomposition never formed where the new rank is smaller).
        Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> decomposition(hj.rows(), hj.cols());
        decomposition.setThreshold(1e-12);
        decomposition.compute(hj);
        y = decomposition.solve(rhs);
        if (breakdown || (rhs - hj * y).norm() <= eta * beta) break;
    }
    u = v.leftCols(steps) * y;
    return true;
}

bool dominant_eigenvalues(const KrylovOperator& op, const Eigen::VectorXd& start, int most, Eigen::VectorXcd& values,
                          double& largest, int& unconverged, int& steps, double tolerance) {
    const auto k = start.size();
    Eigen::MatrixXd v = Eigen::MatrixXd::Zero(k, most + 1), h = Eigen::MatrixXd::Zero(most + 1, most);
    v.col(0) = start.normalized();
    for (int j = 0; j < most; ++j) {
        bool breakdown = false;
        if (!arnoldi_step(op, v, h, j, breakdown)) return false;
        steps = j + 1;
        const int m = j + 1;
        Eigen::EigenSolver<Eigen::MatrixXd> ritz(h.topLeftCorner(m, m), true);
        if (ritz.info() != Eigen::Success) continue;
        std::vector<int> order(static_cast<std::size_t>(m));
        for (int i = 0; i < m; ++i) order[static_cast<std::size_t>(i)] = i;
        std::sort(order.begin(), order.end(), [&](int a, int b) {
            return std::abs(ritz.eigenvalues()(a)) > std::abs(ritz.eigenvalues()(b));
        });
        std::vector<std::complex<double>> kept;
        largest = m > 0 ? std::abs(ritz.eigenvalues()(order.front())) : 0.0;
        unconverged = 0;
        for (int rank = 0; rank < m; ++rank) {
            const int i = order[static_cast<std::size_t>(rank)];
            const std::complex<double> theta = ritz.eigenvalues()(i);
            const Eigen::VectorXcd y = ritz.eigenvectors().col(i).normalized();
            const double residual = breakdown ? 0.0 : h(m, m - 1) * std::abs(y(m - 1));
            if (residual <= tolerance * std::max(1.0, std::abs(theta)))
                kept.push_back(theta);
            else if (rank < arnoldi_count && std::abs(theta) >= arnoldi_dominant)
                ++unconverged;
        }
        values = Eigen::Map<Eigen::VectorXcd>(kept.data(), static_cast<Eigen::Index>(kept.size()));
        if (breakdown || (unconverged == 0 && m >= std::min<int>(static_cast<int>(k), 8))) break;
    }
    return true;
}

}  // namespace hbf::detail
