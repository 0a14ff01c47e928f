// The force elements without friction (laws polynomial, gap, damper): harmonic balance against
// closed forms derived here at H = 1, against time integration at higher H, aliasing, the
// stability of the Duffing oscillator's branches, and bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <tuple>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "hbf/modes.hpp"
#include "hbf/tracking.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

constexpr double pi = 3.14159265358979323846;

/// One DOF: m y'' + c y' + k y + f(y) = F cos(w t), f the law of `contact` (DOF 0 to ground).
System one_dof(double m, double c, double k, double force, Contact contact) {
    System s;
    s.mass = sparse(Eigen::MatrixXd::Constant(1, 1, m));
    s.damping = sparse(Eigen::MatrixXd::Constant(1, 1, c));
    s.stiffness = sparse(Eigen::MatrixXd::Constant(1, 1, k));
    s.excitation = Eigen::VectorXd::Constant(1, force);
    contact.dof = 0;
    s.contacts.push_back(contact);
    return s;
}

Contact cubic_spring(double k3) {
    Contact c;
    c.law = FrictionLaw::polynomial;
    c.values["cubic"] = k3;
    return c;
}

/// The first harmonic (a cos + b sin) of DOF 0 at a branch point: a - i b.
std::complex<double> first_harmonic(HarmonicBalance& hb, const SolutionPoint& p) {
    const Eigen::MatrixXd y = hb.dofs(p.x, p.omega);
    return {y(1, 0), -y(2, 0)};
}

FrfSettings band(double from, double to, int harmonics) {
    FrfSettings s;
    s.harmonic_balance.harmonics = harmonics;
    s.continuation.omega_start = from;
    s.continuation.omega_end = to;
    s.continuation.max_step = 0.01;
    s.error_points = 0;
    return s;
}

}  // namespace

// Duffing at H = 1: y = Re(Y e^{i w t}), y^3's first harmonic is (3/4) |Y|^2 Y, so the balance
// of harmonic 1 is (k - m w^2 + i c w + (3/4) k3 |Y|^2) Y = F: every point of the branch
// satisfies it (both signs of k3, through both folds), and the largest amplitude is the
// closed form's peak: d/dw of A^2 (D^2 + c^2 w^2) = F^2 with D = k - m w^2 + (3/4) k3 A^2 and
// dA/dw = 0 gives D = c^2 / (2 m), hence m w^2 = k + (3/4) k3 A^2 - c^2 / (2 m) and
// A = F / sqrt(D^2 + c^2 w^2).
TEST_CASE("Duffing oscillator at H = 1: every point of the FRF on the first-order closed form, the peak on "
          "the backbone",
          "[force_elements]") {
    const double m = 1.0, c = 0.02, k = 1.0, F = 0.02;
    for (const double k3 : {0.5, -0.05}) {
        INFO("k3 = " << k3);
        const System s = one_dof(m, c, k, F, cubic_spring(k3));
        HarmonicBalance hb(s, HarmonicBalanceOptions{1, 0});
        const FrfResult r = compute_frf(hb, band(0.7, 1.5, 1));
        INFO(r.summary());
        REQUIRE(r.status() == "completed");
        double worst = 0.0, largest = 0.0;
        int backwards = 0;
        for (std::size_t i = 0; i < r.points.size(); ++i) {
            const SolutionPoint& p = r.points[i];
            const std::complex<double> Y = first_harmonic(hb, p);
            const double a2 = std::norm(Y);
            const std::complex<double> lhs = (k - m * p.omega * p.omega + 0.75 * k3 * a2 + std::complex<double>(0, c * p.omega)) * Y;
            worst = std::max(worst, std::abs(lhs - F) / F);
            largest = std::max(largest, std::sqrt(a2));
            if (i > 0 && p.omega < r.points[i - 1].omega) ++backwards;
        }
        CHECK(worst <= 1e-9);
        CHECK(backwards > 0);  // the branch turned at a fold (both signs: F / c puts it past them)
        // The peak, by fixed point on (w, A).
        const double D = c * c / (2.0 * m);
        double w = 1.0, peak = F / (c * w);
        for (int it = 0; it < 500; ++it) {
            w = std::sqrt((k + 0.75 * k3 * peak * peak - D) / m);
            peak = F / std::hypot(D, c * w);
        }
        REQUIRE(!r.peaks.empty());
        double found = 0.0;
        for (const Peak& p : r.peaks) found = std::max(found, p.y_max);
        CHECK(test::relative_difference(found, peak) <= 1e-6);
        CHECK(largest <= peak * (1.0 + 1e-9));
    }
}

TEST_CASE("Duffing backbone at H = 1: w^2 = (k + (3/4) k3 A^2) / m along hbf modes, hardening and softening",
          "[force_elements]") {
    const double m = 2.0, k = 3.0;
    for (const double k3 : {0.8, -0.3}) {
        INFO("k3 = " << k3);
        const System s = one_dof(m, 0.0, k, 0.0, cubic_spring(k3));
        ModeOptions o;
        o.amplitude_min = 1e-3;
        o.amplitude_max = k3 > 0 ? 2.0 : 1.0;
        HarmonicBalanceOptions hbo{1, 0};
        const ModeRun run = compute_mode(s, hbo, o, {}, false);
        INFO(run.backbone.message);
        REQUIRE(run.backbone.status == ModeStatus::completed);
        REQUIRE(run.backbone.points.size() > 10);
        double worst = 0.0;
        for (std::size_t i = 0; i < run.backbone.points.size(); ++i) {
            const ModePoint& p = run.backbone.points[i];
            const double A = run.metrics[i].output_amp1[0];
            const double w = std::sqrt((k + 0.75 * k3 * A * A) / m);
            worst = std::max(worst, std::abs(p.omega - w) / w);
            CHECK(std::abs(p.xi) <= 1e-9 * p.omega);  // conservative: no modal damping
        }
        CHECK(worst <= 1e-9);
    }
}

TEST_CASE("Duffing oscillator at H = 9: harmonic balance equals time integration to 1e-6", "[force_elements]") {
    const double m = 1.0, c = 0.05, k = 1.0, F = 0.1, k3 = 1.0;
    const System s = one_dof(m, c, k, F, cubic_spring(k3));
    for (const double omega : {0.6, 1.0, 2.0}) {  // single-valued there (the fold lies near 1.3)
        INFO("w = " << omega);
        const PeriodicResponse ti = integrate_steady_state(s, omega, test::tight_time_integration());
        INFO(ti.summary());
        REQUIRE(ti.converged);
        HarmonicBalance hb(s, HarmonicBalanceOptions{9, 0});
        const SolutionAt at = solve_at(hb, omega, 0.5);
        REQUIRE(at.found);
        const PointMetrics pm = Analyser(hb)(at.point);
        INFO("HB " << pm.y_max[0] << ", TI " << ti.y_max[0]);
        CHECK(test::relative_difference(pm.y_max[0], ti.y_max[0]) <= 1e-6);
        CHECK(test::relative_difference(pm.y_amp1[0], ti.y_amp1[0]) <= 1e-6);
        CHECK(pm.regime == "none");
        CHECK(ti.regime == "none");
    }
}

// Aliasing: y^3 of an H-harmonic motion has harmonics up to 3H, which N_t samples fold onto
// N_t - 3H and above: alias-free when N_t > 4H. The automatic N_t (16 H + 8 rounded up to a
// power of two) is; forced to 4H - 8, the balanced harmonics change and the FRF says so.
TEST_CASE("Cubic spring at H = 10: the automatic N_t is alias-free to rounding, below (p + 1) H the FRF is doubtful",
          "[force_elements]") {
    const System s = one_dof(1.0, 0.05, 1.0, 1.0, cubic_spring(1.0));
    const double omega = 0.8;  // amplitude about 1: strongly nonlinear, rich in harmonics
    auto y_at = [&](int time_samples) {
        HarmonicBalance hb(s, HarmonicBalanceOptions{10, time_samples});
        const SolutionAt at = solve_at(hb, omega, 0.5);
        REQUIRE(at.found);
        return hb.dofs(at.point.x, omega);
    };
    // N_t = 24: y^3's harmonics 14..23 fold onto 10..1
    const Eigen::MatrixXd automatic = y_at(0), fine = y_at(1024), coarse = y_at(24);
    CHECK((automatic - fine).cwiseAbs().maxCoeff() <= 1e-13 * fine.cwiseAbs().maxCoeff());
    CHECK((coarse - fine).cwiseAbs().maxCoeff() >= 1e-9 * fine.cwiseAbs().maxCoeff());  // aliasing is real

    FrfSettings settings = band(0.6, 0.9, 10);
    settings.harmonic_balance.time_samples = 24;
    const FrfResult r = compute_frf(s, settings);
    CHECK(r.status() != "completed");
    INFO(r.verdict.summary());
    CHECK(r.verdict.summary().find("alias-free when N_t > (p + 1) H") != std::string::npos);
}

// Quadratic damper c2 |v| v at H = 1: v = -w A sin(w t + phi), and |sin| sin has the first
// harmonic (8 / (3 pi)) sin, so the damper is the dashpot c_eq = (8 / (3 pi)) c2 w A:
// A^2 ((k - m w^2)^2 + ((c + c_eq) w)^2) = F^2.
TEST_CASE("Quadratic damper at H = 1: the equivalent dashpot (8 / 3 pi) c2 w A, to 1e-10 along the FRF",
          "[force_elements]") {
    const double m = 1.0, c = 0.01, k = 1.0, F = 0.05, c2 = 0.2;
    Contact d;
    d.law = FrictionLaw::damper;
    d.values["coefficient"] = c2;
    const System s = one_dof(m, c, k, F, d);
    HarmonicBalance hb(s, HarmonicBalanceOptions{1, 8192});
    const FrfResult r = compute_frf(hb, band(0.5, 1.5, 1));
    REQUIRE(r.status() == "completed");
    double worst = 0.0;
    for (const SolutionPoint& p : r.points) {
        const double A = std::abs(first_harmonic(hb, p));
        const double ceq = 8.0 / (3.0 * pi) * c2 * p.omega * A;
        const double lhs = A * std::hypot(k - m * p.omega * p.omega, (c + ceq) * p.omega);
        worst = std::max(worst, std::abs(lhs - F) / F);
    }
    // |sin| sin is not a polynomial: N_t samples alias its harmonics N_t - 1, N_t + 1, ...
    // (amplitudes ~ k^-3) onto the first: about 2e-12 at N_t = 8192
    CHECK(worst <= 1e-10);
}

TEST_CASE("Gap spring, quadratic damper: harmonic balance equals time integration (H = 40 / 15)",
          "[force_elements]") {
    Contact gap;
    gap.law = FrictionLaw::gap;
    gap.stiffness = 4.0;
    gap.values["gap"] = 0.2;
    Contact damper;
    damper.law = FrictionLaw::damper;
    damper.values["coefficient"] = 0.1;
    // the gap closes at each frequency (y_max > 0.2) on a period-1 orbit (at 0.8 and 1.1 the
    // time integration finds no period-1 steady state: the impacting response is not periodic)
    using Case = std::tuple<Contact, int, double, std::vector<double>>;
    for (const auto& [contact, harmonics, tolerance, frequencies] :
         {Case{gap, 40, 2e-4, {0.9, 1.0, 1.2}}, Case{damper, 15, 1e-6, {0.8, 1.0, 1.25}}}) {
        const System s = one_dof(1.0, 0.05, 1.0, 0.1, contact);
        INFO("law " << to_string(contact.law));
        for (const double omega : frequencies) {
            INFO("w = " << omega);
            const PeriodicResponse ti = integrate_steady_state(s, omega, test::tight_time_integration());
            INFO(ti.summary());
            REQUIRE(ti.converged);
            HarmonicBalance hb(s, HarmonicBalanceOptions{harmonics, 0});
            const SolutionAt at = solve_at(hb, omega, 0.3);
            REQUIRE(at.found);
            const PointMetrics pm = Analyser(hb)(at.point);
            INFO("HB " << pm.y_max[0] << " (separated " << pm.contacts[0].separated_fraction << "), TI " << ti.y_max[0]);
            CHECK(test::relative_difference(pm.y_max[0], ti.y_max[0]) <= tolerance);
            CHECK(test::relative_difference(pm.y_amp1[0], ti.y_amp1[0]) <= tolerance);
            if (contact.law == FrictionLaw::gap) {
                CHECK(pm.contacts[0].separated_fraction > 0.05);
                CHECK(pm.contacts[0].separated_fraction < 0.95);
                // the open share: HB's samples (N_t = 1024 at H = 40) against the integrator's closing
                // and opening events, within one sample (measured 2e-4 to 4e-4)
                INFO("separated: HB " << pm.contacts[0].separated_fraction << ", TI " << ti.contacts[0].separated_fraction);
                CHECK(std::abs(pm.contacts[0].separated_fraction - ti.contacts[0].separated_fraction) <= 1.0 / 1024);
            } else {
                CHECK(std::isnan(pm.contacts[0].separated_fraction));
            }
        }
    }
}

// Between the two folds of the hardening Duffing FRF the branch runs backwards in w and is a
// saddle (unstable); outside them the branch is stable (light damping: no other instability).
TEST_CASE("Duffing FRF: the middle branch between the folds is unstable, the rest stable (Hill and monodromy)",
          "[force_elements]") {
    const System s = one_dof(1.0, 0.05, 1.0, 0.1, cubic_spring(1.0));
    FrfSettings settings = band(0.6, 2.0, 9);
    settings.stability = true;
    int calls = 0, last_done = 0, last_total = 0;  // the progress: once per point, in order
    bool ordered = true;
    settings.stability_options.progress = [&](int done, int total) {
        ordered = ordered && done == last_done + 1;
        ++calls;
        last_done = done;
        last_total = total;
    };
    const FrfResult r = compute_frf(s, settings);
    INFO(r.summary());
    REQUIRE(r.stability);
    const std::vector<FloquetResult>& st = r.stability->points;
    CHECK(ordered);
    CHECK(calls == static_cast<int>(st.size()));
    CHECK(last_total == static_cast<int>(st.size()));
    REQUIRE(st.size() >= r.branch.points.size());
    int checked = 0, wrong = 0;
    const std::vector<SolutionPoint>& p = r.branch.points;
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
        const bool backwards = p[i + 1].omega < p[i].omega && p[i].omega < p[i - 1].omega;
        const bool forwards = p[i + 1].omega > p[i].omega && p[i].omega > p[i - 1].omega;
        if (!backwards && !forwards) continue;  // at a fold
        ++checked;
        const Stability expected = backwards ? Stability::unstable : Stability::stable;
        if (st[i].stability != expected) ++wrong;
    }
    CHECK(checked > 20);
    CHECK(wrong == 0);
}

TEST_CASE("Force elements' bad input is refused naming the key", "[force_elements]") {
    auto refused = [](Contact c, const std::string& needle) {
        const System s = one_dof(1.0, 0.0, 1.0, 1.0, c);
        try {
            s.validate();
        } catch (const InvalidInput& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(needle) != std::string::npos);
            return;
        }
        FAIL("accepted: expected an error naming " << needle);
    };
    Contact p;
    p.law = FrictionLaw::polynomial;
    refused(p, "no term");
    p.lists["terms"] = {2.5, 1.0};
    refused(p, "terms[1]: exponent 2.5");
    p.lists["terms"] = {16, 1.0};
    refused(p, "1..15");
    p.lists["terms"] = {3, std::nan("")};
    refused(p, "terms[1]: coefficient");
    p.lists.erase("terms");
    p.values["cubic"] = std::numeric_limits<double>::infinity();
    refused(p, "cubic");
    Contact g;
    g.law = FrictionLaw::gap;
    refused(g, "stiffness");
    g.stiffness = 1.0;
    g.values["gap"] = 0.1;
    g.values["preload"] = 0.2;
    refused(g, "preload");
    Contact d;
    d.law = FrictionLaw::damper;
    refused(d, "coefficient is missing");
    d.values["coefficient"] = 1.0;
    d.values["exponent"] = 0.5;
    refused(d, "exponent");
}

// The cusp of the Duffing FRF at H = 1, where its two folds merge as the force decreases: with
// u = A^2, sigma = k - m w^2 and beta = (3/4) k3, the folds in w at fixed F are the double roots
// in u of u ((sigma + beta u)^2 + c^2 w^2) = F^2, i.e. 3 beta^2 u^2 + 4 beta sigma u + sigma^2 +
// c^2 w^2 = 0, real while sigma^2 > 3 c^2 w^2. They merge at sigma = -sqrt(3) c w (beta > 0):
// m w^2 - sqrt(3) c w - k = 0, u = -2 sigma / (3 beta), F^2 = 8 sqrt(3) c^3 w^3 / (9 beta).
TEST_CASE("Duffing folds tracked through the force to their cusp: at the closed form's force and frequency (H = 1)",
          "[force_elements][tracking]") {
    const double m = 1.0, c = 0.05, k = 1.0, k3 = 1.0, F0 = 0.1;
    const auto system = [&](double p) { return one_dof(m, c, k, p * F0, cubic_spring(k3)); };
    const double beta = 0.75 * k3;
    const double wc = (std::sqrt(3.0) * c + std::sqrt(3.0 * c * c + 4.0 * m * k)) / (2.0 * m);
    const double Fc = std::sqrt(8.0 * std::sqrt(3.0) * std::pow(c * wc, 3) / (9.0 * beta));
    FrfSettings settings = band(0.6, 2.0, 1);
    TrackOptions o;
    o.feature = TrackFeature::fold;
    o.p_start = 1.0;
    o.p_end = 0.05;
    const TrackResult r = track(system, settings, o);
    INFO(r.summary());
    REQUIRE(r.events.size() == 1);
    const TrackEvent& cusp = r.events.front();
    CHECK(cusp.kind == "cusp");
    INFO("cusp at F = " << cusp.p * F0 << ", w = " << cusp.omega << "; closed form F = " << Fc << ", w = " << wc
                        << " (relative " << test::relative_difference(cusp.p * F0, Fc) << ", "
                        << test::relative_difference(cusp.omega, wc) << ")");
    // measured 2.0e-6 in F and 2.3e-7 in w: the cusp is where the folds' p turns back, located by
    // the secant method on the tangent's p-component, whose own tolerance this is
    CHECK(test::relative_difference(cusp.p * F0, Fc) <= 1e-5);
    CHECK(test::relative_difference(cusp.omega, wc) <= 1e-5);
}

// NLvib's examples rebuilt from their published parameters (examples/systems/nlvib/): each
// against hbf's time integration at three frequencies where the response is single-valued.
TEST_CASE("NLvib's Duffing example: its FRF with two folds and the unstable branch between them, harmonic balance "
          "equals time integration to 1e-5",
          "[force_elements][examples]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/nlvib/duffing.toml");
    FrfSettings settings = frf_settings(config.system, {}, config.choices);
    settings.stability = true;
    const FrfResult r = compute_frf(config.system, settings);
    INFO(r.summary());
    CHECK(r.status() == "completed");
    REQUIRE(r.stability);
    int folds = 0;
    for (const SolutionPoint& p : r.points) folds += p.kind == PointKind::fold;
    CHECK(folds == 2);
    REQUIRE(r.stability->unstable.size() == 1);
    // the unstable interval spans the folds' frequencies
    std::vector<double> fold_w;
    for (const SolutionPoint& p : r.points)
        if (p.kind == PointKind::fold) fold_w.push_back(p.omega);
    REQUIRE(fold_w.size() == 2);
    const auto [low, high] = std::minmax(r.stability->unstable.front().omega_from, r.stability->unstable.front().omega_to);
    CHECK(std::abs(low - std::min(fold_w[0], fold_w[1])) < 0.02);
    CHECK(std::abs(high - std::max(fold_w[0], fold_w[1])) < 0.02);
    for (const double omega : {0.7, 0.95, 1.6}) {
        INFO("w = " << omega);
        const PeriodicResponse ti = integrate_steady_state(config.system, omega, test::tight_time_integration());
        REQUIRE(ti.converged);
        HarmonicBalance hb(config.system, HarmonicBalanceOptions{15, 0});
        const SolutionAt at = solve_at(hb, omega, 0.5);
        REQUIRE(at.found);
        const PointMetrics pm = Analyser(hb)(at.point);
        INFO("HB " << pm.y_max[0] << ", TI " << ti.y_max[0]);
        CHECK(test::relative_difference(pm.y_max[0], ti.y_max[0]) <= 1e-5);
    }
}

// Friction and polynomial stiffness in one model (examples/systems/beam/beam200_jointed.toml:
// a reduced cantilever, a Dahl joint and a cubic spring at its tip): the hardening FRF with its
// folds and the unstable stretch between them, time integration at three frequencies, and the
// backbone, whose frequency at the FRF peak's tip amplitude is the peak's (light damping).
TEST_CASE("Jointed beam with geometric stiffening: FRF, stability, backbone and the time-integration reference",
          "[force_elements][examples]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/beam200_jointed.toml");
    FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);
    settings.stability = true;
    settings.stability_options.method = StabilityMethod::hill;
    const FrfResult r = compute_frf(config.system, settings);
    INFO(r.summary());
    CHECK(r.status() == "completed");
    REQUIRE(r.stability);
    std::vector<double> folds;
    for (const SolutionPoint& p : r.points)
        if (p.kind == PointKind::fold) folds.push_back(p.omega);
    REQUIRE(folds.size() == 2);
    REQUIRE(r.stability->unstable.size() == 1);
    const auto [low, high] = std::minmax(r.stability->unstable.front().omega_from, r.stability->unstable.front().omega_to);
    CHECK(std::abs(low - std::min(folds[0], folds[1])) < 0.01 * low);
    CHECK(std::abs(high - std::max(folds[0], folds[1])) < 0.01 * high);
    // time integration where the response is single-valued (below the folds and above them)
    for (const double omega : {60.0, 90.0, 150.0}) {
        INFO("w = " << omega);
        TimeIntegrationOptions o;  // the FE model's stiffness stalls the Poincare map near 1e-10
        o.relative_tolerance = 1e-10;
        o.absolute_tolerance = 1e-12;
        o.steady_tolerance = 1e-8;
        o.outputs = config.outputs;
        const PeriodicResponse ti = integrate_steady_state(config.system, omega, o);
        INFO(ti.summary());
        REQUIRE(ti.converged);
        HarmonicBalance hb(config.system, settings.harmonic_balance);
        const SolutionAt at = solve_at(hb, omega, 30.0);
        REQUIRE(at.found);
        const PointMetrics pm = Analyser(hb, {}, config.outputs)(at.point);
        INFO("HB " << pm.output_max[0] << ", TI " << ti.output_max[0]);
        // measured 4e-6 at the file's automatic H = 10 (Dahl's truncation)
        CHECK(test::relative_difference(pm.output_max[0], ti.output_max[0]) <= 2e-5);
    }
    ModeOptions mo;
    mo.amplitude_min = 1e-5;
    mo.amplitude_max = 5e-3;
    const ModeRun run = compute_mode(config.system, settings.harmonic_balance, mo, config.outputs, false);
    INFO(run.verdict.summary());
    REQUIRE(run.verdict.status() == "completed");
    // the FRF's peak: the tip's first harmonic there, and the backbone's w at that tip amplitude
    REQUIRE(!r.peaks.empty());
    const Peak& peak = r.peaks.front();
    HarmonicBalance hb(config.system, settings.harmonic_balance);
    const SolutionAt at = solve_at(hb, peak.omega, 30.0);
    REQUIRE(at.found);
    const double tip = Analyser(hb, {}, config.outputs)(at.point).output_amp1[1];
    double w_backbone = 0.0;
    for (std::size_t k = 1; k < run.metrics.size(); ++k) {
        const double a = run.metrics[k - 1].output_amp1[1], b = run.metrics[k].output_amp1[1];
        if ((a - tip) * (b - tip) <= 0.0) {
            const ModePoint &p = run.backbone.points[k - 1], &q = run.backbone.points[k];
            w_backbone = p.omega + (tip - a) / (b - a) * (q.omega - p.omega);
            break;
        }
    }
    INFO("peak at w = " << peak.omega << " (tip amplitude " << tip << "), backbone there w = " << w_backbone);
    // measured 0.47 %: the damping (Rayleigh 1 % and the joint's) moves the peak off the backbone
    CHECK(std::abs(w_backbone - peak.omega) <= 0.01 * peak.omega);
}

TEST_CASE("NLvib's three-mass chain with Jenkins, cubic and gap springs: harmonic balance converges to time "
          "integration where the contacts slip",
          "[force_elements][examples]") {
    // Where both Jenkins elements stick throughout (below w = 0.9), the periodic state is a family
    // (each slider anywhere in its admissible range): harmonic balance takes the centred sliders,
    // time integration keeps those its history left (6e-5 apart in y2_max at w = 0.7, at any
    // H), so the comparison is made where a contact slips. The branch from below ends at w =
    // 1.6577 (the upper branch's end, where contact 1's last slip samples vanish): 1.9 is reached
    // from above.
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/nlvib/chain3.toml");
    for (const auto& [omega, from] : {std::pair<double, double>{1.1, 0.5}, {1.2, 0.5}, {1.9, 2.0}}) {
        INFO("w = " << omega);
        const PeriodicResponse ti = integrate_steady_state(config.system, omega, test::tight_time_integration());
        INFO(ti.summary());
        REQUIRE(ti.converged);
        double error = 0.0;
        for (const int harmonics : {10, 40}) {
            HarmonicBalance hb(config.system, HarmonicBalanceOptions{harmonics, 0});
            const SolutionAt at = solve_at(hb, omega, from);
            REQUIRE(at.found);
            const PointMetrics pm = Analyser(hb)(at.point);
            REQUIRE(pm.contacts[0].regime != "stick");
            error = std::abs(pm.y_max[1] - ti.y_max[1]) / ti.y_max[1];
            UNSCOPED_INFO("w = " << omega << ", H = " << harmonics << ": y2_max " << pm.y_max[1] << " against "
                                 << ti.y_max[1] << " (" << error << ", contact 1 " << pm.contacts[0].regime << ")");
        }
        // measured at H = 40: 7.1e-6, 6.1e-6, 9.8e-6 (from 1.4e-4, 4.2e-4, 3.0e-4 at H = 10); the
        // corners of the Jenkins and gap forces make the error oscillate with H (1.6e-5 at w = 1.2
        // and H = 48): 2e-5 bounds it
        CHECK(error <= 2e-5);
    }
}

// NLvib's cantilever with a cubic spring at its tip (examples/systems/nlvib/make_cantilever.py).
// Backbone (NLvib's computation: the undamped beam, modal amplitude a from 1e-5 to 1e-3): near a
// = 0 the single-mode first-order closed form, with y = phi a cos(theta) (phi the first linear
// mode, M-normalised, phi_t its tip entry) the cubic spring's first harmonic on the mode is
// (3/4) k3 phi_t^4 a^3, so w^2 = w1^2 + (3/4) k3 phi_t^4 a^2 (phi and w1 from Eigen's
// generalised eigensolver, independently of hbf's stuck modes). Forced response (the file's
// damping and tip force): time integration at three frequencies where it is single-valued or
// on the lower branch, the upper branch's state integrated from harmonic balance's orbit stays
// there (stable), and the monodromy's verdict on the three branches at one frequency.
TEST_CASE("NLvib's cantilever with a cubic tip spring: backbone against the closed form's limit, FRF against time "
          "integration, the branches' stability",
          "[force_elements][examples]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/nlvib/cantilever_cubic.toml");
    const System& forced = config.system;
    const int n = static_cast<int>(forced.mass.rows());
    REQUIRE(n == 38);
    const int tip = n - 2;
    const double k3 = forced.contacts.front().values.at("cubic");
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(forced.stiffness),
                                                                        Eigen::MatrixXd(forced.mass));
    const double w1 = std::sqrt(eig.eigenvalues()(0));
    const double phi_t = eig.eigenvectors()(tip, 0);  // M-normalised by the solver
    SECTION("backbone of the undamped beam: the closed form's limit, the 5:1 internal resonance") {
        System undamped = forced;
        undamped.damping = SparseMatrix(n, n);
        ModeOptions mo;
        mo.amplitude_min = 1e-5;
        mo.amplitude_max = 1e-3;
        const ModeRun run = compute_mode(undamped, HarmonicBalanceOptions{}, mo, {}, false);
        INFO(run.verdict.summary());
        REQUIRE(run.backbone.points.size() > 10);
        const ModePoint& first = run.backbone.points.front();
        const double a = first.amplitude;
        const double shift = 0.75 * k3 * std::pow(phi_t, 4) * a * a;  // w^2 - w1^2 of the closed form
        INFO("a = " << a << ": w = " << first.omega << ", w1 = " << w1 << ", closed form's shift " << shift
                    << ", harmonic balance's " << first.omega * first.omega - w1 * w1);
        CHECK(first.omega * first.omega - w1 * w1 == Approx(shift).epsilon(2e-3));
        CHECK(std::abs(first.xi) <= 1e-9 * w1);  // undamped: no artificial damping
        // Undamped, the hardening backbone meets the second mode's fifth subharmonic (5 w = w2,
        // both hardened): it turns back in a there, onto that mode's branch (the classical
        // internal-resonance tongue, which damping breaks: the file's backbone below crosses it).
        const double w2 = std::sqrt(eig.eigenvalues()(1));
        std::size_t turn = 0;
        while (turn + 1 < run.backbone.points.size() &&
               run.backbone.points[turn + 1].amplitude > run.backbone.points[turn].amplitude)
            ++turn;
        const ModePoint& top = run.backbone.points[turn];
        INFO("the backbone turns back at a = " << top.amplitude << ", w = " << top.omega << " (w2 / 5 = " << w2 / 5.0
                                               << ")");
        REQUIRE(turn + 1 < run.backbone.points.size());
        CHECK(top.omega > w2 / 5.0);
        CHECK(top.omega < 1.03 * w2 / 5.0);  // measured 189.07 against 186.34
    }
    SECTION("backbone of the damped beam: complete, converged in H (NLvib's H = 5 against 10)") {
        ModeOptions mo;
        mo.amplitude_min = 1e-5;
        mo.amplitude_max = 1e-3;
        double omega_end[2] = {0.0, 0.0};
        for (const int harmonics : {5, 10}) {
            const ModeRun run = compute_mode(forced, HarmonicBalanceOptions{harmonics, 0}, mo, {}, false);
            INFO("H = " << harmonics << ": " << run.verdict.summary());
            REQUIRE(run.verdict.status() == "completed");
            CHECK(run.backbone.points.back().amplitude == Approx(1e-3).epsilon(1e-12));
            omega_end[harmonics == 5 ? 0 : 1] = run.backbone.points.back().omega;
        }
        INFO("w at a = 1e-3: " << omega_end[0] << " (H = 5), " << omega_end[1] << " (H = 10)");
        CHECK(omega_end[1] > 1.7 * w1);  // measured 265.53 = 1.79 w1
        CHECK(test::relative_difference(omega_end[0], omega_end[1]) <= 1e-6);  // measured 9e-8
    }
    SECTION("forced response against time integration, stability") {
        TimeIntegrationOptions o;
        o.method = IntegrationMethod::bdf;  // the FE beam's stiff high modes
        o.relative_tolerance = 1e-11;
        o.absolute_tolerance = 1e-12;
        o.steady_tolerance = 1e-9;
        HarmonicBalance hb(forced, HarmonicBalanceOptions{});
        FrfSettings settings = frf_settings(forced, config.outputs, config.choices);
        settings.error_points = 0;
        const std::vector<double> frequencies{140.0, 180.0, 250.0};  // 180: three solutions
        settings.at = frequencies;
        const FrfResult r = compute_frf(forced, settings);
        REQUIRE(r.status() == "completed");
        for (const double omega : frequencies) {
            INFO("w = " << omega);
            std::vector<std::pair<double, SolutionPoint>> samples;  // by the tip's amplitude
            for (const SolutionPoint& q : r.points)
                if (q.kind == PointKind::sample && q.omega == omega) samples.emplace_back(Analyser(hb)(q).y_max[tip], q);
            REQUIRE(samples.size() == (omega == 180.0 ? 3u : 1u));
            std::sort(samples.begin(), samples.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
            // from rest, time integration reaches the lowest solution
            const PeriodicResponse ti = integrate_steady_state(forced, omega, o);
            INFO(ti.summary());
            REQUIRE(ti.converged);
            INFO("HB " << samples.front().first << ", TI " << ti.y_max[tip]);
            CHECK(test::relative_difference(samples.front().first, ti.y_max[tip]) <= 1e-5);  // measured <= 1.3e-8
            if (omega != 180.0) continue;
            // lower (stable), middle between the folds (unstable), upper (stable) by the monodromy
            StabilityOptions so;
            so.method = StabilityMethod::monodromy;
            StabilityAnalyser stability(hb, so);
            const std::vector<Stability> expected{Stability::stable, Stability::unstable, Stability::stable};
            for (std::size_t k = 0; k < 3; ++k) {
                const FloquetResult f = stability(samples[k].second);
                INFO("solution " << k + 1 << ": " << f.message << ", margin " << f.margin);
                CHECK(f.stability == expected[k]);
            }
            // the upper solution's orbit, integrated in time, stays on it
            const Eigen::VectorXd start = stability.start_state(samples[2].second);
            const PeriodicResponse upper = integrate_steady_state(forced, omega, o, &start);
            INFO(upper.summary());
            REQUIRE(upper.converged);
            CHECK(test::relative_difference(samples[2].first, upper.y_max[tip]) <= 1e-5);
        }
    }
}

// Where the chain's branch from below stops (w_end = 1.6577 at the file's H = 7): the upper
// branch's orbit has contact 1 about to stick throughout. Time integration from harmonic
// balance's end state sticks there for the whole period (a stuck Jenkins slider keeps the offset
// its history left: the stuck orbits are a family, which the branch cannot follow as a curve),
// and a little above w_end the same start falls to the lower branch (y3_max a sixth): the upper
// branch ends in a fold at w_end, and the branch from above (2.0 down) is the rest of the FRF.
TEST_CASE("NLvib's three-mass chain: the branch from below ends where the upper branch folds with contact 1 "
          "stuck, time integration confirms it",
          "[force_elements][examples]") {
    const io::SystemConfig config =
        io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/nlvib/chain3.toml");
    FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);
    settings.error_points = 0;
    const FrfResult r = compute_frf(config.system, settings);
    INFO(r.summary());
    REQUIRE(!r.branch.points.empty());
    const SolutionPoint& end = r.branch.points.back();
    HarmonicBalance hb(config.system, settings.harmonic_balance);
    const PointMetrics at_end = Analyser(hb)(end);
    INFO("branch ends at w = " << end.omega << ", contact 1 stuck " << at_end.contacts[0].stick_fraction
                               << " of the period, y3_max " << at_end.y_max[2]);
    CHECK(end.omega == Approx(1.6577).margin(0.01));
    CHECK(at_end.contacts[0].stick_fraction >= 0.95);
    TimeIntegrationOptions o;
    o.relative_tolerance = 1e-10;
    o.absolute_tolerance = 1e-12;
    o.steady_tolerance = 1e-9;
    const Eigen::VectorXd start = StabilityAnalyser(hb).start_state(end);
    const PeriodicResponse upper = integrate_steady_state(config.system, end.omega, o, &start);
    INFO(upper.summary());
    REQUIRE(upper.converged);
    CHECK(upper.contacts[0].stick_fraction == 1.0);
    // H = 7 against the integrated orbit: measured 2.5e-4 in y3_max
    CHECK(test::relative_difference(at_end.y_max[2], upper.y_max[2]) <= 3e-3);
    const double above = end.omega + 0.005;
    const PeriodicResponse fallen = integrate_steady_state(config.system, above, o, &start);
    INFO(fallen.summary());
    REQUIRE(fallen.converged);
    INFO("w = " << above << ": time integration y3_max " << fallen.y_max[2] << ", the upper orbit's at w_end "
                << upper.y_max[2]);
    CHECK(fallen.y_max[2] < 0.5 * upper.y_max[2]);  // measured 0.18 against 1.07
}
