// General systems from a TOML file (`hbf frf --config`): the shipped examples against the
// preset, Den Hartog's exact solution and the time integrator; validation messages.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "hbf/analytic.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/time_integration.hpp"

using namespace test;

namespace {
const std::string systems = std::string(HBF_SOURCE_DIR) + "/examples/systems/";


/// The sample rows (point = sample) at frequency w of an `hbf frf` CSV.
/// The index of the column `name` in the header row.
std::size_t column(const std::vector<std::vector<std::string>>& rows, const std::string& name) {
    const auto at = std::find(rows.front().begin(), rows.front().end(), name);
    REQUIRE(at != rows.front().end());
    return static_cast<std::size_t>(at - rows.front().begin());
}

/// The rows of kind sample at w.
std::vector<std::vector<std::string>> samples_at(const std::vector<std::vector<std::string>>& rows, double w) {
    const std::size_t point_column = column(rows, "point");
    std::vector<std::vector<std::string>> found;
    for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k][point_column] == "sample" && std::stod(rows[k][0]) == w) found.push_back(rows[k]);
    return found;
}
}  // namespace

TEST_CASE("examples/systems/absorber.toml gives exactly the preset's FRF", "[config]") {
    TempDir dir;
    const Result preset = run_hbf("frf --quiet", dir);
    const Result file = run_hbf("frf --quiet --config '" + systems + "absorber.toml'", dir);
    REQUIRE(preset.exit_code == 0);
    REQUIRE(file.exit_code == 0);
    CHECK(parse_csv(file.out).size() > 100);
    CHECK(file.out == preset.out);  // the same system, the same numbers, bit for bit
}

TEST_CASE("examples/systems/den_hartog.toml reproduces Den Hartog's exact non-sticking solution to 1e-9", "[config]") {
    // hbf frf's defaults: HB at H = 10 for the branch, every point polished by the exact solver.
    TempDir dir;
    const Result r = run_hbf("frf --quiet --config '" + systems + "den_hartog.toml' --at 0.6,0.7", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    REQUIRE(rows[0][1] == "y1_max");
    REQUIRE(rows[0][7] == "point");
    REQUIRE(rows[0][11] == "exact");
    for (std::size_t k = 1; k < rows.size(); ++k) {  // every branch point too
        const double eta = std::stod(rows[k][0]);
        REQUIRE(rows[k][11] == "yes");
        CHECK(std::abs(std::stod(rows[k][1]) - hbf::analytic::den_hartog(eta, 0.3).amplitude) <= 1e-9);
        CHECK(rows[k][4] == "slip");
    }
    for (double eta : {0.6, 0.7}) CHECK(samples_at(rows, eta).size() == 1);
}

TEST_CASE("examples/systems/chain3_exact.toml (Jenkins + Coulomb) polished: equal to tight time integration",
          "[config][exact]") {
    const hbf::io::SystemConfig config = hbf::io::read_system_config(systems + "chain3_exact.toml");
    TempDir dir;
    const Result r = run_hbf("frf --quiet --config '" + systems + "chain3_exact.toml' --at 0.33,1,2.3", dir);
    REQUIRE(r.exit_code == 0);  // no failed polish
    const auto rows = parse_csv(r.out);
    hbf::TimeIntegrationOptions tight;
    tight.relative_tolerance = 1e-12;
    tight.absolute_tolerance = 1e-14;
    tight.steady_tolerance = 1e-11;
    for (double w : {0.33, 1.0, 2.3}) {
        const auto at = samples_at(rows, w);
        REQUIRE(at.size() == 1);
        REQUIRE(at[0][column(rows, "exact")] == "yes");
        const hbf::PeriodicResponse ti = hbf::integrate_steady_state(config.system, w, tight);
        REQUIRE(ti.converged);
        INFO("w = " << w << ": exact y1 " << at[0][1] << ", y3 " << at[0][2] << "; TI " << ti.summary());
        // The damped chain settles on its own; where the Jenkins contact sticks all period (w = 0.33,
        // 2.3) its slider offset is not determined: the exact solver centres its force (zero
        // mean), CVODE keeps the offset its transient left, so y_max may differ by the offset.
        // The first harmonics are offset-free.
        CHECK(std::abs(std::stod(at[0][3]) - ti.y_amp1[0]) <= 1e-8);
        CHECK(std::abs(std::stod(at[0][4]) - ti.y_amp1[2]) <= 1e-8);
        if (w == 1.0) {
            CHECK(std::abs(std::stod(at[0][1]) - ti.y_max[0]) <= 1e-8);
            CHECK(std::abs(std::stod(at[0][2]) - ti.y_max[2]) <= 1e-8);
        }
    }
}

TEST_CASE("examples/systems/chain3.toml: two contacts, reported DOFs 1 and 3, equal to time integration",
          "[config]") {
    const hbf::io::SystemConfig config = hbf::io::read_system_config(systems + "chain3.toml");
    REQUIRE(config.system.dofs() == 3);
    REQUIRE(config.system.contacts.size() == 2);
    CHECK(config.system.stiffness.coeff(2, 1) == -1.0);  // mirrored from the symmetric Matrix Market file
    REQUIRE(config.outputs.size() == 2);
    CHECK(config.outputs[0].single_dof() == 0);
    CHECK(config.outputs[1].single_dof() == 2);
    CHECK(config.outputs[1].name() == "y3");
    TempDir dir;
    const double w = 1.0;
    const Result r = run_hbf("frf --quiet --error-points 0 --config '" + systems + "chain3.toml' --at 1", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    const std::vector<std::string> head = {"w", "y1_max", "y3_max", "y1_amp1", "y3_amp1"};
    CHECK(std::vector<std::string>(rows[0].begin(), rows[0].begin() + 5) == head);
    // Jenkins and Dahl at H = 10 are within 1e-4 of time integration (test_verification);
    // the chain is damped, so the time integration from rest settles on its own.
    const hbf::PeriodicResponse ti = hbf::integrate_steady_state(config.system, w, hbf::TimeIntegrationOptions{});
    REQUIRE(ti.converged);
    const auto at = samples_at(rows, w);
    REQUIRE(!at.empty());
    double best = std::numeric_limits<double>::infinity();  // the HB solution TI found
    std::size_t k = 0;
    for (std::size_t i = 0; i < at.size(); ++i)
        if (std::abs(std::stod(at[i][1]) - ti.y_max[0]) < best) best = std::abs(std::stod(at[k = i][1]) - ti.y_max[0]);
    INFO("HB y1_max " << at[k][1] << ", y3_max " << at[k][2] << "; TI " << ti.y_max[0] << ", " << ti.y_max[2]);
    CHECK(std::abs(std::stod(at[k][1]) - ti.y_max[0]) <= 1e-3 * ti.y_max[0]);
    CHECK(std::abs(std::stod(at[k][2]) - ti.y_max[2]) <= 1e-3 * ti.y_max[2]);
}

TEST_CASE("Command-line flags override the file, the preset's flags are rejected with --config", "[config]") {
    TempDir dir;
    const Result r = run_hbf("frf --quiet --config '" + systems + "den_hartog.toml' --wmin 0.6 --harmonics 10", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    CHECK(std::stod(rows[1][0]) == 0.6);
    CHECK(std::stod(rows.back()[0]) == 0.75);  // wmax from the file
    const fs::path out = dir.path / "x.csv";
    const Result bad = run_hbf("frf --config '" + systems + "den_hartog.toml' --mu 0.3 --out '" + out.string() + "'", dir);
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Catch::Contains("--mu") && Catch::Contains("--config"));
    CHECK(dir.empty());
}

TEST_CASE("Bad system files: the message names the file, the line and the key, exit 2, no output", "[config]") {
    TempDir dir;
    const std::string good_structure = "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [1.0]\n";
    struct Case {
        std::string text;
        std::vector<std::string> expected;  // substrings of the message
    };
    const std::vector<Case> cases = {
        {"[structure]\nmas = [1.0]\nstiffness = [1.0]\nexcitation = [1.0]\n", {":2:", "structure.mas", "unknown key"}},
        {"[structure]\nmass = [[1.0, 0.0], [0.0]]\nstiffness = [1.0]\nexcitation = [1.0]\n",
         {":2:", "structure.mass", "row 2"}},
        {"[structure]\nmass = [1.0, 1.0]\nstiffness = [1.0]\nexcitation = [1.0, 0.0]\n",
         {":3:", "structure.stiffness", "2 x 2"}},
        {"[structure]\nmass = [-1.0]\nstiffness = [1.0]\nexcitation = [1.0]\n",
         {":2:", "structure.mass", "positive semi-definite"}},
        {good_structure + "[[contact]]\ndof = 1\nlaw = \"coulomb\"\nfriction_limit = 0.2\nstiffness = 3.0\n",
         {":9:", "contact[1].stiffness", "does not apply to law 'coulomb'"}},
        {good_structure + "[[contact]]\ndof = 2\nlaw = \"coulomb\"\nfriction_limit = 0.2\n",
         {":6:", "contact[1].dof", "allowed 1..1"}},
        {good_structure + "[[contact]]\ndof = 1\nlaw = \"dahl\"\nfriction_limit = 0.2\n",
         {"contact[1]", "stiffness"}},
        {good_structure + "[[contact]]\ndof = 1\nlaw = \"stickum\"\nfriction_limit = 0.2\n",
         {":7:", "contact[1].law", "allowed coulomb"}},
        {good_structure + "[output]\nreport = [2]\n", {":6:", "output.report", "allowed 1..1"}},
        {good_structure + "[frequency]\nwmin = 2.0\nwmax = 1.0\n", {":7:", "frequency.wmax"}},
        {good_structure + "[solver]\nharmonics = 0\n", {":6:", "solver.harmonics", "1..100"}},
        {"[structure\nmass = [1.0]\n", {":1:", "syntax error"}},
    };
    for (const Case& c : cases) {
        std::vector<std::string> expected = c.expected;
        expected.emplace_back("system.toml");  // every message names the file
        check_bad_config(c.text, expected, dir);
    }
    const Result missing = run_hbf("frf --config '" + (dir.path / "none.toml").string() + "'", dir);
    CHECK(missing.exit_code == 2);
    CHECK_THAT(missing.err, Catch::Contains("none.toml") && Catch::Contains("cannot be read"));
}

TEST_CASE("Matrix Market: coordinate and array formats, general and symmetric", "[config]") {
    TempDir dir;
    const fs::path a = dir.path / "a.mtx", b = dir.path / "b.mtx", c = dir.path / "c.mtx";
    write_file(a, "%%MatrixMarket matrix array real symmetric\n% lower triangle, column-major\n2 2\n4\n-1\n3\n");
    write_file(b, "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 4\n1 2 -1\n2 2 3\n");
    write_file(c, "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 4\n3 1 1\n");
    Eigen::Matrix2d expected;
    expected << 4, -1, -1, 3;
    CHECK(Eigen::MatrixXd(hbf::io::read_matrix_market(a.string())) == Eigen::MatrixXd(expected));
    expected(1, 0) = 0.0;
    CHECK(Eigen::MatrixXd(hbf::io::read_matrix_market(b.string())) == Eigen::MatrixXd(expected));
    CHECK_THROWS_WITH(hbf::io::read_matrix_market(c.string()), Catch::Contains("c.mtx:4") && Catch::Contains("index"));
    // Read sparse: a 100,000 x 100,000 diagonal (dense: 80 GB) is 100,000 stored entries.
    const fs::path big = dir.path / "big.mtx";
    {
        std::ofstream out(big);
        out << "%%MatrixMarket matrix coordinate real symmetric\n100000 100000 100000\n";
        for (int i = 1; i <= 100000; ++i) out << i << ' ' << i << " 2.5\n";
    }
    const hbf::SparseMatrix m = hbf::io::read_matrix_market(big.string());
    CHECK(m.rows() == 100000);
    CHECK(m.nonZeros() == 100000);
    CHECK(m.coeff(99999, 99999) == 2.5);
    // Hostile files: an entry twice (also mirrored in a symmetric file), data beyond the
    // announced entries, and a device are refused by name.
    const fs::path twice = dir.path / "twice.mtx", mirrored = dir.path / "mirrored.mtx", extra = dir.path / "extra.mtx";
    write_file(twice, "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 2 4\n1 2 1\n");
    write_file(mirrored, "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n2 1 4\n1 2 4\n");
    write_file(extra, "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 4\n2 2 3\n");
    CHECK_THROWS_WITH(hbf::io::read_matrix_market(twice.string()), Catch::Contains("twice.mtx:4") && Catch::Contains("given twice"));
    CHECK_THROWS_WITH(hbf::io::read_matrix_market(mirrored.string()), Catch::Contains("one triangle"));
    CHECK_THROWS_WITH(hbf::io::read_matrix_market(extra.string()), Catch::Contains("extra.mtx:4") && Catch::Contains("more data"));
    CHECK_THROWS_WITH(hbf::io::read_matrix_market("/dev/zero"), Catch::Contains("not a regular file"));
}

TEST_CASE("Matrix Market fields are read whole: the Fortran D exponent is the number it means, anything else "
          "is refused by file, line and field", "[config]") {
    TempDir dir;
    // The same 2 x 2 matrix with E and with Fortran D/d exponents (as FE codes print them).
    const fs::path e = dir.path / "e.mtx", d = dir.path / "d.mtx";
    write_file(e, "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1.0E-1\n1 2 -2.5e+0\n2 2 3.0E2\n");
    write_file(d, "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1.0D-1\n1 2 -2.5d+0\n2 2 3.0D2\n");
    const Eigen::MatrixXd me(hbf::io::read_matrix_market(e.string())), md(hbf::io::read_matrix_market(d.string()));
    CHECK(md(0, 0) == 0.1);
    CHECK(md(0, 1) == -2.5);
    CHECK(md(1, 1) == 300.0);
    CHECK(md == me);
    // hbf frf on the absorber whose K is read with D exponents writes the FRF of its E twin.
    write_file(dir.path / "ke.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1.1E0\n2 1 -1.0E-1\n2 2 1.0E-1\n");
    write_file(dir.path / "kd.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1.1D0\n2 1 -1.0D-1\n2 2 1.0d-1\n");
    for (const char* k : {"ke", "kd"})
        write_file(dir.path / (std::string(k) + ".toml"),
                   "[structure]\nmass = [1.0, 0.1]\nstiffness = \"" + std::string(k) + ".mtx\"\nexcitation = [0.5, 0.0]\n"
                   "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"dahl\"\nfriction_limit = 0.2\nstiffness = 0.016\n");
    const Result with_e = run_hbf("frf --quiet --config '" + (dir.path / "ke.toml").string() + "'", dir);
    const Result with_d = run_hbf("frf --quiet --config '" + (dir.path / "kd.toml").string() + "'", dir);
    REQUIRE(with_e.exit_code == 0);
    CHECK(with_d.exit_code == 0);
    CHECK(parse_csv(with_e.out).size() > 50);
    CHECK(with_d.out == with_e.out);
    // Refused, with the file, the line and the field: a decimal comma, trailing characters,
    // hexadecimal, non-finite values (named as such), a size line or an entry with an extra
    // field, an index that is not an integer, a value that is not one in an integer file.
    struct Case {
        std::string text;
        std::vector<std::string> expected;
    };
    const std::string head = "%%MatrixMarket matrix coordinate real general\n";
    const std::vector<Case> cases = {
        {head + "2 2 1\n1 1 1,5\n", {"bad.mtx:3", "field 3 (value) = '1,5'", "not a decimal number"}},
        {head + "2 2 1\n1 1 1.1abc\n", {"bad.mtx:3", "'1.1abc'", "not a decimal number"}},
        {head + "2 2 1\n1 1 0x1.1p0\n", {"bad.mtx:3", "'0x1.1p0'", "not a decimal number"}},
        {head + "2 2 1\n1 1 nan\n", {"bad.mtx:3", "'nan' is not finite"}},
        {head + "2 2 1\n1 1 -inf\n", {"bad.mtx:3", "'-inf' is not finite"}},
        {head + "2 2 1\n1 1 1e999\n", {"bad.mtx:3", "'1e999' is not finite (it overflows"}},
        {head + "2 2 1 7\n1 1 1.0\n", {"bad.mtx:2", "4 fields: expected 3", "size line"}},
        {head + "2 2 1\n1 1 1.0 2.0\n", {"bad.mtx:3", "4 fields: expected 3", "entry 1"}},
        {head + "2 2 1\n1.0 1 1.0\n", {"bad.mtx:3", "field 1 (row) = '1.0'", "not an integer"}},
        {"%%MatrixMarket matrix coordinate integer general\n2 2 1\n1 1 1.5\n", {"bad.mtx:3", "'1.5'", "integer"}},
        {"%%MatrixMarket matrix array real general\n1 1\n1.0 2.0\n", {"bad.mtx:3", "2 fields: expected 1"}},
        {"%%MatrixMarket matrix coordinate real general extra\n1 1 1\n1 1 1.0\n", {"bad.mtx:1", "expected '%%MatrixMarket"}},
    };
    const fs::path bad = dir.path / "bad.mtx";
    for (const Case& c : cases) {
        write_file(bad, c.text);
        INFO(c.text);
        try {
            (void)hbf::io::read_matrix_market(bad.string());
            FAIL("accepted");
        } catch (const hbf::InvalidInput& error) {
            for (const std::string& part : c.expected) CHECK_THAT(error.what(), Catch::Contains(part));
        }
    }
}

TEST_CASE("Config: force_direction contacts and vector excitation from Matrix Market, massless DOFs accepted", "[config]") {
    TempDir dir;
    write_file(dir.path / "f.mtx", "%%MatrixMarket matrix coordinate real general\n3 1 2\n1 1 1.0\n3 1 0.5\n");
    const fs::path file = dir.path / "s.toml";
    write_file(file, "[structure]\nmass = [1.0, 0.5, 0.0]\nstiffness = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.5]]\n"
                "excitation = \"f.mtx\"\n[[contact]]\nforce_direction = [0.0, 1.0, -1.0]\nlaw = \"coulomb\"\n"
                "friction_limit = 0.2\n");
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    CHECK(config.system.excitation == Eigen::Vector3d(1.0, 0.0, 0.5));
    CHECK(config.system.contact_direction(config.system.contacts[0]) == Eigen::Vector3d(0.0, 1.0, -1.0));
    CHECK(!config.system.has_positive_definite_mass());
    write_file(file, "[structure]\nmass = [1.0, 1.0]\nstiffness = [1.0, 1.0]\nexcitation = [1.0, 0.0]\n[[contact]]\n"
                "dof = 1\nforce_direction = [1.0, -1.0]\nlaw = \"coulomb\"\nfriction_limit = 0.2\n");
    CHECK_THROWS_WITH(hbf::io::read_system_config(file.string()), Catch::Contains("force_direction") && Catch::Contains("together"));
    write_file(file, "[structure]\nmass = [1.0, 1.0]\nstiffness = [1.0, 1.0]\nexcitation = [1.0, 0.0]\n[[contact]]\n"
                "force_direction = [1.0, -1.0, 0.0]\nlaw = \"coulomb\"\nfriction_limit = 0.2\n");
    CHECK_THROWS_WITH(hbf::io::read_system_config(file.string()), Catch::Contains("contact[1].force_direction") && Catch::Contains("3 entries"));
}

TEST_CASE("examples/systems/jenkins_negative_stiffness.toml: stable stick, unstable stick-slip in the CSV",
          "[config][exact]") {
    TempDir dir;
    const fs::path json = dir.path / "s.json";
    const Result r = run_hbf("frf --quiet --config '" + systems + "jenkins_negative_stiffness.toml' --summary '" +
                                 json.string() + "'",
                             dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    REQUIRE(rows[0][12] == "stable");
    int unstable = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        REQUIRE(rows[k][11] == "yes");
        // Full stick is a stable (damped, stiffness 1) linear motion; every stick-slip orbit of
        // this negative spring is unstable (tests/test_event_exact.cpp checks the growth by CVODE).
        CHECK(rows[k][12] == (rows[k][4] == "stick" ? "true" : "false"));
        if (rows[k][12] == "false") ++unstable;
    }
    CHECK(unstable > 10);
    CHECK_THAT(slurp(json), Catch::Contains("\"unstable\": " + std::to_string(unstable)));
}

TEST_CASE("examples/systems/chain3_exact.toml: both contacts' regimes in the CSV, their transitions in the JSON",
          "[config][exact][contacts]") {
    TempDir dir;
    const fs::path json = dir.path / "s.json";
    const Result r =
        run_hbf("frf --quiet --config '" + systems + "chain3_exact.toml' --summary '" + json.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    // Two contacts: a stick fraction and a regime per contact, no unsuffixed column.
    CHECK(std::find(rows[0].begin(), rows[0].end(), "regime") == rows[0].end());
    const std::size_t point = column(rows, "point"), w = column(rows, "w");
    const std::size_t regime[2] = {column(rows, "regime_c1"), column(rows, "regime_c2")};
    const std::size_t fraction[2] = {column(rows, "stick_fraction_c1"), column(rows, "stick_fraction_c2")};
    int csv_transitions = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        if (rows[k][point] == "transition") ++csv_transitions;
        for (int c = 0; c < 2; ++c) {  // the regime is the stick fraction's
            const double f = std::stod(rows[k][fraction[c]]);
            const std::string& g = rows[k][regime[c]];
            CHECK(g == (f == 1.0 ? "stick" : f == 0.0 ? "slip" : "stick-slip"));
        }
    }
    const nlohmann::json summary = nlohmann::json::parse(slurp(json));
    const nlohmann::json& transitions = summary.at("transitions");
    CHECK(static_cast<int>(transitions.size()) == csv_transitions);
    int per_contact[2] = {0, 0};
    for (const nlohmann::json& t : transitions) {
        const int c = t.at("contact").get<int>();
        REQUIRE((c == 1 || c == 2));
        ++per_contact[c - 1];
        // Its row: the stick side of that contact's boundary.
        const std::string stuck = t.at("between").get<std::string>() == "stick|stick-slip" ? "stick" : "stick-slip";
        bool found = false;
        for (std::size_t k = 1; k < rows.size(); ++k)
            if (rows[k][point] == "transition" &&
                std::abs(std::stod(rows[k][w]) - t.at("w").get<double>()) <= 1e-13 * t.at("w").get<double>()) {
                found = true;
                CHECK(rows[k][regime[c - 1]] == stuck);
            }
        CHECK(found);
    }
    CHECK(per_contact[0] > 0);
    CHECK(per_contact[1] > 0);
}
