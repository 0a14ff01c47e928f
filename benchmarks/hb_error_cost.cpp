// Benchmark: the cost of harmonic balance's truncation-error estimate (FrfSettings::
// error_points): the same FRF of the paper's absorber computed with the estimate (the default,
// 12 maxima and 12 spread points solved again at 2H) and without it, in this process, for
// several laws and H. Prints, per case, both times (the best of --repeat runs each), their
// ratio and the largest estimate; the last line is one JSON object. Run by hand:
// `build/benchmarks/hb_error_cost [--repeat 3]`.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/frf.hpp"

using namespace hbf;

namespace {
/// The best wall time of `repeat` FRFs with `points` estimate points, and the last result.
double best_seconds(const System& s, FrfSettings settings, int points, int repeat, FrfResult& last) {
    settings.error_points = points;
    double best = 1e300;
    for (int k = 0; k < repeat; ++k) {
        const auto start = std::chrono::steady_clock::now();
        last = compute_frf(s, settings);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app("cost of harmonic balance's error estimate");
    int repeat = 3;
    app.add_option("--repeat", repeat, "runs per variant (the best counts)")->check(CLI::Range(1, 100));
    CLI11_PARSE(app, argc, argv);
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%-12s %4s %12s %12s %8s %12s\n", "law", "H", "without [s]", "with [s]", "ratio", "estimate");
    for (const auto& [law, harmonics] : std::vector<std::pair<FrictionLaw, int>>{
             {FrictionLaw::coulomb, 10}, {FrictionLaw::coulomb, 20}, {FrictionLaw::coulomb, 40},
             {FrictionLaw::jenkins, 10}, {FrictionLaw::dahl, 10}, {FrictionLaw::lugre, 10}}) {
        AbsorberParameters p;
        p.excitation = 1.0;
        p.friction_coefficient = 0.5;
        const System s = friction_absorber(p, law);
        FrfChoices c;
        c.harmonics = harmonics;
        c.exact = false;
        const FrfSettings settings = frf_settings(s, {}, c);
        FrfResult plain, estimated;
        const double without = best_seconds(s, settings, 0, repeat, plain);
        const double with = best_seconds(s, settings, FrfSettings{}.error_points, repeat, estimated);
        const std::string name = to_string(law);
        std::printf("%-12s %4d %12.4f %12.4f %8.2f %12.3e\n", name.c_str(), harmonics, without, with, with / without,
                    estimated.hb_error);
        rows.push_back({{"law", name}, {"harmonics", harmonics}, {"without_seconds", without}, {"with_seconds", with},
                        {"ratio", with / without}, {"hb_error", estimated.hb_error}});
    }
    std::printf("%s\n", nlohmann::json{{"benchmark", "hb_error_cost"}, {"rows", rows}}.dump().c_str());
    return 0;
}
