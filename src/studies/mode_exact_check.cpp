// hbfriction — a nonlinear mode's point checked against the event-exact solver: the free orbit
// with C - xi M by shooting with exact events (modes.hpp: NonlinearModes::exact_check).
#include "hbf/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"

namespace hbf {

ExactModeCheck NonlinearModes::exact_check(const ModePoint& point) {
    ExactModeCheck out;
    if (system_.cyclic.active()) {
        out.message = "the event-exact solver is not available for a sector model (cyclic symmetry)";
        return out;
    }
    const int dofs = system_.dofs(), contacts = static_cast<int>(system_.contacts.size());
    for (const Contact& c : system_.contacts)
        if ((c.law != FrictionLaw::coulomb && c.law != FrictionLaw::jenkins) || system_.contact_directions(c).cols() != 1) {
            out.message = "the event-exact solver covers exact Coulomb and Jenkins contacts along one direction only";
            return out;
        }
    if (contacts == 0 || dofs > exact_solver_max_dofs ||
        Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(system_.mass)).info() != Eigen::Success) {
        out.message = "the event-exact flow needs contacts, M positive definite and at most " +
                      std::to_string(exact_solver_max_dofs) + " DOFs";
        return out;
    }
    // The section: the middle of the longest stretch of samples where every contact slips.
    const int nt = hb_->time_samples();
    const Eigen::MatrixXd y = motion(point);
    std::vector<bool> slipping(static_cast<std::size_t>(nt), true);
    for (int c = 0; c < contacts; ++c) {
        const Eigen::VectorXd stick = hb_->stick_indicator(point.x, point.omega, c);
        for (int j = 0; j < nt; ++j) slipping[static_cast<std::size_t>(j)] = slipping[static_cast<std::size_t>(j)] && stick(j) >= 0.0;
    }
    int best = 0, best_end = -1;
    for (int j = 0, run = 0; j < 2 * nt; ++j) {  // twice round: a stretch across theta = 0
        run = slipping[static_cast<std::size_t>(j % nt)] ? std::min(run + 1, nt) : 0;
        if (run > best) {
            best = run;
            best_end = j;
        }
    }
    if (best < 4) {
        out.message = "no contact slips over the period (permanent stick: the linear mode of the stuck structure)";
        return out;
    }
    const double theta0 = 2.0 * M_PI * ((best_end - best / 2) % nt) / nt;
    // The harmonic-balance orbit at theta0: y and y' = omega dy/dtheta.
    Eigen::VectorXd y0 = y.row(0).transpose(), v0 = Eigen::VectorXd::Zero(dofs);
    for (int k = 1; k <= hb_->harmonics(); ++k) {
        const double c = std::cos(k * theta0), s = std::sin(k * theta0);
        y0 += c * y.row(2 * k - 1).transpose() + s * y.row(2 * k).transpose();
        v0 += point.omega * k * (-s * y.row(2 * k - 1).transpose() + c * y.row(2 * k).transpose());
    }
    const double modal_position = m_phi_.dot(y0), modal_velocity = m_phi_.dot(v0);
    std::vector<Eigen::VectorXd> w;
    for (const Contact& c : system_.contacts) w.push_back(system_.contact_directions(c).col(0));
    // The exact flow's state [y, y', internal, mode] from (y, y'): every contact slips at t = 0
    // with the sign of its velocity, a Jenkins slider at q - mode F_c / k_t.
    auto state_of = [&](const Eigen::VectorXd& yy, const Eigen::VectorXd& vv, bool& ok) {
        Eigen::VectorXd z(2 * dofs + 2 * contacts);
        z << yy, vv, Eigen::VectorXd::Zero(2 * contacts);
        ok = true;
        for (int c = 0; c < contacts; ++c) {
            const double v = w[static_cast<std::size_t>(c)].dot(vv);
            const Contact& contact = system_.contacts[static_cast<std::size_t>(c)];
            const double mode = v > 0.0 ? 1.0 : -1.0;
            ok = ok && v != 0.0;
            if (contact.law == FrictionLaw::jenkins)
                z(2 * dofs + c) = w[static_cast<std::size_t>(c)].dot(yy) - mode * contact.friction_limit / contact.stiffness;
            z(2 * dofs + contacts + c) = mode;
        }
        return z;
    };
    System free = system_;
    free.excitation = Eigen::VectorXd::Zero(dofs);
    const SparseMatrix damping = system_.damping.rows() == dofs ? system_.damping : SparseMatrix(dofs, dofs);
    auto flow = [&](const Eigen::VectorXd& z, double omega, double xi) {
        free.damping = damping - xi * system_.mass;
        return exact_flow(free, omega, z, 1);
    };
    const int size = 2 * dofs;
    Eigen::VectorXd u(size + 2);
    u << y0, v0, point.omega, point.xi;
    const double scale = std::max({y0.cwiseAbs().maxCoeff(), v0.cwiseAbs().maxCoeff() / point.omega, 1e-300});
    auto residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r, Eigen::MatrixXd* jacobian) {
        bool ok = false;
        const Eigen::VectorXd z = state_of(at.head(dofs), at.segment(dofs, dofs), ok);
        if (!ok || !(at(size) > 0.0)) return false;
        const ExactFlow f = flow(z, at(size), at(size + 1));
        if (!f.ok) return false;
        r.resize(size + 2);
        r.head(size) = f.state.head(size) - at.head(size);
        r.segment(dofs, dofs) /= at(size);  // velocities by omega
        r(size) = m_phi_.dot(at.head(dofs)) - modal_position;
        r(size + 1) = (m_phi_.dot(at.segment(dofs, dofs)) - modal_velocity) / at(size);
        r /= scale;
        if (!jacobian) return true;
        // d z(T) / d(y, y'): the monodromy, a Jenkins slider's column carried by its q = w^T y.
        Eigen::MatrixXd& j = *jacobian;
        j.setZero(size + 2, size + 2);
        j.topLeftCorner(size, size) = f.monodromy.topLeftCorner(size, size);
        for (int c = 0; c < contacts; ++c)
            if (system_.contacts[static_cast<std::size_t>(c)].law == FrictionLaw::jenkins)
                j.topLeftCorner(size, dofs) += f.monodromy.block(0, size + c, size, 1) * w[static_cast<std::size_t>(c)].transpose();
        j.topLeftCorner(size, size) -= Eigen::MatrixXd::Identity(size, size);
        for (int col : {size, size + 1}) {  // omega, xi: central differences of the flow
            const double h = 1e-7 * std::max(point.omega, std::abs(at(col)));
            Eigen::VectorXd up = at, down = at;
            up(col) += h;
            down(col) -= h;
            const ExactFlow fu = flow(z, up(size), up(size + 1)), fd = flow(z, down(size), down(size + 1));
            if (!fu.ok || !fd.ok) return false;
            j.col(col).head(size) = (fu.state.head(size) - fd.state.head(size)) / (2.0 * h);
        }
        j.block(dofs, 0, dofs, size + 2) /= at(size);
        j.block(size, 0, 1, dofs) = m_phi_.transpose();
        j.block(size + 1, dofs, 1, dofs) = m_phi_.transpose() / at(size);
        j /= scale;
        return true;
    };
    Eigen::VectorXd r, trial_r;
    Eigen::MatrixXd j;
    for (int iteration = 0;; ++iteration) {
        if (!residual(u, r, &j)) {
            out.message = "the exact flow failed (an event at the section, or chattering)";
            return out;
        }
        out.iterations = iteration;
        out.residual = r.cwiseAbs().maxCoeff();
        if (out.residual <= 1e-12) break;
        if (iteration >= 30) {
            out.message = "the exact shooting did not converge: residual " + format_number(out.residual);
            return out;
        }
        const Eigen::VectorXd step = Eigen::FullPivLU<Eigen::MatrixXd>(j).solve(-r);
        double length = 1.0;
        bool accepted = false;
        for (int halving = 0; halving < 12 && !accepted; ++halving, length *= 0.5) {
            const Eigen::VectorXd trial = u + length * step;
            if (residual(trial, trial_r, nullptr) && trial_r.cwiseAbs().maxCoeff() < out.residual) {
                u = trial;
                accepted = true;
            }
        }
        if (!accepted) {
            out.message = "the exact shooting stalled: residual " + format_number(out.residual);
            return out;
        }
    }
    out.checked = true;
    out.omega = u(size);
    out.xi = u(size + 1);
    out.gap = std::max(std::abs(out.omega - point.omega), std::abs(out.xi - point.xi)) / out.omega;
    return out;
}

}  // namespace hbf
