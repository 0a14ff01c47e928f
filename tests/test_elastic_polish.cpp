// Tests of the exact polish of harmonic-balance branches for law elastic (exact_polish.hpp with
// elastic_exact.hpp's solver): the polished points against the time integrator's steady states,
// the located stick|stick-slip transition bracketed by time integration, the default's rule,
// the probe's budget and the command line.
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/time_integration.hpp"
#include "cli_support.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

System liftoff3_example() { return io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system; }

/// The FRF of `s` over [w0, w1] at H = 10 with the exact polish on (no HB error estimate).
FrfResult polished(const System& s, double w0, double w1, HarmonicBalance& hb) {
    FrfChoices choices;
    choices.omega_start = w0;
    choices.omega_end = w1;
    choices.exact = true;
    FrfSettings settings = frf_settings(s, {}, choices);
    settings.error_points = 0;
    return compute_frf(hb, settings);
}

}  // namespace

TEST_CASE("elastic polish: liftoff3 points equal the integrator's steady states", "[elastic_polish][verification]") {
    const System s = liftoff3_example();
    HarmonicBalance hb(s, {10, 0});
    const FrfResult r = polished(s, 1.5, 2.16, hb);
    REQUIRE(r.polish);
    const PolishedBranch& p = *r.polish;
    INFO(p.summary());
    CHECK(p.failed == 0);
    CHECK(p.polished == static_cast<int>(p.points.size()));
    CHECK(p.unstable == 0);
    // HB at H = 10 is close to, not at, the exact orbit
    CHECK(p.max_hb_gap > 1e-9);
    CHECK(p.max_hb_gap < 5e-3);

    // The stick|stick-slip transition near 1.83: time integration from rest sticks all period
    // 1e-3 below it and slips 1e-3 above it. The first lift-off near 2.1 (closed|lift-off, the
    // grazing orbit): closed all period 1e-3 below it, open part of it 1e-3 above it.
    const TimeIntegrationOptions tight = hbf::test::tight_time_integration();
    std::vector<Boundary> found;
    for (std::size_t k = 0; k < p.points.size(); ++k) {
        if (p.points[k].kind != PointKind::transition) continue;
        const Boundary boundary = p.points[k].boundary;
        found.push_back(boundary);
        const double w = p.points[k].omega;
        INFO("transition " << to_string(boundary) << " at w = " << w);
        const PeriodicResponse below = integrate_steady_state(s, w * (1.0 - 1e-3), tight, nullptr);
        const PeriodicResponse above = integrate_steady_state(s, w * (1.0 + 1e-3), tight, nullptr);
        REQUIRE(below.converged);
        REQUIRE(above.converged);
        if (boundary == Boundary::stick_stick_slip) {
            CHECK(below.contacts[0].stick_fraction == 1.0);
            CHECK(above.contacts[0].stick_fraction < 1.0 - 1e-3);
        } else {
            CHECK(p.metrics[k].contacts[0].separated_fraction == 0.0);
            CHECK(below.contacts[0].separated_fraction == 0.0);
            CHECK(above.contacts[0].separated_fraction > 1e-3);
        }
    }
    CHECK(found == std::vector<Boundary>{Boundary::stick_stick_slip, Boundary::closed_lift_off});

    // Stick-slip points (with lift-off above 2.1): the orbit is unique, so maxima,
    // first harmonics and shares equal the integrator's from rest. A permanently stuck point
    // (1.6): the orbits form a family in the slider's held position, which shifts the mean
    // only: the first harmonics equal the integrator's.
    double opened = 0.0;
    for (const double target : {1.6, 1.95, 2.15}) {
        std::size_t at = 0;
        for (std::size_t k = 0; k < p.points.size(); ++k)
            if (p.points[k].kind == PointKind::regular &&
                std::abs(p.points[k].omega - target) < std::abs(p.points[at].omega - target))
                at = k;
        const double w = p.points[at].omega;
        const PointMetrics& m = p.metrics[at];
        INFO("w = " << w << ": " << p.exact[at].message);
        REQUIRE(p.exact[at].status == PolishStatus::exact);
        const PeriodicResponse ti = integrate_steady_state(s, w, tight, nullptr);
        REQUIRE(ti.converged);
        for (std::size_t i = 0; i < 2; ++i) CHECK(m.y_amp1[i] == Approx(ti.y_amp1[i]).epsilon(1e-8));
        if (target < 1.8) {
            CHECK(m.contacts[0].stick_fraction == 1.0);
            // stuck and closed: N = N_0 + k_n y2 is a sinusoid about its mean, its half range
            // k_n |y2's first harmonic| (k_n = 5; the range from 4096 samples: 1.2e-6)
            CHECK(m.contacts[0].normal_amplitude == Approx(5.0 * m.y_amp1[1]).epsilon(2e-6));
            continue;
        }
        CHECK(m.contacts[0].normal_mean == Approx(ti.contacts[0].normal_mean).epsilon(1e-8));
        for (std::size_t i = 0; i < 2; ++i) CHECK(m.y_max[i] == Approx(ti.y_max[i]).epsilon(1e-8));
        CHECK(m.contacts[0].stick_fraction == Approx(ti.contacts[0].stick_fraction).margin(1e-8));
        CHECK(m.contacts[0].separated_fraction == Approx(ti.contacts[0].separated_fraction).margin(1e-8));
        opened = std::max(opened, m.contacts[0].separated_fraction);
    }
    CHECK(opened > 0.05);
}

TEST_CASE("elastic polish: off by default, the solver's bound, the probe's budget", "[elastic_polish]") {
    // off by default (harmonic balance and its error estimate), with the reason
    FrfChoices automatic;
    automatic.omega_start = 0.5;
    automatic.omega_end = 1.0;
    const FrfSettings off = frf_settings(hbf::test::elastic_chain(3), {}, automatic);
    CHECK_FALSE(off.exact);
    CHECK_THAT(off.exact_note, Catch::Contains("off by default for law elastic"));
    // beyond the solver's bound the polish is refused, naming the count
    CHECK_THAT(exact_polish_refusal(hbf::test::elastic_chain(300)), Catch::Contains("601 continuous states"));
    CHECK(exact_polish_refusal(hbf::test::elastic_chain(299)).empty());
    // and an FRF of such a model is harmonic balance's, the note saying why
    const FrfSettings beyond = frf_settings(hbf::test::elastic_chain(300), {}, automatic);
    CHECK_FALSE(beyond.exact);
    CHECK_THAT(beyond.exact_note, Catch::Contains("the exact polish is off here") && Catch::Contains("601 continuous states"));

    // An optional polish whose probe exceeds the budget is stopped there and declined.
    const System s = liftoff3_example();
    HarmonicBalance hb(s, {10, 0});
    FrfChoices choices;
    choices.omega_start = 1.9;
    choices.omega_end = 2.0;
    choices.exact = false;
    FrfSettings settings = frf_settings(s, {}, choices);
    settings.error_points = 0;
    const FrfResult r = compute_frf(hb, settings);
    std::vector<PointMetrics> metrics = r.metrics;
    PolishOptions po;
    po.decline_seconds = 1e-6;
    const PolishedBranch declined = polish_branch(hb, r.points, metrics, po, settings.continuation.corrector);
    CHECK_THAT(declined.declined, Catch::Contains("was stopped after"));
    CHECK(declined.points.empty());
}

TEST_CASE("elastic polish from the command line equals the exact sweep", "[elastic_polish][cli]") {
    ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml";
    const auto frf_csv = dir.path / "frf.csv", exact_csv = dir.path / "exact.csv";
    const ::test::Result frf = ::test::run_hbf(
        "frf --config '" + example + "' --wmin 1.9 --wmax 2.1 --exact on --at 2.0 --out '" + frf_csv.string() + "'", dir);
    INFO(frf.err);
    REQUIRE(frf.exit_code == 0);
    const ::test::Result exact = ::test::run_hbf(
        "timeint --config '" + example + "' --method exact --w 2.0 --out '" + exact_csv.string() + "'", dir);
    INFO(exact.err);
    REQUIRE(exact.exit_code == 0);
    const auto f = ::test::parse_csv(::test::slurp(frf_csv)), e = ::test::parse_csv(::test::slurp(exact_csv));
    REQUIRE(e.size() == 2);
    const std::vector<std::string> row = ::test::sample_row(f, 2.0);
    REQUIRE(!row.empty());
    const auto column = [&](const char* name) {
        return static_cast<std::size_t>(std::find(f.front().begin(), f.front().end(), name) - f.front().begin());
    };
    for (std::size_t k = 1; k < f.size(); ++k) CHECK(f[k][column("exact")] == "yes");
    for (const char* name : {"y1_max", "y2_max", "y1_amp1", "stick_fraction", "separated_fraction"})
        CHECK(::test::column(f, row, name) == Approx(::test::column(e, e[1], name)).epsilon(1e-9).margin(1e-12));
    CHECK(::test::column(f, row, "hb_gap") > 0.0);
}
