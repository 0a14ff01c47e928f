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

/// The local error allowed per step, relative to the state's size (directions: radians); in a
/// start's flows (ConeEngine::set_start_flows) start_tolerance.
constexpr double collocation_tolerance = 1e-12;
constexpr double start_tolerance = 1e-10;
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

void ConeEngine::rates_jacobian(const VectorXd& zhat, const Modes& modes, const std::vector<char>& frozen,
                                const std::vector<int>& dyn, MatrixXd& J, VectorXd& rate) const {
    rates_jacobian(zhat, modes, frozen, dyn, dyn, J, rate);
}

void ConeEngine::rates_jacobian(const VectorXd& zhat, const Modes& modes, const std::vector<char>& frozen,
                                const std::vector<int>& dyn, const std::vector<int>& wrt, MatrixXd& J,
                                VectorXd& rate, ContactDerivatives* more) const {
    // Notation: lambda = A(theta)^-1 r, r = diag(kept) free_ zhat - (held positions s of stuck
    // contacts, gaps); y'' = base_ zhat + transmit_ lambda; the moving directions' rates solve
    // P theta' = b with b_a = -d_perp_a . q1_{T_a}, q1 = free_ z1 - G A^-1 diag(kept) free_ z1
    // (z1: zhat's rate without theta'), P(a, b) = -d_perp_a . (G A^-1 e_b)_{T_a},
    // e_b = mu_b lambda_{N_b} d_perp_b on contact b's tangential rows. For any slipping 3D
    // contact c, d A^-1 / d theta_c x = A^-1 (mu_c (A^-1 x)_{N_c} d_perp_c on T_c).
    const int nm = n_dofs_, n = n_, L = s_.lambdas, y2 = 2 * nm;
    const auto m = static_cast<Eigen::Index>(dyn.size()), nw = static_cast<Eigen::Index>(wrt.size());
    const MatrixXd c = series(zhat, modes, 0.0, 1, frozen, false);
    rate.resize(m);
    for (Eigen::Index k = 0; k < m; ++k) rate(k) = c(dyn[static_cast<std::size_t>(k)], 1);
    std::vector<int> moving;  // the moving directions' contacts, in dyn's order
    for (Eigen::Index k = y2; k < m; ++k) moving.push_back(dyn[static_cast<std::size_t>(k)] - theta(0));
    const auto nv = static_cast<Eigen::Index>(moving.size());
    const PatternSolve lu = pattern_lu(zhat, modes);
    const VectorXd kept = kept_rows(modes);
    const VectorXd lambda = c.col(0).tail(L);
    // Per column of wrt: its contact if it is a direction (-1 otherwise), its position in moving.
    std::vector<int> turning(static_cast<std::size_t>(nw), -1), in_moving(static_cast<std::size_t>(nw), -1);
    MatrixXd right = MatrixXd::Zero(L, nw);  // d r / d wrt
    MatrixXd dz = MatrixXd::Zero(y2, nw);    // d (y, y') / d wrt
    for (Eigen::Index k = 0; k < nw; ++k) {
        const int i = wrt[static_cast<std::size_t>(k)];
        if (i < y2) {
            right.col(k) = kept.cwiseProduct(free_.col(i));
            dz(i, k) = 1.0;
        } else if (i >= theta(0)) {
            const int q = i - theta(0);
            if (modes[static_cast<std::size_t>(q)] == slip && directions(q) == 2) turning[static_cast<std::size_t>(k)] = q;
            const auto it = std::find(moving.begin(), moving.end(), q);
            if (it != moving.end()) in_moving[static_cast<std::size_t>(k)] = static_cast<int>(it - moving.begin());
        } else {  // a held position: only a stuck contact's enters
            for (int q = 0; q < n_contacts_; ++q)
                if (i >= slider(q) && i < slider(q) + directions(q) && modes[static_cast<std::size_t>(q)] == stuck)
                    right(tangential(q) + (i - slider(q)), k) = -1.0;
        }
    }
    // x's turn with the directions of wrt's columns
    auto turned = [&](const VectorXd& x) {
        MatrixXd out = MatrixXd::Zero(L, nw);
        for (Eigen::Index k = 0; k < nw; ++k) {
            const int q = turning[static_cast<std::size_t>(k)];
            if (q < 0) continue;
            const double angle = zhat(theta(q)), weight = s_.blocks[static_cast<std::size_t>(q)].mu * x(normal(q));
            out(tangential(q), k) = -weight * std::sin(angle);
            out(tangential(q) + 1, k) = weight * std::cos(angle);
        }
        return out;
    };
    // d lambda / d wrt, d y'' / d wrt
    const MatrixXd dlambda = lu.solve(right + turned(lambda));
    MatrixXd dacc = transmit_ * dlambda;
    for (Eigen::Index k = 0; k < nw; ++k)
        if (wrt[static_cast<std::size_t>(k)] < y2) dacc.col(k) += base_.col(wrt[static_cast<std::size_t>(k)]);
    J = MatrixXd::Zero(m, nw);
    J.topRows(nm) = dz.bottomRows(nm);
    J.middleRows(nm, nm) = dacc;
    if (more) {
        MatrixXd on_free = MatrixXd::Zero(L, nw);  // free_'s columns of wrt (q0 moves with y only)
        for (Eigen::Index k = 0; k < nw; ++k)
            if (wrt[static_cast<std::size_t>(k)] < y2) on_free.col(k) = free_.col(wrt[static_cast<std::size_t>(k)]);
        more->lambda = lambda;
        more->dlambda = dlambda;
        more->relative = free_ * c.col(0).head(n) - s_.G * lambda;
        more->drelative = on_free - s_.G * dlambda;
    }
    if (nv == 0 && !more) return;
    // z1 and its derivative (its rows y, y' move)
    VectorXd z1 = VectorXd::Zero(n);
    z1.head(y2) = c.col(1).head(y2);
    z1(cos_index()) = c(cos_index(), 1);
    z1(sin_index()) = c(sin_index(), 1);
    MatrixXd dz1(y2, nw);
    dz1.topRows(nm) = dz.bottomRows(nm);
    dz1.bottomRows(nm) = dacc;
    const MatrixXd free_y = kept.asDiagonal() * free_.leftCols(y2);
    const VectorXd x1 = lu.solve(kept.cwiseProduct(free_ * z1));
    const VectorXd q1 = free_ * z1 - s_.G * x1;
    const MatrixXd dq1 = free_.leftCols(y2) * dz1 - s_.G * lu.solve(free_y * dz1 + turned(x1));
    if (nv == 0) {
        more->relative_rate = q1;
        more->drelative_rate = dq1;
        return;
    }
    // P, and the derivative of P theta' with theta' held
    VectorXd thetadot(nv);
    MatrixXd E = MatrixXd::Zero(L, nv);
    for (Eigen::Index b = 0; b < nv; ++b) {
        const int q = moving[static_cast<std::size_t>(b)], T = tangential(q);
        thetadot(b) = c(theta(q), 1);
        const double angle = zhat(theta(q)), weight = s_.blocks[static_cast<std::size_t>(q)].mu * lambda(normal(q));
        E(T, b) = -weight * std::sin(angle);
        E(T + 1, b) = weight * std::cos(angle);
    }
    const MatrixXd GAE = s_.G * lu.solve_on_cones(E);
    const VectorXd what = lu.solve_on_cones(E * thetadot).col(0);
    const VectorXd Gw = s_.G * what;
    right = turned(what);
    for (Eigen::Index b = 0; b < nv; ++b) {
        const int q = moving[static_cast<std::size_t>(b)], T = tangential(q);
        const double angle = zhat(theta(q)), mu = s_.blocks[static_cast<std::size_t>(q)].mu;
        const Eigen::Vector2d perp(-std::sin(angle), std::cos(angle)), along(std::cos(angle), std::sin(angle));
        for (int i = 0; i < 2; ++i) right.row(T + i) += (mu * perp(i) * thetadot(b)) * dlambda.row(normal(q));
        for (Eigen::Index k = 0; k < nw; ++k)
            if (in_moving[static_cast<std::size_t>(k)] == b)
                for (int i = 0; i < 2; ++i) right(T + i, k) -= mu * lambda(normal(q)) * along(i) * thetadot(b);
    }
    const MatrixXd dGw = s_.G * lu.solve_on_cones(right);
    MatrixXd P(nv, nv), D(nv, nw);
    for (Eigen::Index a = 0; a < nv; ++a) {
        const int T = tangential(moving[static_cast<std::size_t>(a)]);
        const double angle = zhat(theta(moving[static_cast<std::size_t>(a)]));
        const double sa = std::sin(angle), ca = std::cos(angle);
        P.row(a) = -(-sa * GAE.row(T) + ca * GAE.row(T + 1));
        // d b_a - d (P theta')_a
        D.row(a) = -(-sa * dq1.row(T) + ca * dq1.row(T + 1)) + (-sa * dGw.row(T) + ca * dGw.row(T + 1));
        for (Eigen::Index k = 0; k < nw; ++k)
            if (in_moving[static_cast<std::size_t>(k)] == a)
                D(a, k) += (ca * q1(T) + sa * q1(T + 1)) - (ca * Gw(T) + sa * Gw(T + 1));
    }
    J.bottomRows(nv) = P.fullPivLu().solve(D);
    if (more) {
        more->relative_rate = q1 - Gw;
        more->drelative_rate = dq1 - dGw - GAE * J.bottomRows(nv);
    }
}

std::vector<int> ConeEngine::independent(const Modes& modes) const {
    std::vector<int> x;
    for (int k = 0; k < 2 * n_dofs_; ++k) x.push_back(k);
    for (int q = 0; q < n_contacts_; ++q)
        if (modes[static_cast<std::size_t>(q)] == stuck)
            for (int j = 0; j < directions(q); ++j) x.push_back(slider(q) + j);
    for (int q = 0; q < n_contacts_; ++q)
        if (modes[static_cast<std::size_t>(q)] == slip && directions(q) == 2) x.push_back(theta(q));
    return x;
}

void ConeEngine::step_sensitivity(const MatrixXd& u, double h, double s_end, bool implicit, const Modes& modes,
                                  const std::vector<char>& frozen, bool opens_at_end, MatrixXd& phi) const {
    // The variational equation d(dv)/dt = J_v dv + J_c dc along the step's polynomial (dv: y, y'
    // and the moving directions; dc: the held positions and held directions, constant over the
    // step), by Radau IIA with collocation_stages stages: on an implicit step over the step
    // itself (the trajectory's own method and step), on a Taylor step over substeps of at most
    // half a period of the structure's fastest mode over pi (its order-11 error then below
    // rounding).
    const RadauTable& R = radau_table(collocation_stages);
    const int s = R.stages, nm = n_dofs_, n = n_;
    const std::vector<int> x = independent(modes);
    const auto nx = static_cast<Eigen::Index>(x.size());
    const std::vector<int> dyn = moving_entries(modes, frozen);
    const auto m = static_cast<Eigen::Index>(dyn.size());
    // the rows of x that move (dyn), and those that stay; of those, the ones phi depends on (a
    // held position's row is zero where the flow is not differentiated with respect to it and
    // no event has set it: its Jacobian's column is not needed)
    std::vector<Eigen::Index> moves, stays;
    for (Eigen::Index k = 0; k < nx; ++k) {
        if (std::find(dyn.begin(), dyn.end(), x[static_cast<std::size_t>(k)]) != dyn.end())
            moves.push_back(k);
        else if (phi.row(k).cwiseAbs().maxCoeff() > 0.0)
            stays.push_back(k);
    }
    // the Jacobian's columns: the moving entries (dyn's order), then the stays
    std::vector<int> wrt = dyn;
    for (const Eigen::Index k : stays) wrt.push_back(x[static_cast<std::size_t>(k)]);
    int substeps = 1;
    // At a step's end where a slipping contact opens, its direction's rate is 0 / 0 (its normal
    // force and the force's turning are both zero to rounding there): the last stage's Jacobian
    // is then rounding divided by rounding, and the stiff stage equation (the direction's rate
    // ~ 1 / lambda_N) carries it into the whole step's sensitivity. The stage is taken
    // opening_back_off of its substep before the end instead (where the quotient is accurate and
    // the stage still as stiff: the result does not change between 1e-7 and 1e-3 of it). Where
    // the matrix itself is singular there, the Jacobian just before the end.
    auto stage_jacobian = [&](double sigma) {
        MatrixXd J;
        VectorXd rate;
        if (opens_at_end && s_end > 0.0 && sigma >= s_end * (1.0 - 1e-12))
            sigma = s_end - opening_back_off * s_end / substeps;
        for (double back : {0.0, 1e-9, 1e-7, 1e-5}) {
            try {
                rates_jacobian(evaluate(u, sigma * (1.0 - back)).head(n), modes, frozen, dyn, wrt, J, rate);
                return J;  // m x wrt
            } catch (const std::runtime_error&) {
                if (back == 1e-5) throw;
            }
        }
        return J;
    };
    if (!implicit) {
        const MatrixXd J0 = stage_jacobian(0.0);
        const double fastest = std::sqrt(J0.block(nm, 0, nm, nm).cwiseAbs().rowwise().sum().maxCoeff());
        substeps = std::clamp(static_cast<int>(std::ceil(s_end * h * fastest / 0.5)), 1, 256);
    }
    const auto held = static_cast<Eigen::Index>(stays.size());
    MatrixXd dc(held, phi.cols());
    for (Eigen::Index k = 0; k < held; ++k) dc.row(k) = phi.row(stays[static_cast<std::size_t>(k)]);
    for (int sub = 0; sub < substeps; ++sub) {
        const double a0 = s_end * sub / substeps, width = s_end / substeps, length = width * h;
        // per stage: Jv (m x m), and Jc dc (the held entries' share of the rates' change)
        std::vector<MatrixXd> Jv(static_cast<std::size_t>(s)), Jcdc(static_cast<std::size_t>(s));
        for (int i = 0; i < s; ++i) {
            const MatrixXd J = stage_jacobian(a0 + R.c(i) * width);
            Jv[static_cast<std::size_t>(i)] = J.leftCols(m);
            if (held > 0) Jcdc[static_cast<std::size_t>(i)].noalias() = J.rightCols(held) * dc;
        }
        // (I - length (A x I) blockdiag(Jv)) dV = 1 x dv_a + length (A x I) [Jc_j dc]
        MatrixXd M = MatrixXd::Identity(s * m, s * m);
        MatrixXd dva(m, phi.cols());
        for (Eigen::Index k = 0; k < m; ++k) dva.row(k) = phi.row(moves[static_cast<std::size_t>(k)]);
        MatrixXd rhs(s * m, phi.cols());
        for (int i = 0; i < s; ++i) {
            rhs.middleRows(i * m, m) = dva;
            for (int j = 0; j < s; ++j) {
                M.block(i * m, j * m, m, m) -= (length * R.a(i, j)) * Jv[static_cast<std::size_t>(j)];
                if (held > 0) rhs.middleRows(i * m, m) += (length * R.a(i, j)) * Jcdc[static_cast<std::size_t>(j)];
            }
        }
        const MatrixXd dV = M.partialPivLu().solve(rhs);
        for (Eigen::Index k = 0; k < m; ++k) phi.row(moves[static_cast<std::size_t>(k)]) = dV.row((s - 1) * m + k);
    }
}

std::vector<int> ConeEngine::moving_entries(const Modes& modes, const std::vector<char>& frozen) const {
    std::vector<int> dyn;
    for (int k = 0; k < 2 * n_dofs_; ++k) dyn.push_back(k);
    for (int q = 0; q < n_contacts_; ++q)
        if (modes[static_cast<std::size_t>(q)] == slip && directions(q) == 2 &&
            !(!frozen.empty() && frozen[static_cast<std::size_t>(q)]))
            dyn.push_back(theta(q));
    return dyn;
}

MatrixXd ConeEngine::event_sensitivity(const MatrixXd& u, double h, double s_end, const Modes& before,
                                       const std::vector<char>& frozen, const std::vector<Guard>& triggers,
                                       const Modes& after, const VectorXd& zhat_after,
                                       const std::vector<char>& closing, const MatrixXd& phi,
                                       EventTimes& times) const {
    // A perturbed flow meets the event dtau later, dtau = -(grad g . dx) / g' (g the first
    // trigger's guard); just after it, each independent entry of the new pattern is a function
    // R of the state before (carried, the held position of a contact that sticks: its q_T, the
    // direction of one that slips: its force's, or the consistent one where it starts from zero
    // force), and dx+ = DR (dx- + f- dtau) - f+ dtau (f-, f+: the rates before and after).
    const int nm = n_dofs_, n = n_, L = s_.lambdas;
    const std::vector<int> xb = independent(before), xa = independent(after);
    const VectorXd zb = evaluate(u, s_end).head(n);
    // the recorded vector's rate (per time) before the event
    VectorXd rate_before = VectorXd::Zero(n + L);
    {
        double power = 1.0;
        for (Eigen::Index k = 1; k < u.cols(); ++k) {
            rate_before += (static_cast<double>(k) * power) * u.col(k);
            power *= s_end;
        }
        rate_before /= h;
    }
    MatrixXd J;
    VectorXd rate;
    ContactDerivatives D;
    // where a slipping contact opens its direction equation is singular at the event: the
    // derivatives just before it instead
    for (double back : {0.0, 1e-9, 1e-7, 1e-5}) {
        try {
            rates_jacobian(back == 0.0 ? zb : VectorXd(evaluate(u, s_end * (1.0 - back)).head(n)), before, frozen,
                           moving_entries(before, frozen), xb, J, rate, &D);
            break;
        } catch (const std::runtime_error&) {
            if (back == 1e-5) throw;
        }
    }
    auto row_of = [](const std::vector<int>& x, int entry) {
        return static_cast<Eigen::Index>(std::find(x.begin(), x.end(), entry) - x.begin());
    };
    // each trigger's time change: its guard's gradient over xb and its rate along the flow
    auto timing = [&](const Guard& g) -> Eigen::RowVectorXd {
        const int c = g.contact, T = tangential(c), N = normal(c);
        const double mu = s_.blocks[static_cast<std::size_t>(c)].mu;
        Eigen::RowVectorXd grad;
        switch (g.kind) {
            case guard_gap: grad = -D.drelative.row(N); break;
            case guard_normal: grad = D.dlambda.row(N); break;
            case guard_limit:
            case guard_limit_negative:
                if (directions(c) == 2)
                    grad = 2.0 * mu * mu * D.lambda(N) * D.dlambda.row(N) - 2.0 * D.lambda(T) * D.dlambda.row(T) -
                           2.0 * D.lambda(T + 1) * D.dlambda.row(T + 1);
                else
                    grad = mu * D.dlambda.row(N) + (g.kind == guard_limit ? -1.0 : 1.0) * D.dlambda.row(T);
                break;
            default: {  // the slip speed
                if (directions(c) == 2) {
                    const double angle = zb(theta(c)), ca = std::cos(angle), sa = std::sin(angle);
                    grad = ca * D.drelative_rate.row(T) + sa * D.drelative_rate.row(T + 1);
                    grad(row_of(xb, theta(c))) += -sa * D.relative_rate(T) + ca * D.relative_rate(T + 1);
                } else {
                    grad = (before[static_cast<std::size_t>(c)] > 0 ? 1.0 : -1.0) * D.drelative_rate.row(T);
                }
            }
        }
        double slope = 0.0, terms = 0.0, power = 1.0;
        for (Eigen::Index k = 1; k < g.row.size(); ++k) {
            slope += static_cast<double>(k) * power * g.row(k);
            terms += static_cast<double>(k) * power * std::abs(g.row(k));
            power *= s_end;
        }
        if (!(std::abs(slope) > 1e-10 * terms)) {  // grazing: no time change (as the 2D engine)
            times.grazing = true;
            return Eigen::RowVectorXd::Zero(phi.cols());
        }
        return -(grad * phi) / (slope / h);
    };
    // Simultaneous events (symmetric contacts): each contact's new entries move with its own
    // event's time; the carried entries with the first's. (Where such events couple, the map is
    // only piecewise differentiable: the order of the perturbed events matters.)
    // A cascade (events at the instant of the last ones, after a step of zero length): their
    // times are the last events' (the perturbed flow meets the cascade where it meets those).
    const bool cascade = !(s_end > 0.0) && times.first.size() == phi.cols();
    std::vector<Eigen::RowVectorXd> dtau_of(static_cast<std::size_t>(n_contacts_));
    if (cascade) times.of.resize(static_cast<std::size_t>(n_contacts_));
    for (const Guard& t : triggers) {
        const auto c = static_cast<std::size_t>(t.contact);
        dtau_of[c] = !cascade ? timing(t) : times.of[c].size() ? times.of[c] : times.first;
    }
    const Eigen::RowVectorXd dtau =
        cascade ? times.first : dtau_of[static_cast<std::size_t>(triggers.front().contact)];
    if (!cascade) times.of.assign(static_cast<std::size_t>(n_contacts_), Eigen::RowVectorXd());
    for (const Guard& t : triggers) times.of[static_cast<std::size_t>(t.contact)] = dtau_of[static_cast<std::size_t>(t.contact)];
    times.first = dtau;
    // the rates after, with the directions the flow's next step holds: those closing here and
    // the slipping contacts pressed below hold_share (one that closed at this instant, before a
    // cascade: its free direction's rate would divide by its zero normal force)
    const MatrixXd next = series(zhat_after, after, 0.0, 1, closing, true);
    MatrixXd out(static_cast<Eigen::Index>(xa.size()), phi.cols());
    std::vector<char> triggered(static_cast<std::size_t>(n_contacts_), 0);
    for (const Guard& t : triggers) triggered[static_cast<std::size_t>(t.contact)] = 1;
    for (std::size_t r = 0; r < xa.size(); ++r) {
        const int i = xa[r];
        const auto row = static_cast<Eigen::Index>(r);
        if (i < 2 * nm) {
            out.row(row) = phi.row(row_of(xb, i));  // y'' is continuous
            continue;
        }
        if (i < theta(0)) {  // a held position
            const int q = slider_contact(i);
            if (before[static_cast<std::size_t>(q)] == stuck) {
                out.row(row) = phi.row(row_of(xb, i));
            } else {  // it sticks here: its q_T
                const int e = tangential(q) + (i - slider(q));
                const Eigen::RowVectorXd& own = dtau_of[static_cast<std::size_t>(q)].size() ? dtau_of[static_cast<std::size_t>(q)] : dtau;
                out.row(row) = D.drelative.row(e) * phi + rate_before(i) * own;
            }
            continue;
        }
        const int q = i - theta(0);
        if (!triggered[static_cast<std::size_t>(q)] && before[static_cast<std::size_t>(q)] == slip) {
            out.row(row) = phi.row(row_of(xb, i)) + (rate_before(i) - next(i, 1)) * dtau;
            continue;
        }
        const int Tq = tangential(q);
        const Eigen::RowVectorXd& own = dtau_of[static_cast<std::size_t>(q)].size() ? dtau_of[static_cast<std::size_t>(q)] : dtau;
        if (before[static_cast<std::size_t>(q)] == stuck && !closing[static_cast<std::size_t>(q)]) {
            // from stick: its force's direction
            const double l1 = D.lambda(Tq), l2 = D.lambda(Tq + 1), norm2 = l1 * l1 + l2 * l2;
            const Eigen::RowVectorXd dtheta = (l1 * D.dlambda.row(Tq + 1) - l2 * D.dlambda.row(Tq)) / norm2;
            const double turning = (l1 * rate_before(n + Tq + 1) - l2 * rate_before(n + Tq)) / norm2;
            out.row(row) = dtheta * phi + (turning - next(i, 1)) * own;
            continue;
        }
        // from zero force (a closing) or from a stop (a slip that restarts at once): the consistent
        // direction, phi_q(theta, z) = d_perp . q_T' = 0 in the new pattern with the direction
        // held; its derivatives over xb and theta_q, and its change along the flow before
        // (differences in time of the state before)
        std::vector<int> wrt = xb;
        wrt.push_back(i);
        MatrixXd Ja;
        VectorXd ra;
        ContactDerivatives Da;
        // with q's direction held (a moving direction keeps d_perp . q_T' = 0 by its own rate:
        // a restart after a stop would give 0 / 0)
        std::vector<char> held = closing;
        held[static_cast<std::size_t>(q)] = 1;
        rates_jacobian(zhat_after, after, held, moving_entries(after, held), wrt, Ja, ra, &Da);
        const double angle = zhat_after(i), ca = std::cos(angle), sa = std::sin(angle);
        const Eigen::RowVectorXd dphi = -sa * Da.drelative_rate.row(Tq) + ca * Da.drelative_rate.row(Tq + 1);
        const double along = dphi(dphi.size() - 1) - (ca * Da.relative_rate(Tq) + sa * Da.relative_rate(Tq + 1));
        Eigen::RowVectorXd dtheta = -dphi.head(dphi.size() - 1) / along;
        // a slip that restarts after a stop: its direction before does not enter (replaced)
        if (const Eigen::Index old = row_of(xb, i); old < static_cast<Eigen::Index>(xb.size())) dtheta(old) = 0.0;
        // the explicit time dependence (the forcing's phase) by the state before at s_end +- delta
        auto consistency = [&](double sigma) {
            VectorXd z = evaluate(u, sigma).head(n);
            z(i) = angle;
            z.segment(slider(q), directions(q)) = zhat_after.segment(slider(q), directions(q));
            const MatrixXd cz = series(z, after, 0.0, 1, held, false);
            return -sa * cz(slider(q), 1) + ca * cz(slider(q) + 1, 1);
        };
        const double delta = 1e-6;
        const double moving_phi = (consistency(s_end + delta) - consistency(s_end - delta)) / (2.0 * delta * h);
        out.row(row) = dtheta * phi + (-moving_phi / along) * own;
    }
    return out;
}

bool ConeEngine::collocation_step(const VectorXd& zhat, const Modes& modes, double h, const std::vector<char>& frozen,
                                  StartJacobian& start, const PreviousStep& last, MatrixXd& u, double& error) const {
    const double tolerance = start_flows_ ? start_tolerance : collocation_tolerance;
    const RadauTable& R = radau_table(collocation_stages);
    const int s = R.stages, nm = n_dofs_, n = n_, L = s_.lambdas;
    // The integrated components: y, y' and the directions of the slipping 3D contacts not held.
    const std::vector<int> dyn = moving_entries(modes, frozen);
    const int m = static_cast<int>(dyn.size());
    const double size = size_scale_ > 0.0 ? size_scale_ : 1.0;
    // A direction's error counts by the friction force it steers: in radians at a contact pressed
    // by the largest force met, looser in proportion where its normal force is smaller (the
    // tangential force's error mu lambda_N dtheta is then the same share of the forces).
    VectorXd w0;
    try {
        w0 = series(zhat, modes, 0.0, 0, frozen, false).col(0);
    } catch (const std::runtime_error&) {  // a singular pattern at the start: a failed step
        return false;
    }
    auto direction_scale = [&](int k, double pressed) {
        const int q = dyn[static_cast<std::size_t>(k)] - theta(0);
        const double normal_force = std::max(pressed, w0(n + normal(q)));
        return normal_force > 0.0 && force_scale_ > normal_force ? force_scale_ / normal_force : 1.0;
    };
    VectorXd scale(m);
    for (int k = 0; k < m; ++k) scale(k) = dyn[static_cast<std::size_t>(k)] < nm ? size
                                           : dyn[static_cast<std::size_t>(k)] < 2 * nm ? size * omega_
                                                                                        : direction_scale(k, 0.0);
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
            const MatrixXd c = series(z, modes, 0.0, 1, frozen, false, true);
            for (int k = 0; k < m; ++k) f(k) = c(dyn[static_cast<std::size_t>(k)], 1);
        } catch (const std::runtime_error&) {  // a singular pattern at a trial state: a shorter step
            f.setConstant(std::numeric_limits<double>::quiet_NaN());
        }
        return f;
    };
    VectorXd v0(m);
    for (int k = 0; k < m; ++k) v0(k) = zhat(dyn[static_cast<std::size_t>(k)]);
    // Newton's matrix: the rates' Jacobian at the step's start, unless one of an earlier start
    // of the pattern is kept.
    if (start.J.rows() != m) {
        try {
            rates_jacobian(zhat, modes, frozen, dyn, start.J, start.rate);
        } catch (const std::runtime_error&) {
            return false;
        }
        start.fresh = true;
    }
    if (start.rate.size() != m) start.rate = rate(zhat);
    const VectorXd& f0 = start.rate;
    const MatrixXd& J = start.J;
    // Newton's matrix I - h A (x) J by A's eigen-decomposition (radau.hpp): one complex m x m
    // system per eigenvalue, one per conjugate pair, instead of one of size s m.
    std::vector<Eigen::PartialPivLU<Eigen::MatrixXcd>> lus(static_cast<std::size_t>(s));
    {
        const Eigen::MatrixXcd hJ = (h * J).cast<std::complex<double>>();
        for (int k = 0; k < s; ++k)
            if (R.partner(k) < 0)
                lus[static_cast<std::size_t>(k)].compute(R.lambda(k) * Eigen::MatrixXcd::Identity(m, m) - hJ);
    }
    auto newton_step = [&](const MatrixXd& G) {
        const Eigen::MatrixXcd rhs = -G * R.right;
        Eigen::MatrixXcd w(m, s);
        for (int k = 0; k < s; ++k)
            if (R.partner(k) < 0) w.col(k) = lus[static_cast<std::size_t>(k)].solve(rhs.col(k));
        for (int k = 0; k < s; ++k)
            if (R.partner(k) >= 0) w.col(k) = w.col(R.partner(k)).conjugate();
        return MatrixXd((w * R.vectors.transpose()).real());
    };
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
        const MatrixXd dz = newton_step(Z - h * F * R.a.transpose());
        Z += dz;
        double change = 0.0;
        for (int i = 0; i < s; ++i) change = std::max(change, (dz.col(i).array().abs() / scale.array()).maxCoeff());
        if (!std::isfinite(change)) return false;
        if (change <= newton_share * tolerance) {
            converged = true;
            break;
        }
        if (it >= 2 && change > 0.5 * previous) {  // not contracting: rounding, or a shorter step
            converged = change <= tolerance;
            break;
        }
        previous = change;
    }
    if (!converged) return false;
    // The recorded vector [zhat, lambda] at the nodes, and its polynomial in sigma: the value at
    // sigma = 0 plus the polynomial of the increments (the integrated rows' from Z).
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
        VectorXd value = VectorXd::Zero(n + L), slope = VectorXd::Zero(n);
        double power = 1.0;
        for (int k = 0; k <= s; ++k) {
            value += power * u.col(k);
            if (k + 1 <= s) slope += (k + 1) * power * u.col(k + 1).head(n);
            power *= sigma;
        }
        VectorXd v(m), dv(m), weight = scale;
        for (int k = 0; k < m; ++k) {
            v(k) = value(dyn[static_cast<std::size_t>(k)]);
            dv(k) = slope(dyn[static_cast<std::size_t>(k)]) / h;
            if (dyn[static_cast<std::size_t>(k)] >= 2 * nm)
                weight(k) = direction_scale(k, value(n + normal(dyn[static_cast<std::size_t>(k)] - theta(0))));
        }
        const VectorXd defect = dv - rate(full(v, sigma));
        const VectorXd e = filter.solve(h * defect);
        if (!e.allFinite()) return false;
        const double worst = (e.array().abs() / weight.array()).maxCoeff();
        error = std::max(error, worst / tolerance);
    }
    return true;
}

}  // namespace hbf::detail::exact
