// Cyclic symmetry (cyclic.hpp): a lumped bladed disk of N = 12 sectors, each a disk mass, a
// platform and a blade tip, the disks coupled to their neighbours and a friction contact
// between neighbouring platforms (across the cut). The references are the whole wheel
// assembled here by hand from the same sector: its eigenvalues for the nodal-diameter
// families, and its harmonic-balance residual and Newton's method for the forced response.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "../benchmarks/lumped_wheel.hpp"
#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/modes.hpp"
#include "hbf/optimize.hpp"
#include "hbf/reduction.hpp"
#include "hbf/tracking.hpp"
#include "hbf/stability.hpp"
#include "hbf/time_integration.hpp"

using namespace hbf;

namespace {

using bench::lumped_sector;
using bench::lumped_wheel;
using bench::wheel_dof;

std::vector<double> sorted_frequencies(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k, m);
    std::vector<double> out;
    for (Eigen::Index i = 0; i < solver.eigenvalues().size(); ++i) out.push_back(std::sqrt(solver.eigenvalues()(i)));
    std::sort(out.begin(), out.end());
    return out;
}

/// Every frequency of the family, each nodal diameter d counted for the wheel's harmonic
/// indices d and N - d (once for d = 0 and d = N / 2).
std::vector<double> family_spectrum(const NodalDiameterFamily& family) {
    std::vector<double> out;
    for (Eigen::Index d = 0; d < family.frequencies.rows(); ++d) {
        const int copies = d == 0 || 2 * d == family.sectors ? 1 : 2;
        for (Eigen::Index j = 0; j < family.frequencies.cols(); ++j)
            if (std::isfinite(family.frequencies(d, j)))
                for (int c = 0; c < copies; ++c) out.push_back(family.frequencies(d, j));
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("Cyclic symmetry: the nodal-diameter families of a sector are the eigenvalues of the whole wheel",
          "[cyclic]") {
    for (int n : {12, 7}) {  // an even and an odd number of sectors
        const System s = lumped_sector(n, 3, 0.1);
        const System w = lumped_wheel(s);
        // released: M, K
        const std::vector<double> wheel_released = sorted_frequencies(Eigen::MatrixXd(w.stiffness), Eigen::MatrixXd(w.mass));
        const std::vector<double> released = family_spectrum(nodal_diameter_family(s, false));
        REQUIRE(released.size() == wheel_released.size());
        for (std::size_t i = 0; i < released.size(); ++i)
            CHECK(std::abs(released[i] - wheel_released[i]) <= 1e-10 * wheel_released[i]);
        // stuck: every contact's spring k_t added along its direction
        Eigen::MatrixXd k(w.stiffness);
        for (const Contact& c : w.contacts) {
            const Eigen::VectorXd d = w.contact_direction(c);
            k += c.stiffness * d * d.transpose();
        }
        const std::vector<double> wheel_stuck = sorted_frequencies(k, Eigen::MatrixXd(w.mass));
        const std::vector<double> stuck = family_spectrum(nodal_diameter_family(s, true));
        REQUIRE(stuck.size() == wheel_stuck.size());
        for (std::size_t i = 0; i < stuck.size(); ++i)
            CHECK(std::abs(stuck[i] - wheel_stuck[i]) <= 1e-10 * wheel_stuck[i]);
        // the contacts join neighbouring platforms: stiffer in every nodal diameter but 0
        const NodalDiameterFamily r = nodal_diameter_family(s, false), t = nodal_diameter_family(s, true);
        CHECK(std::abs(t.frequencies(0, 0) - r.frequencies(0, 0)) <= 1e-12 * r.frequencies(0, 0));
        CHECK(t.frequencies(n / 2, 0) > 1.01 * r.frequencies(n / 2, 0));
    }
    CHECK(nodal_diameter(lumped_sector(12, 3, 0.1).cyclic, 1) == 3);
    CHECK(nodal_diameter(lumped_sector(12, 3, 0.1).cyclic, 3) == 3);  // 9 = 12 - 3
    CHECK(nodal_diameter(lumped_sector(12, 5, 0.1).cyclic, 2) == 2);  // 10 = 12 - 2
}

namespace {

/// The sector's FRF over the first mode of the engine order's nodal diameter (released to stuck)
/// at H harmonics and a corrector tolerance of 1e-12, and every point placed on the whole
/// wheel assembled by hand (sector j delayed by j phi / omega): the wheel's harmonic-balance
/// residual there, with the travelling force, and how far Newton's method on the wheel moves it.
struct WheelCheck {
    FrfResult frf;
    double residual = 0, change = 0;  ///< largest, relative to the force and to the state
};
WheelCheck against_the_wheel(const System& s, int harmonics, Formulation formulation = Formulation::full) {
    const int n = s.cyclic.sectors, own = bench::own_dofs(s), d = nodal_diameter(s.cyclic, 1);
    const NodalDiameterFamily released = nodal_diameter_family(s, false), stuck = nodal_diameter_family(s, true);
    FrfChoices choices;
    choices.omega_start = 0.8 * released.frequencies(d, 0);
    choices.omega_end = 1.2 * stuck.frequencies(d, 0);
    choices.harmonics = harmonics;
    FrfSettings settings = frf_settings(s, {Output::dof(2)}, choices);
    settings.continuation.corrector.tolerance = 1e-12;
    settings.error_points = 0;
    settings.harmonic_balance.formulation = formulation;
    CHECK_FALSE(settings.exact);  // the polish does not take a sector: harmonic balance's FRF
    WheelCheck out;
    out.frf = compute_frf(s, settings);
    HarmonicBalanceOptions o;
    o.harmonics = harmonics;
    o.formulation = formulation;
    HarmonicBalance sector_hb(s, o);
    REQUIRE(sector_hb.formulation() == formulation);
    o.formulation = Formulation::full;
    const System w = lumped_wheel(s);
    HarmonicBalance wheel_hb(w, o);
    const int coefficients = 2 * harmonics + 1;
    const double phi = s.cyclic.phase();
    for (std::size_t p = 0; p < out.frf.points.size(); ++p) {
        const double omega = out.frf.points[p].omega;
        const Eigen::MatrixXd y = sector_hb.dofs(out.frf.points[p].x, omega);  // every sector DOF's harmonics
        const Eigen::VectorXd x = bench::placed_on_wheel(s, y);
        // The residual with the travelling force's sine part: -F sin(j phi) on each sin 1 row.
        auto residual = [&](const Eigen::VectorXd& at, Eigen::MatrixXd* jacobian) {
            Eigen::VectorXd r;
            wheel_hb.evaluate(at, omega, r, jacobian);
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < own; ++i)
                    r(wheel_dof(s, j, i) * coefficients + 2) -= s.excitation(i) * std::sin(j * phi);
            return r;
        };
        const double scale = s.excitation.cwiseAbs().maxCoeff();
        Eigen::VectorXd r = residual(x, nullptr);
        out.residual = std::max(out.residual, r.cwiseAbs().maxCoeff() / scale);
        // Newton's method on the wheel from there: it stays (the wheel's own solution).
        Eigen::VectorXd z = x;
        for (int it = 0; it < 4; ++it) {
            Eigen::MatrixXd jac;
            r = residual(z, &jac);
            z -= jac.partialPivLu().solve(r);
        }
        out.change = std::max(out.change, (z - x).cwiseAbs().maxCoeff() / x.cwiseAbs().maxCoeff());
    }
    return out;
}

}  // namespace

TEST_CASE("Cyclic symmetry: the sector's harmonic balance is the whole wheel's, at every point of an FRF "
          "through stick, stick-slip and slip, in the full and the condensed formulation",
          "[cyclic]") {
    const Formulation formulation = GENERATE(Formulation::full, Formulation::condensed);
    INFO("formulation " << to_string(formulation));
    const WheelCheck c = against_the_wheel(lumped_sector(12, 3, 0.05), 5, formulation);
    INFO(c.frf.summary());
    REQUIRE(c.frf.status() == "completed");
    REQUIRE(c.frf.points.size() >= 20);
    std::set<std::string> regimes;
    for (const PointMetrics& p : c.frf.metrics) regimes.insert(p.regime);
    CHECK(regimes == std::set<std::string>{"stick", "stick-slip", "slip"});
    INFO("largest wheel residual " << c.residual << ", largest Newton change " << c.change);
    CHECK(c.residual <= 1e-11);
    CHECK(c.change <= 1e-10);
}

TEST_CASE("Cyclic symmetry: with law elastic across the cut, the sector's harmonic balance is the whole "
          "wheel's through stick, slip and lift-off, in the full and the condensed formulation",
          "[cyclic]") {
    const Formulation formulation = GENERATE(Formulation::full, Formulation::condensed);
    INFO("formulation " << to_string(formulation));
    const WheelCheck c = against_the_wheel(bench::lumped_sector_elastic(12, 3, 0.3), 5, formulation);
    INFO(c.frf.summary());
    REQUIRE(c.frf.status() == "completed");
    // The normal force on the platforms opens the contact over part of the period at every
    // frequency of the band; it sticks, slips and opens within one period.
    double open = 1.0, stuck = 0.0, slipping = 0.0;
    for (const PointMetrics& p : c.frf.metrics) {
        const ContactRegime& r = p.contacts[0];
        open = std::min(open, r.separated_fraction);
        stuck = std::max(stuck, r.stick_fraction);
        slipping = std::max(slipping, 1.0 - r.stick_fraction - r.separated_fraction);
    }
    INFO("smallest open share " << open << ", largest stuck share " << stuck << ", largest slipping share " << slipping);
    CHECK(open > 0.05);
    CHECK(stuck > 0.2);
    CHECK(slipping > 0.2);
    INFO("largest wheel residual " << c.residual << ", largest Newton change " << c.change);
    CHECK(c.residual <= 1e-11);
    CHECK(c.change <= 1e-10);
}

TEST_CASE("Cyclic symmetry: bad sectors are refused naming the field, and the computations that do not take "
          "a sector say so",
          "[cyclic]") {
    auto refused = [](System s, const std::string& what) {
        CHECK_THROWS_WITH(s.validate(), Catch::Contains(what));
    };
    System s = lumped_sector(12, 3, 0.1);
    s.cyclic.sectors = 1;
    refused(s, "sectors = 1 is out of range: allowed >= 2");
    s = lumped_sector(12, 12, 0.1);
    refused(s, "engine_order = 12 is out of range: allowed 0..11");
    s = lumped_sector(12, 3, 0.1);
    s.cyclic.neighbours.push_back({3, 2});
    refused(s, "DOF 4 is listed twice");
    s = lumped_sector(12, 3, 0.1);
    s.cyclic.neighbours = {{3, 0}, {4, 3}};
    refused(s, "DOF 4 is the next sector's image of DOF 5");  // a master that is itself dependent
    s = lumped_sector(12, 3, 0.1);
    s.cyclic.neighbours = {{3, 7}};
    refused(s, "names a DOF outside the model: allowed 1..5");
    s = lumped_sector(12, 3, 0.1);
    s.excitation(4) = 1.0;
    refused(s, "the excitation loads DOF 5, a DOF of the next sector");

    // a sector too large for the dense families is refused before the work
    System large = lumped_sector(12, 3, 0.1);
    const int big = nodal_diameter_dof_limit + 3;
    Eigen::VectorXd diagonal = Eigen::VectorXd::Ones(big);
    diagonal(big - 2) = 0.0;  // the next sector's copies carry no mass
    diagonal(big - 1) = 0.0;
    large.mass = sparse(Eigen::MatrixXd(diagonal.asDiagonal()));
    large.stiffness = large.mass;
    large.damping = SparseMatrix(big, big);
    large.excitation = Eigen::VectorXd::Zero(big);
    large.excitation(0) = 1.0;
    large.contacts.clear();
    large.cyclic.neighbours = {{big - 2, 0}, {big - 1, 1}};
    CHECK_THROWS_WITH(nodal_diameter_family(large, false), Catch::Contains("allowed up to 2000"));

    const System ok = lumped_sector(12, 3, 0.1);
    HarmonicBalanceOptions o;
    o.harmonics = 3;
    o.formulation = Formulation::condensed;
    o.modes = 2;  // the condensed formulation takes a sector with the direct solve only
    CHECK_THROWS_WITH(HarmonicBalance(ok, o), Catch::Contains("the modal receptance does not take a sector model"));
    o.modes = 0;
    CHECK(HarmonicBalance(ok, o).formulation() == Formulation::condensed);
    o.formulation = Formulation::automatic;  // automatic: the full formulation for a sector
    CHECK(HarmonicBalance(ok, o).formulation() == Formulation::full);
    CHECK_THROWS_WITH(integrate_steady_state(ok, 2.0, TimeIntegrationOptions{}),
                      Catch::Contains("not available for a sector model"));
    CHECK_FALSE(stability_refusal(ok).empty());
    CHECK_THROWS_WITH(stuck_modes(ok), Catch::Contains("not available for a sector model"));
}

TEST_CASE("Cyclic symmetry in a system file: [cyclic], neighbour_dof, hbf frf and hbf nodal-diameters on the "
          "bladed-disk example, and bad tables refused naming the key",
          "[cyclic]") {
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/bladed_disk/wheel24.toml";
    const io::SystemConfig config = io::read_system_config(example);
    const System& s = config.system;
    // The file's 5 DOFs and the next sector's platform, added for the damper across the cut.
    REQUIRE(s.dofs() == 6);
    CHECK(s.cyclic.sectors == 24);
    CHECK(s.cyclic.engine_order == 3);
    REQUIRE(s.cyclic.neighbours.size() == 2);
    CHECK(s.cyclic.neighbours[0] == std::make_pair(4, 0));  // right = [5] is the next sector's left = [1]
    CHECK(s.cyclic.neighbours[1] == std::make_pair(5, 1));  // neighbour_dof = 2: the next sector's platform
    REQUIRE(s.contacts.size() == 1);
    CHECK(s.contacts[0].dof == 1);
    CHECK(s.contacts[0].other_dof == 5);
    CHECK(Eigen::MatrixXd(s.mass).row(5).cwiseAbs().maxCoeff() == 0.0);
    CHECK(Eigen::MatrixXd(s.stiffness).row(5).cwiseAbs().maxCoeff() == 0.0);
    CHECK(config.outputs.size() == 2);  // [output] report = [4, 2]

    test::TempDir dir;
    const std::string out = (dir.path / "nd.csv").string();
    test::Result r = test::run_hbf("nodal-diameters --config '" + example + "' --out '" + out + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto rows = test::parse_csv(test::slurp(out));
    const NodalDiameterFamily released = nodal_diameter_family(s, false), stuck = nodal_diameter_family(s, true);
    REQUIRE(rows.size() == 1 + 13 * 4);  // nodal diameters 0..12, four modes each (the sector's own DOFs)
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const int d = std::stoi(rows[k][0]), j = std::stoi(rows[k][1]) - 1;
        CHECK(std::stod(rows[k][2]) == Approx(released.frequencies(d, j)).epsilon(1e-14));
        CHECK(std::stod(rows[k][3]) == Approx(stuck.frequencies(d, j)).epsilon(1e-14));
        // engine order 3 on 24 sectors: harmonic k meets nodal diameter 3k mod 24 folded
        const std::string excited = rows[k].size() > 4 ? rows[k][4] : "";
        if (d == 3) CHECK(excited == "1 7 9");
        if (d == 0) CHECK(excited == "8");
        if (d == 1 || d == 2) CHECK(excited.empty());
    }
    // --modes: the lowest families only, the same numbers; beyond the sector's own DOFs refused
    r = test::run_hbf("nodal-diameters --config '" + example + "' --modes 2 --out '" + out + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto two = test::parse_csv(test::slurp(out));
    REQUIRE(two.size() == 1 + 13 * 2);
    for (std::size_t k = 1; k < two.size(); ++k) CHECK(two[k] == rows[1 + 4 * ((k - 1) / 2) + (k - 1) % 2]);
    r = test::run_hbf("nodal-diameters --config '" + example + "' --modes 5 --out '" + (dir.path / "x.csv").string() + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--modes = 5 is out of range: allowed 1..4") != std::string::npos);
    // The forced response of engine order 3: a completed FRF whose peak lies between the
    // released and the stuck resonance of nodal diameter 3.
    const std::string frf = (dir.path / "frf.csv").string(), summary = (dir.path / "frf.json").string();
    r = test::run_hbf("frf --config '" + example + "' --out '" + frf + "' --summary '" + summary + "' --error-points 0",
                      dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string json = test::slurp(summary);
    const std::size_t at = json.find("\"peaks\"");
    REQUIRE(at != std::string::npos);
    const double w_peak = std::stod(json.substr(json.find("\"w\":", at) + 4));
    CHECK(w_peak > released.frequencies(3, 0));
    CHECK(w_peak < stuck.frequencies(3, 0));

    // The nonlinear mode of nodal diameter 3 (the engine order's family): from its stuck
    // frequency down towards the released one, energy balanced, the plot titled with it.
    const std::string modes = (dir.path / "modes.csv").string(), modes_summary = (dir.path / "modes.json").string();
    r = test::run_hbf("modes --config '" + example + "' --out '" + modes + "' --summary '" + modes_summary +
                          "' --plot '" + (dir.path / "modes.svg").string() + "'",
                      dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json m = nlohmann::json::parse(test::slurp(modes_summary));
    CHECK(m["status"] == "completed");
    CHECK(m["nodal_diameter"] == 3);
    CHECK(m["sectors"] == 24);
    CHECK_FALSE(m.contains("force_scale"));  // the file's force, as given
    CHECK(m["linear"]["omega"].get<double>() == Approx(stuck.frequencies(3, 0)).epsilon(1e-12));
    CHECK(m["largest_energy_error"].get<double>() <= 1e-8);
    const double w_last = m["last"]["w"].get<double>();  // slipping: just above the released frequency
    CHECK(w_last > released.frequencies(3, 0));
    CHECK(w_last < 1.001 * released.frequencies(3, 0));
    CHECK(test::slurp((dir.path / "modes.svg").string()).find("(nodal diameter 3) of 24 sectors") != std::string::npos);

    // Bad tables: exit 2 naming the key, nothing written.
    auto refused = [&](const std::string& cyclic, const std::string& contact, const std::string& key,
                       const std::string& text) {
        const std::string file = (dir.path / "bad.toml").string();
        test::write_file(file, "[structure]\nmass = [1.0, 1.0, 0.0]\nstiffness = [[2.0, -1.0, 0.0], [-1.0, 2.0, 0.0], "
                               "[0.0, 0.0, 1.0]]\nexcitation = [1.0, 0.0, 0.0]\n" +
                                   cyclic + contact);
        const test::Result b = test::run_hbf("frf --config '" + file + "' --out '" + (dir.path / "x.csv").string() + "'", dir);
        INFO(cyclic << contact << "\n" << b.err);
        CHECK(b.exit_code == 2);
        CHECK(b.err.find(key) != std::string::npos);
        CHECK(b.err.find(text) != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(dir.path / "x.csv"));
    };
    const std::string jenkins = "[[contact]]\nlaw = \"jenkins\"\ndof = 1\nstiffness = 1.0\nfriction_limit = 0.1\n";
    refused("[cyclic]\nsectors = 1\nengine_order = 0\n", jenkins, "cyclic.sectors", "allowed >= 2");
    refused("[cyclic]\nsectors = 6\nengine_order = 1\nleft = [1, 2]\nright = [3]\n", jenkins, "cyclic.right",
            "1 DOFs against 2");
    refused("[cyclic]\nsectors = 6\nengine_order = 1\nleft = [1]\nright = [1]\n", jenkins, "cyclic.right",
            "in both cut faces");
    refused("[cyclic]\nsectors = 6\nengine_order = 1\nleft = [4]\nright = [3]\n", jenkins, "cyclic.left",
            "out of range: allowed 1..3");
    refused("", jenkins + "neighbour_dof = 2\n", "contact[1].neighbour_dof", "allowed with a [cyclic] table only");
    refused("[cyclic]\nsectors = 6\nengine_order = 1\n", jenkins + "neighbour_dof = 7\n", "contact[1].neighbour_dof",
            "out of range: allowed 1..3");
    // an engine order beyond N - 1 is its alias, with a note
    const std::string file = (dir.path / "alias.toml").string();
    test::write_file(file, "[structure]\nmass = [1.0, 1.0, 0.0]\nstiffness = [[2.0, -1.0, -1.0], [-1.0, 2.0, 0.0], "
                           "[-1.0, 0.0, 1.0]]\nexcitation = [1.0, 0.0, 0.0]\n[cyclic]\nsectors = 6\nengine_order = 13\n"
                           "left = [1]\nright = [3]\n" + jenkins);
    r = test::run_hbf("frf --config '" + file + "' --dry-run", dir);
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.err.find("cyclic.engine_order = 13 is engine order 1 on 6 sectors") != std::string::npos);
    CHECK(io::read_system_config(file).system.cyclic.engine_order == 1);
}

TEST_CASE("Cyclic symmetry: several engine orders in one hbf map run, each the FRF of its own engine order",
          "[cyclic]") {
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/bladed_disk/wheel24.toml";
    test::TempDir dir;
    const std::string map = (dir.path / "map.csv").string();
    test::Result r = test::run_hbf("map --config '" + example + "' --param cyclic.engine_order --values 1,3,5 --threads 2 "
                                   "--error-points 0 --out '" + map + "'",
                                   dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto rows = test::parse_csv(test::slurp(map));
    REQUIRE(rows.size() > 3);
    // each engine order's rows against hbf frf on the file with that engine order
    std::string text = test::slurp(example);
    for (int eo : {1, 3, 5}) {
        const std::string file = (dir.path / ("eo" + std::to_string(eo) + ".toml")).string();
        std::string changed = text;
        const std::size_t at = changed.find("engine_order = 3");
        REQUIRE(at != std::string::npos);
        changed.replace(at, 16, "engine_order = " + std::to_string(eo));
        test::write_file(file, changed);
        const std::string frf = (dir.path / ("eo" + std::to_string(eo) + ".csv")).string();
        r = test::run_hbf("frf --config '" + file + "' --error-points 0 --out '" + frf + "'", dir);
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const auto single = test::parse_csv(test::slurp(frf));
        std::vector<std::vector<std::string>> mine;
        for (std::size_t k = 1; k < rows.size(); ++k)
            if (rows[k][0] == std::to_string(eo)) mine.push_back(rows[k]);
        INFO("engine order " << eo);
        REQUIRE(mine.size() == single.size() - 1);
        for (std::size_t k = 0; k < mine.size(); ++k) {
            CHECK(std::stod(mine[k][2]) == std::stod(single[k + 1][0]));  // w
            CHECK(std::stod(mine[k][3]) == Approx(std::stod(single[k + 1][1])).epsilon(1e-12));  // y4_max
        }
    }
    // integer values only, on a sector only; hbf track and hbf optimize refuse it
    for (const std::string& bad :
         {"map --config '" + example + "' --param cyclic.engine_order --values 2.5",
          "map --config '" + example + "' --param cyclic.engine_order --values 24",
          "map --config '" + std::string(HBF_SOURCE_DIR) + "/examples/systems/chain3.toml' --param cyclic.engine_order --values 1",
          "track --config '" + example + "' --param cyclic.engine_order --range 1:3",
          "optimize --config '" + example + "' --param cyclic.engine_order --range 1:3"}) {
        const test::Result b = test::run_hbf(bad + " --out '" + (dir.path / "x.csv").string() + "'", dir);
        INFO(bad << "\n" << b.err);
        CHECK(b.exit_code == 2);
        CHECK(b.err.find("cyclic.engine_order") != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(dir.path / "x.csv"));
    }
}

TEST_CASE("Cyclic symmetry: a finite-element sector reduced inside hbf (Craig-Bampton, the cut faces kept) is "
          "the sector itself with every fixed-interface mode, and converges with fewer",
          "[cyclic]") {
    // examples/systems/bladed_disk/sector.toml: 76 FE DOFs (plane stress) and the next sector's
    // lip DOF for the damper across the cut; the file's [reduction] keeps 12 modes.
    const std::string dir = std::string(HBF_SOURCE_DIR) + "/examples/systems/bladed_disk/";
    const io::SystemConfig file = io::read_system_config(dir + "sector.toml");
    REQUIRE(file.reduction);
    test::TempDir tmp;
    std::string text = test::slurp(dir + "sector.toml");
    for (std::size_t at = text.find("\"sector_"); at != std::string::npos; at = text.find("\"sector_", at + dir.size() + 2))
        text.insert(at + 1, dir);
    const std::size_t from = text.find("[reduction]"), to = text.find("[frequency]");
    REQUIRE(from != std::string::npos);
    REQUIRE(to != std::string::npos);
    test::write_file((tmp.path / "fe.toml").string(), text.substr(0, from) + text.substr(to));
    const io::SystemConfig fe_file = io::read_system_config((tmp.path / "fe.toml").string());
    System fe = fe_file.system;
    REQUIRE(fe.dofs() == 77);
    REQUIRE(fe.cyclic.active());
    fe.damping = 2e-6 * fe.stiffness;  // the file's Rayleigh damping, on the FE model
    ReductionOptions o;
    o.method = ReductionMethod::craig_bampton;
    o.interface_dofs = {73, 69, 76};  // the damper's DOFs (u_t of both lips' tips, the next sector's copy)
    auto reduced = [&](int modes) {
        ReductionOptions with = o;
        with.modes = modes;
        return reduce(fe, with);
    };
    const ReducedSystem all = reduced(65);  // 77 - 12 retained (the cut faces added by the reduction)
    CHECK(all.model.retained.size() == 12);
    CHECK(all.system.cyclic.neighbours.size() == fe.cyclic.neighbours.size());
    for (const auto& [d, m] : all.system.cyclic.neighbours) {  // retained coordinates of the same FE pairs
        REQUIRE(d < static_cast<int>(all.model.retained.size()));
        REQUIRE(m < static_cast<int>(all.model.retained.size()));
        const std::pair<int, int> pair{all.model.retained[static_cast<std::size_t>(d)],
                                       all.model.retained[static_cast<std::size_t>(m)]};
        CHECK(std::find(fe.cyclic.neighbours.begin(), fe.cyclic.neighbours.end(), pair) != fe.cyclic.neighbours.end());
    }
    // the nodal-diameter families: every fixed-interface mode kept, the FE sector's to 1e-10
    for (bool stuck : {false, true}) {
        const NodalDiameterFamily exact = nodal_diameter_family(fe, stuck), r = nodal_diameter_family(all.system, stuck);
        for (Eigen::Index d = 0; d < exact.frequencies.rows(); ++d)
            for (Eigen::Index j = 0; j < 3; ++j)
                CHECK(std::abs(r.frequencies(d, j) - exact.frequencies(d, j)) <= 1e-10 * exact.frequencies(d, j));
    }
    // A sector of 12 (the file's) or 24 modes: its FRF points, recovered on the FE sector
    // (y = T q), corrected by Newton's method on the FE sector's harmonic balance: the change of
    // the tip's amplitude is the truncation's error (the modes left out).
    const std::vector<Output> tip = {Output::dof(65)};
    HarmonicBalanceOptions ho;
    ho.harmonics = *fe_file.choices.harmonics;
    ho.formulation = Formulation::full;
    HarmonicBalance fe_hb(fe, ho);
    const int coefficients = 2 * ho.harmonics + 1;
    const std::vector<int> own = independent_dofs(fe);
    REQUIRE(fe_hb.unknowns() == coefficients * static_cast<int>(own.size()));
    const auto tip_at = std::find(own.begin(), own.end(), 65) - own.begin();
    auto truncation = [&](const ReducedSystem& sector) {
        FrfSettings settings = frf_settings(sector.system, reduced_outputs(tip, sector.model), fe_file.choices);
        settings.error_points = 0;
        const FrfResult frf = compute_frf(sector.system, settings);
        REQUIRE(frf.status() == "completed");
        HarmonicBalance reduced_hb(sector.system, ho);
        double change = 0.0;
        for (std::size_t p = 0; p < frf.points.size(); p += 6) {
            const double omega = frf.points[p].omega;
            const Eigen::MatrixXd y = reduced_hb.dofs(frf.points[p].x, omega) * sector.model.recovery.transpose();
            Eigen::VectorXd x(fe_hb.unknowns()), r;
            for (std::size_t i = 0; i < own.size(); ++i)
                x.segment(static_cast<Eigen::Index>(i) * coefficients, coefficients) = y.col(own[i]);
            Eigen::VectorXd z = x;
            for (int it = 0; it < 5; ++it) {
                Eigen::MatrixXd jacobian;
                fe_hb.evaluate(z, omega, r, &jacobian);
                z -= jacobian.partialPivLu().solve(r);
            }
            fe_hb.evaluate(z, omega, r);
            REQUIRE(r.cwiseAbs().maxCoeff() <= 1e-9 * fe.excitation.cwiseAbs().maxCoeff());  // Newton converged
            const auto amplitude = [&](const Eigen::VectorXd& v) {
                return std::hypot(v(tip_at * coefficients + 1), v(tip_at * coefficients + 2));
            };
            change = std::max(change, std::abs(amplitude(z) - amplitude(x)) / amplitude(z));
        }
        return change;
    };
    const ReducedSystem twelve = reduced(12);
    const double error12 = truncation(twelve), error24 = truncation(reduced(24));
    INFO("the tip's amplitude corrected on the FE sector by " << error12 << " (12 modes), " << error24 << " (24 modes)");
    CHECK(error12 <= 1e-3);
    CHECK(error24 <= 0.3 * error12);
    // The example as a user runs it: the damper near its optimum holds the peak between the
    // released and the stuck nodal-diameter-3 resonances, far below either.
    const std::string summary = (tmp.path / "sector.json").string();
    const test::Result r = test::run_hbf("frf --config '" + dir + "sector.toml' --out '" + (tmp.path / "sector.csv").string() +
                                             "' --summary '" + summary + "' --error-points 0",
                                         tmp);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(test::slurp(summary));
    const double w_peak = j["peaks"][0]["w"].get<double>();
    const NodalDiameterFamily released = nodal_diameter_family(file.system, false), stuck = nodal_diameter_family(file.system, true);
    CHECK(w_peak > 1.01 * released.frequencies(3, 0));
    CHECK(w_peak < stuck.frequencies(3, 0));
    // the file's own reduction is the 12-mode one
    CHECK(file.system.dofs() == twelve.system.dofs());
    // macneal keeps no cut face physical: refused for a sector
    ReductionOptions macneal = o;
    macneal.method = ReductionMethod::macneal;
    macneal.modes = 5;
    CHECK_THROWS_WITH(reduce(fe, macneal), Catch::Contains("not for a sector model"));
}

TEST_CASE("Cyclic symmetry: the damper's optimal slip force on the 24-sector example, by tracking the peak, "
          "checked by FRFs at 10 values and by the optimiser",
          "[cyclic]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/bladed_disk/wheel24.toml");
    const System base = config.system;
    auto with_limit = [&](double f) {
        System s = base;
        s.contacts[0].friction_limit = f;
        return s;
    };
    FrfSettings settings = frf_settings(base, config.outputs, config.choices);
    settings.error_points = 0;
    TrackOptions o;
    o.p_start = 0.002;
    o.p_end = 0.3;
    std::vector<double> values;
    for (int k = 0; k < 10; ++k) values.push_back(0.004 * std::pow(0.25 / 0.004, k / 9.0));
    o.at = values;
    const TrackResult r = track(with_limit, settings, o);
    INFO(r.summary());
    REQUIRE(r.status() == "completed");
    REQUIRE(r.curves.size() == 1);
    const TrackCurve& c = r.curves[0];
    const std::vector<FrfResult> frfs = compute_frfs(
        static_cast<int>(values.size()), [&](int k) { return with_limit(values[static_cast<std::size_t>(k)]); },
        settings, 2);
    double best = 1e300, best_p = 0;
    for (std::size_t k = 0; k < values.size(); ++k) {
        REQUIRE(frfs[k].status() == "completed");
        const auto at = std::find_if(c.points.begin(), c.points.end(), [&](const TrackPoint& p) {
            return p.kind == "at" && std::abs(p.p - values[k]) <= 1e-12 * values[k];
        });
        REQUIRE(at != c.points.end());
        INFO("slip force " << values[k]);
        // the same peak: where the stick/slip pattern switches at the peak, the peak is a kink of
        // the H = 7 branch, whose value both locate to 1e-3 and whose w to 0.5 %
        CHECK(std::abs(at->value - frfs[k].peak.value) <= 1e-3 * frfs[k].peak.value);
        CHECK(std::abs(at->omega - frfs[k].peak.omega) <= 5e-3 * frfs[k].peak.omega);
        if (frfs[k].peak.value < best) {
            best = frfs[k].peak.value;
            best_p = values[k];
        }
    }
    // An optimum inside the range (the under-platform damper's classic curve: too light a load
    // slips freely, too heavy a load sticks).
    CHECK(best_p > values.front());
    CHECK(best_p < values.back());
    OptimizeOptions oo;
    oo.lower = 0.004;
    oo.upper = 0.25;
    const OptimizeResult opt = optimize_parameter(with_limit, settings, oo);
    INFO(opt.summary("slip force"));
    CHECK(opt.status == OptimizeStatus::converged);
    CHECK(opt.peak.value <= best * (1.0 + 1e-9));  // no worse than the best of the ten
    // the tracked curve's minimum agrees with the optimiser's
    double curve_min = 1e300;
    for (const TrackPoint& p : c.points) curve_min = std::min(curve_min, p.value);
    CHECK(std::abs(curve_min - opt.peak.value) <= 2e-3 * opt.peak.value);
}

TEST_CASE("Cyclic symmetry: a nonlinear mode of the nodal-diameter-3 family is the whole wheel's free periodic "
          "motion through stick, stick-slip and slip, and its synthesised response meets the forced FRF",
          "[cyclic]") {
    const System s = lumped_sector(12, 3, 0.05);
    HarmonicBalanceOptions hbo;
    hbo.harmonics = 5;
    hbo.formulation = Formulation::full;
    ModeOptions mo;
    const SlipOnset onset = slip_onset(s, hbo, mo);
    REQUIRE(onset.found);
    mo.amplitude_min = onset.amplitude_min;
    mo.amplitude_max = onset.amplitude_max;
    mo.tolerance = 1e-12;
    NonlinearModes nm(s, hbo, mo);
    // The linear limit: the first stuck mode of nodal diameter 3, a travelling wave (complex).
    const NodalDiameterFamily stuck = nodal_diameter_family(s, true);
    CHECK(std::abs(nm.linear().omega - stuck.frequencies(3, 0)) <= 1e-10 * stuck.frequencies(3, 0));
    REQUIRE(nm.linear().shape_imag.size() == s.dofs());
    CHECK(nm.linear().shape_imag.cwiseAbs().maxCoeff() > 0.1 * nm.linear().shape.cwiseAbs().maxCoeff());
    const Backbone b = nm.follow();
    INFO(b.message);
    REQUIRE(b.status == ModeStatus::completed);
    std::vector<ModeMetrics> metrics;
    std::set<std::string> regimes;
    double worst_energy = 0.0;
    for (const ModePoint& p : b.points) {
        metrics.push_back(nm.metrics(p, {Output::dof(2)}));
        regimes.insert(metrics.back().contacts[0].regime);
        worst_energy = std::max(worst_energy, metrics.back().energy_error);
    }
    CHECK(regimes == std::set<std::string>{"stick", "stick-slip", "slip"});
    INFO("largest energy-balance error " << worst_energy);
    CHECK(worst_energy <= 1e-8);
    // Friction softens and damps the mode: the slipping end is the released family's frequency.
    const NodalDiameterFamily released = nodal_diameter_family(s, false);
    CHECK(b.points.back().omega < b.points.front().omega);
    CHECK(std::abs(b.points.back().omega - released.frequencies(3, 0)) <= 0.02 * released.frequencies(3, 0));

    // Every third point on the whole wheel (sector j delayed by j phi / omega): the wheel's free
    // motion with the artificial damping -xi M y', R(X) - xi omega (D1 Y) M = 0.
    const System w = lumped_wheel(s);
    HarmonicBalanceOptions o = hbo;
    HarmonicBalance wheel_hb(w, o);
    const int coefficients = 2 * hbo.harmonics + 1, dofs = w.dofs();
    const Eigen::MatrixXd mass(w.mass);
    double largest = 0.0;
    for (std::size_t k = 0; k < b.points.size(); k += 3) {
        const ModePoint& p = b.points[k];
        const Eigen::VectorXd x = bench::placed_on_wheel(s, nm.motion(p));
        Eigen::VectorXd r;
        wheel_hb.evaluate(x, p.omega, r);
        for (int i = 0; i < dofs; ++i) r(i * coefficients + 1) += w.excitation(i);  // unforced
        const Eigen::Map<const Eigen::MatrixXd> y(x.data(), coefficients, dofs);
        const Eigen::MatrixXd d1y = wheel_hb.fourier().derivative() * y;
        const Eigen::MatrixXd damping = p.xi * p.omega * d1y * mass;
        const Eigen::MatrixXd inertia = p.omega * p.omega * (wheel_hb.fourier().derivative() * d1y) * mass;
        const Eigen::VectorXd rest = r - Eigen::Map<const Eigen::VectorXd>(damping.data(), damping.size());
        largest = std::max(largest, rest.cwiseAbs().maxCoeff() / inertia.cwiseAbs().maxCoeff());
    }
    INFO("largest wheel residual relative to the inertial force " << largest);
    CHECK(largest <= 1e-11);

    // The synthesised response to the travelling force against the sector's forced FRF: the peak.
    const std::vector<SynthesisPoint> curve = nm.synthesize(b, metrics, s.excitation, {Output::dof(2)});
    REQUIRE(!curve.empty());
    const auto top = std::max_element(curve.begin(), curve.end(), [](const SynthesisPoint& a, const SynthesisPoint& c) {
        return a.output_amp1[0] < c.output_amp1[0];
    });
    FrfChoices choices;
    choices.omega_start = 0.8 * released.frequencies(3, 0);
    choices.omega_end = 1.2 * stuck.frequencies(3, 0);
    choices.harmonics = hbo.harmonics;
    FrfSettings settings = frf_settings(s, {Output::dof(2)}, choices);
    settings.error_points = 0;
    const FrfResult frf = compute_frf(s, settings);
    REQUIRE(frf.status() == "completed");
    std::size_t peak = 0;  // the forced FRF's largest first-harmonic amplitude (its points)
    for (std::size_t k = 0; k < frf.metrics.size(); ++k)
        if (frf.metrics[k].output_amp1[0] > frf.metrics[peak].output_amp1[0]) peak = k;
    const double forced = frf.metrics[peak].output_amp1[0], forced_w = frf.points[peak].omega;
    INFO("synthesised peak " << top->output_amp1[0] << " at w = " << top->omega << "; forced FRF's " << forced
                             << " at w = " << forced_w << " (max |y| " << frf.peak.value << " at " << frf.peak.omega << ")");
    // single-mode synthesis near an isolated mode: the peak within 2 %, its frequency within 1 %
    CHECK(std::abs(top->output_amp1[0] - forced) <= 0.02 * forced);
    CHECK(std::abs(top->omega - forced_w) <= 0.01 * forced_w);
}
