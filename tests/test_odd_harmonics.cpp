// Odd harmonics only (HarmonicBalanceOptions::odd_harmonics, `--harmonics odd`): the
// half-wave symmetric solutions y(t + T/2) = -y(t) with half the unknowns. Reference: the
// balance of every harmonic, whose solution of these symmetric problems has zero mean and
// zero even harmonics (checked), must equal the odd-only one to the solver tolerance.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>

#include "cli_support.hpp"
#include "support.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/harmonic_balance.hpp"

using namespace hbf;
using hbf::test::relative_error;
using hbf::test::sampled_dofs;

namespace {

/// Largest |even harmonic or mean| of every DOF relative to the largest coefficient.
double even_share(const Eigen::MatrixXd& y) {
    double even = std::abs(y.row(0).cwiseAbs().maxCoeff());
    for (Eigen::Index k = 2; 2 * k <= y.rows() - 1; k += 2)
        even = std::max({even, y.row(2 * k - 1).cwiseAbs().maxCoeff(), y.row(2 * k).cwiseAbs().maxCoeff()});
    return even / y.cwiseAbs().maxCoeff();
}

/// A damped 3-DOF chain (M > 0, C = 0.02 K: modal) with a Jenkins contact between DOFs 1 and 2
/// and a Dahl contact of DOF 3 to the ground, for the modal receptance.
System chain3() {
    Eigen::Matrix3d k;
    k << 2, -1, 0, -1, 2, -1, 0, -1, 1;
    System s;
    s.mass = sparse(Eigen::Vector3d(1.0, 0.5, 0.8).asDiagonal());
    s.stiffness = sparse(k);
    s.damping = sparse(0.02 * k);
    s.excitation = Eigen::Vector3d(1.0, 0.0, 0.0);
    Contact jenkins;
    jenkins.dof = 0;
    jenkins.other_dof = 1;
    jenkins.law = FrictionLaw::jenkins;
    jenkins.friction_limit = 0.2;
    jenkins.stiffness = 1.5;
    Contact dahl;
    dahl.dof = 2;
    dahl.law = FrictionLaw::dahl;
    dahl.friction_limit = 0.15;
    dahl.stiffness = 2.0;
    s.contacts = {jenkins, dahl};
    return s;
}

}  // namespace

TEST_CASE("Odd harmonics only equal the balance of every harmonic on symmetric problems, with half the unknowns",
          "[odd_harmonics][condensed]") {
    // four_dofs: a massless DOF, Dahl and exact Coulomb on a force direction; chain3 with the
    // modal receptance (2 of 3 modes + residual flexibility: the same approximation in both).
    const std::vector<double> omegas = {0.6, 0.9, 1.2, 1.5};
    struct Case {
        std::string name;
        System system;
        HarmonicBalanceOptions options;
    };
    const std::vector<Case> cases = {
        {"four_dofs condensed", hbf::test::four_dofs(), {9, 64, Formulation::condensed}},
        {"four_dofs full", hbf::test::four_dofs(), {9, 64, Formulation::full}},
        {"chain3 modal", chain3(), {9, 64, Formulation::condensed, 2}},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        HarmonicBalanceOptions odd = c.options;
        odd.odd_harmonics = true;
        const HarmonicBalance all_hb(c.system, c.options), odd_hb(c.system, odd);
        // H = 9: harmonics 1, 3, 5, 7, 9, so 10 coefficients per signal against 19
        CHECK(odd_hb.balanced_coefficients() == 10);
        CHECK(odd_hb.unknowns() * 19 == all_hb.unknowns() * 10);
        const auto all = sampled_dofs(c.system, c.options, omegas, 0.5, 1.6);
        const auto half = sampled_dofs(c.system, odd, omegas, 0.5, 1.6);
        for (std::size_t k = 0; k < omegas.size(); ++k) {
            INFO("w = " << omegas[k]);
            CHECK(even_share(all[k]) < 1e-10);
            CHECK(relative_error(half[k], all[k]) < 1e-9);
        }
    }
}

TEST_CASE("Odd harmonics only: the Jacobians equal central differences, and a low-H solution embeds",
          "[odd_harmonics][condensed]") {
    for (Formulation f : {Formulation::condensed, Formulation::full}) {
        INFO(to_string(f));
        HarmonicBalanceOptions o{5, 64, f};
        o.odd_harmonics = true;
        HarmonicBalance hb(hbf::test::four_dofs(), o);
        const double omega = 0.9;
        Eigen::VectorXd x = hb.linear_guess(omega);
        for (Eigen::Index k = 0; k < x.size(); ++k) x(k) += 0.05 * std::sin(0.3 + 2.9 * static_cast<double>(k));
        Eigen::VectorXd r, dr_domega, fd_omega;
        Eigen::MatrixXd J, fd;
        hb.evaluate(x, omega, r, &J, &dr_domega);
        REQUIRE(J.rows() == hb.unknowns());
        hbf::test::central_differences(hb, x, omega, fd, fd_omega);
        CHECK(relative_error(J, fd) < 1e-5);
        CHECK(relative_error(dr_domega, fd_omega) < 1e-5);

        // Harmonics 1, 3 (H = 3) placed into H = 5: harmonic 5 zero, the others unchanged.
        HarmonicBalanceOptions low_options = o;
        low_options.harmonics = 3;
        const HarmonicBalance low(hbf::test::four_dofs(), low_options);
        const Eigen::VectorXd low_x = low.linear_guess(omega);
        const Eigen::VectorXd embedded = hb.embed_harmonics(low_x, 3);
        for (int c = 0; c < 2; ++c) {
            const Eigen::VectorXd q = hb.relative(embedded, c), q_low = low.relative(low_x, c);
            CHECK(q.head(7) == q_low);
            CHECK(q.tail(4).cwiseAbs().maxCoeff() == 0.0);
        }
    }
}

TEST_CASE("Odd harmonics only need a force at an odd harmonic", "[odd_harmonics]") {
    HarmonicBalanceOptions o{6, 0, Formulation::automatic};
    o.odd_harmonics = true;
    System s = hbf::test::four_dofs();
    s.excitation_harmonic = 2;
    CHECK_THROWS_WITH(HarmonicBalance(s, o), Catch::Contains("excitation harmonic h = 2") && Catch::Contains("odd h"));
    s.excitation_harmonic = 3;
    CHECK_NOTHROW(HarmonicBalance(s, o));
}

TEST_CASE("hbf frf --harmonics odd gives the default FRF for every law, and refuses what it cannot do",
          "[odd_harmonics][cli]") {
    ::test::TempDir dir;
    for (const std::string law : {"coulomb", "jenkins", "dahl", "lugre", "coulomb-reg"}) {
        INFO(law);
        const ::test::Result all = ::test::run_hbf("frf --quiet --exact off --error-points 0 --law " + law + " --at 0.7,0.9,1.2", dir);
        const ::test::Result odd = ::test::run_hbf("frf --quiet --exact off --error-points 0 --law " + law +
                                                       " --harmonics odd --at 0.7,0.9,1.2 --summary '" +
                                                       (dir.path / "s.json").string() + "'",
                                                   dir);
        REQUIRE(all.exit_code == 0);
        REQUIRE(odd.exit_code == 0);
        const auto rows_all = ::test::parse_csv(all.out), rows_odd = ::test::parse_csv(odd.out);
        for (double w : {0.7, 0.9, 1.2}) {
            INFO("w = " << w);
            const auto a = ::test::sample_row(rows_all, w), b = ::test::sample_row(rows_odd, w);
            REQUIRE(!a.empty());
            REQUIRE(!b.empty());
            for (const char* name : {"y1_max", "y2_max", "energy"})
                CHECK(::test::column(rows_odd, b, name) ==
                      Approx(::test::column(rows_all, a, name)).epsilon(1e-8).margin(1e-12));
        }
        const nlohmann::json summary = nlohmann::json::parse(::test::slurp(dir.path / "s.json"));
        CHECK(summary["parameters"]["odd_harmonics"] == 1);
    }
    ::test::check_bad_input("frf --quiet --harmonics odd:0", {"allowed odd (automatic H) or odd:H"}, dir);
    ::test::check_bad_input("frf --quiet --harmonics odd:x", {"--harmonics"}, dir);
    ::test::check_bad_input("frf --quiet --harmonics even", {"--harmonics"}, dir);
    ::test::check_bad_input("frf --quiet --harmonics odd:101", {"allowed 0 (automatic), 1..100, odd, or odd:H"}, dir);
    ::test::check_bad_input("frf --quiet --harmonics odd --excitation-harmonic 2", {"odd h"}, dir);
    const ::test::fs::path file = dir.path / "odd.toml";
    const std::string structure =
        "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [0.2]\n"
        "[[contact]]\ndof = 1\nlaw = \"dahl\"\nfriction_limit = 0.2\nstiffness = 2.0\n[solver]\nharmonics = 9\n";
    ::test::check_bad_config(structure + "odd_harmonics = 1\n", {"solver.odd_harmonics", "expected true or false"}, dir);
    ::test::write_file(file, structure + "odd_harmonics = true\n");
    const ::test::Result good =
        ::test::run_hbf("frf --quiet --config '" + file.string() + "' --summary '" + (dir.path / "c.json").string() + "'",
                        dir);
    REQUIRE(good.exit_code == 0);
    const nlohmann::json summary = nlohmann::json::parse(::test::slurp(dir.path / "c.json"));
    CHECK(summary["parameters"]["odd_harmonics"] == 1);
    CHECK(summary["parameters"]["harmonics"] == 9);
}
