// Rigid unilateral contact with Coulomb friction on massless coordinates (law `unilateral`,
// issue 31) by the dynamic Lagrangian: a massless node tied by springs k_t, k_n to a structure
// and touching a rigid obstacle is law elastic's element (src/contact/unilateral.cpp), so every
// check here has an independent reference: law elastic's harmonic balance and time integration
// on the structure without the node, and the law's own time integrator (a complementarity
// solve per step).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/modes.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/static_state.hpp"
#include "hbf/time_integration.hpp"
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "contact/massless_contacts.hpp"
#include "hbf/normal_contact.hpp"
#include "backbone_support.hpp"
#include "nodes_model.hpp"
#include "support.hpp"

using namespace hbf;
using hbf::test::nodes_model;

namespace {

const FrictionLaw unilateral = parse_friction_law("unilateral");

System liftoff3() {
    return io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
}

PointMetrics solve(HarmonicBalance& hb, double omega, SolutionPoint& p, const Eigen::VectorXd& start = {},
                   double tolerance = 1e-9) {
    CorrectorOptions options;
    options.max_iterations = 100;
    options.tolerance = tolerance;
    Corrector corrector(hb, options);
    p.x = start.size() > 0 ? start : hb.linear_guess(omega);
    p.omega = omega;
    INFO("solve at w = " << omega);
    REQUIRE(corrector.solve_at(p.x, omega, hb.unknown_scale(p.x), p.iterations, p.residual));
    return Analyser(hb, {0})(p);
}

/// The largest difference of the first harmonics of the first `dofs` DOFs of two
/// harmonic-balance points, relative to the largest of b's.
double first_harmonic_gap(HarmonicBalance& a, const SolutionPoint& pa, HarmonicBalance& b, const SolutionPoint& pb,
                          int dofs) {
    const Eigen::MatrixXd ya = a.dofs(pa.x, pa.omega), yb = b.dofs(pb.x, pb.omega);
    double worst = 0, size = 0;
    for (int i = 0; i < dofs; ++i) {
        worst = std::max(worst, std::hypot(ya(1, i) - yb(1, i), ya(2, i) - yb(2, i)));
        size = std::max(size, std::hypot(yb(1, i), yb(2, i)));
    }
    return worst / size;
}

/// Harmonic balance's unknowns (condensed) of the node model `hb` from law elastic's point p
/// of `elastic` (H harmonics or more): the nodes where the element's slider and normal spring put
/// them, u - T / k_t and v + (N_0 - N) / k_n, and the multipliers lambda = (T, N), projected on
/// hb's harmonics. A start for the corrector, which then solves the node model itself.
Eigen::VectorXd from_elastic(HarmonicBalance& hb, HarmonicBalance& elastic, const SolutionPoint& p, const Contact& c) {
    const int ne = elastic.coefficients(), n = hb.coefficients(), nt = elastic.time_samples();
    const Eigen::VectorXd q = elastic.relative(p.x, 0), f = elastic.force_samples(p.x, p.omega, 0);
    const int signals = static_cast<int>(q.size()) / ne, d = signals - 1;
    Fourier fe(elastic.harmonics(), nt), fu(hb.harmonics(), nt);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(hb.unknowns()), samples(nt), coefficients(n);
    const double preload = c.values.count("preload") ? c.values.at("preload") : 0.0;
    for (int a = 0; a < signals; ++a) {
        fe.to_time(q.segment(a * ne, ne), samples);
        const Eigen::VectorXd force = f.segment(a * nt, nt);
        const Eigen::VectorXd node = a < d ? Eigen::VectorXd(samples - force / c.stiffness)
                                           : Eigen::VectorXd((samples.array() + (preload - force.array()) /
                                                                                    c.values.at("normal_stiffness")).matrix());
        fu.to_coefficients(node, coefficients);
        x.segment(a * n, n) = coefficients;
        fu.to_coefficients(force, coefficients);
        x.segment((signals + a) * n, n) = coefficients;
    }
    return x;
}

}  // namespace

TEST_CASE("unilateral contact: a massless node on springs is law elastic's element: harmonic balance converges in "
          "H to law elastic's and to its own time integration (liftoff3.toml in stick, stick-slip and lift-off)",
          "[unilateral_contact][time_integration]") {
    const System elastic = liftoff3();
    const System nodes = nodes_model(elastic);
    // measured, relative first-harmonic gaps of the three masses to law elastic's point (H = 40,
    // itself 2e-7 from its time integration) at H = 5, 10, 20, 40: stick 6e-14 at every H;
    // stick-slip 3.6e-2, 1.6e-2, 5.7e-3, 1.9e-3; lift-off 8.6e-3, 8.3e-3, 4.5e-3, 1.8e-3 (the
    // dynamic Lagrangian of a rigid contact converges about like 1/H, as for law coulomb)
    struct Case {
        double omega;
        std::string regime;
        double bound_h40;
    };
    for (const Case& c : {Case{0.8, "stick", 1e-9}, Case{1.2, "stick-slip", 3e-3}, Case{2.8, "lift-off", 3e-3}}) {
        INFO(c.regime << " at w = " << c.omega);
        const Eigen::VectorXd rest = linear_stuck_state(elastic, c.omega);
        const PeriodicResponse te = integrate_steady_state(elastic, c.omega, hbf::test::tight_time_integration(), &rest);
        REQUIRE(te.converged);
        HarmonicBalance reference(elastic, HarmonicBalanceOptions{40, 0, Formulation::condensed});
        SolutionPoint pr;
        const PointMetrics mr =
            solve(reference, c.omega, pr, hbf::test::from_orbit(reference, te, elastic.contact_directions(elastic.contacts[0])));
        TimeIntegrationOptions options;
        options.steady_tolerance = 1e-10;
        const PeriodicResponse tu = integrate_steady_state(nodes, c.omega, options);
        INFO(tu.message);
        REQUIRE(tu.converged);
        std::vector<double> errors, to_time;
        for (int harmonics : {5, 10, 20, 40}) {
            HarmonicBalance hb(nodes, HarmonicBalanceOptions{harmonics, 0, Formulation::condensed});
            SolutionPoint p;
            const PointMetrics m = solve(hb, c.omega, p, from_elastic(hb, reference, pr, elastic.contacts[0]));
            errors.push_back(first_harmonic_gap(hb, p, reference, pr, elastic.dofs()));
            const Eigen::MatrixXd y = hb.dofs(p.x, c.omega);
            double gap = 0;
            for (int i = 0; i < elastic.dofs(); ++i)
                gap = std::max(gap, std::abs(std::complex<double>(y(1, i), -y(2, i)) - tu.harmonic1(i)));
            to_time.push_back(gap / tu.harmonic1.head(elastic.dofs()).cwiseAbs().maxCoeff());
            CHECK(m.regime == mr.regime);
            CHECK(std::abs(m.contacts[0].separated_fraction - mr.contacts[0].separated_fraction) <= 0.02);
            CHECK(m.energy_error <= 1e-8);  // input work = viscous + friction dissipation
            CHECK(m.contacts[0].normal_mean == Approx(mr.contacts[0].normal_mean).epsilon(0.02));
        }
        INFO("H = 5, 10, 20, 40: against law elastic " << errors[0] << ", " << errors[1] << ", " << errors[2] << ", "
                                                       << errors[3] << "; against time integration " << to_time[0]
                                                       << ", " << to_time[1] << ", " << to_time[2] << ", " << to_time[3]);
        CHECK(errors[3] <= c.bound_h40);
        CHECK(to_time[3] <= c.bound_h40 + 1e-5);
        if (c.regime != "stick") {
            CHECK(errors[3] < errors[0] / 3);
            CHECK(to_time[3] < to_time[0] / 3);
        }
        CHECK(tu.regime == te.regime);
    }
}

TEST_CASE("unilateral contact, time integration: the complementarity solve per step converges at second order to law "
          "elastic's event-driven integration (stick, stick-slip, lift-off), with the energy balance",
          "[unilateral_contact][time_integration]") {
    const System elastic = liftoff3();
    const System nodes = nodes_model(elastic);
    // measured gaps (first harmonics of the masses, relative) at 2048, 4096, 8192 steps per
    // period: stick-slip 7.4e-6, 1.9e-6, 4.7e-7; lift-off 3.7e-6, 1.1e-6, 2.7e-7 (the closing
    // instant interpolated within its step; held at the step's start it was first order and
    // irregular, 4.4e-5, 4.1e-5, 4.1e-5, then 8.5e-6 at 32768)
    for (double omega : {0.8, 1.2, 2.8}) {
        const Eigen::VectorXd rest = linear_stuck_state(elastic, omega);
        const PeriodicResponse te = integrate_steady_state(elastic, omega, hbf::test::tight_time_integration(), &rest);
        REQUIRE(te.converged);
        std::vector<double> gaps;
        for (int samples : {128, 256, 512}) {
            TimeIntegrationOptions options;
            options.steady_tolerance = 1e-11;
            options.samples_per_period = samples;
            const PeriodicResponse tu = integrate_steady_state(nodes, omega, options);
            INFO("w = " << omega << ", " << samples << " samples: " << tu.message);
            REQUIRE(tu.converged);
            CHECK(tu.steps % samples == 0);
            CHECK(tu.regime == te.regime);
            CHECK(std::abs(tu.contacts[0].separated_fraction - te.contacts[0].separated_fraction) <= 2.0 / (16 * samples));
            CHECK(tu.energy_error <= 1e-6);
            CHECK(tu.state.size() == 2 * nodes.dofs());
            double gap = 0;
            for (int i = 0; i < elastic.dofs(); ++i) gap = std::max(gap, std::abs(tu.harmonic1(i) - te.harmonic1(i)));
            gaps.push_back(gap / te.harmonic1.cwiseAbs().maxCoeff());
        }
        INFO("w = " << omega << ": " << gaps[0] << ", " << gaps[1] << ", " << gaps[2]);
        if (te.regime == "stick") {
            CHECK(gaps[2] <= 1e-6);
        } else {
            CHECK(gaps[2] <= 1e-6);
            CHECK(gaps[1] / gaps[2] > 3.0);  // second order: 4 per halving of the step
            CHECK(gaps[0] / gaps[1] > 3.0);
        }
    }
}

TEST_CASE("unilateral contact: the exact Jacobians of both formulations against central differences, 2D and 3D, "
          "through stick, slip and separation, and in permanent stick",
          "[unilateral_contact]") {
    // Two masses (y1 tangential, y2 normal; y3 a second tangential mass in 3D) tied to massless
    // nodes of law elastic's springs (nodes_model).
    for (int directions : {1, 2}) {
        const int dofs = directions + 1;
        System base;
        const Eigen::VectorXd masses = Eigen::Vector3d(1.0, 0.7, 0.5).head(dofs);
        const Eigen::VectorXd springs = Eigen::Vector3d(3.0, 2.5, 2.0).head(dofs);
        base.mass = sparse(Eigen::MatrixXd(masses.asDiagonal()));
        base.stiffness = sparse(Eigen::MatrixXd(springs.asDiagonal()));
        base.damping = sparse(Eigen::MatrixXd(0.02 * springs.asDiagonal()));
        base.excitation = Eigen::VectorXd::Constant(dofs, 0.5);
        Contact c;
        c.law = parse_friction_law("elastic");
        c.dof = 0;
        c.stiffness = 2.0;
        c.values["normal_stiffness"] = 4.0;
        c.values["friction_coefficient"] = 0.4;
        c.values["preload"] = 0.3;
        c.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(dofs), 0.0);
        c.lists["normal_direction"][1] = 1.0;
        if (directions == 2) c.lists["second_direction"] = {0.0, 0.0, 1.0};
        base.contacts.push_back(c);
        const System s = nodes_model(base);
        for (Formulation formulation : {Formulation::condensed, Formulation::full}) {
            for (bool permanent : {false, true}) {
                HarmonicBalance hb(s, HarmonicBalanceOptions{4, 64, formulation});
                const int n = hb.coefficients();
                Eigen::VectorXd x = Eigen::VectorXd::Zero(hb.unknowns());
                for (int signal = 0; signal < hb.unknowns() / n; ++signal) {
                    const double a = permanent ? 0.01 : 0.3;
                    x(signal * n + 1) = a * std::cos(1.0 + signal);
                    x(signal * n + 2) = a * std::sin(2.0 + signal);
                    x(signal * n + 3) = 0.1 * a * (signal + 1);
                    x(signal * n) = 0.05 * signal;
                }
                // the normal force's mean: closed throughout in permanent stick, else half the time
                const int normal = (hb.unknowns() / n - 1) * n;
                x(normal) = permanent ? 1.0 : 0.1;
                Eigen::VectorXd r, r_omega, fd_omega;
                Eigen::MatrixXd j, fd;
                hb.evaluate(x, 1.3, r, &j, &r_omega);
                hbf::test::central_differences(hb, x, 1.3, fd, fd_omega, 1e-7);
                INFO(directions << " tangential direction(s), " << to_string(formulation)
                                << (permanent ? ", permanent stick" : ""));
                const double scale = j.cwiseAbs().maxCoeff();
                CHECK((j - fd).cwiseAbs().maxCoeff() <= 1e-6 * scale);
                CHECK((r_omega - fd_omega).cwiseAbs().maxCoeff() <= 1e-6 * std::max(1.0, r_omega.cwiseAbs().maxCoeff()));
                const Eigen::VectorXd phi = hb.stick_indicator(x, 1.3, 0);
                if (permanent) {
                    CHECK(phi.maxCoeff() < 0.0);  // every sample stuck
                } else {
                    CHECK(phi.maxCoeff() == 1.0);             // separated
                    CHECK((phi.array() == 0.0).count() > 0);  // slipping
                    CHECK((phi.array() < 0.0).count() > 0);   // stuck
                }
            }
        }
    }
}

namespace {

/// The anisotropic 3D structure of test_elastic_contact.cpp (y1, y2 tangential, y3 normal)
/// whose contact slides on an elliptic orbit, as law elastic.
/// Law elastic's 3D element on y1, y2 (tangential) and y3 (normal).
Contact elastic_3d(double kt, double kn, double mu, double preload) {
    Contact c;
    c.law = parse_friction_law("elastic");
    c.dof = 0;
    c.stiffness = kt;
    c.values["normal_stiffness"] = kn;
    c.values["friction_coefficient"] = mu;
    c.values["preload"] = preload;
    c.lists["second_direction"] = {0.0, 1.0, 0.0};
    c.lists["normal_direction"] = {0.0, 0.0, 1.0};
    return c;
}

System anisotropic_3d() {
    System s;
    s.mass = sparse(Eigen::MatrixXd(Eigen::Vector3d(1.0, 1.2, 0.8).asDiagonal()));
    s.damping = sparse(Eigen::MatrixXd(0.02 * Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal()));
    s.stiffness = sparse(Eigen::MatrixXd(Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal()));
    s.excitation = Eigen::Vector3d(0.6, 0.5, 0.1);
    s.contacts.push_back(elastic_3d(1.5, 4.0, 0.3, 1.0));
    return s;
}

/// The unknowns x of a contact's two tangential signals (and multipliers) turned by `angle`
/// in their plane: the start of the rotated contact.
Eigen::VectorXd rotate_tangential(const Eigen::VectorXd& x, int n, double angle) {
    Eigen::VectorXd out = x;
    for (int first : {0, 3}) {  // the relative displacements (signals 0, 1), the multipliers (3, 4)
        const Eigen::VectorXd a = x.segment(first * n, n), b = x.segment((first + 1) * n, n);
        out.segment(first * n, n) = std::cos(angle) * a + std::sin(angle) * b;
        out.segment((first + 1) * n, n) = -std::sin(angle) * a + std::cos(angle) * b;
    }
    return out;
}

}  // namespace

TEST_CASE("unilateral contact 3D: rotating the tangential directions leaves the response unchanged (1e-10), "
          "circular sliding dissipates the closed-form energy, and harmonic balance converges to time integration",
          "[unilateral_contact][time_integration]") {
    const System elastic = anisotropic_3d();
    const System nodes = nodes_model(elastic);
    const double angle = 0.7;
    System rotated = nodes;
    Contact& turned = rotated.contacts[0];
    turned.direction = Eigen::VectorXd::Zero(nodes.dofs());
    turned.direction(3) = std::cos(angle);
    turned.direction(4) = std::sin(angle);
    turned.lists["second_direction"] = std::vector<double>(static_cast<std::size_t>(nodes.dofs()), 0.0);
    turned.lists["second_direction"][3] = -std::sin(angle);
    turned.lists["second_direction"][4] = std::cos(angle);
    for (double omega : {0.9, 1.1, 1.3}) {
        HarmonicBalance reference(elastic, HarmonicBalanceOptions{8, 0, Formulation::condensed});
        SolutionPoint pr;
        solve(reference, omega, pr);
        HarmonicBalance a(nodes, HarmonicBalanceOptions{8, 0, Formulation::condensed}),
            b(rotated, HarmonicBalanceOptions{8, 0, Formulation::condensed});
        SolutionPoint pa, pb;
        const Eigen::VectorXd start = from_elastic(a, reference, pr, elastic.contacts[0]);
        const PointMetrics ma = solve(a, omega, pa, start);
        const PointMetrics mb = solve(b, omega, pb, rotate_tangential(pa.x, a.coefficients(), angle));
        const Eigen::MatrixXd ya = a.dofs(pa.x, omega), yb = b.dofs(pb.x, omega);
        INFO("w = " << omega << ": stick " << ma.contacts[0].stick_fraction << ", open "
                    << ma.contacts[0].separated_fraction << ", energy " << ma.energy);
        CHECK((ya - yb).cwiseAbs().maxCoeff() <= 1e-10 * ya.cwiseAbs().maxCoeff());
        CHECK(std::abs(ma.energy - mb.energy) <= 1e-10 * std::abs(ma.energy));
        CHECK(std::abs(ma.contacts[0].stick_fraction - mb.contacts[0].stick_fraction) <= 1e-12);
        CHECK(ma.energy > 0.0);
        CHECK(ma.energy_error <= 1e-8);
    }
    // Circular motion u = a (cos, sin) at a constant N_0 (drivers as in test_elastic_contact.cpp:
    // y1 on a stiff spring kappa, y2 at its own resonance behind a large damper, y3 held): the
    // node circles at radius sqrt(a^2 - (mu N_0 / k_t)^2) with T (|T| = mu N_0) along its
    // velocity, dissipating 2 pi mu N_0 sqrt(a^2 - (mu N_0 / k_t)^2) per cycle. Every signal is
    // a single harmonic: the dynamic Lagrangian is exact at any H, to the drivers' 1e-6 (kappa
    // 1e6: the corrector's acceptance is relative to the excitation, here kappa a, so that the
    // multipliers' rows, of the size mu N_0, are solved to 1e-14 kappa a; at kappa = 1e9 and the
    // default 1e-9 they were not, and the energy erred by 2e-2).
    const double kt = 2.0, mu = 0.4, n0 = 1.0, radius = 0.5, kappa = 1e6, omega = 1.0;
    const double exact = 2 * M_PI * mu * n0 * std::sqrt(radius * radius - std::pow(mu * n0 / kt, 2));
    System turning = anisotropic_3d();
    turning.mass = sparse(Eigen::MatrixXd(Eigen::Matrix3d::Identity()));
    turning.damping = sparse(Eigen::MatrixXd(Eigen::Vector3d(0.0, kappa, 0.0).asDiagonal()));
    turning.stiffness = sparse(Eigen::MatrixXd(Eigen::Vector3d(kappa, omega * omega, kappa).asDiagonal()));
    turning.excitation = Eigen::Vector3d((kappa - omega * omega) * radius, omega * kappa * radius, 0.0);
    turning.contacts[0].stiffness = kt;
    turning.contacts[0].values["friction_coefficient"] = mu;
    turning.contacts[0].values["preload"] = n0;
    const System circle = nodes_model(turning);
    for (int harmonics : {3, 10}) {
        HarmonicBalance reference(turning, HarmonicBalanceOptions{harmonics, 0, Formulation::condensed});
        SolutionPoint pr;
        solve(reference, omega, pr);
        HarmonicBalance hb(circle, HarmonicBalanceOptions{harmonics, 0, Formulation::condensed});
        SolutionPoint p;
        const PointMetrics m = solve(hb, omega, p, from_elastic(hb, reference, pr, turning.contacts[0]), 1e-14);
        INFO("H = " << harmonics << ": W = " << m.energy << " against " << exact);

        CHECK(m.contacts[0].stick_fraction == 0.0);
        CHECK(m.contacts[0].separated_fraction == 0.0);
        CHECK(m.energy == Approx(exact).epsilon(1e-5));
    }
    // Harmonic balance against the law's time integration on the elliptic orbit at w = 1.1. In
    // 3D the per-step Coulomb law slides along the force at the step's end: first order where
    // the slip direction turns (measured against H = 40: 2.7e-4 at 2048 steps per period,
    // 1.3e-4 at 4096), while harmonic balance has converged in H by H = 20 (sliding throughout:
    // the same gaps at H = 20 and 40 to 1e-7; 1.4e-3, 3.5e-4 at H = 5, 10).
    HarmonicBalance reference(elastic, HarmonicBalanceOptions{8, 0, Formulation::condensed});
    SolutionPoint pr;
    solve(reference, 1.1, pr);
    std::vector<SolutionPoint> points;
    std::vector<std::unique_ptr<HarmonicBalance>> balances;
    for (int harmonics : {5, 20, 40}) {
        balances.push_back(std::make_unique<HarmonicBalance>(nodes, HarmonicBalanceOptions{harmonics, 0, Formulation::condensed}));
        points.emplace_back();
        const PointMetrics m = solve(*balances.back(), 1.1, points.back(), from_elastic(*balances.back(), reference, pr, elastic.contacts[0]));
        CHECK(m.regime == "slip");
        CHECK(m.energy_error <= 1e-8);
    }
    std::vector<std::vector<double>> gaps;  // [steps][H]
    for (int samples : {128, 256}) {
        TimeIntegrationOptions options;
        options.steady_tolerance = 1e-10;
        options.samples_per_period = samples;
        const PeriodicResponse tu = integrate_steady_state(nodes, 1.1, options);
        INFO(tu.message);
        REQUIRE(tu.converged);
        CHECK(tu.regime == "slip");
        CHECK(tu.energy_error <= 1e-6);
        gaps.emplace_back();
        for (std::size_t k = 0; k < points.size(); ++k) {
            const Eigen::MatrixXd y = balances[k]->dofs(points[k].x, 1.1);
            double gap = 0;
            for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(std::complex<double>(y(1, i), -y(2, i)) - tu.harmonic1(i)));
            gaps.back().push_back(gap / tu.harmonic1.head(3).cwiseAbs().maxCoeff());
        }
    }
    INFO("H = 5, 20, 40 against 2048 steps: " << gaps[0][0] << ", " << gaps[0][1] << ", " << gaps[0][2]
                                            << "; against 4096: " << gaps[1][0] << ", " << gaps[1][1] << ", " << gaps[1][2]);
    CHECK(std::abs(gaps[1][1] - gaps[1][2]) <= 1e-6);     // converged in H
    CHECK(gaps[0][2] / gaps[1][2] == Approx(2.0).epsilon(0.15));  // first order in the step
    CHECK(gaps[1][2] <= 2e-4);
    CHECK(gaps[1][0] > 5 * gaps[1][2]);  // H = 5 is not converged
}

TEST_CASE("unilateral contact from a system file: examples/systems/liftoff3_rigid.toml passes through stick, "
          "stick-slip and lift-off in hbf frf and hbf timeint, and bad keys, directions and models exit 2",
          "[unilateral_contact][cli]") {
    const ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";
    const ::test::fs::path out = dir.path / "frf.csv", summary = dir.path / "frf.json";
    const ::test::Result r = ::test::run_hbf(
        "frf --config '" + example + "' --out '" + out.string() + "' --summary '" + summary.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json json = nlohmann::json::parse(::test::slurp(summary));
    CHECK(json.at("status") == "completed");
    const nlohmann::json contacts = json.at("contacts");
    REQUIRE(contacts.size() == 1);
    CHECK(contacts[0].at("stick_fraction_max").get<double>() == 1.0);
    CHECK(contacts[0].at("separated_fraction_max").get<double>() > 0.5);
    CHECK(contacts[0].at("open_from_w").get<double>() > 2.0);
    const auto rows = ::test::parse_csv(::test::slurp(out));
    REQUIRE(rows.size() > 100);
    bool stick = false, slip = false, open = false;
    double worst = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double stuck = ::test::column(rows, rows[k], "stick_fraction");
        stick = stick || stuck == 1.0;
        slip = slip || (stuck > 0.0 && stuck < 1.0);
        open = open || ::test::column(rows, rows[k], "separated_fraction") > 0.0;
        worst = std::max(worst, ::test::column(rows, rows[k], "energy_error"));
        CHECK(::test::column(rows, rows[k], "normal_force_mean") > 0.0);
    }
    CHECK(stick);
    CHECK(slip);
    CHECK(open);
    CHECK(worst <= 1e-8);  // input work = viscous + friction dissipation on every point
    // the law's time integration from the command line, in lift-off
    const ::test::fs::path integrated = dir.path / "timeint.csv";
    const ::test::Result t = ::test::run_hbf("timeint --config '" + example + "' --w 2.8 --out '" + integrated.string() + "'", dir);
    INFO(t.err);
    REQUIRE(t.exit_code == 0);
    const auto ti = ::test::parse_csv(::test::slurp(integrated));
    REQUIRE(ti.size() == 2);
    CHECK(::test::column(ti, ti[1], "separated_fraction") == Approx(0.596).margin(0.002));  // law elastic: 0.5963

    const std::string head = "[structure]\nmass = [1.0, 0.0, 0.0]\nstiffness = [[3.0, -1.0, 0.0], [-1.0, 1.0, 0.0], "
                             "[0.0, 0.0, 1.0]]\nexcitation = [1.0, 0.0, 0.0]\nstatic_load = [0.0, 0.0, 1.0]\n"
                             "[[contact]]\ndof = 2\nlaw = \"unilateral\"\n";
    const std::string normal = "normal_direction = [0.0, 0.0, 1.0]\n";
    ::test::check_bad_config(head + normal, {"contact[1]", "friction_coefficient", "missing"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\n", {"normal_direction", "missing"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = -0.3\n" + normal, {"contact[1]", "friction_coefficient", ">= 0"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\ngap = -1.0\n" + normal, {"contact[1]", "gap", ">= 0"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\nstiffness = 2.0\n" + normal,
                             {"contact[1].stiffness", "does not apply to law 'unilateral'"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\nnormal_direction = [0.0, 0.6, 0.8]\n",
                             {"contact[1]", "normal_direction", "not orthogonal"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\nnormal_direction = [0.0, 1.0, 1.0]\n",
                             {"contact[1].normal_direction", "has length 1.414", "allowed a unit vector"}, dir);
    ::test::check_bad_config(head + "friction_coefficient = 0.3\nnormal_direction = [0.0, 0.0, 1.0, 0.0]\n",
                             {"contact[1].normal_direction", "4 entries", "allowed 3"}, dir);
    // a rigid contact on a coordinate with mass: refused (it would impact)
    const std::string massive = "[structure]\nmass = [1.0, 1.0]\nstiffness = [[2.0, 0.0], [0.0, 2.0]]\n"
                                "excitation = [1.0, 0.0]\n[[contact]]\ndof = 1\nlaw = \"unilateral\"\n"
                                "friction_coefficient = 0.3\nnormal_direction = [0.0, 1.0]\n";
    ::test::check_bad_config(massive, {"contact 1", "carries mass", "massless contact coordinates"}, dir);
    // --stability: the exact orbits' verdicts (tests/test_stability.cpp checks them against the
    // integrator): between w = 2.2 and 2.7 unstable intervals, written and summarised
    const ::test::fs::path table = dir.path / "stability.csv", stability = dir.path / "stability.json";
    const ::test::Result st = ::test::run_hbf("frf --config '" + example + "' --stability on --wmin 2.2 --wmax 2.7 --out '" +
                                                  table.string() + "' --summary '" + stability.string() + "'",
                                              dir);
    INFO(st.err);
    REQUIRE(st.exit_code == 0);
    const nlohmann::json verdicts = nlohmann::json::parse(::test::slurp(stability)).at("stability");
    CHECK(verdicts.at("unstable").get<int>() > 10);
    CHECK(verdicts.at("stable").get<int>() > 10);
    CHECK(verdicts.at("uncertain").get<int>() == 0);
    CHECK(verdicts.at("unstable_intervals").size() >= 1);
    const auto stability_rows = ::test::parse_csv(::test::slurp(table));
    const auto column = std::find(stability_rows[0].begin(), stability_rows[0].end(), "stable") - stability_rows[0].begin();
    int unstable_rows = 0;
    for (std::size_t k = 1; k < stability_rows.size(); ++k) unstable_rows += stability_rows[k][static_cast<std::size_t>(column)] == "false";
    CHECK(unstable_rows == verdicts.at("unstable").get<int>());
    // stability comes from the exact solver: refused where that solver refuses the model
    std::string second = ::test::slurp(example);
    second.replace(second.find("excitation ="), 0, "excitation_harmonic = 2\n");
    const ::test::fs::path harmonic = dir.path / "harmonic2.toml";
    ::test::write_file(harmonic, second);
    ::test::check_bad_input("frf --config '" + harmonic.string() + "' --stability on",
                            {"stability of law unilateral", "excitation_harmonic = 2", "allowed 1"}, dir);
    ::test::check_bad_input("frf --law unilateral", {"law = unilateral has no preset"}, dir);
    // time integration: a damped massless node is refused, naming it
    const std::string damped = head + "friction_coefficient = 0.3\n" + normal +
                               "";  // (damping below, in [structure])
    const ::test::fs::path file = dir.path / "damped.toml";
    std::string text = damped;
    text.replace(text.find("excitation"), 0, "damping = [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.0]]\n");
    ::test::write_file(file, text);
    const ::test::Result d = ::test::run_hbf("timeint --config '" + file.string() + "' --w 1.0", dir);
    CHECK(d.exit_code == 2);
    CHECK_THAT(d.err, Catch::Contains("DOF 2 is massless and damped"));
}

TEST_CASE("unilateral contact: the static state under static loads equals law elastic's (liftoff3: stuck, slipping "
          "both ways, open), and harmonic balance under a static load matches the law's time integration",
          "[unilateral_contact][static_load]") {
    // The node model's static state is a complementarity problem on the whole structure; law
    // elastic's is Newton's method on its piecewise-linear static force (its own closed forms in
    // test_elastic_contact.cpp): the same forces and displacements of the masses.
    const System base = liftoff3();
    for (const Eigen::Vector3d& load : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.2, 0),
                                        Eigen::Vector3d(-0.3, 0.2, 0), Eigen::Vector3d(0, -1.5, 0.1)}) {
        System elastic = base;
        elastic.static_load = load;
        const System nodes = nodes_model(elastic);
        const StaticState e = static_state(elastic), u = static_state(nodes);
        INFO("load " << load.transpose() << ": " << e.message << " / " << u.message);
        REQUIRE(e.ok);
        REQUIRE(u.ok);
        CHECK(u.contacts[0].state == e.contacts[0].state);
        CHECK((u.contacts[0].force - e.contacts[0].force).cwiseAbs().maxCoeff() <= 1e-12);
        CHECK((u.displacement.head(3) - e.displacement).cwiseAbs().maxCoeff() <= 1e-12);
        CHECK(u.residual <= 1e-12);
    }
    // A tangential static load at w = 1.2 (stick-slip): harmonic balance, started from the
    // static state, against the law's time integration (the static load on every step).
    System loaded = base;
    loaded.static_load = Eigen::Vector3d(0.05, 0.1, 0.0);
    const System nodes = nodes_model(loaded);
    TimeIntegrationOptions options;
    options.steady_tolerance = 1e-10;
    const PeriodicResponse tu = integrate_steady_state(nodes, 1.2, options);
    INFO(tu.message);
    REQUIRE(tu.converged);
    const Eigen::VectorXd rest = linear_stuck_state(loaded, 1.2);
    const PeriodicResponse te = integrate_steady_state(loaded, 1.2, hbf::test::tight_time_integration(), &rest);
    REQUIRE(te.converged);
    HarmonicBalance reference(loaded, HarmonicBalanceOptions{40, 0, Formulation::condensed});
    SolutionPoint pr;
    solve(reference, 1.2, pr, hbf::test::from_orbit(reference, te, loaded.contact_directions(loaded.contacts[0])));
    HarmonicBalance hb(nodes, HarmonicBalanceOptions{40, 0, Formulation::condensed});
    REQUIRE(hb.rest_state());
    CHECK(hb.rest_state()->ok);
    SolutionPoint p;
    const PointMetrics m = solve(hb, 1.2, p, from_elastic(hb, reference, pr, loaded.contacts[0]));
    const Eigen::MatrixXd y = hb.dofs(p.x, 1.2);
    double gap = 0, mean = 0;
    for (int i = 0; i < 3; ++i) {
        gap = std::max(gap, std::abs(std::complex<double>(y(1, i), -y(2, i)) - tu.harmonic1(i)));
        mean = std::max(mean, std::abs(y(0, i) - tu.displacement.col(i).mean()));
    }
    INFO("first harmonics " << gap / tu.harmonic1.head(3).cwiseAbs().maxCoeff() << ", means " << mean);
    CHECK(gap <= 5e-3 * tu.harmonic1.head(3).cwiseAbs().maxCoeff());  // measured 2.9e-3 (1/H, above)
    CHECK(mean <= 1e-4);  // the static load's mean deflection (measured 2.4e-5)
    CHECK(m.energy_error <= 1e-8);
    CHECK(tu.regime == m.regime);
}

TEST_CASE("unilateral contact: the contact problem converges from a warm start on which Newton's halving test stalls, "
          "to forces that meet Signorini's and Coulomb's conditions",
          "[unilateral_contact]") {
    // The mitred bar's 27 nodes at one step of the time integrator at 100 N (tests/data: q0, the
    // tangential reference, the warm start), G from the model itself. The solution is checked
    // against the conditions it must meet, independently of the solver: per node no penetration
    // (q_N <= gap), lambda_N >= 0 and lambda_N (gap - q_N) = 0; |lambda_T| <= mu lambda_N; stuck
    // (inside the cone) where the node stays at its reference, else slipping along its force.
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const detail::MasslessContacts split = detail::split_massless_contacts(config.system, "the test");
    std::ifstream in(std::string(HBF_SOURCE_DIR) + "/tests/data/mitre_contact_step.txt");
    std::string comment;
    std::getline(in, comment);
    const Eigen::Index m = split.G.rows();
    Eigen::VectorXd q0(m), reference(m), warm(m);
    for (Eigen::Index i = 0; i < m; ++i) REQUIRE(static_cast<bool>(in >> q0(i) >> reference(i) >> warm(i)));
    for (const bool cold : {false, true}) {
        INFO((cold ? "from zero" : "from the warm start"));
        RigidContactSolution solution;
        if (!cold) solution.lambda = warm;
        REQUIRE(solve_rigid_contacts(split.blocks, split.G, q0, reference, solution));
        const Eigen::VectorXd q = q0 - split.G * solution.lambda;
        const double force = solution.lambda.cwiseAbs().maxCoeff(), length = q0.cwiseAbs().maxCoeff();
        int stuck = 0, slipping = 0, open = 0;
        for (const RigidContact& b : split.blocks) {
            const int n = b.first + b.d;
            const double normal = solution.lambda(n), gap = b.gap - q(n);
            CHECK(normal >= -1e-10 * force);
            CHECK(gap >= -1e-10 * length);
            CHECK(std::abs(normal * gap) <= 1e-10 * force * length);
            const Eigen::VectorXd tangential = solution.lambda.segment(b.first, b.d);
            const Eigen::VectorXd moved = q.segment(b.first, b.d) - reference.segment(b.first, b.d);
            CHECK(tangential.norm() <= b.mu * normal + 1e-10 * force);
            if (normal <= 1e-10 * force) {
                ++open;
            } else if (tangential.norm() < b.mu * normal * (1.0 - 1e-9)) {
                ++stuck;
                CHECK(moved.norm() <= 1e-10 * length);
            } else {
                ++slipping;  // moved = s lambda_T with s >= 0: parallel and along the force
                CHECK(std::abs(moved.norm() * tangential.norm() - moved.dot(tangential)) <=
                      1e-8 * moved.norm() * tangential.norm() + 1e-10 * length * force);
            }
        }
        // the state the solver reports is the one the conditions give
        CHECK(stuck == static_cast<int>(std::count(solution.state.begin(), solution.state.end(), 1)));
        CHECK(open == static_cast<int>(std::count(solution.state.begin(), solution.state.end(), 0)));
        CHECK(slipping > 0);
        CHECK(stuck > 0);
    }
}

TEST_CASE("unilateral contact 3D: in permanent stick the forces keep the largest margin to the cone, so the backbone "
          "of one node leaves stick at the largest amplitude any mean allows (slip_onset)",
          "[unilateral_contact]") {
    // Three masses (y1, y2 tangential, y3 normal) coupled by K, pressed by a preload through law
    // elastic's springs on massless nodes: the preload loads the node tangentially too (T_0 =
    // 31 % of mu N_0), and the stuck mode moves both tangential directions and the normal force.
    System base;
    base.mass = sparse(Eigen::MatrixXd(Eigen::Vector3d(1.0, 0.8, 0.6).asDiagonal()));
    Eigen::Matrix3d k;
    k << 3.0, 0.4, 0.8, 0.4, 2.5, 0.3, 0.8, 0.3, 2.0;
    base.stiffness = sparse(Eigen::MatrixXd(k));
    base.damping = sparse(Eigen::MatrixXd(0.002 * k));
    base.excitation = Eigen::Vector3d(0.5, 0.3, 0.1);
    base.contacts.push_back(elastic_3d(2.0, 4.0, 0.4, 0.3));
    const System s = nodes_model(base);
    HarmonicBalanceOptions hbo;
    hbo.harmonics = 5;
    ModeOptions o;
    const SlipOnset onset = slip_onset(s, hbo, o);
    REQUIRE(onset.found);
    INFO("a* = " << onset.amplitude << ", with the static slider " << onset.static_amplitude);
    CHECK_FALSE(onset.opens);
    // The static slider (and harmonic balance's former rule, a mean tangential force of 0)
    // touches the cone well before a*: the test tells the rules apart.
    CHECK(onset.static_amplitude < 0.9 * onset.amplitude);
    o.amplitude_min = 0.9 * onset.amplitude;
    o.amplitude_max = 1.05 * onset.amplitude;
    o.max_step = 0.001;
    o.initial_step = 0.001;
    const Backbone b = NonlinearModes(s, hbo, o).follow();
    INFO(b.message);
    REQUIRE(b.status == ModeStatus::completed);
    const double departure = hbf::test::backbone_departure(b);
    INFO("the backbone departs at " << departure);
    CHECK(departure > onset.amplitude * (1.0 - 3e-3));
    CHECK(departure < onset.amplitude * (1.0 + 3e-3));
}
