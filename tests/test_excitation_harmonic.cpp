// A force at a higher harmonic of the response's fundamental: F cos(h w t), h =
// System::excitation_harmonic (model.hpp). Independent references:
// * relabelling: the h = 1 problem at frequency h w with K harmonics, its harmonic k put on
//   harmonic h k, solves the problem at w with H = h K harmonics (odd subharmonics zero) on the
//   same AFT samples, so both balances must agree to their tolerance;
// * the paper's closed form of the stuck absorber at the force's frequency h w (analytic.hpp);
// * the project's time integration (CVODE), whose load and energy quadrature are cos(h w t);
// * the energy balance: the work of the force equals the friction energy when C = 0.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>

#include "cli_support.hpp"
#include "support.hpp"
#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/time_integration.hpp"

using namespace hbf;
using hbf::test::relative_error;
using hbf::test::sampled_dofs;

namespace {

System with_harmonic(System s, int h) {
    s.excitation_harmonic = h;
    return s;
}

/// The h = 1 coefficients (harmonics 0..K) placed on harmonics 0, h, 2h, ..., hK.
Eigen::MatrixXd spread(const Eigen::MatrixXd& y, int h) {
    const Eigen::Index k_max = (y.rows() - 1) / 2;
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(2 * h * k_max + 1, y.cols());
    out.row(0) = y.row(0);
    for (Eigen::Index k = 1; k <= k_max; ++k) {
        out.row(2 * h * k - 1) = y.row(2 * k - 1);
        out.row(2 * h * k) = y.row(2 * k);
    }
    return out;
}

}  // namespace

TEST_CASE("A force at h w: the balance at w equals the h = 1 balance at h w, relabelled (massless DOF, Dahl and "
          "exact Coulomb, both formulations)",
          "[excitation_harmonic][condensed]") {
    // K = 5 harmonics on 64 samples at h = 1; H = h K on h 64 samples: the same AFT samples of
    // the same signals, so the dynamic Lagrangian's exact Coulomb is reproduced too.
    const System base = hbf::test::four_dofs();
    const std::vector<double> omegas = {0.6, 0.9, 1.2, 1.5};
    for (Formulation f : {Formulation::condensed, Formulation::full}) {
        const auto reference = sampled_dofs(base, {5, 64, f}, omegas, 0.5, 1.6);
        for (int h : {2, 3}) {
            std::vector<double> fundamentals;
            for (double w : omegas) fundamentals.push_back(w / h);
            const auto y = sampled_dofs(with_harmonic(base, h), {5 * h, 64 * h, f}, fundamentals, 0.5 / h, 1.6 / h);
            for (std::size_t k = 0; k < omegas.size(); ++k) {
                INFO(to_string(f) << ", h = " << h << ", w = " << fundamentals[k]);
                CHECK(relative_error(y[k], spread(reference[k], h)) < 1e-9);
            }
        }
    }
}

TEST_CASE("A force at h w: the exact Jacobians equal central differences (the load's rows and its w-derivative)",
          "[excitation_harmonic][condensed]") {
    for (Formulation f : {Formulation::condensed, Formulation::full}) {
        HarmonicBalance hb(with_harmonic(hbf::test::four_dofs(), 2), HarmonicBalanceOptions{4, 64, f});
        const int n = hb.coefficients();
        const double omega = 0.45;
        Eigen::VectorXd x = hb.linear_guess(omega);
        for (Eigen::Index k = 0; k < x.size(); ++k) x(k) += 0.05 * std::sin(1.0 + 3.7 * static_cast<double>(k)) / (1 + (k % n));
        Eigen::VectorXd r, dr_domega, fd_omega;
        Eigen::MatrixXd J, fd;
        hb.evaluate(x, omega, r, &J, &dr_domega);
        hbf::test::central_differences(hb, x, omega, fd, fd_omega);
        INFO(to_string(f));
        CHECK(relative_error(J, fd) < 1e-5);
        CHECK(relative_error(dr_domega, fd_omega) < 1e-5);
    }
}

TEST_CASE("A force at 2 w on the stuck absorber: HB and time integration give the closed form at 2 w, and no "
          "first harmonic",
          "[excitation_harmonic][timeint]") {
    // mu = 5 keeps the contact stuck below the limit friction coefficient at these frequencies:
    // both masses move as one at the force's frequency 2 w (paper eqs. 11-13).
    AbsorberParameters p;
    p.friction_coefficient = 5.0;
    const System s = with_harmonic(friction_absorber(p, FrictionLaw::coulomb), 2);
    const std::vector<double> omegas = {0.2, 0.55};
    HarmonicBalance hb(s, HarmonicBalanceOptions{10, 0, Formulation::automatic});
    const auto samples = hbf::test::sampled_points(hb, omegas, 0.15, 0.6);
    Analyser analyse(hb);
    for (const SolutionPoint& point : samples) {
        const double closed = std::abs(analytic::coulomb_stick(p, 2.0 * point.omega).y1);
        const PointMetrics m = analyse(point);
        INFO("w = " << point.omega);
        CHECK(m.regime == "stick");
        CHECK(m.y_max[0] == Approx(closed).epsilon(1e-9));
        CHECK(m.y_max[1] == Approx(closed).epsilon(1e-9));
        CHECK(m.y_amp1[0] < 1e-12 * closed);
        const PeriodicResponse t =
            integrate_steady_state(s, point.omega, hbf::test::tight_time_integration(), nullptr);
        REQUIRE(t.converged);
        CHECK(t.y_max[0] == Approx(closed).epsilon(1e-7));
        CHECK(t.y_amp1[0] < 1e-7 * closed);
    }
}

TEST_CASE("A force at 2 w in stick-slip: HB against time integration, and the force's work against the friction "
          "energy",
          "[excitation_harmonic][timeint]") {
    // Jenkins (k_t = r wb^2 = 0.016) and Dahl on the paper's absorber (C = 0: every bit of the
    // force's work per period is dissipated by friction).
    for (FrictionLaw law : {FrictionLaw::jenkins, FrictionLaw::dahl}) {
        const System s = with_harmonic(friction_absorber(AbsorberParameters{}, law), 2);
        HarmonicBalance hb(s, HarmonicBalanceOptions{40, 0, Formulation::automatic});
        INFO(to_string(law));
        // stick-slip at these w (the h = 1 FRF is stick-slip near 2 w = 0.86-0.88 and 1.19-1.20)
        const auto samples = hbf::test::sampled_points(hb, {0.43, 0.435, 0.5975}, 0.25, 0.8);
        Analyser analyse(hb);
        int sliding = 0;
        for (const SolutionPoint& point : samples) {
            const PointMetrics m = analyse(point);
            INFO("w = " << point.omega << ", " << m.regime);
            sliding += m.regime != "stick";
            CHECK(m.input_energy == Approx(m.energy).epsilon(1e-6));
            // from the linear stuck state at 2 w, as hbf timeint starts (from rest, Dahl at
            // w = 0.5975 stalls at a Poincare change of 6e-11, the rounding floor of two
            // forcing periods at rtol 1e-12, against the 1e-11 asked)
            const Eigen::VectorXd start = linear_stuck_state(s, point.omega);
            const PeriodicResponse t =
                integrate_steady_state(s, point.omega, hbf::test::tight_time_integration(), &start);
            REQUIRE(t.converged);
            CHECK(m.y_max[0] == Approx(t.y_max[0]).epsilon(1e-3));
            CHECK(m.y_max[1] == Approx(t.y_max[1]).epsilon(1e-3));
            CHECK(t.input_energy == Approx(t.energy).epsilon(1e-6));
            CHECK(m.energy == Approx(t.energy).epsilon(2e-3));
        }
        CHECK(sliding >= 2);
    }
}

TEST_CASE("A force at 2 w on a massless contact DOF: time integration's condensation against harmonic balance",
          "[excitation_harmonic][timeint][massless]") {
    // The massless DOF's static displacement carries the load's part at 2 w (expand); HB
    // (condensed) solves the same equations. Exact Coulomb by HB errs like 1/H at stick-slip.
    const System s = with_harmonic(hbf::test::massless_contact(0.8, 0.3), 2);
    HarmonicBalance hb(s, HarmonicBalanceOptions{40, 0, Formulation::automatic});
    const auto samples = hbf::test::sampled_points(hb, {0.3, 0.55, 0.8}, 0.2, 0.9);
    Analyser analyse(hb);
    for (const SolutionPoint& point : samples) {
        const PointMetrics m = analyse(point);
        const PeriodicResponse t = integrate_steady_state(s, point.omega, hbf::test::tight_time_integration(), nullptr);
        INFO("w = " << point.omega << ", " << m.regime);
        REQUIRE(t.converged);
        CHECK(m.y_max[0] == Approx(t.y_max[0]).epsilon(1e-2));
        CHECK(m.y_max[1] == Approx(t.y_max[1]).epsilon(2e-2));
        CHECK(t.y_amp1[0] < 1e-6 * t.y_max[0]);
    }
}

TEST_CASE("Excitation harmonic: bad values are refused with the parameter named, and the exact solver refuses h > 1",
          "[excitation_harmonic][cli]") {
    System s = hbf::test::four_dofs();
    s.excitation_harmonic = 0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("excitation harmonic h = 0") && Catch::Contains("allowed 1..100"));
    s.excitation_harmonic = 3;
    CHECK_THROWS_WITH(HarmonicBalance(s, HarmonicBalanceOptions{2, 0, Formulation::automatic}),
                      Catch::Contains("harmonics = 2") && Catch::Contains("allowed harmonics >= h"));
    const System den_hartog = with_harmonic(hbf::test::den_hartog_oscillator(0.2), 2);
    CHECK_FALSE(exact_solver_supports(den_hartog));
    CHECK_THROWS_WITH(exact_periodic_orbit(den_hartog, 0.5, linear_stuck_state(den_hartog, 0.5)),
                      Catch::Contains("excitation harmonic h = 2"));

    ::test::TempDir dir;
    ::test::check_bad_input("frf --quiet --excitation-harmonic 0", {"--excitation-harmonic = 0 is out of range: allowed 1..100"}, dir);
    ::test::check_bad_input("frf --quiet --excitation-harmonic 2.5", {"--excitation-harmonic"}, dir);
    ::test::check_bad_input("frf --quiet --excitation-harmonic 3 --harmonics 2", {"allowed harmonics >= h"}, dir);
    ::test::check_bad_input("frf --quiet --excitation-harmonic 2 --exact on", {"excitation harmonic h = 2"}, dir);
    ::test::check_bad_config("[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [1.0]\nexcitation_harmonic = 101\n"
                             "[[contact]]\ndof = 1\nlaw = \"coulomb\"\nfriction_limit = 0.2\n",
                             {"structure.excitation_harmonic", "allowed 1..100"}, dir);
}

TEST_CASE("hbf frf --excitation-harmonic 2 is the default FRF at half the frequency, and --config's key does the "
          "same",
          "[excitation_harmonic][cli]") {
    // Automatic H doubles with h (the law's H harmonics of the force's frequency), the AFT
    // samples double with H: the relabelled h = 1 balance, so y_max agrees to the tolerance.
    ::test::TempDir dir;
    const ::test::Result one = ::test::run_hbf("frf --quiet --law dahl --at 0.6,1.0,1.4", dir);
    const ::test::Result two = ::test::run_hbf(
        "frf --quiet --law dahl --excitation-harmonic 2 --wmin 0.25 --wmax 0.8 --at 0.3,0.5,0.7 --summary '" + (dir.path / "s.json").string() + "'",
        dir);
    REQUIRE(one.exit_code == 0);
    REQUIRE(two.exit_code == 0);
    const auto rows_one = ::test::parse_csv(one.out), rows_two = ::test::parse_csv(two.out);
    for (double w : {0.3, 0.5, 0.7}) {
        INFO("w = " << w);
        const auto a = ::test::sample_row(rows_two, w), b = ::test::sample_row(rows_one, 2.0 * w);
        REQUIRE(!a.empty());
        REQUIRE(!b.empty());
        for (const char* name : {"y1_max", "y2_max"})
            CHECK(::test::column(rows_two, a, name) == Approx(::test::column(rows_one, b, name)).epsilon(1e-8));
        CHECK(::test::column(rows_two, a, "y1_amp1") < 1e-9);
        CHECK(::test::column(rows_two, a, "energy") == Approx(2.0 * ::test::column(rows_one, b, "energy")).epsilon(1e-7));
    }
    const nlohmann::json summary = nlohmann::json::parse(::test::slurp(dir.path / "s.json"));
    CHECK(summary["parameters"]["excitation_harmonic"] == 2);
    CHECK(summary["parameters"]["harmonics"] == 20);

    const ::test::fs::path file = dir.path / "h2.toml";
    ::test::write_file(file,
                     "[structure]\nmass = [1.0, 0.1]\nstiffness = [[1.1, -0.1], [-0.1, 0.1]]\nexcitation = [0.5, 0.0]\n"
                     "excitation_harmonic = 2\n[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"dahl\"\n"
                     "friction_limit = 0.2\nstiffness = 0.016\n[frequency]\nwmin = 0.25\nwmax = 0.8\n");
    const ::test::Result config = ::test::run_hbf("frf --quiet --config '" + file.string() + "' --at 0.5", dir);
    REQUIRE(config.exit_code == 0);
    const auto rows = ::test::parse_csv(config.out);
    const auto a = ::test::sample_row(rows, 0.5), b = ::test::sample_row(rows_one, 1.0);
    REQUIRE(!a.empty());
    CHECK(::test::column(rows, a, "y1_max") == Approx(::test::column(rows_one, b, "y1_max")).epsilon(1e-8));
}
