// Stability of harmonic-balance solutions (stability.hpp): Hill's sorted exponents and the
// monodromy of the variational equation against a closed form, against each other, and every
// verdict against a perturbed time integration.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "../benchmarks/contact_chain.hpp"
#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/frf.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/stability.hpp"
#include "hbf/table.hpp"
#include "hbf/time_integration.hpp"

using namespace hbf;

namespace {

const std::string source = HBF_SOURCE_DIR;

/// A damped SDOF (m = 1, k = 1, c) with a Dahl contact to the ground (sigma0 = 1) whose
/// friction limit is never approached: the bristle is a linear spring, z' = v.
System linear_dahl(double c) {
    System s;
    s.mass = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.stiffness = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.damping = sparse(c * Eigen::MatrixXd::Identity(1, 1));
    s.excitation = Eigen::VectorXd::Constant(1, 0.1);
    Contact contact;
    contact.law = FrictionLaw::dahl;
    contact.friction_limit = 1e7;
    contact.stiffness = 1.0;
    s.contacts = {contact};
    return s;
}

SolutionPoint solve(HarmonicBalance& hb, double omega) {
    Corrector corrector(hb, {});
    SolutionPoint p;
    p.omega = omega;
    p.x = hb.linear_guess(omega);
    REQUIRE(corrector.solve_at(p.x, omega, hb.unknown_scale(p.x), p.iterations, p.residual));
    return p;
}

/// An FRF with --stability of a shipped system file at H harmonics over [wmin, wmax], its
/// HarmonicBalance kept for the checks that follow.
struct StabilityRun {
    io::SystemConfig config;
    std::unique_ptr<HarmonicBalance> hb;
    FrfResult frf;
};
StabilityRun stability_run(const std::string& file, int harmonics, double wmin, double wmax, bool exact) {
    StabilityRun run;
    run.config = io::read_system_config(source + "/examples/systems/" + file);
    FrfSettings settings;
    settings.harmonic_balance = {harmonics, 0};
    settings.continuation.omega_start = wmin;
    settings.continuation.omega_end = wmax;
    settings.exact = exact;
    settings.stability = true;
    run.hb = std::make_unique<HarmonicBalance>(run.config.system, settings.harmonic_balance);
    run.frf = compute_frf(*run.hb, settings);
    return run;
}

/// |mu| of every expected multiplier has a partner in `mu` within `tolerance`.
void check_contains(const Eigen::VectorXcd& mu, const std::vector<std::complex<double>>& expected, double tolerance) {
    for (const auto& e : expected) {
        double best = 1e300;
        for (Eigen::Index k = 0; k < mu.size(); ++k) best = std::min(best, std::abs(mu(k) - e));
        INFO("expected multiplier " << e << " in " << mu.transpose());
        CHECK(best < tolerance);
    }
}

/// Integrates `periods` periods of the system from `state` (time_integration.hpp's convention)
/// and returns the state (y, y', internal) after them.
Eigen::VectorXd flow(const System& s, double omega, const Eigen::VectorXd& state, int periods, int d) {
    TimeIntegrationOptions o;
    o.relative_tolerance = 1e-12;
    o.absolute_tolerance = 1e-14;
    o.method = IntegrationMethod::bdf;
    o.min_periods = o.max_periods = periods + 1;  // `state` is the start of the last period
    o.shooting = false;
    o.stick_restart = false;
    o.steady_tolerance = 1e-14;
    return integrate_steady_state(s, omega, o, &state).state.head(d);
}

/// The growth over n periods of a perturbation delta * v (v the monodromy's eigenvector of its
/// largest multiplier, real part) of the orbit starting at `start`, measured by two time
/// integrations: |x_n(start + delta v) - x_n(start)| / |delta v|, and predicted by the
/// monodromy: |Phi^n v|. n is chosen so that |mu|^n is about 2 or 1/2 (1..400 periods).
struct Growth {
    double measured = 0, predicted = 0, mismatch = 0;  ///< mismatch: |measured - predicted vector| / |predicted|
    int periods = 0;
};
Growth perturbed_growth(const System& s, double omega, const Eigen::VectorXd& start, const Eigen::MatrixXd& monodromy) {
    const int d = static_cast<int>(monodromy.rows());
    Eigen::EigenSolver<Eigen::MatrixXd> eig(monodromy);
    Eigen::Index top = 0;
    eig.eigenvalues().cwiseAbs().maxCoeff(&top);
    const double modulus = std::abs(eig.eigenvalues()(top));
    Eigen::VectorXd v = eig.eigenvectors().col(top).real();
    if (v.norm() < 1e-3) v = eig.eigenvectors().col(top).imag();
    v.normalize();
    Growth g;
    g.periods = std::clamp(static_cast<int>(std::ceil(std::log(2.0) / std::abs(std::log(modulus)))), 1, 400);
    Eigen::VectorXd predicted = v;
    for (int k = 0; k < g.periods; ++k) predicted = monodromy * predicted;
    g.predicted = predicted.norm();
    const double delta = 1e-7 * std::max(1.0, start.head(d).cwiseAbs().maxCoeff());
    Eigen::VectorXd moved = start;
    moved.head(d) += delta * v;
    const Eigen::VectorXd measured = (flow(s, omega, moved, g.periods, d) - flow(s, omega, start, g.periods, d)) / delta;
    g.measured = measured.norm();
    g.mismatch = (measured - predicted).norm() / g.predicted;
    return g;
}

/// A completed FRF of these points, every one polished (its exact points `polish`).
FrfResult polished_frf(const std::vector<SolutionPoint>& points, const std::vector<ExactPoint>& polish) {
    FrfResult frf;
    frf.branch.status = ContinuationStatus::completed;
    frf.points = points;
    frf.metrics.resize(points.size());
    frf.exact = polish;
    frf.polish = PolishedBranch{};
    frf.polish->polished = static_cast<int>(points.size());
    return frf;
}

/// An FRF's verdict without peaks, which has neither errors nor warnings.
Verdict judged_quietly(const FrfResult& frf) {
    FrfSettings settings;
    settings.peaks = false;
    Verdict v = judge_frf(frf, settings);
    CHECK(v.errors.empty());
    CHECK(v.warnings.empty());
    return v;
}

}  // namespace

TEST_CASE("Floquet multipliers of a linear Dahl oscillator: Hill and the monodromy against the closed form",
          "[stability]") {
    // z = q (the bristle never slides): y'' + c y' + (k + sigma0) y = F cos(w t) plus the
    // neutral mode z - q = const, so mu = exp(lambda T) with lambda = -c/2 +- i sqrt(2 - c^2/4)
    // and mu = 1 (to the 1e-7 of |v| / F_c).
    for (double c : {0.05, -0.05}) {
        const System s = linear_dahl(c);
        HarmonicBalance hb(s, {8, 0, Formulation::full});
        const double omega = 0.8, period = 2.0 * M_PI / omega;
        const SolutionPoint p = solve(hb, omega);
        const std::complex<double> lambda(-0.5 * c, std::sqrt(2.0 - 0.25 * c * c));
        const std::vector<std::complex<double>> expected = {std::exp(lambda * period), std::exp(std::conj(lambda) * period),
                                                            1.0};
        StabilityAnalyser analyse(hb);
        INFO("c = " << c);
        const Eigen::VectorXcd hill = analyse.hill(p);
        REQUIRE(hill.size() == 3);
        check_contains(hill, expected, 1e-6);
        const Eigen::VectorXcd monodromy = Eigen::EigenSolver<Eigen::MatrixXd>(analyse.monodromy(p)).eigenvalues();
        REQUIRE(monodromy.size() == 3);
        check_contains(monodromy, expected, 1e-6);
        const FloquetResult r = analyse(p);
        CHECK(r.route == "hill+monodromy");
        CHECK(r.stability == (c > 0 ? Stability::stable : Stability::unstable));
        CHECK(r.margin == Approx(std::max(1.0, std::exp(-0.5 * c * period))).epsilon(1e-6));
    }
}

TEST_CASE("Dahl superharmonic folds: every verdict confirmed by a perturbed time integration", "[stability]") {
    // examples/systems/dahl_superharmonic_fold.toml: the branch folds twice near w = 0.198; the
    // part between the folds is unstable.
    const StabilityRun run = stability_run("dahl_superharmonic_fold.toml", 20, 0.17, 0.23, false);
    HarmonicBalance& hb = *run.hb;
    const FrfResult& frf = run.frf;
    REQUIRE(frf.branch.status == ContinuationStatus::completed);
    REQUIRE(frf.stability);
    const BranchStability& b = *frf.stability;
    INFO(b.summary());
    CHECK(b.not_computed == 0);
    // The only uncertain verdicts are at located folds (where a multiplier is 1 by definition).
    // And every located fold is uncertain, saying why: a multiplier passes through 1 there (a
    // fold located at a corner of the HB branch had a one-sided monodromy of 1.1 while time
    // integration from the orbit decayed: it was called unstable).
    for (std::size_t k = 0; k < frf.points.size(); ++k) {
        if (b.points[k].stability == Stability::uncertain) CHECK(frf.points[k].kind == PointKind::fold);
        if (frf.points[k].kind == PointKind::fold) {
            CHECK(b.points[k].stability == Stability::uncertain);
            CHECK_FALSE(b.points[k].message.empty());  // the fold, or Hill and the monodromy disagreeing
        }
    }
    CHECK(b.sorting_disagreements == 0);
    CHECK(b.unstable_points >= 3);
    REQUIRE(b.unstable.size() == 1);
    // Two folds, bracketing the unstable interval, where the branch's own dw/ds changes sign.
    std::vector<double> folds, marked;
    for (const auto& f : b.bifurcations) {
        CHECK(f.kind == "fold");
        folds.push_back(f.omega);
    }
    for (const SolutionPoint& p : frf.points)
        if (p.kind == PointKind::fold) marked.push_back(p.omega);
    REQUIRE(folds.size() == 2);
    REQUIRE(marked.size() == 2);
    CHECK(std::max(folds[0], folds[1]) >= b.unstable[0].omega_from);
    CHECK(std::min(folds[0], folds[1]) <= b.unstable[0].omega_to);
    for (std::size_t k = 0; k < 2; ++k) CHECK(std::abs(folds[k] - marked[k]) < 2e-4);
    // The located folds: the upper one is smooth, dR/dX is singular there to rounding and Hill
    // has a multiplier 1; the lower one is a corner of the HB branch (a sample's |v| changes
    // sign there): w is extremal against its neighbours on the branch.
    StabilityOptions hill_only;
    hill_only.method = StabilityMethod::hill;
    StabilityAnalyser hill(hb, hill_only);
    int smooth = 0;
    for (std::size_t k = 1; k + 1 < frf.points.size(); ++k) {
        const SolutionPoint& p = frf.points[k];
        if (p.kind != PointKind::fold) continue;
        const double before = p.omega - frf.points[k - 1].omega, after = p.omega - frf.points[k + 1].omega;
        CHECK(before * after > 0.0);
        Eigen::VectorXd r, r_omega;
        Eigen::MatrixXd J;
        hb.evaluate(p.x, p.omega, r, &J, &r_omega);
        const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
        if (sv(sv.size() - 1) < 1e-12 * sv(0)) {
            ++smooth;
            const Eigen::VectorXcd mu = hill(p).multipliers;
            CHECK((mu.array() - 1.0).abs().minCoeff() < 1e-8);
        }
    }
    CHECK(smooth == 1);
    // Every verdict against time integration: the monodromy's leading perturbation grows (unstable)
    // or decays (stable) as |mu|^n.
    StabilityAnalyser analyse(hb);
    int grown = 0, decayed = 0;
    for (std::size_t k = 0; k < frf.points.size(); ++k) {
        const SolutionPoint& p = frf.points[k];
        if (b.points[k].stability == Stability::uncertain) continue;  // a fold (above)
        const Growth g = perturbed_growth(hb.system(), p.omega, analyse.start_state(p), analyse.monodromy(p));
        INFO("w = " << p.omega << ", verdict " << to_string(b.points[k].stability) << ", margin " << b.points[k].margin
                    << ": over " << g.periods << " periods measured " << g.measured << ", predicted " << g.predicted);
        if (b.points[k].stability == Stability::unstable) {
            CHECK(g.measured > 1.0);
            ++grown;
        } else {
            CHECK(g.measured < 1.0);
            ++decayed;
        }
        // Away from the folds the HB orbit's monodromy predicts the perturbation vector itself.
        // Near a fold (within 2e-4 in w) the branch is nearly vertical, so the truncation's shift
        // of the fold (2e-5 in w between H = 20 and H = 40) moves the orbit at a given w far in
        // state space; the verdicts above still hold there.
        bool near_fold = false;
        for (double f : folds) near_fold = near_fold || std::abs(p.omega - f) < 2e-4;
        if (!near_fold && std::abs(b.points[k].margin - 1.0) > 0.1) CHECK(g.mismatch < 0.15);
    }
    CHECK(grown == b.unstable_points);
    CHECK(decayed == b.stable);
}

TEST_CASE("Jenkins: the exact route's verdicts confirmed by a perturbed time integration", "[stability][exact]") {
    // A negative spring held by a Jenkins contact (stable in full stick, unstable in stick-slip),
    // and the absorber at wb = 31.62, fe = 1 whose H = 10 branch shows fold pairs (HB artefacts:
    // the exact orbits there are stable).
    const System negative =
        io::read_system_config(source + "/examples/systems/jenkins_negative_stiffness.toml").system;
    AbsorberParameters ap;
    ap.contact_stiffness_ratio = 31.62;
    ap.excitation = 1.0;
    const System absorber = friction_absorber(ap, FrictionLaw::jenkins);
    struct Case {
        const System* system;
        double wmin, wmax;
    };
    int unstable = 0, stable = 0;
    for (const Case& c : {Case{&negative, 0.3, 2.0}, Case{&absorber, 1.18, 1.3}}) {
        FrfSettings settings;
        settings.harmonic_balance = {10, 0};
        settings.continuation.omega_start = c.wmin;
        settings.continuation.omega_end = c.wmax;
        settings.stability = true;
        HarmonicBalance hb(*c.system, settings.harmonic_balance);
        const FrfResult frf = compute_frf(hb, settings);
        REQUIRE(frf.stability);
        INFO(frf.stability->summary());
        // Close to the capped resonance at w = 1.17, HB at H = 10 is 30 % off the exact orbit: those
        // few points are uncertain (the exact orbit is not recognisably the HB one), never guessed.
        CHECK(frf.stability->uncertain <= 3);
        StabilityAnalyser analyse(hb);
        const int n = c.system->dofs(), d = 2 * n + 1;
        for (std::size_t k = 0; k < frf.points.size(); k += 3) {
            const SolutionPoint& p = frf.points[k];
            const FloquetResult& r = frf.stability->points[k];
            if (r.stability == Stability::uncertain) {
                CHECK_THAT(r.message, Catch::Contains("differs"));
                continue;
            }
            // The exact orbit and its exact monodromy over (y, y', slider).
            const ExactOrbit orbit = exact_periodic_orbit(*c.system, p.omega, analyse.start_state(p));
            REQUIRE(orbit.converged);
            const ExactFlow exact = exact_flow(*c.system, p.omega, orbit.state);
            REQUIRE(exact.ok);
            if (std::abs(orbit.max_multiplier - 1.0) < 1e-3) continue;  // neutral (undamped stick): no decay
            const Growth g = perturbed_growth(*c.system, p.omega, orbit.state, exact.monodromy.topLeftCorner(d, d));
            INFO("w = " << p.omega << ", verdict " << to_string(r.stability) << ", margin " << r.margin << ": over "
                        << g.periods << " periods measured " << g.measured << ", predicted " << g.predicted);
            if (r.stability == Stability::unstable) {
                CHECK(g.measured > 1.5);
                ++unstable;
            } else {
                CHECK(g.measured < 0.75);
                ++stable;
            }
            CHECK(g.mismatch < 0.05);
        }
    }
    CHECK(unstable >= 5);
    CHECK(stable >= 10);
}

namespace {

/// Law unilateral's time integrator (velocity Verlet with the contacts' complementarity problem
/// every step) over `periods` periods of `samples` steps from `state` ([y, y'] of every DOF):
/// the state after them.
Eigen::VectorXd rigid_flow(const System& s, double omega, const Eigen::VectorXd& state, int periods, int samples) {
    // The integrator's state after `periods` periods is the start of the one it records, which
    // it integrates once their Poincare change is within the (here loose) steady tolerance.
    TimeIntegrationOptions o;
    o.samples_per_period = samples;
    o.min_periods = o.max_periods = periods;
    o.steady_tolerance = TimeIntegrationOptions::largest_steady_tolerance;
    const PeriodicResponse r = integrate_steady_state(s, omega, o, &state);
    REQUIRE(r.periods == periods + 1);
    return r.state.head(2 * s.dofs());
}

/// The rate per period at which a perturbation of the orbit from `start` grows or decays under
/// the time integrator: two integrations, from start and from start + delta r (r a fixed
/// pseudo-random direction on the DOFs with mass, delta 1e-8 of the state's size), their
/// difference d_k after k periods on the DOFs with mass (velocities / omega: the massless nodes'
/// velocities in the integrator's state are differences over one step); after `settle` periods,
/// over the `periods` that follow: (|d_settle+periods| / |d_settle|)^(1 / periods).
double integrator_rate(const System& s, double omega, const Eigen::VectorXd& start, int settle, int periods,
                       int samples) {
    const int n = s.dofs();
    const Eigen::VectorXd mass = Eigen::MatrixXd(s.mass).diagonal();
    Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * n);
    for (int i = 0; i < n; ++i) {
        if (mass(i) == 0.0) continue;
        r(i) = std::sin(1.0 + 2.3 * i);
        r(n + i) = omega * std::cos(0.7 + 1.9 * i);
    }
    const double delta = 1e-8 * std::max(1.0, start.head(n).cwiseAbs().maxCoeff());
    Eigen::VectorXd a = start, b = start + delta * r.normalized();
    auto gap = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {  // on the DOFs with mass
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            if (mass(i) != 0.0) sum += std::pow(x(i) - y(i), 2) + std::pow((x(n + i) - y(n + i)) / omega, 2);
        return std::sqrt(sum);
    };
    a = rigid_flow(s, omega, a, settle, samples);
    b = rigid_flow(s, omega, b, settle, samples);
    const double first = gap(a, b);
    a = rigid_flow(s, omega, a, periods, samples);
    b = rigid_flow(s, omega, b, periods, samples);
    return std::pow(gap(a, b) / first, 1.0 / periods);
}

}  // namespace

TEST_CASE("law unilateral: the exact route's verdicts confirmed by a perturbed time integration", "[stability][exact]") {
    // liftoff3_rigid.toml between w = 2.1 and 2.7: stick-slip with lift-off, stable and unstable
    // orbits (harmonic balance at H = 10, its points polished by the rigid-contact exact solver,
    // whose exact monodromy gives the verdicts). Each verdict's largest multiplier against the
    // rate at which the time integrator (1024 steps a period, independent of the event solver)
    // amplifies a perturbation of the same orbit, at every twelfth point.
    const StabilityRun run = stability_run("liftoff3_rigid.toml", 10, 2.1, 2.7, true);
    const io::SystemConfig& config = run.config;
    HarmonicBalance& hb = *run.hb;
    const FrfResult& frf = run.frf;
    REQUIRE(frf.polish);
    REQUIRE(frf.stability);
    INFO(frf.stability->summary());
    CHECK(frf.stability->uncertain == 0);
    CHECK(frf.stability->not_computed == 0);
    CHECK(frf.stability->unstable_points >= 10);
    CHECK(frf.stability->stable >= 10);
    StabilityAnalyser analyse(hb);
    int unstable = 0, stable = 0;
    for (std::size_t k = 0; k < frf.points.size(); k += 12) {
        const SolutionPoint& p = frf.points[k];
        const FloquetResult& r = frf.stability->points[k];
        REQUIRE(r.route == "exact");
        const ExactOrbit orbit = rigid_periodic_orbit(config.system, p.omega, analyse.start_state(p));
        REQUIRE(orbit.converged);
        CHECK(std::abs(orbit.max_multiplier - r.margin) <= 1e-6 * r.margin);
        // long enough for the largest multiplier to dominate and to move the gap a hundredfold
        const int periods = std::clamp(static_cast<int>(std::ceil(std::log(100.0) / std::abs(std::log(r.margin)))), 4, 80);
        const double rate = integrator_rate(config.system, p.omega, orbit.state, 8, periods, 1024);
        INFO("w = " << p.omega << ", verdict " << to_string(r.stability) << ", largest |mu| " << r.margin
                    << ", the integrator's rate " << rate << " over " << periods << " periods");
        CHECK(std::abs(rate - r.margin) <= 0.025 * r.margin);
        CHECK((rate > 1.0) == (r.stability == Stability::unstable));
        ++(r.stability == Stability::unstable ? unstable : stable);
    }
    CHECK(unstable >= 3);
    CHECK(stable >= 3);
}

TEST_CASE("law unilateral in 3D: the exact orbits' largest multipliers are the rates at which the time integrator "
          "amplifies perturbations",
          "[stability][exact]") {
    // The 3D chain (three masses on rigid contacts with Coulomb friction, forced along both
    // tangential directions: the nodes slip along curved paths) at three frequencies: each exact
    // orbit's largest Floquet multiplier (from its monodromy or, where the flow's derivative is
    // not the period map's, Arnoldi on central differences) against the rate per period at which
    // law unilateral's time integrator (independent of the event solver; first order where a slip
    // direction turns) amplifies a perturbation of that orbit.
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    for (double omega : {0.6, 1.6, 2.5}) {
        TimeIntegrationOptions o;
        o.samples_per_period = 512;
        const PeriodicResponse settled = integrate_steady_state(system, omega, o);
        REQUIRE(settled.converged);
        const ExactOrbit orbit = rigid_periodic_orbit(system, omega, settled.state);
        INFO("w = " << omega << ": " << orbit.message);
        REQUIRE(orbit.converged);
        REQUIRE(std::isfinite(orbit.max_multiplier));
        const double mu = orbit.max_multiplier;
        // long enough for the largest multiplier to dominate and to move the gap a hundredfold
        const double needed = std::log(100.0) / std::max(std::abs(std::log(mu)), 1e-3);
        const int periods = static_cast<int>(std::clamp(std::ceil(needed), 4.0, 80.0));
        const double rate = integrator_rate(system, omega, orbit.state, 8, periods, 2048);
        INFO("largest |mu| " << mu << ", the integrator's rate " << rate << " over " << periods << " periods");
        CHECK(std::abs(rate - mu) <= 0.01 * mu);
        if (std::abs(mu - 1.0) > 0.05) CHECK((rate > 1.0) == !orbit.stable);
    }
}

TEST_CASE("law unilateral without the polish: each point's exact orbit from its HB state, and a stop request ends "
          "the analysis at the point it answers before",
          "[stability][exact]") {
    const StabilityRun exact = stability_run("liftoff3_rigid.toml", 10, 2.1, 2.7, true);
    const FrfResult& polished = exact.frf;
    REQUIRE(polished.stability);
    // The HB branch alone (no polish): the analyser solves each point's exact orbit from the HB
    // state; at H = 10 those are the polished points' orbits, with their verdicts.
    const StabilityRun run = stability_run("liftoff3_rigid.toml", 10, 2.1, 2.7, false);
    HarmonicBalance& hb = *run.hb;
    const FrfResult& plain = run.frf;
    REQUIRE(plain.stability);
    // The polish adds the first lift-off (closed|lift-off near 2.1025), which the HB branch
    // has no point for: the other points pair up in order.
    std::vector<std::size_t> pairs;
    for (std::size_t k = 0; k < polished.points.size(); ++k)
        if (polished.points[k].kind != PointKind::transition || polished.points[k].boundary != Boundary::closed_lift_off)
            pairs.push_back(k);
    CHECK(polished.points.size() - pairs.size() == 1);
    REQUIRE(plain.points.size() == pairs.size());
    int same = 0;
    for (std::size_t k = 0; k < plain.points.size(); ++k) {
        const FloquetResult& a = plain.stability->points[k];
        const FloquetResult& b = polished.stability->points[pairs[k]];
        CHECK(plain.points[k].omega == Approx(polished.points[pairs[k]].omega).epsilon(1e-9));
        CHECK(a.route == "exact");
        if (a.stability == Stability::uncertain) continue;  // HB 25 % off the exact orbit there
        CHECK(a.stability == b.stability);
        CHECK(std::abs(a.margin - b.margin) <= 1e-6 * b.margin);
        ++same;
    }
    CHECK(same >= static_cast<int>(plain.points.size()) - 3);
    // A stop answering from its 40th question on (asked before every point and after every
    // period the exact solver flows): the points before the one it answered in are the whole
    // run's, that one and the rest not computed, with the reason.
    int asked = 0;
    StabilityOptions options;
    options.stop = [&asked]() { return ++asked >= 40 ? std::string("the test's stop") : std::string(); };
    const BranchStability stopped = analyse_branch_stability(hb, plain.points, options);
    CHECK(stopped.stopped == "the test's stop");
    REQUIRE(stopped.points.size() == plain.points.size());
    std::size_t first = 0;
    while (first < stopped.points.size() && stopped.points[first].stability != Stability::not_computed) ++first;
    CHECK(first >= 1);
    CHECK(first < 20);
    for (std::size_t k = 0; k < stopped.points.size(); ++k) {
        INFO("point " << k);
        if (k < first) {
            CHECK(stopped.points[k].stability == plain.stability->points[k].stability);
            CHECK(stopped.points[k].margin == plain.stability->points[k].margin);
        } else {
            CHECK(stopped.points[k].stability == Stability::not_computed);
            CHECK(stopped.points[k].message == "stopped: the test's stop");
        }
    }
    CHECK(stopped.not_computed == static_cast<int>(plain.points.size() - first));
}

TEST_CASE("Hill's sorted selection agrees with the monodromy on the shipped smooth cases", "[stability]") {
    // The paper's absorber with each smooth law, and the Dahl fold example: wherever both routes
    // are confident (|largest |mu| - 1| > 1e-3; fold points, where a multiplier is 1, not
    // counted) their verdicts agree at H = 20.
    struct Case {
        System system;
        double wmin, wmax;
    };
    const AbsorberParameters ap;
    std::vector<Case> cases = {{friction_absorber(ap, FrictionLaw::dahl), 0.5, 1.6},
                               {friction_absorber(ap, FrictionLaw::lugre), 0.5, 1.6},
                               {friction_absorber(ap, FrictionLaw::coulomb_regularized), 0.5, 1.6},
                               {io::read_system_config(source + "/examples/systems/dahl_superharmonic_fold.toml").system,
                                0.17, 0.23}};
    int confident = 0;
    for (const Case& c : cases) {
        FrfSettings settings;
        settings.harmonic_balance = {20, 0};
        settings.continuation.omega_start = c.wmin;
        settings.continuation.omega_end = c.wmax;
        settings.continuation.max_step = 0.1;
        settings.stability = true;
        const FrfResult frf = compute_frf(c.system, settings);
        REQUIRE(frf.stability);
        INFO(to_string(c.system.contacts[0].law) << ": " << frf.stability->summary());
        CHECK(frf.stability->sorting_disagreements == 0);
        for (std::size_t k = 0; k < frf.points.size(); ++k)  // uncertain only at a fold corner
            if (frf.stability->points[k].stability == Stability::uncertain) CHECK(frf.points[k].kind == PointKind::fold);
        confident += frf.stability->both_confident;
    }
    CHECK(confident > 100);
}

TEST_CASE("Stability options and refusals", "[stability]") {
    StabilityOptions o;
    o.tolerance = -1;
    CHECK_THROWS_AS(o.validate(), InvalidInput);
    o = {};
    o.integration_tolerance = 1e-2;
    CHECK_THROWS_AS(o.validate(), InvalidInput);
    o = {};
    o.exact_threads = 3;
    CHECK_THROWS_WITH(o.validate(), Catch::Contains("stability exact_threads = 3 is out of range: allowed 0"));
    CHECK_THROWS_AS(parse_stability_method("sorted"), InvalidInput);
    CHECK(parse_stability_method("monodromy") == StabilityMethod::monodromy);
    // Mixed laws: no route covers both.
    System s = linear_dahl(0.1);
    Contact jenkins;
    jenkins.law = FrictionLaw::jenkins;
    jenkins.friction_limit = 0.1;
    jenkins.stiffness = 1.0;
    s.contacts.push_back(jenkins);
    CHECK_THAT(stability_refusal(s), Catch::Contains("mix"));
    CHECK(stability_refusal(linear_dahl(0.1)).empty());
    CHECK_THROWS_AS(linearize(jenkins, 0.0, 0.1, 0.0), InvalidInput);
}

TEST_CASE("hbf frf --stability: the columns and unstable intervals and bifurcations and bad input", "[stability][cli]") {
    test::TempDir dir;
    const std::string config = source + "/examples/systems/dahl_superharmonic_fold.toml";
    const auto csv = dir.path / "frf.csv", json = dir.path / "frf.json", png = dir.path / "frf.png";
    const test::Result r = test::run_hbf("frf --config '" + config + "' --harmonics 20 --stability on --out '" +
                                             csv.string() + "' --summary '" + json.string() + "' --plot '" +
                                             png.string() + "'",
                                         dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.err, Catch::Contains("uncertain"));  // said, with the reason
    const auto rows = test::parse_csv(test::slurp(csv));
    const auto& header = rows.front();
    const auto at = [&](const std::string& name) {
        return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
    };
    REQUIRE(at("stability_margin") < header.size());
    int unstable = 0;
    double w_min = 1e9, w_max = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const std::string verdict = rows[k][at("stable")];
        const double margin = std::stod(rows[k][at("stability_margin")]);
        if (verdict == "uncertain") {  // the corner fold, where the routes disagree
            CHECK(rows[k][at("point")] == "fold");
            continue;
        }
        REQUIRE((verdict == "true" || verdict == "false"));
        CHECK((verdict == "false") == (margin > 1.0 + 1e-6));
        if (verdict == "false") {
            ++unstable;
            w_min = std::min(w_min, std::stod(rows[k][0]));
            w_max = std::max(w_max, std::stod(rows[k][0]));
        }
    }
    CHECK(unstable >= 3);
    const nlohmann::json summary = nlohmann::json::parse(test::slurp(json));
    const nlohmann::json stability = summary.at("stability");
    CHECK(stability.at("unstable").get<int>() == unstable);
    REQUIRE(stability.at("unstable_intervals").size() == 1);
    CHECK(stability.at("unstable_intervals")[0].at("w_from").get<double>() == Approx(w_max).epsilon(1e-12));
    CHECK(stability.at("bifurcations").size() == 2);
    CHECK(std::filesystem::file_size(png) > 1000);
    // Bad input: nothing written.
    test::check_bad_input("frf --stability sometimes", {"--stability", "off, on, hill, monodromy, both"}, dir);
    const auto mixed = dir.path / "mixed.toml";
    test::write_file(mixed, test::slurp(config) +
                                "\n[[contact]]\ndof = 1\nlaw = \"jenkins\"\nfriction_limit = 0.1\nstiffness = 1.0\n");
    test::check_bad_input("frf --config '" + mixed.string() + "' --stability on", {"--stability on", "mix"}, dir);
}


TEST_CASE("Bifurcations from the multipliers: fold and branch point and period doubling and Neimark-Sacker",
          "[stability]") {
    // Constructed multipliers along one branch (w = 1, 2, ...): each kind crosses the unit
    // circle once, and the crossing w is interpolated linearly in the modulus.
    using C = std::complex<double>;
    const std::vector<std::vector<C>> mu = {
        {0.5, C(0.95 * std::cos(1.0), 0.95 * std::sin(1.0)), C(0.95 * std::cos(1.0), -0.95 * std::sin(1.0))},  // w = 1
        {0.9, C(1.05 * std::cos(1.0), 1.05 * std::sin(1.0)), C(1.05 * std::cos(1.0), -1.05 * std::sin(1.0))},  // w = 2: NS
        {1.3, C(1.05 * std::cos(1.0), 1.05 * std::sin(1.0)), C(1.05 * std::cos(1.0), -1.05 * std::sin(1.0))},  // w = 3: fold
        {1.3, -0.9, 0.1},   // w = 4: uncertain (skipped)
        {1.3, -1.2, 0.1},   // w = 5: period doubling between 3 and 5 (the pair left too: NS)
        {0.8, -1.2, 0.1},   // w = 6: back through +1 without a turn
    };
    std::vector<SolutionPoint> points;
    BranchStability b;
    for (std::size_t k = 0; k < mu.size(); ++k) {
        SolutionPoint p;
        p.omega = double(k + 1);
        if (k == 2) p.kind = PointKind::fold;  // the branch turns at w = 3, not at w = 6
        points.push_back(p);
        FloquetResult r;
        r.multipliers = Eigen::Map<const Eigen::VectorXcd>(mu[k].data(), 3);
        r.margin = r.multipliers.cwiseAbs().maxCoeff();
        r.stability = k == 3 ? Stability::uncertain : r.margin > 1 + 1e-6 ? Stability::unstable : Stability::stable;
        b.points.push_back(r);
    }
    find_bifurcations(points, 1e-6, b);
    REQUIRE(b.bifurcations.size() == 5);
    CHECK(b.bifurcations[0].kind == "neimark-sacker");
    CHECK(b.bifurcations[0].omega == Approx(1.5));
    CHECK(b.bifurcations[1].kind == "fold");
    CHECK(b.bifurcations[1].omega == Approx(2.25));  // 0.9 -> 1.3
    CHECK(b.bifurcations[2].kind == "period-doubling");
    CHECK(b.bifurcations[2].after == 2);             // from w = 3 to 5, past the uncertain w = 4
    CHECK(b.bifurcations[2].at == 4);
    CHECK(b.bifurcations[2].omega == Approx(3.0 + 2.0 * (1.0 - 0.0) / 1.2));
    CHECK(b.bifurcations[3].kind == "neimark-sacker");
    CHECK(b.bifurcations[4].kind == "branch-point");
    CHECK(b.bifurcations[4].omega == Approx(5.0 + 0.3 / 0.5));
    REQUIRE(b.unstable.size() == 2);  // w = 2..3, then 5..6 (the uncertain w = 4 breaks the run)
    CHECK(b.unstable[0].omega_from == 2.0);
    CHECK(b.unstable[0].omega_to == 3.0);
    CHECK(b.unstable[1].omega_from == 5.0);
    CHECK(b.unstable[1].omega_to == 6.0);
    // On the points: the first point past each crossing that is not a fold already.
    mark_bifurcations(b, points);
    CHECK(points[1].kind == PointKind::neimark_sacker);
    CHECK(points[2].kind == PointKind::fold);
    CHECK(points[4].kind == PointKind::period_doubling);  // the first of the two crossings there
    CHECK(points[5].kind == PointKind::branch_point);
    b.points.pop_back();
    CHECK_THROWS_AS(find_bifurcations(points, 1e-6, b), InvalidInput);
}

TEST_CASE("An exact orbit whose multipliers are unknown is neither stable nor unstable", "[stability][exact]") {
    // The exact solver leaves max_multiplier NaN (no multipliers) where a converged orbit's could
    // not be computed (law unilateral's central differences, where a perturbed period fails):
    // every reader takes that as unknown, never as a verdict (NaN compares false either way).
    const double NaN = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> margins = {0.9, NaN, 1.5};
    const System s = linear_dahl(0.1);
    REQUIRE(s.damping.nonZeros() > 0);  // judge_sweep's energy balance (undamped only) stays out
    HarmonicBalance hb(s, {5, 0});
    std::vector<SolutionPoint> points(margins.size());
    std::vector<ExactPoint> polish(margins.size());
    std::vector<PeriodicResponse> responses(margins.size());
    for (std::size_t k = 0; k < margins.size(); ++k) {
        points[k].omega = responses[k].omega = 1.0 + 0.1 * static_cast<double>(k);
        points[k].x = Eigen::VectorXd::Zero(hb.unknowns());
        polish[k].status = PolishStatus::exact;
        polish[k].max_multiplier = responses[k].max_multiplier = margins[k];
        polish[k].stable = margins[k] <= 1.0 + 1e-6;
        if (std::isfinite(margins[k])) polish[k].multipliers = Eigen::VectorXcd::Constant(1, margins[k]);
        polish[k].message = "the orbit's message " + std::to_string(k);
        responses[k].converged = true;
        responses[k].message = "Newton on the period map converged" +
                               std::string(std::isfinite(margins[k]) ? "" : "; the multipliers are unknown (why)");
    }
    // the FRF's verdicts from its polish
    const BranchStability b = analyse_branch_stability(hb, points, StabilityOptions{}, &polish);
    REQUIRE(b.points.size() == margins.size());
    CHECK(b.points[0].stability == Stability::stable);
    CHECK(b.points[1].stability == Stability::uncertain);
    CHECK_THAT(b.points[1].message, Catch::Contains("could not be computed") && Catch::Contains("the orbit's message 1"));
    CHECK(b.points[2].stability == Stability::unstable);
    CHECK(b.stable == 1);
    CHECK(b.uncertain == 1);
    CHECK(b.unstable_points == 1);
    // the FRF's table (the polish alone): stable = uncertain and no margin where unknown
    std::ostringstream csv;
    io::write_frf_csv(csv, points, std::vector<PointMetrics>(margins.size()), {}, polish);
    const auto rows = test::parse_csv(csv.str());
    REQUIRE(rows.size() == margins.size() + 1);
    auto column = [&](const std::string& name) {
        const auto at = std::find(rows[0].begin(), rows[0].end(), name);
        REQUIRE(at != rows[0].end());
        return static_cast<std::size_t>(at - rows[0].begin());
    };
    const std::size_t stable = column("stable"), margin = column("stability_margin");
    CHECK(rows[1][stable] == "true");
    CHECK(rows[2][stable] == "uncertain");
    CHECK(rows[3][stable] == "false");
    CHECK(std::stod(rows[1][margin]) == 0.9);
    CHECK(rows[2][margin].empty());
    CHECK(std::stod(rows[3][margin]) == 1.5);
    // the FRF's verdict without --stability: the polish's unknown verdicts are noted, with the
    // first one's w and message; with --stability its own note says it instead
    FrfResult frf = polished_frf(points, polish);
    frf.polish->stability_unknown = 1;
    const Verdict polished = judged_quietly(frf);
    REQUIRE(polished.notes.size() == 1);
    CHECK_THAT(polished.notes[0], Catch::Contains("1 exact point(s) of unknown stability") &&
                                      Catch::Contains("the first at w = 1.1: the orbit's message 1"));
    frf.stability = b;
    const Verdict analysed = judged_quietly(frf);
    REQUIRE(analysed.notes.size() == 1);
    CHECK_THAT(analysed.notes[0], Catch::Contains("stable = uncertain (or empty) have no verdict"));
    // hbf timeint --method exact's verdict: a note for each kind, no warning, no error
    const ExactOptions solver;  // the options the sweep ran with
    const Verdict v = judge_sweep(s, responses, TimeIntegrationOptions{}, &solver);
    CHECK(v.errors.empty());
    CHECK(v.warnings.empty());
    REQUIRE(v.notes.size() == 2);
    CHECK_THAT(v.notes[0], Catch::Contains("1 of 3 exact orbits have an unknown stability") && Catch::Contains("the first at w = 1.1: the multipliers are unknown (why)"));
    CHECK_THAT(v.notes[1], Catch::Contains("1 of 3 exact orbits are unstable") && Catch::Contains("the largest, 1.5,"));
    // time integration's responses have no multipliers at all: nothing said
    CHECK(judge_sweep(s, responses, TimeIntegrationOptions{}, nullptr).notes.empty());
    // an exact orbit Newton left at the flow's rounding (its residual above the tolerance, the
    // solver's floor below 1e-9) is converged, and its accuracy is said
    responses[0].poincare_change = 3e-10;
    responses[2].poincare_change = 1e-13;  // within the tolerance 1e-12: not counted
    const Verdict rounded = judge_sweep(s, responses, TimeIntegrationOptions{}, &solver);
    REQUIRE(rounded.notes.size() == 3);
    CHECK_THAT(rounded.notes[1], Catch::Contains("1 of 3 exact orbits converged to the flow's rounding") &&
                                     Catch::Contains("up to 3e-10 (at w = 1)"));
    // judged against the tolerance and stability margin the sweep ran with (--steady-tol 1e-9:
    // a residual of 3e-10 is within it; a margin of 0.6 makes 1.5 stable), not the defaults
    ExactOptions loose;
    loose.tolerance = 1e-9;
    loose.stability_tolerance = 0.6;
    const Verdict judged = judge_sweep(s, responses, TimeIntegrationOptions{}, &loose);
    REQUIRE(judged.notes.size() == 1);
    CHECK_THAT(judged.notes[0], Catch::Contains("1 of 3 exact orbits have an unknown stability"));
}

TEST_CASE("An exact orbit whose largest multiplier, from central differences, is within their accuracy of 1 is "
          "uncertain, not unstable", "[stability][exact]") {
    // The block example's offset orbit at 17,900 rad/s: 1.0017 by Arnoldi on differences, an orbit
    // the integrator settles on (a neutral direction); its symmetric orbit: 1.0064, unstable. The
    // same 1.0017 from the flow's own derivative (accuracy 0) is unstable.
    const std::vector<double> margins = {1.0017, 1.0064, 1.0017};
    const std::vector<double> accuracy = {difference_multiplier_accuracy, difference_multiplier_accuracy, 0.0};
    const System s = linear_dahl(0.1);
    HarmonicBalance hb(s, {5, 0});
    std::vector<SolutionPoint> points(margins.size());
    std::vector<ExactPoint> polish(margins.size());
    std::vector<PeriodicResponse> responses(margins.size());
    for (std::size_t k = 0; k < margins.size(); ++k) {
        ExactOrbit orbit;
        orbit.converged = true;
        orbit.max_multiplier = margins[k];
        orbit.stable = margins[k] <= 1.0 + ExactOptions{}.stability_tolerance;
        orbit.multiplier_accuracy = accuracy[k];
        points[k].omega = responses[k].omega = 1.0 + 0.1 * static_cast<double>(k);
        points[k].x = Eigen::VectorXd::Zero(hb.unknowns());
        polish[k].status = PolishStatus::exact;
        polish[k].max_multiplier = responses[k].max_multiplier = margins[k];
        polish[k].stable = orbit.stable;
        polish[k].stability_unresolved = orbit.stability_unresolved();
        polish[k].multipliers = Eigen::VectorXcd::Constant(1, margins[k]);
        responses[k].multiplier_accuracy = accuracy[k];
        responses[k].converged = true;
    }
    REQUIRE(polish[0].stability_unresolved);
    REQUIRE(!polish[1].stability_unresolved);
    REQUIRE(!polish[2].stability_unresolved);
    const BranchStability b = analyse_branch_stability(hb, points, StabilityOptions{}, &polish);
    REQUIRE(b.points.size() == margins.size());
    CHECK(b.points[0].stability == Stability::uncertain);
    CHECK_THAT(b.points[0].message, Catch::Contains("accuracy"));
    CHECK(b.points[1].stability == Stability::unstable);
    CHECK(b.points[2].stability == Stability::unstable);
    // the FRF's table (the polish alone)
    std::ostringstream csv;
    io::write_frf_csv(csv, points, std::vector<PointMetrics>(margins.size()), {}, polish);
    const auto rows = test::parse_csv(csv.str());
    REQUIRE(rows.size() == margins.size() + 1);
    const auto at = std::find(rows[0].begin(), rows[0].end(), std::string("stable"));
    REQUIRE(at != rows[0].end());
    const auto stable = static_cast<std::size_t>(at - rows[0].begin());
    CHECK(rows[1][stable] == "uncertain");
    CHECK(rows[2][stable] == "false");
    CHECK(rows[3][stable] == "false");
    // the FRF's verdict without --stability: a note with the first such point
    FrfResult frf = polished_frf(points, polish);
    frf.polish->stability_unresolved = 1;
    frf.polish->unstable = 2;
    const Verdict polished = judged_quietly(frf);
    REQUIRE(polished.notes.size() == 1);
    CHECK_THAT(polished.notes[0], Catch::Contains("1 exact point(s) of uncertain stability (the first at w = 1, "
                                                  "largest multiplier 1.0017)") &&
                                      Catch::Contains("stable = uncertain"));
    // hbf timeint --method exact's verdict: the uncertain one apart from the two unstable ones
    const ExactOptions solver;
    const Verdict v = judge_sweep(s, responses, TimeIntegrationOptions{}, &solver);
    CHECK(v.errors.empty());
    CHECK(v.warnings.empty());
    REQUIRE(v.notes.size() == 2);
    CHECK_THAT(v.notes[0], Catch::Contains("2 of 3 exact orbits are unstable") && Catch::Contains("the largest, 1.0064,"));
    CHECK_THAT(v.notes[1], Catch::Contains("1 of 3 exact orbits have an uncertain stability (the first at w = 1)"));
}
