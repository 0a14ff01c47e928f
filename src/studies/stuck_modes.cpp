// hbfriction — the linear modes of the stuck structure, where nonlinear modes start (modes.hpp:
// stuck_modes).
#include "hbf/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <type_traits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/cyclic.hpp"
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
    refuse_cyclic(system, "the stuck structure's modes");
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

namespace {

// The damped linear mode (damped_linear_mode) of M, K', C' (real, or a sector's Hermitian
// matrices on its own DOFs) continuing the undamped shape phi.
template <class Scalar>
DampedLinearMode damped_mode(const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& mass,
                             const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& stiffness,
                             const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& damping,
                             const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& phi) {
    using Complex = std::complex<double>;
    using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
    DampedLinearMode out;
    const auto n = mass.rows();
    const Eigen::LLT<Matrix> mass_factor(mass);
    if (mass_factor.info() != Eigen::Success) {
        out.why = "a singular mass matrix";
        return out;
    }
    const Matrix minv_k = mass_factor.solve(stiffness), minv_c = mass_factor.solve(damping);
    // The eigenvalues s of M s^2 + (C' - xi M) s + K' in state space, [[0, I], [-M^-1 K', -M^-1 C' + xi I]].
    const auto eigen = [&](double xi, Eigen::VectorXcd& values, Eigen::MatrixXcd& vectors) {
        Matrix a = Matrix::Zero(2 * n, 2 * n);
        a.topRightCorner(n, n).setIdentity();
        a.bottomLeftCorner(n, n) = -minv_k;
        a.bottomRightCorner(n, n) = -minv_c + xi * Matrix::Identity(n, n);
        if constexpr (std::is_same_v<Scalar, double>) {
            Eigen::EigenSolver<Matrix> solver(a, true);
            if (solver.info() != Eigen::Success) return false;
            values = solver.eigenvalues();
            vectors = solver.eigenvectors().topRows(n);
        } else {
            Eigen::ComplexEigenSolver<Matrix> solver(a, true);
            if (solver.info() != Eigen::Success) return false;
            values = solver.eigenvalues();
            vectors = solver.eigenvectors().topRows(n);
        }
        return true;
    };
    Eigen::VectorXcd values;
    Eigen::MatrixXcd vectors;
    if (!eigen(0.0, values, vectors)) {
        out.why = "the damped eigenproblem did not converge";
        return out;
    }
    // The oscillating eigenvalue whose shape is the undamped mode's (largest MAC in the M-norm).
    const Eigen::MatrixXcd mass_c = mass.template cast<Complex>();
    const Eigen::VectorXcd m_phi = mass_c * phi.template cast<Complex>();
    const double phi_norm = std::real(phi.template cast<Complex>().dot(m_phi));
    const auto mac = [&](const Eigen::VectorXcd& v) {
        const double norm = std::real(v.dot(mass_c * v));
        return std::norm(v.dot(m_phi)) / (norm * phi_norm);
    };
    Eigen::Index best = -1;
    double best_mac = 0.0;
    for (Eigen::Index j = 0; j < values.size(); ++j) {
        if (!(values(j).imag() > 1e-8 * std::abs(values(j)))) continue;
        const double m = mac(vectors.col(j));
        if (m > best_mac) {
            best_mac = m;
            best = j;
        }
    }
    if (best < 0 || best_mac < 0.5) {
        out.why = best < 0 ? "no oscillating damped mode (every one overdamped)"
                           : "no damped mode resembles it (largest MAC " + format_number(best_mac) + ")";
        return out;
    }
    // xi with Re s(xi) = 0 (the EPMC's linear limit), by the secant method from xi = -2 Re s;
    // the eigenvalue followed as the one nearest the previous.
    Complex s = values(best);
    Eigen::VectorXcd shape = vectors.col(best);
    double xi0 = 0.0, r0 = s.real(), xi1 = -2.0 * s.real();
    for (int it = 0; it < 50 && std::abs(s.real()) > 1e-13 * std::abs(s); ++it) {
        if (!eigen(xi1, values, vectors)) break;
        Eigen::Index nearest = 0;
        for (Eigen::Index j = 1; j < values.size(); ++j)
            if (std::abs(values(j) - s) < std::abs(values(nearest) - s)) nearest = j;
        s = values(nearest);
        shape = vectors.col(nearest);
        const double r1 = s.real();
        if (r1 == r0) break;
        const double next = xi1 - r1 * (xi1 - xi0) / (r1 - r0);
        xi0 = xi1;
        r0 = r1;
        xi1 = next;
    }
    if (!(std::abs(s.real()) <= 1e-10 * std::abs(s)) || !(s.imag() > 0.0)) {
        out.why = "the modal damping of its linear limit was not found";
        return out;
    }
    out.ok = true;
    out.omega = s.imag();
    out.xi = xi0;
    // y = Re(psi e^{i theta}) with the M-norm of (Re psi, Im psi) 1 and phi^H M psi real
    // (the EPMC's amplitude and phase conditions: s1 = -Im psi).
    const Complex z = shape.dot(m_phi);  // psi^H M phi
    shape *= z / std::abs(z);            // phi^H M psi real and > 0
    const double norm = std::sqrt(std::real(shape.dot(mass_c * shape)));
    out.shape = shape / norm;
    out.mac = best_mac;
    return out;
}

}  // namespace

DampedLinearMode damped_linear_mode(const System& system, const LinearMode& mode) {
    DampedLinearMode out;
    const int n = system.dofs();
    const bool sector = system.cyclic.active();
    const auto own = sector ? static_cast<int>(independent_dofs(system).size()) : n;
    if (own > damped_linear_mode_dofs) {
        out.why = "more than " + std::to_string(damped_linear_mode_dofs) + " DOFs";
        return out;
    }
    const Eigen::MatrixXd mass = dense_or_zero(system.mass, n);
    Eigen::MatrixXd stiffness = dense_or_zero(system.stiffness, n), damping = dense_or_zero(system.damping, n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Eigen::MatrixXd directions = system.contact_directions(system.contacts[c]);
        for (Eigen::Index j = 0; j < directions.cols() && j < static_cast<Eigen::Index>(elements[c].size()); ++j) {
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            if (e.rigid) {
                out.why = "a rigid stuck contact";
                return out;
            }
            if (sector) continue;  // a contact across the cut turns with the phase: below
            stiffness += e.stiffness * directions.col(j) * directions.col(j).transpose();
            damping += e.damping * directions.col(j) * directions.col(j).transpose();
        }
    }
    if (!sector) return damped_mode<double>(mass, stiffness, damping, mode.shape);
    // A sector: the travelling wave's Hermitian matrices on its own DOFs (cyclic.hpp), the
    // stuck elements along each direction turned, d = T^T w; the shape on the own DOFs.
    using Complex = std::complex<double>;
    const Eigen::MatrixXcd t = cyclic_transform(system, system.cyclic.phase());
    Eigen::MatrixXcd k = t.adjoint() * stiffness.cast<Complex>() * t, c = t.adjoint() * damping.cast<Complex>() * t;
    for (std::size_t i = 0; i < system.contacts.size(); ++i) {
        const Eigen::MatrixXd directions = system.contact_directions(system.contacts[i]);
        for (Eigen::Index j = 0; j < directions.cols() && j < static_cast<Eigen::Index>(elements[i].size()); ++j) {
            const StuckElement& e = elements[i][static_cast<std::size_t>(j)];
            const Eigen::VectorXcd d = t.transpose() * directions.col(j).cast<Complex>();
            k += e.stiffness * d.conjugate() * d.transpose();
            c += e.damping * d.conjugate() * d.transpose();
        }
    }
    const Eigen::MatrixXcd m = t.adjoint() * mass.cast<Complex>() * t;
    // phi on the own DOFs: the independent DOFs' entries of shape + i shape_imag.
    const std::vector<int> independent = independent_dofs(system);
    Eigen::VectorXcd phi(static_cast<Eigen::Index>(independent.size()));
    for (std::size_t j = 0; j < independent.size(); ++j)
        phi(static_cast<Eigen::Index>(j)) =
            Complex(mode.shape(independent[j]), mode.shape_imag.size() ? mode.shape_imag(independent[j]) : 0.0);
    return damped_mode<Complex>(Eigen::MatrixXcd((m + m.adjoint()) / 2.0), Eigen::MatrixXcd((k + k.adjoint()) / 2.0),
                                Eigen::MatrixXcd((c + c.adjoint()) / 2.0), phi);
}

}  // namespace hbf
