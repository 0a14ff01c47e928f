// hbfriction — the largest-margin centre of a stuck 3D contact (enclosing_circle.hpp).
#include "contact/enclosing_circle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace hbf::detail {

namespace {

class Welzl {
public:
    Welzl(const Eigen::MatrixXd& u, const Eigen::VectorXd& r, double scale) : u_(u), r_(r), scale_(scale) {}

    EnclosingCircle solve() const {
        const int count = static_cast<int>(u_.rows());
        std::vector<int> order(static_cast<std::size_t>(count));
        for (int j = 0; j < count; ++j) order[static_cast<std::size_t>(j)] = j;
        unsigned long long state = 0x9E3779B97F4A7C15ull;
        for (int j = count - 1; j > 0; --j) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            std::swap(order[static_cast<std::size_t>(j)], order[static_cast<std::size_t>((state >> 33) % (j + 1))]);
        }
        const double tolerance = 1e-12 * scale_;
        EnclosingCircle b = one(order[0]);
        for (int i = 1; i < count; ++i) {
            const int pi = order[static_cast<std::size_t>(i)];
            if (excess(pi, b) <= tolerance) continue;
            b = one(pi);
            for (int j = 0; j < i; ++j) {
                const int pj = order[static_cast<std::size_t>(j)];
                if (excess(pj, b) <= tolerance) continue;
                b = two(pi, pj);
                for (int k = 0; k < j; ++k) {
                    const int pk = order[static_cast<std::size_t>(k)];
                    if (excess(pk, b) <= tolerance) continue;
                    b = three(pi, pj, pk);
                }
            }
        }
        return b;
    }

private:
    Eigen::Vector2d point(int j) const { return u_.row(j).transpose(); }
    double excess(int j, const EnclosingCircle& b) const { return (b.centre - point(j)).norm() - r_(j) - b.value; }
    EnclosingCircle one(int a) const {
        EnclosingCircle b;
        b.centre = point(a);
        b.value = -r_(a);
        b.member[0] = a;
        b.size = 1;
        return b;
    }
    /// The optimum of constraints a and b, both tight when possible.
    EnclosingCircle two(int a, int b) const {
        const Eigen::Vector2d gap = point(b) - point(a);
        const double distance = gap.norm(), t = 0.5 * (distance + r_(a) - r_(b));
        if (t <= 0.0) return one(a);
        if (t >= distance) return one(b);
        EnclosingCircle out;
        out.centre = point(a) + t * gap / distance;
        out.value = t - r_(a);
        out.member = {a, b, -1};
        out.size = 2;
        return out;
    }
    /// The optimum of constraints a, b and c: the point with |s - u_i| - r_i equal for the three
    /// (the circle tangent to three, the smallest common value) where that is the optimum, else
    /// the best pair or single constraint. Each candidate is judged by its own largest excess
    /// over the three, so that rounding near a degenerate configuration (collinear centres, a
    /// tangent circle that barely exists) picks the best of them instead of none.
    EnclosingCircle three(int a, int b, int c) const {
        EnclosingCircle best;
        double best_value = std::numeric_limits<double>::infinity();
        const auto consider = [&](EnclosingCircle candidate) {
            candidate.value = std::max({(candidate.centre - point(a)).norm() - r_(a),
                                        (candidate.centre - point(b)).norm() - r_(b),
                                        (candidate.centre - point(c)).norm() - r_(c)});
            if (candidate.value < best_value) {
                best_value = candidate.value;
                best = candidate;
            }
        };
        // 2 s.(u_i - u_a) + 2 R (r_i - r_a) = |u_i|^2 - |u_a|^2 - r_i^2 + r_a^2 (i = b, c),
        // then |s - u_a| = R + r_a, a quadratic in R.
        const Eigen::Vector2d ua = point(a);
        Eigen::Matrix2d A;
        Eigen::Vector2d rhs, coupling;
        int row = 0;
        for (int i : {b, c}) {
            const Eigen::Vector2d ui = point(i);
            A.row(row) = 2.0 * (ui - ua).transpose();
            coupling(row) = 2.0 * (r_(i) - r_(a));
            rhs(row) = ui.squaredNorm() - ua.squaredNorm() - r_(i) * r_(i) + r_(a) * r_(a);
            ++row;
        }
        const Eigen::FullPivLU<Eigen::Matrix2d> lu(A);
        if (lu.isInvertible()) {
            const Eigen::Vector2d s0 = lu.solve(rhs), s1 = -lu.solve(coupling);
            const Eigen::Vector2d w = s0 - ua;
            const double qa = s1.squaredNorm() - 1.0, qb = 2.0 * (w.dot(s1) - r_(a)), qc = w.squaredNorm() - r_(a) * r_(a);
            double roots[2];
            int count = 0;
            if (std::abs(qa) < 1e-14) {
                if (qb != 0.0) roots[count++] = -qc / qb;
            } else {
                const double disc = qb * qb - 4.0 * qa * qc;
                if (disc >= 0.0) {
                    const double root = std::sqrt(disc);
                    roots[count++] = (-qb - root) / (2.0 * qa);
                    roots[count++] = (-qb + root) / (2.0 * qa);
                }
            }
            const double floor = -std::min({r_(a), r_(b), r_(c)});
            for (int k = 0; k < count; ++k) {
                if (!(roots[k] >= floor) || !std::isfinite(roots[k])) continue;
                EnclosingCircle tangent;
                tangent.centre = s0 + roots[k] * s1;
                tangent.member = {a, b, c};
                tangent.size = 3;
                consider(tangent);
            }
        }
        // The pairs and the single constraints (collinear centres, no tangent circle, or one of
        // them the optimum).
        const std::array<std::array<int, 2>, 3> pairs = {{{a, b}, {a, c}, {b, c}}};
        for (const auto& p : pairs) consider(two(p[0], p[1]));
        for (int i : {a, b, c}) consider(one(i));
        // Newton on the three tangencies from the best candidate: near collinear centres the
        // closed form above loses digits (measured: 1.7e-9 of a margin of 9 above the optimum).
        Eigen::Vector2d centre = best.centre;
        double common = best.value;
        for (int iteration = 0; iteration < 6; ++iteration) {
            Eigen::Matrix3d jacobian;
            Eigen::Vector3d mismatch;
            int k = 0;
            for (int i : {a, b, c}) {
                const Eigen::Vector2d d = centre - point(i);
                const double distance = d.norm();
                if (!(distance > 0.0)) return best;
                mismatch(k) = distance - r_(i) - common;
                jacobian.row(k) << d.transpose() / distance, -1.0;
                ++k;
            }
            const Eigen::Vector3d step = jacobian.fullPivLu().solve(-mismatch);
            if (!step.allFinite()) return best;
            centre += step.head<2>();
            common += step(2);
        }
        EnclosingCircle polished;
        polished.centre = centre;
        polished.member = {a, b, c};
        polished.size = 3;
        consider(polished);
        return best;
    }

    const Eigen::MatrixXd& u_;
    const Eigen::VectorXd& r_;
    double scale_;
};

}  // namespace

EnclosingCircle smallest_enclosing_circle(const Eigen::MatrixXd& u, const Eigen::VectorXd& r, double scale) {
    if (u.rows() == 0 || u.cols() != 2 || r.size() != u.rows())
        throw std::runtime_error("smallest_enclosing_circle: " + std::to_string(u.rows()) + " x " +
                                 std::to_string(u.cols()) + " points and " + std::to_string(r.size()) + " radii");
    return Welzl(u, r, scale).solve();
}

EnclosingDerivative enclosing_circle_derivative(const Eigen::MatrixXd& u, const Eigen::VectorXd& r,
                                                const EnclosingCircle& b) {
    EnclosingDerivative out;
    for (int k = 0; k < 3; ++k) {
        out.du[static_cast<std::size_t>(k)].setZero();
        out.dr[static_cast<std::size_t>(k)].setZero();
    }
    const auto point = [&](int j) -> Eigen::Vector2d { return u.row(j).transpose(); };
    if (b.size == 1) {
        out.du[0].setIdentity();
        return out;
    }
    if (b.size == 2) {  // s = u_a + t e, t = (|u_c - u_a| + r_a - r_c) / 2, e = (u_c - u_a) / |u_c - u_a|
        const int a = b.member[0], c = b.member[1];
        const Eigen::Vector2d gap = point(c) - point(a);
        const double distance = gap.norm(), t = 0.5 * (distance + r(a) - r(c));
        const Eigen::Vector2d e = gap / distance;
        const Eigen::Matrix2d along = e * e.transpose(), across = Eigen::Matrix2d::Identity() - along;
        // ds = du_a + e dt + (t / D) (I - e e^T) dgap, dgap = du_c - du_a, dt = e^T dgap / 2 + (dr_a - dr_c) / 2
        out.du[1] = 0.5 * along + (t / distance) * across;
        out.du[0] = Eigen::Matrix2d::Identity() - out.du[1];
        out.dr[0] = 0.5 * e;
        out.dr[1] = -0.5 * e;
        return out;
    }
    // [n_i^T, -1] d(s, R) = n_i^T d u_i + d r_i over the three tight constraints.
    Eigen::Matrix3d A;
    std::array<Eigen::Vector2d, 3> normals;
    for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d n = (b.centre - point(b.member[static_cast<std::size_t>(k)])).normalized();
        normals[static_cast<std::size_t>(k)] = n;
        A.row(k) << n.transpose(), -1.0;
    }
    const Eigen::Matrix3d inverse = A.fullPivLu().inverse();
    for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d column = inverse.col(k).head<2>();
        out.du[static_cast<std::size_t>(k)] = column * normals[static_cast<std::size_t>(k)].transpose();
        out.dr[static_cast<std::size_t>(k)] = column;
    }
    return out;
}

}  // namespace hbf::detail
