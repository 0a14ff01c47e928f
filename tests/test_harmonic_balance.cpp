// Fourier transforms, and the harmonic-balance Jacobians against central finite differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "hbf/error.hpp"
#include "support.hpp"
#include "hbf/absorber.hpp"
#include "hbf/harmonic_balance.hpp"

using namespace hbf;
using hbf::test::relative_error;

TEST_CASE("Fourier: FFTW transforms agree with the definition and invert each other", "[fourier]") {
    const int H = 7, nt = 64;
    Fourier f(H, nt);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd c(f.size());
    for (int k = 0; k < f.size(); ++k) c(k) = u(rng);
    Eigen::VectorXd x(nt), back(f.size());
    f.to_time(c, x);
    for (int j = 0; j < nt; ++j) {
        const double theta = 2.0 * M_PI * j / nt;
        double expected = c(0);
        for (int k = 1; k <= H; ++k) expected += c(2 * k - 1) * std::cos(k * theta) + c(2 * k) * std::sin(k * theta);
        CHECK(x(j) == Approx(expected).margin(1e-13));
    }
    CHECK((f.synthesis() * c - x).norm() < 1e-12);
    f.to_coefficients(x, back);
    CHECK((back - c).norm() < 1e-13);
    CHECK((f.analysis() * x - c).norm() < 1e-13);
    // Derivative: d/dtheta of the series, checked on the samples by the exact derivative.
    Eigen::VectorXd dx(nt);
    f.to_time(f.derivative() * c, dx);
    for (int j = 0; j < nt; ++j) {
        const double theta = 2.0 * M_PI * j / nt;
        double expected = 0.0;
        for (int k = 1; k <= H; ++k) expected += k * (-c(2 * k - 1) * std::sin(k * theta) + c(2 * k) * std::cos(k * theta));
        CHECK(dx(j) == Approx(expected).margin(1e-12));
    }
    CHECK_THROWS_AS(Fourier(5, 10), InvalidInput);  // N_t must exceed 2H
    CHECK(Fourier::default_time_samples(10) == 256);
}

TEST_CASE("Fourier: the FFT-built multiplication matrix equals P diag(d) E", "[fourier]") {
    // Including N_t < 4H + 1, where harmonics 2H of d lie beyond N_t / 2 and alias.
    for (const auto& [H, nt] : {std::pair{7, 64}, std::pair{7, 16}, std::pair{6, 17}, std::pair{1, 3}}) {
        Fourier f(H, nt);
        std::mt19937 rng(static_cast<unsigned>(nt));
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        Eigen::VectorXd d(nt);
        for (int j = 0; j < nt; ++j) d(j) = u(rng);
        Eigen::MatrixXd fast(f.size(), f.size());
        f.multiplication_matrix(d, fast);
        const Eigen::MatrixXd direct = f.analysis() * d.asDiagonal() * f.synthesis();
        INFO("H = " << H << ", N_t = " << nt);
        CHECK((fast - direct).cwiseAbs().maxCoeff() < 1e-14 * nt);
        CHECK((f.times_derivative(direct) - direct * f.derivative()).cwiseAbs().maxCoeff() < 1e-14);
    }
}

namespace {
System absorber(FrictionLaw law) {
    AbsorberParameters p;
    p.regularization = 0.05;
    if (law == FrictionLaw::jenkins) p.contact_stiffness_ratio = 3.0;  // k_t = 0.9: the slider moves
    if (law == FrictionLaw::lugre) {  // exercise every LuGre term: Stribeck curve and viscous
        p.contact_damping_ratio = 0.2;
        p.static_friction_coefficient = 0.3;
        p.stribeck_velocity = 0.1;
        p.viscous_coefficient = 0.02;
    }
    return friction_absorber(p, law);
}

}  // namespace

TEST_CASE("Harmonic-balance Jacobians equal central finite differences", "[harmonic_balance]") {
    // Exact Coulomb's residual is piecewise linear in the unknowns (a sample switches between
    // stick and slip at |lambda + eps v| = F_c): its Jacobian is exact on each pattern, which
    // central differences see unless a sample sits within h of a switch.
    for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre, FrictionLaw::coulomb_regularized, FrictionLaw::coulomb,
                            FrictionLaw::jenkins}) {
        for (int state = 0; state < 3; ++state) {
            HarmonicBalance hb(absorber(law), HarmonicBalanceOptions{4, 64});
            const double omega = 0.8 + 0.15 * state;
            std::mt19937 rng(11 + state);
            std::normal_distribution<double> normal(0.0, 1.0);
            // A state with harmonics of decreasing size, around a relative motion of amplitude
            // ~ 0.5 * (state + 1), so that stick-like, mixed and slipping samples all occur.
            Eigen::VectorXd x = hb.linear_guess(omega);
            for (int k = 0; k < x.size(); ++k) x(k) += 0.3 * (state + 1) * normal(rng) / (1 + (k % hb.coefficients()));
            Eigen::VectorXd r, dr_domega;
            Eigen::MatrixXd J, fd;
            Eigen::VectorXd fd_omega;
            hb.evaluate(x, omega, r, &J, &dr_domega);
            hbf::test::central_differences(hb, x, omega, fd, fd_omega);
            INFO("law " << to_string(law) << ", state " << state);
            // Central differences of a function whose samples are piecewise smooth (|v| has a
            // kink): the error is O(h^2) away from kinks; 1e-5 relative leaves room for that.
            CHECK(relative_error(J, fd) < 1e-5);
            CHECK(relative_error(dr_domega, fd_omega) < 1e-5);
        }
    }
}

TEST_CASE("Exact Coulomb: a negative dynamic Lagrangian parameter is rejected, zero is automatic", "[harmonic_balance]") {
    AbsorberParameters p;
    p.lagrangian_penalty = -1.0;
    CHECK_THROWS_WITH(HarmonicBalance(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{}),
                      Catch::Contains("lagrangian_penalty"));
    p.lagrangian_penalty = 0.0;
    CHECK_NOTHROW(HarmonicBalance(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{}));
}

TEST_CASE("HarmonicBalance::validate (the dry run's check) throws exactly what the constructor throws",
          "[harmonic_balance]") {
    // Each case is one bad input; the message of validate must equal the constructor's, and a
    // good input passes both (validate builds no Fourier matrices).
    auto message = [](auto&& make) -> std::string {
        try {
            make();
        } catch (const InvalidInput& e) {
            return e.what();
        }
        return "";
    };
    struct Case {
        AbsorberParameters p;
        FrictionLaw law;
        HarmonicBalanceOptions o;
    };
    std::vector<Case> cases;
    auto add = [&cases](auto edit, FrictionLaw law = FrictionLaw::coulomb) {
        Case c{AbsorberParameters{}, law, HarmonicBalanceOptions{}};
        edit(c);
        cases.push_back(c);
    };
    add([](Case& c) { c.o.harmonics = 0; });
    add([](Case& c) { c.o.time_samples = -1; });
    add([](Case& c) { c.o.time_samples = 20; });  // <= 2H
    add([](Case& c) { c.o.harmonics = 20000; });
    add([](Case& c) { c.o.modes = -2; });
    add([](Case& c) { c.p.lagrangian_penalty = 1e-6; });  // below 1/30 of the automatic value
    add([](Case& c) { c.p.lagrangian_penalty = 1e6; });   // above 4 times
    add([](Case& c) { c.o.modes = 5; }, FrictionLaw::dahl);  // 2 DOF: more modes than DOFs?
    add([](Case& c) { c.o.modes = 1; c.o.formulation = Formulation::full; });
    add([](Case& c) { c.o.odd_harmonics = true; c.o.harmonics = 5; });  // good
    add([](Case& c) { c.o.harmonics = 3; });                              // good
    int refused = 0;
    for (const Case& c : cases) {
        const System system = friction_absorber(c.p, c.law);
        const std::string constructed = message([&] { HarmonicBalance hb(system, c.o); });
        const std::string validated = message([&] { HarmonicBalance::validate(system, c.o); });
        CHECK(validated == constructed);
        if (!constructed.empty()) ++refused;
    }
    CHECK(refused >= 8);
}

TEST_CASE("Jenkins element under q = Q cos: the hysteresis loop's first harmonic (describing function)",
          "[friction][jenkins]") {
    // Derived by hand: from q = Q (theta = 0) the slider rests until k_t (q - Q) + F_c = -F_c,
    // i.e. cos beta = 1 - 2 F_c / (k_t Q), then slides with f = -F_c to theta = pi; the second
    // half is the mirror image. Its first harmonic f ~ c1 cos + s1 sin:
    //   c1 = (k_t Q / pi) (beta - sin(2 beta) / 2),   s1 = -(4 F_c / pi) (1 - F_c / (k_t Q)),
    // (s1: the dissipated energy per cycle -pi Q s1 = 4 F_c (Q - F_c / k_t)). The samples of q
    // include both turning points, so the marched samples are exact and the error is the
    // quadrature's: f has two kinks of slope jump <= k_t Q, each costing at most
    // k_t Q h^2 / 8 on the integral (h = 2 pi / N_t), so |error| <= k_t Q pi / N_t^2.
    Contact c;
    c.law = FrictionLaw::jenkins;
    c.friction_limit = 0.3;
    c.stiffness = 2.0;
    const auto model = make_friction_model(c);
    for (double amplitude : {0.2, 0.5, 3.0}) {  // 0.2: k_t Q < F_c, permanent stick
        const double kq = c.stiffness * amplitude;
        double c1 = kq, s1 = 0.0;
        if (kq > c.friction_limit) {
            const double beta = std::acos(1.0 - 2.0 * c.friction_limit / kq);
            c1 = kq / M_PI * (beta - 0.5 * std::sin(2.0 * beta));
            s1 = -4.0 / M_PI * c.friction_limit * (1.0 - c.friction_limit / kq);
        }
        for (int nt : {64, 256, 1024}) {
            Fourier fourier(1, nt);
            Eigen::VectorXd q = Eigen::VectorXd::Zero(3), z;
            q(1) = amplitude;
            FrictionEvaluation out;
            model->evaluate(fourier, 1.0, q, z, out, true);
            const double bound = kq * M_PI / (double(nt) * nt);
            INFO("Q = " << amplitude << ", N_t = " << nt);
            CHECK(std::abs(out.force(0)) <= 1e-14 * kq);
            CHECK(std::abs(out.force(1) - c1) <= bound);
            CHECK(std::abs(out.force(2) - s1) <= bound);
            // Permanent stick: the centred slider, f = k_t q exactly.
            if (kq < c.friction_limit) CHECK(std::abs(out.force(1) - kq) <= 1e-14 * kq);
        }
    }
}
