// The condensed formulation of harmonic balance (harmonic_balance.hpp: the unknowns are the
// contacts' relative displacements, the structure solved per harmonic by the receptance)
// against the full all-DOF formulation, finite differences, an independent equivalent model
// (a massless contact DOF behind a spring is a Jenkins element), and its errors.
#include <tuple>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <iomanip>
#include <cmath>
#include <random>

#include "cli_support.hpp"
#include "support.hpp"
#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/receptance.hpp"

using namespace hbf;
using hbf::test::four_dofs;
using hbf::test::grounded_coulomb;
using hbf::test::relative_error;
using hbf::test::sampled_dofs;


TEST_CASE("Condensed and full Jacobians equal central finite differences (massless DOF, force direction, two laws)",
          "[condensed]") {
    // Exact Coulomb's residual is piecewise linear (stick/slip samples): central differences
    // see its Jacobian unless a sample sits within h of a switch; 1e-5 relative as in
    // test_harmonic_balance.cpp.
    for (Formulation f : {Formulation::condensed, Formulation::full}) {
        HarmonicBalance hb(four_dofs(), HarmonicBalanceOptions{4, 64, f});
        REQUIRE(hb.formulation() == f);
        const int contacts = 2, n = hb.coefficients();
        // + Dahl's z and the Coulomb contact's force (the dynamic Lagrangian's unknown signal)
        CHECK(hb.unknowns() == (f == Formulation::condensed ? contacts : 4) * n + 2 * n);
        for (int state = 0; state < 3; ++state) {
            const double omega = 0.7 + 0.3 * state;
            std::mt19937 rng(5 + state);
            std::normal_distribution<double> normal(0.0, 1.0);
            Eigen::VectorXd x = hb.linear_guess(omega);
            for (int k = 0; k < x.size(); ++k) x(k) += 0.3 * (state + 1) * normal(rng) / (1 + (k % n));
            Eigen::VectorXd r, dr_domega, fd_omega;
            Eigen::MatrixXd J, fd;
            hb.evaluate(x, omega, r, &J, &dr_domega);
            hbf::test::central_differences(hb, x, omega, fd, fd_omega);
            INFO(to_string(f) << ", state " << state);
            CHECK(relative_error(J, fd) < 1e-5);
            CHECK(relative_error(dr_domega, fd_omega) < 1e-5);
        }
    }
}

TEST_CASE("Condensed and full harmonic balance give the same solutions to 1e-9 (massless DOF, two contacts)",
          "[condensed]") {
    // The same equations in other unknowns: solved to 1e-12, the DOFs' coefficients (the
    // condensed ones recovered from the contact forces) agree to rounding, far below 1e-9.
    const std::vector<double> omegas = {0.6, 0.9, 1.2, 1.5};
    const System s = four_dofs();
    const auto condensed = sampled_dofs(s, {8, 0, Formulation::condensed}, omegas, 0.5, 1.6);
    const auto full = sampled_dofs(s, {8, 0, Formulation::full}, omegas, 0.5, 1.6);
    for (std::size_t k = 0; k < omegas.size(); ++k) {
        INFO("w = " << omegas[k]);
        CHECK(relative_error(condensed[k], full[k]) < 1e-9);
    }
}

TEST_CASE("A massless contact DOF behind a spring is a Jenkins element: condensed HB against the exact Jenkins orbit",
          "[condensed]") {
    // Independent reference: the event-exact periodic orbit of the 1-DOF Jenkins model (exact
    // to rounding). HB with exact Coulomb (dynamic Lagrangian) errs like 1/H at stick-slip
    // (the switching events are read off a truncated velocity): at H = 20, 1 % on y_max.
    const double kt = 0.8, limit = 0.3;
    const std::vector<double> omegas = {0.5, 0.9, 1.1, 1.6};
    const auto y = sampled_dofs(hbf::test::massless_contact(kt, limit), {20, 0, Formulation::condensed}, omegas, 0.4, 1.8);
    const System jenkins = hbf::test::jenkins_equivalent(kt, limit);
    for (std::size_t k = 0; k < omegas.size(); ++k) {
        const ExactOrbit orbit = exact_periodic_orbit(jenkins, omegas[k], Eigen::VectorXd::Zero(4));
        INFO("w = " << omegas[k] << ": " << orbit.summary());
        REQUIRE(orbit.converged);
        // The mass's first-harmonic amplitude, which a 1/H error in the switching times barely
        // moves, and its y_max bound |c0| + sum |Y_k| against the exact y_max.
        const Eigen::VectorXd c = y[k].col(0);
        const double amplitude = std::hypot(c(1), c(2));
        CHECK(amplitude == Approx(std::abs(orbit.harmonic1(0))).epsilon(0.01));
    }
}

TEST_CASE("Condensed formulation: singular static stiffness, a contact-free system and bad directions are errors",
          "[condensed]") {
    // A free mass (K = 0) held only by friction: Z_0 is singular, condensed is refused by
    // name and automatic falls back to the full formulation.
    System s = hbf::test::jenkins_equivalent(1.0, 0.3);
    s.contacts[0].law = FrictionLaw::coulomb;
    s.stiffness = SparseMatrix(1, 1);
    CHECK_THROWS_WITH(HarmonicBalance(s, HarmonicBalanceOptions{4, 0, Formulation::condensed}),
                      Catch::Contains("formulation = condensed") && Catch::Contains("singular"));
    CHECK(HarmonicBalance(s, HarmonicBalanceOptions{4, 0, Formulation::automatic}).formulation() == Formulation::full);
    System linear = hbf::test::jenkins_equivalent(1.0, 0.3);
    linear.contacts.clear();
    CHECK_THROWS_WITH(HarmonicBalance(linear, HarmonicBalanceOptions{4, 0, Formulation::condensed}),
                      Catch::Contains("at least one contact"));
    System bad = four_dofs();
    bad.contacts[1].direction = Eigen::Vector3d(1.0, 0.0, 0.0);
    CHECK_THROWS_WITH(bad.validate(), Catch::Contains("contact 2") && Catch::Contains("force_direction has 3 entries"));
    bad.contacts[1].direction = Eigen::Vector4d::Zero();
    CHECK_THROWS_WITH(bad.validate(), Catch::Contains("not all zero"));
    bad = four_dofs();
    bad.mass.coeffRef(3, 3) = -0.1;
    CHECK_THROWS_WITH(bad.validate(), Catch::Contains("not positive semi-definite"));
    // An undamped resonance of the free structure hit exactly is regular: the condensed
    // structure carries the contact's spring and damper (subtracted from the friction force).
    System undamped = hbf::test::massless_contact(0.8, 0.3);
    undamped.damping = SparseMatrix(2, 2);
    HarmonicBalance shifted(undamped, HarmonicBalanceOptions{3, 0, Formulation::condensed});
    Eigen::VectorXd r;
    shifted.evaluate(Eigen::VectorXd::Zero(shifted.unknowns()), 1.0, r);  // w = 1: the mass on k1 alone
    CHECK(r.allFinite());
    // A mode that no contact moves, undamped and hit exactly by harmonic 1 (DOF 1 alone on its
    // spring, the contact on DOF 2): the contacts do not see it, so their residual is regular
    // (issue 28: it was NaN, and the branch could not start); the DOF it moves is unbounded
    // there (F excites it): infinite in the recovered response and its amplitude bound, never
    // a number passed off as a solution.
    const System apart = grounded_coulomb(Eigen::Matrix2d::Identity(), Eigen::Matrix2d(Eigen::Vector2d(1.0, 4.0).asDiagonal()),
                                          Eigen::Vector2d(1.0, 1.0), 1, 0.3);
    HarmonicBalance hb(apart, HarmonicBalanceOptions{3, 0, Formulation::condensed});
    hb.evaluate(Eigen::VectorXd::Zero(hb.unknowns()), 1.0, r);
    CHECK(r.allFinite());
    CHECK(hb.structure_failure().empty());
    const Eigen::MatrixXd y = hb.dofs(Eigen::VectorXd::Zero(hb.unknowns()), 1.0);
    CHECK(std::isinf(y(1, 0)));  // DOF 1's cosine coefficient of harmonic 1
    CHECK(y.col(1).allFinite());
    CHECK(std::isinf(hb.amplitude_bound(Eigen::VectorXd::Zero(hb.unknowns()), 1.0)));
}

TEST_CASE("Uncoupled oscillators, one with a contact: condensed equals full and y2 = F2 / (k2 - m2 w^2)",
          "[condensed][resonances]") {
    // Issue 28: M = I, K = diag(1, 4), undamped, exact Coulomb (0.3) from DOF 1 to the ground.
    // Harmonic 4 hits DOF 2's resonance 2 exactly at w = 0.5: the condensed start failed
    // ("residual inf", exit 1) while the full formulation computed the branch. DOF 2 is a free
    // linear oscillator: its harmonic 1 is F2 / (k2 - w^2), its other harmonics zero. F1 = 0.2
    // is below 0.3: DOF 1 stays stuck (zero).
    const System s = grounded_coulomb(Eigen::Matrix2d::Identity(), Eigen::Matrix2d(Eigen::Vector2d(1.0, 4.0).asDiagonal()),
                                      Eigen::Vector2d(0.2, 1.0), 0, 0.3);
    const std::vector<double> omegas = {0.5, 0.9, 1.3, 1.7};
    const auto condensed = sampled_dofs(s, {5, 0, Formulation::condensed}, omegas, 0.5, 1.8);
    const auto full = sampled_dofs(s, {5, 0, Formulation::full}, omegas, 0.5, 1.8);
    for (std::size_t k = 0; k < omegas.size(); ++k) {
        INFO("w = " << omegas[k]);
        CHECK(relative_error(condensed[k], full[k]) < 1e-9);
        const double closed = 1.0 / (4.0 - omegas[k] * omegas[k]);
        CHECK(std::abs(condensed[k](1, 1) - closed) < 1e-10 * closed);
        CHECK(condensed[k].col(0).cwiseAbs().maxCoeff() < 1e-10);
    }
    // DOF 2's resonance w = 2 inside the band: the response is unbounded there; both
    // formulations cap on each flank (never a step across it, never a failed start).
    for (Formulation f : {Formulation::condensed, Formulation::full}) {
        HarmonicBalance hb(s, {5, 0, f});
        ContinuationOptions o;
        o.omega_start = 1.5;
        o.omega_end = 2.5;
        const BranchResult b = continue_branch(hb, o);
        INFO(to_string(f) << ": " << b.summary());
        CHECK(b.status == ContinuationStatus::amplitude_cap);
        std::vector<double> caps;
        for (const SolutionPoint& p : b.points)
            if (p.kind == PointKind::cap) caps.push_back(p.omega);
        REQUIRE(caps.size() == 2);
        CHECK(caps[0] < 2.0);
        CHECK(caps[1] > 2.0);
        CHECK(caps[1] - caps[0] < 1e-3);
        // Every point below the cap: the closed form (amplitude 1 / |4 - w^2|).
        for (const SolutionPoint& p : b.points) {
            const Eigen::MatrixXd y = hb.dofs(p.x, p.omega);
            if (p.kind == PointKind::cap || !y.allFinite()) continue;
            const double closed = 1.0 / (4.0 - p.omega * p.omega);
            CHECK(std::abs(y(1, 1) - closed) < 1e-8 * std::abs(closed));
        }
    }
}

TEST_CASE("hbf frf ending exactly on an undamped resonance no contact sees: amplitude_cap, inf, never NaN or a failed polish",
          "[condensed][resonances][cli][exact]") {
    // M = I, K = diag(1, 4), F = (1, 1), exact Coulomb (0.3) from DOF 2 to the ground; wmax = 1
    // is DOF 1's resonance exactly. DOF 1 is a free linear oscillator, y1 = 1 / |1 - w^2|: the
    // branch reaches the amplitude cap on the way and lands on w = 1, where y1 is infinite. The
    // point there is written with inf (it was NaN: inf * cos(pi / 2)) and left unpolished
    // (exact = off; the exact solver has no orbit there and the run ended in exit 1); the
    // verdict is amplitude_cap, exit 3. Every finite y1_max below the cap is the closed form to
    // 1e-9 (polished rows: exact).
    ::test::TempDir dir;
    const auto system = dir.path / "apart.toml";
    std::ofstream(system) << "[structure]\nmass = [1.0, 1.0]\nstiffness = [1.0, 4.0]\nexcitation = [1.0, 1.0]\n"
                             "[[contact]]\ndof = 2\nlaw = \"coulomb\"\nfriction_limit = 0.3\n"
                             "[frequency]\nwmin = 0.5\nwmax = 1.0\n";
    const ::test::Result r = ::test::run_hbf("frf --config '" + system.string() + "'", dir);
    INFO(r.err);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("amplitude_cap"));
    CHECK(r.out.find("nan") == std::string::npos);
    const auto rows = ::test::parse_csv(r.out);
    REQUIRE(rows.size() > 10);
    const auto column = [&](const std::string& name) {
        const auto at = std::find(rows[0].begin(), rows[0].end(), name);
        REQUIRE(at != rows[0].end());
        return static_cast<std::size_t>(at - rows[0].begin());
    };
    const std::size_t w = column("w"), y1 = column("y1_max"), exact = column("exact");
    int infinite = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double omega = std::stod(rows[k][w]);
        if (rows[k][y1] == "inf") {
            ++infinite;
            CHECK(omega == 1.0);
            CHECK(rows[k][exact] == "off");
            continue;
        }
        CHECK(rows[k][exact] == "yes");
        const double closed = 1.0 / std::abs(1.0 - omega * omega);
        CHECK(std::abs(std::stod(rows[k][y1]) - closed) <= 1e-9 * closed);
    }
    CHECK(infinite >= 1);
    // The modal receptance with both modes (no truncation) is the same FRF: the hidden mode's
    // limit (it was "residual inf" at the start, where harmonic 2 hits w = 1 and harmonic 4
    // hits DOF 2's mode w = 2, which the contact sees and regularises).
    const ::test::Result modal = ::test::run_hbf("frf --modes 2 --config '" + system.string() + "'", dir);
    INFO(modal.err);
    CHECK(modal.exit_code == 3);
    CHECK(modal.out.find("nan") == std::string::npos);
    const auto modal_rows = ::test::parse_csv(modal.out);
    REQUIRE(modal_rows.size() == rows.size());
    for (std::size_t k = 1; k < rows.size(); ++k)
        for (const std::size_t c : {w, y1, column("y2_max")}) {
            if (rows[k][c] == "inf") {
                CHECK(modal_rows[k][c] == "inf");
                continue;
            }
            CHECK(std::abs(std::stod(modal_rows[k][c]) - std::stod(rows[k][c])) <= 1e-9 * std::stod(rows[k][c]));
        }
}

TEST_CASE("hbf frf: --formulation condensed and full give the same --at samples on the shipped systems", "[condensed]") {
    ::test::TempDir dir;
    const std::string systems = std::string(HBF_SOURCE_DIR) + "/examples/systems/";
    const std::string options = " --exact off --tolerance 1e-11";
    const std::vector<std::string> cases = {"--config " + systems + "chain3.toml",
                                            "--config " + systems + "chain3_exact.toml",
                                            // undamped: condensed cannot start at w = 0.5, where Z_2 is singular
                                            "--config " + systems + "den_hartog.toml --wmin 0.52 --wmax 0.96",
                                            "--law dahl",
                                            "--law lugre",
                                            "--law jenkins",
                                            "--law coulomb-reg",
                                            "--law coulomb"};
    for (const std::string& c : cases) {
        // every --at frequency inside the range (one outside is an error)
        const std::string at = c.find("den_hartog") != std::string::npos ? " --at 0.55,0.8,0.95"
                                                                          : " --at 0.55,0.8,0.95,1.2,1.45";
        const ::test::Result condensed = ::test::run_hbf("frf " + c + at + options + " --error-points 0 --formulation condensed", dir);
        const ::test::Result full = ::test::run_hbf("frf " + c + at + options + " --error-points 0 --formulation full", dir);
        INFO(c << "\n" << condensed.err << full.err);
        REQUIRE(condensed.exit_code == 0);
        REQUIRE(full.exit_code == 0);
        auto samples = [](const std::string& csv) {
            std::vector<std::vector<std::string>> rows;
            const auto all = ::test::parse_csv(csv);
            const auto column = std::find(all.front().begin(), all.front().end(), "point") - all.front().begin();
            for (const auto& row : all)
                if (static_cast<long>(row.size()) > column && row[static_cast<std::size_t>(column)] == "sample") rows.push_back(row);
            return rows;
        };
        const auto a = samples(condensed.out), b = samples(full.out);
        REQUIRE(a.size() == b.size());
        REQUIRE(a.size() >= 3);
        const auto header = ::test::parse_csv(condensed.out).front();
        for (std::size_t k = 0; k < a.size(); ++k)
            for (std::size_t j = 0; j < header.size(); ++j)
                if (header[j].find("_max") != std::string::npos || header[j].find("_amp1") != std::string::npos) {
                    const double x = std::stod(a[k][j]), y = std::stod(b[k][j]);
                    INFO("w = " << a[k][0] << " " << header[j]);
                    CHECK(std::abs(x - y) <= 1e-9 * std::max(1.0, std::abs(y)));
                }
    }
}

TEST_CASE("The absorber preset: condensed (the default) and full (the previous formulation) agree to 1e-12 in y1_max",
          "[condensed]") {
    // At the default corrector tolerance (1e-9 of the force) both sides carry ~1e-9 of
    // solver error; converged to 1e-14 they are the same solution to 1e-12 (measured up to
    // 1.5e-13), so nothing of the preset's answer changed with the formulation.
    ::test::TempDir dir;
    for (const std::string law : {"coulomb", "jenkins", "dahl", "lugre", "coulomb-reg"}) {
        const std::string common = "frf --quiet --law " + law + " --tolerance 1e-14 --exact off --error-points 0 --at 0.6,0.8,0.9,1,1.1,1.3,1.5";
        const ::test::Result condensed = ::test::run_hbf(common + " --formulation condensed", dir);
        const ::test::Result full = ::test::run_hbf(common + " --formulation full", dir);
        INFO(law << "\n" << condensed.err << full.err);
        REQUIRE(condensed.exit_code == 0);
        REQUIRE(full.exit_code == 0);
        std::vector<double> a, b;
        for (const auto& row : ::test::parse_csv(condensed.out))
            if (row.size() > 9 && row[9] == "sample") a.push_back(std::stod(row[1]));
        for (const auto& row : ::test::parse_csv(full.out))
            if (row.size() > 9 && row[9] == "sample") b.push_back(std::stod(row[1]));
        REQUIRE(a.size() == 7);
        REQUIRE(b.size() == 7);
        for (std::size_t k = 0; k < a.size(); ++k) CHECK(std::abs(a[k] - b[k]) <= 1e-12 * b[k]);
    }
}

namespace {
/// The shipped beam (examples/systems/beam/beam200.toml) with the tip's friction limit set.
System beam(double friction_limit) {
    hbf::io::SystemConfig config =
        hbf::io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/beam200.toml");
    config.system.contacts[0].friction_limit = friction_limit;
    return config.system;
}
}  // namespace

TEST_CASE("Finite-element beam (200 DOFs, Matrix Market): the stuck and the free linear limits of dense solves",
          "[condensed][beam]") {
    // Independent references: the complex amplitude Y = Z^-1 F of the beam by a dense LU
    // (Eigen) of the 200 x 200 dynamic stiffness, with the tip's transverse DOF removed
    // (a friction limit of 1e9 N never slips: the tip is pinned) or free (1e-9 N: the
    // friction force is 1e-10 of the 10 N excitation). Harmonic balance at H = 3 on the
    // condensed formulation, at 35, 52 (near the free first mode) and 70 rad/s; DOFs recovered
    // from the contact force. Solved to 1e-10 of the 10 N force scale, compared to 1e-8 of
    // the largest amplitude (amplification near the mode ~50).
    const std::vector<double> omegas = {35.0, 52.0, 70.0};
    for (const bool stuck : {true, false}) {
        const System s = beam(stuck ? 1e9 : 1e-9);
        const int tip = s.contacts[0].dof, mid = 98;  // DOF 99 (1-based): mid-span, transverse
        const auto y = sampled_dofs(s, {3, 0, Formulation::condensed}, omegas, 30.0, 80.0, 1e-10);
        for (std::size_t k = 0; k < omegas.size(); ++k) {
            const double w = omegas[k];
            // In long double: Z rounded to double moves this lightly damped resonance of a
            // badly conditioned K (entries up to 1e10) by ~1e-7 relative.
            using Long = std::complex<long double>;
            using LongMatrix = Eigen::Matrix<Long, Eigen::Dynamic, Eigen::Dynamic>;
            const long double w2 = static_cast<long double>(w) * w;
            LongMatrix z = Eigen::MatrixXd(s.stiffness).cast<long double>().cast<Long>() -
                           (w2 * Eigen::MatrixXd(s.mass).cast<long double>()).cast<Long>() +
                           Long(0.0L, static_cast<long double>(w)) * Eigen::MatrixXd(s.damping).cast<long double>().cast<Long>();
            Eigen::Matrix<Long, Eigen::Dynamic, 1> f = s.excitation.cast<long double>().cast<Long>();
            if (stuck) {  // y_tip = 0: its row and column replaced by the identity
                z.row(tip).setZero();
                z.col(tip).setZero();
                z(tip, tip) = 1.0L;
                f(tip) = 0.0L;
            }
            const Eigen::Matrix<Long, Eigen::Dynamic, 1> solved = z.partialPivLu().solve(f);
            Eigen::VectorXcd reference(solved.size());
            for (Eigen::Index i = 0; i < solved.size(); ++i)
                reference(i) = std::complex<double>(static_cast<double>(solved(i).real()), static_cast<double>(solved(i).imag()));
            INFO((stuck ? "stuck" : "free") << ", w = " << w);
            for (int dof : {mid, tip}) {
                const std::complex<double> hb(y[k](1, dof), -y[k](2, dof));
                const double scale = reference.cwiseAbs().maxCoeff();
                CHECK(std::abs(hb - reference(dof)) < 1e-8 * scale);
            }
            CHECK(y[k].row(0).cwiseAbs().maxCoeff() < 1e-8 * reference.cwiseAbs().maxCoeff());  // no mean
        }
    }
}

TEST_CASE("hbf frf on the beam: the JSON peaks belong to every reported DOF, each at least the CSV's largest",
          "[condensed][beam][cli]") {
    // beam200.toml reports DOFs 99 (mid-span) and 199 (tip): the summary has the peaks of
    // both, and for each the largest peak is at least its largest _max row that is a local
    // maximum of the branch (a maximum at wmin or wmax is not a peak), and at most a few %
    // above it (refined between branch points a few % apart).
    ::test::TempDir dir;
    const std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/beam200.toml";
    const auto json = dir.path / "s.json";
    const ::test::Result r = ::test::run_hbf("frf --quiet --config '" + file + "' --summary '" + json.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json summary = nlohmann::json::parse(::test::slurp(json));
    const auto rows = ::test::parse_csv(r.out);
    REQUIRE(rows.front()[1] == "y99_max");
    REQUIRE(rows.front()[2] == "y199_max");
    for (const auto& [column, name, dof] : {std::tuple{1, "y99", 99}, std::tuple{2, "y199", 199}}) {
        INFO(name);
        double largest = 0.0;
        for (std::size_t k = 2; k + 1 < rows.size(); ++k) {
            const double y = std::stod(rows[k][column]);
            if (y >= std::stod(rows[k - 1][column]) && y >= std::stod(rows[k + 1][column])) largest = std::max(largest, y);
        }
        REQUIRE(largest > 0.0);
        double peak = 0.0;
        for (const auto& p : summary.at("peaks"))
            if (p.at("output") == name) {
                CHECK(p.at("dof") == dof);
                peak = std::max(peak, p.at("y_max").get<double>());
            }
        CHECK(peak >= largest * (1.0 - 1e-12));
        CHECK(peak <= largest * 1.05);
    }
}

namespace {
/// The 200-DOF beam's default FRF (exact by default: polished on its modal form, modal_exact.hpp)
/// against BDF time integration of the full model at the frequencies given, in the shipped
/// beam200.toml (limit 3 N: stick-slip) or with a limit of 30 N (the tip stays stuck).
/// Reference: hbf timeint --config (CVODE BDF with the sparse Newton solve, rtol 1e-10, atol
/// 1e-10 of the response scale, steady-tol 1e-7: y_max to ~1e-6). Tolerance 1e-6 of the
/// mid-span y_max (the tip is ~0 when stuck): the modal form's estimated truncation is below
/// 1e-11 (hbf frf's note: 10 modes in stick, 20 otherwise), so the difference is the
/// integrator's. Measured, largest of mid-span and tip: 8e-9 (stick, w = 40), 4e-8 (w = 40),
/// 2.5e-7 (w = 75), 8e-7 (w = 160, a stick phase of 7.6 % of the period whose ends BDF
/// locates to its own tolerance).
struct BeamCase {
    bool stuck;
    std::string omega;
    const char* regime;
    double max_stick_fraction;
};
void beam_against_bdf(const std::vector<BeamCase>& cases) {
    ::test::TempDir dir;
    const std::string beam = std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/";
    std::string text = ::test::slurp(beam + "beam200.toml");
    const auto limit = text.find("friction_limit = 3\n");
    REQUIRE(limit != std::string::npos);
    text.replace(limit, 19, "friction_limit = 30\n");
    for (std::size_t p = text.find("\"beam200_"); p != std::string::npos; p = text.find("\"beam200_", p + beam.size() + 2))
        text.insert(p + 1, beam);
    const auto stuck = dir.path / "stuck.toml";
    {
        std::ofstream(stuck) << text;
    }
    for (const BeamCase& c : cases) {
        const std::string& w = c.omega;
        const std::string file = c.stuck ? stuck.string() : beam + "beam200.toml";
        // a band of +-2 rad/s around w (the branch reaches the --at sample; the polish's
        // cost is per point)
        const double omega = std::stod(w);
        const ::test::Result hb = ::test::run_hbf("frf --quiet --config '" + file + "' --wmin " +
                                                      std::to_string(omega - 2.0) + " --wmax " +
                                                      std::to_string(omega + 2.0) + " --at " + w,
                                                  dir);
        const ::test::Result ti = ::test::run_hbf(
            "timeint --quiet --config '" + file + "' --w " + w + " --method bdf --steady-tol 1e-7", dir);
        INFO("w = " << w << "\nHB: " << hb.err << "\nTI: " << ti.err);
        REQUIRE(hb.exit_code == 0);
        REQUIRE(ti.exit_code == 0);
        CHECK_THAT(hb.err, Catch::Contains("the exact polish ran on the modal form ("));  // the note, kept with --quiet
        auto hb_rows = ::test::parse_csv(hb.out);  // the branch, then the --at sample
        const auto ti_rows = ::test::parse_csv(ti.out);
        const auto point = std::find(hb_rows[0].begin(), hb_rows[0].end(), "point") - hb_rows[0].begin();
        const auto exact = std::find(hb_rows[0].begin(), hb_rows[0].end(), "exact") - hb_rows[0].begin();
        REQUIRE(point < static_cast<long>(hb_rows[0].size()));
        REQUIRE(exact < static_cast<long>(hb_rows[0].size()));
        hb_rows.erase(std::remove_if(hb_rows.begin() + 1, hb_rows.end(),
                                     [&](const std::vector<std::string>& row) { return row[static_cast<std::size_t>(point)] != "sample"; }),
                      hb_rows.end());
        REQUIRE(hb_rows.size() == 2);
        REQUIRE(ti_rows.size() == 2);
        CHECK(hb_rows[1][static_cast<std::size_t>(exact)] == "yes");
        REQUIRE(ti_rows[1][6] == c.regime);
        CHECK(std::stod(ti_rows[1][5]) <= c.max_stick_fraction);
        for (int column : {1, 2}) {  // y99_max (mid-span) and y199_max (tip)
            const double y_ti = std::stod(ti_rows[1][static_cast<std::size_t>(column)]);
            const double y_hb = std::stod(hb_rows[1][static_cast<std::size_t>(column)]);
            const double scale = std::stod(ti_rows[1][1]);  // the tip is ~0 when stuck
            INFO(hb_rows[0][static_cast<std::size_t>(column)] << ": exact " << std::setprecision(12) << y_hb << ", TI "
                                                             << y_ti << ", difference / scale "
                                                             << std::abs(y_hb - y_ti) / scale);
            CHECK(std::abs(y_hb - y_ti) <= 1e-6 * scale);
        }
    }
}
}  // namespace

TEST_CASE("The 200-DOF beam: the exact FRF (modal form) against BDF time integration of the full model in stick, "
          "stick-slip and slip",
          "[condensed][beam][timeint][cli][exact]") {
    // w = 160 rad/s (mostly slip: stuck 7.6 %), and stuck at w = 40 with the 30 N limit; 40 and
    // 75 rad/s in stick-slip in the long tests (the BDF reference at 40 takes 90 s).
    beam_against_bdf({{true, "40", "stick", 1.0}, {false, "160", "stick-slip", 0.1}});
}

TEST_CASE("The 200-DOF beam at 40 and 75 rad/s in stick-slip: the exact FRF against BDF time integration (long: "
          "ctest -L long)",
          "[.long][condensed][beam][timeint][cli][exact]") {
    // 40 rad/s: the tip stuck 55 % of the period.
    beam_against_bdf({{false, "40", "stick-slip", 1.0}, {false, "75", "stick-slip", 1.0}});
}

TEST_CASE("The reduced beam (massless contact shoe, output vector, SI units): the exact polish and harmonic balance "
          "against time integration",
          "[condensed][beam][timeint][massless][cli][exact]") {
    // examples/systems/beam/beam200_reduced.toml: beam200 reduced (Guyan) onto 5 master
    // displacements, plus a massless shoe joined to the tip by a spring and sliding on the
    // ground (exact Coulomb, 3 N); mid-span is the output vector "midspan". Time integration
    // and the exact solver condense the massless shoe statically (it is then a Jenkins
    // element); harmonic balance keeps it as a coordinate (condensed formulation). At w = 40
    // (stick-slip) and 160 rad/s (stick-slip, mostly sliding), and with a 30 N limit at 40
    // (stuck: linear). Reference: hbf timeint --config (Adams, steady-tol 1e-9, atol 1e-11 of the
    // response scale: at the default 1e-10 the stuck case's Poincare change stalls at ~5e-8,
    // the integration's error per period, and never reaches 1e-9). Tolerances
    // relative to each output: stuck 1e-6 (TI keeps the stuck shoe's offset of its transient,
    // ~1e-8); stick-slip by the exact polish (on by default here) 1e-7 (measured 3e-13
    // against tighter TI), by harmonic balance alone (--exact off) 3 % (DLFT at H = 20;
    // measured 0.4 % and 1.1 % at 40, 0.03 % at 160).
    ::test::TempDir dir;
    const std::string reduced = std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/beam200_reduced.toml";
    std::string text = ::test::slurp(reduced);
    const auto limit = text.find("friction_limit = 3\n");
    REQUIRE(limit != std::string::npos);
    text.replace(limit, 19, "friction_limit = 30\n");
    const auto stuck = dir.path / "stuck.toml";
    std::ofstream(stuck) << text;
    struct Case {
        std::string file, omega, range, exact, regime;
        double tolerance;
    };
    const std::vector<Case> cases = {{stuck.string(), "40", "--wmin 35 --wmax 45", "off", "stick", 1e-6},
                                     {reduced, "40", "--wmin 35 --wmax 45", "off", "stick-slip", 3e-2},
                                     {reduced, "160", "--wmin 155 --wmax 165", "off", "stick-slip", 3e-2},
                                     {stuck.string(), "40", "--wmin 35 --wmax 45", "yes", "stick", 1e-6},
                                     {reduced, "40", "--wmin 35 --wmax 45", "yes", "stick-slip", 1e-7},
                                     {reduced, "160", "--wmin 155 --wmax 165", "yes", "stick-slip", 1e-7}};
    for (const Case& c : cases) {
        const ::test::Result hb = ::test::run_hbf("frf --quiet --error-points 0 --config '" + c.file + "' " + c.range +
                                                      (c.exact == "off" ? " --exact off" : "") + " --at " + c.omega,
                                                  dir);
        const ::test::Result ti =
            ::test::run_hbf("timeint --quiet --config '" + c.file + "' --w " + c.omega + " --steady-tol 1e-9 --atol 1e-11", dir);
        INFO("w = " << c.omega << ", exact " << c.exact << "\nHB: " << hb.err << "\nTI: " << ti.err);
        REQUIRE(hb.exit_code == 0);
        REQUIRE(ti.exit_code == 0);
        const auto hb_rows = ::test::parse_csv(hb.out), ti_rows = ::test::parse_csv(ti.out);
        const auto sample = ::test::sample_row(hb_rows, std::stod(c.omega));
        REQUIRE(!sample.empty());
        REQUIRE(ti_rows.size() == 2);
        CHECK(ti_rows[1][6] == c.regime);
        CHECK(sample[6] == c.regime);
        const auto exact_column = std::find(hb_rows[0].begin(), hb_rows[0].end(), "exact") - hb_rows[0].begin();
        CHECK(sample[static_cast<std::size_t>(exact_column)] == c.exact);
        for (std::size_t column : {1, 2, 3, 4}) {  // midspan_max, tip_max, midspan_amp1, tip_amp1
            REQUIRE(hb_rows[0][column] == ti_rows[0][column]);
            const double y_ti = std::stod(ti_rows[1][column]), y_hb = std::stod(sample[column]);
            INFO(hb_rows[0][column] << ": HB " << y_hb << ", TI " << y_ti);
            CHECK(std::abs(y_hb - y_ti) <= c.tolerance * y_ti);
        }
    }
}

TEST_CASE("hbf frf --modes: the beam's FRF by the modal receptance equals the direct solve, and refusals exit 2",
          "[condensed][beam][modal][cli]") {
    // beam200 at H = 20 (harmonics up to 20 x 75 rad/s = 1500 rad/s; mode 40 is near 1.3e6
    // rad/s): the truncation is negligible, the difference is the eigenvectors' rounding
    // (measured 3e-8 mid-span, 1e-7 tip). Tolerance 1e-6 relative. Harmonic balance alone
    // (--exact off): the polish, on by default, would replace both by the exact orbits.
    ::test::TempDir dir;
    const std::string beam = std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/";
    const auto json = dir.path / "s.json";
    const ::test::Result direct =
        ::test::run_hbf("frf --quiet --exact off --error-points 0 --config '" + beam + "beam200.toml' --at 40,60,75", dir);
    const ::test::Result modal = ::test::run_hbf("frf --quiet --exact off --error-points 0 --config '" + beam +
                                                     "beam200.toml' --modes 40 --at 40,60,75 --summary '" +
                                                     json.string() + "'",
                                                 dir);
    INFO(direct.err << modal.err);
    REQUIRE(direct.exit_code == 0);
    REQUIRE(modal.exit_code == 0);
    auto samples = [](const std::string& csv) {
        std::vector<std::vector<std::string>> out;
        for (const auto& row : ::test::parse_csv(csv))
            if (row.size() > 9 && row[9] == "sample") out.push_back(row);
        return out;
    };
    const auto a = samples(direct.out), b = samples(modal.out);
    REQUIRE(a.size() == 3);
    REQUIRE(b.size() == 3);
    for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t column : {1, 2, 3, 4}) {
            INFO("w = " << a[k][0] << ", column " << column);
            CHECK(std::stod(b[k][column]) == Approx(std::stod(a[k][column])).epsilon(1e-6));
        }
    const nlohmann::json summary = nlohmann::json::parse(::test::slurp(json));
    CHECK(summary.at("parameters").at("modes") == 40);
    // Every peak of both outputs refined (the tip's at 36.3 rad/s was not: its bracket holds a
    // corner where Brent settled on a lower local maximum; each side of it alone finds it).
    REQUIRE(summary.at("peaks").size() >= 10);
    for (const auto& p : summary.at("peaks")) {
        INFO(p.dump());
        CHECK(p.at("refined").get<bool>());
    }
    // The reduced beam has a massless shoe: the modal basis needs M > 0.
    const auto out = dir.path / "r.csv";
    const ::test::Result refused = ::test::run_hbf(
        "frf --config '" + beam + "beam200_reduced.toml' --modes 5 --out '" + out.string() + "'", dir);
    CHECK(refused.exit_code == 2);
    CHECK_THAT(refused.err, Catch::Contains("positive definite mass"));
    CHECK(!::test::fs::exists(out));
    const ::test::Result negative = ::test::run_hbf("frf --modes -1", dir);
    CHECK(negative.exit_code == 2);
    CHECK_THAT(negative.err, Catch::Contains("--modes"));
}

namespace {
/// A uniform Euler-Bernoulli cantilever of `elements` Hermite-cubic elements (clamped at x = 0;
/// DOFs 2 i, 2 i + 1 = transverse displacement and rotation of node i + 1), the make_beam.py
/// beam (steel, 1 m, 40 mm x 10 mm), with an exact Coulomb contact at the tip's displacement.
System hermite_cantilever(int elements, double ei, double rho_a, double length) {
    const int n = 2 * elements;
    const double l = length / elements;
    Eigen::Matrix4d ke, me;
    ke << 12, 6 * l, -12, 6 * l, 6 * l, 4 * l * l, -6 * l, 2 * l * l, -12, -6 * l, 12, -6 * l, 6 * l, 2 * l * l,
        -6 * l, 4 * l * l;
    me << 156, 22 * l, 54, -13 * l, 22 * l, 4 * l * l, 13 * l, -3 * l * l, 54, 13 * l, 156, -22 * l, -13 * l,
        -3 * l * l, -22 * l, 4 * l * l;
    ke *= ei / (l * l * l);
    me *= rho_a * l / 420.0;
    std::vector<Eigen::Triplet<double>> k, m;
    for (int e = 0; e < elements; ++e)
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) {
                const int i = 2 * e - 2 + a, j = 2 * e - 2 + b;  // node e's DOFs start at 2 e - 2
                if (i < 0 || j < 0) continue;                    // the clamped node
                k.emplace_back(i, j, ke(a, b));
                m.emplace_back(i, j, me(a, b));
            }
    System s;
    s.stiffness.resize(n, n);
    s.mass.resize(n, n);
    s.stiffness.setFromTriplets(k.begin(), k.end());
    s.mass.setFromTriplets(m.begin(), m.end());
    s.damping = 1e-4 * s.stiffness;
    s.excitation = Eigen::VectorXd::Zero(n);
    s.excitation(n / 2 - 2) = 10.0;  // mid-span
    Contact c;
    c.dof = n - 2;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = 3.0;
    s.contacts.push_back(c);
    return s;
}
}  // namespace

TEST_CASE("The automatic DLFT penalty is the contact's impedance capped by the structure's: mesh-independent",
          "[condensed][beam]") {
    // Hand-derived references. Paper's absorber (r = 0.1, wa = 1): along w = (1, -1) k = w'Kw =
    // 1 + 4 r wa^2 = 1.4 and m = w'Mw = 1.1; the static deflection under a unit contact load is
    // u = K^-1 w = (0, -10): kappa = 1 / (w'u) = 0.1 and phi = u / (w'u) = (0, -1), m_s = r = 0.1,
    // so the cap 30 sqrt(kappa m_s) = 3 leaves sqrt(1.54).
    for (const Formulation f : {Formulation::condensed, Formulation::full}) {
        const HarmonicBalance hb(friction_absorber(AbsorberParameters{}, FrictionLaw::coulomb), {5, 0, f});
        CHECK(std::abs(hb.system().contacts[0].lagrangian_penalty / std::sqrt(1.4 * 1.1) - 1.0) < 1e-14);
    }
    // Cantilever with a tip contact: Hermite cubics represent the static tip-load deflection
    // exactly, so for any number of elements kappa = 3 EI / L^3 and the Rayleigh mass of
    // phi(x) = x^2 (3 L - x) / (2 L^3) is rho A L int_0^1 (xi^2 (3 - xi) / 2)^2 dxi =
    // rho A L (9/5 - 1 + 1/7) / 4 = 33/140 rho A L. The tip node's own sqrt(k m) grows like
    // the number of elements and is capped from 20 elements on: the penalty of 100 and 1000
    // elements is the same 30 sqrt(kappa m_s) (the start of the 1000-element beam failed with
    // sqrt(k m)).
    const double ei = 2.1e11 * 0.04 * 1e-6 / 12.0, rho_a = 7850.0 * 0.04 * 0.01, length = 1.0;
    const double cap = 30.0 * std::sqrt(3.0 * ei / std::pow(length, 3) * 33.0 / 140.0 * rho_a * length);
    for (const int elements : {4, 100, 1000}) {
        const System s = hermite_cantilever(elements, ei, rho_a, length);
        const int tip = s.contacts[0].dof;
        const double own = std::sqrt(s.stiffness.coeff(tip, tip) * s.mass.coeff(tip, tip));
        const HarmonicBalance hb(s, {5, 0, Formulation::automatic});
        INFO(elements << " elements: sqrt(k m) = " << own << ", cap = " << cap);
        CHECK(std::abs(hb.system().contacts[0].lagrangian_penalty / std::min(own, cap) - 1.0) < 1e-9);
        if (elements >= 100) CHECK(own > 5.0 * cap);
        if (elements == 4) CHECK(own < cap);
    }
}

TEST_CASE("The condensed residual is smooth in w at the shifted structure's own resonance (10,000-DOF beam)",
          "[condensed][beam]") {
    // The condensed formulation solves the structure with a spring kappa = 1 / G_0 and a damper
    // delta along each contact (harmonic_balance.cpp). On the cantilever, kappa = 3 EI / L^3 at
    // the tip, and that spring gives the shifted structure a resonance of its own. Derived: the
    // clamped shape W = A (cosh bx - cos bx) + B (sinh bx - sin bx) with W''(L) = 0 and
    // EI W'''(L) = k W(L) has a nonzero (A, B) where
    // EI b^3 (1 + cos bL cosh bL) + k (sin bL cosh bL - cos bL sinh bL) = 0 (k = 0: the
    // cantilever's 1 + cos cosh = 0; k -> inf: clamped-pinned, tan = tanh); with k = 3 EI / L^3,
    // x = bL solves x^3 (1 + cos x cosh x) + 3 (sin x cosh x - cos x sinh x) = 0 between 1.875
    // and 3.927 (x = 2.2135, w = 73.15 rad/s). Fully stuck (a friction limit of 1e9 N), the
    // residual at a fixed X is linear in the receptances, smooth in w: its Taylor remainder
    // R(X, w + d) - R(X, w) - dR/dw d shrinks like d^2. With delta from the tip node's own mass
    // (sqrt(kappa w^T M w) = 0.7 N s/m on 5000 elements, against sqrt(kappa m_s) = 39 N s/m from
    // the static deflection shape) the shifted Z_1 was singular to working precision there: the
    // remainder stayed at 3e-4 to 2e-3 of the force scale for d from 1e-4 w down to 1e-6 w
    // (noise), the corrector found spurious solutions and the continuation stalled.
    const double ei = 2.1e11 * 0.04 * 1e-6 / 12.0, rho_a = 7850.0 * 0.04 * 0.01, length = 1.0;
    auto equation = [](double x) {
        return x * x * x * (1.0 + std::cos(x) * std::cosh(x)) +
               3.0 * (std::sin(x) * std::cosh(x) - std::cos(x) * std::sinh(x));
    };
    double low = 1.875, high = 3.927;
    REQUIRE(equation(low) > 0.0);
    REQUIRE(equation(high) < 0.0);
    for (int i = 0; i < 100; ++i) (equation(0.5 * (low + high)) > 0.0 ? low : high) = 0.5 * (low + high);
    const double x = 0.5 * (low + high), shifted = x * x * std::sqrt(ei / (rho_a * std::pow(length, 4)));
    System s = hermite_cantilever(5000, ei, rho_a, length);
    s.contacts[0].friction_limit = 1e9;
    HarmonicBalance hb(s, {3, 0, Formulation::condensed});
    for (const double offset : {-3e-3, 0.0, 3e-3}) {
        const double w = shifted * (1.0 + offset);
        const Eigen::VectorXd guess = hb.linear_guess(w);
        Eigen::VectorXd r, r_omega, moved;
        Eigen::MatrixXd jacobian;
        hb.evaluate(guess, w, r, &jacobian, &r_omega);
        std::vector<double> remainder;
        for (const double d : {1e-4, 1e-5}) {
            hb.evaluate(guess, w * (1.0 + d), moved);
            remainder.push_back((moved - r - r_omega * (w * d)).cwiseAbs().maxCoeff() / hb.force_scale());
        }
        INFO("w = " << w << " (the shifted resonance " << shifted << "): remainders " << remainder[0] << ", "
                    << remainder[1]);
        // Measured 5.5e-9 and 5.5e-11 at the resonance (second order).
        CHECK(remainder[0] < 1e-7);
        CHECK(remainder[1] < 0.02 * remainder[0]);
    }
}

TEST_CASE("The modal receptance of a refined mesh is exact: a 1000-element cantilever against the closed form",
          "[condensed][beam][modal][receptance]") {
    // The Euler-Bernoulli cantilever's receptance at its free end (deflection per tip force):
    // G(w) = (sin bL cosh bL - cos bL sinh bL) / (EI b^3 (1 + cos bL cosh bL)), b^4 = rho A w^2 /
    // EI (it tends to L^3 / (3 EI) as w -> 0). Hermite elements converge to it like h^4; with
    // 1000 elements the stiffness entries reach 8e12 N/m against lambda_1 ~ 3e3 (the shipped
    // generator's beam2000): Spectra's modes carried their factorisation's rounding and the
    // modal receptance erred by 1e-5 whatever the number of modes, until the subspace sweeps
    // in use_modes. Undamped, at 0.5, 1.7 and 3.9 times the first natural frequency (between
    // the first two modes).
    const double ei = 2.1e11 * 0.04 * 1e-6 / 12.0, rho_a = 7850.0 * 0.04 * 0.01, length = 1.0;
    const double w1 = std::pow(1.87510406871196, 2) * std::sqrt(ei / (rho_a * std::pow(length, 4)));
    auto exact = [&](double omega) {
        const double b = std::pow(rho_a * omega * omega / ei, 0.25), x = b * length;
        return (std::sin(x) * std::cosh(x) - std::cos(x) * std::sinh(x)) /
               (ei * b * b * b * (1.0 + std::cos(x) * std::cosh(x)));
    };
    for (const int elements : {100, 1000}) {
        System s = hermite_cantilever(elements, ei, rho_a, length);
        const int n = s.dofs(), tip = s.contacts[0].dof;
        Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 1), t = Eigen::MatrixXd::Zero(1, n);
        w(tip, 0) = 1.0;
        t(0, tip) = 1.0;
        Receptance modal(s.mass, Eigen::SparseMatrix<double>(n, n), s.stiffness, w, s.excitation, t);
        modal.use_modes(40, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1));
        // The direct sparse solve too: its refinement's residual in double-double (in long
        // double it stalled at 1e-8 on the 1000-element beam: G noisy at 2e-8, 2.4e-7 off).
        Receptance direct(s.mass, Eigen::SparseMatrix<double>(n, n), s.stiffness, w, s.excitation, t);
        for (const double ratio : {0.5, 1.7, 3.9})
            for (Receptance* r : {&modal, &direct}) {
                const Receptance::Harmonic h = r->solve(1, ratio * w1, false, false);
                REQUIRE(h.ok);
                INFO(elements << " elements, w = " << ratio << " w1, " << (r == &modal ? "modal " : "direct ")
                              << h.contact(0, 0).real() << ", exact " << exact(ratio * w1));
                CHECK(std::abs(h.contact(0, 0).imag()) == 0.0);
                // To 1e-8 of the static flexibility L^3 / (3 EI), G's scale (measured 6e-10 at
                // most; 4.7e-6 with 1000 elements before the sweeps).
                CHECK(std::abs(h.contact(0, 0).real() - exact(ratio * w1)) < 1e-8 * std::pow(length, 3) / (3.0 * ei));
            }
    }
}

TEST_CASE("Free motion (nonlinear modes): the residual's exact derivative in xi equals central differences, "
          "direct and modal receptance, exact Coulomb with Dahl and an elastic contact with lift-off",
          "[condensed][modes]") {
    // four_dofs: a massless DOF, exact Coulomb (a multiplier signal) and Dahl (states), the
    // direct solve; liftoff3: an elastic contact (springs shift the receptance), 3 modes.
    const System liftoff = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    struct Case {
        const char* name;
        System system;
        int modes;
    };
    for (const Case& c : {Case{"four_dofs", four_dofs(), 0}, Case{"liftoff3 modal", liftoff, 3},
                          Case{"liftoff3 direct", liftoff, 0}}) {
        HarmonicBalanceOptions options{4, 64, Formulation::condensed};
        options.modes = c.modes;
        HarmonicBalance hb(c.system, options);
        const double omega = 0.83, xi = 0.021, d = 1e-6;
        std::mt19937 rng(3);
        std::normal_distribution<double> normal(0.0, 1.0);
        Eigen::VectorXd x = hb.linear_guess(omega);
        const double size = x.cwiseAbs().maxCoeff();
        for (int k = 0; k < x.size(); ++k) x(k) += 0.5 * size * normal(rng) / (1 + (k % hb.coefficients()));
        Eigen::VectorXd plus, minus, exact;
        hb.set_free_motion(xi + d);
        hb.evaluate(x, omega, plus);
        hb.set_free_motion(xi - d);
        hb.evaluate(x, omega, minus);
        hb.set_free_motion(xi);
        REQUIRE(hb.free_motion_xi_derivative(x, omega, exact));
        const Eigen::VectorXd fd = (plus - minus) / (2 * d);
        INFO(c.name << ": |fd| = " << fd.norm() << ", |exact - fd| = " << (exact - fd).norm());
        CHECK(fd.norm() > 1e-3 * plus.norm());  // xi matters here: not 0 = 0
        CHECK((exact - fd).norm() < 1e-6 * fd.norm());
        // The free response without the N x signals matrix equals the matrix applied.
        const Eigen::VectorXcd lambda = hb.shifted_force_harmonic(x, omega, 1);
        const Eigen::VectorXcd expected = -(hb.contact_response(1, omega) * lambda);
        CHECK((hb.free_response(1, omega, lambda) - expected).norm() < 1e-11 * expected.norm());
    }
}
