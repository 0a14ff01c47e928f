// The periodic orbit of law elastic (elastic_exact.hpp): the flow's derivative against central
// differences of the period map, the orbit against time integration to its steady state, the
// multipliers against the linear stuck structure's closed form and against the decay of a
// perturbation.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "time_integration/elastic_integrator.hpp"
#include "hbf/config.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"
#include "hbf/time_integration.hpp"
#include <nlohmann/json.hpp>
#include "cli_support.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

System liftoff3() { return io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system; }

/// A 3D contact on an anisotropic structure: the slip direction turns along an elliptic path,
/// and the normal load varies (the normal coordinate is forced too).
System cone3d(double normal_force) {
    System s;
    s.mass = sparse(Eigen::Vector3d(1.0, 1.2, 0.8).asDiagonal());
    s.damping = sparse(0.02 * Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal());
    s.stiffness = sparse(Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal());
    s.excitation = Eigen::Vector3d(0.6, 0.5, normal_force);
    Contact c = hbf::test::elastic_contact(1.5, 4.0, 0.3, 1.0, {0.0, 0.0, 1.0});
    c.lists["second_direction"] = {0.0, 1.0, 0.0};
    s.contacts = {c};
    return s;
}

/// The orbit at omega from rest, required to converge.
ExactOrbit orbit_from_rest(const System& s, double omega) {
    const ExactOrbit orbit = elastic_periodic_orbit(s, omega, Eigen::VectorXd());
    INFO("w = " << omega << ": " << orbit.message);
    REQUIRE(orbit.converged);
    return orbit;
}

/// The units of the continuous state: 1 for displacements and sliders, omega for velocities.
Eigen::VectorXd units(const System& s, double omega, int continuous) {
    Eigen::VectorXd unit = Eigen::VectorXd::Ones(continuous);
    unit.segment(s.dofs(), s.dofs()).setConstant(omega);
    return unit;
}

/// max |Phi - central differences of the period map| in the units above, relative to max |Phi|,
/// at the state `x` (steps of 1e-5 of its size).
double derivative_gap(const System& s, double omega, const Eigen::VectorXd& x, int& events) {
    TimeIntegrationOptions flow;
    flow.relative_tolerance = flow.absolute_tolerance = 1e-12;
    const double scale = response_scale(s, omega);
    detail::ElasticIntegrator plain(s, omega, flow, scale), variational(s, omega, flow, scale, true);
    const detail::ElasticIntegrator::Record r = variational.period(x, 0);
    REQUIRE(r.ok);
    events = static_cast<int>(r.events.size());
    const int k = plain.continuous(), n = s.dofs();
    const Eigen::VectorXd unit = units(s, omega, k);
    const double size = x.head(n).cwiseAbs().maxCoeff();
    Eigen::MatrixXd differences(k, k);
    for (int j = 0; j < k; ++j) {
        const double h = 1e-5 * size * unit(j);
        Eigen::VectorXd plus = x, minus = x;
        plus(j) += h;
        minus(j) -= h;
        const detail::ElasticIntegrator::Record a = plain.period(plus, 0), b = plain.period(minus, 0);
        REQUIRE((a.ok && b.ok));
        differences.col(j) = (a.end.head(k) - b.end.head(k)) / (2.0 * h);
    }
    const Eigen::MatrixXd exact = unit.cwiseInverse().asDiagonal() * r.monodromy * unit.asDiagonal();
    const Eigen::MatrixXd central = unit.cwiseInverse().asDiagonal() * differences * unit.asDiagonal();
    return (exact - central).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("elastic exact: the flow's derivative over a period (variational equation and saltation at the events) "
          "equals central differences of the period map through stick, slip and lift-off, 2D and 3D",
          "[elastic_exact]") {
    struct Case {
        const char* name;
        System system;
        double omega;
        int min_events;
    };
    // liftoff3 at 2.2: stick -> slip -> open -> slip (a closing straight into slip) -> stick
    const std::vector<Case> cases = {{"liftoff3, stick-slip", liftoff3(), 1.2, 2},
                                     {"liftoff3, lift-off", liftoff3(), 2.2, 4},
                                     {"3D cone, turning slip", cone3d(0.1), 1.1, 0}};
    for (const Case& c : cases) {
        INFO(c.name);
        const ExactOrbit orbit = orbit_from_rest(c.system, c.omega);
        int events = 0;
        const double gap = derivative_gap(c.system, c.omega, orbit.state, events);
        INFO("events " << events << ", relative gap " << gap);
        CHECK(events >= c.min_events);
        CHECK(gap <= 1e-5);
    }
}

TEST_CASE("elastic exact: from time integration's final state, the orbit equals its steady state (converged in "
          "its tolerance) in maxima, first harmonics and contact shares, through stick-slip and lift-off, 2D and 3D",
          "[elastic_exact]") {
    struct Case {
        System system;
        double omega;
    };
    // liftoff3: stick-slip at 1.2, with lift-off at 1.9 and 2.4; the 3D cone with lift-off at
    // 1.3 (its slip next to the openings is stiff: Newton's matrix by differences)
    const std::vector<Case> cases = {{liftoff3(), 1.2}, {liftoff3(), 1.9}, {liftoff3(), 2.4}, {cone3d(0.3), 1.3}};
    const TimeIntegrationOptions tight = hbf::test::tight_time_integration();
    double opened = 0.0;
    for (const Case& c : cases) {
        const System& s = c.system;
        const double omega = c.omega;
        const PeriodicResponse ti = integrate_steady_state(s, omega, tight, nullptr);
        INFO("system with " << s.dofs() << " DOFs");
        // from the integrator's final state: the orbit it settled on (at 2.4 the solver from
        // rest finds another stable orbit, its maxima 3 to 8 times these)
        const ExactOrbit orbit = elastic_periodic_orbit(s, omega, ti.state);
        INFO("w = " << omega << ": " << ti.message << " | " << orbit.message);
        REQUIRE(ti.converged);
        REQUIRE(orbit.converged);
        CHECK(orbit.residual <= 1e-9);
        CHECK(orbit.switches >= 2);
        opened = std::max(opened, orbit.contacts[0].separated_fraction);
        for (int i = 0; i < s.dofs(); ++i) {
            const auto k = static_cast<std::size_t>(i);
            CHECK(orbit.y_max[k] == Approx(ti.y_max[k]).epsilon(1e-8));
            CHECK(std::abs(orbit.harmonic1(i) - ti.harmonic1(i)) <= 1e-8 * ti.harmonic1.cwiseAbs().maxCoeff());
        }
        CHECK(orbit.contacts[0].stick_fraction == Approx(ti.contacts[0].stick_fraction).margin(1e-8));
        CHECK(orbit.contacts[0].separated_fraction == Approx(ti.contacts[0].separated_fraction).margin(1e-8));
        CHECK(orbit.stable);
    }
    CHECK(opened >= 0.1);
}

TEST_CASE("elastic exact: on a permanently stuck orbit the multipliers are exp(lambda T) of the stuck linear "
          "structure, the slider's held position among them at 1",
          "[elastic_exact]") {
    const System s = liftoff3();
    const double omega = 0.6;
    const ExactOrbit orbit = orbit_from_rest(s, omega);
    REQUIRE(orbit.permanent_stick);
    // [y, y', s]: y'' = M^-1 (F - (K + k_t w w^T + k_n n n^T) y - C y' + k_t w s + N_0 n), s' = 0
    const Eigen::MatrixXd w = s.contact_directions(s.contacts[0]);
    const ElasticContact element = elastic_element(s.contacts[0]);
    const int n = s.dofs();
    const Eigen::MatrixXd minv = Eigen::MatrixXd(s.mass).inverse();
    const Eigen::MatrixXd stuck = Eigen::MatrixXd(s.stiffness) +
                                  element.tangential_stiffness * w.col(0) * w.col(0).transpose() +
                                  element.normal_stiffness * w.col(1) * w.col(1).transpose();
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n + 1, 2 * n + 1);
    a.block(0, n, n, n).setIdentity();
    a.block(n, 0, n, n) = -minv * stuck;
    a.block(n, n, n, n) = -minv * Eigen::MatrixXd(s.damping);
    a.block(n, 2 * n, n, 1) = element.tangential_stiffness * minv * w.col(0);
    const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
    const double period = 2.0 * M_PI / omega;
    REQUIRE(orbit.multipliers.size() == lambda.size());
    std::vector<bool> used(static_cast<std::size_t>(lambda.size()), false);
    for (Eigen::Index k = 0; k < orbit.multipliers.size(); ++k) {
        double nearest = 1e300;
        Eigen::Index at = -1;
        for (Eigen::Index j = 0; j < lambda.size(); ++j) {
            const double gap = std::abs(orbit.multipliers(k) - std::exp(lambda(j) * period));
            if (!used[static_cast<std::size_t>(j)] && gap < nearest) {
                nearest = gap;
                at = j;
            }
        }
        INFO("multiplier " << orbit.multipliers(k) << " nearest closed form at " << nearest);
        CHECK(nearest <= 1e-7);
        if (at >= 0) used[static_cast<std::size_t>(at)] = true;
    }
    CHECK(orbit.max_multiplier == Approx(1.0).margin(1e-7));  // the held slider
}

TEST_CASE("elastic exact: multipliers by central differences carry their accuracy: on the permanently stuck orbit "
          "each is within it of exp(lambda T), and the held slider's multiplier at 1 is never called unstable",
          "[elastic_exact][stability]") {
    const System s = liftoff3();
    const double omega = 0.6;
    const ExactOrbit own = orbit_from_rest(s, omega);  // the flow's own derivative
    REQUIRE(own.permanent_stick);
    CHECK(own.multiplier_accuracy == 0.0);
    const ExactOrbit orbit = detail::elastic_orbit(s, omega, Eigen::VectorXd(), {}, detail::ElasticRoute::differences);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK_THAT(orbit.message, Catch::Contains("central differences"));
    CHECK(orbit.multiplier_accuracy == difference_multiplier_accuracy);
    // Each multiplier by differences against the closed form's nearest (the flow's own
    // derivative matches exp(lambda T) to 1e-7, previous test): the stated accuracy holds.
    REQUIRE(orbit.multipliers.size() == own.multipliers.size());
    double worst = 0.0;
    for (Eigen::Index k = 0; k < orbit.multipliers.size(); ++k)
        worst = std::max(worst, (own.multipliers.array() - orbit.multipliers(k)).abs().minCoeff());
    INFO("largest gap to the flow's own multipliers " << worst << ", largest |mu| " << orbit.max_multiplier);
    CHECK(worst <= orbit.multiplier_accuracy);
    CHECK(std::abs(orbit.max_multiplier - 1.0) <= orbit.multiplier_accuracy);  // the held slider's 1
    CHECK((orbit.stable || orbit.stability_unresolved()));
    // The verdict's band: above 1 + stability_tolerance, within the accuracy of 1 is uncertain;
    // beyond it, unstable; the summary line says which.
    ExactOrbit near = orbit, beyond = orbit;
    near.max_multiplier = 1.0 + 0.5 * difference_multiplier_accuracy;
    near.stable = false;
    beyond.max_multiplier = 1.0 + 2.0 * difference_multiplier_accuracy;
    beyond.stable = false;
    CHECK(near.stability_unresolved());
    CHECK_THAT(near.summary(), Catch::Contains("stability uncertain"));
    CHECK(!beyond.stability_unresolved());
    CHECK_THAT(beyond.summary(), Catch::Contains("unstable"));
    ExactOrbit exact_route = beyond;  // the flow's own multipliers: 1 + stability_tolerance decides
    exact_route.max_multiplier = near.max_multiplier;
    exact_route.multiplier_accuracy = 0.0;
    CHECK(!exact_route.stability_unresolved());
}

TEST_CASE("elastic exact: an unstable orbit (liftoff3.toml at w = 2.2, where time integration settles nowhere): a "
          "perturbation grows by the largest multiplier each period",
          "[elastic_exact]") {
    const System s = liftoff3();
    const double omega = 2.2;
    const ExactOrbit orbit = orbit_from_rest(s, omega);
    INFO(orbit.message);
    CHECK(!orbit.stable);
    TimeIntegrationOptions flow;
    flow.relative_tolerance = flow.absolute_tolerance = 1e-12;
    detail::ElasticIntegrator plain(s, omega, flow, response_scale(s, omega));
    const int k = plain.continuous(), n = s.dofs();
    const double size = orbit.state.head(n).cwiseAbs().maxCoeff();
    Eigen::VectorXd x = orbit.state;
    x.head(k) += 1e-9 * size * Eigen::VectorXd::LinSpaced(k, 1.0, -0.5);
    plain.settle(x);
    std::vector<double> gaps;
    for (int p = 0; p < 40; ++p) {
        const detail::ElasticIntegrator::Record r = plain.period(x, 0);
        REQUIRE(r.ok);
        x = r.end;
        gaps.push_back((x.head(2 * n) - orbit.state.head(2 * n)).cwiseAbs().maxCoeff() / size);
    }
    const double rate = std::pow(gaps[39] / gaps[19], 1.0 / 20.0);
    INFO("growth per period " << rate << ", largest multiplier " << orbit.max_multiplier << ", gap after 40 periods "
                              << gaps[39]);
    CHECK(gaps[39] <= 1e-5);  // still a perturbation
    CHECK(rate == Approx(orbit.max_multiplier).epsilon(1e-3));
}

TEST_CASE("elastic exact: Newton-Krylov on a 67-state chain equals the full matrix's route", "[elastic_exact]") {
    // 33 DOFs and one contact: 67 continuous states, beyond the variational equation's size.
    const System s = hbf::test::elastic_chain(33);
    REQUIRE(elastic_continuous_states(s) == 67);
    const double omega = 0.6;
    const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration(), nullptr);
    INFO(ti.message);
    REQUIRE(ti.converged);
    REQUIRE(ti.contacts[0].stick_fraction < 0.9);  // stick, slip and lift-off: events in the period
    REQUIRE(ti.contacts[0].separated_fraction > 0.1);
    const ExactOrbit krylov = elastic_periodic_orbit(s, omega, ti.state);
    const ExactOrbit full = detail::elastic_orbit(s, omega, ti.state, {}, detail::ElasticRoute::differences);
    INFO(krylov.message << " | " << full.message);
    REQUIRE(krylov.converged);
    REQUIRE(full.converged);
    CHECK_THAT(krylov.message, Catch::Contains("Newton-Krylov"));
    for (std::size_t i : {std::size_t{0}, std::size_t{32}}) CHECK(krylov.y_max[i] == Approx(ti.y_max[i]).epsilon(1e-8));
    CHECK(krylov.contacts[0].stick_fraction == Approx(ti.contacts[0].stick_fraction).margin(1e-8));
    // Each multiplier Arnoldi returns is one of the full matrix's (to the differences' accuracy),
    // the largest among them.
    REQUIRE(krylov.multipliers.size() >= 1);
    for (Eigen::Index i = 0; i < krylov.multipliers.size(); ++i) {
        const double nearest = (full.multipliers.array() - krylov.multipliers(i)).abs().minCoeff();
        CHECK(nearest <= 1e-4 * std::max(1.0, std::abs(krylov.multipliers(i))));
    }
    CHECK(krylov.max_multiplier == Approx(full.max_multiplier).margin(1e-4));
    CHECK(krylov.stable == full.stable);
    // fewer periods than the matrix's 2 c + 1 per Newton iteration and for the multipliers
    CHECK(krylov.periods < full.periods);
}

TEST_CASE("elastic exact: bad input is refused naming the cause", "[elastic_exact]") {
    const System s = liftoff3();
    CHECK_THROWS_WITH(elastic_periodic_orbit(s, 0.0, Eigen::VectorXd()), Catch::Contains("omega = 0"));
    CHECK_THROWS_WITH(elastic_periodic_orbit(s, 1.0, Eigen::VectorXd::Zero(3)), Catch::Contains("initial state has 3"));
    System mixed = s;
    mixed.contacts[0].law = FrictionLaw::jenkins;
    CHECK(elastic_solver_refusal(mixed).find("all of law elastic") != std::string::npos);
    CHECK_THROWS_AS(elastic_periodic_orbit(mixed, 1.0, Eigen::VectorXd()), InvalidInput);
}

TEST_CASE("law elastic from the command line: the exact sweep equals the integrator where it settles, and the band "
          "where it settles nowhere is unstable",
          "[elastic_exact][cli]") {
    ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml";
    const std::string grid = " --wmin 1.9 --wmax 2.4 --points 6";
    const auto exact_csv = dir.path / "exact.csv", ti_csv = dir.path / "ti.csv";
    const ::test::Result exact =
        ::test::run_hbf("timeint --config '" + example + "' --method exact" + grid + " --out '" + exact_csv.string() + "'", dir);
    INFO(exact.err);
    REQUIRE(exact.exit_code == 0);
    CHECK(exact.err.find("2 of 6 exact orbits are unstable") != std::string::npos);
    const ::test::Result ti =
        ::test::run_hbf("timeint --config '" + example + "'" + grid + " --out '" + ti_csv.string() + "'", dir);
    INFO(ti.err);
    CHECK(ti.exit_code == 1);  // no steady state at 2.2 and 2.3
    const auto e = ::test::parse_csv(::test::slurp(exact_csv)), t = ::test::parse_csv(::test::slurp(ti_csv));
    REQUIRE(e.size() == 7);
    REQUIRE(t.size() == 7);
    int compared = 0;
    for (std::size_t k = 1; k < e.size(); ++k) {
        const double w = std::stod(e[k][0]);
        INFO("w = " << w);
        const auto at = static_cast<std::size_t>(std::find(t.front().begin(), t.front().end(), "converged") - t.front().begin());
        REQUIRE(at < t.front().size());
        CHECK(e[k][at] == "true");  // the same columns
        const bool settled = t[k][at] == "true";
        CHECK(settled == !(w > 2.15 && w < 2.35));
        if (!settled) continue;
        for (const char* name : {"y1_max", "y2_max", "y1_amp1", "y2_amp1", "stick_fraction", "separated_fraction"})
            CHECK(::test::column(e, e[k], name) == Approx(::test::column(t, t[k], name)).epsilon(1e-6).margin(1e-9));
        ++compared;
    }
    CHECK(compared == 4);

    const auto summary = dir.path / "frf.json";
    const ::test::Result frf = ::test::run_hbf("frf --config '" + example + "' --wmin 2.0 --wmax 2.5 --stability on --out '" +
                                                   (dir.path / "frf.csv").string() + "' --summary '" + summary.string() + "'",
                                               dir);
    INFO(frf.err);
    REQUIRE(frf.exit_code == 0);
    const nlohmann::json stability = nlohmann::json::parse(::test::slurp(summary))["stability"];
    // unstable between two period doublings near 2.19 and 2.31 (a multiplier through -1)
    REQUIRE(stability["unstable_intervals"].size() == 1);
    const double from = stability["unstable_intervals"][0]["w_from"], to = stability["unstable_intervals"][0]["w_to"];
    CHECK(from > 2.15);
    CHECK(from < 2.25);
    CHECK(to > 2.3);
    CHECK(to < 2.35);
    REQUIRE(stability["bifurcations"].size() == 2);
    for (const auto& b : stability["bifurcations"]) CHECK(b["kind"] == "period-doubling");
    CHECK(stability["bifurcations"][0]["w"].get<double>() == Approx(2.19).margin(0.03));
    CHECK(stability["bifurcations"][1]["w"].get<double>() == Approx(2.31).margin(0.03));
    CHECK(stability["uncertain"] == 0);
}
