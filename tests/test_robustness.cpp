// Robustness (issue 13): randomised parameter sets of the paper's absorber, every law, run
// through the hbf command as a user would. Seeded (reproducible); each run is time-bounded.
// Asserted for every run: no NaN or infinity in any output field, an exit code that matches
// the JSON's outcome and status (0: completed and spanning [wmin, wmax]; 3: incomplete, with
// warnings; 1: failed, with errors), and no file but the documented outputs.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "cli_support.hpp"

namespace {

struct Run {
    std::string args;
    ::test::Result result;
    std::string csv, json;
    std::set<std::string> files;  ///< what the directory holds afterwards
};

/// Runs the commands two at a time (the machine's cores); Catch's assertions are made by the
/// caller, in this thread.
std::vector<Run> run_all(const std::vector<std::string>& commands, const std::string& outputs) {
    auto one = [&outputs](const std::string& args) {
        ::test::TempDir dir;
        Run run;
        run.args = args;
        // timeout: a hang is a failure (exit 124), never a stuck test suite.
        run.result = ::test::run_hbf(args + outputs, dir, "cd '" + dir.path.string() + "' && timeout 120");
        run.csv = ::test::slurp(dir.path / "out.csv");
        run.json = ::test::slurp(dir.path / "out.json");
        for (const auto& entry : ::test::fs::directory_iterator(dir.path)) run.files.insert(entry.path().filename());
        return run;
    };
    std::vector<Run> runs;
    for (std::size_t k = 0; k < commands.size(); k += 2) {
        auto first = std::async(std::launch::async, one, commands[k]);
        if (k + 1 < commands.size()) {
            Run second = one(commands[k + 1]);
            runs.push_back(first.get());
            runs.push_back(std::move(second));
        } else {
            runs.push_back(first.get());
        }
    }
    return runs;
}

/// Every field of every data row is a finite number or a known word.
bool finite_fields(const std::string& csv, std::string& bad) {
    const auto rows = ::test::parse_csv(csv);
    for (std::size_t k = 1; k < rows.size(); ++k)
        for (const std::string& field : rows[k]) {
            if (field.empty()) continue;
            char* end = nullptr;
            const double value = std::strtod(field.c_str(), &end);
            if (*end != '\0') {  // a word: regime, point kind, exact, stable
                if (field.find("nan") != std::string::npos || field.find("inf") != std::string::npos) {
                    bad = field;
                    return false;
                }
                continue;
            }
            if (!std::isfinite(value)) {
                bad = field;
                return false;
            }
        }
    return true;
}

/// Seeded random draws of the absorber's parameters.
struct Draw {
    std::mt19937 random;
    explicit Draw(unsigned seed) : random(seed) {}
    double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(random); }
    double log_uniform(double low, double high) { return std::exp(uniform(std::log(low), std::log(high))); }
    int integer(int low, int high) { return std::uniform_int_distribution<int>(low, high)(random); }
};

const std::vector<std::string> laws = {"coulomb", "jenkins", "dahl", "lugre", "coulomb-reg"};

}  // namespace

TEST_CASE("Robustness: 240 random absorbers, every law: finite outputs, honest exit codes, no stray files",
          "[robustness][cli]") {
    Draw d(20261124);
    std::vector<std::string> commands;
    for (int k = 0; k < 240; ++k) {
        const std::string& law = laws[static_cast<std::size_t>(k) % laws.size()];
        const double wmin = d.uniform(0.3, 1.0);
        std::ostringstream args;
        args.precision(6);
        args << "frf --quiet --law " << law << " --r " << d.log_uniform(0.01, 1.0) << " --wa " << d.uniform(0.5, 2.0)
             << " --mu " << d.log_uniform(0.01, 2.0) << " --fe " << d.log_uniform(0.01, 2.0) << " --wmin " << wmin
             << " --wmax " << wmin * d.uniform(1.2, 2.5) << " --harmonics " << d.integer(3, 8);
        if (law == "jenkins" || law == "dahl" || law == "lugre") args << " --wb " << d.log_uniform(0.1, 3.0);
        if (law == "lugre") args << " --xi " << d.uniform(0.0, 0.1);
        if (law == "coulomb-reg") args << " --eps " << d.log_uniform(0.01, 0.5);
        if (law == "coulomb" && k % 2 == 1) args << " --exact off";
        commands.push_back(args.str());
    }
    const std::vector<Run> runs = run_all(commands, " --out out.csv --summary out.json");
    std::map<int, int> codes;
    for (const Run& run : runs) {
        INFO(run.args << "\n" << run.result.err);
        const int code = run.result.exit_code;
        ++codes[code];
        REQUIRE((code == 0 || code == 1 || code == 3));
        std::string bad;
        const bool finite = finite_fields(run.csv, bad);
        INFO("bad field: " << bad);
        CHECK(finite);
        CHECK(run.files == std::set<std::string>{"out.csv", "out.json"});
        const nlohmann::json s = nlohmann::json::parse(run.json);
        const std::string outcome = s.at("outcome");
        if (code == 0) {
            CHECK(outcome == "completed");
            CHECK(s.at("status") == "completed");
            CHECK(s.at("coverage").get<double>() >= 1.0 - 1e-12);
            CHECK(s.at("warnings").empty());
            CHECK(s.at("max_energy_error").get<double>() <= 1e-6);
        } else if (code == 3) {
            CHECK(outcome == "incomplete");
            CHECK(!s.at("warnings").empty());
            CHECK(s.at("errors").empty());
        } else {
            CHECK(outcome == "failed");
            CHECK(!s.at("errors").empty());
        }
        // Whatever the outcome, stderr says it: one line per warning and error.
        if (code != 0) CHECK_THAT(run.result.err, Catch::Contains(code == 1 ? "error:" : "warning:"));
    }
    // The random set is not all failures: most runs complete.
    CHECK(codes[0] > static_cast<int>(runs.size()) / 2);
}

TEST_CASE("Robustness: 60 random steady states by time integration, every law: finite rows, converged matches the exit code",
          "[robustness][cli]") {
    Draw d(1124);
    std::vector<std::string> commands;
    for (int k = 0; k < 60; ++k) {
        const std::string& law = laws[static_cast<std::size_t>(k) % laws.size()];
        std::ostringstream args;
        args.precision(6);
        args << "timeint --quiet --law " << law << " --r " << d.log_uniform(0.01, 1.0) << " --mu "
             << d.log_uniform(0.05, 2.0) << " --fe " << d.log_uniform(0.05, 2.0) << " --w " << d.uniform(0.4, 1.6)
             << " --max-periods 300";
        if (law == "jenkins" || law == "dahl" || law == "lugre") args << " --wb " << d.log_uniform(0.1, 3.0);
        if (law == "coulomb-reg") args << " --eps " << d.log_uniform(0.02, 0.5);
        if ((law == "coulomb" || law == "jenkins") && k % 2 == 1) args << " --method exact";
        commands.push_back(args.str());
    }
    const std::vector<Run> runs = run_all(commands, " --out out.csv");
    int converged_runs = 0;
    for (const Run& run : runs) {
        INFO(run.args << "\n" << run.result.err);
        const int code = run.result.exit_code;
        REQUIRE((code == 0 || code == 1 || code == 3));
        std::string bad;
        const bool finite = finite_fields(run.csv, bad);
        INFO("bad field: " << bad);
        CHECK(finite);
        CHECK(run.files == std::set<std::string>{"out.csv"});
        const auto rows = ::test::parse_csv(run.csv);
        REQUIRE(rows.size() == 2);
        const auto where = std::find(rows[0].begin(), rows[0].end(), "converged") - rows[0].begin();
        REQUIRE(static_cast<std::size_t>(where) < rows[1].size());
        const bool converged = rows[1][static_cast<std::size_t>(where)] == "true";
        CHECK(converged == (code != 1));
        if (converged) ++converged_runs;
    }
    CHECK(converged_runs > 45);
}
