// Reported outputs o(t) = c^T y(t) ([[output]] in a system file, model.hpp's Output): the
// same quantity from harmonic balance, the event-exact solver and time integration, against
// the closed-form stuck response and against each other.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>
#include <complex>

#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/linear_limits.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"

using namespace test;

namespace {

const std::string systems = std::string(HBF_SOURCE_DIR) + "/examples/systems/";


/// chain3_exact.toml's structure (Jenkins between DOFs 1 and 2, Coulomb from DOF 3 to the
/// ground) with the given friction limits and three outputs: spread = y1 - 0.5 y2 + 2 y3,
/// y3 (a DOF), and rel = y2 - y3 from a 1 x 3 Matrix Market row beside the file.
fs::path chain_with_outputs(const fs::path& dir, double jenkins_limit, double coulomb_limit) {
    write_file(dir / "row.mtx", "%%MatrixMarket matrix coordinate real general\n1 3 2\n1 2 1.0\n1 3 -1.0\n");
    const fs::path file = dir / "chain.toml";
    write_file(file, "[structure]\nmass = [1.0, 0.5, 0.25]\nstiffness = \"" + systems + "chain3_stiffness.mtx\"\n"
                "damping = [[0.02, -0.01, 0.0], [-0.01, 0.02, -0.01], [0.0, -0.01, 0.01]]\n"
                "excitation = [1.0, 0.0, 0.0]\n"
                "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"jenkins\"\nfriction_limit = " +
                    std::to_string(jenkins_limit) + "\nstiffness = 2.0\n"
                    "[[contact]]\ndof = 3\nlaw = \"coulomb\"\nfriction_limit = " + std::to_string(coulomb_limit) + "\n"
                    "[[output]]\nname = \"spread\"\nrow = [1.0, -0.5, 2.0]\n"
                    "[[output]]\ndof = 3\n"
                    "[[output]]\nname = \"rel\"\nrow = \"row.mtx\"\n");
    return file;
}

}  // namespace

TEST_CASE("[[output]] vectors: read from the file, in order, with their names and terms", "[outputs][config]") {
    TempDir dir;
    const hbf::io::SystemConfig config = hbf::io::read_system_config(chain_with_outputs(dir.path, 0.3, 0.1).string());
    REQUIRE(config.outputs.size() == 3);
    CHECK(config.outputs[0].name() == "spread");
    CHECK(config.outputs[0].terms() == std::vector<hbf::Output::Term>{{0, 1.0}, {1, -0.5}, {2, 2.0}});
    CHECK(config.outputs[1].name() == "y3");
    CHECK(config.outputs[1].single_dof() == 2);
    CHECK(config.outputs[2].name() == "rel");
    CHECK(config.outputs[2].terms() == std::vector<hbf::Output::Term>{{1, 1.0}, {2, -1.0}});
}

TEST_CASE("[[output]] vectors in stick: HB, exact and time integration equal the closed-form |c^T Y|",
          "[outputs][config][exact][timeint]") {
    // Friction limits of 100 keep both contacts stuck: the structure is linear (Jenkins = its
    // spring, Coulomb = a rigid support) and o(t) = Re(c^T Y e^{i w t}), so max |o| = |c^T Y|
    // with Y from stuck_linear_response (y3 is held at 0 by the Coulomb support).
    TempDir dir;
    const fs::path file = chain_with_outputs(dir.path, 100.0, 100.0);
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    const double w = 0.7;
    const hbf::StuckResponse stuck = hbf::stuck_linear_response(config.system, w);
    REQUIRE(stuck.ok);
    auto reference = [&](const hbf::Output& o) {
        std::complex<double> sum = 0.0;
        for (const auto& [i, c] : o.terms()) sum += c * stuck.amplitude(i);
        return std::abs(sum);
    };
    for (const std::string exact : {"off", "on"}) {
        const Result r = run_hbf("frf --quiet --config '" + file.string() + "' --exact " + exact + " --at 0.7", dir);
        INFO("--exact " << exact << ": " << r.err);
        REQUIRE(r.exit_code == 0);
        const auto rows = parse_csv(r.out);
        CHECK(rows.front()[1] == "spread_max");
        const auto row = sample_row(rows, w);
        REQUIRE(!row.empty());
        for (const hbf::Output& o : config.outputs) {
            INFO(o.name());
            CHECK(column(rows, row, o.name() + "_max") == Approx(reference(o)).epsilon(1e-9).margin(1e-12));
            CHECK(column(rows, row, o.name() + "_amp1") == Approx(reference(o)).epsilon(1e-9).margin(1e-12));
        }
    }
    hbf::TimeIntegrationOptions tio;
    tio.outputs = config.outputs;
    const hbf::PeriodicResponse ti = hbf::integrate_steady_state(config.system, w, tio);
    REQUIRE(ti.converged);
    for (std::size_t j = 0; j < config.outputs.size(); ++j) {
        INFO(config.outputs[j].name());
        CHECK(ti.output_max[j] == Approx(reference(config.outputs[j])).epsilon(1e-7).margin(1e-10));
        CHECK(ti.output_amp1[j] == Approx(reference(config.outputs[j])).epsilon(1e-7).margin(1e-10));
    }
}

TEST_CASE("[[output]] vectors in stick-slip: the exact orbit's turning points equal time integration's roots",
          "[outputs][config][exact][timeint]") {
    // At w = 1 the Jenkins contact slips part of the period: o(t) is not harmonic, and its max
    // comes from the turning points of c^T y' = 0 (the exact solver: roots of the step
    // polynomials; CVODE: root finding), two independent computations. Harmonic balance (plain,
    // H = 20) is within its truncation error of them.
    TempDir dir;
    const fs::path file = chain_with_outputs(dir.path, 0.3, 0.1);
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    hbf::TimeIntegrationOptions tight;
    tight.relative_tolerance = 1e-12;
    tight.absolute_tolerance = 1e-14;
    tight.steady_tolerance = 1e-11;
    tight.outputs = config.outputs;
    const hbf::PeriodicResponse ti = hbf::integrate_steady_state(config.system, 1.0, tight);
    REQUIRE(ti.converged);
    REQUIRE(ti.regime == "stick-slip");
    const fs::path json = dir.path / "s.json";
    const Result exact = run_hbf("frf --quiet --config '" + file.string() + "' --at 1 --summary '" + json.string() + "'", dir);
    const Result plain = run_hbf("frf --quiet --config '" + file.string() + "' --exact off --harmonics 20 --at 1", dir);
    REQUIRE(exact.exit_code == 0);
    REQUIRE(plain.exit_code == 0);
    const auto exact_rows = parse_csv(exact.out), plain_rows = parse_csv(plain.out);
    const auto exact_row = sample_row(exact_rows, 1.0), plain_row = sample_row(plain_rows, 1.0);
    REQUIRE(!exact_row.empty());
    REQUIRE(!plain_row.empty());
    for (std::size_t j = 0; j < config.outputs.size(); ++j) {
        const std::string& name = config.outputs[j].name();
        INFO(name << ": TI " << ti.output_max[j]);
        CHECK(std::abs(column(exact_rows, exact_row, name + "_max") - ti.output_max[j]) <= 1e-8);
        CHECK(std::abs(column(exact_rows, exact_row, name + "_amp1") - ti.output_amp1[j]) <= 1e-8);
        CHECK(column(plain_rows, plain_row, name + "_max") == Approx(ti.output_max[j]).epsilon(2e-2));
    }
    // The summary has the peaks of every output, by name (and the DOF of y3).
    const nlohmann::json summary = nlohmann::json::parse(slurp(json));
    int spread = 0, y3 = 0;
    for (const auto& p : summary.at("peaks")) {
        if (p.at("output") == "spread") ++spread;
        if (p.at("output") == "y3") {
            ++y3;
            CHECK(p.at("dof") == 3);
        }
        CHECK(p.at("refined") == true);
    }
    CHECK(spread >= 1);
    CHECK(y3 >= 1);
    // hbf timeint --config writes the same columns from the same integration.
    const Result t = run_hbf("timeint --quiet --config '" + file.string() +
                                 "' --wmin 1 --wmax 1.5 --points 2 --rtol 1e-12 --atol 1e-14 --steady-tol 1e-11",
                             dir);
    INFO(t.err);
    REQUIRE(t.exit_code == 0);
    const auto rows = parse_csv(t.out);
    REQUIRE(rows.size() == 3);
    CHECK(rows.front()[1] == "spread_max");
    CHECK(rows.front()[4] == "spread_amp1");
    CHECK(std::stod(rows[1][1]) == Approx(ti.output_max[0]).epsilon(1e-7));
}

TEST_CASE("[[output]] errors name the key and the allowed values, and no output file is written", "[outputs][config][cli]") {
    TempDir dir;
    const std::string structure = "[structure]\nmass = [1.0, 1.0]\nstiffness = [1.0, 1.0]\nexcitation = [1.0, 0.0]\n";
    struct Case {
        std::string text;
        std::vector<std::string> expected;
    };
    const std::vector<Case> cases = {
        {structure + "[[output]]\nrow = [1.0, 1.0]\n", {"output[1].name", "needs a name"}},
        {structure + "[[output]]\nname = \"a\"\nrow = [1.0]\n", {"output[1].row", "1 entries: allowed 2"}},
        {structure + "[[output]]\nname = \"a\"\nrow = [0.0, 0.0]\n", {"output[1].row", "every entry is zero"}},
        {structure + "[[output]]\nname = \"a\"\ndof = 1\nrow = [1.0, 0.0]\n", {"output[1]", "exactly one of 'dof'"}},
        {structure + "[[output]]\ndof = 3\n", {"output[1].dof", "allowed 1..2"}},
        {structure + "[[output]]\nname = \"y2\"\nrow = [1.0, 0.0]\n", {"output[1].name", "reserved for DOF 2"}},
        {structure + "[[output]]\nname = \"2tip\"\nrow = [1.0, 0.0]\n", {"output[1].name", "a letter, then"}},
        {structure + "[[output]]\nname = \"a\"\nrow = [1.0, 0.0]\n[[output]]\nname = \"a\"\nrow = [0.0, 1.0]\n",
         {"output[2].name", "already an output name"}},
        {structure + "[[output]]\ndof = 1\n[[output]]\ndof = 1\n", {"output[2].name", "already an output name"}},
        {structure + "[[output]]\nname = \"a\"\nrow = [1.0, 0.0]\nscale = 2\n", {"output[1].scale", "unknown key"}},
        {structure + "[output]\nreport = [1, 1]\n", {"output.report", "listed twice"}},
    };
    for (const Case& c : cases) check_bad_config(c.text, c.expected, dir);
}

TEST_CASE("JSON folds and transitions carry <name>_max of every output, as the CSV's rows there", "[outputs][cli]") {
    // The paper's absorber (exact Coulomb: four stick-slip transitions) with the outputs y1
    // and the relative displacement q = y1 - y2.
    TempDir dir;
    const fs::path file = dir.path / "absorber_outputs.toml";
    write_file(file, "[structure]\nmass = [1.0, 0.1]\nstiffness = [[1.1, -0.1], [-0.1, 0.1]]\nexcitation = [0.5, 0.0]\n"
                     "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"coulomb\"\nfriction_limit = 0.2\n"
                     "[[output]]\ndof = 1\n[[output]]\nname = \"q\"\nrow = [1.0, -1.0]\n");
    const fs::path json = dir.path / "s.json";
    const Result r = run_hbf("frf --quiet --config '" + file.string() + "' --summary '" + json.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(r.out);
    const auto& header = rows.front();
    const auto kind = static_cast<std::size_t>(std::find(header.begin(), header.end(), "point") - header.begin());
    const nlohmann::json summary = nlohmann::json::parse(slurp(json));
    int matched = 0;
    for (const auto& t : summary.at("transitions")) {
        const double w = t.at("w");
        for (std::size_t k = 1; k < rows.size(); ++k) {
            if (rows[k][kind] != "transition" || std::abs(std::stod(rows[k][0]) - w) > 1e-12 * w) continue;
            ++matched;
            for (const std::string name : {"y1_max", "q_max"})
                CHECK(t.at(name).get<double>() == Approx(column(rows, rows[k], name)).epsilon(1e-12));
        }
    }
    CHECK(matched == 4);
}
