// Peaks and stick-slip boundaries followed through a second parameter (tracking.hpp, hbf track),
// against independent references: the refined peaks of FRFs computed one by one (what hbf map
// does), the paper's closed-form limit friction coefficient, FRFs just before and after the
// events the tracking reports.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "cli_support.hpp"
#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/tracking.hpp"

namespace {
using namespace hbf;

AbsorberParameters absorber_fe1(double mu) {
    AbsorberParameters p;
    p.excitation = 1.0;
    p.friction_coefficient = mu;
    return p;
}
System coulomb_absorber(double mu) { return friction_absorber(absorber_fe1(mu), FrictionLaw::coulomb); }

/// The refined peaks of y1 on the FRF of `system` (compute_frf, as hbf frf and hbf map).
std::vector<Peak> frf_peaks(const System& system) {
    const FrfResult r = compute_frf(system, default_frf_settings(system, {}));
    std::vector<Peak> out;
    for (const Peak& k : r.peaks)
        if (k.output == 0 && k.refined) out.push_back(k);
    return out;
}
}  // namespace

TEST_CASE("track: the absorber's exact Coulomb peaks over mu equal the refined peaks of 40 FRFs, the equal-peak "
          "point and the end of a peak agree with FRFs around them",
          "[tracking]") {
    // fe = 1, mu from 0.3 to 1 (below about 0.29 the resonance is unbounded): the case.
    const FrfSettings settings = default_frf_settings(coulomb_absorber(0.3), {});
    REQUIRE(settings.exact);
    TrackOptions o;
    o.p_start = 0.3;
    o.p_end = 1.0;
    std::vector<double> values;
    for (int k = 0; k < 40; ++k) values.push_back(0.3 + 0.7 * k / 39.0);
    values.back() = 1.0;
    o.at = values;
    const TrackResult r = track(coulomb_absorber, settings, o);
    INFO(r.summary());
    CHECK(r.exact);
    CHECK(r.status() == "completed");
    REQUIRE(r.curves.size() == 2);

    // The largest peak at each value against the FRFs' (hbf map's) largest refined peak.
    const std::vector<FrfResult> frfs = compute_frfs(
        static_cast<int>(values.size()), [&](int k) { return coulomb_absorber(values[static_cast<std::size_t>(k)]); },
        settings, 2);
    double dw = 0.0, dy = 0.0;
    int compared = 0;
    for (std::size_t k = 0; k < values.size(); ++k) {
        REQUIRE(frfs[k].peak.state == PeakState::bounded);
        // The tracked value at values[k]: the start (k = 0) or the "at" point, largest of the curves.
        double w = 0.0, y = -1.0;
        for (const TrackCurve& c : r.curves)
            for (const TrackPoint& q : c.points)
                if (std::abs(q.p - values[k]) <= 1e-12 && (q.kind == "at" || q.kind == "start") && q.value > y) {
                    y = q.value;
                    w = q.omega;
                }
        REQUIRE(y > 0.0);
        dw = std::max(dw, std::abs(w - frfs[k].peak.omega) / w);
        dy = std::max(dy, std::abs(y - frfs[k].peak.value) / y);
        ++compared;
    }
    CHECK(compared == 40);
    CHECK(dw < 1e-8);
    CHECK(dy < 1e-8);

    // One exchange (the equal-peak design): the FRF there has two refined peaks of that value.
    const auto exchange = std::find_if(r.events.begin(), r.events.end(), [](const TrackEvent& e) { return e.kind == "exchange"; });
    REQUIRE(exchange != r.events.end());
    const std::vector<Peak> at_exchange = frf_peaks(coulomb_absorber(exchange->p));
    REQUIRE(at_exchange.size() == 2);
    CHECK(std::abs(at_exchange[0].y_max - exchange->value) < 1e-8 * exchange->value);
    CHECK(std::abs(at_exchange[1].y_max - exchange->value) < 1e-8 * exchange->value);
    CHECK(std::abs(at_exchange[0].omega - exchange->omega) < 1e-8);
    CHECK(std::abs(at_exchange[1].omega - exchange->other_omega) < 1e-8);

    // The upper peak ends inside the range (near mu = 0.544, after it turned into the corner of
    // a stick/slip transition, which the FRFs' branch points may straddle): two peaks on the
    // FRF 0.01 before, one 0.01 after.
    const TrackCurve& upper = r.curves[1];
    CHECK(upper.status == TrackStatus::vanished);
    const double end = upper.points.back().p;
    CHECK(end > 0.5);
    CHECK(end < 0.6);
    CHECK(frf_peaks(coulomb_absorber(end - 1e-2)).size() == 2);
    CHECK(frf_peaks(coulomb_absorber(end + 1e-2)).size() == 1);
    CHECK(r.curves[0].status == TrackStatus::completed);
}

TEST_CASE("track: long ranges in mu (0.3:2, 0.3:5, 0.3:10) keep both peak curves: the largest tracked peak equals "
          "the FRFs' at 20 values and the equal-peak exchange is found each time",
          "[tracking]") {
    // Regression: with a longer range the first step was longer, predicted the start's own w and
    // took the neighbouring peak (the two move in w faster than they are apart near mu = 0.3).
    const FrfSettings settings = default_frf_settings(coulomb_absorber(0.3), {});
    std::vector<double> values;
    for (int k = 1; k <= 20; ++k) values.push_back(0.3 + 1.7 * k / 20.0);  // 0.385 .. 2
    const std::vector<FrfResult> frfs = compute_frfs(
        static_cast<int>(values.size()), [&](int k) { return coulomb_absorber(values[static_cast<std::size_t>(k)]); },
        settings, 2);
    for (const double end : {2.0, 5.0, 10.0}) {
        TrackOptions o;
        o.p_start = 0.3;
        o.p_end = end;
        o.at = values;
        const TrackResult r = track(coulomb_absorber, settings, o);
        INFO("range 0.3:" << end << ": " << r.summary());
        REQUIRE(r.curves.size() == 2);
        CHECK(r.curves[0].status == TrackStatus::completed);
        double dw = 0.0, dy = 0.0;
        std::string worst;
        for (std::size_t k = 0; k < values.size(); ++k) {
            INFO("mu = " << values[k] << ", FRF: " << frfs[k].summary());
            REQUIRE(frfs[k].peak.state == PeakState::bounded);
            double w = 0.0, y = -1.0;
            for (const TrackCurve& c : r.curves)
                for (const TrackPoint& q : c.points)
                    if (std::abs(q.p - values[k]) <= 1e-12 && q.kind != "search" && q.kind != "exchange" && q.value > y) {
                        y = q.value;
                        w = q.omega;
                    }
            REQUIRE(y > 0.0);
            if (std::abs(w - frfs[k].peak.omega) / w > dw)
                worst = "mu = " + std::to_string(values[k]) + ": tracked w = " + std::to_string(w) + ", FRF: " +
                        frfs[k].summary();
            dw = std::max(dw, std::abs(w - frfs[k].peak.omega) / w);
            dy = std::max(dy, std::abs(y - frfs[k].peak.value) / y);
        }
        INFO("worst in w: " << worst);
        CHECK(dw < 1e-8);
        CHECK(dy < 1e-8);
        const auto exchanges = std::count_if(r.events.begin(), r.events.end(), [](const TrackEvent& e) { return e.kind == "exchange"; });
        CHECK(exchanges == 1);
        for (const TrackEvent& e : r.events)
            if (e.kind == "exchange") CHECK(std::abs(e.p - 0.4721231377) < 1e-8);
    }
}

TEST_CASE("track: the exact Coulomb stick boundaries follow the paper's limit friction coefficient to 1e-10",
          "[tracking]") {
    // Full stick holds iff mu >= mu_limit(w) = fe r w^2 / |1 - (1 + r) w^2| (analytic.hpp, paper
    // eqs. 14-15 as derived): the stick|stick-slip boundaries are mu = mu_limit(w), on both sides
    // of the stuck resonance 1 / sqrt(1 + r).
    const FrfSettings settings = default_frf_settings(coulomb_absorber(0.3), {});
    TrackOptions o;
    o.feature = TrackFeature::boundary;
    o.p_start = 0.3;
    o.p_end = 2.0;
    const TrackResult r = track(coulomb_absorber, settings, o);
    INFO(r.summary());
    int stick_curves = 0, points = 0;
    double worst = 0.0;
    const double w_stuck = 1.0 / std::sqrt(1.1);
    bool below = false, above = false;
    for (const TrackCurve& c : r.curves) {
        if (c.boundary != Boundary::stick_stick_slip) continue;
        ++stick_curves;
        CHECK(c.status == TrackStatus::completed);
        for (const TrackPoint& q : c.points) {
            const double limit = analytic::coulomb_limit_friction(absorber_fe1(q.p), q.omega);
            worst = std::max(worst, std::abs(limit - q.p) / q.p);
            ++points;
            (q.omega < w_stuck ? below : above) = true;
        }
    }
    CHECK(stick_curves == 2);
    CHECK(below);
    CHECK(above);
    CHECK(points > 20);
    CHECK(worst < 1e-10);
    // The two stick-slip|slip boundaries close the pure-slip interval where they meet.
    int slip_curves = 0;
    for (const TrackCurve& c : r.curves)
        if (c.boundary == Boundary::stick_slip_slip) {
            ++slip_curves;
            CHECK(c.status == TrackStatus::vanished);
        }
    CHECK(slip_curves == 2);
}

TEST_CASE("track: the exact Jenkins stick boundaries follow the closed-form limit friction coefficient",
          "[tracking]") {
    // A Jenkins contact (spring k_t = r wb^2 in series with the slider) sticks as long as the
    // stuck linear system's spring force stays below mu. That stuck system is the Dahl
    // absorber's linear limit (its pre-sliding stiffness sigma0 = r wb^2, no damping), so
    // mu_limit(w) = contact_limit_friction(p, w, dahl) (analytic.hpp: fe r w^2 wb^2 / |Delta2|):
    // four boundaries around the two stuck resonances.
    const auto jenkins = [](double mu) { return friction_absorber(absorber_fe1(mu), FrictionLaw::jenkins); };
    const FrfSettings settings = default_frf_settings(jenkins(0.3), {});
    REQUIRE(settings.exact);
    TrackOptions o;
    o.feature = TrackFeature::boundary;
    o.p_start = 0.3;
    o.p_end = 1.5;
    const TrackResult r = track(jenkins, settings, o);
    INFO(r.summary());
    CHECK(r.status() == "completed");
    CHECK(r.curves.size() == 4);
    double worst = 0.0;
    int points = 0;
    for (const TrackCurve& c : r.curves) {
        CHECK(c.boundary == Boundary::stick_stick_slip);
        for (const TrackPoint& q : c.points) {
            const double limit = analytic::contact_limit_friction(absorber_fe1(q.p), q.omega, FrictionLaw::dahl);
            worst = std::max(worst, std::abs(limit - q.p) / q.p);
            ++points;
        }
    }
    CHECK(points > 40);
    CHECK(worst < 1e-10);
}

TEST_CASE("track: harmonic-balance peaks of a smooth law (Dahl) follow the FRFs' refined peaks", "[tracking]") {
    // Dahl absorber, mu = 0.5, the force fe from 0.8 to 1: HB (H = 10) at both ends; the peak
    // is sharp (Y'' w^2 / Y ~ 1e5) and the FRF's peaks come from solves at HB's default
    // tolerance 1e-9 (the tracking's at 1e-10): measured 6e-5 in w.
    AbsorberParameters base;
    base.friction_coefficient = 0.5;
    const auto system = [&](double fe) {
        AbsorberParameters p = base;
        p.excitation = fe;
        return friction_absorber(p, FrictionLaw::dahl);
    };
    const FrfSettings settings = default_frf_settings(system(0.8), {});
    REQUIRE_FALSE(settings.exact);
    TrackOptions o;
    o.p_start = 0.8;
    o.p_end = 1.0;
    o.at = {0.9};
    const TrackResult r = track(system, settings, o);
    INFO(r.summary());
    CHECK_FALSE(r.exact);
    CHECK(r.status() == "completed");
    for (double fe : {0.9, 1.0}) {
        const FrfResult frf = compute_frf(system(fe), settings);
        for (const Peak& k : frf.peaks) {
            if (k.output != 0) continue;
            double best = 1.0;
            for (const TrackCurve& c : r.curves)
                for (const TrackPoint& q : c.points)
                    if (std::abs(q.p - fe) < 1e-12) best = std::min(best, std::abs(q.omega - k.omega) / k.omega);
            CHECK(best < 2e-4);
        }
    }
}

TEST_CASE("track: a stop request ends every curve before the step it answers at, the points so far the whole run's",
          "[tracking]") {
    // The exact Coulomb absorber's peaks over mu from 0.3 to 0.5 (as the first case), stopped at
    // the 4th step; then the superharmonic folds, stopped at the 3rd.
    const auto system = [](double mu) { return coulomb_absorber(mu); };
    const FrfSettings settings = default_frf_settings(system(0.3), {});
    TrackOptions o;
    o.p_start = 0.3;
    o.p_end = 0.5;
    const TrackResult whole = track(system, settings, o);
    REQUIRE(whole.status() == "completed");
    int asked = 0;
    o.stop = [&asked]() { return ++asked == 4 ? std::string("enough") : std::string(); };
    const TrackResult early = track(system, settings, o);
    INFO(early.summary());
    CHECK(asked == 4);
    CHECK(early.status() == "incomplete");
    CHECK(early.frfs == 1);  // the check FRF at p_end is not computed
    REQUIRE(early.curves.size() == whole.curves.size());
    for (std::size_t c = 0; c < early.curves.size(); ++c) {
        const TrackCurve &e = early.curves[c], &w = whole.curves[c];
        CHECK(e.status == TrackStatus::stopped);
        CHECK_THAT(e.message, Catch::Contains("stopped at p = ") && Catch::Contains("enough"));
        REQUIRE(e.points.size() == 4);  // the start and three steps
        for (std::size_t k = 0; k < e.points.size(); ++k) {
            CHECK(e.points[k].p == Approx(w.points[k].p).epsilon(1e-14));
            CHECK(e.points[k].omega == Approx(w.points[k].omega).epsilon(1e-12));
        }
    }
    const io::SystemConfig config = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/dahl_superharmonic_fold.toml");
    const auto forced = [&](double fe) {
        System s = config.system;
        s.excitation *= fe;
        return s;
    };
    FrfSettings fold_settings = frf_settings(config.system, {}, config.choices);
    fold_settings.error_points = 0;
    TrackOptions f;
    f.feature = TrackFeature::fold;
    f.p_start = 1.0;
    f.p_end = 0.5;
    asked = 0;
    f.stop = [&asked]() { return ++asked == 3 ? std::string("enough") : std::string(); };
    const TrackResult folds = track(forced, fold_settings, f);
    REQUIRE(folds.curves.size() == 2);
    CHECK(folds.curves[0].status == TrackStatus::stopped);
    CHECK(folds.curves[0].points.size() == 3);
    CHECK(folds.status() == "incomplete");
}

TEST_CASE("track: a curve that leaves the range or the amplitude cap is a warning, bad options name themselves",
          "[tracking]") {
    FrfSettings settings = default_frf_settings(coulomb_absorber(0.6), {});
    TrackOptions o;
    o.p_start = 0.6;
    o.p_end = 1.0;
    o.omega = 0.91;
    settings.continuation.omega_end = 0.92;  // the peak reaches w = 0.92 near mu = 0.83
    TrackResult r = track(coulomb_absorber, settings, o);
    REQUIRE(r.curves.size() == 1);
    CHECK(r.curves[0].status == TrackStatus::left_range);
    CHECK(r.status() == "incomplete");
    CHECK(r.curves[0].points.back().omega > 0.92);
    settings.continuation.omega_end = 1.6;
    settings.continuation.max_amplitude = 12.0;  // the peak reaches 12 near mu = 0.83
    r = track(coulomb_absorber, settings, o);
    CHECK(r.curves[0].status == TrackStatus::amplitude_cap);
    CHECK(r.status() == "incomplete");
    settings.continuation.max_amplitude = 1e3;
    // No peak near the start frequency: an error listing the peaks found.
    o.omega = 1.4;
    CHECK_THROWS_WITH(track(coulomb_absorber, settings, o), Catch::Contains("no peak of y1 within 10 %") &&
                                                               Catch::Contains("found at w = 0.9"));
    o.omega = std::numeric_limits<double>::quiet_NaN();
    o.p_end = o.p_start;
    CHECK_THROWS_WITH(track(coulomb_absorber, settings, o), Catch::Contains("p_end = 0.6 is out of range"));
    o.p_end = 1.0;
    o.at = {1.5};
    CHECK_THROWS_WITH(track(coulomb_absorber, settings, o), Catch::Contains("at: p = 1.5 is out of range"));
}

TEST_CASE("hbf track: CSV, summary and exit codes, bad input is exit 2 with nothing written", "[tracking][cli]") {
    test::TempDir dir;
    const std::string preset = "track --law coulomb --fe 1 --param mu ";
    const auto in = [&](const char* name) { return "'" + (dir.path / name).string() + "'"; };
    auto r = test::run_hbf(preset + "--range 0.6:1 --omega 0.91 --out " + in("t.csv") + " --summary " + in("t.json") + " --quiet", dir);
    CHECK(r.exit_code == 0);
    const auto rows = test::parse_csv(test::slurp(dir.path / "t.csv"));
    REQUIRE(rows.size() > 5);
    CHECK(rows[0] == std::vector<std::string>{"curve", "mu", "w", "y1_max", "kind", "regime", "curvature", "corner"});
    const std::string json = test::slurp(dir.path / "t.json");
    CHECK_THAT(json, Catch::Contains("\"outcome\": \"completed\""));
    CHECK_THAT(json, Catch::Contains("\"solver\": \"exact\""));
    // the peak leaves [wmin, wmax]: written, exit 3
    r = test::run_hbf(preset + "--range 0.6:1 --omega 0.91 --wmax 0.92 --out " + in("l.csv") + " --quiet", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("left_range"));
    CHECK(std::filesystem::exists(dir.path / "l.csv"));
    // bad input: nothing written
    for (const std::string& bad : {std::string("--param zz --range 0.6:1"), std::string("--param mu --range 0.6:1 --output y9"),
                                   std::string("--param mu --range 0.6:1 --omega 1.4"),
                                   std::string("--param mu --range 0.6:0.6"), std::string("--param mu --range 0.6:1 --feature fold2"),
                                   std::string("--param mu --range -1:1")}) {
        test::TempDir empty;
        r = test::run_hbf("track --law coulomb --fe 1 " + bad + " --out '" + (empty.path / "x.csv").string() + "' --quiet", empty);
        INFO(bad << ": " << r.err);
        CHECK(r.exit_code == 2);
        CHECK_FALSE(std::filesystem::exists(empty.path / "x.csv"));
        CHECK_THAT(r.err, Catch::Contains("error"));
    }
    r = test::run_hbf("track --law coulomb --param mu --range 0.6:1 --output y9 --out " + in("x.csv"), dir);
    CHECK_THAT(r.err, Catch::Contains("--output = 'y9' is not an output of the system: allowed y1, y2"));
    r = test::run_hbf("track --law coulomb --param zz --range 0.6:1 --out " + in("x.csv"), dir);
    CHECK_THAT(r.err, Catch::Contains("--param = 'zz' is not known"));
    // hbf map draws the tracked curve over its heat map; the overlay is an input of the run
    r = test::run_hbf("map --law coulomb --fe 1 --param mu --values 0.6,0.8 --overlay " + in("t.csv") + " --plot " +
                          in("m.png") + " --out " + in("m.csv") + " --quiet",
                      dir);
    CHECK(r.exit_code == 0);
    // the overlay draws on the plot: without --plot it is refused, not silently unused
    r = test::run_hbf("map --law coulomb --fe 1 --param mu --values 0.6,0.8 --overlay " + in("t.csv") + " --out " +
                          in("m3.csv") + " --quiet",
                      dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("add --plot"));
    CHECK_FALSE(std::filesystem::exists(dir.path / "m3.csv"));
    r = test::run_hbf("map --law coulomb --param fe --values 0.6,0.8 --overlay " + in("t.csv") + " --plot " +
                          in("m2.png") + " --out " + in("m2.csv") + " --quiet",
                      dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("has no column 'fe'"));
    r = test::run_hbf("map --law coulomb --fe 1 --param mu --values 0.6,0.8 --overlay " + in("t.csv") + " --out " +
                          in("t.csv") + " --quiet",
                      dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--overlay"));
    CHECK(test::parse_csv(test::slurp(dir.path / "t.csv")).size() == rows.size());  // not replaced
}

TEST_CASE("optimize_by_tracking: the friction coefficient of the smallest largest peak, checked by FRFs around it",
          "[tracking][design]") {
    // fe = 0.5, mu in 0.005..5 (hbf optimize's default range). wa = 1/(1 + r): the optimum is an
    // equal-peak design (the two peaks of the FRF there equal); wa = 1: the minimum of one peak
    // (the largest peak grows on both sides). benchmarks/tracking compares both with the
    // golden-section search at 1e-8: |dmu|/mu 2e-10 and 1.6e-8.
    for (double wa : {1.0 / 1.1, 1.0}) {
        AbsorberParameters base;
        base.tuning_ratio = wa;
        const auto system = [&](double mu) {
            AbsorberParameters p = base;
            p.friction_coefficient = mu;
            return friction_absorber(p, FrictionLaw::coulomb);
        };
        const FrfSettings settings = default_frf_settings(system(0.2), {});
        OptimizeOptions o;
        o.lower = 0.005;
        o.upper = 5.0;
        o.threads = 2;
        const TrackOptimum r = optimize_by_tracking(system, settings, o);
        INFO("wa = " << wa << ": " << r.summary("mu"));
        CHECK(r.status == OptimizeStatus::converged);
        CHECK(r.verdict("mu").status() == "completed");
        CHECK(r.kind == (wa < 1.0 ? "equal peaks" : "minimum"));
        // the FRF at the optimum: its largest peak is the tracked value
        const FrfResult at = compute_frf(system(r.parameter), settings);
        CHECK(std::abs(at.peak.value - r.value) < 1e-8 * r.value);
        if (wa < 1.0) {
            std::vector<double> peaks;
            for (const Peak& k : at.peaks)
                if (k.output == 0 && k.refined) peaks.push_back(k.y_max);
            REQUIRE(peaks.size() == 2);
            CHECK(std::abs(peaks[0] - peaks[1]) < 1e-8 * r.value);
        }
        // a minimum: the largest peak is larger on both sides (1e-4 relative away)
        for (double f : {1.0 - 1e-4, 1.0 + 1e-4}) {
            const FrfResult side = compute_frf(system(r.parameter * f), settings);
            CHECK(side.peak.state == PeakState::bounded);
            CHECK(side.peak.value > r.value);
        }
    }
}

TEST_CASE("optimize_by_tracking: exchanges between smaller peaks are not the optimum (the upper envelope decides)",
          "[tracking][design]") {
    // chain3_exact.toml (Jenkins + exact Coulomb), F_c of contact 1 in 1.3..1.65: the main peak
    // (w = 0.69) has an interior minimum near F_c = 1.451 while two smaller peaks (w = 0.22 and
    // 2.01) exchange at 1.4555 without ever being the largest: that exchange, at which the other
    // curves have no solved point, must not be taken for the optimum (it was, with a "largest
    // peak" of 0.96 where the FRF's is 10.5).
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/chain3_exact.toml");
    const auto system = [&](double fc) {
        System s = config.system;
        s.contacts[0].friction_limit = fc;
        return s;
    };
    const FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);
    OptimizeOptions o;
    o.lower = 1.3;
    o.upper = 1.65;
    o.scan_points = 3;
    o.threads = 2;
    const TrackOptimum r = optimize_by_tracking(system, settings, o);
    INFO(r.summary("F_c"));
    REQUIRE(r.status == OptimizeStatus::converged);
    CHECK(r.kind == "minimum");
    CHECK(r.restarts == 0);
    // the FRF at the optimum has the tracked value as its largest peak, and FRFs 1e-3 away on
    // either side have larger ones
    const FrfResult at = compute_frf(system(r.parameter), settings);
    CHECK(std::abs(at.peak.value - r.value) < 1e-8 * r.value);
    CHECK(std::abs(at.peak.omega - 0.6912) < 1e-3);
    for (double f : {1.0 - 1e-3, 1.0 + 1e-3}) {
        const FrfResult side = compute_frf(system(r.parameter * f), settings);
        CHECK(side.peak.value > r.value);
    }
}

TEST_CASE("hbf optimize --method tracking: the optimum and its cost in the JSON, what it cannot do is refused",
          "[tracking][cli]") {
    test::TempDir dir;
    const auto in = [&](const char* name) { return "'" + (dir.path / name).string() + "'"; };
    auto r = test::run_hbf("optimize --law coulomb --wa 0.9090909090909091 --method tracking --threads 2 --out " +
                               in("o.csv") + " --summary " + in("o.json") + " --quiet",
                           dir);
    INFO(r.err);
    CHECK(r.exit_code == 0);
    const std::string json = test::slurp(dir.path / "o.json");
    CHECK_THAT(json, Catch::Contains("\"method\": \"tracking\""));
    CHECK_THAT(json, Catch::Contains("\"kind\": \"equal peaks\""));
    CHECK_THAT(test::slurp(dir.path / "o.csv"), Catch::StartsWith("track,curve,mu,w,peak,kind,regime\n"));
    r = test::run_hbf("optimize --law coulomb --param mu,wa --method tracking --out " + in("x.csv"), dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--method tracking follows the peaks in one parameter"));
    r = test::run_hbf("optimize --law coulomb --method newton --out " + in("x.csv"), dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--method = 'newton' is not known"));
    CHECK_FALSE(std::filesystem::exists(dir.path / "x.csv"));
}

TEST_CASE("track: the Dahl superharmonic folds followed in the force until they merge in a cusp, checked by FRFs",
          "[tracking][folds]") {
    // examples/systems/dahl_superharmonic_fold.toml (H = 10, its automatic one): two folds near
    // w = 0.198 at the file's force; lowering the force, the S-shaped stretch closes.
    const io::SystemConfig config = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/dahl_superharmonic_fold.toml");
    const auto system = [&](double fe) {
        System s = config.system;
        s.excitation *= fe;
        return s;
    };
    FrfSettings settings = frf_settings(config.system, {}, config.choices);
    settings.error_points = 0;  // the folds' positions are checked by FRFs below
    TrackOptions o;
    o.feature = TrackFeature::fold;
    o.p_start = 1.0;
    o.p_end = 0.5;
    const TrackResult r = track(system, settings, o);
    INFO(r.summary());
    REQUIRE(r.curves.size() == 2);
    CHECK(r.status() == "completed");
    CHECK(r.curves[0].status == TrackStatus::vanished);
    REQUIRE(r.events.size() == 1);
    const TrackEvent& cusp = r.events.front();
    CHECK(cusp.kind == "cusp");
    CHECK(cusp.p > 0.6);
    CHECK(cusp.p < 0.8);
    // The two folds approach each other all the way to the cusp.
    const TrackCurve &a = r.curves[0], &b = r.curves[1];
    const double first_gap = std::abs(a.points.front().omega - b.points.front().omega);
    const double last_gap = std::abs(a.points[a.points.size() - 2].omega - b.points[b.points.size() - 2].omega);
    CHECK(last_gap < 1e-2 * first_gap);
    // FRFs (hbf frf's settings) 0.02 before the cusp: folds near its w; 0.02 after: none.
    const auto folds_near = [&](double fe) {
        const FrfResult frf = compute_frf(system(fe), settings);
        int n = 0;
        for (const SolutionPoint& q : frf.points)
            if (q.kind == PointKind::fold && std::abs(q.omega - cusp.omega) < 0.02 * cusp.omega) ++n;
        return n;
    };
    CHECK(folds_near(cusp.p + 0.02) >= 2);
    CHECK(folds_near(cusp.p - 0.02) == 0);
    // At the start the tracked folds are the FRF's.
    const FrfResult at_start = compute_frf(system(1.0), settings);
    std::vector<double> start_folds;
    for (const SolutionPoint& q : at_start.points)
        if (q.kind == PointKind::fold) start_folds.push_back(q.omega);
    REQUIRE(start_folds.size() == 2);
    CHECK(std::abs(a.points.front().omega - start_folds[0]) < 1e-6 * start_folds[0]);
    CHECK(std::abs(b.points.front().omega - start_folds[1]) < 1e-6 * start_folds[1]);
}

TEST_CASE("optimize_by_tracking equals the golden-section optimum to 1e-6 in mu (long)", "[.long][tracking]") {
    // The comparison: hbf optimize's golden-section search at a tight tolerance (1e-8,
    // 54 FRFs each) against tracking, at wa = 1 and wa = 1/(1 + r); benchmarks/tracking times them.
    for (double wa : {1.0, 1.0 / 1.1}) {
        AbsorberParameters base;
        base.tuning_ratio = wa;
        const auto system = [&](double mu) {
            AbsorberParameters p = base;
            p.friction_coefficient = mu;
            return friction_absorber(p, FrictionLaw::coulomb);
        };
        const FrfSettings settings = default_frf_settings(system(0.2), {});
        OptimizeOptions o;
        o.lower = 0.005;
        o.upper = 5.0;
        o.threads = 2;
        const TrackOptimum t = optimize_by_tracking(system, settings, o);
        o.tolerance = 1e-8;
        const OptimizeResult g = optimize_parameter(system, settings, o);
        INFO("wa = " << wa << ": tracking " << t.summary("mu") << "; golden " << g.summary("mu"));
        REQUIRE(g.status == OptimizeStatus::converged);
        REQUIRE(t.status == OptimizeStatus::converged);
        CHECK(std::abs(t.parameter - g.parameter) < 1e-6 * g.parameter);
        CHECK(std::abs(t.value - g.peak.value) < 1e-8 * g.peak.value);
    }
}

TEST_CASE("track: a peak born inside the range is reported, and the same peak located a little apart by the "
          "final FRF is not",
          "[tracking]") {
    // The paper's absorber (fe = 0.5) from mu = 1 (the contact stuck: one peak of y1) down to 0.2
    // (stick-slip: two peaks, 0.880 and 0.895): the second is born on the way, and the FRF at 0.2
    // shows it behind a valley.
    auto absorber_mu = [](double mu) {
        AbsorberParameters p;
        p.friction_coefficient = mu;
        return friction_absorber(p, FrictionLaw::coulomb);
    };
    const FrfSettings settings = default_frf_settings(absorber_mu(1.0), {});
    TrackOptions o;
    o.p_start = 1.0;
    o.p_end = 0.2;
    const TrackResult r = track(absorber_mu, settings, o);
    INFO(r.summary());
    const std::vector<Peak> end = frf_peaks(absorber_mu(0.2));
    REQUIRE(end.size() == 2);
    REQUIRE(r.curves.size() == 1);
    const double reached = r.curves[0].points.back().omega;
    const Peak& same = std::abs(end[0].omega - reached) < std::abs(end[1].omega - reached) ? end[0] : end[1];
    const Peak& other = &same == &end[0] ? end[1] : end[0];
    CHECK(std::abs(reached - same.omega) <= 1e-6 * same.omega);  // the curve ends on one of them
    int born = 0;
    for (const TrackEvent& e : r.events)
        if (e.kind == "born") {
            ++born;
            CHECK(std::abs(e.omega - other.omega) <= 1e-8 * other.omega);
        }
    CHECK(born == 1);
    CHECK(r.status() == "incomplete");
}
