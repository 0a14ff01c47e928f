// Continuation and harmonic-balance solutions against independent references: exact linear
// FRFs, the energy balance, the pre-sliding closed forms, convergence in H, and folds.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hbf/analytic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/linear_limits.hpp"
#include "hbf/post_processing.hpp"
#include "support.hpp"
#include "../src/numerics/golden_section.hpp"

using namespace hbf;

namespace {
/// The last point of a short continuation from 0.95 omega to `omega` (lands exactly on it).
SolutionPoint solve_by_continuation(HarmonicBalance& hb, double omega) {
    ContinuationOptions o;
    o.omega_start = 0.95 * omega;
    o.omega_end = omega;
    const BranchResult b = continue_branch(hb, o);
    REQUIRE(b.status == ContinuationStatus::completed);
    REQUIRE(b.points.back().omega == omega);
    return b.points.back();
}

/// Sign of det(dR/dX) at a point, from the LU factors (the determinant itself under- or
/// overflows at these sizes).
int jacobian_determinant_sign(HarmonicBalance& hb, const SolutionPoint& point) {
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    hb.evaluate(point.x, point.omega, r, &J);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(J);
    int sign = static_cast<int>(lu.permutationP().determinant());
    for (int i = 0; i < J.rows(); ++i) sign *= lu.matrixLU()(i, i) < 0.0 ? -1 : 1;
    return sign;
}
}  // namespace

TEST_CASE("Linear limit: LuGre with a huge friction limit follows the exact linear FRF", "[continuation]") {
    AbsorberParameters p;
    p.friction_coefficient = 1e9;  // the bristle never slides: f = sigma0 q + sigma1 q'
    p.contact_damping_ratio = 0.05;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::lugre), HarmonicBalanceOptions{3, 0});
    ContinuationOptions o;
    const BranchResult b = continue_branch(hb, o);
    REQUIRE(b.status == ContinuationStatus::completed);
    REQUIRE(b.points.size() > 5);
    for (const SolutionPoint& point : b.points) {
        const analytic::Response exact = analytic::contact_stick(p, point.omega, FrictionLaw::lugre);
        const Eigen::VectorXd y1 = hb.dofs(point.x, point.omega).col(0), y2 = hb.dofs(point.x, point.omega).col(1);
        // y = Re(Y e^{i theta}) = Re Y cos theta - Im Y sin theta.
        CHECK(std::abs(y1(1) - exact.y1.real()) < 1e-8 * std::abs(exact.y1));
        CHECK(std::abs(y1(2) + exact.y1.imag()) < 1e-8 * std::abs(exact.y1));
        CHECK(std::abs(y2(1) - exact.y2.real()) < 1e-8 * std::abs(exact.y2));
        CHECK(y1.tail(4).norm() < 1e-8 * std::abs(exact.y1));  // no higher harmonics
    }
    // Permanent stick: the bristle force sigma0 |z| = sigma0 |Q| (z = q) stays far below
    // 0.95 F_c, so every sample sticks, and the indicator's maximum is sigma0 |Q| / (0.95 F_c)
    // - 1 up to the AFT grid ((pi / N_t)^2 / 2 relative on the maximum of a sinusoid). The
    // indicator is about -1 + 1e-9, so indicator + 1 carries the rounding of numbers near 1
    // (a few 1e-16 absolute): 1e-15 absolute on top of 1e-8 relative.
    Analyser analyse(hb);
    const Contact& contact = hb.system().contacts[0];
    const double grid = 0.5 * std::pow(M_PI / hb.time_samples(), 2);
    for (const SolutionPoint& point : b.points) {
        const analytic::Response exact = analytic::contact_stick(p, point.omega, FrictionLaw::lugre);
        const PointMetrics m = analyse(point);
        CHECK(m.stick_fraction == 1.0);
        CHECK(m.regime == "stick");
        const double expected = contact.stiffness * std::abs(exact.y1 - exact.y2) / (stick_force_ratio * contact.friction_limit);
        CHECK(m.stick_indicator_max + 1.0 <= expected * (1.0 + 1e-8) + 1e-15);
        CHECK(m.stick_indicator_max + 1.0 >= expected * (1.0 - grid));
    }
}

TEST_CASE("Peaks: refined maxima of y1_max equal the exact linear resonance peaks", "[continuation]") {
    AbsorberParameters p;
    p.friction_coefficient = 1e9;  // linear: f = sigma0 q + sigma1 q'
    p.contact_damping_ratio = 0.05;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::lugre), HarmonicBalanceOptions{3, 0});
    const BranchResult b = continue_branch(hb, ContinuationOptions{});
    REQUIRE(b.status == ContinuationStatus::completed);
    // y_max of a pure sinusoid is |Y1| (the time grid alone would be off by up to 5e-6;
    // 1e-8 is the accuracy of the solution itself).
    Analyser analyse(hb);
    for (const SolutionPoint& point : b.points)
        CHECK(analyse(point).y_max[0] ==
              Approx(std::abs(analytic::contact_stick(p, point.omega, FrictionLaw::lugre).y1)).epsilon(1e-8));
    // Reference: the local maxima of the closed-form |Y1(w)|, from a fine scan polished by a
    // golden-section search on the closed form itself.
    auto exact = [&](double w) { return std::abs(analytic::contact_stick(p, w, FrictionLaw::lugre).y1); };
    std::vector<std::pair<double, double>> reference;
    const int n = 20000;
    for (int k = 1; k < n; ++k) {
        const double h = 1.1 / n, w = 0.5 + k * h;
        if (!(exact(w) > exact(w - h) && exact(w) >= exact(w + h))) continue;
        double lo = w - h, hi = w + h;
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        while (hi - lo > 1e-12) {
            const double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
            (exact(c) >= exact(d) ? hi : lo) = exact(c) >= exact(d) ? d : c;
        }
        reference.emplace_back(0.5 * (lo + hi), exact(0.5 * (lo + hi)));
    }
    REQUIRE(reference.size() == 2);  // the two resonances of the coupled system
    const auto peaks = find_peaks(hb, b, 0, CorrectorOptions{});
    REQUIRE(peaks.size() == reference.size());
    for (std::size_t k = 0; k < peaks.size(); ++k) {
        INFO("peak " << k << ": w = " << peaks[k].omega << " vs " << reference[k].first);
        CHECK(peaks[k].refined);
        CHECK(peaks[k].y_max == Approx(reference[k].second).epsilon(1e-8));
        // The maximum is flat: w is located to about sqrt(rounding) relative.
        CHECK(peaks[k].omega == Approx(reference[k].first).epsilon(1e-5));
    }
}

TEST_CASE("Linear limit: regularised Coulomb with huge eps is a viscous damper F_c / eps", "[continuation]") {
    AbsorberParameters p;
    const double damper = 0.03;
    p.regularization = 1e6;
    p.friction_coefficient = damper * p.regularization;  // f = F_c tanh(v / eps) = damper v (1 + O(1e-12))
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb_regularized), HarmonicBalanceOptions{3, 0});
    const BranchResult b = continue_branch(hb, ContinuationOptions{});
    REQUIRE(b.status == ContinuationStatus::completed);
    for (const SolutionPoint& point : b.points) {
        const Eigen::VectorXcd exact = test::absorber_with_linear_contact(p, point.omega, 0.0, damper);
        const Eigen::VectorXd y1 = hb.dofs(point.x, point.omega).col(0);
        CHECK(std::abs(std::complex<double>(y1(1), -y1(2)) - exact(0)) < 1e-8 * std::abs(exact(0)));
    }
}

TEST_CASE("Energy balance: input work per cycle equals friction dissipation at every point", "[continuation]") {
    for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre, FrictionLaw::coulomb_regularized}) {
        AbsorberParameters p;
        HarmonicBalance hb(friction_absorber(p, law), HarmonicBalanceOptions{8, 0});
        const BranchResult b = continue_branch(hb, ContinuationOptions{});
        REQUIRE(b.status == ContinuationStatus::completed);
        Analyser analyse(hb);
        for (const SolutionPoint& point : b.points) {
            const PointMetrics m = analyse(point);
            INFO(to_string(law) << " at w = " << point.omega);
            // The structure is undamped: all input work goes into the contact. The residual
            // tolerance 1e-9 (relative to the force scale) bounds the mismatch.
            CHECK(std::abs(m.input_energy - m.energy) <= 1e-6 * std::max(m.energy, 1e-3));
            CHECK(m.energy > 0.0);
        }
    }
}

TEST_CASE("Small excitation: Dahl and LuGre tend to the pre-sliding closed form in proportion to fe",
          "[continuation]") {
    for (FrictionLaw law : {FrictionLaw::dahl, FrictionLaw::lugre}) {
        for (double omega : {0.7, 1.3}) {
            double previous = 0.0;
            for (double fe : {1e-2, 1e-3, 1e-4}) {
                AbsorberParameters p;
                p.excitation = fe;
                HarmonicBalance hb(friction_absorber(p, law), HarmonicBalanceOptions{5, 0});
                const SolutionPoint s = solve_by_continuation(hb, omega);
                // Complex first harmonic: a first-order phase change moves |Y1| only at second
                // order (measured: Dahl's |Y1| deviates like fe^2), the complex value like fe.
                const Eigen::VectorXd y1 = hb.dofs(s.x, s.omega).col(0);
                const std::complex<double> first(y1(1), -y1(2));
                const std::complex<double> exact = analytic::contact_stick(p, omega, law).y1;
                const double difference = std::abs(first - exact) / std::abs(exact);
                INFO(to_string(law) << " w = " << omega << " fe = " << fe << " difference " << difference);
                if (previous > 0.0) {
                    CHECK(difference / previous > 0.05);  // falls like fe: ratio 0.1
                    CHECK(difference / previous < 0.2);
                }
                previous = difference;
            }
        }
    }
}

TEST_CASE("Convergence in H: the error against a fine-H solution falls with H", "[continuation]") {
    // LuGre absorber at w = 0.95 in stick-slip: the force has kinks (|v|), so the error falls
    // algebraically; require monotone decrease and at least a factor 4 from H = 4 to H = 16.
    AbsorberParameters p;
    auto y1_max = [&](int harmonics) {
        HarmonicBalance hb(friction_absorber(p, FrictionLaw::lugre), HarmonicBalanceOptions{harmonics, 0});
        const SolutionPoint s = solve_by_continuation(hb, 0.95);
        Analyser analyse(hb);
        return analyse(s).y_max[0];
    };
    const double reference = y1_max(64);
    std::vector<double> errors;
    for (int h : {2, 4, 8, 16}) errors.push_back(std::abs(y1_max(h) - reference) / reference);
    INFO("errors H = 2, 4, 8, 16: " << errors[0] << " " << errors[1] << " " << errors[2] << " " << errors[3]);
    for (std::size_t k = 1; k < errors.size(); ++k) CHECK(errors[k] < errors[k - 1]);
    CHECK(errors[3] < errors[1] / 4.0);
}

TEST_CASE("Sampling at given frequencies solves exactly there, near the branch", "[continuation]") {
    HarmonicBalance hb(friction_absorber(AbsorberParameters{}, FrictionLaw::lugre), HarmonicBalanceOptions{6, 0});
    const BranchResult b = continue_branch(hb, ContinuationOptions{});
    REQUIRE(b.status == ContinuationStatus::completed);
    const std::vector<double> at = {0.6, 0.95, 1.25};
    const auto samples = sample_branch(hb, b, at, CorrectorOptions{});
    REQUIRE(samples.size() == at.size());  // this branch does not fold: one solution each
    Analyser analyse(hb);
    for (std::size_t k = 0; k < at.size(); ++k) {
        CHECK(samples[k].omega == at[k]);
        CHECK(samples[k].kind == PointKind::sample);
        Eigen::VectorXd r;
        hb.evaluate(samples[k].x, samples[k].omega, r);
        CHECK(r.cwiseAbs().maxCoeff() <= 1e-9 * hb.force_scale());
        // Between the two neighbouring branch points in w, y1_max lies between theirs.
        for (std::size_t i = 0; i + 1 < b.points.size(); ++i) {
            if (b.points[i].omega <= at[k] && at[k] <= b.points[i + 1].omega) {
                const double ya = analyse(b.points[i]).y_max[0], yb = analyse(b.points[i + 1]).y_max[0];
                const double y = analyse(samples[k]).y_max[0];
                CHECK(y >= std::min(ya, yb) * (1 - 1e-9));
                CHECK(y <= std::max(ya, yb) * (1 + 1e-9));
            }
        }
    }
}

TEST_CASE("An unbounded resonance stops at the amplitude cap and restarts from wmax", "[continuation]") {
    AbsorberParameters p;
    p.excitation = 1.0;  // Coulomb-like friction cannot absorb the input at the resonances
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb_regularized), HarmonicBalanceOptions{5, 0});
    ContinuationOptions o;
    o.max_amplitude = 50.0;
    const BranchResult b = continue_branch(hb, o);
    CHECK(b.status == ContinuationStatus::amplitude_cap);
    CHECK_THAT(b.message, Catch::Contains("amplitude cap"));
    double cap_w = 0.0, last_w = 0.0;
    bool second = false;
    for (const SolutionPoint& point : b.points) {
        if (point.branch == 1) cap_w = point.omega;
        second = second || point.branch == 2;
        if (point.branch == 2) CHECK(point.omega > cap_w);
        if (point.branch == 2) last_w = point.omega;
    }
    REQUIRE(second);
    CHECK(last_w == o.omega_end);  // branch 2 is written in increasing w
}

namespace {
/// The band of the Dahl oscillator's superharmonic resonance whose branch folds twice
/// (test::dahl_oscillator(10, 1, 1.28, 0.003) at H = 20: the tests below).
ContinuationOptions folding_band() {
    ContinuationOptions o;
    o.omega_start = 0.5;
    o.omega_end = 0.6;
    return o;
}
}  // namespace

TEST_CASE("Fold location stops within one bracketing step when the run is asked to stop (an interrupt, the time "
          "limit), and says so",
          "[continuation][fold]") {
    // The Dahl oscillator's two folds (the test below); the stop request trips as the first
    // fold's location starts: it is not located, nor is the second, and the branch says why.
    HarmonicBalance hb(test::dahl_oscillator(10.0, 1.0, 1.28, 0.003), HarmonicBalanceOptions{20, 0});
    ContinuationOptions o = folding_band();
    bool locating = false;
    int started = 0;
    o.fold_progress = [&](int, int) {
        locating = true;
        ++started;
    };
    o.stop = [&]() { return locating ? std::string("the test's stop") : std::string(); };
    const BranchResult b = continue_branch(hb, o);
    CHECK(started == 1);
    CHECK(b.located_folds == 0);
    CHECK(b.unconfirmed_folds == 0);
    CHECK(b.status == ContinuationStatus::stopped);
    CHECK_THAT(b.message, Catch::Contains("2 fold(s) not located (stopped: the test's stop)"));
    CHECK(b.points.back().omega == o.omega_end);  // the branch itself is whole
}

TEST_CASE("A solver exception during a step ends the branch with status solver_error, the points before it kept",
          "[continuation][status]") {
    // The exception comes from the progress callback, called after each accepted point: the
    // same path as a contact model that throws inside the next step's correction.
    HarmonicBalance hb(test::dahl_oscillator(10.0, 1.0, 1.28, 0.003), HarmonicBalanceOptions{20, 0});
    ContinuationOptions o = folding_band();
    o.locate_folds = false;
    const BranchResult whole = continue_branch(hb, o);
    REQUIRE(whole.status == ContinuationStatus::completed);
    REQUIRE(whole.points.size() > 12);
    o.progress = [](double, int points) {
        if (points == 12) throw std::runtime_error("the model could not evaluate the point");
    };
    const BranchResult b = continue_branch(hb, o);
    CHECK(b.status == ContinuationStatus::solver_error);
    CHECK(to_string(b.status) == "solver_error");
    REQUIRE(b.points.size() == 12);
    CHECK_THAT(b.message, Catch::Contains("the solver failed on the step from w = ") &&
                              Catch::Contains("the model could not evaluate the point"));
    // The points kept are the branch's own: those of the uninterrupted run.
    for (std::size_t k = 0; k < b.points.size(); ++k) {
        CHECK(b.points[k].omega == Approx(whole.points[k].omega).epsilon(1e-12));
        CHECK((b.points[k].x - whole.points[k].x).cwiseAbs().maxCoeff() <= 1e-12 * whole.points[k].x.norm());
    }
    CHECK(b.coverage < whole.coverage);
    // Bad input is not a solver failure: it propagates.
    o.progress = [](double, int points) {
        if (points == 3) throw InvalidInput("x = 1 is out of range");
    };
    CHECK_THROWS_AS(continue_branch(hb, o), InvalidInput);
}

TEST_CASE("A fold whose location the solver ends by an exception is counted, said, and the branch kept",
          "[continuation][fold][status]") {
    // The Dahl oscillator's two folds (the test below): the first location's first stop request
    // throws (inside the location's solves), the second fold is located as usual.
    HarmonicBalance hb(test::dahl_oscillator(10.0, 1.0, 1.28, 0.003), HarmonicBalanceOptions{20, 0});
    ContinuationOptions o = folding_band();
    int started = 0;
    bool thrown = false;
    o.fold_progress = [&](int, int) { ++started; };
    o.stop = [&]() {
        if (started == 1 && !thrown) {
            thrown = true;
            throw std::runtime_error("the contact solve broke down");
        }
        return std::string();
    };
    const BranchResult b = continue_branch(hb, o);
    CHECK(thrown);
    CHECK(started == 2);
    CHECK(b.status == ContinuationStatus::completed);
    CHECK(b.location_errors == 1);
    CHECK(b.located_folds == 1);
    CHECK_THAT(b.message, Catch::Contains("a fold's location failed in the solver: the contact solve broke down"));
    CHECK(b.points.back().omega == o.omega_end);
}

TEST_CASE("Continuation through folds: the branch bends over and comes back", "[continuation][fold]") {
    // A 1-DOF Dahl oscillator (stiffness 11 in stick, 1 in slip) lightly damped, forced near
    // the threshold 4 F_c / pi: its superharmonic resonance near w = 0.55 (3w on the softened
    // stiffness) bends over. Measured fold frequencies: H = 20 and H = 40 agree to 5e-4.
    HarmonicBalance hb(test::dahl_oscillator(10.0, 1.0, 1.28, 0.003), HarmonicBalanceOptions{20, 0});
    ContinuationOptions o = folding_band();
    const BranchResult b = continue_branch(hb, o);
    REQUIRE(b.status == ContinuationStatus::completed);
    CHECK(b.points.back().omega == o.omega_end);  // not lost: the branch reaches wmax
    std::vector<std::size_t> folds;
    for (std::size_t k = 0; k < b.points.size(); ++k)
        if (b.points[k].kind == PointKind::fold) folds.push_back(k);
    REQUIRE(folds.size() == 2);
    const double upper = b.points[folds[0]].omega, lower = b.points[folds[1]].omega;
    INFO("folds at w = " << upper << " and " << lower);
    CHECK(upper > lower + 1e-3);  // S-shaped: forward, back, forward again
    CHECK(upper == Approx(0.5471).margin(2e-3));
    CHECK(lower == Approx(0.5446).margin(2e-3));
    // Independent of the tangent test that flagged them: at a turning point dR/dX is singular,
    // so det(dR/dX) changes sign across each fold and nowhere else on the branch.
    int changes = 0;
    for (std::size_t k = 0; k + 1 < b.points.size(); ++k) {
        const bool change = jacobian_determinant_sign(hb, b.points[k]) != jacobian_determinant_sign(hb, b.points[k + 1]);
        if (!change) continue;
        ++changes;
        // The flag sits on the first point past the turn (or on the one before it).
        const bool near_flag = std::any_of(folds.begin(), folds.end(), [&](std::size_t f) { return f == k || f == k + 1; });
        CHECK(near_flag);
    }
    CHECK(changes == 2);
    // Between the folds three solutions coexist; each is solved exactly there, is distinct,
    // and balances its energy.
    const auto samples = sample_branch(hb, b, {0.5 * (upper + lower)}, CorrectorOptions{});
    REQUIRE(samples.size() == 3);
    Analyser analyse(hb);
    std::vector<double> amplitudes;
    for (const SolutionPoint& s : samples) {
        const PointMetrics m = analyse(s);
        amplitudes.push_back(m.y_max[0]);
        CHECK(s.residual <= 1e-9);
        // The viscous damper dissipates too: input = friction + pi c w^2 sum_k k^2 |Y_k|^2.
        const Eigen::VectorXd y = hb.dofs(s.x, s.omega).col(0);
        double viscous = 0.0;
        for (int k = 1; k <= hb.harmonics(); ++k)
            viscous += M_PI * 0.003 * s.omega * k * k * (y(2 * k - 1) * y(2 * k - 1) + y(2 * k) * y(2 * k));
        CHECK(std::abs(m.input_energy - m.energy - viscous) <= 1e-6 * m.input_energy);
    }
    std::sort(amplitudes.begin(), amplitudes.end());
    CHECK(amplitudes[1] - amplitudes[0] > 1e-3);
    CHECK(amplitudes[2] - amplitudes[1] > 1e-3);
}

TEST_CASE("A stick-slip start is found by ramping the excitation, and matches the branch", "[continuation]") {
    // At w = 0.7 this oscillator is in stick-slip, far from both linear guesses (stiffness
    // 11 or 1), which do not converge even with the start's 100 iterations; the start ramps
    // the force up from 1e-3 F.
    System s = test::dahl_oscillator(10.0, 1.0, 1.4, 0.003);
    HarmonicBalance hb(s, HarmonicBalanceOptions{10, 0});
    CorrectorOptions patient;
    patient.max_iterations = 100;
    Corrector corrector(hb, patient);
    int iterations = 0;
    double residual = 0.0;
    bool direct = false;
    for (const bool sliding : {false, true}) {
        Eigen::VectorXd x = hb.linear_guess(0.7, sliding);
        direct = direct || corrector.solve_at(x, 0.7, std::max(1.4, x.cwiseAbs().maxCoeff()), iterations, residual);
    }
    CHECK_FALSE(direct);  // the ramp is really needed here
    ContinuationOptions o;
    o.omega_start = 0.7;
    o.omega_end = 0.75;
    const BranchResult started = continue_branch(hb, o);
    REQUIRE(started.status == ContinuationStatus::completed);
    // Independent path: continue from w = 0.3 (where the pre-sliding guess converges) up to
    // 0.7; the same periodic solution must be reached.
    o.omega_start = 0.3;
    o.omega_end = 0.7;
    const BranchResult walked = continue_branch(hb, o);
    REQUIRE(walked.status == ContinuationStatus::completed);
    const Eigen::VectorXd& a = started.points.front().x;
    const Eigen::VectorXd& c = walked.points.back().x;
    CHECK((a - c).cwiseAbs().maxCoeff() <= 1e-8 * c.cwiseAbs().maxCoeff());
}

TEST_CASE("Exact Coulomb with a huge friction limit: permanent stick, the closed form, the symmetric solution",
          "[continuation][coulomb]") {
    AbsorberParameters p;
    p.friction_coefficient = 100.0;  // never slips at fe = 0.5
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{5, 0});
    ContinuationOptions o;
    o.omega_end = 0.9;  // the stuck structure is undamped: its resonance 1/sqrt(1 + r) is unbounded
    const BranchResult b = continue_branch(hb, o);
    REQUIRE(b.status == ContinuationStatus::completed);
    Analyser analyse(hb);
    for (const SolutionPoint& point : b.points) {
        const analytic::Response exact = analytic::coulomb_stick(p, point.omega);
        const Eigen::VectorXd y1 = hb.dofs(point.x, point.omega).col(0), y2 = hb.dofs(point.x, point.omega).col(1), force = hb.state(point.x, 0);
        INFO("w = " << point.omega);
        CHECK(std::abs(std::complex<double>(y1(1), -y1(2)) - exact.y1) < 1e-8 * std::abs(exact.y1));
        CHECK((y1 - y2).cwiseAbs().maxCoeff() < 1e-8 * std::abs(exact.y1));  // stuck: q = 0
        CHECK(y1.tail(8).norm() < 1e-8 * std::abs(exact.y1));                 // no higher harmonics
        // The convention of permanent stick: the force centred in the cone, i.e. the
        // symmetric solution: zero mean force and zero mean displacement.
        CHECK(std::abs(force(0)) < 1e-8 * p.friction_coefficient);
        CHECK(std::abs(y1(0)) < 1e-8 * std::abs(exact.y1));
        CHECK(analyse(point).energy == Approx(0.0).margin(1e-8));  // sticking dissipates nothing
    }
}

TEST_CASE("Exact Coulomb, H = 1, large fe: the describing-function solution, to the AFT sampling error",
          "[continuation][coulomb]") {
    // With one harmonic the force is balanced through its first harmonic only: the
    // equivalent-viscous (describing-function) solution of the paper, except that the AFT
    // computes the first harmonic of F_c sign(v) on N_t samples: 4 F_c / pi times a factor
    // between 1 - (pi / N_t)^2 / 3 (zero crossings on the grid) and 1, depending on where the
    // zero crossings of v fall: the error is bounded by O(N_t^-2), not monotone in N_t.
    AbsorberParameters p;
    p.excitation = 1.0;
    const double omega = 1.0;
    const double exact = std::abs(analytic::coulomb_slip(p, omega)->y1);
    for (int nt : {64, 128, 256}) {
        HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{1, nt});
        const SolutionPoint s = solve_by_continuation(hb, omega);
        const Eigen::VectorXd y1 = hb.dofs(s.x, s.omega).col(0);
        const double error = std::abs(std::hypot(y1(1), y1(2)) - exact) / exact;
        INFO("N_t = " << nt << ": relative difference " << error);
        CHECK(error < (M_PI / nt) * (M_PI / nt));
    }
}

TEST_CASE("Stick-slip transitions of exact Coulomb and Jenkins lie where the stuck closed form reaches the limit",
          "[continuation][transition]") {
    // Stuck, the absorber moves with the main mass: y = fe / (1 - (1 + r) w^2) cos, and the
    // contact carries the absorber's inertia force, amplitude r w^2 |y| (its spring is not
    // stretched). Stick ends where r w^2 fe / |1 - (1 + r) w^2| = mu, i.e. (derived by hand)
    //   w^2 = mu / (r fe + mu (1 + r))  below the resonance, mu / (mu (1 + r) - r fe) above.
    // Jenkins stuck is the linear system with the spring k_t = r wb^2: stick ends where
    // k_t |Q| = F_c, i.e. where the pre-sliding (Dahl, xi = 0) limit coefficient equals mu.
    // The bisection stops at 1e-10 in scaled arclength; the closed forms are exact.
    const AbsorberParameters p;
    const double r = p.mass_ratio, fe = p.excitation, mu = p.friction_coefficient;
    const std::vector<double> coulomb = {std::sqrt(mu / (r * fe + mu * (1 + r))),
                                         std::sqrt(mu / (mu * (1 + r) - r * fe))};
    for (FrictionLaw law : {FrictionLaw::coulomb, FrictionLaw::jenkins}) {
        HarmonicBalance hb(friction_absorber(p, law), HarmonicBalanceOptions{10, 0});
        const BranchResult b = continue_branch(hb, ContinuationOptions{});
        INFO(to_string(law) << ": " << b.summary());
        REQUIRE(b.status == ContinuationStatus::completed);
        std::vector<double> found;
        Analyser analyse(hb);
        for (std::size_t k = 0; k < b.points.size(); ++k) {
            const SolutionPoint& t = b.points[k];
            if (t.kind != PointKind::transition || t.boundary != Boundary::stick_stick_slip) continue;
            found.push_back(t.omega);
            CHECK(analyse(t).regime == "stick");  // the stick-side point of the boundary
            // Its neighbours on the branch: one of them is not stuck.
            CHECK((analyse(b.points[k - 1]).regime != "stick" || analyse(b.points[k + 1]).regime != "stick"));
            if (law == FrictionLaw::jenkins)
                CHECK(analytic::contact_limit_friction(p, t.omega, FrictionLaw::dahl) == Approx(mu).epsilon(1e-7));
        }
        if (law == FrictionLaw::coulomb) {
            REQUIRE(found.size() == coulomb.size());
            for (std::size_t k = 0; k < found.size(); ++k) CHECK(found[k] == Approx(coulomb[k]).epsilon(1e-8));
        } else {
            CHECK(found.size() == 4);  // two stick-slip bands, each around one resonance
        }
        CHECK(b.transitions >= static_cast<int>(found.size()));
    }
}

TEST_CASE("Jenkins with a huge friction limit is the linear spring k_t: the pre-sliding closed form",
          "[continuation][jenkins]") {
    AbsorberParameters p;
    p.friction_coefficient = 1e6;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::jenkins), HarmonicBalanceOptions{3, 0});
    // Solved to 1e-11: near the unbounded resonances the response amplifies a residual by
    // ~100, and the comparison below is at 1e-8 of the amplitude.
    ContinuationOptions o;
    o.corrector.tolerance = 1e-11;
    const BranchResult b = continue_branch(hb, o);
    // Undamped and linear: both resonances are unbounded, so the branches stop at the cap.
    REQUIRE(b.status == ContinuationStatus::amplitude_cap);
    REQUIRE(b.points.size() > 5);
    for (const SolutionPoint& point : b.points) {
        const analytic::Response exact = analytic::contact_stick(p, point.omega, FrictionLaw::dahl);
        const Eigen::VectorXd y1 = hb.dofs(point.x, point.omega).col(0), y2 = hb.dofs(point.x, point.omega).col(1);
        INFO("w = " << point.omega);
        CHECK(std::abs(std::complex<double>(y1(1), -y1(2)) - exact.y1) < 1e-8 * std::abs(exact.y1));
        CHECK(std::abs(std::complex<double>(y2(1), -y2(2)) - exact.y2) < 1e-8 * std::abs(exact.y1));
        CHECK(y1.tail(4).norm() < 1e-8 * std::abs(exact.y1));
    }
}

TEST_CASE("The last point before each amplitude cap is marked cap and the caps bracket the stuck resonances",
          "[continuation][jenkins]") {
    // Jenkins with a huge friction limit is the undamped linear absorber with the contact spring
    // r wb^2: both resonances (analytic::stuck_resonances, the eigenfrequencies) are unbounded.
    // Branch 1 stops below the first, branch 2 (from wmax) above the second, branch 3 between
    // them on both sides: four caps, each at the first point whose amplitude bound passed
    // max_amplitude, each within a few percent of its resonance (the response ~ 1/|w - w_r|).
    AbsorberParameters p;
    p.friction_coefficient = 1e6;
    p.contact_stiffness_ratio = 0.8;  // resonances at w = 0.912 and 1.405, inside [0.5, 1.6]
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::jenkins), HarmonicBalanceOptions{3, 0});
    ContinuationOptions o;
    const BranchResult b = continue_branch(hb, o);
    REQUIRE(b.status == ContinuationStatus::amplitude_cap);
    const std::vector<double> resonance = analytic::stuck_resonances(p, FrictionLaw::dahl);
    REQUIRE(resonance[1] < o.omega_end);
    std::vector<std::pair<int, double>> caps;
    for (const SolutionPoint& q : b.points) {
        if (q.kind != PointKind::cap) continue;
        caps.emplace_back(q.branch, q.omega);
        CHECK(hb.amplitude_bound(q.x, q.omega) > o.max_amplitude);
    }
    std::sort(caps.begin(), caps.end(), [](const auto& a, const auto& c) { return a.second < c.second; });
    REQUIRE(caps.size() == 4);
    CHECK(caps[0].first == 1);
    CHECK(caps[3].first == 2);
    CHECK(caps[1].first == 3);
    CHECK(caps[2].first == 3);
    CHECK(caps[0].second < resonance[0]);
    CHECK(caps[1].second > resonance[0]);
    CHECK(caps[2].second < resonance[1]);
    CHECK(caps[3].second > resonance[1]);
    for (int k = 0; k < 4; ++k) CHECK(std::abs(caps[k].second / resonance[k / 2] - 1.0) < 0.03);
    // Every other point is below the cap.
    for (const SolutionPoint& q : b.points)
        if (q.kind != PointKind::cap) CHECK(hb.amplitude_bound(q.x, q.omega) <= o.max_amplitude);
}

TEST_CASE("linear_resonances: the absorber's released, stuck and rigid limits against the closed forms",
          "[continuation][resonances]") {
    // det(K - w^2 M) / r of the absorber with the coupling stiffness r s (s = wa^2 released,
    // wa^2 + wb^2 with the stuck spring r wb^2): w^4 - (1 + s (1 + r)) w^2 + s = 0. Rigid
    // (y1 = y2): one mass 1 + r on the spring 1, w = 1 / sqrt(1 + r).
    AbsorberParameters p;  // r = 0.1, wa = 1, wb = 0.4
    const double r = p.mass_ratio;
    auto roots = [r](double s) {
        const double b = 1.0 + s * (1.0 + r), d = std::sqrt(b * b - 4.0 * s);
        return std::pair<double, double>{std::sqrt(0.5 * (b - d)), std::sqrt(0.5 * (b + d))};
    };
    const auto released = roots(1.0), stuck = roots(1.0 + 0.16);
    const double rigid = 1.0 / std::sqrt(1.0 + r);
    const std::vector<LinearResonance> dahl = linear_resonances(friction_absorber(p, FrictionLaw::dahl), 0.5, 1.6);
    REQUIRE(dahl.size() == 5);  // sorted: released, stuck, rigid, released, stuck
    const std::vector<std::pair<double, LinearResonance::Limit>> expected = {
        {released.first, LinearResonance::Limit::released}, {stuck.first, LinearResonance::Limit::stuck},
        {rigid, LinearResonance::Limit::rigid}, {released.second, LinearResonance::Limit::released},
        {stuck.second, LinearResonance::Limit::stuck}};
    for (std::size_t k = 0; k < expected.size(); ++k) {
        INFO(k);
        CHECK(dahl[k].omega == Approx(expected[k].first).epsilon(1e-12));
        CHECK(dahl[k].limit == expected[k].second);
    }
    // Exact Coulomb has no stuck spring: released and rigid only; a band excludes what is outside.
    const std::vector<LinearResonance> coulomb =
        linear_resonances(friction_absorber(p, FrictionLaw::coulomb), 0.9, 1.6);
    REQUIRE(coulomb.size() == 2);
    CHECK(coulomb[0].omega == Approx(rigid).epsilon(1e-12));
    CHECK(coulomb[1].omega == Approx(released.second).epsilon(1e-12));
    // A force at 2 w meets each natural frequency at half of it.
    System twice = friction_absorber(p, FrictionLaw::coulomb);
    twice.excitation_harmonic = 2;
    const std::vector<LinearResonance> half = linear_resonances(twice, 0.25, 0.8);
    REQUIRE(half.size() == 3);
    CHECK(half[1].omega == Approx(0.5 * rigid).epsilon(1e-12));
}

TEST_CASE("A large step does not jump across the unbounded stuck resonance: the branch climbs it to the cap",
          "[continuation][resonances]") {
    // Exact Coulomb, r = 1e-12: the contact holds the absorber (it needs r w^2 |Y| < mu, |Y| <
    // 2e11), so the response is the rigid structure's, y1 = fe / (1 - (1 + r) w^2): unbounded
    // at w_r = 1 / sqrt(1 + r). With max_step 1 the corrector used to land across it (10
    // points, completed, a "peak" of 7.9e9).
    AbsorberParameters p;
    p.mass_ratio = 1e-12;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::coulomb), HarmonicBalanceOptions{10, 0});
    const double w_r = 1.0 / std::sqrt(1.0 + p.mass_ratio);
    ContinuationOptions o;
    const BranchResult b = continue_branch(hb, o);
    CHECK(b.status == ContinuationStatus::amplitude_cap);
    CHECK(b.resonance_rejections > 0);
    std::vector<double> caps;
    for (const SolutionPoint& q : b.points)
        if (q.kind == PointKind::cap) {
            caps.push_back(q.omega);
            // The stuck closed form at the cap point, above the cap.
            const Eigen::MatrixXd y = hb.dofs(q.x, q.omega);
            const double y1 = std::hypot(y(1, 0), y(2, 0));
            CHECK(y1 == Approx(p.excitation / std::abs(1.0 - (1.0 + p.mass_ratio) * q.omega * q.omega)).epsilon(1e-6));
            CHECK(y1 > o.max_amplitude);
        }
    REQUIRE(caps.size() == 2);
    CHECK(caps[0] < w_r);
    CHECK(caps[1] > w_r);
    // Without the resolution the same options step across it: the guard is what catches it.
    ContinuationOptions blind = o;
    blind.resolve_resonances = false;
    CHECK(continue_branch(hb, blind).status == ContinuationStatus::completed);
}

TEST_CASE("Peak refinement by Brent's method: the maximum of a resonance curve in fewer evaluations than golden section",
          "[continuation][peaks]") {
    // |Y(x)| = 1 / sqrt((1 - x^2)^2 + (2 z x)^2) (a damped oscillator, x = w / w_n) has its
    // maximum at x* = sqrt(1 - 2 z^2), |Y|* = 1 / (2 z sqrt(1 - z^2)) (derived by setting the
    // derivative of the denominator to zero). Brackets of two neighbouring branch points, on
    // the peak's flanks and off centre; z = 0.01 and 0.1. Both searches to 1e-9 relative in x:
    // the value to 1e-12 (the maximum is quadratic: an x error of 1e-9 costs ~(1e-9 / z)^2),
    // x to 1e-8; Brent in at most half the evaluations of golden section.
    for (const double z : {0.01, 0.1}) {
        const double x_star = std::sqrt(1.0 - 2.0 * z * z), y_star = 1.0 / (2.0 * z * std::sqrt(1.0 - z * z));
        for (const auto& [lo, hi] : {std::pair{x_star - 0.01, x_star + 0.02}, std::pair{x_star - 0.003, x_star + 0.001},
                                     std::pair{0.9 * x_star, 1.2 * x_star}}) {
            int golden_calls = 0, brent_calls = 0;
            auto response = [&](double x, int& calls) {
                ++calls;
                return 1.0 / std::sqrt(std::pow(1.0 - x * x, 2) + std::pow(2.0 * z * x, 2));
            };
            bool ok = true;
            const auto golden = hbf::detail::golden_section_maximum(
                [&](double x, bool&) { return response(x, golden_calls); }, lo, hi, 1e-9, ok);
            const auto brent = hbf::detail::brent_maximum([&](double x, bool&) { return response(x, brent_calls); }, lo,
                                                          hi, 1e-9, ok);
            INFO("z = " << z << ", [" << lo << ", " << hi << "]: golden " << golden_calls << ", brent " << brent_calls);
            REQUIRE(ok);
            CHECK(std::abs(golden.value / y_star - 1.0) < 1e-12);
            CHECK(std::abs(brent.value / y_star - 1.0) < 1e-12);
            CHECK(std::abs(brent.x / x_star - 1.0) < 1e-8);
            CHECK(2 * brent_calls <= golden_calls);
        }
    }
    // A failed evaluation stops the search and is reported.
    bool ok = true;
    int calls = 0;
    hbf::detail::brent_maximum([&](double x, bool& good) { good = ++calls < 4; return -x * x; }, -1.0, 2.0, 1e-9, ok);
    CHECK_FALSE(ok);
    CHECK(calls == 4);
}

TEST_CASE("refine_peak: a lower local maximum in the bracket, corners, folds and failed solves, each with its reason",
          "[continuation][peaks]") {
    using hbf::PointKind;
    auto point = [](double w, PointKind kind = PointKind::regular) {
        hbf::SolutionPoint p;
        p.omega = w;
        p.kind = kind;
        return p;
    };
    // y = max(0.75 - 2 (w - 0.3)^2, 1 - 300 |w - 0.62|): a smooth local maximum 0.75 at 0.3
    // and a narrow peak 1 at the corner 0.62. Branch points 0, 0.6195 (y = 0.85) and 1: Brent
    // over [0, 1] settles on 0.3 (below y(0.6195)); each side of 0.6195 alone finds 0.62.
    auto y = [](double w) { return std::max(0.75 - 2.0 * (w - 0.3) * (w - 0.3), 1.0 - 300.0 * std::abs(w - 0.62)); };
    bool ok = true;
    CHECK(hbf::detail::brent_maximum([&](double w, bool&) { return y(w); }, 0.0, 1.0, 1e-9, ok).value < y(0.6195));
    hbf::Peak peak{0.6195, y(0.6195), 1, false, 0, {}};
    hbf::refine_peak(peak, point(0.0), point(0.6195), point(1.0), [&](double w, bool&) { return y(w); });
    INFO(peak.why);
    CHECK(peak.refined);
    CHECK(std::abs(peak.omega - 0.62) < 1e-8);
    CHECK(std::abs(peak.y_max - 1.0) < 1e-7);
    // A fold beside it, and a failed solve, named.
    hbf::Peak folded{0.6195, y(0.6195), 1, false, 0, {}};
    hbf::refine_peak(folded, point(0.0), point(0.6195), point(1.0, PointKind::fold), [&](double w, bool&) { return y(w); });
    CHECK_FALSE(folded.refined);
    CHECK_THAT(folded.why, Catch::Contains("a fold at w = 1"));
    hbf::Peak failed{0.6195, y(0.6195), 1, false, 0, {}};
    hbf::refine_peak(failed, point(0.0), point(0.6195), point(1.0), [&](double w, bool& ok) {
        ok = w < 0.5;
        return y(w);
    });
    CHECK_FALSE(failed.refined);
    CHECK_THAT(failed.why, Catch::Contains("the solve failed at w = 0.6"));
    // A corner exactly at the branch point: a located transition is the peak itself; a regular
    // point is reported as such, with the largest value the search found.
    auto tent = [](double w) { return 1.0 - std::abs(w - 0.6); };
    hbf::Peak at_transition{0.6, 1.0, 1, false, 0, {}};
    hbf::refine_peak(at_transition, point(0.0), point(0.6, PointKind::transition), point(1.0),
                     [&](double w, bool&) { return tent(w); });
    CHECK(at_transition.refined);
    CHECK(at_transition.omega == 0.6);
    CHECK(at_transition.y_max == 1.0);
    // Rounding is not a peak: 1e-9 of the output's largest value.
    CHECK_FALSE(hbf::is_peak_value(1e-9, 1.0, 1e-12));
    CHECK(hbf::is_peak_value(1e-7, 1.0, 1e-12));
    CHECK_FALSE(hbf::is_peak_value(1e-7, 1e-6, 2e-7));
}
