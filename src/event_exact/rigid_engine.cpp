// hbfriction — the flow engine of rigid unilateral contacts on massless nodes (rigid_engine.hpp).
#include "event_exact/rigid_engine.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "hbf/error.hpp"

namespace hbf::detail::exact {

namespace {

int massive_dofs(const System& system) {
    const Eigen::MatrixXd M(system.mass);
    int count = 0;
    for (Eigen::Index i = 0; i < M.cols(); ++i)
        if (M.col(i).cwiseAbs().maxCoeff() > 0.0) ++count;
    return count;
}

/// A guard's value or rate is "zero" within this share of the sum of its terms' sizes.
double terms(const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) {
    return (row.cwiseAbs().array() * z.transpose().cwiseAbs().array()).sum();
}

}  // namespace

RigidEngine::RigidEngine(const System& system, double omega, bool split)
    : PatternEngine(omega, split, massive_dofs(system), static_cast<int>(system.contacts.size()),
                    2 * massive_dofs(system) + static_cast<int>(system.contacts.size())),
      system_(system),
      s_(split_massless_contacts(system, "the exact solver")) {
    for (std::size_t c = 0; c < s_.blocks.size(); ++c)
        if (s_.blocks[c].d != 1)
            throw InvalidInput("contact " + std::to_string(c + 1) +
                               ": second_direction is given (a 3D contact): the exact solver of law unilateral "
                               "covers contacts with one tangential direction (2D); allowed: no second_direction");
    if (system.excitation_harmonic != 1)
        throw InvalidInput("excitation_harmonic = " + std::to_string(system.excitation_harmonic) +
                           ": the exact solver of law unilateral takes the force at the fundamental; allowed 1");
    MasslessRows rows = massless_rows(s_, n_, cos_index(), one_index());
    free_nodes_ = std::move(rows.free_nodes);
    free_ = std::move(rows.free);
    base_ = std::move(rows.base);
    transmit_ = std::move(rows.transmit);
}

ModeData RigidEngine::build(const Modes& modes) const {
    const int nm = n_dofs_, L = s_.lambdas, n = n_;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(L, L), R = Eigen::MatrixXd::Zero(L, n);
    for (int c = 0; c < n_contacts_; ++c) {
        const int T = tangential(c), N = normal(c), mode = modes[static_cast<std::size_t>(c)];
        const RigidContact& b = s_.blocks[static_cast<std::size_t>(c)];
        if (mode == rigid_open) {
            A(T, T) = 1.0;
            A(N, N) = 1.0;
            continue;
        }
        A.row(N) = s_.G.row(N);
        R.row(N) = free_.row(N);
        R(N, one_index()) -= b.gap;
        if (mode == rigid_stuck) {
            A.row(T) = s_.G.row(T);
            R.row(T) = free_.row(T);
            R(T, slider(c)) -= 1.0;
        } else {
            A(T, T) = 1.0;
            A(T, N) = -(mode > 0 ? 1.0 : -1.0) * b.mu;
        }
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    if (!lu.isInvertible())
        throw std::runtime_error("a contact pattern has no unique contact forces (the friction makes the slipping "
                                 "contacts' normal problem singular)");
    ModeData m;
    m.lambda = lu.solve(R);
    m.relative = free_ - s_.G * m.lambda;
    m.a = Eigen::MatrixXd::Zero(n, n);
    m.a.block(0, nm, nm, nm).setIdentity();
    m.a.middleRows(nm, nm) = base_ + transmit_ * m.lambda;
    for (int c = 0; c < n_contacts_; ++c) {
        if (modes[static_cast<std::size_t>(c)] == rigid_stuck) continue;
        // s = q_T, which depends on y and cos (and stuck sliders, constant): s' = q_T,y y' - w q_T,cos sin
        const int T = tangential(c);
        m.a.row(slider(c)).segment(nm, nm) = m.relative.row(T).head(nm);
        m.a(slider(c), sin_index()) = -omega_ * m.relative(T, cos_index());
    }
    m.a(cos_index(), sin_index()) = -omega_;
    m.a(sin_index(), cos_index()) = omega_;
    const int N_dofs = system_.dofs();
    m.displacement = Eigen::MatrixXd::Zero(N_dofs, n);
    for (int k = 0; k < nm; ++k) m.displacement(s_.massive[static_cast<std::size_t>(k)], k) = 1.0;
    const Eigen::MatrixXd nodes = free_nodes_ - s_.B * m.lambda;
    for (std::size_t k = 0; k < s_.massless.size(); ++k)
        m.displacement.row(s_.massless[k]) = nodes.row(static_cast<Eigen::Index>(k));
    m.force = Eigen::MatrixXd(n_contacts_, n);
    for (int c = 0; c < n_contacts_; ++c) {
        m.force.row(c) = m.lambda.row(tangential(c));
        const int T = tangential(c), N = normal(c), mode = modes[static_cast<std::size_t>(c)];
        const double mu = s_.blocks[static_cast<std::size_t>(c)].mu;
        if (mode == rigid_open) {
            Guard g{c, -m.relative.row(N), {}, guard_gap};
            g.row(one_index()) += s_.blocks[static_cast<std::size_t>(c)].gap;
            m.guards.push_back(g);
            continue;
        }
        m.guards.push_back({c, m.lambda.row(N), {}, guard_normal});
        if (mode == rigid_stuck) {
            m.guards.push_back({c, mu * m.lambda.row(N) - m.lambda.row(T), {}, guard_limit_positive});
            m.guards.push_back({c, mu * m.lambda.row(N) + m.lambda.row(T), {}, guard_limit_negative});
        } else {
            m.guards.push_back({c, (mode > 0 ? 1.0 : -1.0) * m.a.row(slider(c)), {}, guard_slip});
        }
    }
    finish(m);
    return m;
}

bool RigidEngine::holds(const Eigen::VectorXd& zhat, const Modes& modes, int c, double tolerance) {
    const ModeData& m = mode(modes);
    Eigen::VectorXd rate;
    for (const Guard& g : m.guards) {
        if (g.contact != c) continue;
        const double value = g.row.dot(zhat);
        const double size = terms(g.row, zhat);
        if (value > tolerance * size) continue;
        if (value < -tolerance * size) return false;
        if (rate.size() == 0) rate = m.a * zhat;
        if (g.row.dot(rate) < -tolerance * terms(g.row, rate)) return false;
    }
    return true;
}

Modes RigidEngine::settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) {
    constexpr double tolerance = 1e-9;
    const int c = trigger.contact;
    std::vector<int> candidates;
    switch (trigger.kind) {
        case guard_gap: {  // closing: stuck, else slipping the way the force would go
            Modes stuck = modes;
            stuck[static_cast<std::size_t>(c)] = rigid_stuck;
            const double force_rate = mode(stuck).lambda.row(tangential(c)).dot(mode(stuck).a * zhat);
            const int first = force_rate >= 0.0 ? rigid_slip_positive : rigid_slip_negative;
            candidates = {rigid_stuck, first, -first};
            break;
        }
        case guard_normal: candidates = {rigid_open}; break;
        case guard_limit_positive: candidates = {rigid_slip_positive}; break;
        case guard_limit_negative: candidates = {rigid_slip_negative}; break;
        case guard_slip: candidates = {rigid_stuck}; break;  // a reversal would make lambda_T jump
        default: break;
    }
    for (int candidate : candidates) {
        Modes trial = modes;
        trial[static_cast<std::size_t>(c)] = candidate;
        if (holds(zhat, trial, c, tolerance)) return trial;
    }
    return modes;  // a touch of the boundary: the pattern goes on
}

Modes RigidEngine::initial_modes(Eigen::VectorXd& zhat) {
    const Eigen::VectorXd q0 = free_ * zhat;
    Eigen::VectorXd reference = Eigen::VectorXd::Zero(s_.lambdas);
    for (int c = 0; c < n_contacts_; ++c) reference(tangential(c)) = zhat(slider(c));
    RigidContactSolution solution;
    if (!solve_rigid_contacts(s_.blocks, s_.G, q0, reference, solution))
        throw std::runtime_error("the contact problem of the start state did not converge (residual " +
                                 format_number(solution.residual) + ")");
    Modes modes(static_cast<std::size_t>(n_contacts_), rigid_open);
    for (int c = 0; c < n_contacts_; ++c) {
        const int state = solution.state[static_cast<std::size_t>(c)];
        modes[static_cast<std::size_t>(c)] = state == 0   ? rigid_open
                                             : state == 1 ? rigid_stuck
                                                          : (solution.lambda(tangential(c)) >= 0.0 ? rigid_slip_positive
                                                                                                   : rigid_slip_negative);
        zhat(slider(c)) = solution.q(tangential(c));
    }
    return modes;
}

void RigidEngine::restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const {
    restore_forcing(zhat, t);
    const ModeData* m = cached(modes);
    if (!m) return;
    for (int c = 0; c < n_contacts_; ++c)
        if (modes[static_cast<std::size_t>(c)] != rigid_stuck) zhat(slider(c)) = m->relative.row(tangential(c)).dot(zhat);
}

}  // namespace hbf::detail::exact
