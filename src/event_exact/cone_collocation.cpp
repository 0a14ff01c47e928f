// hbfriction — the implicit steps of the cone engine (cone_engine.hpp): Radau IIA collocation
// of a pattern's flow where its slip directions are stiff.
#include "event_exact/cone_engine.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <limits>
#include <vector>

#include "event_exact/radau.hpp"

namespace hbf::detail::exact {

namespace {
using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The local error allowed per step, relative to the state's size (directions: radians).
constexpr double collocation_tolerance = 1e-12;
/// Newton's update below this share of the tolerance ends the stage iteration.
constexpr double newton_share = 1e-2;
constexpr int newton_iterations = 12;
}  // namespace

double ConeEngine::state_size(const VectorXd& zhat) {
    const int nm = n_dofs_;
    double size = 0.0;
    if (nm > 0)
        size = std::max(zhat.head(nm).cwiseAbs().maxCoeff(), zhat.segment(nm, nm).cwiseAbs().maxCoeff() / omega_);
    size_scale_ = std::max(size_scale_, size);
    return size_scale_ > 0.0 ? size_scale_ : 1.0;
}

bool ConeEngine::collocation_step(const VectorXd& zhat, const Modes& modes, double h, const std::vector<char>& frozen,
                                  StartJacobian& start, const PreviousStep& last, MatrixXd& u, double& error) const {
    const RadauTable& R = radau_table(collocation_stages);
    const int s = R.stages, nm = n_dofs_, n = n_, L = s_.lambdas;
    // The integrated components: y, y' and the directions of the slipping 3D contacts not held.
    std::vector<int> dyn;
    for (int k = 0; k < 2 * nm; ++k) dyn.push_back(k);
    for (int q = 0; q < n_contacts_; ++q)
        if (modes[static_cast<std::size_t>(q)] == slip && directions(q) == 2 &&
            !(!frozen.empty() && frozen[static_cast<std::size_t>(q)]))
            dyn.push_back(theta(q));
    const int m = static_cast<int>(dyn.size());
    const double size = size_scale_ > 0.0 ? size_scale_ : 1.0;
    VectorXd scale(m);
    for (int k = 0; k < m; ++k) scale(k) = dyn[static_cast<std::size_t>(k)] < nm ? size
                                           : dyn[static_cast<std::size_t>(k)] < 2 * nm ? size * omega_
                                                                                        : 1.0;
    const std::complex<double> phase(zhat(cos_index()), zhat(sin_index()));
    auto full = [&](const VectorXd& v, double sigma) {
        VectorXd z = zhat;
        for (int k = 0; k < m; ++k) z(dyn[static_cast<std::size_t>(k)]) = v(k);
        const std::complex<double> p = phase * std::polar(1.0, omega_ * sigma * h);
        z(cos_index()) = p.real();
        z(sin_index()) = p.imag();
        return z;
    };
    // The held directions are the step's start's (frozen) at every stage: the rates stay smooth.
    auto rate = [&](const VectorXd& z) {
        VectorXd f(m);
        try {
            const MatrixXd c = series(z, modes, 0.0, 1, frozen, false);
            for (int k = 0; k < m; ++k) f(k) = c(dyn[static_cast<std::size_t>(k)], 1);
        } catch (const std::runtime_error&) {  // a singular pattern at a trial state: a shorter step
            f.setConstant(std::numeric_limits<double>::quiet_NaN());
        }
        return f;
    };
    VectorXd v0(m);
    for (int k = 0; k < m; ++k) v0(k) = zhat(dyn[static_cast<std::size_t>(k)]);
    // Newton's matrix from forward differences of the rates at the step's start, unless one of
    // an earlier start of the pattern is kept.
    if (start.rate.size() != m) start.rate = rate(zhat);
    if (start.J.rows() != m) {
        start.fresh = true;
        start.J.resize(m, m);
        for (int k = 0; k < m; ++k) {
            const double delta = 1e-7 * std::max(std::abs(v0(k)), scale(k));
            VectorXd v = v0;
            v(k) += delta;
            start.J.col(k) = (rate(full(v, 0.0)) - start.rate) / delta;
        }
    }
    const VectorXd& f0 = start.rate;
    const MatrixXd& J = start.J;
    MatrixXd M = MatrixXd::Identity(s * m, s * m);
    for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j) M.block(i * m, j * m, m, m) -= (h * R.a(i, j)) * J;
    const Eigen::PartialPivLU<MatrixXd> lu(M);
    // The stage increments Z_i = V_i - v_0 are the unknowns (their rounding relative to
    // themselves, not to v_0: the polynomial's slope stays accurate on short steps).
    // First guess: the previous step's polynomial extrapolated to the stages (it ends where this
    // step starts), else the start's rates.
    MatrixXd Z(m, s), F(m, s);
    if (last.valid() && last.u.rows() == n + L) {
        const double ratio = h / last.h;
        auto at = [&](double sigma) {
            VectorXd value = VectorXd::Zero(m);
            for (Eigen::Index k = last.u.cols() - 1; k >= 0; --k)
                for (int j = 0; j < m; ++j) value(j) = value(j) * sigma + last.u(dyn[static_cast<std::size_t>(j)], k);
            return value;
        };
        const VectorXd end = at(1.0);
        for (int i = 0; i < s; ++i) Z.col(i) = at(1.0 + R.c(i) * ratio) - end;
        if (!Z.allFinite())
            for (int i = 0; i < s; ++i) Z.col(i) = (R.c(i) * h) * f0;
    } else {
        for (int i = 0; i < s; ++i) Z.col(i) = (R.c(i) * h) * f0;
    }
    double previous = std::numeric_limits<double>::infinity();
    bool converged = false;
    for (int it = 0; it < newton_iterations; ++it) {
        start.iterations = it + 1;
        for (int i = 0; i < s; ++i) F.col(i) = rate(full(v0 + Z.col(i), R.c(i)));
        if (!F.allFinite()) return false;
        const MatrixXd G = Z - h * F * R.a.transpose();
        const VectorXd dz = lu.solve(-Eigen::Map<const VectorXd>(G.data(), G.size()));
        Z += Eigen::Map<const MatrixXd>(dz.data(), m, s);
        double change = 0.0;
        for (int i = 0; i < s; ++i) change = std::max(change, (dz.segment(i * m, m).array().abs() / scale.array()).maxCoeff());
        if (!std::isfinite(change)) return false;
        if (change <= newton_share * collocation_tolerance) {
            converged = true;
            break;
        }
        if (it >= 2 && change > 0.5 * previous) {  // not contracting: rounding, or a shorter step
            converged = change <= collocation_tolerance;
            break;
        }
        previous = change;
    }
    if (!converged) return false;
    // The recorded vector [zhat, lambda] at the nodes, and its polynomial in sigma: the value at
    // sigma = 0 plus the polynomial of the increments (the integrated rows' from Z).
    const VectorXd w0 = series(zhat, modes, 0.0, 0, frozen, false).col(0);
    MatrixXd increments = MatrixXd::Zero(n + L, s + 1);
    for (int i = 0; i < s; ++i) {
        try {
            increments.col(i + 1) = series(full(v0 + Z.col(i), R.c(i)), modes, 0.0, 0, frozen, false).col(0) - w0;
        } catch (const std::runtime_error&) {
            return false;
        }
        for (int k = 0; k < m; ++k) increments(dyn[static_cast<std::size_t>(k)], i + 1) = Z(k, i);
    }
    if (!increments.allFinite()) return false;
    u = increments * R.to_monomial.transpose();
    u.col(0) = w0;
    // The defect at the midpoints between the nodes, filtered by (I - h J)^-1.
    const Eigen::PartialPivLU<MatrixXd> filter(MatrixXd::Identity(m, m) - h * J);
    error = 0.0;
    double left = 0.0;
    for (int i = 0; i < s; ++i) {
        const double sigma = 0.5 * (left + R.c(i));
        left = R.c(i);
        VectorXd value = VectorXd::Zero(n), slope = VectorXd::Zero(n);
        double power = 1.0;
        for (int k = 0; k <= s; ++k) {
            value += power * u.col(k).head(n);
            if (k + 1 <= s) slope += (k + 1) * power * u.col(k + 1).head(n);
            power *= sigma;
        }
        VectorXd v(m), dv(m);
        for (int k = 0; k < m; ++k) {
            v(k) = value(dyn[static_cast<std::size_t>(k)]);
            dv(k) = slope(dyn[static_cast<std::size_t>(k)]) / h;
        }
        const VectorXd defect = dv - rate(full(v, sigma));
        const VectorXd e = filter.solve(h * defect);
        if (!e.allFinite()) return false;
        const double worst = (e.array().abs() / scale.array()).maxCoeff();
        error = std::max(error, worst / collocation_tolerance);
    }
    return true;
}

}  // namespace hbf::detail::exact
