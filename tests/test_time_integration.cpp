// Verification of the time-integration reference (CVODE) against independent references:
// the linear response, Den Hartog's closed form, energy balance, limits between laws.
#include <catch2/catch.hpp>
#include <cmath>

#include "hbf/analytic.hpp"
#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/time_integration.hpp"
#include "support.hpp"

using namespace hbf;

namespace {
constexpr double pi = 3.14159265358979323846;

/// The paper's absorber with a viscous damper c on the main mass, so that the energy balance
/// has all three terms and transients decay in every regime.
System damped_absorber(FrictionLaw law, double wb, double c) {
    AbsorberParameters p;
    p.contact_stiffness_ratio = wb;
    System s = friction_absorber(p, law);
    s.damping.coeffRef(0, 0) = c;
    return s;
}
}  // namespace

TEST_CASE("A coulomb contact that never slips gives the linear response of the stuck structure", "[timeint]") {
    // 2 DOF with Rayleigh damping C = 0.2 K + 0.1 M, a coulomb contact between the DOFs with an
    // unreachable limit. Reference: the 1-DOF structure with y1 = y2 = u (T = [1, 1]) solved
    // by linear_response on T^T M T, T^T C T, T^T K T, T^T F (independent of the integrator and
    // of linear_stuck_state). From rest, without the shortcuts (restart, shooting): the
    // transient decays by exp(-zeta omega_n T) ~ 0.4 per period, so the Poincare tolerance
    // 1e-10 leaves ~1e-10 of transient; integration tolerance 1e-10 per step. Tolerance 1e-7
    // relative on the complex first harmonic.
    System s;
    Eigen::Matrix2d k;
    k << 2.0, -1.0, -1.0, 1.0;
    s.mass = sparse(Eigen::Vector2d(1.0, 0.5).asDiagonal());
    s.stiffness = sparse(k);
    s.damping = 0.2 * s.stiffness + 0.1 * s.mass;
    s.excitation = Eigen::Vector2d(1.0, 0.3);
    Contact c;
    c.dof = 0;
    c.other_dof = 1;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = 1e6;
    s.contacts.push_back(c);
    const Eigen::Vector2d t(1.0, 1.0);
    TimeIntegrationOptions o;
    o.stick_restart = false;
    o.shooting = false;
    o.steady_tolerance = 1e-10;
    for (double omega : {0.5, 1.0, 2.0}) {
        const PeriodicResponse r = integrate_steady_state(s, omega, o);
        const std::complex<double> u =
            linear_response(Eigen::MatrixXd::Constant(1, 1, t.dot(s.mass * t)),
                            Eigen::MatrixXd::Constant(1, 1, t.dot(s.damping * t)),
                            Eigen::MatrixXd::Constant(1, 1, t.dot(s.stiffness * t)),
                            Eigen::VectorXd::Constant(1, t.dot(s.excitation)), omega)(0);
        INFO("omega = " << omega << ": " << r.summary());
        REQUIRE(r.converged);
        CHECK(r.regime == "stick");
        CHECK(r.stick_fraction == 1.0);
        CHECK(r.switches == 0);
        for (int i = 0; i < 2; ++i) {
            CHECK(test::relative_difference(r.harmonic1(i), u) < 1e-7);
            CHECK(test::relative_difference(r.y_max[static_cast<std::size_t>(i)], std::abs(u)) < 1e-7);
        }
        // a pure harmonic: the friction (constraint) force does no work, input = viscous
        CHECK(std::abs(r.energy) < 1e-8 * r.input_energy);
        CHECK(std::abs(r.viscous_energy - r.input_energy) < 1e-7 * r.input_energy);
    }
}

TEST_CASE("Den Hartog's closed form: the literature's form and the ODE", "[timeint][analytic]") {
    // Den Hartog (1930): x0/x_st = sqrt(V^2 - (rho U)^2), V = 1/(1 - eta^2),
    // U = sin(pi/eta) / (eta (1 + cos(pi/eta))). The same number as our derivation.
    for (double eta : {0.7, 0.8, 1.2, 1.5, 2.0, 3.0})
        for (double rho : {0.1, 0.3}) {
            const auto d = analytic::den_hartog(eta, rho);
            const double v = 1.0 / (1.0 - eta * eta);
            const double u = std::sin(pi / eta) / (eta * (1.0 + std::cos(pi / eta)));
            CHECK(d.amplitude == Approx(std::sqrt(v * v - rho * rho * u * u)).epsilon(1e-12));
            // the closed form solves u'' + u + rho sign(u') = cos(eta tau) (central differences,
            // error O(h^2) = 1e-8 relative to the terms of size 1)
            const double h = 1e-4;
            for (double tau : {0.3, 1.1, 2.9, 4.0}) {
                const double acc = (d.displacement(tau + h) - 2 * d.displacement(tau) + d.displacement(tau - h)) / (h * h);
                const double vel = d.velocity(tau);
                if (std::abs(vel) < 1e-3) continue;
                CHECK(acc + d.displacement(tau) + rho * (vel > 0 ? 1 : -1) == Approx(std::cos(eta * tau)).margin(1e-6));
            }
            // maximum A at eta tau = psi with zero velocity
            CHECK(d.displacement(d.phase / eta) == Approx(d.amplitude).epsilon(1e-12));
            CHECK(std::abs(d.velocity(d.phase / eta)) < 1e-10);
        }
    // outside the non-sticking range
    CHECK_FALSE(analytic::den_hartog_check(0.3, 0.3).valid);  // no continuous solution
    CHECK_FALSE(analytic::den_hartog_check(0.5, 0.5).valid);  // sticks at the turning points
    CHECK_THROWS_AS(analytic::den_hartog(0.5, 0.5), InvalidInput);
    CHECK_THROWS_AS(analytic::den_hartog(-1.0, 0.1), InvalidInput);
}

TEST_CASE("The integrator reproduces Den Hartog's non-sticking steady state", "[timeint]") {
    // From rest; friction is the only damping. Integration tolerance 1e-10 and Poincare
    // tolerance 1e-8 (measured agreement ~1e-10..1e-8): amplitude and the whole signal
    // (phase included) to 1e-6, and not a single instant of stick (exact event logic).
    TimeIntegrationOptions o;
    for (const auto& [eta, rho] : std::vector<std::pair<double, double>>{{0.8, 0.3}, {1.5, 0.5}, {2.0, 0.1}, {0.7, 0.7}}) {
        const auto d = analytic::den_hartog(eta, rho);
        const PeriodicResponse r = integrate_steady_state(test::den_hartog_oscillator(rho), eta, o);
        INFO("eta = " << eta << ", rho = " << rho << ": " << r.summary());
        REQUIRE(r.converged);
        CHECK(r.y_max[0] == Approx(d.amplitude).epsilon(1e-6));
        double signal_error = 0;
        for (Eigen::Index j = 0; j < r.time.size(); ++j)
            signal_error = std::max(signal_error, std::abs(r.displacement(j, 0) - d.displacement(r.time(j))));
        CHECK(signal_error < 1e-6 * d.amplitude);
        CHECK(r.stick_fraction == 0.0);
        CHECK(r.regime == "slip");
        CHECK(r.switches == 2);            // two reversals per cycle
        CHECK(r.stick_margin_max > 0.0);   // at each stop the force exceeds the friction limit
        CHECK(std::abs(r.energy - r.input_energy) < 1e-6 * r.input_energy);
    }
}

TEST_CASE("Energy balance in stick-slip: friction + viscous energy = input work", "[timeint]") {
    // Over a periodic steady state the mechanical energy returns to its value, so the input
    // work equals the dissipated energies. All three are quadratures integrated with the
    // motion; the imbalance is the non-periodicity left by the Poincare tolerance (1e-8 of
    // the state, times amplitude/force ~ 10) plus the integration error: 1e-6 relative.
    struct Case {
        FrictionLaw law;
        double wb, omega;
    };
    TimeIntegrationOptions o;
    for (const Case& k : {Case{FrictionLaw::dahl, 2.0, 1.0}, Case{FrictionLaw::lugre, 2.0, 1.0},
                          Case{FrictionLaw::coulomb, 0.4, 0.88}, Case{FrictionLaw::jenkins, 0.4, 0.9}}) {
        const PeriodicResponse r = integrate_steady_state(damped_absorber(k.law, k.wb, 0.05), k.omega, o);
        INFO(to_string(k.law) << ": " << r.summary());
        REQUIRE(r.converged);
        CHECK(r.regime == "stick-slip");
        CHECK(r.stick_fraction > 0.05);
        CHECK(r.stick_fraction < 0.95);
        CHECK(r.energy > 0.02 * r.input_energy);  // both dissipations take part
        CHECK(r.viscous_energy > 0.02 * r.input_energy);
        CHECK(std::abs(r.energy + r.viscous_energy - r.input_energy) < 1e-6 * r.input_energy);
    }
}

TEST_CASE("Regularised Coulomb tends to exact Coulomb as eps -> 0", "[timeint]") {
    // Damped absorber at w = 1 (exact Coulomb slips there). The tanh law differs from the
    // sign law only for |v| <~ eps, so the response converges like eps: measured y1_max
    // differences 3.9e-4, 1.6e-5, 6.6e-7 for eps = 0.05, 0.01, 0.002. Asserted: each
    // difference shrinks by > 4x and the last is < 1e-5 relative.
    TimeIntegrationOptions o;
    const PeriodicResponse exact = integrate_steady_state(damped_absorber(FrictionLaw::coulomb, 0.4, 0.05), 1.0, o);
    REQUIRE(exact.converged);
    double previous = 1.0;
    for (double eps : {0.05, 0.01, 0.002}) {
        System s = damped_absorber(FrictionLaw::coulomb_regularized, 0.4, 0.05);
        s.contacts[0].regularization = eps;
        const PeriodicResponse r = integrate_steady_state(s, 1.0, o);
        INFO("eps = " << eps << ": " << r.summary());
        REQUIRE(r.converged);
        const double difference = test::relative_difference(r.y_max[0], exact.y_max[0]);
        CHECK(difference < previous / 4.0);
        previous = difference;
    }
    CHECK(previous < 1e-5);
}

TEST_CASE("Jenkins with a stiff spring tends to exact Coulomb", "[timeint]") {
    // k_t = r wb^2: wb = 3, 10, 30. The elastic stick phases shrink like F_c / k_t: measured
    // y1_max differences 7e-3, 5e-4, 5e-5 relative. Asserted: shrinking by > 4x each time and
    // the stiffest < 2e-4.
    TimeIntegrationOptions o;
    const PeriodicResponse exact = integrate_steady_state(damped_absorber(FrictionLaw::coulomb, 0.4, 0.05), 1.0, o);
    REQUIRE(exact.converged);
    double previous = 1.0;
    for (double wb : {3.0, 10.0, 30.0}) {
        const PeriodicResponse r = integrate_steady_state(damped_absorber(FrictionLaw::jenkins, wb, 0.05), 1.0, o);
        INFO("wb = " << wb << ": " << r.summary());
        REQUIRE(r.converged);
        const double difference = test::relative_difference(r.y_max[0], exact.y_max[0]);
        CHECK(difference < previous / 4.0);
        previous = difference;
    }
    CHECK(previous < 2e-4);
}

TEST_CASE("Dahl at small amplitude sticks and is the linear pre-sliding spring", "[timeint]") {
    // y'' + 0.1 y' + y + sigma0 z = F cos(omega t), sigma0 = 1, F_c = 1, F = 1e-4, away from
    // the stuck resonance sqrt(2): the bristle deflection z ~ y_max ~ 1e-4 F_c / sigma0, so
    // Dahl's correction sigma0 |v| z / F_c to z' = v is of relative size eta = sigma0 y_max / F_c
    // and the response is the linear one with stiffness 1 + sigma0 (z = q) up to O(eta).
    // Tolerance 2 eta (measured 0.34 eta and 0.11 eta). The stick indicator stays far below the limit.
    const System s = test::dahl_oscillator(1.0, 1.0, 1e-4, 0.1);
    TimeIntegrationOptions o;
    for (double omega : {0.8, 2.5}) {
        const PeriodicResponse r = integrate_steady_state(s, omega, o);
        const double eta = 1.0 * r.y_max[0] / 1.0;
        INFO(r.summary());
        REQUIRE(r.converged);
        const std::complex<double> y =
            linear_response(Eigen::MatrixXd(s.mass), Eigen::MatrixXd(s.damping),
                            Eigen::MatrixXd(s.stiffness) + Eigen::MatrixXd::Identity(1, 1), s.excitation, omega)(0);
        CHECK(r.stick_fraction == 1.0);
        CHECK(r.regime == "stick");
        CHECK(r.stick_margin_max < -0.99);
        CHECK(test::relative_difference(r.harmonic1(0), y) < 2.0 * eta);
        CHECK(eta < 2e-4);
    }
}

TEST_CASE("Poincare non-convergence is a status with a message, not an exception", "[timeint]") {
    TimeIntegrationOptions o;
    o.min_periods = 1;
    o.max_periods = 2;
    o.shooting = false;
    const System s = damped_absorber(FrictionLaw::dahl, 2.0, 0.05);
    const PeriodicResponse r = integrate_steady_state(s, 1.0, o);
    CHECK_FALSE(r.converged);
    CHECK(r.periods == 2);
    CHECK(r.message.find("not converged after 2 periods") != std::string::npos);
    CHECK(r.poincare_change > o.steady_tolerance);
    REQUIRE(r.y_max.size() == 2);
    CHECK(std::isfinite(r.y_max[0]));
    CHECK(r.state.size() == state_size(s));

    CHECK_THROWS_AS(integrate_steady_state(s, 0.0, o), InvalidInput);
    const Eigen::VectorXd wrong = Eigen::VectorXd::Zero(3);
    CHECK_THROWS_AS(integrate_steady_state(s, 1.0, o, &wrong), InvalidInput);
    o.max_periods = 0;
    CHECK_THROWS_AS(integrate_steady_state(s, 1.0, o), InvalidInput);
}

TEST_CASE("Sweeps up and down on the paper's absorber agree and match the stick closed form", "[timeint]") {
    // Exact Coulomb, paper defaults (r = 0.1, wa = 1, mu = 0.2, fe = 0.5, C = 0): the
    // solution is unique at these frequencies (full stick at 0.8, 1.2, 1.3; slip at 0.9, 1.0,
    // checked with both sweep directions and the stuck start). Points agree to 1e-6 (Poincare
    // tolerance 1e-8 with contraction factors up to ~0.99 in slip); full-stick points equal
    // Y = fe / (1 - (1 + r) w^2) (analytic::coulomb_stick) to 1e-8.
    const AbsorberParameters p;
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    const std::vector<double> up = {0.8, 0.9, 1.0, 1.1, 1.2, 1.3};
    const std::vector<double> down(up.rbegin(), up.rend());
    TimeIntegrationOptions o;
    const Eigen::VectorXd start_up = linear_stuck_state(s, up.front());
    const Eigen::VectorXd start_down = linear_stuck_state(s, down.front());
    const auto a = sweep(s, up, o, &start_up);
    const auto b = sweep(s, down, o, &start_down);
    REQUIRE(a.size() == up.size());
    for (std::size_t k = 0; k < up.size(); ++k) {
        const PeriodicResponse& x = a[k];
        const PeriodicResponse& y = b[up.size() - 1 - k];
        INFO(x.summary() << " | " << y.summary());
        REQUIRE(x.converged);
        REQUIRE(y.converged);
        CHECK(x.periods >= o.min_periods);
        CHECK(y.periods >= o.min_periods);
        CHECK(x.regime == y.regime);
        for (int i = 0; i < 2; ++i)
            CHECK(test::relative_difference(x.y_max[static_cast<std::size_t>(i)], y.y_max[static_cast<std::size_t>(i)]) < 1e-6);
        if (x.regime == "stick") {
            CHECK(test::relative_difference(x.y_max[0], std::abs(analytic::coulomb_stick(p, up[k]).y1)) < 1e-8);
            CHECK(x.stick_margin_max < 0.0);
        }
    }
    CHECK(a[0].regime == "stick");
    CHECK(a[2].regime == "slip");
}

namespace {
/// A damped chain of n unit masses and unit springs (fixed at the left end), Rayleigh damping
/// C = 0.02 K + 0.02 M, force F cos(w t) on the middle mass, and the given contact on the last.
System damped_chain(int n, const Contact& contact) {
    System s;
    std::vector<Eigen::Triplet<double>> k, m;
    for (int i = 0; i < n; ++i) {
        m.emplace_back(i, i, 1.0);
        k.emplace_back(i, i, i + 1 < n ? 2.0 : 1.0);
        if (i + 1 < n) {
            k.emplace_back(i, i + 1, -1.0);
            k.emplace_back(i + 1, i, -1.0);
        }
    }
    s.mass = SparseMatrix(n, n);
    s.mass.setFromTriplets(m.begin(), m.end());
    s.stiffness = SparseMatrix(n, n);
    s.stiffness.setFromTriplets(k.begin(), k.end());
    s.damping = 0.02 * s.stiffness + 0.02 * s.mass;
    s.excitation = Eigen::VectorXd::Zero(n);
    s.excitation(n / 2) = 1.0;
    Contact c = contact;
    c.dof = n - 1;
    c.other_dof = Contact::ground;
    s.contacts.push_back(c);
    return s;
}
}  // namespace

TEST_CASE("Large models: BDF with the sparse second-order Newton solve and GMRES shooting equal the stuck linear response",
          "[timeint][sparse]") {
    // 24 DOFs (beyond dense_newton_max_dofs = 16, 48 continuous states: GMRES shooting forced
    // by shooting_dense_max_states = 0). The coulomb contact on the last mass never slips
    // (limit 1e6): reference = the linear response of the structure with that mass held,
    // solved densely by linear_response on the 23 free DOFs (independent of the integrator).
    // Tolerances 1e-11 per step and 1e-11 on the Poincare map: 1e-7 relative on the first
    // harmonic (the transients decay by >= exp(-0.01 * 2 pi) per period of the slowest mode).
    Contact c;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = 1e6;
    const System s = damped_chain(24, c);
    const double omega = 0.7;
    TimeIntegrationOptions o;
    o.method = IntegrationMethod::bdf;
    o.relative_tolerance = 1e-11;
    o.absolute_tolerance = 1e-13;
    o.steady_tolerance = 1e-11;
    o.stick_restart = false;
    o.shooting_dense_max_states = 0;
    o.max_periods = 4000;
    const PeriodicResponse r = integrate_steady_state(s, omega, o);
    INFO(r.summary());
    REQUIRE(r.converged);
    CHECK(r.regime == "stick");
    // fewer periods than one per state: the Newton steps are matrix-free
    CHECK(r.periods < 2 * 48);

    const int free = 23;
    const Eigen::MatrixXd m = Eigen::MatrixXd(s.mass).topLeftCorner(free, free);
    const Eigen::MatrixXd k = Eigen::MatrixXd(s.stiffness).topLeftCorner(free, free);
    const Eigen::MatrixXd d = Eigen::MatrixXd(s.damping).topLeftCorner(free, free);
    const Eigen::VectorXcd reference = linear_response(m, d, k, s.excitation.head(free), omega);
    const double scale = reference.cwiseAbs().maxCoeff();
    for (int i = 0; i < free; ++i) CHECK(std::abs(r.harmonic1(i) - reference(i)) <= 1e-7 * scale);
    CHECK(std::abs(r.harmonic1(free)) <= 1e-9 * scale);
}

TEST_CASE("Large models: the sparse BDF Newton solve and GMRES shooting agree with Adams (no Newton) in stick-slip",
          "[timeint][sparse]") {
    // Same chain, the last mass on a coulomb contact that sticks and slips (stick fraction
    // strictly between 0 and 1 is checked). Adams with fixed-point iteration uses neither the
    // Newton solver nor (with shooting off) any Jacobian: an independent route to the same
    // periodic orbit. Tolerance 1e-6 relative on every y_max (integration tolerances 1e-10).
    for (FrictionLaw law : {FrictionLaw::coulomb}) {
        Contact c;
        c.law = law;
        c.friction_limit = 0.4;
        c.stiffness = 5.0;  // dahl sigma0
        const System s = damped_chain(20, c);
        const double omega = 0.35;
        TimeIntegrationOptions o;
        o.relative_tolerance = 1e-10;
        o.absolute_tolerance = 1e-12;
        o.steady_tolerance = 1e-10;
        o.max_periods = 6000;
        TimeIntegrationOptions bdf = o;
        bdf.method = IntegrationMethod::bdf;
        bdf.shooting_dense_max_states = 0;
        TimeIntegrationOptions adams = o;
        adams.shooting = false;
        const PeriodicResponse a = integrate_steady_state(s, omega, adams);
        const PeriodicResponse b = integrate_steady_state(s, omega, bdf);
        INFO(to_string(law) << ": adams " << a.summary() << "; bdf " << b.summary());
        REQUIRE(a.converged);
        REQUIRE(b.converged);
        if (law == FrictionLaw::coulomb) {
            CHECK(a.stick_fraction > 0.05);
            CHECK(a.stick_fraction < 0.95);
        }
        for (std::size_t i = 0; i < a.y_max.size(); ++i) CHECK(b.y_max[i] == Approx(a.y_max[i]).epsilon(1e-6));
        CHECK(b.stick_fraction == Approx(a.stick_fraction).margin(1e-6));
    }
}

namespace {
/// DOF 1 (mass 1, damper 0.05, spring 1 to the ground) tied by a spring 2 to DOF 2, massless,
/// held by a spring 3 to the ground; the force (1, f2).
System massless_chain(double f2) {
    System s;
    Eigen::Matrix2d k;
    k << 3.0, -2.0, -2.0, 5.0;
    s.mass = sparse(Eigen::Vector2d(1.0, 0.0).asDiagonal());
    s.stiffness = sparse(k);
    s.damping = sparse(Eigen::Vector2d(0.05, 0.0).asDiagonal());
    s.excitation = Eigen::Vector2d(1.0, f2);
    return s;
}
}  // namespace

TEST_CASE("Massless DOFs: a spring chain condensed statically gives the closed-form linear response", "[timeint][massless]") {
    // DOF 1 (mass 1, damper 0.05, spring 1 to the ground) is tied by a spring k_b = 2 to DOF 2,
    // massless, held by k_c = 3 to the ground; the force (1, F2) acts on both. Closed form:
    // the massless DOF is static, 5 y2 = 2 y1 + F2 cos, so y1 sees k = 1 + 2 - 4/5 and the force
    // 1 + 2 F2 / 5; y2 = (2 Y1 + F2) / 5. A linear structure: the steady state is reached from the
    // linear stuck start (there is no contact) and must equal it to the integrator's accuracy.
    for (double f2 : {0.0, 0.7}) {
        const System s = massless_chain(f2);
        TimeIntegrationOptions o;
        o.outputs = {Output("spread", {{0, 1.0}, {1, -1.0}})};
        for (double omega : {0.8, 1.5}) {
            const std::complex<double> y1 =
                (1.0 + 2.0 * f2 / 5.0) / std::complex<double>(3.0 - 4.0 / 5.0 - omega * omega, 0.05 * omega);
            const std::complex<double> y2 = (2.0 * y1 + f2) / 5.0;
            const PeriodicResponse r = integrate_steady_state(s, omega, o);
            INFO("F2 = " << f2 << ", omega = " << omega << ": " << r.summary());
            REQUIRE(r.converged);
            CHECK(r.y_max[0] == Approx(std::abs(y1)).epsilon(1e-7));
            CHECK(r.y_amp1[0] == Approx(std::abs(y1)).epsilon(1e-7));
            CHECK(r.y_amp1[1] == Approx(std::abs(y2)).epsilon(1e-7));
            CHECK(r.y_max[1] == Approx(std::abs(y2)).epsilon(1e-3));  // sampled: 256 per period
            CHECK(r.output_amp1[0] == Approx(std::abs(y1 - y2)).epsilon(1e-7));
            CHECK(r.output_max[0] == Approx(std::abs(y1 - y2)).epsilon(1e-3));
            REQUIRE(r.state.size() == state_size(s));
            CHECK(r.state(1) == Approx(std::real(y2)).epsilon(1e-6));  // y2(0) = Re(Y2)
        }
    }
}

TEST_CASE("Massless DOFs: a Coulomb shoe behind a spring equals the exact Jenkins orbit", "[timeint][massless][exact]") {
    // DOF 1 (mass 1, damper 0.05, spring 1) holds a massless shoe (DOF 2) by a spring k_c = 4;
    // the shoe slides on the ground with exact Coulomb friction F_c = 0.3 (support.hpp). The shoe's balance
    // k_c (y2 - y1) + f = 0 makes the pair a Jenkins element (k_t = k_c, F_c) on DOF 1 with the
    // slider at y2. Reference: the event-exact solver on that 1-DOF Jenkins system (independent
    // code), its y1 and force samples giving y2 = y1 - f / k_c.
    const double kc = 4.0, limit = 0.3;
    const System shoe = test::massless_contact(kc, limit), jenkins = test::jenkins_equivalent(kc, limit);
    TimeIntegrationOptions o;
    o.relative_tolerance = 1e-12;
    o.absolute_tolerance = 1e-14;
    o.steady_tolerance = 1e-11;
    ExactOptions eo;
    eo.samples = o.samples_per_period;
    for (double omega : {0.6, 1.0, 1.3, 2.5}) {
        const PeriodicResponse r = integrate_steady_state(shoe, omega, o, nullptr);
        const ExactOrbit e = exact_periodic_orbit(jenkins, omega, linear_stuck_state(jenkins, omega), eo);
        INFO("omega = " << omega << ": TI " << r.summary() << "; exact " << e.summary());
        REQUIRE(r.converged);
        REQUIRE(e.converged);
        CHECK(r.regime == e.regime);
        CHECK(r.y_max[0] == Approx(e.y_max[0]).epsilon(1e-8));
        CHECK(r.y_amp1[0] == Approx(e.y_amp1[0]).epsilon(1e-8));
        CHECK(r.stick_fraction == Approx(e.stick_fraction).margin(1e-7));
        CHECK(r.energy == Approx(e.energy).epsilon(1e-7));
        // The shoe: sampled at the same instants on both sides.
        double shoe_max = 0.0;
        for (Eigen::Index s = 0; s < e.time.size(); ++s)
            shoe_max = std::max(shoe_max, std::abs(e.displacement(s, 0) - e.friction_force(s, 0) / kc));
        CHECK(r.y_max[1] == Approx(shoe_max).epsilon(1e-7).margin(1e-9));
        CHECK(r.displacement.cols() == 2);
        CHECK((r.friction_force.col(0) - e.friction_force.col(0)).cwiseAbs().maxCoeff() < 1e-7);
    }
}

TEST_CASE("Massless DOFs that time integration cannot condense are refused with the reason", "[timeint][massless]") {
    const System s = massless_chain(0.0);
    auto message = [](const System& system) {
        try {
            integrate_steady_state(system, 1.0, TimeIntegrationOptions{});
        } catch (const InvalidInput& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    System damped = s;
    damped.damping = sparse(Eigen::Vector2d(0.05, 0.01).asDiagonal());
    CHECK_THAT(message(damped), Catch::Contains("massless DOF 2 has damping"));
    System dahl = s;
    Contact c;
    c.dof = 1;
    c.law = FrictionLaw::dahl;
    c.friction_limit = 0.3;
    c.stiffness = 1.0;
    dahl.contacts = {c};
    CHECK_THAT(message(dahl), Catch::Contains("contact 1 (dahl) moves massless DOFs"));
    System loose = s;
    Eigen::Matrix2d k2;
    k2 << 1.0, 0.0, 0.0, 0.0;
    loose.stiffness = sparse(k2);
    CHECK_THAT(message(loose), Catch::Contains("K_SS) is singular"));
}

TEST_CASE("Massless DOFs: a load on the massless shoe reaches the slider as its spring's base motion",
          "[timeint][massless][exact]") {
    // The shoe of test::massless_contact loaded too, F = (1, F2). Its balance
    // kc (y2 - y1) + f = F2 cos gives f = kc (y1 + (F2 / kc) cos - y2), and the mass's row
    // y1'' + 0.05 y1' + y1 + kc (y1 - y2) = cos becomes y1'' + 0.05 y1' + y1 + f = (1 + F2) cos:
    // a Jenkins element (kc, F_c, slider y2) whose spring's far end moves by (F2 / kc) cos, on
    // DOF 1 loaded by 1 + F2 (by hand). Reference: the exact solver on that hand-built 1-DOF
    // system. Time integration and the exact solver of the 2-DOF model, each through the
    // library's static condensation, must equal it; without the base motion (the load only
    // moved to DOF 1) the response differs by more than 100 times that tolerance (1e-4 at the
    // resonance, w = 1, to 1e-2 away from it).
    const double kc = 4.0, limit = 0.3, f2 = 0.6;
    System shoe = test::massless_contact(kc, limit);
    shoe.excitation = Eigen::Vector2d(1.0, f2);
    System by_hand = test::jenkins_equivalent(kc, limit);
    by_hand.excitation(0) = 1.0 + f2;
    by_hand.contacts[0].base_motion = f2 / kc;
    System without = by_hand;
    without.contacts[0].base_motion = 0.0;
    const TimeIntegrationOptions o = test::tight_time_integration();
    ExactOptions eo;
    eo.samples = o.samples_per_period;
    for (double omega : {0.6, 1.0, 1.3, 2.5}) {
        // Each solver from the linear stuck state of its own model.
        const ExactOrbit reference = exact_periodic_orbit(by_hand, omega, linear_stuck_state(by_hand, omega), eo);
        const ExactOrbit e = exact_periodic_orbit(shoe, omega, linear_stuck_state(shoe, omega), eo);
        const PeriodicResponse r = integrate_steady_state(shoe, omega, o, nullptr);
        const ExactOrbit other = exact_periodic_orbit(without, omega, linear_stuck_state(without, omega), eo);
        INFO("omega = " << omega << ": reference " << reference.summary() << "; exact " << e.summary() << "; TI "
                        << r.summary() << "; without base motion " << other.summary());
        REQUIRE(reference.converged);
        REQUIRE(e.converged);
        REQUIRE(r.converged);  // its energy balance includes the load's work through the base motion
        CHECK(e.regime == reference.regime);
        CHECK(r.regime == reference.regime);
        CHECK(e.y_max[0] == Approx(reference.y_max[0]).epsilon(1e-10));
        CHECK(e.y_amp1[0] == Approx(reference.y_amp1[0]).epsilon(1e-10));
        CHECK(e.stick_fraction == Approx(reference.stick_fraction).margin(1e-10));
        CHECK(e.energy == Approx(reference.energy).epsilon(1e-10).margin(1e-14));
        CHECK(r.y_max[0] == Approx(reference.y_max[0]).epsilon(1e-8));
        CHECK(r.y_amp1[0] == Approx(reference.y_amp1[0]).epsilon(1e-8));
        CHECK(r.stick_fraction == Approx(reference.stick_fraction).margin(1e-7));
        CHECK(r.energy == Approx(reference.energy).epsilon(1e-7).margin(1e-12));
        // The force's work on both DOFs: time integration sums F^T y' cos (the shoe's share
        // through the base motion), the exact solver takes pi F^T s1 of the expanded orbit.
        CHECK(r.input_energy == Approx(e.input_energy).epsilon(1e-7).margin(1e-12));
        // The shoe y2 = y1 - (f - F2 cos) / kc, sampled at the same instants on both sides.
        double shoe_max = 0.0;
        for (Eigen::Index k = 0; k < reference.time.size(); ++k)
            shoe_max = std::max(shoe_max, std::abs(reference.displacement(k, 0) -
                                                   (reference.friction_force(k, 0) -
                                                    f2 * std::cos(omega * reference.time(k))) / kc));
        CHECK(r.y_max[1] == Approx(shoe_max).epsilon(1e-7).margin(1e-9));
        CHECK(std::abs(other.y_max[0] - reference.y_max[0]) > 100 * 1e-8 * reference.y_max[0]);
    }
}

TEST_CASE("Far above the resonances the stuck absorber is the stuck closed form at any response scale", "[timeint][scale]") {
    // Paper absorber, exact Coulomb (r = 0.1, wa = 1, mu = 0.2, fe = 0.5, C = 0). Both masses
    // stuck together (y1 = y2 = u) are one mass 1 + r on the main spring: adding the two rows
    // of model.hpp's equations, (1 + r) u'' + u = fe cos(w t), so |Y1| = |Y2| =
    // fe / ((1 + r) w^2 - 1) above the resonance. The contact holds: its force r u'' has the
    // amplitude r w^2 |Y| -> fe r / (1 + r) = 0.045 < mu. At w = 1e4..1e9 the response is
    // 4.5e-9..4.5e-19, far below a fixed absolute tolerance (the old 1e-12): the tolerances
    // must follow the response's scale. From rest (undamped: the free vibration never decays,
    // and the Poincare map hardly sees it, it turns by 2 pi 0.95 / w per period, so the
    // permanent-stick check must move it to the centred state) and from the linear stuck state;
    // adams and bdf. Tolerance 1e-6 relative (physics_tolerance() at the defaults).
    const AbsorberParameters p;
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    const double r = p.mass_ratio;
    for (const IntegrationMethod method : {IntegrationMethod::adams, IntegrationMethod::bdf}) {
        TimeIntegrationOptions o;
        o.method = method;
        for (double omega : {1e4, 1e6, 1e9}) {
            const double closed = p.excitation / ((1.0 + r) * omega * omega - 1.0);
            const Eigen::VectorXd stuck = linear_stuck_state(s, omega);
            for (const Eigen::VectorXd* start : {static_cast<const Eigen::VectorXd*>(nullptr), &stuck}) {
                const PeriodicResponse x = integrate_steady_state(s, omega, o, start);
                INFO(to_string(method) << (start ? " from the stuck state: " : " from rest: ") << x.summary());
                REQUIRE(x.converged);
                CHECK(x.regime == "stick");
                CHECK(test::relative_difference(x.y_max[0], closed) < 1e-6);
                CHECK(test::relative_difference(x.y_max[1], closed) < 1e-6);
                CHECK(test::relative_difference(x.y_amp1[0], closed) < 1e-6);
                CHECK(x.energy_error <= o.physics_tolerance());
                CHECK(x.stick_error <= o.physics_tolerance());
            }
        }
    }
}

TEST_CASE("The response scale is the quasi-static response below the resonances and the mass line above", "[timeint][scale]") {
    // Absorber: K^-1 F = (fe, fe) (the two springs in series with the force on the main mass,
    // no load on the absorber spring: y1 = y2 = fe / 1), M^-1 F = (fe, 0), so the scale is
    // min(fe, fe / w^2). Den Hartog's oscillator (k = m = F = 1): min(1, 1 / w^2) although its
    // stuck response is zero (the contact holds the mass to the ground).
    const AbsorberParameters p;
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    for (double omega : {0.1, 2.0, 1e3, 1e9})
        CHECK(test::relative_difference(response_scale(s, omega),
                                        std::min(p.excitation, p.excitation / (omega * omega))) < 1e-12);
    const System d = test::den_hartog_oscillator(0.3);
    CHECK(test::relative_difference(response_scale(d, 0.5), 1.0) < 1e-12);
    CHECK(test::relative_difference(response_scale(d, 4.0), 1.0 / 16.0) < 1e-12);
    // A free mass (DOF 1, m = 1, force 3) joined by a spring 2 to a massless shoe (DOF 2) that
    // slides on the ground: K = [[2, -2], [-2, 2]] is singular and M = diag(1, 0) too. The
    // shoe's contact held by a spring of K's largest diagonal, 2: [[2, -2], [-2, 4]] y = (3, 0)
    // gives y = (3, 1.5), the scale 3 (not the fallback 1, which the old beam test met: a
    // reduced beam with such a shoe got an absolute tolerance of 1e-10 m on a 1e-4 m response).
    const System shoe = test::grounded_coulomb((Eigen::MatrixXd(2, 2) << 1, 0, 0, 0).finished(),
                                              (Eigen::MatrixXd(2, 2) << 2, -2, -2, 2).finished(),
                                              Eigen::Vector2d(3.0, 0.0), 1, 0.3);
    CHECK(test::relative_difference(response_scale(shoe, 0.5), 3.0) < 1e-12);
    TimeIntegrationOptions o;
    o.displacement_scale = -1.0;
    CHECK_THROWS_AS(o.validate(), InvalidInput);
}

TEST_CASE("A steady state integrated too coarsely for its scale fails its physics checks, not converged", "[timeint][scale]") {
    // The old fixed absolute tolerance 1e-12 (displacement_scale = 1) at w = 1e6, where the
    // response is 4.5e-13 (closed form above): the integration cannot resolve it. Whatever
    // the Poincare map says, the result is either the closed form to 1e-6 or not converged
    // with the failed check in its message; measured: not converged.
    const AbsorberParameters p;
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    const double omega = 1e6;
    const double closed = p.excitation / ((1.0 + p.mass_ratio) * omega * omega - 1.0);
    TimeIntegrationOptions o;
    o.displacement_scale = 1.0;
    o.max_periods = 200;
    const PeriodicResponse x = integrate_steady_state(s, omega, o);
    INFO(x.summary());
    if (x.converged) {
        CHECK(test::relative_difference(x.y_max[0], closed) < 1e-6);
        CHECK(test::relative_difference(x.y_max[1], closed) < 1e-6);
    } else {
        CHECK_THAT(x.message, Catch::Contains("physics check"));
    }
}

TEST_CASE("TimeIntegrationOptions::validate holds the ranges hbf timeint shows, max_periods bounded for every front end",
          "[timeint]") {
    using T = TimeIntegrationOptions;
    TimeIntegrationOptions o;
    REQUIRE_NOTHROW(o.validate());
    o.max_periods = T::largest_max_periods;
    CHECK_NOTHROW(o.validate());
    o.max_periods = T::largest_max_periods + 1;  // Python's timeint(max_periods=...) as hbf's --max-periods
    CHECK_THROWS_WITH(o.validate(), "max_periods = 1000001 is out of range: allowed min_periods = 3..1000000");
    o = T{};
    o.relative_tolerance = T::largest_relative_tolerance * 2;
    CHECK_THROWS_WITH(o.validate(), Catch::Contains("relative_tolerance (CVODE relative tolerance) = 0.002 is out of "
                                                    "range: allowed 1e-14..0.001"));
    o = T{};
    o.absolute_tolerance = T::smallest_absolute_tolerance / 2;
    CHECK_THROWS_WITH(o.validate(), Catch::Contains("allowed 1e-16..0.001"));
    o = T{};
    o.steady_tolerance = T::largest_steady_tolerance * 2;
    CHECK_THROWS_WITH(o.validate(), Catch::Contains("allowed 1e-14..0.01"));
}

TEST_CASE("A stop request ends the integration after the period it answers in (CVODE, law unilateral, law elastic), "
          "and a sweep computes no further frequency",
          "[timeint][status]") {
    // Each integration is asked after every period; the fourth answer is a reason. At least 10
    // periods are required for convergence, so none converges first: the response is stopped
    // after exactly 4 periods (counted independently by the calls), not converged, and says why.
    const std::string dir = std::string(HBF_SOURCE_DIR) + "/examples/systems/";
    const std::vector<std::pair<std::string, System>> systems = {
        {"CVODE (dahl)", test::dahl_oscillator(20.0, 0.5, 1.0, 0.05)},
        {"law unilateral", io::read_system_config(dir + "liftoff3_rigid.toml").system},
        {"law elastic", io::read_system_config(dir + "liftoff3.toml").system}};
    for (const auto& [name, system] : systems) {
        INFO(name);
        TimeIntegrationOptions options;
        options.min_periods = 10;
        int calls = 0;
        options.stop = [&calls] { return ++calls >= 4 ? std::string("asked to stop") : std::string(); };
        const PeriodicResponse r = integrate_steady_state(system, 1.2, options);
        CHECK(r.stopped);
        CHECK_FALSE(r.converged);
        CHECK(calls == 4);
        CHECK(r.periods == 4);
        CHECK_THAT(r.message, Catch::Contains("stopped after 4 periods") && Catch::Contains("asked to stop"));
        // Without the request the same integration goes on (and is not stopped).
        options.stop = nullptr;
        options.max_periods = 12;
        const PeriodicResponse free = integrate_steady_state(system, 1.2, options);
        CHECK_FALSE(free.stopped);
        CHECK(free.periods >= 10);
    }
    // A sweep: the first frequency is stopped, the others are not computed.
    TimeIntegrationOptions options;
    options.min_periods = 10;
    int calls = 0;
    options.stop = [&calls] { return ++calls >= 4 ? std::string("asked to stop") : std::string(); };
    const std::vector<PeriodicResponse> swept = sweep(test::dahl_oscillator(20.0, 0.5, 1.0, 0.05), {1.0, 1.1, 1.2}, options);
    REQUIRE(swept.size() == 1);
    CHECK(swept[0].stopped);
    CHECK(calls == 4);
}
