// Law polynomial over several coordinates (f_i = sum_k C_ki prod_j q_j^E_kj along directions
// w_1..w_m): against the same springs given one contact each, in physical and in modal
// coordinates, in every analysis (harmonic balance full and condensed, its Jacobian, time
// integration, stability, the backbone, fold tracking), the alias-free N_t of its degree, the
// system file (tables and Matrix Market files) and bad input.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <vector>

#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/modes.hpp"
#include "hbf/stability.hpp"
#include "hbf/time_integration.hpp"
#include "hbf/tracking.hpp"
#include "support.hpp"

using namespace hbf;

namespace several_coordinates {

/// A quartic spring k (L^T y)^4 / 4 along the linear form L of the DOFs (its force on y is
/// -k (L^T y)^3 L): the two-DOF chain's springs, ground - 1 (k = 0.5) and 1 - 2 (k = 1).
struct Spring {
    double k;
    Eigen::Vector2d form;
};
const std::vector<Spring> springs = {{0.5, Eigen::Vector2d(1.0, 0.0)}, {1.0, Eigen::Vector2d(-1.0, 1.0)}};

System chain_structure() {
    System s;
    Eigen::Matrix2d m, k, c;
    m << 1.0, 0.0, 0.0, 2.0;
    k << 2.0, -1.0, -1.0, 2.0;
    c << 0.03, -0.01, -0.01, 0.03;
    s.mass = sparse(m);
    s.stiffness = sparse(k);
    s.damping = sparse(c);
    s.excitation = Eigen::Vector2d(1.0, 0.0);
    return s;
}

/// The reference: each spring its own contact along one direction (law polynomial, cubic).
System one_by_one() {
    System s = chain_structure();
    for (const Spring& spring : springs) {
        Contact c;
        c.law = FrictionLaw::polynomial;
        c.direction = spring.form;
        c.values["cubic"] = spring.k;
        s.contacts.push_back(c);
    }
    return s;
}

/// The same springs as one polynomial of the coordinates q = D^T y (D's columns the
/// directions; y = B q with B = D^-T). In q a spring's form is l = B^T L and its force on q is
/// k (l^T q)^3 l: by the multinomial expansion (l^T q)^3 = sum_{e1 + e2 = 3} 3! / (e1! e2!)
/// l1^e1 l2^e2 q1^e1 q2^e2, a row (e1, e2) with coefficients k 3! / (e1! e2!) l1^e1 l2^e2 l.
/// Acting as -D f on y, the force is -D k (l^T q)^3 B^T L = -k (L^T y)^3 L: the springs'.
System together(const Eigen::Matrix2d& d) {
    System s = chain_structure();
    const Eigen::Matrix2d b = d.transpose().inverse();
    Eigen::MatrixXd exponents(4 * springs.size(), 2), coefficients(4 * springs.size(), 2);
    const double multinomial[4] = {1.0, 3.0, 3.0, 1.0};  // 3! / (e1! (3 - e1)!)
    int row = 0;
    for (const Spring& spring : springs) {
        const Eigen::Vector2d l = b.transpose() * spring.form;
        for (int e1 = 0; e1 <= 3; ++e1, ++row) {
            exponents.row(row) << e1, 3 - e1;
            coefficients.row(row) =
                spring.k * multinomial[e1] * std::pow(l(0), e1) * std::pow(l(1), 3 - e1) * l.transpose();
        }
    }
    Contact c;
    c.law = FrictionLaw::polynomial;
    c.direction = d.col(0);
    c.tables["directions"] = d.col(1).transpose();
    c.tables["exponents"] = exponents;
    c.tables["coefficients"] = coefficients;
    s.contacts.push_back(c);
    return s;
}

/// The physical coordinates q = y, and the modal ones q = Phi^T M y (Phi the mass-normalised
/// modes: y = Phi q), whose polynomial couples every term.
Eigen::Matrix2d physical() { return Eigen::Matrix2d::Identity(); }
Eigen::Matrix2d modal() {
    const System s = chain_structure();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(Eigen::MatrixXd(s.stiffness), Eigen::MatrixXd(s.mass));
    return Eigen::MatrixXd(s.mass) * modes.eigenvectors();
}

FrfSettings settings(int harmonics) {
    FrfSettings f;
    f.harmonic_balance.harmonics = harmonics;
    f.continuation.omega_start = 0.5;
    f.continuation.omega_end = 2.5;
    f.continuation.max_step = 0.05;
    f.error_points = 0;
    f.at = {0.8, 1.0, 1.6};
    f.stability = true;
    f.stability_options.method = StabilityMethod::both;
    return f;
}

std::vector<double> fold_frequencies(const FrfResult& r) {
    std::vector<double> out;
    for (const SolutionPoint& p : r.branch.points)
        if (p.kind == PointKind::fold) out.push_back(p.omega);
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace several_coordinates

TEST_CASE("Polynomial over several coordinates: the harmonic-balance Jacobian equals central differences "
          "(full and condensed formulations)",
          "[force_elements][several]") {
    using namespace several_coordinates;
    for (const Eigen::Matrix2d& d : {physical(), modal()})
        for (const Formulation f : {Formulation::full, Formulation::condensed}) {
            HarmonicBalanceOptions o{4, 64};
            o.formulation = f;
            HarmonicBalance hb(together(d), o);
            std::mt19937 rng(7);
            std::normal_distribution<double> normal(0.0, 1.0);
            const double omega = 1.1;
            Eigen::VectorXd x = hb.linear_guess(omega);
            for (int k = 0; k < x.size(); ++k) x(k) += 0.5 * normal(rng) / (1 + (k % hb.coefficients()));
            Eigen::VectorXd r, dr_domega, fd_omega;
            Eigen::MatrixXd J, fd;
            hb.evaluate(x, omega, r, &J, &dr_domega);
            test::central_differences(hb, x, omega, fd, fd_omega);
            INFO("formulation " << (f == Formulation::full ? "full" : "condensed") << ", modal " << (d != physical()));
            CHECK(test::relative_error(J, fd) < 1e-7);  // a polynomial: central differences' error is O(h^2) only
            CHECK(test::relative_error(dr_domega, fd_omega) < 1e-7);
        }
}

TEST_CASE("Polynomial over several coordinates equals its springs given one by one: FRF, folds and stability "
          "(full and condensed), time integration, backbone, in physical and modal coordinates",
          "[force_elements][several]") {
    using namespace several_coordinates;
    const System reference = one_by_one();
    const FrfResult expected = compute_frf(reference, settings(7));
    INFO(expected.summary());
    REQUIRE(expected.status() == "completed");
    const std::vector<double> expected_folds = fold_frequencies(expected);
    REQUIRE(expected_folds.size() >= 2);
    for (const Eigen::Matrix2d& d : {physical(), modal()}) {
        const System s = together(d);
        for (const Formulation f : {Formulation::full, Formulation::condensed}) {
            FrfSettings o = settings(7);
            o.harmonic_balance.formulation = f;
            const FrfResult r = compute_frf(s, o);
            INFO("modal " << (d != physical()) << ", formulation " << (f == Formulation::full ? "full" : "condensed")
                          << ": " << r.summary());
            REQUIRE(r.status() == "completed");
            // The samples at the same frequencies: every solution there, the same outputs.
            const auto samples = [](const FrfResult& x) {
                std::vector<std::pair<double, double>> out;  // (w, y1_max)
                for (std::size_t i = 0; i < x.points.size(); ++i)
                    if (x.points[i].kind == PointKind::sample) out.emplace_back(x.points[i].omega, x.metrics[i].y_max[0]);
                std::sort(out.begin(), out.end());
                return out;
            };
            const auto got = samples(r), want = samples(expected);
            REQUIRE(got.size() == want.size());
            REQUIRE(got.size() >= 3);
            for (std::size_t i = 0; i < got.size(); ++i) {
                CHECK(got[i].first == Approx(want[i].first).epsilon(1e-12));
                CHECK(test::relative_difference(got[i].second, want[i].second) <= 1e-8);
            }
            // The folds where the reference's are, each with the stability changing there.
            const std::vector<double> folds = fold_frequencies(r);
            REQUIRE(folds.size() == expected_folds.size());
            for (std::size_t i = 0; i < folds.size(); ++i) CHECK(std::abs(folds[i] - expected_folds[i]) <= 1e-7);
            REQUIRE(r.stability);
            REQUIRE(expected.stability);
            // The verdicts at the samples (the same solutions, so the same multipliers).
            auto verdicts = [](const FrfResult& x) {
                std::vector<std::pair<double, Stability>> out;
                for (std::size_t i = 0; i < x.points.size(); ++i)
                    if (x.points[i].kind == PointKind::sample)
                        out.emplace_back(x.metrics[i].y_max[0], x.stability->points[i].stability);
                std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                return out;
            };
            const auto vr = verdicts(r), ve = verdicts(expected);
            int unstable = 0;
            for (std::size_t i = 0; i < vr.size(); ++i) {
                CHECK(vr[i].second == ve[i].second);
                unstable += vr[i].second == Stability::unstable;
            }
            CHECK(unstable >= 1);  // the middle solution at w = 1.6
            // The energy balance closes: a conservative polynomial does no net work.
            for (const PointMetrics& m : r.metrics) CHECK(std::abs(m.energy_error) <= 1e-6);
        }
        // Time integration of the polynomial against the springs' (both in time) and against
        // harmonic balance at H = 15 (its truncation) at w = 0.5, below the folds.
        const PeriodicResponse ti = integrate_steady_state(s, 0.5, test::tight_time_integration());
        const PeriodicResponse ti_reference = integrate_steady_state(reference, 0.5, test::tight_time_integration());
        INFO(ti.summary());
        REQUIRE(ti.converged);
        REQUIRE(ti_reference.converged);
        for (int i = 0; i < 2; ++i)
            CHECK(test::relative_difference(ti.y_max[static_cast<std::size_t>(i)],
                                            ti_reference.y_max[static_cast<std::size_t>(i)]) <= 1e-8);
        HarmonicBalance hb(s, HarmonicBalanceOptions{15, 0});
        const SolutionAt at = solve_at(hb, 0.5, 0.5);
        REQUIRE(at.found);
        const PointMetrics pm = Analyser(hb)(at.point);
        CHECK(test::relative_difference(pm.y_max[0], ti.y_max[0]) <= 1e-6);
        CHECK(test::relative_difference(pm.y_max[1], ti.y_max[1]) <= 1e-6);
        // The first nonlinear mode from the same start to the same end.
        ModeOptions mo;
        mo.amplitude_min = 1e-2;
        mo.amplitude_max = 1.0;
        const ModeRun mode = compute_mode(s, HarmonicBalanceOptions{7, 0}, mo, {}, false);
        const ModeRun mode_reference = compute_mode(reference, HarmonicBalanceOptions{7, 0}, mo, {}, false);
        INFO(mode.backbone.message);
        REQUIRE(mode.backbone.status == ModeStatus::completed);
        REQUIRE(mode_reference.backbone.status == ModeStatus::completed);
        for (const bool last : {false, true}) {
            const ModePoint& p = last ? mode.backbone.points.back() : mode.backbone.points.front();
            const ModePoint& q = last ? mode_reference.backbone.points.back() : mode_reference.backbone.points.front();
            CHECK(p.amplitude == Approx(q.amplitude).epsilon(1e-12));
            CHECK(test::relative_difference(p.omega, q.omega) <= 1e-8);
            CHECK(std::abs(p.xi - q.xi) <= 1e-8 * q.omega);
        }
        CHECK(mode.backbone.points.back().omega > 1.01 * mode.backbone.points.front().omega);  // hardening
        for (const ModeMetrics& m : mode.metrics) CHECK(m.energy_error <= 1e-6);
    }
}

TEST_CASE("Polynomial over several coordinates: hbf track follows the folds through the force to their cusp "
          "where the springs' are",
          "[force_elements][several][tracking][cli]") {
    using namespace several_coordinates;
    test::TempDir dir;
    // The chain as system files: the springs one by one, and one polynomial of y1, y2 whose
    // terms are (y1 - y2)^3 expanded by hand plus the ground spring on y1.
    const std::string structure = R"(
[structure]
mass = [1.0, 2.0]
stiffness = [[2.0, -1.0], [-1.0, 2.0]]
damping = [[0.03, -0.01], [-0.01, 0.03]]
excitation = [1.0, 0.0]
[frequency]
wmin = 0.3
wmax = 1.0
[solver]
harmonics = 5
)";
    test::write_file(dir.path / "springs.toml", structure + R"(
[[contact]]
dof = 1
law = "polynomial"
cubic = 0.5
[[contact]]
dof = 2
other_dof = 1
law = "polynomial"
cubic = 1.0
)");
    test::write_file(dir.path / "together.toml", structure + R"(
[[contact]]
dof = 1
law = "polynomial"
directions = [[0.0, 1.0]]
exponents = [[3, 0], [2, 1], [1, 2], [0, 3]]
coefficients = [[1.5, -1.0], [-3.0, 3.0], [3.0, -3.0], [-1.0, 1.0]]
)");
    auto cusp = [&](const std::string& name) {
        const test::Result r = test::run_hbf("track --config '" + (dir.path / name).string() +
                                                 "' --feature fold --param fe --range 1:0.3 --quiet --error-points 0",
                                             dir);
        INFO(name << ": " << r.err);
        CHECK(r.exit_code == 0);
        const auto rows = test::parse_csv(r.out);
        REQUIRE(rows.size() > 2);
        const auto& header = rows.front();
        const auto kind = static_cast<std::size_t>(std::find(header.begin(), header.end(), "kind") - header.begin());
        for (std::size_t k = 1; k < rows.size(); ++k)
            if (rows[k].size() > kind && rows[k][kind] == "cusp")
                return std::make_pair(test::column(rows, rows[k], "fe"), test::column(rows, rows[k], "w"));
        FAIL("no cusp");
        return std::make_pair(0.0, 0.0);
    };
    const auto expected = cusp("springs.toml"), got = cusp("together.toml");
    CHECK(expected.first < 0.9);
    // The cusp is located by bisection in p on whether a local branch still shows the S, whose
    // width shrinks like (p - p_c)^(3/2): the two formulations' branches step differently and
    // resolve it to a few 1e-4 in p (measured 1.8e-4 apart), the frequency far better.
    CHECK(test::relative_difference(got.first, expected.first) <= 1e-3);
    CHECK(test::relative_difference(got.second, expected.second) <= 1e-4);
}

TEST_CASE("Polynomial over several coordinates: N_t from the largest row sum, and the stuck springs of its "
          "linear terms",
          "[force_elements][several]") {
    Contact c;
    c.law = FrictionLaw::polynomial;
    c.dof = 0;
    c.tables["directions"] = Eigen::RowVector3d(0.0, 1.0, 0.0);
    Eigen::MatrixXd e(3, 2), k(3, 2);
    e << 2, 3,  // degree 5
        1, 0,   // a linear term on q1
        0, 1;   // and on q2
    k << 1.0, -2.0, 0.7, 0.0, 0.0, 0.3;
    c.tables["exponents"] = e;
    c.tables["coefficients"] = k;
    System s;
    s.mass = sparse(Eigen::Matrix3d::Identity());
    s.stiffness = sparse(Eigen::Matrix3d::Identity());
    s.damping = sparse(Eigen::Matrix3d::Zero());
    s.excitation = Eigen::Vector3d(1.0, 0.0, 0.0);
    s.contacts.push_back(c);
    REQUIRE_NOTHROW(s.validate());
    CHECK(s.contact_directions(c).cols() == 2);
    const std::unique_ptr<FrictionModel> model = make_friction_model(c);
    CHECK(model->signals() == 2);
    Fourier fourier(10, 128);
    CHECK(model->time_samples_needed(fourier, 1.0, Eigen::VectorXd::Zero(42)) == (5 + 1) * 10 + 1);
    CHECK_THAT(model->time_samples_reason(), Catch::Contains("degree 5"));
    const std::vector<StuckElement> stuck = contact_law(c.law).stuck_directions(c);
    REQUIRE(stuck.size() == 2);
    CHECK(stuck[0].stiffness == 0.7);
    CHECK(stuck[1].stiffness == 0.3);
    // The static force and its Jacobian at q = (0.5, -1): f_1 = q1^2 q2^3 + 0.7 q1,
    // f_2 = -2 q1^2 q2^3 + 0.3 q2 (derived by hand).
    StaticForce f;
    REQUIRE(contact_law(c.law).static_force(c, Eigen::Vector2d(0.5, -1.0), f));
    CHECK(f.force(0) == Approx(0.25 * -1.0 + 0.35));
    CHECK(f.force(1) == Approx(-2.0 * 0.25 * -1.0 - 0.3));
    CHECK(f.jacobian(0, 0) == Approx(2 * 0.5 * -1.0 + 0.7));
    CHECK(f.jacobian(0, 1) == Approx(0.25 * 3.0));
    CHECK(f.jacobian(1, 0) == Approx(-2.0 * 2 * 0.5 * -1.0));
    CHECK(f.jacobian(1, 1) == Approx(-2.0 * 0.25 * 3.0 + 0.3));
}

TEST_CASE("Polynomial over several coordinates in a system file: tables and Matrix Market files, the same FRF, "
          "bad tables refused naming the key",
          "[force_elements][several][config]") {
    using namespace several_coordinates;
    test::TempDir dir;
    const std::string structure = R"(
[structure]
mass = [[1.0, 0.0], [0.0, 2.0]]
stiffness = [[2.0, -1.0], [-1.0, 2.0]]
damping = [[0.03, -0.01], [-0.01, 0.03]]
excitation = [1.0, 0.0]
[frequency]
wmin = 0.5
wmax = 2.5
[solver]
harmonics = 5
)";
    // The physical coordinates: (y1 - y2)^3 expanded by hand, the ground spring on q1.
    const std::string contact = R"(
[[contact]]
dof = 1
law = "polynomial"
directions = [[0.0, 1.0]]
)";
    const std::string tables = R"(exponents = [[3, 0], [2, 1], [1, 2], [0, 3]]
coefficients = [[1.5, -1.0], [-3.0, 3.0], [3.0, -3.0], [-1.0, 1.0]]
)";
    test::write_file(dir.path / "tables.toml", structure + contact + tables);
    test::write_file(dir.path / "exponents.mtx", "%%MatrixMarket matrix array real general\n4 2\n3\n2\n1\n0\n0\n1\n2\n3\n");
    test::write_file(dir.path / "coefficients.mtx",
                     "%%MatrixMarket matrix array real general\n4 2\n1.5\n-3\n3\n-1\n-1\n3\n-3\n1\n");
    test::write_file(dir.path / "files.toml",
                     structure + contact + "exponents = \"exponents.mtx\"\ncoefficients = \"coefficients.mtx\"\n");
    const System reference = one_by_one();
    for (const char* name : {"tables.toml", "files.toml"}) {
        INFO(name);
        const io::SystemConfig config = io::read_system_config((dir.path / name).string());
        REQUIRE(config.system.contacts.size() == 1);
        const Contact& c = config.system.contacts.front();
        REQUIRE(c.tables.count("exponents") == 1);
        CHECK(c.tables.at("exponents").rows() == 4);
        CHECK(config.system.contact_directions(c).cols() == 2);
        // The default outputs are both coordinates' DOFs.
        CHECK(config.outputs.size() == 2);
        HarmonicBalance hb(config.system, HarmonicBalanceOptions{5, 0});
        HarmonicBalance hb_reference(reference, HarmonicBalanceOptions{5, 0});
        const SolutionAt at = solve_at(hb, 1.2, 0.5), at_reference = solve_at(hb_reference, 1.2, 0.5);
        REQUIRE(at.found);
        REQUIRE(at_reference.found);
        CHECK(test::relative_difference(Analyser(hb)(at.point).y_max[1], Analyser(hb_reference)(at_reference.point).y_max[1]) <= 1e-9);
    }
    const std::filesystem::path bad = dir.path / "bad.toml";
    auto refused = [&](const std::string& text, const std::vector<std::string>& parts) {
        test::check_refused_config(bad, structure + contact + text, parts);
    };
    refused("exponents = [[3, 0], [2.5, 1]]\ncoefficients = [[1, 0], [1, 0]]\n", {"exponents[2]", "2.5", "0..15"});
    refused("exponents = [[3, 0], [-1, 1]]\ncoefficients = [[1, 0], [1, 0]]\n", {"exponents[2]", "-1"});
    refused("exponents = [[9, 7]]\ncoefficients = [[1, 0]]\n", {"exponents[1]", "degree (row sum) 16", "1..15"});
    refused("exponents = [[0, 0]]\ncoefficients = [[1, 0]]\n", {"exponents[1]", "static_load"});
    refused("exponents = [[3, 0]]\ncoefficients = [[nan, 0]]\n", {"coefficients[1]", "finite"});
    refused("exponents = [[3, 0]]\ncoefficients = [[1, 0], [1, 0]]\n", {"coefficients", "2 rows", "allowed 1"});
    refused("exponents = [[3, 0, 1]]\ncoefficients = [[1, 0, 0]]\n", {"exponents", "3 columns", "allowed 2"});
    refused("exponents = [[3, 0]]\n", {"coefficients is missing"});
    refused("", {"directions", "without exponents"});
    refused("exponents = [[0, 1]]\ncoefficients = [[1, 0]]\n", {"coefficients[1]", "linear term", "stiffness matrix K"});
    refused("exponents = [[3, 0], [2, 1]\ncoefficients = [[1, 0]]\n", {"bad.toml"});  // not TOML
    test::check_refused_config(bad, structure + "[[contact]]\ndof = 1\nlaw = \"polynomial\"\ndirections = [[0.0, 1.0, 0.0]]\n" + tables,
                               {"directions", "allowed 2"});
    test::check_refused_config(bad, structure + "[[contact]]\ndof = 1\nlaw = \"polynomial\"\ndirections = [[0.0, 0.0]]\n" + tables,
                               {"directions[1]", "not all zero"});
    test::check_refused_config(bad, structure + "[[contact]]\ndof = 1\nlaw = \"jenkins\"\nfriction_limit = 1.0\nstiffness = 1.0\n" + tables,
                               {"does not apply to law 'jenkins'"});
}

// NLvib's sixth example (examples/systems/nlvib/two_springs.toml): the quadratic and cubic
// geometric stiffness of a mass on two orthogonal springs, one polynomial of both modal
// coordinates.
TEST_CASE("NLvib's mass on two springs with geometric stiffness: harmonic balance equals time integration at "
          "three frequencies, the backbone leaves w1 softening and passes through the FRF's peak",
          "[force_elements][several]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/nlvib/two_springs.toml");
    const System& s = config.system;
    REQUIRE(s.contact_directions(s.contacts.front()).cols() == 2);
    FrfSettings f;
    f.harmonic_balance.harmonics = 7;
    f.continuation.omega_start = 1.0;
    f.continuation.omega_end = 1.2;
    f.error_points = 0;
    f.at = {1.0, 1.1, 1.2};  // single-valued there (the folds lie near 1.1273 and 1.1285)
    f.outputs = {Output::dof(0), Output::dof(1)};
    const FrfResult r = compute_frf(s, f);
    INFO(r.summary());
    REQUIRE(r.status() == "completed");
    HarmonicBalance hb(s, HarmonicBalanceOptions{7, 0});
    Analyser analyse(hb);
    int compared = 0;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
        if (r.points[i].kind != PointKind::sample) continue;
        const double w = r.points[i].omega;
        const PeriodicResponse ti = integrate_steady_state(s, w, test::tight_time_integration());
        INFO("w = " << w << ": " << ti.summary());
        REQUIRE(ti.converged);
        for (int k = 0; k < 2; ++k)
            CHECK(test::relative_difference(r.metrics[i].output_max[static_cast<std::size_t>(k)],
                                            ti.y_max[static_cast<std::size_t>(k)]) <= 1e-5);
        ++compared;
    }
    CHECK(compared == 3);
    // The backbone: from w1 = 1.13 at small amplitude, softening; at the FRF's peak amplitude
    // its frequency is the peak's (damping 0.1 %: the peak lies on the backbone to O(zeta)).
    ModeOptions mo;
    mo.amplitude_min = 1e-3;
    mo.amplitude_max = 0.3;
    const ModeRun mode = compute_mode(s, HarmonicBalanceOptions{7, 0}, mo, {Output::dof(0)}, false);
    INFO(mode.backbone.message);
    REQUIRE(mode.backbone.status == ModeStatus::completed);
    CHECK(std::abs(mode.backbone.points.front().omega - 1.13) <= 1e-4 * 1.13);
    CHECK(mode.backbone.points.back().omega < 1.12);
    REQUIRE(!r.peaks.empty());
    const double peak_w = r.peak.omega, peak_amplitude = [&] {
        double best = 0.0;
        for (const PointMetrics& m : r.metrics) best = std::max(best, m.output_amp1[0]);
        return best;
    }();
    double backbone_w = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 1; i < mode.metrics.size(); ++i) {
        const double a0 = mode.metrics[i - 1].output_amp1[0], a1 = mode.metrics[i].output_amp1[0];
        if ((a0 - peak_amplitude) * (a1 - peak_amplitude) <= 0.0 && a1 != a0) {
            const double t = (peak_amplitude - a0) / (a1 - a0);
            backbone_w = mode.backbone.points[i - 1].omega + t * (mode.backbone.points[i].omega - mode.backbone.points[i - 1].omega);
            break;
        }
    }
    INFO("peak at w = " << peak_w << ", amplitude " << peak_amplitude << "; backbone there " << backbone_w);
    CHECK(std::abs(backbone_w - peak_w) <= 1e-3 * peak_w);
}
