// Harmonic balance's estimated truncation error (FrfSettings::error_points, the column
// hb_error) against the error measured exactly: the same branch points polished by the
// event-exact solver (hb_gap), and the CLI's warning, flags and refusals.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "hbf/absorber.hpp"
#include "hbf/frf.hpp"

namespace {
using namespace hbf;

System absorber_half() {
    AbsorberParameters p;
    p.excitation = 1.0;
    p.friction_coefficient = 0.5;
    return friction_absorber(p, FrictionLaw::coulomb);
}

FrfResult absorber_frf(int harmonics, bool exact, int error_points = FrfSettings{}.error_points) {
    const System s = absorber_half();
    FrfChoices c;
    c.harmonics = harmonics;
    c.exact = exact;
    FrfSettings settings = frf_settings(s, {}, c);
    settings.error_points = error_points;
    return compute_frf(s, settings);
}
}  // namespace

TEST_CASE("HB error estimate: on exact Coulomb (the absorber, H = 3..20) the largest estimate is within a factor 2 "
          "of the largest error the exact solver measures at the same points (both relative to the FRF's largest "
          "value), zero where both are",
          "[hb_error]") {
    for (const int h : {3, 5, 10, 20}) {
        const FrfResult estimated = absorber_frf(h, false);
        const FrfResult exact = absorber_frf(h, true);
        INFO("H = " << h << ": " << estimated.summary());
        REQUIRE(exact.polish.has_value());
        CHECK(estimated.error_harmonics == 2 * h);
        double largest_estimate = 0.0, largest_true = 0.0, scale = 0.0;
        for (const PointMetrics& m : estimated.metrics) scale = std::max(scale, m.output_max[0]);
        int compared = 0;
        for (std::size_t k = 0; k < estimated.points.size(); ++k) {
            const double e = estimated.metrics[k].hb_error;
            if (!std::isfinite(e)) continue;
            // The same branch point polished (the continuation is the same at the same H).
            const auto same = std::find_if(exact.points.begin(), exact.points.end(), [&](const SolutionPoint& q) {
                return std::abs(q.omega - estimated.points[k].omega) <= 1e-12 * q.omega;
            });
            if (same == exact.points.end()) continue;
            const std::size_t j = static_cast<std::size_t>(same - exact.points.begin());
            const ExactPoint& x = exact.exact[j];
            if (x.status != PolishStatus::exact || !std::isfinite(x.hb_gap)) continue;
            // hb_gap is relative to the exact value at the point; the estimate to the FRF's scale.
            const double error = x.hb_gap * exact.metrics[j].output_max[0] / scale;
            INFO("w = " << estimated.points[k].omega << ": estimate " << e << ", exact error " << error);
            if (error <= 1e-12) CHECK(e <= 1e-9);  // permanent stick: HB is exact, and says so
            largest_estimate = std::max(largest_estimate, e);
            largest_true = std::max(largest_true, error);
            ++compared;
        }
        INFO("largest estimate " << largest_estimate << ", largest exact error " << largest_true << " at " << compared
                                 << " points");
        CHECK(compared >= 10);
        CHECK(largest_true > 1e-3);
        CHECK(largest_estimate >= 0.5 * largest_true);
        CHECK(largest_estimate <= 2.0 * largest_true);
        // The verdict: a warning above the default limit (1e-2), a note below.
        CHECK((largest_estimate > 1e-2) == (estimated.status() == "incomplete"));
        CHECK(estimated.hb_error == largest_estimate);
        // A polished FRF is not estimated (its hb_gap is the measured error).
        for (const PointMetrics& m : exact.metrics) CHECK_FALSE(std::isfinite(m.hb_error));
    }
    // error_points = 0: no estimate, no column value, the status of the FRF alone.
    const FrfResult none = absorber_frf(5, false, 0);
    CHECK(none.error_harmonics == 0);
    for (const PointMetrics& m : none.metrics) CHECK_FALSE(std::isfinite(m.hb_error));
    CHECK(none.status() == "completed");
}

TEST_CASE("hbf frf: the estimate's warning is exit 3 and names the limit, --error-limit and --error-points set it, "
          "bad values are exit 2",
          "[hb_error][cli]") {
    using test::TempDir;
    TempDir dir;
    const std::string base = "frf --fe 1 --mu 0.5 --exact off --harmonics 5";
    const test::Result warned = test::run_hbf(base + " --out '" + (dir.path / "a.csv").string() + "'", dir);
    INFO(warned.err);
    CHECK(warned.exit_code == 3);
    CHECK_THAT(warned.err, Catch::Contains("harmonic balance's estimated error is"));
    CHECK_THAT(warned.err, Catch::Contains("above the error limit 0.01"));
    const auto rows = test::parse_csv(test::slurp(dir.path / "a.csv"));
    const auto& header = rows.front();
    const auto column = static_cast<std::size_t>(std::find(header.begin(), header.end(), "hb_error") - header.begin());
    REQUIRE(column < header.size());
    int filled = 0;
    double largest = 0.0;
    for (std::size_t k = 1; k < rows.size(); ++k)
        if (column < rows[k].size() && !rows[k][column].empty()) {
            ++filled;
            largest = std::max(largest, std::stod(rows[k][column]));
        }
    CHECK(filled >= 10);
    CHECK(largest > 1e-2);
    const test::Result lenient =
        test::run_hbf(base + " --error-limit 0.5 --out '" + (dir.path / "b.csv").string() + "'", dir);
    CHECK(lenient.exit_code == 0);
    CHECK_THAT(lenient.err, !Catch::Contains("above the error limit"));
    const test::Result off = test::run_hbf(base + " --error-points 0 --out '" + (dir.path / "c.csv").string() + "'", dir);
    CHECK(off.exit_code == 0);
    test::check_bad_input(base + " --error-points -1", {"error-points", "0..1000"}, dir);
    test::check_bad_input(base + " --error-limit 0", {"error-limit", "> 0"}, dir);
}

TEST_CASE("HB error estimate: the saw-tooth maxima of a rigid contact at H = 3 (liftoff3_rigid) are marked within "
          "the estimated error, and those left unmarked are the exact FRF's peaks",
          "[hb_error][cli]") {
    using test::TempDir;
    TempDir dir;
    const std::string file = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";
    const auto peaks_of_y1 = [&](const std::string& flags) {
        const auto json = dir.path / "s.json";
        const test::Result r =
            test::run_hbf("frf --config '" + file + "' " + flags + " --out /dev/null --summary '" + json.string() + "'", dir);
        INFO(flags << ": " << r.err);
        CHECK((r.exit_code == 0 || r.exit_code == 3));
        std::vector<std::pair<double, bool>> out;  // (w, within_hb_error)
        const nlohmann::json summary = nlohmann::json::parse(test::slurp(json));  // kept: the loop refers into it
        for (const auto& p : summary.at("peaks"))
            if (p.at("output").get<std::string>() == "y1") out.emplace_back(p.at("w").get<double>(), p.value("within_hb_error", false));
        return out;
    };
    const auto exact = peaks_of_y1("");  // 2D rigid contact: polished by the exact solver by default
    const auto coarse = peaks_of_y1("--exact off --harmonics 3");
    REQUIRE(exact.size() >= 3);
    REQUIRE(coarse.size() >= 3);
    int within = 0, kept = 0;
    for (const auto& [w, flagged] : coarse) {
        INFO("H = 3 peak at w = " << w << (flagged ? " (within the error)" : ""));
        if (flagged) {
            ++within;
            CHECK((w > 2.39 && w < 2.45));  // the saw-tooth at the top of the resonance
            continue;
        }
        ++kept;
        // An unmarked peak is one of the exact FRF's, within H = 3's shift of it (2 % in w).
        double nearest = 1e300;
        for (const auto& e : exact) nearest = std::min(nearest, std::abs(e.first - w) / e.first);
        CHECK(nearest < 0.02);
    }
    CHECK(within >= 6);
    CHECK(kept >= 2);
    for (const auto& e : exact) CHECK_FALSE(e.second);  // the polished FRF has no estimate
}

TEST_CASE("hbf map: FRFs whose estimated error passes the limit make the map doubtful (exit 3), each FRF's estimate "
          "in the JSON",
          "[hb_error][cli][map]") {
    using test::TempDir;
    TempDir dir;
    const auto json = dir.path / "m.json";
    const std::string base = "map --fe 1 --exact off --harmonics 5 --param mu --values 0.45:0.55:3 --quiet --out '" +
                             (dir.path / "m.csv").string() + "' --summary '" + json.string() + "'";
    const test::Result r = test::run_hbf(base, dir);
    INFO(r.err);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("3 of 3 FRFs have an estimated harmonic-balance error above the error limit 0.01"));
    const nlohmann::json summary = nlohmann::json::parse(test::slurp(json));
    REQUIRE(summary.at("frfs").size() == 3);
    for (const auto& f : summary.at("frfs")) {
        // H = 5 of exact Coulomb: a few per cent (the FRF test above measures it against the exact solver)
        CHECK(f.at("hb_error").get<double>() > 1e-2);
        CHECK(f.at("hb_error").get<double>() < 0.1);
    }
    const test::Result lenient = test::run_hbf(base + " --error-limit 0.5", dir);
    CHECK(lenient.exit_code == 0);
}
