// End-to-end tests of the `hbf` executable: output format and values, help, and bad input.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "progress.hpp"  // src/cli
#include "hbf/analytic.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/version.hpp"
#include "hbf/absorber.hpp"

namespace fs = std::filesystem;
namespace an = hbf::analytic;

using namespace test;

namespace {
const char* header = "w,y1_stick,y2_stick,y1_slip,y2_slip,mu_limit,mu_opt_den_hartog";
}  // namespace

TEST_CASE("hbf analytic prints the documented table with closed-form values", "[cli]") {
    TempDir dir;
    const Result r = run_hbf("analytic --law lugre --fe 0.8 --wmin 0.6 --wmax 1.4 --points 9", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.empty());
    const auto rows = parse_csv(r.out);
    REQUIRE(rows.size() == 10);
    std::string first_line = r.out.substr(0, r.out.find('\n'));
    CHECK(first_line == header);
    hbf::AbsorberParameters p;
    p.excitation = 0.8;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        REQUIRE(rows[k].size() == 7);
        const double omega = std::stod(rows[k][0]);
        CHECK(omega == Approx(0.6 + 0.1 * static_cast<double>(k - 1)).epsilon(1e-14));
        const auto stick = an::contact_stick(p, omega, hbf::FrictionLaw::lugre);
        CHECK(std::stod(rows[k][1]) == Approx(std::abs(stick.y1)).epsilon(1e-13));
        CHECK(std::stod(rows[k][2]) == Approx(std::abs(stick.y2)).epsilon(1e-13));
        const auto slip = an::coulomb_slip(p, omega);
        CHECK(rows[k][3].empty() == !slip.has_value());
        if (slip) CHECK(std::stod(rows[k][3]) == Approx(std::abs(slip->y1)).epsilon(1e-13));
        CHECK(std::stod(rows[k][5]) == Approx(an::contact_limit_friction(p, omega, hbf::FrictionLaw::lugre)).epsilon(1e-13));
        CHECK(std::stod(rows[k][6]) == Approx(an::den_hartog_friction(p, omega)).epsilon(1e-13));
    }
}

TEST_CASE("hbf analytic defaults: paper system, 221 points on [0.5, 1.6], --out writes a file", "[cli]") {
    TempDir dir;
    const fs::path file = dir.path / "frf.csv";
    const Result r = run_hbf("analytic --out '" + file.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.empty());
    const auto rows = parse_csv(slurp(file));
    REQUIRE(rows.size() == 222);
    CHECK(std::stod(rows[1][0]) == 0.5);
    CHECK(std::stod(rows.back()[0]) == 1.6);
    const hbf::AbsorberParameters p;  // r = 0.1, wa = 1, mu = 0.2, fe = 0.5
    const double omega = std::stod(rows[100][0]);
    CHECK(std::stod(rows[100][1]) == Approx(std::abs(an::coulomb_stick(p, omega).y1)).epsilon(1e-13));
    CHECK(std::stod(rows[100][5]) == Approx(an::coulomb_limit_friction(p, omega)).epsilon(1e-13));
    // Nothing but the requested file is left in the directory (no temporary files).
    CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}) == 1);
}

TEST_CASE("hbf --help documents the commands and exit codes, analytic --help every flag and column", "[cli]") {
    TempDir dir;
    const Result top = run_hbf("--help", dir);
    CHECK(top.exit_code == 0);
    CHECK_THAT(top.out, Catch::Contains("analytic") && Catch::Contains("Exit codes") &&
                            Catch::Contains("2 bad input"));
    const Result sub = run_hbf("analytic --help", dir);
    CHECK(sub.exit_code == 0);
    for (const char* word : {"--law", "--r", "--wa", "--mu", "--fe", "--wb", "--xi", "--wmin", "--wmax",
                             "--points", "--out", "y1_stick", "y2_stick", "y1_slip", "y2_slip", "mu_limit",
                             "mu_opt_den_hartog", "x_s = N / k1"})
        CHECK_THAT(sub.out, Catch::Contains(word));
}

TEST_CASE("hbf <command> --columns lists the output columns, and hbf reference every command, law and key",
          "[cli]") {
    TempDir dir;
    const Result columns = run_hbf("frf --columns", dir);
    CHECK(columns.exit_code == 0);
    CHECK(columns.err.empty());
    // The same columns as --help lists (a line "name: meaning" each), in its order.
    const Result help = run_hbf("frf --help", dir);
    std::istringstream lines(columns.out);
    std::string line;
    std::size_t count = 0, last = 0;
    while (std::getline(lines, line)) {
        ++count;
        const std::size_t at = help.out.find("  " + line + "\n");
        INFO(line);
        CHECK(at != std::string::npos);
        CHECK(at >= last);
        if (at != std::string::npos) last = at;
    }
    CHECK(count >= 20);
    CHECK_THAT(columns.out, Catch::StartsWith("w: "));

    const Result reference = run_hbf("reference", dir);
    REQUIRE(reference.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(reference.out);
    CHECK(j["version"] == hbf::version());
    std::vector<std::string> commands;
    for (const auto& c : j["commands"]) commands.push_back(c["name"]);
    CHECK(commands == std::vector<std::string>{"analytic", "frf", "loop", "map", "modes", "nodal-diameters", "optimize",
                                               "timeint", "track"});
    for (const auto& c : j["commands"]) {
        // Every flag --help prints, with its description.
        const Result h = run_hbf(c["name"].get<std::string>() + " --help", dir);
        for (const auto& f : c["flags"]) {
            const std::string name = f["name"];
            INFO(c["name"] << " " << name);
            CHECK_THAT(h.out, Catch::Contains(name.substr(name.rfind(',') + 1)));
            // --help: one line each, short; the details are in the reference.
            const std::string summary = f["summary"];
            CHECK_FALSE(summary.empty());
            CHECK(summary.size() <= 160);
            CHECK(summary.find('\n') == std::string::npos);
            if (!f["details"].get<std::string>().empty()) CHECK_THAT(h.out, !Catch::Contains(f["details"].get<std::string>()));
        }
        CHECK(c["output"]["columns"].size() >= 3);
    }
    // Every command's flags read in a minute: their summaries at most 14 words on average (with
    // every detail inline, hbf frf's were 1,900 words for 38 flags).
    for (const auto& c : j["commands"]) {
        std::size_t words = 0;
        for (const auto& f : c["flags"]) {
            std::istringstream in(f["summary"].get<std::string>());
            for (std::string word; in >> word;) ++words;
        }
        INFO(c["name"]);
        CHECK(words <= 14 * c["flags"].size());
    }
    CHECK(j["laws"].size() == hbf::contact_laws().size());
    for (std::size_t k = 0; k < hbf::contact_laws().size(); ++k) {
        CHECK(j["laws"][k]["name"] == hbf::contact_laws()[k]->name());
        CHECK(j["laws"][k]["parameters"].size() == hbf::contact_laws()[k]->parameters().size());
    }
    CHECK(j["config"].size() == hbf::io::config_keys().size());
}

TEST_CASE("hbf modes without an amplitude range chooses it around the slip onset and says so", "[cli][modes]") {
    TempDir dir;
    const fs::path out = dir.path / "modes.csv";
    const Result r = run_hbf("modes --law jenkins --quiet --out '" + out.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string said = "a* = ";
    const auto at = r.err.find(said);
    CHECK_THAT(r.err, Catch::Contains("no stuck motion above it, contact 1 slips there"));
    REQUIRE(at != std::string::npos);
    CHECK_THAT(r.err, Catch::Contains("hbf modes: note: the range a = "));
    const double onset = std::stod(r.err.substr(at + said.size()));
    const auto rows = parse_csv(slurp(out));
    REQUIRE(rows.size() > 10);
    const double first = column(rows, rows[1], "a"), last = column(rows, rows.back(), "a");
    CHECK(std::abs(first / (onset / 10.0) - 1.0) <= 1e-6);
    CHECK(std::abs(last / (onset * 100.0) - 1.0) <= 1e-6);
    // The backbone itself sticks below the onset and slips soon above it.
    double first_slip = 0.0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double a = column(rows, rows[k], "a"), stick = column(rows, rows[k], "stick_fraction_c1");
        if (a < onset * (1.0 - 1e-9)) CHECK(stick == 1.0);
        if (stick < 1.0 && first_slip == 0.0) first_slip = a;
    }
    CHECK(first_slip >= onset * (1.0 - 1e-9));
    CHECK(first_slip <= 1.6 * onset);
    // A given range is used as given; half of one is refused.
    const Result given = run_hbf("modes --law jenkins --quiet --amin 0.1 --amax 1 --out '" + out.string() + "'", dir);
    CHECK(given.exit_code == 0);
    CHECK_THAT(given.err, !Catch::Contains("the range a = "));
    check_bad_input("modes --law jenkins --amin 0.1", {"--amax is missing"}, dir);
}

TEST_CASE("hbf analytic rejects bad input with exit code 2, a named parameter and no file", "[cli]") {
    struct Case {
        std::string args;
        std::string names;  // what the message must mention
    };
    const std::vector<Case> cases = {
        {"--r -0.1", "r (mass ratio"},
        {"--r 0", "r (mass ratio"},
        {"--mu 0", "mu (friction coefficient"},
        {"--mu -1", "mu (friction coefficient"},
        {"--fe 0", "fe (excitation"},
        {"--wmin 1.6 --wmax 1.6", "wmax"},
        {"--wmin 1.7", "wmax"},
        {"--wmin 0", "wmin"},
        {"--wmin -0.5", "wmin"},
        {"--points 1", "points"},
        {"--points 0", "points"},
        {"--points 100000000", "points"},
        {"--points 99999999999999999999999", "--points"},
        {"--points 2.5", "--points"},
        {"--mu nan", "--mu"},
        {"--fe inf", "--fe"},
        {"--wmax -inf", "--wmax"},
        {"--wa 1e999", "--wa"},
        {"--r 1e-999", "--r"},
        {"--mu abc", "--mu"},
        {"--mu 0.2x", "--mu"},
        {"--mu ''", "--mu"},
        {"--law stribeck", "--law"},
        {"--law dahl --wb 0", "wb"},
        {"--law lugre --xi -0.1", "xi"},
        {"--law coulomb --wb 0.4", "--wb"},
        {"--law dahl --xi 0.1", "--xi"},
        {"--frobnicate 3", "--frobnicate"},
        {"--mu", "--mu"},
        {"--sweep wb --values 1", "--sweep"},
        {"--law lugre --sweep wb --values 1 --wb 2", "--wb"},
        {"--law lugre --sweep wb --values 0,1", "wb"},
        {"--law lugre --sweep wb", "--values"},
        {"--values 1,2", "--sweep"},
        {"--sweep fe --values 1 --points 5", "--points"},
        {"--sweep fe --values 1:2:0", "--values"},
    };
    for (const Case& c : cases) {
        TempDir dir;
        const fs::path file = dir.path / "out.csv";
        const Result r = run_hbf("analytic --out '" + file.string() + "' " + c.args, dir);
        INFO("args: " << c.args << "\nstderr: " << r.err);
        CHECK(r.exit_code == 2);
        CHECK_THAT(r.err, Catch::Contains(c.names));
        CHECK(r.out.empty());
        CHECK(dir.empty());  // no output file and no temporary left behind
    }
}

TEST_CASE("hbf analytic --sweep: the band's largest mu_limit per value, as --summary and the closed forms give it",
          "[cli]") {
    TempDir dir;
    const Result sweep = run_hbf("analytic --law lugre --fe 1 --xi 0.05 --sweep wb --values 0.2,2,20", dir);
    REQUIRE(sweep.exit_code == 0);
    const auto rows = parse_csv(sweep.out);
    REQUIRE(rows.size() == 4u);
    CHECK(rows[0] == std::vector<std::string>{"wb", "w_at_max", "mu_limit_max"});
    for (std::size_t k = 1; k < rows.size(); ++k) {
        // The same maximum from --summary of the single system, and from the library directly.
        const Result single = run_hbf("analytic --law lugre --fe 1 --xi 0.05 --wb " + rows[k][0] +
                                          " --out /dev/null --summary '" + (dir.path / "s.json").string() + "'",
                                      dir);
        REQUIRE(single.exit_code == 0);
        const std::string json = slurp(dir.path / "s.json");
        const double value = std::stod(rows[k][2]);
        hbf::AbsorberParameters p;
        p.excitation = 1.0;
        p.contact_damping_ratio = 0.05;
        p.contact_stiffness_ratio = std::stod(rows[k][0]);
        const auto m = an::limit_friction_maximum(p, hbf::FrictionLaw::lugre, 0.5, 1.6);
        CHECK(value == Approx(m.value).epsilon(1e-13));
        CHECK(std::stod(rows[k][1]) == Approx(m.omega).epsilon(1e-13));
        // ... and never below the closed form on a dense grid.
        for (double w : an::uniform_grid(0.5, 1.6, 20001))
            CHECK(an::limit_friction(p, w, hbf::FrictionLaw::lugre) <= value * (1.0 + 1e-13));
        CHECK_THAT(json, Catch::Contains("\"bounded\": true"));
    }
    // Coulomb's stuck resonance 1/sqrt(1 + r) lies in the band for every mu: empty, unbounded.
    const Result coulomb = run_hbf("analytic --law coulomb --sweep mu --values 0.1,0.3", dir);
    REQUIRE(coulomb.exit_code == 0);
    const auto c = parse_csv(coulomb.out);
    REQUIRE(c.size() == 3u);
    for (std::size_t k = 1; k < 3; ++k) {
        CHECK(std::stod(c[k][1]) == Approx(1.0 / std::sqrt(1.1)).epsilon(1e-14));
        CHECK((c[k].size() == 2u || c[k][2].empty()));
    }
}

TEST_CASE("hbf without a command or with an unknown command is bad input", "[cli]") {
    TempDir dir;
    CHECK(run_hbf("", dir).exit_code == 2);
    const Result r = run_hbf("frobnicate", dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("frobnicate"));
}

TEST_CASE("an output path in a missing directory is bad input found before any work, a failed write a failure",
          "[cli]") {
    TempDir dir;
    const Result r = run_hbf("analytic --out '" + (dir.path / "missing" / "x.csv").string() + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--out") && Catch::Contains("missing/x.csv") && Catch::Contains("does not exist"));
    CHECK(dir.empty());
    const Result full = run_hbf("analytic --out /dev/full", dir);  // the device takes no data
    CHECK(full.exit_code == 1);
    CHECK_THAT(full.err, Catch::Contains("cannot write"));
}

TEST_CASE("hbf frf writes the documented columns, samples and a JSON summary", "[cli]") {
    TempDir dir;
    const fs::path csv = dir.path / "frf.csv", json = dir.path / "frf.json";
    const Result r = run_hbf("frf --law dahl --harmonics 5 --wmin 0.6 --wmax 1.2 --at 0.7,1.1 --quiet --out '" +
                                 csv.string() + "' --summary '" + json.string() + "'",
                             dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(slurp(csv));
    REQUIRE(rows.size() > 10);
    const std::vector<std::string> header = {"w",      "y1_max", "y2_max",     "y1_amp1",  "y2_amp1",
                                             "stick_fraction", "regime", "energy", "branch", "point",
                                             "iterations", "residual", "step", "exact", "stable", "hb_gap",
                                             "hb_error", "energy_error", "stability_margin"};
    CHECK(rows[0] == header);
    CHECK(std::stod(rows[1][0]) == 0.6);
    int samples = 0, estimated = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        REQUIRE(rows[k].size() == header.size());
        // max |y1| >= rms(y1) >= amp1 / sqrt(2) (Parseval); not >= amp1: harmonics can flatten a peak.
        CHECK(std::stod(rows[k][1]) >= std::stod(rows[k][3]) / std::sqrt(2.0));
        if (rows[k][9] == "sample") {
            ++samples;
            CHECK((std::stod(rows[k][0]) == 0.7 || std::stod(rows[k][0]) == 1.1));
        }
        CHECK(std::stod(rows[k][11]) <= 1e-9);
        CHECK(rows[k][13] == "off");  // dahl: no exact polish, plain harmonic balance
        CHECK(rows[k][14].empty());
        CHECK(rows[k][15].empty());
        // Harmonic balance's estimated error: Dahl converges fast (below 1e-3 at H = 5 here).
        if (!rows[k][16].empty()) {
            ++estimated;
            CHECK(std::stod(rows[k][16]) < 1e-2);
        }
        // Input work = friction energy (no viscous damping) at every converged point.
        CHECK(std::stod(rows[k][17]) <= 1e-6);
    }
    CHECK(samples == 2);
    CHECK(estimated >= 12);
    const std::string summary = slurp(json);
    for (const char* key : {"\"parameters\"", "\"solver\"", "\"peaks\"", "\"folds\"", "\"status\": \"completed\"",
                            "\"wall_time_seconds\"", "\"harmonics\": 5"})
        CHECK_THAT(summary, Catch::Contains(key));
}

TEST_CASE("hbf frf --law coulomb writes the located stick-slip transitions as rows and in the summary", "[cli]") {
    TempDir dir;
    const fs::path csv = dir.path / "frf.csv", json = dir.path / "frf.json";
    const Result r = run_hbf("frf --law coulomb --quiet --out '" + csv.string() + "' --summary '" + json.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(slurp(csv));
    REQUIRE(rows.size() > 10);
    // Closed form (test_continuation): stick ends where r w^2 fe / |1 - (1 + r) w^2| = mu.
    const double r_ = 0.1, fe = 0.5, mu = 0.2;
    const std::vector<double> expected = {std::sqrt(mu / (r_ * fe + mu * (1 + r_))), std::sqrt(mu / (mu * (1 + r_) - r_ * fe))};
    std::vector<double> found;
    for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k][9] == "transition" && rows[k][6] == "stick")  // the stick|stick-slip ones
            found.push_back(std::stod(rows[k][0]));
    REQUIRE(found.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) CHECK(found[k] == Approx(expected[k]).epsilon(1e-8));
    const std::string summary = slurp(json);
    CHECK_THAT(summary, Catch::Contains("\"transitions\"") && Catch::Contains("\"between\": \"stick|stick-slip\""));
}

TEST_CASE("hbf frf rejects bad input with exit code 2 and no files", "[cli]") {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--law coulomb --dlft-eps 0", "--dlft-eps"}, {"--law lugre --dlft-eps 1", "--dlft-eps"},
        {"--law coulomb --xi 0.1", "--xi"},   {"--law dahl --exact on", "--exact"}, {"--exact yes", "--exact"},   {"--harmonics -1", "--harmonics"}, {"--max-step 0", "--max-step"}, {"--harmonics 1e3", "--harmonics"},
        {"--time-samples 5", "--time-samples"}, {"--at 0.7,x", "--at"},       {"--at 0.7,-1", "--at"},
        {"--max-amplitude 0", "max_amplitude"}, {"--tolerance 1", "--tolerance"}, {"--law lugre --eps 0.1", "--eps"},
        {"--law dahl --viscous 0.1", "--viscous"}, {"--law coulomb-reg --eps 0", "eps"}, {"--wmin 2", "wmax"},
    };
    for (const auto& [args, names] : cases) {
        TempDir dir;
        const Result r = run_hbf("frf --out '" + (dir.path / "a.csv").string() + "' --summary '" +
                                     (dir.path / "a.json").string() + "' " + args,
                                 dir);
        INFO("args: " << args << "\nstderr: " << r.err);
        CHECK(r.exit_code == 2);
        CHECK_THAT(r.err, Catch::Contains(names));
        CHECK(dir.empty());
    }
}

TEST_CASE("Plots: PNG and SVG through gnuplot, with time-integration markers and their CSV from --overlay-timeint",
          "[cli][plot]") {
    TempDir dir;
    const fs::path png = dir.path / "frf.png", svg = dir.path / "an.svg", ti = dir.path / "ti.svg";
    Result r = run_hbf("frf --quiet --wmin 0.5 --wmax 0.8 --out /dev/null --plot '" + png.string() +
                           "' --overlay-timeint 4",
                       dir);
    REQUIRE(r.exit_code == 0);
    const std::string image = slurp(png);
    REQUIRE(image.size() > 1000);
    CHECK(image.substr(1, 3) == "PNG");
    // The overlay CSV beside the plot: hbf timeint's columns; w = 0.5 is in full stick, where
    // y1_max = fe / |1 - (1 + r) w^2| exactly (derived by hand), to the integration accuracy.
    const auto rows = parse_csv(slurp(dir.path / "frf-timeint.csv"));
    REQUIRE(rows.size() == 5);
    CHECK(rows[0][9] == "converged");
    CHECK(std::stod(rows[1][0]) == 0.5);
    CHECK(std::stod(rows[1][1]) == Approx(0.5 / (1.0 - 1.1 * 0.25)).epsilon(1e-8));
    CHECK(std::stod(rows[4][0]) == 0.8);
    for (std::size_t k = 1; k < rows.size(); ++k) CHECK(rows[k][9] == "true");
    r = run_hbf("analytic --law dahl --out /dev/null --plot '" + svg.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(slurp(svg), Catch::Contains("<svg") && Catch::Contains("y1_stick"));
    r = run_hbf("timeint --law coulomb --wmin 0.5 --wmax 0.6 --points 3 --out /dev/null --plot '" + ti.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(slurp(ti), Catch::Contains("<svg") && Catch::Contains("time integration"));
}

TEST_CASE("Plots: an unknown image type is bad input, a missing gnuplot a failure, never a partial file",
          "[cli][plot]") {
    TempDir dir;
    const fs::path csv = dir.path / "a.csv";
    for (const std::string command : {"frf", "analytic", "timeint --w 0.8"}) {
        const Result r = run_hbf(command + " --out '" + csv.string() + "' --plot '" + (dir.path / "a.jpg").string() + "'", dir);
        INFO(command << ": " << r.err);
        CHECK(r.exit_code == 2);
        CHECK_THAT(r.err, Catch::Contains("--plot") && Catch::Contains(".png or .svg"));
        CHECK(dir.empty());
    }
    // Without gnuplot on the PATH: exit 1 with the installation hint, nothing written.
    const Result r = run_hbf("frf --out '" + csv.string() + "' --plot '" + (dir.path / "a.png").string() + "'", dir,
                             "env PATH=/nonexistent");
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Catch::Contains("gnuplot") && Catch::Contains("apt-get install gnuplot-nox"));
    CHECK(dir.empty());
    const Result lonely = run_hbf("frf --overlay-timeint 5", dir);
    CHECK(lonely.exit_code == 2);
    CHECK_THAT(lonely.err, Catch::Contains("--overlay-timeint") && Catch::Contains("--plot"));
}

TEST_CASE("hbf loop writes one period of the solution: the stuck absorber's exact contact force", "[cli][loop]") {
    // Coulomb at w = 0.8, fe = 0.5 is in full stick: both masses move as one with
    // y = fe / (1 - (1 + r) w^2) cos(w t), q = v = 0, and the contact carries the absorber's
    // inertia force (derived by hand from r y2'' + r wa^2 (y2 - y1) = f with y2 = y1):
    // f = r y2'' = -r w^2 y. The time grid contains t = 0, where y1 is largest.
    TempDir dir;
    const fs::path csv = dir.path / "loop.csv", png = dir.path / "loop.png";
    const Result r = run_hbf("loop --w 0.8 --out '" + csv.string() + "' --plot '" + png.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(slurp(csv));
    const std::vector<std::string> header = {"t", "y1", "y2", "q", "v", "f", "stick", "f_series"};
    REQUIRE(rows[0] == header);
    REQUIRE(rows.size() == 513);  // N_t = 512 at H = 20, the default for coulomb
    const double w = 0.8, y = 0.5 / (1.0 - 1.1 * w * w);
    CHECK(std::stod(rows[1][0]) == 0.0);
    CHECK(std::stod(rows[1][1]) == Approx(y).epsilon(1e-8));
    CHECK(std::stod(rows[1][5]) == Approx(-0.1 * w * w * y).epsilon(1e-8));
    for (std::size_t k = 1; k < rows.size(); ++k) {
        CHECK(std::abs(std::stod(rows[k][4])) < 1e-8);  // v = 0: stuck
        CHECK(rows[k][6] == "1");
    }
    CHECK(std::stod(rows.back()[0]) == Approx(2.0 * M_PI / w * 511.0 / 512.0).epsilon(1e-12));
    CHECK(slurp(png).substr(1, 3) == "PNG");
    const Result missing = run_hbf("loop --out '" + csv.string() + "'", dir);
    CHECK(missing.exit_code == 2);
    CHECK_THAT(missing.err, Catch::Contains("--w"));
    // Above an unbounded resonance (fe = 1) the branch from wmin stops at the amplitude cap;
    // the solution at w is the one branch 2 starts from.
    const Result beyond = run_hbf("loop --fe 1 --w 1.3 --harmonics 10", dir);
    CHECK(beyond.exit_code == 0);
    CHECK(parse_csv(beyond.out).size() == 257);
    const Result contact = run_hbf("loop --w 0.8 --contact 2", dir);
    CHECK(contact.exit_code == 2);
    CHECK_THAT(contact.err, Catch::Contains("--contact") && Catch::Contains("1..1"));
}

TEST_CASE("hbf loop keeps the zero-mean convention far above the resonances", "[cli][loop]") {
    // Coulomb, fe = 0.5, both masses stuck together (the contact holds: its force r w^2 |Y|
    // tends to fe r / (1 + r) = 0.045 < mu): one mass 1 + r on the main spring, y1 = y2 =
    // fe / (1 - (1 + r) w^2) cos(w t), q = 0 and the force f = r y2'' = -r w^2 y1. In permanent
    // stick any offset of the stuck contact is periodic too; the convention (mean force zero)
    // makes every mean vanish. At w = 1e6 the response is 4.5e-13: an offset at the
    // corrector's tolerance (a force error ~1e-11 held by the absorber spring 0.1, i.e. ~1e-10)
    // was 60 times it. Tolerances: 1e-6 of the response (the closed form), the means below
    // 1e-6 of it.
    TempDir dir;
    for (const double w : {1e3, 1e6}) {
        const Result r = run_hbf(std::string("loop --w ") + (w == 1e3 ? "1e3" : "1e6"), dir);
        INFO("w = " << w << ": " << r.err);
        REQUIRE(r.exit_code == 0);
        const auto rows = parse_csv(r.out);
        REQUIRE(rows.size() > 2);
        const double y = 0.5 / (1.0 - 1.1 * w * w);
        double mean1 = 0.0, mean2 = 0.0, meanq = 0.0;
        for (std::size_t k = 1; k < rows.size(); ++k) {
            mean1 += std::stod(rows[k][1]);
            mean2 += std::stod(rows[k][2]);
            meanq += std::stod(rows[k][3]);
            CHECK(rows[k][6] == "1");
        }
        const double samples = static_cast<double>(rows.size() - 1);
        CHECK(std::abs(mean1 / samples) < 1e-6 * std::abs(y));
        CHECK(std::abs(mean2 / samples) < 1e-6 * std::abs(y));
        CHECK(std::abs(meanq / samples) < 1e-6 * std::abs(y));
        CHECK(std::stod(rows[1][1]) == Approx(y).epsilon(1e-6));  // t = 0: y1 largest
        CHECK(std::stod(rows[1][2]) == Approx(y).epsilon(1e-6));
        CHECK(std::stod(rows[1][5]) == Approx(-0.1 * w * w * y).epsilon(1e-6));
    }
}

TEST_CASE("hbf frf polishes coulomb by default: exact rows, stability, HB gap, and --exact off is plain HB", "[cli][exact]") {
    TempDir dir;
    const fs::path csv = dir.path / "frf.csv", json = dir.path / "frf.json";
    const Result r = run_hbf("frf --quiet --out '" + csv.string() + "' --summary '" + json.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = parse_csv(slurp(csv));
    REQUIRE(rows.size() > 10);
    REQUIRE(rows[0].size() == 19);
    CHECK(rows[0][13] == "exact");
    CHECK(rows[0][18] == "stability_margin");
    double largest_gap = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        CHECK(rows[k][13] == "yes");
        CHECK(rows[k][14] == "true");
        CHECK(std::stod(rows[k][18]) <= 1.0 + 1e-6);  // the exact orbit's largest |multiplier|
        CHECK(rows[k][16].empty());  // no estimate where the error is measured (hb_gap)
        largest_gap = std::max(largest_gap, std::stod(rows[k][15]));
    }
    // HB at H = 10 is visibly off at some points (the 1/H error of exact Coulomb), a few percent.
    CHECK(largest_gap > 1e-3);
    CHECK(largest_gap < 0.1);
    const std::string summary = slurp(json);
    CHECK_THAT(summary, Catch::Contains("\"exact\"") && Catch::Contains("\"failed\": 0") &&
                            Catch::Contains("\"harmonics\": 10"));

    const Result off = run_hbf("frf --quiet --exact off --summary '" + json.string() + "'", dir);
    // Plain HB (H = 20) estimates its own error: exit 3 exactly when the estimate passes 1e-2.
    const double estimate = nlohmann::json::parse(slurp(json))["hb_error"]["largest"].get<double>();
    CHECK(estimate > 1e-3);
    CHECK(estimate < 0.1);
    REQUIRE(off.exit_code == (estimate > 1e-2 ? 3 : 0));
    const auto plain = parse_csv(off.out);
    for (std::size_t k = 1; k < plain.size(); ++k) CHECK(plain[k][13] == "off");
    CHECK_THAT(slurp(json), Catch::Contains("\"harmonics\": 20") && Catch::Contains("\"enabled\": false"));
}

TEST_CASE("hbf frf --at: a frequency within rounding of wmin is sampled, one outside the branch is an error", "[cli]") {
    // 3e-13 below wmin = 0.5 is the start of the branch (it used to be dropped silently); 2.0 is
    // beyond wmax = 1.6: no row, named on standard error, exit 1, the other rows written.
    TempDir dir;
    const Result r = run_hbf("frf --quiet --exact off --at 0.4999999999997,0.7,2.0", dir);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Catch::Contains("--at w = 2") && Catch::Contains("no solution written"));
    int samples = 0;
    for (const auto& row : parse_csv(r.out))
        if (row.size() > 9 && row[9] == "sample") ++samples;
    CHECK(samples == 2);
}

TEST_CASE("hbf frf with wmax = wmin: one point from a cold start, the branch's solution at that w", "[cli]") {
    // The paper's absorber (dahl, H = 5): the point at w = 0.8 alone, from the start-point search,
    // against the --at sample of the whole branch at 0.8 (the response is unique there); and the
    // system file liftoff3_rigid.toml with [frequency] wmin = wmax. A band below zero width is refused.
    TempDir dir;
    const fs::path one = dir.path / "one.csv", json = dir.path / "one.json", band = dir.path / "band.csv";
    const Result r = run_hbf("frf --law dahl --harmonics 5 --wmin 0.8 --wmax 0.8 --quiet --out '" + one.string() +
                                 "' --summary '" + json.string() + "'",
                             dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const Result whole = run_hbf("frf --law dahl --harmonics 5 --at 0.8 --quiet --out '" + band.string() + "'", dir);
    REQUIRE(whole.exit_code == 0);
    const auto rows = parse_csv(slurp(one));
    REQUIRE(rows.size() == 2);
    CHECK(std::stod(rows[1][0]) == 0.8);
    CHECK(rows[1][9] == "regular");
    std::vector<std::string> sample;
    for (const auto& row : parse_csv(slurp(band)))
        if (row.size() > 9 && row[9] == "sample") sample = row;
    REQUIRE(!sample.empty());
    for (int column : {1, 2, 3, 4, 7}) {  // y1_max, y2_max, y1_amp1, y2_amp1, energy
        INFO("column " << rows[0][static_cast<std::size_t>(column)]);
        CHECK(std::stod(rows[1][static_cast<std::size_t>(column)]) ==
              Approx(std::stod(sample[static_cast<std::size_t>(column)])).epsilon(1e-8));
    }
    const nlohmann::json summary = nlohmann::json::parse(slurp(json));
    CHECK(summary.at("status") == "completed");
    CHECK_THAT(summary.at("message").get<std::string>(), Catch::Contains("one point") && Catch::Contains("cold start"));
    // a system file whose band is one frequency
    const fs::path file = dir.path / "one.toml";
    std::string text = slurp(fs::path(HBF_SOURCE_DIR) / "examples/systems/liftoff3_rigid.toml");
    const std::string::size_type at = text.find("wmin = 0.3\nwmax = 3.0");
    REQUIRE(at != std::string::npos);
    text.replace(at, std::string("wmin = 0.3\nwmax = 3.0").size(), "wmin = 1.1\nwmax = 1.1");
    write_file(file, text);
    const Result config = run_hbf("frf --config '" + file.string() + "' --quiet --dry-run", dir);
    INFO(config.err);
    CHECK(config.exit_code == 0);
    const Result below = run_hbf("frf --law dahl --wmin 0.8 --wmax 0.7", dir);
    CHECK(below.exit_code == 2);
    CHECK_THAT(below.err, Catch::Contains("wmax") && Catch::Contains("wmax = wmin: one point"));
}

TEST_CASE("hbf frf --start-harmonics: the start at H from the H0 solution is the cold start's point, and H0 out "
          "of range is refused before any output",
          "[cli]") {
    // liftoff3_rigid.toml (law unilateral) at w = 1.1, H = 10: one point from the usual cold start
    // (the linear guesses at H = 10) and one from the H = 3 solution padded with zero harmonics:
    // the same harmonic-balance solution (unique there), every column to 1e-8.
    TempDir dir;
    const std::string config = "frf --config '" + (fs::path(HBF_SOURCE_DIR) / "examples/systems/liftoff3_rigid.toml").string() +
                               "' --wmin 1.1 --wmax 1.1 --harmonics 10 --exact off --error-points 0 --quiet";
    const fs::path cold = dir.path / "cold.csv", low = dir.path / "low.csv", json = dir.path / "low.json";
    const Result a = run_hbf(config + " --out '" + cold.string() + "'", dir);
    INFO(a.err);
    REQUIRE(a.exit_code == 0);
    const Result b = run_hbf(config + " --start-harmonics 3 --out '" + low.string() + "' --summary '" + json.string() + "'", dir);
    INFO(b.err);
    REQUIRE(b.exit_code == 0);
    const auto ra = parse_csv(slurp(cold)), rb = parse_csv(slurp(low));
    REQUIRE(ra.size() == 2);
    REQUIRE(rb.size() == 2);
    REQUIRE(ra[0] == rb[0]);
    int compared = 0;
    for (std::size_t k = 0; k < ra[1].size(); ++k) {
        char* end = nullptr;
        const double x = std::strtod(ra[1][k].c_str(), &end);
        if (end == ra[1][k].c_str() || *end != '\0') continue;  // words: regimes, kinds
        const std::string& name = ra[0][k];
        if (name == "iterations" || name == "residual" || name == "energy_error") continue;  // Newton's own path
        INFO(name);
        CHECK(std::stod(rb[1][k]) == Approx(x).epsilon(1e-8).margin(1e-12));
        ++compared;
    }
    CHECK(compared >= 10);
    const nlohmann::json summary = nlohmann::json::parse(slurp(json));
    CHECK(summary.at("status") == "completed");
    CHECK_THAT(summary.at("message").get<std::string>(), Catch::Contains("from a cold start at H = 3, padded to H = 10"));
    for (const char* h0 : {"10", "12", "-1"}) {
        const fs::path out = dir.path / (std::string("bad") + h0 + ".csv");
        const Result bad = run_hbf(config + " --start-harmonics " + h0 + " --out '" + out.string() + "'", dir);
        INFO("--start-harmonics " << h0 << ": " << bad.err);
        CHECK(bad.exit_code == 2);
        CHECK_THAT(bad.err, Catch::Contains("--start-harmonics") && Catch::Contains("allowed 0..H - 1"));
        CHECK(!fs::exists(out));
    }
}

TEST_CASE("Progress: a redrawn line on a terminal, one kept line per interval into a log, nothing when off",
          "[cli]") {
    // hbf frf on a 10,000-DOF beam runs for 20 minutes: into a log file (standard error not a
    // terminal) it writes one progress line a minute, none within the first minute, so that
    // short runs stay silent. Here the interval is zero or an hour, and the sink a temporary file.
    auto run = [](hbf::cli::ProgressLine::Mode mode, std::chrono::steady_clock::duration interval) {
        std::FILE* sink = std::tmpfile();
        REQUIRE(sink != nullptr);
        {
            hbf::cli::ProgressLine line(mode, "frf", sink, interval);
            for (int k = 0; k < 3; ++k) line.update("w = " + std::to_string(k));
            line.update("w = 3", true);
        }
        std::rewind(sink);
        std::string text;
        for (int c = std::fgetc(sink); c != EOF; c = std::fgetc(sink)) text += static_cast<char>(c);
        std::fclose(sink);
        return text;
    };
    using Mode = hbf::cli::ProgressLine::Mode;
    const std::string every = run(Mode::log, std::chrono::steady_clock::duration::zero());
    CHECK(std::count(every.begin(), every.end(), '\n') == 4);
    CHECK(every.rfind("hbf frf: w = 0 ", 0) == 0);
    CHECK(every.find('\r') == std::string::npos);
    CHECK(run(Mode::log, std::chrono::hours(1)).empty());
    CHECK(run(Mode::off, std::chrono::steady_clock::duration::zero()).empty());
    const std::string terminal = run(Mode::terminal, std::chrono::hours(1));
    CHECK(terminal.rfind("\rhbf frf: w = 0 ", 0) == 0);  // the first update, then the forced last
    CHECK(terminal.find("w = 3") != std::string::npos);
    CHECK(terminal.size() >= 4);
    CHECK(terminal.compare(terminal.size() - 4, 4, "\r\033[K") == 0);  // erased when done
    CHECK(terminal.find('\n') == std::string::npos);
}
