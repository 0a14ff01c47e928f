// hbfriction — the linear modes of the stuck structure, where nonlinear modes start (modes.hpp:
// stuck_modes).
#include "hbf/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "hbf/error.hpp"
#include "hbf/static_state.hpp"

namespace hbf {

namespace {

Eigen::MatrixXd dense_or_zero(const SparseMatrix& matrix, int n) {
    if (matrix.rows() != n || matrix.cols() != n) return Eigen::MatrixXd::Zero(n, n);
    return Eigen::MatrixXd(matrix);
}

}  // namespace

std::vector<LinearMode> stuck_modes(const System& system) {
    system.validate();
    const int n = system.dofs();
    const Eigen::MatrixXd mass = dense_or_zero(system.mass, n);
    Eigen::MatrixXd stiffness = dense_or_zero(system.stiffness, n), damping = dense_or_zero(system.damping, n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);
    std::vector<Eigen::VectorXd> rigid;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Eigen::MatrixXd directions = system.contact_directions(system.contacts[c]);
        for (Eigen::Index j = 0; j < directions.cols() && j < static_cast<Eigen::Index>(elements[c].size()); ++j) {
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            const Eigen::VectorXd w = directions.col(j);
            if (e.rigid) {
                rigid.push_back(w);
            } else {
                stiffness += e.stiffness * w * w.transpose();
                damping += e.damping * w * w.transpose();
            }
        }
    }
    // The motions the rigid contacts allow: an orthonormal basis T of {y : w^T y = 0}.
    Eigen::MatrixXd basis = Eigen::MatrixXd::Identity(n, n);
    if (!rigid.empty()) {
        Eigen::MatrixXd w(n, static_cast<Eigen::Index>(rigid.size()));
        for (std::size_t j = 0; j < rigid.size(); ++j) w.col(static_cast<Eigen::Index>(j)) = rigid[j];
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(w, Eigen::ComputeFullU);
        const auto rank = svd.rank();
        if (rank >= n) throw InvalidInput("the stuck structure has no motion: its rigid (exact Coulomb) contacts constrain every DOF");
        basis = svd.matrixU().rightCols(n - rank);
    }
    Eigen::MatrixXd mr = basis.transpose() * mass * basis, kr = basis.transpose() * stiffness * basis;
    mr = 0.5 * (mr + mr.transpose()).eval();
    kr = 0.5 * (kr + kr.transpose()).eval();
    std::vector<LinearMode> modes;
    if (Eigen::LLT<Eigen::MatrixXd>(mr).info() == Eigen::Success) {
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(kr, mr);  // K v = lambda M v, v^T M v = 1
        if (solver.info() != Eigen::Success) throw InvalidInput("the stuck structure's eigenproblem did not converge");
        const double largest = std::max(solver.eigenvalues().cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
        for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j) {
            LinearMode m;
            const double lambda = solver.eigenvalues()(j);
            // Rigid where lambda is at the eigensolver's rounding of the largest (64 eps): a stiff
            // penalty contact (k_n / k = 1e12, common in FE practice) leaves the structure's own
            // modes 1e-12 of the largest, and they are not rigid.
            m.omega = lambda > 64.0 * std::numeric_limits<double>::epsilon() * largest ? std::sqrt(lambda) : 0.0;
            m.shape = basis * solver.eigenvectors().col(j);
            modes.push_back(m);
        }
    } else if (Eigen::LLT<Eigen::MatrixXd>(kr).info() == Eigen::Success) {
        // Massless DOFs: M v = mu K v (mu = 1 / lambda); mu = 0 are the massless directions.
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(mr, kr);
        if (solver.info() != Eigen::Success) throw InvalidInput("the stuck structure's eigenproblem did not converge");
        const double largest = solver.eigenvalues().maxCoeff();
        for (Eigen::Index j = solver.eigenvalues().size() - 1; j >= 0; --j) {
            const double mu = solver.eigenvalues()(j);
            if (!(mu > 1e-14 * largest)) continue;
            LinearMode m;
            m.omega = std::sqrt(1.0 / mu);
            m.shape = basis * solver.eigenvectors().col(j) / std::sqrt(mu);  // v^T K v = 1 -> phi^T M phi = 1
            modes.push_back(m);
        }
    } else {
        throw InvalidInput("the stuck structure's mass and stiffness matrices are both singular (a rigid-body "
                           "mode and massless DOFs): nonlinear modes need one of them positive definite");
    }
    for (std::size_t j = 0; j < modes.size(); ++j) {
        LinearMode& m = modes[j];
        m.index = static_cast<int>(j) + 1;
        // The Rayleigh quotient of the eigenvector: its error is the vector's squared. A dense
        // eigensolver on a finite-element K (entries to 1e10, condition ~N^4) gives the 200-DOF
        // beam's stuck frequency 3e-9 off; the quotient, 1e-11 (inverse iteration as reference).
        if (m.omega > 0.0) {
            const double quotient = m.shape.dot(stiffness * m.shape) / m.shape.dot(mass * m.shape);
            if (quotient > 0.0) m.omega = std::sqrt(quotient);
        }
        Eigen::Index largest = 0;
        m.shape.cwiseAbs().maxCoeff(&largest);
        if (m.shape(largest) < 0.0) m.shape = -m.shape;  // reproducible sign: the largest entry positive
        m.zeta = m.omega > 0.0 ? m.shape.dot(damping * m.shape) / (2.0 * m.omega) : 0.0;
    }
    return modes;
}

}  // namespace hbf
