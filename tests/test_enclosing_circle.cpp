// The largest-margin centre of a stuck 3D contact (src/contact/enclosing_circle.hpp): Welzl's
// optimum against a direct minimisation of the same max, and its derivative against central
// differences.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "contact/enclosing_circle.hpp"

using hbf::detail::EnclosingCircle;

namespace {

double margin(const Eigen::MatrixXd& u, const Eigen::VectorXd& r, const Eigen::Vector2d& s) {
    double worst = -1e300;
    for (Eigen::Index j = 0; j < u.rows(); ++j) worst = std::max(worst, (s - u.row(j).transpose()).norm() - r(j));
    return worst;
}

/// min over s of margin by nested golden sections (the max of convex functions is convex).
double direct_minimum(const Eigen::MatrixXd& u, const Eigen::VectorXd& r) {
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    const auto golden = [&](auto f, double lo, double hi) {
        double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
        for (int it = 0; it < 90; ++it) {
            if (f1 < f2) {
                hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
            } else {
                lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
            }
        }
        return std::min(f1, f2);
    };
    const double lo0 = u.col(0).minCoeff(), hi0 = u.col(0).maxCoeff();
    const double lo1 = u.col(1).minCoeff(), hi1 = u.col(1).maxCoeff();
    return golden([&](double s0) { return golden([&](double s1) { return margin(u, r, {s0, s1}); }, lo1, hi1); },
                  lo0, hi0);
}

}  // namespace

TEST_CASE("Enclosing circle: Welzl's largest-margin centre equals a direct minimisation, and its derivative "
          "central differences",
          "[normal_contact]") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    int sizes[3] = {0, 0, 0};
    for (int trial = 0; trial < 60; ++trial) {
        // A stuck contact's samples: an elliptic loop of the forces (reversed) and a normal load
        // varying over the period, plus noise that moves the optimum's basis around.
        const int nt = 16 + trial % 5 * 8;
        Eigen::MatrixXd u(nt, 2);
        Eigen::VectorXd r(nt);
        const double a = 0.5 + 0.5 * uniform(random), b = 0.3 * uniform(random), phase = 3.0 * uniform(random);
        for (int j = 0; j < nt; ++j) {
            const double t = 2.0 * M_PI * j / nt;
            u(j, 0) = a * std::cos(t) + 0.05 * uniform(random);
            u(j, 1) = b * std::sin(t + phase) + 0.05 * uniform(random);
            r(j) = 1.0 + 0.4 * std::cos(t + 0.7 * trial) + 0.05 * uniform(random);
        }
        const EnclosingCircle c = hbf::detail::smallest_enclosing_circle(u, r, 1.0);
        REQUIRE(c.size >= 1);
        ++sizes[c.size - 1];
        INFO("trial " << trial << ", basis of " << c.size);
        CHECK(std::abs(c.value - margin(u, r, c.centre)) <= 1e-12);
        CHECK(std::abs(c.value - direct_minimum(u, r)) <= 1e-9);
        // The derivative with respect to each basis member's point and radius.
        const hbf::detail::EnclosingDerivative d = hbf::detail::enclosing_circle_derivative(u, r, c);
        const double h = 1e-6;
        for (int k = 0; k < c.size; ++k) {
            const int i = c.member[static_cast<std::size_t>(k)];
            for (int axis = 0; axis < 3; ++axis) {
                Eigen::MatrixXd up = u, down = u;
                Eigen::VectorXd rp = r, rm = r;
                if (axis < 2) {
                    up(i, axis) += h;
                    down(i, axis) -= h;
                } else {
                    rp(i) += h;
                    rm(i) -= h;
                }
                const Eigen::Vector2d fd = (hbf::detail::smallest_enclosing_circle(up, rp, 1.0).centre -
                                            hbf::detail::smallest_enclosing_circle(down, rm, 1.0).centre) /
                                           (2.0 * h);
                const Eigen::Vector2d exact = axis < 2 ? Eigen::Vector2d(d.du[static_cast<std::size_t>(k)].col(axis))
                                                       : d.dr[static_cast<std::size_t>(k)];
                CHECK((fd - exact).norm() <= 1e-6 * std::max(1.0, exact.norm()));
            }
        }
    }
    // The data reach every kind of basis.
    CHECK(sizes[1] > 0);
    CHECK(sizes[2] > 0);
}

TEST_CASE("Enclosing circle: near-degenerate samples (a node pressed hard, its forces moving little) give the "
          "optimum, never no centre",
          "[normal_contact]") {
    // Samples along a short, nearly straight path, radii about 9 varying by as much as the
    // points move: the circle tangent to three samples barely exists, and rounding used to leave
    // neither it nor a covering pair (measured on the mitre example at H = 5: an error thrown
    // mid-continuation). The seeds include two such configurations (trials 472 and 806).
    std::mt19937 random(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int trial = 0; trial < 2000; ++trial) {
        const int nt = 3 + trial % 8 * 16;
        Eigen::MatrixXd u(nt, 2);
        Eigen::VectorXd r(nt);
        const double size = 2e-3, slope = 0.3 * uniform(random), bend = 1e-3 * uniform(random),
                     phase = 3.0 * uniform(random);
        for (int j = 0; j < nt; ++j) {
            const double t = 2.0 * M_PI * j / nt, s = size * std::cos(t + phase);
            u(j, 0) = s;
            u(j, 1) = slope * s + bend * std::sin(t);
            r(j) = 9.27 + 1e-3 * std::cos(t + 0.3 * trial);
        }
        INFO("trial " << trial);
        EnclosingCircle c;
        REQUIRE_NOTHROW(c = hbf::detail::smallest_enclosing_circle(u, r, 10.0));
        REQUIRE(std::abs(c.value - margin(u, r, c.centre)) <= 1e-12);
        // The optimum of a convex function: no nearby centre does better.
        for (int k = 0; k < 16; ++k) {
            const double angle = 2.0 * M_PI * k / 16;
            const Eigen::Vector2d step(1e-7 * std::cos(angle), 1e-7 * std::sin(angle));
            REQUIRE(margin(u, r, c.centre + step) >= c.value - 1e-12);
        }
        if (trial == 472 || trial == 806 || trial % 200 == 0) REQUIRE(std::abs(c.value - direct_minimum(u, r)) <= 1e-9);
    }
}
