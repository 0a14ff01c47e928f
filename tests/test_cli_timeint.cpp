// End-to-end tests of `hbf timeint`: columns, a value against the library's closed form, bad
// input (exit code 2, the flag named, no file left).
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_support.hpp"
#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/table.hpp"

using namespace test;

TEST_CASE("hbf timeint writes the documented columns and the exact stick amplitude", "[cli][timeint]") {
    TempDir dir;
    const fs::path file = dir.path / "ti.csv";
    const Result r = run_hbf("timeint --law coulomb --wmin 0.8 --wmax 1.3 --points 3 --out '" + file.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.empty());
    CHECK(r.err.empty());  // every point converged, no progress when not a terminal
    const auto rows = parse_csv(slurp(file));
    REQUIRE(rows.size() == 4);
    const auto columns = hbf::io::timeint_columns(2);
    REQUIRE(rows[0].size() == columns.size());
    for (std::size_t k = 0; k < columns.size(); ++k) CHECK(rows[0][k] == columns[k].name);
    CHECK(rows[0][0] == "w");
    CHECK(rows[0][1] == "y1_max");
    CHECK(rows[0][6] == "regime");
    CHECK(rows[0][8] == "periods");
    CHECK(rows[0][9] == "converged");
    // w = 0.8 is in full stick: |Y1| = fe / |1 - (1 + r) w^2| exactly (closed form), to the
    // integration accuracy (1e-8 relative; measured 1e-11).
    const hbf::AbsorberParameters p;
    CHECK(std::stod(rows[1][0]) == 0.8);
    CHECK(std::stod(rows[1][1]) == Approx(std::abs(hbf::analytic::coulomb_stick(p, 0.8).y1)).epsilon(1e-8));
    CHECK(rows[1][6] == "stick");
    CHECK(std::stod(rows[1][5]) == 1.0);
    for (std::size_t k = 1; k < rows.size(); ++k) CHECK(rows[k][9] == "true");
    CHECK(std::stod(rows[3][0]) == 1.3);  // ascending by default

    const Result down = run_hbf("timeint --law coulomb --wmin 0.8 --wmax 1.3 --points 3 --sweep down", dir);
    REQUIRE(down.exit_code == 0);
    const auto down_rows = parse_csv(down.out);
    REQUIRE(down_rows.size() == 4);
    CHECK(std::stod(down_rows[1][0]) == 1.3);
}

TEST_CASE("hbf timeint: a point that does not converge is written as such and the exit code is 1", "[cli][timeint]") {
    // Coulomb at w = 1 slips and needs about 40 periods (with shooting) to settle to 1e-8;
    // four periods cannot reach it.
    TempDir dir;
    const fs::path file = dir.path / "ti.csv";
    const Result r = run_hbf("timeint --law coulomb --w 1.0 --min-periods 3 --max-periods 4 --out '" + file.string() + "'", dir);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("did not converge") != std::string::npos);
    const auto rows = parse_csv(slurp(file));
    REQUIRE(rows.size() == 2);
    CHECK(rows[1][9] == "false");
    CHECK(rows[1][8] == "4");
}

TEST_CASE("hbf timeint --help lists every column", "[cli][timeint]") {
    TempDir dir;
    const Result r = run_hbf("timeint --help", dir);
    REQUIRE(r.exit_code == 0);
    for (const auto& c : hbf::io::timeint_columns(2)) CHECK(r.out.find("  " + c.name + ": ") != std::string::npos);
    for (const char* flag : {"--w ", "--wmin", "--wmax", "--points", "--sweep", "--rtol", "--atol", "--steady-tol",
                             "--max-periods", "--law"})
        CHECK(r.out.find(flag) != std::string::npos);
}

TEST_CASE("hbf timeint rejects bad input with exit code 2, the flag named and no file", "[cli][timeint]") {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--law coulomb --wmin 1 --wmax 2 --points 0", "--points"},
        {"--law coulomb --wmin 1 --wmax 2 --points 3 --sweep sideways", "--sweep"},
        {"--law coulomb --w 0", "--w"},
        {"--law coulomb --w 1 --wmin 0.5", "--w"},
        {"--law coulomb --wmin 2 --wmax 1 --points 3", "--wmax"},
        {"--law coulomb --w 1 --rtol 1", "--rtol"},
        {"--law coulomb --w 1 --max-periods 0", "--max-periods"},
        {"--law coulomb --w 1 --wb 2", "--wb"},
        {"--law friction --w 1", "law"},
        {"--law coulomb", "--w"},
    };
    for (const auto& [args, flag] : cases) {
        TempDir dir;
        const fs::path file = dir.path / "ti.csv";
        const Result r = run_hbf("timeint " + args + " --out '" + file.string() + "'", dir);
        INFO(args << " -> " << r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find(flag) != std::string::npos);
        CHECK(fs::is_empty(dir.path));  // no output file and no temporary left behind
    }
}

TEST_CASE("hbf timeint --method exact agrees with CVODE and refuses the smooth laws", "[cli][timeint][exact]") {
    TempDir dir;
    const std::string sweep = "timeint --law coulomb --wmin 0.8 --wmax 1.3 --points 11 ";
    const Result exact = run_hbf(sweep + "--method exact", dir);
    const Result cvode = run_hbf(sweep + "--rtol 1e-12 --atol 1e-14 --steady-tol 1e-11", dir);
    REQUIRE(exact.exit_code == 0);
    REQUIRE(cvode.exit_code == 0);
    const auto a = parse_csv(exact.out), b = parse_csv(cvode.out);
    REQUIRE(a.size() == 12);
    REQUIRE(a.size() == b.size());
    CHECK(a[0] == b[0]);
    for (std::size_t k = 1; k < a.size(); ++k) {
        INFO("w = " << a[k][0]);
        CHECK(a[k][9] == "true");
        CHECK(std::abs(std::stod(a[k][1]) - std::stod(b[k][1])) < 1e-8);  // y1_max
        CHECK(a[k][6] == b[k][6]);                                          // regime
        CHECK(a[k][12] == b[k][12]);                                        // switches
    }
    for (const char* law : {"dahl", "lugre", "coulomb-reg"}) {
        const Result bad = run_hbf(std::string("timeint --law ") + law + " --w 1 --method exact", dir);
        CHECK(bad.exit_code == 2);
        CHECK_THAT(bad.err, Catch::Contains("--method exact"));
    }
}

TEST_CASE("hbf timeint --config writes the DOFs the file reports, as hbf frf does", "[cli][timeint]") {
    // chain3.toml reports DOFs 1 and 3 ([output] report): timeint writes exactly those
    // columns, as frf does (it used to write every DOF).
    TempDir dir;
    const std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/chain3.toml";
    const Result r = run_hbf("timeint --config '" + file + "' --w 1.0", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    REQUIRE(rows.size() == 2);
    CHECK(rows[0][1] == "y1_max");
    CHECK(rows[0][2] == "y3_max");
    CHECK(rows[0][3] == "y1_amp1");
    CHECK(rows[0][4] == "y3_amp1");
    const Result f = run_hbf("frf --config '" + file + "' --exact off --error-points 0 --at 1.0", dir);
    REQUIRE(f.exit_code == 0);
    CHECK(parse_csv(f.out)[0][2] == "y3_max");
}

TEST_CASE("A time-integration row without one integrated period keeps every column: empty numbers and regime failed",
          "[timeint][io]") {
    // Such a row used to be one field short, which moved periods under energy.
    hbf::PeriodicResponse failed;
    failed.omega = 1.25;
    failed.periods = 0;
    hbf::PeriodicResponse ok;
    ok.omega = 1.5;
    ok.converged = true;
    ok.periods = 7;
    ok.switches = 2;
    ok.regime = "slip";
    ok.output_max = {0.5, 0.25};
    ok.output_amp1 = {0.4, 0.2};
    const std::vector<hbf::Output> outputs = {hbf::Output::dof(0), hbf::Output::dof(1)};
    std::ostringstream out;
    hbf::io::write_timeint_csv(out, {failed, ok}, outputs);
    const auto rows = parse_csv(out.str());
    REQUIRE(rows.size() == 3);
    const auto columns = hbf::io::timeint_columns(outputs);
    auto field = [&](std::size_t row, const std::string& name) {
        for (std::size_t k = 0; k < columns.size(); ++k)
            if (columns[k].name == name) return rows[row].at(k);
        FAIL("no column " << name);
        return std::string();
    };
    for (const auto& row : rows) CHECK(row.size() == columns.size());
    CHECK(field(1, "w") == "1.25");
    CHECK(field(1, "y1_max").empty());
    CHECK(field(1, "stick_fraction").empty());
    CHECK(field(1, "regime") == "failed");
    CHECK(field(1, "energy").empty());
    CHECK(field(1, "periods") == "0");
    CHECK(field(1, "converged") == "false");
    CHECK(field(1, "switches").empty());
    CHECK(field(2, "y2_max") == "0.25");
    CHECK(field(2, "periods") == "7");
    CHECK(field(2, "converged") == "true");
    CHECK(field(2, "switches") == "2");
    CHECK(field(2, "max_multiplier").empty());  // time integration: not computed
}

TEST_CASE("hbf timeint far above the resonances: the stuck closed form and the exact solver, or not converged",
          "[cli][timeint][scale]") {
    // The absorber at w = 1e4 (a 1 Hz structure driven at 10 kHz) and 1e9: both masses stuck
    // together are one mass 1 + r on the main spring, |Y1| = |Y2| = fe / ((1 + r) w^2 - 1)
    // (test_time_integration.cpp). Every method must give it to 1e-6 relative (the physics
    // checks' tolerance at the defaults) and agree with --method exact to 1e-6, or say
    // converged = false with a non-zero exit code.
    TempDir dir;
    const hbf::AbsorberParameters p;
    for (const char* w : {"1e4", "1e9"}) {
        const double omega = std::stod(w);
        const double closed = p.excitation / ((1.0 + p.mass_ratio) * omega * omega - 1.0);
        const Result exact = run_hbf(std::string("timeint --w ") + w + " --method exact", dir);
        REQUIRE(exact.exit_code == 0);
        const auto e = parse_csv(exact.out);
        REQUIRE(e.size() == 2);
        CHECK(std::abs(std::stod(e[1][1]) / closed - 1.0) < 1e-6);
        for (const char* method : {"adams", "bdf"}) {
            const Result r = run_hbf(std::string("timeint --w ") + w + " --method " + method, dir);
            const auto rows = parse_csv(r.out);
            INFO("w = " << w << ", " << method << ": " << r.err);
            REQUIRE(rows.size() == 2);
            if (rows[1][9] == "true") {
                CHECK(r.exit_code == 0);
                for (int column : {1, 2}) {  // y1_max, y2_max
                    CHECK(std::abs(std::stod(rows[1][column]) / closed - 1.0) < 1e-6);
                    CHECK(std::abs(std::stod(rows[1][column]) / std::stod(e[1][column]) - 1.0) < 1e-6);
                }
            } else {
                CHECK(r.exit_code != 0);
            }
        }
    }
}

TEST_CASE("hbf timeint --time-limit: the frequencies done are written (exit 3) and a bad limit is refused",
          "[cli][timeint][status]") {
    // 400 frequencies of the Dahl absorber take several seconds; a limit of 1 s writes the first
    // ones, each the same row as that frequency computed alone (the first one: from the same
    // start, the linear stuck state at 0.5).
    TempDir dir;
    const fs::path file = dir.path / "ti.csv";
    const Result r = run_hbf("timeint --law dahl --wmin 0.5 --wmax 2 --points 400 --time-limit 1 --out '" + file.string() + "'", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("time limit of 1 s (--time-limit) is reached") &&
                          Catch::Contains("of 400 frequencies written"));
    const auto rows = parse_csv(slurp(file));
    REQUIRE(rows.size() >= 2);
    CHECK(rows.size() < 401);
    for (std::size_t k = 1; k < rows.size(); ++k) CHECK(rows[k][9] == "true");
    const Result alone = run_hbf("timeint --law dahl --w 0.5", dir);
    REQUIRE(alone.exit_code == 0);
    const auto single = parse_csv(alone.out);
    REQUIRE(single.size() == 2);
    CHECK(single[1] == rows[1]);
    // Out of range: refused before any work, no file.
    const fs::path other = dir.path / "none.csv";
    const Result bad = run_hbf("timeint --law dahl --w 0.5 --time-limit -1 --out '" + other.string() + "'", dir);
    CHECK(bad.exit_code == 2);
    CHECK_THAT(bad.err, Catch::Contains("--time-limit = -1 is out of range"));
    CHECK_FALSE(fs::exists(other));
}

TEST_CASE("hbf timeint --method exact with law unilateral: the integrator's limit, and the unstable orbit it cannot reach",
          "[cli][timeint][exact]") {
    // liftoff3_rigid (three rigid contacts on massless nodes: stick, slip, lift-off): the exact
    // sweep against law unilateral's own integrator (Verlet with a complementarity solve per
    // step, second order) at the same frequencies. Where the integrator settles (2.1, 2.5, 2.7)
    // they agree to its step's error: maxima to 2e-6, the open share to 1e-3 (it counts whole
    // steps), the friction energy to 1e-3, the stick indicator to 3e-3 (both sample it: the
    // integrator on its steps, where the tangential force's passage through zero puts the
    // minimum at -1 between two of them). At 2.3 the orbit is
    // unstable (a period doubling at 2.315): the integrator does not settle there (exit 1) and the
    // exact sweep says so in a note (exit 0: the orbit is exact).
    TempDir dir;
    const std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";
    const std::string sweep = "timeint --config '" + file + "' --wmin 2.1 --wmax 2.7 --points 4 ";
    const Result exact = run_hbf(sweep + "--method exact", dir);
    const Result verlet = run_hbf(sweep, dir);
    REQUIRE(exact.exit_code == 0);
    CHECK(verlet.exit_code == 1);
    CHECK_THAT(exact.err, Catch::Contains("1 of 4 exact orbits are unstable") && Catch::Contains("w = 2.3"));
    const auto a = parse_csv(exact.out), b = parse_csv(verlet.out);
    REQUIRE(a.size() == 5);
    REQUIRE(b.size() == 5);
    REQUIRE(a[0] == b[0]);
    auto column = [&](const std::string& name) {
        const auto at = std::find(a[0].begin(), a[0].end(), name);
        REQUIRE(at != a[0].end());
        return static_cast<std::size_t>(at - a[0].begin());
    };
    auto relative = [](const std::string& x, const std::string& y) { return std::abs(std::stod(x) / std::stod(y) - 1.0); };
    for (std::size_t k = 1; k < a.size(); ++k) {
        INFO("w = " << a[k][0]);
        CHECK(a[k][column("converged")] == "true");
        if (a[k][0] == "2.3") {
            CHECK(b[k][column("converged")] == "false");
            continue;
        }
        REQUIRE(b[k][column("converged")] == "true");
        for (const char* name : {"y1_max", "y2_max", "y1_amp1", "y2_amp1"})
            CHECK(relative(a[k][column(name)], b[k][column(name)]) <= 2e-6);
        CHECK(std::abs(std::stod(a[k][column("separated_fraction")]) - std::stod(b[k][column("separated_fraction")])) <= 1e-3);
        CHECK(relative(a[k][column("energy")], b[k][column("energy")]) <= 1e-3);
        for (const char* name : {"stick_margin_min", "stick_margin_max"})
            CHECK(std::abs(std::stod(a[k][column(name)]) - std::stod(b[k][column(name)])) <= 3e-3);
        CHECK(std::stoi(a[k][column("periods")]) < std::stoi(b[k][column("periods")]));
    }
}

TEST_CASE("hbf timeint --method exact --symmetric on: the mirror-symmetric orbits, the unprojected solver's", "[cli][timeint]") {
    // tests/data/mirror_pair.toml: two masses on preloaded 3D rigid contacts, mirror images of
    // each other (y1 <-> y3, y2 <-> -y4). Swept from rest, whose start is symmetric, the solver
    // without the option (Newton on every unknown, nothing projected) finds the same orbits:
    // the option's projections must not move them (1e-9), and its orbits must be their own
    // mirror images (mirror-image DOFs' maxima and first harmonics equal to 1e-10).
    // Refused where it would do nothing: without --method exact, on contacts without a normal
    // and two tangential directions, on a structure without a mirror symmetry.
    TempDir dir;
    const std::string file = std::string(HBF_SOURCE_DIR) + "/tests/data/mirror_pair.toml";
    const std::string sweep = "timeint --config '" + file + "' --method exact --wmin 0.6 --wmax 0.9 --points 4 ";
    const Result on = run_hbf(sweep + "--symmetric on", dir);
    const Result off = run_hbf(sweep + "--symmetric off", dir);
    INFO(on.err << "\n" << off.err);
    REQUIRE(on.exit_code == 0);
    REQUIRE(off.exit_code == 0);
    const auto a = parse_csv(on.out), b = parse_csv(off.out);
    REQUIRE(a.size() == 5);
    REQUIRE(b.size() == 5);
    REQUIRE(a[0] == b[0]);
    for (std::size_t k = 1; k < a.size(); ++k) {
        INFO("w = " << a[k][0]);
        CHECK(a[k][0] == b[k][0]);
        const double size = column(a, a[k], "y1_max");
        for (const char* name : {"y1_max", "y2_max", "y3_max", "y4_max", "y1_amp1", "y2_amp1", "y3_amp1", "y4_amp1"})
            CHECK(std::abs(column(a, a[k], name) - column(b, b[k], name)) <= 1e-9 * size);
        CHECK(std::abs(column(a, a[k], "y1_max") - column(a, a[k], "y3_max")) <= 1e-10 * size);
        CHECK(std::abs(column(a, a[k], "y2_max") - column(a, a[k], "y4_max")) <= 1e-10 * size);
        CHECK(std::abs(column(a, a[k], "y1_amp1") - column(a, a[k], "y3_amp1")) <= 1e-10 * size);
        CHECK(std::abs(column(a, a[k], "y2_amp1") - column(a, a[k], "y4_amp1")) <= 1e-10 * size);
    }

    check_bad_input("timeint --config '" + file + "' --w 0.7 --symmetric on", {"--symmetric on applies to --method exact"}, dir);
    check_bad_input("timeint --config '" + file + "' --w 0.7 --method exact --symmetric yes",
                    {"--symmetric = 'yes' is not allowed: allowed on, off"}, dir);
    const std::string liftoff = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";
    check_bad_input("timeint --config '" + liftoff + "' --w 2.1 --method exact --symmetric on",
                    {"--symmetric on: mirror-symmetric orbits apply to law unilateral's 3D contacts"}, dir);
    // one spring 1e-6 stiffer on mass a's side: no mirror
    std::string text = slurp(file);
    const std::string row = "stiffness = [[11, 0.5,";
    REQUIRE(text.find(row) != std::string::npos);
    text.replace(text.find(row), row.size(), "stiffness = [[11.000001, 0.5,");
    const fs::path broken = dir.path / "broken.toml";
    write_file(broken, text);
    check_bad_input("timeint --config '" + broken.string() + "' --w 0.7 --method exact --symmetric on",
                    {"--symmetric on: the structure has no mirror symmetry"}, dir);
}
