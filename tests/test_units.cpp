// The same physical problem in other units gives the same answer: the paper's absorber in its
// nondimensional form (m1 = k1 = N = 1) and in SI units (m1 = 3 kg, k1 = 1.2e5 N/m, N = 75 N:
// omega1 = 200 rad/s, x_s = N / k1 = 0.625 mm). The continuation measures its arclength in
// (X / x_ref, omega / omega_ref), both dimensionless; the exact solver's and time
// integration's convergence tests are relative with velocities divided by omega. Before,
// omega entered the arclength in rad/s: the SI Jenkins branch lost both of its folds (298
// points and no fold against 136 points and 2 folds).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>

#include "cli_support.hpp"

using namespace test;

namespace {

constexpr double m1 = 3.0, k1 = 1.2e5, normal = 75.0;
const double omega1 = std::sqrt(k1 / m1), x_s = normal / k1;

/// The absorber (r = 0.1, wa = 1, mu = 0.2, fe = 0.5; sigma0 = r wb^2 = 0.016 for Dahl and
/// Jenkins) over w in [0.5, 1.6] omega1, in units where m1, k1 and N are as given.
fs::path absorber_file(const fs::path& dir, const std::string& name, const std::string& law, double m, double k,
                       double n) {
    const double r = 0.1, w = std::sqrt(k / m);
    std::string text = "[structure]\nmass = [" + std::to_string(m) + ", " + std::to_string(r * m) + "]\n" +
                       "stiffness = [[" + std::to_string(k * 1.1) + ", " + std::to_string(-k * 0.1) + "], [" +
                       std::to_string(-k * 0.1) + ", " + std::to_string(k * 0.1) + "]]\n" +
                       "excitation = [" + std::to_string(0.5 * n) + ", 0.0]\n" +
                       "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"" + law + "\"\nfriction_limit = " +
                       std::to_string(0.2 * n) + "\n";
    if (law != "coulomb") text += "stiffness = " + std::to_string(0.016 * k) + "\n";
    text += "[frequency]\nwmin = " + std::to_string(0.5 * w) + "\nwmax = " + std::to_string(1.6 * w) + "\n";
    const fs::path file = dir / (name + ".toml");
    std::ofstream(file) << text;
    return file;
}

}  // namespace

TEST_CASE("Units: a smooth branch in SI units is the nondimensional branch, point for point",
          "[units][continuation][cli]") {
    TempDir dir;
    for (const std::string law : {"dahl", "jenkins"}) {
        INFO(law);
        const Result a = run_hbf("frf --quiet --exact off --error-points 0 --config '" +
                                     absorber_file(dir.path, "a", law, 1.0, 1.0, 1.0).string() + "'",
                                 dir);
        const Result b = run_hbf("frf --quiet --exact off --error-points 0 --config '" +
                                     absorber_file(dir.path, "b", law, m1, k1, normal).string() + "'",
                                 dir);
        REQUIRE(a.exit_code == 0);
        REQUIRE(b.exit_code == 0);
        const auto rows_a = parse_csv(a.out), rows_b = parse_csv(b.out);
        REQUIRE(rows_a.size() == rows_b.size());
        int folds = 0;
        for (std::size_t k = 1; k < rows_a.size(); ++k) {
            INFO("row " << k);
            CHECK(rows_a[k][9] == rows_b[k][9]);  // point kind: regular, fold, transition
            folds += rows_a[k][9] == "fold";
            // The points lie where the same steps put them; along the branch they agree to the
            // corrector's tolerance amplified by the step control (measured: up to 2e-6).
            CHECK(std::stod(rows_b[k][0]) / omega1 == Approx(std::stod(rows_a[k][0])).epsilon(1e-5));
            CHECK(std::stod(rows_b[k][1]) / x_s == Approx(std::stod(rows_a[k][1])).epsilon(1e-5));
        }
        if (law == "jenkins") CHECK(folds == 2);
    }
}

TEST_CASE("Units: exact Coulomb in SI units has the nondimensional samples, peaks and transitions",
          "[units][exact][cli]") {
    // Where it slides, exact Coulomb's branch has kinks (each AFT sample that switches), and
    // the step control through them follows rounding: the number of branch points differs
    // between the two unit systems (measured 160 and 355). What the branch is for does not:
    // the solutions at given frequencies, the refined peaks and the located transitions.
    TempDir dir;
    const fs::path ja = dir.path / "a.json", jb = dir.path / "b.json";
    const Result a = run_hbf("frf --quiet --config '" + absorber_file(dir.path, "a", "coulomb", 1.0, 1.0, 1.0).string() +
                                 "' --at 0.7,0.9,1,1.2 --summary '" + ja.string() + "'",
                             dir);
    const std::string at_b = std::to_string(0.7 * omega1) + "," + std::to_string(0.9 * omega1) + "," +
                             std::to_string(1.0 * omega1) + "," + std::to_string(1.2 * omega1);
    const Result b = run_hbf("frf --quiet --config '" +
                                 absorber_file(dir.path, "b", "coulomb", m1, k1, normal).string() + "' --at " + at_b +
                                 " --summary '" + jb.string() + "'",
                             dir);
    INFO(a.err << b.err);
    REQUIRE(a.exit_code == 0);
    REQUIRE(b.exit_code == 0);
    std::vector<std::vector<std::string>> samples_a, samples_b;
    for (const auto& row : parse_csv(a.out))
        if (row[9] == "sample") samples_a.push_back(row);
    for (const auto& row : parse_csv(b.out))
        if (row[9] == "sample") samples_b.push_back(row);
    REQUIRE(samples_a.size() == 4);
    REQUIRE(samples_b.size() == 4);
    for (std::size_t k = 0; k < 4; ++k) {
        CHECK(samples_a[k][13] == "yes");
        CHECK(samples_b[k][13] == "yes");
        CHECK(std::stod(samples_b[k][1]) / x_s == Approx(std::stod(samples_a[k][1])).epsilon(1e-9));
        CHECK(std::stod(samples_b[k][2]) / x_s == Approx(std::stod(samples_a[k][2])).epsilon(1e-9));
        CHECK(std::stod(samples_b[k][7]) / (normal * x_s) == Approx(std::stod(samples_a[k][7])).epsilon(1e-8));
    }
    const auto sa = nlohmann::json::parse(slurp(ja)), sb = nlohmann::json::parse(slurp(jb));
    REQUIRE(sa.at("peaks").size() == sb.at("peaks").size());
    REQUIRE(sa.at("peaks").size() >= 2);
    for (std::size_t k = 0; k < sa.at("peaks").size(); ++k) {
        const auto &p = sa.at("peaks")[k], &q = sb.at("peaks")[k];
        CHECK(p.at("output") == q.at("output"));
        CHECK(p.at("refined") == true);
        CHECK(q.at("refined") == true);
        // Brent's bracket shrinks to 1e-9 w, but values locate a maximum only to about
        // sqrt(dy / c) in w/w_peak, with dy the values' rounding (1e-13 of the orbit) and c the
        // curvature y''w^2/(2y) (about 400 on these resonances): 1.6e-8 (measured 1.5e-8 when
        // the searches' solves start from their last orbit). y_max itself is flat there.
        CHECK(q.at("w").get<double>() / omega1 == Approx(p.at("w").get<double>()).epsilon(1e-7));
        CHECK(q.at("y_max").get<double>() / x_s == Approx(p.at("y_max").get<double>()).epsilon(1e-12));
    }
    REQUIRE(sa.at("transitions").size() == sb.at("transitions").size());
    REQUIRE(sa.at("transitions").size() == 4);
    for (std::size_t k = 0; k < 4; ++k)
        CHECK(sb.at("transitions")[k].at("w").get<double>() / omega1 ==
              Approx(sa.at("transitions")[k].at("w").get<double>()).epsilon(1e-9));
}
