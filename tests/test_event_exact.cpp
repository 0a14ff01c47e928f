// The event-exact periodic solver (event_exact.hpp) against independent references: Den
// Hartog's closed form, tight CVODE time integration, the energy balance, a finite-difference
// monodromy of the CVODE period map, the decay of perturbed time integrations, and the
// closed-form permanent-stick state.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/time_integration.hpp"
#include "../benchmarks/chain.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

System absorber(FrictionLaw law, double fe = 0.5, double wb = 0.4) {
    AbsorberParameters p;
    p.excitation = fe;
    p.contact_stiffness_ratio = wb;
    return friction_absorber(p, law);
}

/// The 3-DOF chain example with both contacts given exact laws (Jenkins, Coulomb).
System chain3() {
    io::SystemConfig config = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/chain3.toml");
    config.system.contacts[1].law = FrictionLaw::coulomb;
    return config.system;
}

TimeIntegrationOptions tight() { return test::tight_time_integration(); }

/// One period of CVODE from `state` (the state at the start of the second period).
Eigen::VectorXd cvode_period_map(const System& s, double omega, const Eigen::VectorXd& state) {
    TimeIntegrationOptions o = tight();
    o.min_periods = o.max_periods = 2;
    o.shooting = false;
    o.stick_restart = false;
    return integrate_steady_state(s, omega, o, &state).state;
}

/// Multiplier moduli above `floor`, sorted descending.
std::vector<double> moduli(const Eigen::VectorXcd& mu, double floor) {
    std::vector<double> out;
    for (Eigen::Index k = 0; k < mu.size(); ++k)
        if (std::abs(mu(k)) > floor) out.push_back(std::abs(mu(k)));
    std::sort(out.rbegin(), out.rend());
    return out;
}

}  // namespace

TEST_CASE("Den Hartog's exact non-sticking solution is reproduced to 1e-9 (amplitude, signal, stop times)") {
    const double rho = 0.3;
    const System s = test::den_hartog_oscillator(rho);
    ExactOptions options;
    options.samples = 64;
    for (double eta : {0.55, 0.6, 0.65, 0.7, 0.75}) {
        const analytic::DenHartogResponse dh = analytic::den_hartog(eta, rho);
        Eigen::VectorXd start = linear_stuck_state(s, eta);
        start(0) = 1.5;  // far from the orbit: a stuck start that slips at once
        const ExactOrbit o = exact_periodic_orbit(s, eta, start, options);
        INFO("eta = " << eta << ": " << o.summary());
        REQUIRE(o.converged);
        CHECK(std::abs(o.y_max[0] - dh.amplitude) < 1e-9);
        CHECK(o.regime == "slip");
        CHECK(o.stick_fraction == 0.0);
        for (int j = 0; j < options.samples; ++j) {
            CHECK(std::abs(o.displacement(j, 0) - dh.displacement(o.time(j))) < 1e-9);
            CHECK(std::abs(o.velocity(j, 0) - dh.velocity(o.time(j))) < 1e-9);
        }
        // Two reversals per period, where u' = 0: at the maximum (eta t = psi) and half a period later.
        REQUIRE(o.events.size() == 2);
        const double period = 2 * M_PI / eta;
        const double t_max = dh.phase / eta;
        for (const ExactEvent& e : o.events) {
            const double d = std::fmod(std::abs(e.time - t_max) + 1e-12, period / 2) - 1e-12;
            CHECK(std::min(d, period / 2 - d) < 1e-9);
            CHECK(e.mode_before == -e.mode_after);
        }
        // Energy balance (no viscous damping): friction energy = input work.
        CHECK(std::abs(o.energy - o.input_energy) < 1e-10 * o.energy);
        CHECK(o.stable);
    }
}

TEST_CASE("Exact orbits of the absorber equal tight time integration in every regime (coulomb, jenkins)") {
    struct Case {
        FrictionLaw law;
        double wb, omega;
        const char* regime;
    };
    for (const Case& c : {Case{FrictionLaw::coulomb, 0.4, 0.8, "stick"}, Case{FrictionLaw::coulomb, 0.4, 0.875, "stick-slip"},
                          Case{FrictionLaw::coulomb, 0.4, 0.894927, "slip"}, Case{FrictionLaw::coulomb, 0.4, 1.065, "stick-slip"},
                          Case{FrictionLaw::jenkins, 0.4, 1.2, "stick-slip"}, Case{FrictionLaw::jenkins, 31.62, 0.8624, "stick-slip"},
                          Case{FrictionLaw::jenkins, 31.62, 0.9, "stick-slip"}, Case{FrictionLaw::jenkins, 31.62, 1.1, "stick"}}) {
        const System s = absorber(c.law, 0.5, c.wb);
        const PeriodicResponse r = integrate_steady_state(s, c.omega, tight());
        REQUIRE(r.converged);
        Eigen::VectorXd start = r.state;
        start.head(4) *= 1.03;  // 3 % off
        const ExactOrbit o = exact_periodic_orbit(s, c.omega, start);
        INFO(to_string(c.law) << " wb = " << c.wb << " w = " << c.omega << ": " << o.summary());
        REQUIRE(o.converged);
        CHECK(o.regime == c.regime);
        CHECK(r.regime == c.regime);
        for (int i = 0; i < 2; ++i) {
            CHECK(std::abs(o.y_max[i] - r.y_max[i]) < 1e-8);
            CHECK(std::abs(o.y_amp1[i] - r.y_amp1[i]) < 1e-8);
        }
        CHECK(std::abs(o.stick_fraction - r.stick_fraction) < 1e-8);
        CHECK(std::abs(o.energy - r.energy) < 1e-8 * std::max(1.0, r.energy));
        CHECK(o.switches == r.switches);
        CHECK(std::abs(o.energy - o.input_energy) < 1e-10 * std::max(1.0, o.energy));  // C = 0
        CHECK((o.state.head(4) - r.state.head(4)).cwiseAbs().maxCoeff() < 1e-7);
    }
}

TEST_CASE("The 3-DOF chain with a Jenkins and a Coulomb contact equals tight time integration") {
    const System s = chain3();
    for (double omega : {0.5, 1.0, 1.5}) {
        const PeriodicResponse r = integrate_steady_state(s, omega, tight());
        REQUIRE(r.converged);
        const ExactOrbit o = exact_periodic_orbit(s, omega, linear_stuck_state(s, omega));
        INFO("w = " << omega << ": " << o.summary());
        REQUIRE(o.converged);
        for (int i = 0; i < 3; ++i) CHECK(std::abs(o.y_max[i] - r.y_max[i]) < 1e-8);
        CHECK(o.regime == r.regime);
        CHECK(std::abs(o.stick_fraction - r.stick_fraction) < 1e-8);
        // Energy balance with viscous damping: input = friction + viscous (CVODE's quadrature).
        CHECK(std::abs(o.input_energy - o.energy - r.viscous_energy) < 1e-7 * o.input_energy);
    }
}

TEST_CASE("Floquet multipliers equal those of a finite-difference monodromy of the CVODE period map") {
    struct Case {
        FrictionLaw law;
        double wb, omega;
    };
    // t = 0 lies in a slip phase of the coulomb orbit (all 2N states free) and in a stick
    // phase of the jenkins one (2N + 1 states, the slider free); the exact multipliers live on
    // the section's manifold, so the comparison is on the moduli above 1e-6.
    for (const Case& c : {Case{FrictionLaw::coulomb, 0.4, 1.065}, Case{FrictionLaw::jenkins, 0.4, 1.2}}) {
        const System s = absorber(c.law, 0.5, c.wb);
        const PeriodicResponse r = integrate_steady_state(s, c.omega, tight());
        const ExactOrbit o = exact_periodic_orbit(s, c.omega, r.state);
        REQUIRE(o.converged);
        const int n = c.law == FrictionLaw::jenkins ? 5 : 4;
        Eigen::MatrixXd fd(n, n);
        const double h = 1e-6;
        for (int k = 0; k < n; ++k) {
            Eigen::VectorXd plus = o.state, minus = o.state;
            plus(k) += h;
            minus(k) -= h;
            fd.col(k) = (cvode_period_map(s, c.omega, plus) - cvode_period_map(s, c.omega, minus)).head(n) / (2 * h);
        }
        const std::vector<double> reference = moduli(Eigen::EigenSolver<Eigen::MatrixXd>(fd).eigenvalues(), 1e-4);
        const std::vector<double> exact = moduli(o.multipliers, 1e-4);
        INFO(to_string(c.law) << " w = " << c.omega << ": " << o.summary());
        REQUIRE(reference.size() == exact.size());
        for (std::size_t k = 0; k < exact.size(); ++k) CHECK(std::abs(exact[k] - reference[k]) < 1e-4);
        // The exact solver's own monodromy (exact_flow) from the orbit's state at t = 0.
        const ExactFlow flow = exact_flow(s, c.omega, o.state);
        CHECK((flow.monodromy.topLeftCorner(n, n) - fd).cwiseAbs().maxCoeff() < 1e-4 * std::max(1.0, fd.norm()));
    }
}

TEST_CASE("The stability verdict: a perturbed time integration evolves as the exact monodromy predicts") {
    // Absorber, coulomb, stick-slip at w = 1.065 (t = 0 in slip: all four states free). A
    // small perturbation integrated by CVODE period after period stays equal to M^k delta, M the
    // exact solver's monodromy, to first order; its size decays like max |mu|^k (stable).
    const System s = absorber(FrictionLaw::coulomb);
    const double omega = 1.065;
    const ExactOrbit o = exact_periodic_orbit(s, omega, integrate_steady_state(s, omega, tight()).state);
    REQUIRE(o.converged);
    REQUIRE(o.stable);
    const Eigen::MatrixXd m = exact_flow(s, omega, o.state).monodromy.topLeftCorner(4, 4);
    const Eigen::Vector4d delta(1e-5, -2e-5, 1e-5, 3e-5);
    Eigen::VectorXd x = o.state;
    x.head(4) += delta;
    Eigen::VectorXd predicted = delta;
    for (int k = 1; k <= 30; ++k) {
        x = cvode_period_map(s, omega, x);
        predicted = m * predicted;
        if (k % 10 == 0) {
            const Eigen::VectorXd actual = x.head(4) - o.state.head(4);
            INFO(o.summary() << "; period " << k);
            CHECK((actual - predicted).norm() < 0.02 * predicted.norm());
            CHECK(actual.norm() < 1.5 * std::pow(o.max_multiplier, k) * delta.norm() * 10);
        }
    }
    CHECK(o.max_multiplier < 1.0);
}

TEST_CASE("Permanent stick follows the stated convention: the linear stuck state with zero mean force") {
    ExactOptions options;
    options.samples = 128;
    SECTION("coulomb: rigid contact, constraint force centred") {
        const System s = absorber(FrictionLaw::coulomb);
        const double omega = 0.7;
        Eigen::VectorXd start = linear_stuck_state(s, omega);
        const ExactOrbit o = exact_periodic_orbit(s, omega, start, options);
        REQUIRE(o.converged);
        CHECK(o.permanent_stick);
        CHECK(o.regime == "stick");
        CHECK(o.stick_fraction == 1.0);
        // Rigid contact: y1 = y2 = F / (K11 + K22 + 2 K12 - omega^2 (m1 + m2)) = fe / (1 - 1.1 omega^2).
        const double y = 0.5 / (1.0 - 1.1 * omega * omega);
        CHECK(std::abs(o.y_max[0] - std::abs(y)) < 1e-12);
        CHECK(std::abs(o.friction_force.col(0).mean()) < 1e-12);
        CHECK(permanent_stick_load(s, omega) < 1.0);
        CHECK(o.stable);  // undamped stuck structure: multipliers on the unit circle
        CHECK(std::abs(o.max_multiplier - 1.0) < 1e-9);
    }
    SECTION("jenkins: slider at zero") {
        const System s = absorber(FrictionLaw::jenkins);
        const double omega = 0.8;
        const ExactOrbit o = exact_periodic_orbit(s, omega, linear_stuck_state(s, omega), options);
        REQUIRE(o.converged);
        CHECK(o.permanent_stick);
        CHECK(o.state(4) == 0.0);
        CHECK(std::abs(o.friction_force.col(0).mean()) < 1e-12);
        const PeriodicResponse r = integrate_steady_state(s, omega, tight());
        CHECK(std::abs(o.y_max[0] - r.y_max[0]) < 1e-9);
    }
    SECTION("the stick|stick-slip boundary is where the load crosses 1") {
        const System s = absorber(FrictionLaw::coulomb);
        // Below it the exact orbit sticks, above it slips: checked on both sides of the root.
        double lo = 0.85, hi = 0.87;
        REQUIRE(permanent_stick_load(s, lo) < 1.0);
        REQUIRE(permanent_stick_load(s, hi) > 1.0);
        for (int k = 0; k < 60; ++k) {
            const double mid = 0.5 * (lo + hi);
            (permanent_stick_load(s, mid) <= 1.0 ? lo : hi) = mid;
        }
        const ExactOrbit below = exact_periodic_orbit(s, lo - 1e-6, linear_stuck_state(s, lo));
        const ExactOrbit above = exact_periodic_orbit(s, hi + 1e-6, linear_stuck_state(s, lo));
        REQUIRE(below.converged);
        REQUIRE(above.converged);
        CHECK(below.regime == "stick");
        CHECK(above.regime == "stick-slip");
        // Just above, a slip phase of 0.5 % of the period, shorter than a step: as CVODE has it.
        TimeIntegrationOptions o = tight();
        const PeriodicResponse r = integrate_steady_state(s, hi + 1e-6, o);
        CHECK(std::abs(above.y_max[0] - r.y_max[0]) < 1e-9);
        CHECK(std::abs(above.stick_fraction - r.stick_fraction) < 1e-7);
        CHECK(above.stick_fraction < 0.999);
        // The paper's limit friction coefficient (analytic.hpp, derived independently) is mu there.
        AbsorberParameters p;
        p.excitation = 0.5;
        CHECK(std::abs(analytic::coulomb_limit_friction(p, 0.5 * (lo + hi)) - p.friction_coefficient) < 1e-9);
    }
}

TEST_CASE("Exact solver input checks") {
    const System coulomb = absorber(FrictionLaw::coulomb);
    CHECK_THROWS_AS(exact_periodic_orbit(absorber(FrictionLaw::dahl), 1.0, Eigen::VectorXd::Zero(6)), InvalidInput);
    CHECK_THROWS_AS(exact_periodic_orbit(coulomb, 1.0, Eigen::VectorXd::Zero(5)), InvalidInput);
    CHECK_THROWS_AS(exact_periodic_orbit(coulomb, -1.0, Eigen::VectorXd::Zero(6)), InvalidInput);
    ExactOptions bad;
    bad.tolerance = 0;
    CHECK_THROWS_AS(exact_periodic_orbit(coulomb, 1.0, Eigen::VectorXd::Zero(6), bad), InvalidInput);
    CHECK_FALSE(exact_solver_supports(absorber(FrictionLaw::lugre)));
    CHECK(exact_solver_supports(coulomb));
}

TEST_CASE("The unstable verdict: a perturbed time integration grows as the exact monodromy predicts") {
    // examples/systems/jenkins_negative_stiffness.toml: a negative spring held by a Jenkins
    // contact (a passive structure cannot have |mu| > 1 with these monotone friction laws).
    const System s =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/jenkins_negative_stiffness.toml").system;
    for (double omega : {0.9, 1.2}) {
        const ExactOrbit o = exact_periodic_orbit(s, omega, linear_stuck_state(s, omega));
        INFO(o.summary());
        REQUIRE(o.converged);
        CHECK(o.regime == "stick-slip");
        CHECK_FALSE(o.stable);
        CHECK(o.max_multiplier > 2.0);
        // The orbit itself is right: CVODE started on it stays for a period (to its tolerance).
        const Eigen::VectorXd once = cvode_period_map(s, omega, o.state);
        CHECK((once.head(3) - o.state.head(3)).cwiseAbs().maxCoeff() < 1e-9);
        const Eigen::MatrixXd m = exact_flow(s, omega, o.state).monodromy;
        const Eigen::Vector3d delta(1e-8, -1e-8, 0.5e-8);
        Eigen::VectorXd x = o.state, predicted = delta;
        x.head(3) += delta;
        for (int k = 1; k <= 5; ++k) {
            x = cvode_period_map(s, omega, x);
            predicted = m * predicted;
            const Eigen::VectorXd actual = x.head(3) - o.state.head(3);
            CHECK((actual - predicted).norm() < 0.01 * predicted.norm());
        }
        CHECK((x.head(3) - o.state.head(3)).norm() > 10 * delta.norm());  // it grew
    }
}

TEST_CASE("Massless DOFs: the exact orbit of the condensed system, in the original DOFs, equals the Jenkins model's",
          "[exact][massless]") {
    // massless_contact: a mass on a spring and, behind a spring k_t, a massless DOF held by
    // exact Coulomb friction to the ground. It is exactly the Jenkins element (k_t, F_c) on the
    // mass (jenkins_equivalent), and the massless DOF is its slider: y2(t) = s(t) = y1 - f / k_t.
    const double kt = 0.8, limit = 0.3;
    const System shoe = hbf::test::massless_contact(kt, limit), jenkins = hbf::test::jenkins_equivalent(kt, limit);
    REQUIRE(exact_solver_supports(shoe));
    ExactOptions options;
    options.samples = 4000;
    options.outputs = {Output("gap", {{1, 1.0}, {0, -1.0}}), Output::dof(1)};  // y2 - y1 = -f / k_t, y2
    for (double omega : {0.5, 0.9, 1.1, 1.6}) {
        INFO("w = " << omega);
        const ExactOrbit a = exact_periodic_orbit(shoe, omega, linear_stuck_state(shoe, omega), options);
        ExactOptions plain = options;
        plain.outputs.clear();
        const ExactOrbit b = exact_periodic_orbit(jenkins, omega, linear_stuck_state(jenkins, omega), plain);
        REQUIRE(a.converged);
        REQUIRE(b.converged);
        REQUIRE(a.y_max.size() == 2);
        CHECK(a.regime == b.regime);
        CHECK(a.y_max[0] == Approx(b.y_max[0]).epsilon(1e-10));
        CHECK(a.y_amp1[0] == Approx(b.y_amp1[0]).epsilon(1e-10));
        CHECK(a.energy == Approx(b.energy).epsilon(1e-10));
        CHECK(a.input_energy == Approx(b.input_energy).epsilon(1e-10));
        CHECK(a.switches == b.switches);
        // The massless DOF is the slider, sample for sample; its maximum (turning points
        // refined) is at least every sample's and within the samples' resolution of them.
        double slider_max = 0.0, gap_max = 0.0;
        for (int j = 0; j < options.samples; ++j) {
            const double s = b.displacement(j, 0) - b.friction_force(j, 0) / kt;
            CHECK(a.displacement(j, 1) == Approx(s).margin(1e-10 * b.y_max[0]));
            CHECK(a.friction_force(j, 0) == Approx(b.friction_force(j, 0)).margin(1e-10 * limit));
            slider_max = std::max(slider_max, std::abs(s));
            gap_max = std::max(gap_max, std::abs(b.friction_force(j, 0)) / kt);
        }
        CHECK(a.y_max[1] >= slider_max * (1.0 - 1e-12));
        CHECK(a.y_max[1] == Approx(slider_max).epsilon(1e-5));
        CHECK(a.output_max[1] == a.y_max[1]);
        CHECK(a.output_max[0] >= gap_max * (1.0 - 1e-12));
        CHECK(a.output_max[0] == Approx(gap_max).epsilon(1e-5));
        // The state at t = 0 in the original layout is on the orbit: a start from it converges
        // at once to the same orbit.
        const ExactOrbit again = exact_periodic_orbit(shoe, omega, a.state, options);
        REQUIRE(again.converged);
        CHECK(again.iterations <= 1);
        CHECK(again.y_max[1] == Approx(a.y_max[1]).epsilon(1e-10));
    }
}

TEST_CASE("Massless DOFs the condensation cannot remove are refused by the exact solver, with the reason",
          "[exact][massless]") {
    System dahl_shoe = hbf::test::massless_contact(0.8, 0.3);
    dahl_shoe.contacts[0].law = FrictionLaw::dahl;
    dahl_shoe.contacts[0].stiffness = 2.0;
    CHECK_FALSE(exact_solver_supports(dahl_shoe));
    CHECK_THAT(exact_solver_refusal(dahl_shoe), Catch::Contains("dahl"));
    System damped_shoe = hbf::test::massless_contact(0.8, 0.3);
    damped_shoe.damping = sparse(Eigen::Vector2d(0.05, 0.01).asDiagonal());
    CHECK_THAT(exact_solver_refusal(damped_shoe),
               Catch::Contains("static condensation") && Catch::Contains("damping"));
    CHECK_THROWS_WITH(exact_periodic_orbit(damped_shoe, 1.0, Eigen::VectorXd::Zero(6)),
                      Catch::Contains("massless DOF 2 has damping"));
    CHECK(exact_solver_refusal(hbf::test::massless_contact(0.8, 0.3)).empty());
}

TEST_CASE("Fast modes flowed in closed form: a soft oscillator with a stiff appendage equals tight time integration") {
    // DOF 1 (mass 1, spring 1: w ~ 1) carries the Coulomb contact and the force; DOFs 2 and 3
    // (masses 0.01, springs 1e4 and 2e4) form an appendage ringing near 1000 and 2600 rad/s
    // with 5-13 % stiffness-proportional damping. Its modes lie far above 4 w: the flows take
    // them in closed form, and the steps follow the slow mode and the period, not the stiffest
    // mode (a period takes several thousand Taylor steps of 1 / |lambda_max|).
    System s;
    Eigen::MatrixXd m = Eigen::Vector3d(1.0, 0.01, 0.01).asDiagonal();
    Eigen::MatrixXd k(3, 3);
    k << 1.0 + 1e4, -1e4, 0.0, -1e4, 1e4 + 2e4, -2e4, 0.0, -2e4, 2e4;
    s.mass = sparse(m);
    s.stiffness = sparse(k);
    s.damping = sparse(1e-4 * k + 0.02 * m);
    s.excitation = Eigen::Vector3d(1.0, 0.0, 0.0);
    Contact c;
    c.dof = 0;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = 0.3;
    s.contacts.push_back(c);
    const Eigen::MatrixXd a = m.inverse() * k;
    const double fastest = std::sqrt(Eigen::EigenSolver<Eigen::MatrixXd>(a).eigenvalues().cwiseAbs().maxCoeff());
    for (double omega : {0.6, 1.0, 1.6}) {
        const PeriodicResponse r = integrate_steady_state(s, omega, tight());
        REQUIRE(r.converged);
        const ExactOrbit o = exact_periodic_orbit(s, omega, linear_stuck_state(s, omega));
        INFO("w = " << omega << ": " << o.summary());
        REQUIRE(o.converged);
        for (int i = 0; i < 3; ++i) CHECK(std::abs(o.y_max[i] - r.y_max[i]) < 1e-8 * (1.0 + r.y_max[0]));
        CHECK(o.regime == r.regime);
        CHECK(std::abs(o.stick_fraction - r.stick_fraction) < 1e-8);
        CHECK(std::abs(o.input_energy - o.energy - r.viscous_energy) < 1e-7 * o.input_energy);
    }
    // The cost of a period (Taylor steps, plus the fast modes' samples / 16) no longer grows with
    // the period against the stiffest mode (T |lambda_max|, 6900 at w = 0.6, 69000 at 0.06): the
    // appendage's modes are sampled only while they ring after an event (3 s).
    const double cost = exact_steps_per_period(s, 0.6);
    CHECK(cost < 0.2 * (2.0 * M_PI / 0.6) * fastest);
    CHECK(exact_steps_per_period(s, 0.06) <= 1.01 * cost);
}

TEST_CASE("Fast modes split in any units: the chain's exact orbits in other consistent units are the same orbits") {
    // The 10-DOF chain of exact_scaling with its Coulomb contact, in units where masses are
    // 1e-6 times and stiffnesses 1e9 (or 1) times the numbers (lengths unchanged, time x tu).
    // The stuck pattern's dynamic block carries rounding residues of the constraint's
    // projection (exactly zero in some units, 1e-16 of the block in others); balancing read
    // them as couplings and scaled their coordinates by 2e-7, and the split period map was then
    // noisy at 6e-10 in these units only: Newton stalled near 1e-11 for w tu in [1, 1.42] and
    // fell back on the plain Taylor flows (20 times the periods). The orbit and its cost must
    // not depend on the units.
    const System a = bench::chain(10, 1);
    for (const auto& [mass_unit, stiffness_unit] : {std::pair{1e-6, 1e9}, std::pair{1e-6, 1.0}}) {
        const System b = bench::chain(10, 1, mass_unit, stiffness_unit);
        const double tu = std::sqrt(mass_unit / stiffness_unit);
        for (double x : {1.0, 1.2, 1.4}) {
            const ExactOrbit oa = exact_periodic_orbit(a, x, linear_stuck_state(a, x));
            const ExactOrbit ob = exact_periodic_orbit(b, x / tu, linear_stuck_state(b, x / tu));
            INFO("units " << mass_unit << ", " << stiffness_unit << ", w tu = " << x << ": " << oa.summary() << " | "
                          << ob.summary());
            REQUIRE(oa.converged);
            REQUIRE(ob.converged);
            CHECK(ob.message.find("plain Taylor") == std::string::npos);
            CHECK(ob.periods <= oa.periods + 2);
            for (int i = 0; i < 10; ++i) CHECK(std::abs(ob.y_max[i] - oa.y_max[i]) < 1e-10 * oa.y_max[9]);
            CHECK(ob.energy / stiffness_unit == Approx(oa.energy).epsilon(1e-9));
            CHECK(ob.stick_fraction == Approx(oa.stick_fraction).margin(1e-9));
        }
    }
}
