// hbfriction — the Taylor-series flow of rigid unilateral contacts with friction cones on
// massless nodes (cone_engine.hpp).
#include "event_exact/cone_engine.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hbf/error.hpp"

namespace hbf::detail::exact {

namespace {

using Eigen::MatrixXd;
using Eigen::RowVectorXd;
using Eigen::VectorXd;

/// Order of the Taylor series of a step.
constexpr int order = 30;
/// The series' last two terms below this share of each group's largest term.
constexpr double step_tolerance = 1e-16;
/// Shortest step of a contact whose direction is held (share of the period).
constexpr double closing_step = 1e-8;
/// A slipping 3D contact holds its direction while its normal force is below this share of
/// the largest contact force.
constexpr double hold_share = 1e-6;
/// A Taylor step shorter than period / stiff_steps is short; after stiff_run short ones in a row
/// the stretch is stiff: implicit steps there, until a Taylor step is long again. A short step
/// now and then (a slip direction turning fast under a small normal force for an instant, near a
/// lift-off) is cheaper as a Taylor step than as an implicit one started cold, and its error is
/// rounding's where the implicit step's is 1e-12.
constexpr double stiff_steps = 1000.0;
constexpr int stiff_run = 16;
/// The order of the collocation's local error estimate (cone_engine.hpp).
constexpr int collocation_order = ConeEngine::collocation_stages + 1;
/// A Jacobian is kept for the next implicit step of a pattern while Newton needed at most this
/// many iterations with it.
constexpr int kept_jacobian_iterations = 4;

int massive_dofs(const System& system) {
    const MatrixXd M(system.mass);
    int count = 0;
    for (Eigen::Index i = 0; i < M.cols(); ++i)
        if (M.col(i).cwiseAbs().maxCoeff() > 0.0) ++count;
    return count;
}

int count_tangential(const MasslessContacts& s) {
    int count = 0;
    for (const RigidContact& b : s.blocks) count += b.d;
    return count;
}

/// The product of two truncated series (as many terms as a).
RowVectorXd product(const RowVectorXd& a, const RowVectorXd& b) {
    const Eigen::Index n = a.size();
    RowVectorXd p = RowVectorXd::Zero(n);
    for (Eigen::Index k = 0; k < n; ++k)
        for (Eigen::Index j = 0; j <= k; ++j) p(k) += a(j) * b(k - j);
    return p;
}

/// cos and sin of the series theta (the usual recurrences).
void cos_sin(const RowVectorXd& theta, RowVectorXd& c, RowVectorXd& s) {
    const Eigen::Index n = theta.size();
    c = RowVectorXd::Zero(n);
    s = RowVectorXd::Zero(n);
    c(0) = std::cos(theta(0));
    s(0) = std::sin(theta(0));
    for (Eigen::Index k = 1; k < n; ++k) {
        for (Eigen::Index j = 1; j <= k; ++j) {
            c(k) -= static_cast<double>(j) * theta(j) * s(k - j);
            s(k) += static_cast<double>(j) * theta(j) * c(k - j);
        }
        c(k) /= static_cast<double>(k);
        s(k) /= static_cast<double>(k);
    }
}

/// The derivative's coefficients (same length, last 0).
RowVectorXd derivative(const RowVectorXd& a) {
    RowVectorXd d = RowVectorXd::Zero(a.size());
    for (Eigen::Index k = 1; k < a.size(); ++k) d(k - 1) = static_cast<double>(k) * a(k);
    return d;
}

double angle_difference(double a, double b) { return std::remainder(a - b, 2.0 * pi); }

}  // namespace

ConeEngine::ConeEngine(const System& system, double omega)
    : PatternEngine(omega, false, massive_dofs(system), static_cast<int>(system.contacts.size()), 0),
      system_(system),
      s_(split_massless_contacts(system, "the exact solver")) {
    if (system.excitation_harmonic != 1)
        throw InvalidInput("excitation_harmonic = " + std::to_string(system.excitation_harmonic) +
                           ": the exact solver of law unilateral takes the force at the fundamental; allowed 1");
    tangential_entries_ = count_tangential(s_);
    nz_ = 2 * n_dofs_ + tangential_entries_ + n_contacts_;
    n_ = nz_ + 3;
    int first = 0;
    for (const RigidContact& b : s_.blocks) {
        slider_first_.push_back(first);
        first += b.d;
    }
    MasslessRows rows = massless_rows(s_, n_, cos_index(), one_index());
    free_nodes_ = std::move(rows.free_nodes);
    free_ = std::move(rows.free);
    base_ = std::move(rows.base);
    transmit_ = std::move(rows.transmit);
    free_sparse_ = free_.sparseView();
    base_sparse_ = base_.sparseView();
}

ModeData ConeEngine::build(const Modes& modes) const {
    (void)modes;
    const int n = n_, L = s_.lambdas, r = recorded();
    ModeData m;
    m.lambda = MatrixXd::Zero(L, r);
    m.lambda.rightCols(L).setIdentity();
    m.relative = MatrixXd::Zero(L, r);
    m.relative.leftCols(n) = free_;
    m.relative.rightCols(L) = -s_.G;
    const int N = system_.dofs();
    m.displacement = MatrixXd::Zero(N, r);
    for (int k = 0; k < n_dofs_; ++k) m.displacement(s_.massive[static_cast<std::size_t>(k)], k) = 1.0;
    for (std::size_t k = 0; k < s_.massless.size(); ++k) {
        const auto row = static_cast<Eigen::Index>(k);
        m.displacement.row(s_.massless[k]).head(n) = free_nodes_.row(row);
        m.displacement.row(s_.massless[k]).tail(L) = -s_.B.row(row);
    }
    m.force = MatrixXd(n_contacts_, r);
    for (int c = 0; c < n_contacts_; ++c) m.force.row(c) = m.lambda.row(tangential(c));
    return m;
}

void ConeEngine::PatternSolve::correct(Eigen::Ref<Eigen::MatrixXd> x) const {
    MatrixXd at_normals(w_.cols(), x.cols());
    for (Eigen::Index j = 0; j < w_.cols(); ++j) at_normals.row(j) = x.row(base_->normal_rows[static_cast<std::size_t>(j)]);
    x.noalias() -= w_ * capacitance_.solve(at_normals);
}

Eigen::MatrixXd ConeEngine::PatternSolve::solve_on_cones(const Eigen::MatrixXd& e) const {
    const Base& b = *base_;
    if (e.cols() == 0) return MatrixXd::Zero(e.rows(), 0);
    const auto k = static_cast<Eigen::Index>(b.tangential_rows.size());
    MatrixXd c(2 * k, e.cols());
    MatrixXd rest = e;
    for (Eigen::Index j = 0; j < k; ++j) {
        const int T = b.tangential_rows[static_cast<std::size_t>(j)];
        c.row(j) = e.row(T);
        c.row(k + j) = e.row(T + 1);
        rest.row(T).setZero();
        rest.row(T + 1).setZero();
    }
    if (rest.cwiseAbs().maxCoeff() > 0.0) return solve(e);
    MatrixXd x = b.on_cos * c.topRows(k) + b.on_sin * c.bottomRows(k);
    if (w_.cols() > 0) correct(x);
    return x;
}

ConeEngine::PatternSolve ConeEngine::pattern_lu(const VectorXd& zhat, const Modes& modes) const {
    const int L = s_.lambdas;
    std::vector<int> cones;
    for (int k = 0; k < n_contacts_; ++k)
        if (modes[static_cast<std::size_t>(k)] == slip && directions(k) == 2) cones.push_back(k);
    const auto nk = static_cast<Eigen::Index>(cones.size());
    // From the kept factorisation: A(theta) = A0 + U V^T, U's column j the change of cone j's
    // entries (T, N), (T + 1, N) (-mu cos, -mu sin), V's column j e_N.
    if (pattern_base_ && pattern_base_->modes == modes) {
        const PatternSolve::Base& b = *pattern_base_;
        VectorXd dc(nk), ds(nk);
        double turn = 0.0;
        for (Eigen::Index j = 0; j < nk; ++j) {
            const int q = cones[static_cast<std::size_t>(j)];
            const double angle = zhat(theta(q)), mu = s_.blocks[static_cast<std::size_t>(q)].mu;
            turn = std::max(turn, std::abs(angle - b.theta(j)));
            dc(j) = -mu * (std::cos(angle) - std::cos(b.theta(j)));
            ds(j) = -mu * (std::sin(angle) - std::sin(b.theta(j)));
        }
        if (turn == 0.0) return PatternSolve(pattern_base_, MatrixXd(), {});
        if (turn <= PatternSolve::max_turn) {
            const MatrixXd w = b.on_cos * dc.asDiagonal() + b.on_sin * ds.asDiagonal();
            MatrixXd capacitance = MatrixXd::Identity(nk, nk);
            for (Eigen::Index j = 0; j < nk; ++j) capacitance.row(j) += w.row(b.normal_rows[static_cast<std::size_t>(j)]);
            Eigen::PartialPivLU<MatrixXd> lu(capacitance);
            if (lu.rcond() > PatternSolve::min_rcond) return PatternSolve(pattern_base_, w, std::move(lu));
        }
    }
    MatrixXd A = MatrixXd::Zero(L, L);
    for (int k = 0; k < n_contacts_; ++k) {
        const RigidContact& b = s_.blocks[static_cast<std::size_t>(k)];
        const int T = tangential(k), N = normal(k), mode = modes[static_cast<std::size_t>(k)];
        if (mode == open) {
            A.block(T, T, b.d + 1, b.d + 1).setIdentity();
            continue;
        }
        A.row(N) = s_.G.row(N);
        if (mode == stuck) {
            A.middleRows(T, b.d) = s_.G.middleRows(T, b.d);
        } else if (b.d == 1) {
            A(T, T) = 1.0;
            A(T, N) = -(mode > 0 ? 1.0 : -1.0) * b.mu;
        } else {
            A(T, T) = A(T + 1, T + 1) = 1.0;
            A(T, N) = -b.mu * std::cos(zhat(theta(k)));
            A(T + 1, N) = -b.mu * std::sin(zhat(theta(k)));
        }
    }
    auto base = std::make_shared<PatternSolve::Base>();
    base->lu.compute(A);
    if (!(base->lu.rcond() > 1e-14))
        throw std::runtime_error("a contact pattern has no unique contact forces (the friction makes the slipping "
                                 "contacts' normal problem singular)");
    base->modes = modes;
    base->theta.resize(nk);
    MatrixXd columns = MatrixXd::Zero(L, 2 * nk);
    for (Eigen::Index j = 0; j < nk; ++j) {
        const int q = cones[static_cast<std::size_t>(j)];
        base->theta(j) = zhat(theta(q));
        base->normal_rows.push_back(normal(q));
        base->tangential_rows.push_back(tangential(q));
        columns(tangential(q), j) = 1.0;
        columns(tangential(q) + 1, nk + j) = 1.0;
    }
    if (nk > 0) {  // (Eigen's solve of an empty right side touches its first entry)
        const MatrixXd solved = base->lu.solve(columns);
        base->on_cos = solved.leftCols(nk);
        base->on_sin = solved.rightCols(nk);
    } else {
        base->on_cos = base->on_sin = MatrixXd::Zero(L, 0);
    }
    pattern_base_ = std::move(base);
    return PatternSolve(pattern_base_, MatrixXd(), {});
}

VectorXd ConeEngine::kept_rows(const Modes& modes) const {
    VectorXd mask = VectorXd::Ones(s_.lambdas);
    for (int q = 0; q < n_contacts_; ++q) {
        const int mode = modes[static_cast<std::size_t>(q)], d = directions(q);
        if (mode == open) mask.segment(tangential(q), d + 1).setZero();
        else if (mode != stuck) mask.segment(tangential(q), d).setZero();
    }
    return mask;
}

MatrixXd ConeEngine::series(const VectorXd& zhat, const Modes& modes, double t, int terms,
                            const std::vector<char>& frozen, bool decide_hold, bool rates_only) const {
    (void)t;
    const int nm = n_dofs_, L = s_.lambdas, n = n_, K = terms;
    MatrixXd c = MatrixXd::Zero(n + L, K + 1);
    // the forcing: cos(w (t + tau)) + i sin(...) = exp(i w t) exp(i w tau), its phase from zhat
    std::complex<double> p(zhat(cos_index()), zhat(sin_index()));
    for (int k = 0; k <= K; ++k) {
        c(cos_index(), k) = p.real();
        c(sin_index(), k) = p.imag();
        p *= std::complex<double>(0.0, omega_) / static_cast<double>(k + 1);
    }
    c(one_index(), 0) = 1.0;
    c.col(0).head(nz_) = zhat.head(nz_);
    // the pattern's matrix
    std::vector<int> cones, moving;  // slipping 3D contacts; those whose direction moves
    for (int k = 0; k < n_contacts_; ++k)
        if (modes[static_cast<std::size_t>(k)] == slip && directions(k) == 2) cones.push_back(k);
    const PatternSolve lu = pattern_lu(zhat, modes);
    const auto nk = static_cast<Eigen::Index>(cones.size());
    MatrixXd Dc = MatrixXd::Zero(nk, K + 1), Ds = MatrixXd::Zero(nk, K + 1);
    for (Eigen::Index j = 0; j < nk; ++j) {
        Dc(j, 0) = std::cos(zhat(theta(cones[static_cast<std::size_t>(j)])));
        Ds(j, 0) = std::sin(zhat(theta(cones[static_cast<std::size_t>(j)])));
    }
    auto rhs = [&](int k, VectorXd& r) {
        const VectorXd zk = c.col(k).head(n);
        r = free_sparse_ * zk;
        for (int q = 0; q < n_contacts_; ++q) {
            const RigidContact& b = s_.blocks[static_cast<std::size_t>(q)];
            const int T = tangential(q), N = normal(q), mode = modes[static_cast<std::size_t>(q)];
            if (mode == open) {
                r.segment(T, b.d + 1).setZero();
                continue;
            }
            r(N) -= b.gap * zk(one_index());
            if (mode == stuck) {
                r.segment(T, b.d) -= zk.segment(slider(q), b.d);
            } else {
                r.segment(T, b.d).setZero();
            }
        }
        for (Eigen::Index j = 0; j < nk; ++j) {
            const int q = cones[static_cast<std::size_t>(j)];
            const int T = tangential(q), N = normal(q);
            const double mu = s_.blocks[static_cast<std::size_t>(q)].mu;
            for (int i = 0; i < k; ++i) {
                r(T) += mu * c(n + N, i) * Dc(j, k - i);
                r(T + 1) += mu * c(n + N, i) * Ds(j, k - i);
            }
        }
    };
    // the direction equation's matrix P (cone x cone), after lambda_0
    Eigen::FullPivLU<MatrixXd> direction;
    VectorXd r;
    for (int k = 0;; ++k) {
        if (rates_only && k == K && k > 0) break;  // y, y' and theta of order K are set
        rhs(k, r);
        const VectorXd lambda = lu.solve(r);
        c.col(k).tail(L) = lambda;
        // the relative motion q = free_ z - G lambda of the contacts not stuck: their rows only
        for (int q = 0; q < n_contacts_; ++q)
            if (modes[static_cast<std::size_t>(q)] != stuck) {
                const int T = tangential(q), d = directions(q);
                const VectorXd relative = free_sparse_.middleRows(T, d) * c.col(k).head(n) - s_.G.middleRows(T, d) * lambda;
                c.col(k).segment(slider(q), d) = relative;
            }
        if (k == 0) {
            // contacts pressing too little for their direction equation (its coefficient
            // mu lambda_N vanishes as they close or open): held this step
            const double scale = std::max(lambda.cwiseAbs().maxCoeff(), force_scale_);
            for (std::size_t j = 0; j < cones.size(); ++j) {
                const int q = cones[j];
                const bool hold = (!frozen.empty() && frozen[static_cast<std::size_t>(q)]) ||
                                  (decide_hold && !(lambda(normal(q)) > hold_share * scale));
                if (!hold) moving.push_back(static_cast<int>(j));
            }
            if (!moving.empty() && K > 0) {
                // P(a, b) = -d_perp_a . (G A^-1 e_b) at contact a's tangential rows, e_b the
                // change of the pattern's right side as theta_b turns: all columns at once,
                // and only the moving contacts' rows of G
                const auto nv = static_cast<Eigen::Index>(moving.size());
                MatrixXd E = MatrixXd::Zero(L, nv), rows(2 * nv, L);
                for (Eigen::Index b = 0; b < nv; ++b) {
                    const auto jb = static_cast<Eigen::Index>(moving[static_cast<std::size_t>(b)]);
                    const int q = cones[static_cast<std::size_t>(jb)];
                    const double weight = s_.blocks[static_cast<std::size_t>(q)].mu * lambda(normal(q));
                    E(tangential(q), b) = -weight * Ds(jb, 0);
                    E(tangential(q) + 1, b) = weight * Dc(jb, 0);
                    rows.middleRows(2 * b, 2) = s_.G.middleRows(tangential(q), 2);
                }
                const MatrixXd moved = rows * lu.solve_on_cones(E);
                MatrixXd P(nv, nv);
                for (Eigen::Index a = 0; a < nv; ++a) {
                    const auto ja = static_cast<Eigen::Index>(moving[static_cast<std::size_t>(a)]);
                    P.row(a) = -(-Ds(ja, 0) * moved.row(2 * a) + Dc(ja, 0) * moved.row(2 * a + 1));
                }
                direction.compute(P);
                if (!direction.isInvertible())
                    throw std::runtime_error("the slip directions' equation is singular");
            }
        }
        if (k == K) break;
        const VectorXd zk = c.col(k).head(n);
        const VectorXd acceleration = base_sparse_ * zk + transmit_ * lambda;
        c.col(k + 1).head(nm) = c.col(k).segment(nm, nm) / static_cast<double>(k + 1);
        c.col(k + 1).segment(nm, nm) = acceleration / static_cast<double>(k + 1);
        if (nk == 0) continue;
        // the directions' next terms, first without theta_{k+1}
        for (Eigen::Index j = 0; j < nk; ++j) {
            const int q = cones[static_cast<std::size_t>(j)];
            double cc = 0.0, ss = 0.0;
            for (int i = 1; i <= k; ++i) {
                cc -= i * c(theta(q), i) * Ds(j, k + 1 - i);
                ss += i * c(theta(q), i) * Dc(j, k + 1 - i);
            }
            Dc(j, k + 1) = cc / static_cast<double>(k + 1);
            Ds(j, k + 1) = ss / static_cast<double>(k + 1);
        }
        if (moving.empty()) continue;
        VectorXd r1;
        rhs(k + 1, r1);
        const VectorXd lambda1 = lu.solve(r1);
        const auto nv = static_cast<Eigen::Index>(moving.size());
        VectorXd b(nv);
        for (Eigen::Index a = 0; a < nv; ++a) {
            const auto ja = static_cast<Eigen::Index>(moving[static_cast<std::size_t>(a)]);
            const int q = cones[static_cast<std::size_t>(ja)];
            const int T = tangential(q), S = slider(q);
            // the next order's relative motion on the moving contact's two rows
            const Eigen::Vector2d relative1 = free_sparse_.middleRows(T, 2) * c.col(k + 1).head(n) - s_.G.middleRows(T, 2) * lambda1;
            double sum = (k + 1) * (-Ds(ja, 0) * relative1(0) + Dc(ja, 0) * relative1(1));
            for (int j = 1; j <= k; ++j)
                sum += (k + 1 - j) * (-Ds(ja, j) * c(S, k + 1 - j) + Dc(ja, j) * c(S + 1, k + 1 - j));
            b(a) = -sum;
        }
        const VectorXd rate = direction.solve(b) / static_cast<double>(k + 1);
        for (Eigen::Index a = 0; a < nv; ++a) {
            const auto ja = static_cast<Eigen::Index>(moving[static_cast<std::size_t>(a)]);
            const int q = cones[static_cast<std::size_t>(ja)];
            c(theta(q), k + 1) = rate(a);
            Dc(ja, k + 1) -= rate(a) * Ds(ja, 0);
            Ds(ja, k + 1) += rate(a) * Dc(ja, 0);
        }
    }
    return c;
}

std::vector<Guard> ConeEngine::guards(const MatrixXd& u, const Modes& modes, int only) const {
    const int n = n_, L = s_.lambdas;
    std::vector<Guard> out;
    for (int q = 0; q < n_contacts_; ++q) {
        if (only >= 0 && q != only) continue;
        const RigidContact& b = s_.blocks[static_cast<std::size_t>(q)];
        const int T = tangential(q), N = normal(q), mode = modes[static_cast<std::size_t>(q)];
        if (mode == open) {
            RowVectorXd gap = -(free_.row(N) * u.topRows(n) - s_.G.row(N) * u.bottomRows(L));
            gap(0) += b.gap * u(one_index(), 0);
            out.push_back({q, gap, {}, guard_gap});
            continue;
        }
        const RowVectorXd lambda_n = u.row(n + N);
        out.push_back({q, lambda_n, {}, guard_normal});
        if (mode == stuck) {
            if (!held_.empty() && held_[static_cast<std::size_t>(q)]) continue;
            if (b.d == 1) {
                out.push_back({q, b.mu * lambda_n - u.row(n + T), {}, guard_limit});
                out.push_back({q, b.mu * lambda_n + u.row(n + T), {}, guard_limit_negative});
            } else {
                const RowVectorXd t1 = u.row(n + T), t2 = u.row(n + T + 1);
                out.push_back({q, b.mu * b.mu * product(lambda_n, lambda_n) - product(t1, t1) - product(t2, t2), {},
                               guard_limit});
            }
            continue;
        }
        const int S = slider(q);
        if (b.d == 1) {
            out.push_back({q, (mode > 0 ? 1.0 : -1.0) * derivative(u.row(S)), {}, guard_slip});
        } else {
            RowVectorXd cs, sn;
            cos_sin(u.row(theta(q)), cs, sn);
            out.push_back({q, product(cs, derivative(u.row(S))) + product(sn, derivative(u.row(S + 1))), {}, guard_slip});
        }
    }
    return out;
}

double ConeEngine::guard_size(const Guard& g, double force, double length) const {
    const double mu = s_.blocks[static_cast<std::size_t>(g.contact)].mu;
    return g.kind == guard_normal                        ? force
           : g.kind == guard_gap || g.kind == guard_slip ? length
           : directions(g.contact) == 2                  ? mu * mu * force * force
                                                         : mu * force;
}

bool ConeEngine::holds(const VectorXd& zhat, const Modes& modes, int c, double t, bool closing) {
    constexpr int terms = 6;
    std::vector<char> frozen(static_cast<std::size_t>(n_contacts_), 0);
    frozen[static_cast<std::size_t>(c)] = closing ? 1 : 0;  // lambda = 0: its direction as given
    MatrixXd u = series(zhat, modes, t, terms, frozen);
    // in units of 1 / omega: the terms of a smooth signal are of one size
    double scale = 1.0;
    for (int k = 1; k <= terms; ++k) {
        scale /= omega_;
        u.col(k) *= scale;
    }
    // The sign of a guard is that of its first term beyond rounding of the quantity it measures
    // (forces: the largest contact force; displacements and slip rates: the largest relative
    // displacement), not of the series' largest term: near a contact whose normal force
    // vanishes the slip directions turn fast and the high terms are large.
    const int L = s_.lambdas;
    const double force = std::max(u.col(0).tail(L).cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    const VectorXd relative = free_ * u.col(0).head(n_) - s_.G * u.col(0).tail(L);
    const double length = std::max(relative.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    for (const Guard& g : guards(u, modes, c)) {
        const double size = guard_size(g, force, length);
        for (Eigen::Index k = 0; k < g.row.size(); ++k) {
            // a slip from rest: its first speed is zero to the precision of a held direction
            const double rounding = (closing && g.kind == guard_slip && k == 0 ? hold_share : 1e-9) * size;
            if (g.row(k) > rounding) break;
            if (g.row(k) < -rounding) return false;
        }
    }
    return true;
}

double ConeEngine::closing_direction(const VectorXd& zhat, Modes modes, int c, double t) {
    // The directions d along which slip can start: q_T' (lambda_N' > 0, lambda_T' = mu lambda_N'
    // d) parallel to d, that is d_perp . q_T' = 0 with d . q_T' > 0: the roots of the first on
    // a scan of the circle, refined by bisection; the one nearest the stuck force's rate.
    std::vector<char> frozen(static_cast<std::size_t>(n_contacts_), 0);
    frozen[static_cast<std::size_t>(c)] = 1;
    const int T = tangential(c), S = slider(c), n = n_;
    modes[static_cast<std::size_t>(c)] = stuck;
    MatrixXd u = series(zhat, modes, t, 1, frozen);
    const double stuck_rate = std::atan2(u(n + T + 1, 1), u(n + T, 1));
    modes[static_cast<std::size_t>(c)] = slip;
    VectorXd z = zhat;
    auto rate = [&](double angle) {
        z(theta(c)) = angle;
        u = series(z, modes, t, 1, frozen);
        return std::make_pair(-std::sin(angle) * u(S, 1) + std::cos(angle) * u(S + 1, 1),
                              std::cos(angle) * u(S, 1) + std::sin(angle) * u(S + 1, 1));
    };
    constexpr int samples = 72;
    double best = stuck_rate, best_distance = std::numeric_limits<double>::infinity();
    double a0 = stuck_rate, f0 = rate(a0).first;
    for (int j = 1; j <= samples; ++j) {
        const double a1 = stuck_rate + 2.0 * pi * j / samples;
        const double f1 = rate(a1).first;
        if ((f0 <= 0.0) != (f1 <= 0.0)) {
            double lo = a0, hi = a1, flo = f0;
            for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
                const double mid = 0.5 * (lo + hi);
                const double fm = rate(mid).first;
                if ((fm <= 0.0) == (flo <= 0.0)) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            const double root = 0.5 * (lo + hi);
            const double distance = std::abs(angle_difference(root, stuck_rate));
            const bool pressing = (rate(root), u(n + normal(c), 1) > 0.0);  // lambda_N grows
            if (rate(root).second > 0.0 && pressing && distance < best_distance) {
                best = root;
                best_distance = distance;
            }
        }
        a0 = a1;
        f0 = f1;
    }
    return std::remainder(best, 2.0 * pi);
}

Modes ConeEngine::settle(const VectorXd& zhat, Modes modes, const Guard& trigger) {
    VectorXd z = zhat;
    std::vector<char> closing;
    return settle_state(z, std::move(modes), {trigger}, closing);
}

Modes ConeEngine::settle_state(VectorXd& zhat, Modes modes, const std::vector<Guard>& triggers,
                               std::vector<char>& closing) {
    // Per trigger (one per contact) its successors in order; the direction of a 3D slip from
    // stick is its force's (continuous), from a closing the consistent one (closing_direction,
    // with the other triggered contacts in their trial patterns).
    const std::size_t count = triggers.size();
    std::vector<std::vector<int>> candidates(count);
    std::vector<double> angle(count);
    // A contact that starts from zero force: it closed, or it reached its friction limit while
    // its normal force is below the share at which a slip direction is held (it closed an
    // instant ago and another contact's event changed its forces' rates). Its force's direction
    // is rounding: a slip takes the consistent direction (closing_direction), held a step.
    std::vector<char> from_rest(count, 0);
    const MatrixXd forces = series(zhat, modes, 0.0, 0);
    for (std::size_t i = 0; i < count; ++i) {
        const int c = triggers[i].contact;
        from_rest[i] = triggers[i].kind == guard_gap ||
                       (triggers[i].kind == guard_limit && directions(c) == 2 &&
                        !(forces(n_ + normal(c), 0) > hold_share * force_scale_));
    }
    for (std::size_t i = 0; i < count; ++i) {
        const int c = triggers[i].contact, d = directions(c);
        angle[i] = zhat(theta(c));
        switch (triggers[i].kind) {
            case guard_gap:
                candidates[i] = {stuck};
                if (d == 1) {
                    Modes held = modes;
                    held[static_cast<std::size_t>(c)] = stuck;
                    const MatrixXd u = series(zhat, held, 0.0, 1);
                    const int first = u(n_ + tangential(c), 1) >= 0.0 ? slip : -slip;
                    candidates[i].push_back(first);
                    candidates[i].push_back(-first);
                } else {
                    candidates[i].push_back(slip);
                }
                break;
            case guard_normal: candidates[i] = {open}; break;
            case guard_limit:
                candidates[i] = {slip};
                if (d == 2) angle[i] = std::atan2(forces(n_ + tangential(c) + 1, 0), forces(n_ + tangential(c), 0));
                break;
            case guard_limit_negative: candidates[i] = {-slip}; break;
            case guard_slip: candidates[i] = {stuck}; break;
            default: break;
        }
    }
    // All triggered contacts take their first successor; then each whose successor does not
    // hold (beyond rounding, with the others as they are) tries its next ones, in rounds.
    Modes next = modes;
    VectorXd z = zhat;
    std::vector<std::size_t> choice(count, 0);
    std::vector<char> held(count, 0);
    auto place = [&](std::size_t i, int candidate) {
        const int c = triggers[i].contact;
        next[static_cast<std::size_t>(c)] = candidate;
        if (candidate == slip && directions(c) == 2) {
            if (from_rest[i]) angle[i] = closing_direction(z, next, c, 0.0);
            z(theta(c)) = angle[i];
        }
    };
    for (std::size_t i = 0; i < count; ++i)
        if (!candidates[i].empty()) place(i, candidates[i].front());
    for (std::size_t round = 0; round <= count; ++round) {
        bool changed = false;
        for (std::size_t i = 0; i < count; ++i) {
            if (candidates[i].empty()) continue;
            const int c = triggers[i].contact;
            held[i] = holds(z, next, c, 0.0, from_rest[i] != 0) ? 1 : 0;
            if (held[i]) continue;
            for (std::size_t j = 0; j < candidates[i].size(); ++j) {
                if (j == choice[i]) continue;
                const Modes before = next;
                const VectorXd z_before = z;
                place(i, candidates[i][j]);
                if (holds(z, next, c, 0.0, from_rest[i] != 0)) {
                    choice[i] = j;
                    held[i] = 1;
                    changed = true;
                    break;
                }
                next = before;
                z = z_before;
            }
        }
        if (!changed) break;
    }
    // Several contacts at one instant (a slip spreading over the interface at once) whose
    // successors do not all hold by the rounds above: their patterns from the contact problem a
    // short time later (lookahead), which settles them together.
    const bool unsettled = std::any_of(held.begin(), held.end(), [](char h) { return h == 0; });
    if (count >= 2 && unsettled) {
        Modes ahead;
        std::vector<double> directions_ahead;
        if (lookahead(zhat, modes, ahead, directions_ahead)) {
            for (std::size_t i = 0; i < count; ++i) {
                if (candidates[i].empty()) continue;
                const int c = triggers[i].contact;
                const int mode = ahead[static_cast<std::size_t>(c)];
                if (std::find(candidates[i].begin(), candidates[i].end(), mode) == candidates[i].end() &&
                    mode != modes[static_cast<std::size_t>(c)])
                    continue;  // not a successor of its event: left to the rule below
                next[static_cast<std::size_t>(c)] = mode;
                if (mode == slip && directions(c) == 2)
                    z(theta(c)) = from_rest[i] ? closing_direction(z, next, c, 0.0)
                                                                : directions_ahead[static_cast<std::size_t>(c)];
                held[i] = 1;
            }
        }
    }
    // A contact none of whose successors holds beyond rounding (a touch of two boundaries at
    // once: the old pattern's guard turns negative where the new one's first terms vanish)
    // takes the one the event leads to (a 3D slip where slip is among them), since the old
    // pattern does not go on. A real chatter ends in the flow's event bound.
    closing.assign(static_cast<std::size_t>(n_contacts_), 0);
    for (std::size_t i = 0; i < count; ++i) {
        if (candidates[i].empty()) continue;
        const int c = triggers[i].contact;
        if (!held[i]) {
            const bool cone = directions(c) == 2 &&
                              std::find(candidates[i].begin(), candidates[i].end(), slip) != candidates[i].end();
            place(i, cone ? slip : candidates[i].front());
        }
        if (next[static_cast<std::size_t>(c)] == slip && directions(c) == 2 && from_rest[i])
            closing[static_cast<std::size_t>(c)] = 1;
    }
    zhat = z;
    return next;
}

bool ConeEngine::lookahead(const VectorXd& zhat, const Modes& modes, Modes& ahead, std::vector<double>& angles) const {
    // q0 a thousandth of a millionth of the period later (q0 depends on y and the forcing, whose
    // rates do not depend on the pattern), from the positions the contacts hold now.
    const MatrixXd c = series(zhat, modes, 0.0, 1);
    const double delta = 1e-9 * period_;
    const VectorXd later = c.col(0).head(n_) + delta * c.col(1).head(n_);
    const VectorXd q0 = free_ * later;
    VectorXd reference = VectorXd::Zero(s_.lambdas);
    for (int k = 0; k < n_contacts_; ++k)
        reference.segment(tangential(k), directions(k)) = c.col(0).segment(slider(k), directions(k));
    RigidContactSolution solution;
    solution.lambda = c.col(0).tail(s_.lambdas);
    if (!solve_rigid_contacts(s_.blocks, s_.G, q0, reference, solution)) return false;
    ahead.assign(static_cast<std::size_t>(n_contacts_), open);
    angles.assign(static_cast<std::size_t>(n_contacts_), 0.0);
    for (int k = 0; k < n_contacts_; ++k) {
        const int state = solution.state[static_cast<std::size_t>(k)];
        const int T = tangential(k);
        int mode = state == 0 ? open : state == 1 ? stuck : slip;
        if (mode == slip && directions(k) == 1) mode = solution.lambda(T) >= 0.0 ? slip : -slip;
        if (mode == slip && directions(k) == 2) angles[static_cast<std::size_t>(k)] = std::atan2(solution.lambda(T + 1), solution.lambda(T));
        ahead[static_cast<std::size_t>(k)] = mode;
    }
    return true;
}

Modes ConeEngine::initial_modes(VectorXd& zhat) {
    const VectorXd q0 = free_ * zhat;
    VectorXd reference = VectorXd::Zero(s_.lambdas);
    for (int c = 0; c < n_contacts_; ++c) reference.segment(tangential(c), directions(c)) = zhat.segment(slider(c), directions(c));
    RigidContactSolution solution;
    if (!solve_rigid_contacts(s_.blocks, s_.G, q0, reference, solution))
        throw std::runtime_error("the contact problem of the start state did not converge (residual " +
                                 format_number(solution.residual) + ")");
    Modes modes(static_cast<std::size_t>(n_contacts_), open);
    for (int c = 0; c < n_contacts_; ++c) {
        const int state = solution.state[static_cast<std::size_t>(c)];
        const int T = tangential(c);
        int mode = state == 0 ? open : state == 1 ? stuck : slip;
        if (mode == slip && directions(c) == 1) mode = solution.lambda(T) >= 0.0 ? slip : -slip;
        if (mode == slip && directions(c) == 2) zhat(theta(c)) = std::atan2(solution.lambda(T + 1), solution.lambda(T));
        modes[static_cast<std::size_t>(c)] = mode;
        zhat.segment(slider(c), directions(c)) = solution.q.segment(T, directions(c));
    }
    return modes;
}

void ConeEngine::restore_constraints(VectorXd& zhat, const Modes& modes, double t) const {
    restore_forcing(zhat, t);
    const MatrixXd u = series(zhat, modes, t, 0);
    for (int c = 0; c < n_contacts_; ++c)
        if (modes[static_cast<std::size_t>(c)] != stuck) zhat.segment(slider(c), directions(c)) = u.col(0).segment(slider(c), directions(c));
}

void ConeEngine::make_consistent(VectorXd& zhat, const Modes& modes, double t) { restore_constraints(zhat, modes, t); }

PatternEngine::Flow ConeEngine::flow(VectorXd zhat, Modes modes, double t0, double duration, bool monodromy, bool record,
                                     int max_events) {
    try {
        return taylor_flow(std::move(zhat), std::move(modes), t0, duration, monodromy, record, max_events);
    } catch (const std::runtime_error& error) {  // a singular pattern: a failed flow, not an exception
        Flow out;
        out.ok = false;
        out.message = error.what();
        return out;
    }
}

PatternEngine::Flow ConeEngine::taylor_flow(VectorXd zhat, Modes modes, double t0, double duration, bool monodromy,
                                            bool record, int max_events) {
    Flow out;
    // The derivative of the state's independent entries with respect to the start's, through the
    // steps (step_sensitivity) and the events (event_sensitivity): rows independent(modes),
    // columns the start's.
    // The columns: the start's independent entries but the held positions of contacts held
    // stuck (hold_stuck): constant over the flow, they are not differentiated with respect to
    // (their columns of psi stay zero), and the steps' sensitivities skip them.
    MatrixXd phi;
    const std::vector<int> start_entries = independent(modes);
    std::vector<int> columns;
    for (const int i : start_entries) {
        const bool held_slider = i >= 2 * n_dofs_ && i < theta(0) && !held_.empty() &&
                                 held_[static_cast<std::size_t>(slider_contact(i))] &&
                                 modes[static_cast<std::size_t>(slider_contact(i))] == stuck;
        if (!held_slider) columns.push_back(i);
    }
    if (monodromy) {
        phi = MatrixXd::Zero(static_cast<Eigen::Index>(start_entries.size()), static_cast<Eigen::Index>(columns.size()));
        for (std::size_t r = 0, c = 0; r < start_entries.size() && c < columns.size(); ++r)
            if (start_entries[r] == columns[c]) phi(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c++)) = 1.0;
    }
    double t = t0;
    const double t_end = t0 + duration;
    int events = 0;
    const int nm = n_dofs_, L = s_.lambdas, n = n_;
    // row groups whose terms are compared with their own largest
    const std::vector<std::pair<int, int>> groups = {{0, nm},
                                                     {nm, nm},
                                                     {2 * nm, tangential_entries_},
                                                     {n, L}};
    std::vector<char> frozen(static_cast<std::size_t>(n_contacts_), 0);
    std::vector<char> started(static_cast<std::size_t>(n_contacts_), 0);  // slipping from rest since this instant
    int instant_events = 0;  // events at the instant of the last step's end
    double last_event = -std::numeric_limits<double>::infinity();  // the last event's time
    std::vector<int> last_slips;  // the contacts that started to slip (from stuck) at it
    std::vector<int> regrip;      // of those, the ones an event just after must stick again
    const long max_steps = 200000;
    long steps = 0;
    taylor_steps_ = collocation_steps_ = 0;
    double implicit_h = 0.0;  // the collocation's next step
    int short_steps = 0;      // Taylor steps shorter than period / stiff_steps in a row
    // The last implicit step, its pattern and held directions: the next one's first guess.
    PreviousStep previous;
    const PreviousStep none;
    StartJacobian start;
    EventTimes event_times;  // the last events' time changes (a cascade at their instant moves with them)
    Modes previous_modes;
    std::vector<char> previous_frozen;
    while (t < t_end) {
        if (++steps > max_steps) {
            out.ok = false;
            out.message = "more than " + std::to_string(max_steps) + " steps in one flow at t = " + format_number(t);
            break;
        }
        const ModeData& m = mode(modes);
        // A slipping 3D contact whose normal force is near zero (just closed, or about to open)
        // holds its direction: its equation is singular at lambda_N = 0, and the friction force
        // it steers is below hold_share of the forces.
        const MatrixXd f = series(zhat, modes, t, 1, frozen);
        {
            force_scale_ = std::max(force_scale_, f.col(0).tail(L).cwiseAbs().maxCoeff());
            const double force_scale = force_scale_;
            for (int q = 0; q < n_contacts_; ++q)
                if (modes[static_cast<std::size_t>(q)] == slip && directions(q) == 2 &&
                    !(f(n + normal(q), 0) > hold_share * force_scale))
                    frozen[static_cast<std::size_t>(q)] = 1;
        }
        const double remaining = t_end - t;
        double cap = std::min(period_ / 24.0, remaining);
        for (int q = 0; q < n_contacts_; ++q)  // held until its normal force grows past 2 hold_share
            if (frozen[static_cast<std::size_t>(q)] && f(n + normal(q), 1) > 0.0)
                cap = std::min(cap, std::max(closing_step * period_,
                                             (2.0 * hold_share * force_scale_ - f(n + normal(q), 0)) / f(n + normal(q), 1)));
        bool implicit = stepping_ == Stepping::collocation;
        double h = cap;
        MatrixXd u;
        if (!implicit) {
            const MatrixXd c = series(zhat, modes, t, order, frozen);
            if (!c.allFinite()) {
                if (stepping_ == Stepping::taylor) {
                    out.ok = false;
                    out.message = "the Taylor series of a step overflowed at t = " + format_number(t) +
                                  " (a slip direction turning too fast: a 3D contact slipping under a small normal force)";
                    break;
                }
                implicit = true;
            } else {
                for (int iteration = 0; iteration < 100; ++iteration) {
                    double worst = 0.0;
                    for (const auto& [first, count] : groups) {
                        if (count == 0) continue;
                        double size = 0.0, tail = 0.0, power = 1.0;
                        for (int k = 0; k <= order; ++k) {
                            const double term = c.col(k).segment(first, count).cwiseAbs().maxCoeff() * power;
                            size = std::max(size, term);
                            if (k >= order - 1) tail += term;
                            power *= h;
                        }
                        if (size > 0.0) worst = std::max(worst, tail / (step_tolerance * size));
                    }
                    if (worst <= 1.0) break;
                    h *= std::max(0.1, 0.9 * std::pow(worst, -1.0 / order));
                }
                const bool short_step = h < cap && h < period_ / stiff_steps;
                short_steps = short_step ? short_steps + 1 : 0;
                if (stepping_ == Stepping::automatic && short_step && short_steps > stiff_run) {
                    implicit = true;  // stiff: an implicit step goes further
                } else {
                    if (h >= remaining * (1.0 - 1e-12)) h = remaining;
                    u = c;
                    double power = 1.0;
                    for (int k = 0; k <= order; ++k) {
                        u.col(k) *= power;
                        power *= h;
                    }
                    ++taylor_steps_;
                }
            }
        }
        double error = 0.0;
        const bool continues = previous.valid() && previous_modes == modes && previous_frozen == frozen;
        const PreviousStep& guess = continues ? previous : none;
        // the Jacobian of the last implicit step kept where the pattern goes on and Newton was fast
        if (!continues || start.iterations > kept_jacobian_iterations) start.J.resize(0, 0);
        start.rate.resize(0);
        start.fresh = false;
        if (implicit) {
            state_size(zhat);
            h = implicit_h > 0.0 ? std::min(cap, implicit_h) : cap;
            for (;;) {
                const bool ok = collocation_step(zhat, modes, h, frozen, start, guess, u, error);
                if (ok && error <= 1.0) break;
                if (!ok && !start.fresh) {  // a kept Jacobian that failed: a fresh one, same step
                    start.J.resize(0, 0);
                    continue;
                }
                h *= ok ? std::clamp(0.9 * std::pow(error, -1.0 / collocation_order), 0.1, 0.9) : 0.25;
                if (!(h > 1e-13 * period_)) {
                    out.ok = false;
                    out.message = "the implicit step did not converge at t = " + format_number(t);
                    out.zhat = zhat;
                    out.modes = modes;
                    return out;
                }
            }
            implicit_h = h * std::min(4.0, 0.9 * std::pow(std::max(error, 1e-12), -1.0 / collocation_order));
            ++collocation_steps_;
        }
        const bool last = h >= remaining;
        double best = std::numeric_limits<double>::infinity();
        std::vector<std::pair<double, Guard>> roots;
        // A 3D slip that starts from rest at a closing starts with no speed: its speed's first
        // value is the consistent direction's rounding, zero below hold_share of the relative
        // velocities (the precision of a held direction), so that it does not stop at once.
        // A guard below rounding is not a root: rounding of the guard's own terms, and of its
        // quantity's size (a guard that is zero all along, such as the friction limit of a node
        // whose stuck force runs along its cone's edge, is rounding throughout).
        const VectorXd relative = free_ * u.col(0).head(n) - s_.G * u.col(0).tail(L);
        const double length = relative.cwiseAbs().maxCoeff();
        const double still = hold_share * omega_ * h * length;
        auto find_roots = [&] {
            best = std::numeric_limits<double>::infinity();
            roots.clear();
            for (Guard g : guards(u, modes)) {
                if (g.kind == guard_slip && started[static_cast<std::size_t>(g.contact)] && g.row(0) < 0.0 &&
                    g.row(0) > -still)
                    g.row(0) = 0.0;
                const double eta = 1e-12 * std::max(g.row.cwiseAbs().sum(), guard_size(g, force_scale_, length));
                const double s = first_root(g.row, 1.0, eta);
                if (s < 0.0) continue;
                roots.emplace_back(s, g);
                best = std::min(best, s);
            }
        };
        find_roots();
        // An implicit step ends where a slipping 3D contact's normal force falls to the share at
        // which its direction is held (the next step holds it): its stages keep the start's
        // choice, so the rates stay smooth within the step.
        if (implicit) {
            double hold_at = std::numeric_limits<double>::infinity();
            for (int q = 0; q < n_contacts_; ++q) {
                if (modes[static_cast<std::size_t>(q)] != slip || directions(q) != 2 || frozen[static_cast<std::size_t>(q)])
                    continue;
                Eigen::RowVectorXd row = u.row(n + normal(q));
                row(0) -= 0.999 * hold_share * force_scale_;
                const double s = first_root(row, 1.0, 1e-12 * row.cwiseAbs().sum());
                if (s >= 0.0) hold_at = std::min(hold_at, s);
            }
            MatrixXd v;
            double e = 0.0;
            if (hold_at < best && hold_at > 0.0 && hold_at < 1.0 - 1e-9 &&
                collocation_step(zhat, modes, hold_at * h, frozen, start, guess, v, e)) {
                h *= hold_at;
                u = std::move(v);
                roots.clear();
                best = std::numeric_limits<double>::infinity();
            }
        }
        // An implicit step's polynomial is of order s + 1 inside, 2s - 1 at its end: a step with
        // an event inside is repeated ending at the event (twice at most).
        for (int redo = 0; implicit && redo < 3 && std::isfinite(best) && best < 1.0 - 1e-9; ++redo) {
            const double shorter = best * h;
            MatrixXd v;
            double e = 0.0;
            if (!(shorter > 0.0) || !collocation_step(zhat, modes, shorter, frozen, start, guess, v, e)) break;
            const MatrixXd kept = u;
            const double kept_h = h;
            const auto kept_roots = roots;
            const double kept_best = best;
            h = shorter;
            u = std::move(v);
            find_roots();
            if (!std::isfinite(best)) {  // the root moved just past the shorter step's end: keep the longer
                u = kept;
                h = kept_h;
                roots = kept_roots;
                best = kept_best;
                break;
            }
        }
        // the events at the first root, and those of other contacts within 1e-9 of the step
        // after it (simultaneous by symmetry): settled together
        std::vector<Guard> triggers;
        for (const auto& [s, g] : roots)
            if (s <= best + 1e-9 &&
                std::none_of(triggers.begin(), triggers.end(), [&](const Guard& o) { return o.contact == g.contact; }))
                triggers.push_back(g);
        const bool found = !triggers.empty();
        const double s_end = found ? std::min(best, 1.0) : 1.0;
        if (record) {
            Step st;
            st.t0 = t;
            st.h = h;
            st.s_end = s_end;
            st.modes = modes;
            st.u = u;
            st.data = &m;
            out.steps.push_back(std::move(st));
        }
        if (phi.size() > 0) {
            try {
                // a slipping 3D contact whose direction moves opens at the step's end
                const bool opens_at_end = std::any_of(triggers.begin(), triggers.end(), [&](const Guard& g) {
                    const auto c = static_cast<std::size_t>(g.contact);
                    return g.kind == guard_normal && modes[c] == slip && directions(g.contact) == 2 && !frozen[c];
                });
                step_sensitivity(u, h, s_end, implicit, modes, frozen, opens_at_end, phi);
                if (s_end > 0.0) event_times.clear();  // not a cascade of the last events
                if (!phi.allFinite()) phi.resize(0, 0);
            } catch (const std::runtime_error&) {  // a singular direction equation inside the step
                phi.resize(0, 0);
            }
        }
        const std::vector<char> step_frozen = frozen;
        if (s_end > 0.0) std::fill(started.begin(), started.end(), 0);
        zhat = evaluate(u, s_end).head(n);
        t = (found || !last) ? std::min(t + s_end * h, t_end) : t_end;
        restore_forcing(zhat, t);
        if (implicit && !found) {
            previous.u = u;
            previous.h = h;
            previous_modes = modes;
            previous_frozen = frozen;
        } else {
            previous.h = 0.0;
        }
        std::fill(frozen.begin(), frozen.end(), 0);
        if (s_end > 0.0 && !regrip.empty()) {  // time went on with them slipping: a coincidence
            out.simultaneous = true;
            regrip.clear();
        }
        if (!found) continue;
        std::vector<char> closing;
        const Modes next = settle_state(zhat, modes, triggers, closing);
        {
            // Two triggers whose contacts both change (a trigger whose contact the settled
            // pattern keeps, a stuck node whose force grazes its cone's edge at that instant, is
            // not an event), or an event within 1e-9 of the period of the last by a step. Not
            // where the last event started stuck nodes slipping that this instant's cascade
            // sticks again: nodes stuck all period grazing their cones at the instant of another
            // contact's event (where a shakedown leaves them: their forces' largest ratio is at
            // that kink), whose triggers the root finding put a rounding's time before it.
            int changed = 0;
            for (const Guard& g : triggers)
                changed += next[static_cast<std::size_t>(g.contact)] != modes[static_cast<std::size_t>(g.contact)];
            regrip.erase(std::remove_if(regrip.begin(), regrip.end(),
                                        [&](int c) { return next[static_cast<std::size_t>(c)] == stuck; }),
                         regrip.end());
            if (changed > 1) {
                out.simultaneous = true;
            } else if (changed > 0 && s_end > 0.0 && t - last_event <= 1e-9 * period_) {
                if (last_slips.empty())
                    out.simultaneous = true;
                else
                    regrip = last_slips;
            }
            if (changed > 0) {
                last_event = t;
                last_slips.clear();
                for (const Guard& g : triggers)
                    if (modes[static_cast<std::size_t>(g.contact)] == stuck && next[static_cast<std::size_t>(g.contact)] == slip)
                        last_slips.push_back(g.contact);
            }
        }
        if (phi.size() > 0) {
            try {
                phi = event_sensitivity(u, h, s_end, modes, step_frozen, triggers, next, zhat, closing, phi, event_times);
                if (event_times.grazing) out.grazing = true;
                if (!phi.allFinite()) phi.resize(0, 0);
            } catch (const std::runtime_error&) {  // a singular pattern at the event
                phi.resize(0, 0);
            }
        }
        for (int k = 0; k < n_contacts_; ++k)
            if (closing[static_cast<std::size_t>(k)]) frozen[static_cast<std::size_t>(k)] = started[static_cast<std::size_t>(k)] = 1;
        // Events that repeat at one instant (a pattern whose successors each end at once):
        // not a chatter in time, a contact none of whose patterns goes on. Said so, with which.
        instant_events = s_end > 0.0 ? 1 : instant_events + 1;
        if (instant_events > 4 * n_contacts_ + 16) {
            static const char* const names[] = {"open", "stuck", "slipping"};
            std::string which;
            for (const Guard& g : triggers) {
                const int from = std::abs(modes[static_cast<std::size_t>(g.contact)]);
                const int to = std::abs(next[static_cast<std::size_t>(g.contact)]);
                which += (which.empty() ? "" : ", ") + std::string("contact ") + std::to_string(g.contact + 1) + " " +
                         names[from] + " -> " + names[to];
            }
            out.ok = false;
            out.message = "contact events repeat without time passing at t = " + format_number(t) + " (" + which +
                          "): no pattern of the contacts goes on from there";
            break;
        }
        const bool counted = record_events(out, t, modes, next, zhat, events, max_events);
        modes = next;
        if (!counted) break;
    }
    if (!regrip.empty()) out.simultaneous = true;
    out.zhat = zhat;
    out.modes = modes;
    if (phi.size() > 0 && out.ok) {
        const std::vector<int> x = independent(modes);
        out.psi = MatrixXd::Zero(n, n);
        for (std::size_t i = 0; i < x.size(); ++i)
            for (std::size_t j = 0; j < columns.size(); ++j)
                out.psi(x[i], columns[j]) = phi(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
    return out;
}

}  // namespace hbf::detail::exact
