// Every closed form of hbf::analytic against an independent path: the complex
// dynamic-stiffness solve (Eigen) of the same linear equations, limits, energy balance and
// the self-consistency of the equivalent-viscous solution.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "support.hpp"

using namespace hbf;
using hbf::test::relative_difference;
namespace an = hbf::analytic;

namespace {
constexpr double pi = 3.14159265358979323846;
const std::vector<double> frequencies = {0.3, 0.55, 0.8, 0.9, 0.97, 1.02, 1.1, 1.35, 2.0};

AbsorberParameters paper() { return AbsorberParameters{}; }
AbsorberParameters detuned() {
    AbsorberParameters p;
    p.mass_ratio = 0.25;
    p.tuning_ratio = 0.8;
    p.friction_coefficient = 0.05;
    p.excitation = 0.9;
    p.contact_stiffness_ratio = 1.3;
    p.contact_damping_ratio = 0.2;
    return p;
}
}  // namespace

TEST_CASE("Coulomb full stick equals the one-DOF system of both masses", "[analytic]") {
    for (const AbsorberParameters& p : {paper(), detuned()}) {
        for (double omega : frequencies) {
            Eigen::MatrixXd M(1, 1), C = Eigen::MatrixXd::Zero(1, 1), K(1, 1);
            M << 1.0 + p.mass_ratio;
            K << 1.0;
            Eigen::VectorXd F(1);
            F << p.excitation;
            const std::complex<double> reference = linear_response(M, C, K, F, omega)(0);
            const an::Response stuck = an::coulomb_stick(p, omega);
            CHECK(relative_difference(stuck.y1, reference) < 1e-13);
            CHECK(relative_difference(stuck.y2, reference) < 1e-13);
        }
    }
}

TEST_CASE("Coulomb limit friction is the contact force the stuck motion needs", "[analytic]") {
    for (const AbsorberParameters& p : {paper(), detuned()}) {
        const System s = friction_absorber(p, FrictionLaw::coulomb);
        for (double omega : frequencies) {
            // Stuck motion y = (Y, Y); the second row of (K - w^2 M) y + w_c f = F gives the
            // force the contact must transmit: f = [(K - w^2 M) y]_2 - F_2  (w_c = (1, -1)).
            const std::complex<double> y = an::coulomb_stick(p, omega).y1;
            const Eigen::Vector2cd motion(y, y);
            const Eigen::MatrixXd z = Eigen::MatrixXd(s.stiffness) - omega * omega * Eigen::MatrixXd(s.mass);
            const std::complex<double> force = (z.cast<std::complex<double>>() * motion)(1) - s.excitation(1);
            CHECK(relative_difference(an::coulomb_limit_friction(p, omega), std::abs(force)) < 1e-12);
        }
    }
}

TEST_CASE("Coulomb slip: the equivalent-viscous solution is self-consistent", "[analytic]") {
    for (const AbsorberParameters& p : {paper(), detuned()}) {
        int found = 0;
        for (double omega = 0.5; omega <= 1.6; omega += 0.01) {
            const auto slip = an::coulomb_slip(p, omega);
            if (!slip) continue;
            ++found;
            // Solve the linear system with the damper c_e(|Y1 - Y2|) in the contact: it must
            // reproduce the same response, whose |Y1 - Y2| then gives back the same c_e.
            const double ce = an::equivalent_damping(p, omega, *slip);
            const Eigen::VectorXcd linear = test::absorber_with_linear_contact(p, omega, 0.0, ce);
            CHECK(relative_difference(linear(0), slip->y1) < 1e-11);
            CHECK(relative_difference(linear(1), slip->y2) < 1e-11);
            // Energy balance per cycle: work of fe cos(w t) on y1 = Coulomb dissipation 4 mu |D|.
            const double input = -pi * p.excitation * std::imag(slip->y1);
            const double dissipated = 4.0 * p.friction_coefficient * std::abs(slip->y1 - slip->y2);
            CHECK(relative_difference(input, dissipated) < 1e-11);
        }
        CHECK(found > 5);
    }
}

TEST_CASE("Coulomb slip exists exactly below (pi/4) mu_limit", "[analytic]") {
    AbsorberParameters p = paper();
    for (double omega : frequencies) {
        const double bound = pi / 4.0 * an::coulomb_limit_friction(p, omega);
        p.friction_coefficient = 0.999 * bound;
        CHECK(an::coulomb_slip(p, omega).has_value());
        p.friction_coefficient = 1.001 * bound;
        CHECK_FALSE(an::coulomb_slip(p, omega).has_value());
    }
}

TEST_CASE("Coulomb slip tends to the frictionless absorber as mu -> 0", "[analytic]") {
    AbsorberParameters p = detuned();
    for (double omega : frequencies) {
        const Eigen::VectorXcd free = test::absorber_with_linear_contact(p, omega, 0.0, 0.0);
        double previous = 1.0;
        for (double mu : {1e-3, 1e-4, 1e-5}) {
            p.friction_coefficient = mu;
            const auto slip = an::coulomb_slip(p, omega);
            REQUIRE(slip.has_value());
            // Absolute error in units of fe: at omega = wa the free Y1 is exactly 0.
            const double error = std::abs(slip->y1 - free(0)) / p.excitation;
            CHECK(error < 50.0 * mu);
            CHECK(error < 0.2 * previous);  // falls in proportion to mu
            previous = error;
        }
    }
}

TEST_CASE("Coulomb at large mu: stick holds and no slipping solution exists", "[analytic]") {
    AbsorberParameters p = paper();
    p.friction_coefficient = 1e6;
    for (double omega : frequencies) {
        CHECK(an::coulomb_limit_friction(p, omega) < p.friction_coefficient);
        CHECK_FALSE(an::coulomb_slip(p, omega).has_value());
    }
}

TEST_CASE("Dahl and LuGre stick responses equal the linear contact solve", "[analytic]") {
    for (const AbsorberParameters& p : {paper(), detuned()}) {
        for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre}) {
            const Contact c = friction_absorber(p, law).contacts[0];
            for (double omega : frequencies) {
                const Eigen::VectorXcd reference = test::absorber_with_linear_contact(p, omega, c.stiffness, c.damping);
                const an::Response stuck = an::contact_stick(p, omega, law);
                CHECK(relative_difference(stuck.y1, reference(0)) < 1e-12);
                CHECK(relative_difference(stuck.y2, reference(1)) < 1e-12);
                // Limit: the pre-sliding contact force (sigma0 + i w sigma1) D reaches mu.
                const std::complex<double> force =
                    std::complex<double>(c.stiffness, omega * c.damping) * (reference(0) - reference(1));
                CHECK(relative_difference(an::contact_limit_friction(p, omega, law), std::abs(force)) < 1e-12);
            }
        }
    }
}

TEST_CASE("Dahl ignores xi, LuGre with xi = 0 equals Dahl", "[analytic]") {
    AbsorberParameters p = detuned();
    const double dahl = an::contact_limit_friction(p, 0.9, FrictionLaw::dahl);
    p.contact_damping_ratio = 0.0;
    CHECK(an::contact_limit_friction(p, 0.9, FrictionLaw::dahl) == dahl);
    CHECK(an::contact_limit_friction(p, 0.9, FrictionLaw::lugre) == Approx(dahl).epsilon(1e-15));
}

TEST_CASE("Dahl and LuGre tend to Coulomb stick as wb -> infinity", "[analytic]") {
    for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre}) {
        AbsorberParameters p = paper();
        for (double omega : frequencies) {
            double previous_error = 1.0;
            for (double wb : {1e1, 1e2, 1e3}) {
                p.contact_stiffness_ratio = wb;
                const double error =
                    relative_difference(an::contact_stick(p, omega, law).y1, an::coulomb_stick(p, omega).y1);
                const double limit_error = relative_difference(an::contact_limit_friction(p, omega, law),
                                                               an::coulomb_limit_friction(p, omega));
                CHECK(error < 10.0 / wb);
                CHECK(limit_error < 10.0 / wb);
                CHECK(error < 0.2 * previous_error);  // converges (as 1/wb for LuGre, 1/wb^2 for Dahl)
                previous_error = error;
            }
        }
    }
}

namespace {
/// max over omega in [0.7, 1.3] (both peaks for r <= 0.2) of |Y1| for the linear damped
/// absorber (damper c, tuning wa), sampled every 5e-4.
double peak_of_damped_absorber(AbsorberParameters p, double c) {
    double peak = 0.0;
    for (double omega = 0.7; omega <= 1.3; omega += 5e-4)
        peak = std::max(peak, std::abs(test::absorber_with_linear_contact(p, omega, 0.0, c)(0)));
    return peak;
}
}  // namespace

TEST_CASE("Den Hartog tuning makes the two fixed points equal at fe sqrt(1 + 2/r)", "[analytic]") {
    for (double r : {0.05, 0.1, 0.3}) {
        AbsorberParameters p = paper();
        p.mass_ratio = r;
        p.tuning_ratio = an::den_hartog_tuning(r);
        CHECK(p.tuning_ratio == Approx(1.0 / (1.0 + r)));
        // Den Hartog's fixed points (independent of damping) for the optimal tuning:
        // omega^2 = (1 -+ sqrt(r / (2 + r))) / (1 + r), height fe sqrt(1 + 2 / r).
        for (double sign : {-1.0, 1.0}) {
            const double omega = std::sqrt((1.0 + sign * std::sqrt(r / (2.0 + r))) / (1.0 + r));
            for (double c : {0.01, 0.1, 1.0}) {
                const double height = std::abs(test::absorber_with_linear_contact(p, omega, 0.0, c)(0));
                CHECK(height == Approx(p.excitation * std::sqrt(1.0 + 2.0 / r)).epsilon(1e-10));
            }
        }
    }
}

TEST_CASE("Den Hartog damping ratio goes with the absorber-frequency normalisation", "[analytic]") {
    // Den Hartog's xi_op is an approximation of the minimax damping: with c = 2 r wa xi_op the
    // peak must be within 0.5% of the fixed-point height (it is 0.1-0.3% above for these r),
    // and the numerically best damping within 2% of xi_op. The other normalisation
    // (c = 2 r xi_op, i.e. xi / (1 + r) after tuning) overshoots the fixed points at least
    // three times as much (measured: 8x for r = 0.05, 12x for 0.1, 19x for 0.2).
    for (double r : {0.05, 0.1, 0.2}) {
        AbsorberParameters p = paper();
        p.mass_ratio = r;
        p.excitation = 1.0;
        p.tuning_ratio = an::den_hartog_tuning(r);
        const double xi = an::den_hartog_damping_ratio(r);
        const double fixed_point = std::sqrt(1.0 + 2.0 / r);
        const double peak = peak_of_damped_absorber(p, 2.0 * r * p.tuning_ratio * xi);
        CHECK(peak / fixed_point - 1.0 < 5e-3);
        CHECK(peak / fixed_point - 1.0 > -1e-4);  // no damping goes below the fixed points
        double best_xi = 0.0, best_peak = 1e300;
        for (double trial = 0.9 * xi; trial <= 1.1 * xi; trial += 0.005 * xi) {
            const double q = peak_of_damped_absorber(p, 2.0 * r * p.tuning_ratio * trial);
            if (q < best_peak) best_peak = q, best_xi = trial;
        }
        CHECK(std::abs(best_xi / xi - 1.0) < 0.02);
        const double other = peak_of_damped_absorber(p, 2.0 * r * xi * p.tuning_ratio / (1.0 + r));
        CHECK(other / fixed_point - 1.0 > 3.0 * (peak / fixed_point - 1.0));
    }
}

TEST_CASE("Den Hartog friction gives the optimal equivalent damping", "[analytic]") {
    for (AbsorberParameters p : {paper(), detuned()}) {
        const double wa = an::den_hartog_tuning(p.mass_ratio);
        const double optimal_damping = 2.0 * p.mass_ratio * wa * an::den_hartog_damping_ratio(p.mass_ratio);
        const double given_tuning = p.tuning_ratio;
        for (double omega : frequencies) {
            p.tuning_ratio = given_tuning;
            const double mu = an::den_hartog_friction(p, omega);  // independent of the given wa
            p.tuning_ratio = wa;
            CHECK(an::den_hartog_friction(p, omega) == Approx(mu).epsilon(1e-15));
            p.friction_coefficient = mu;
            const auto slip = an::coulomb_slip(p, omega);
            REQUIRE(slip.has_value());
            CHECK(an::equivalent_damping(p, omega, *slip) == Approx(optimal_damping).epsilon(1e-11));
        }
    }
}

TEST_CASE("The minimum-displacement coefficient is the law's limit coefficient", "[analytic]") {
    const AbsorberParameters p = detuned();
    for (double omega : frequencies) {
        CHECK(an::limit_friction(p, omega, FrictionLaw::coulomb) == an::coulomb_limit_friction(p, omega));
        CHECK(an::limit_friction(p, omega, FrictionLaw::lugre) ==
              an::contact_limit_friction(p, omega, FrictionLaw::lugre));
        CHECK(an::stick(p, omega, FrictionLaw::dahl).y1 == an::contact_stick(p, omega, FrictionLaw::dahl).y1);
    }
    CHECK_THROWS_AS(an::contact_stick(p, 1.0, FrictionLaw::coulomb), InvalidInput);
}

TEST_CASE("uniform_grid includes both ends and rejects bad ranges", "[analytic]") {
    const auto grid = an::uniform_grid(0.5, 1.6, 221);
    REQUIRE(grid.size() == 221);
    CHECK(grid.front() == 0.5);
    CHECK(grid.back() == 1.6);
    CHECK(grid[110] == Approx(1.05).epsilon(1e-14));
    CHECK_THROWS_WITH(an::uniform_grid(0.0, 1.0, 10), Catch::Contains("wmin"));
    CHECK_THROWS_WITH(an::uniform_grid(1.0, 1.0, 10), Catch::Contains("wmax"));
    CHECK_THROWS_WITH(an::uniform_grid(0.5, 1.0, 1), Catch::Contains("points"));
    CHECK_THROWS_WITH(an::uniform_grid(0.5, 1.0, an::max_grid_points + 1LL), Catch::Contains("points"));
}

TEST_CASE("table leaves the slip columns empty where no slipping solution exists", "[analytic]") {
    const AbsorberParameters p = paper();
    const auto rows = an::table(p, FrictionLaw::coulomb, an::uniform_grid(0.5, 1.6, 111));
    int with_slip = 0;
    for (const an::Row& row : rows) {
        const bool exists = p.friction_coefficient < pi / 4.0 * an::coulomb_limit_friction(p, row.omega);
        CHECK(row.y1_slip.has_value() == exists);
        CHECK(row.y2_slip.has_value() == exists);
        with_slip += exists;
        REQUIRE(row.y1_stick.has_value());
        CHECK(*row.y1_stick == Approx(std::abs(an::coulomb_stick(p, row.omega).y1)));
    }
    CHECK(with_slip > 0);
    CHECK(with_slip < static_cast<int>(rows.size()));
}

TEST_CASE("stuck_resonances are the eigenfrequencies of the stuck system", "[analytic]") {
    for (const AbsorberParameters& p : {paper(), detuned()}) {
        const auto coulomb = an::stuck_resonances(p, FrictionLaw::coulomb);
        REQUIRE(coulomb.size() == 1);
        CHECK(coulomb[0] == Approx(1.0 / std::sqrt(1.0 + p.mass_ratio)).epsilon(1e-15));
        // Two masses, absorber spring r wa^2 in parallel with the contact spring r wb^2:
        // generalized eigenproblem K v = w^2 M v, solved by Eigen.
        const double r = p.mass_ratio, k2 = r * (p.tuning_ratio * p.tuning_ratio +
                                                 p.contact_stiffness_ratio * p.contact_stiffness_ratio);
        Eigen::Matrix2d M, K;
        M << 1.0, 0.0, 0.0, r;
        K << 1.0 + k2, -k2, -k2, k2;
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> solver(K, M);
        for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre}) {
            const auto w = an::stuck_resonances(p, law);
            REQUIRE(w.size() == 2);
            CHECK(w[0] == Approx(std::sqrt(solver.eigenvalues()(0))).epsilon(1e-13));
            CHECK(w[1] == Approx(std::sqrt(solver.eigenvalues()(1))).epsilon(1e-13));
        }
    }
}

TEST_CASE("limit_friction_maximum: infinite at an undamped stuck resonance in the band", "[analytic]") {
    const AbsorberParameters p = paper();
    const auto coulomb = an::limit_friction_maximum(p, FrictionLaw::coulomb, 0.5, 1.6);
    CHECK_FALSE(coulomb.bounded);
    CHECK(std::isinf(coulomb.value));
    CHECK(coulomb.omega == Approx(1.0 / std::sqrt(1.1)).epsilon(1e-15));
    const auto dahl = an::limit_friction_maximum(p, FrictionLaw::dahl, 0.5, 1.6);
    CHECK_FALSE(dahl.bounded);
    CHECK(dahl.omega == an::stuck_resonances(p, FrictionLaw::dahl)[0]);
    AbsorberParameters undamped = p;
    undamped.contact_damping_ratio = 0.0;  // LuGre without contact damping is Dahl
    CHECK_FALSE(an::limit_friction_maximum(undamped, FrictionLaw::lugre, 0.5, 1.6).bounded);
}

TEST_CASE("limit_friction_maximum: Coulomb above the stuck resonance peaks at the band's start", "[analytic]") {
    // mu_limit = fe r w^2 / ((1 + r) w^2 - 1) decreases for w > 1/sqrt(1 + r); at w = 1 it is
    // fe r / r = fe.
    AbsorberParameters p = detuned();
    const auto m = an::limit_friction_maximum(p, FrictionLaw::coulomb, 1.0, 1.6, 7);
    CHECK(m.bounded);
    CHECK(m.omega == 1.0);
    CHECK(m.value == Approx(p.excitation).epsilon(1e-14));
}

TEST_CASE("limit_friction_maximum of LuGre: the sharp finite peak, against dense sampling", "[analytic]") {
    // As wb grows the stuck resonance becomes nearly undamped and LuGre's peak narrows far below
    // any practical grid: a brute-force maximum over 200001 frequencies around the resonance must
    // never exceed ours, must approach it as the sampling tightens, and even 2 samples (the band's
    // ends, plus the resonance the function adds) must find the same peak.
    for (double wb : {0.4, 2.0, 8.0, 30.0}) {
        for (double xi : {0.01, 0.2}) {
            AbsorberParameters p = paper();
            p.contact_stiffness_ratio = wb;
            p.contact_damping_ratio = xi;
            INFO("wb = " << wb << ", xi = " << xi);
            const auto m = an::limit_friction_maximum(p, FrictionLaw::lugre, 0.5, 1.6);
            REQUIRE(m.bounded);
            CHECK(an::limit_friction(p, m.omega, FrictionLaw::lugre) == m.value);
            const auto coarse = an::limit_friction_maximum(p, FrictionLaw::lugre, 0.5, 1.6, 2);
            CHECK(coarse.value == Approx(m.value).epsilon(1e-12));
            double brute = 0.0;
            for (double half_width : {1e-1, 1e-3, 1e-5}) {
                brute = 0.0;
                const auto grid = an::uniform_grid(std::max(0.5, m.omega - half_width),
                                                   std::min(1.6, m.omega + half_width), 200001);
                for (double w : grid) brute = std::max(brute, an::limit_friction(p, w, FrictionLaw::lugre));
                CHECK(brute <= m.value * (1.0 + 1e-13));
            }
            CHECK(brute == Approx(m.value).epsilon(1e-9));
        }
    }
}
