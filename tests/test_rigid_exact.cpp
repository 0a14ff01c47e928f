// Exact periodic orbits of rigid unilateral contacts with Coulomb friction on massless nodes
// (law unilateral, include/hbf/rigid_exact.hpp). The references are independent of the event
// solver: law unilateral's time integrator (velocity Verlet with a complementarity solve per
// step, second order), whose error against the exact orbit must fall like dt^2; the energy
// balance (the force's work equals the friction's plus the viscous one, over the exact period);
// the Floquet multipliers against the growth of a perturbation under the exact flow; and
// limits where the contacts never slip or never close (the linear structure's steady state).
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <cmath>
#include <stdexcept>
#include <complex>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/model.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"

#include "event_exact/cone_engine.hpp"
#include "contact/massless_contacts.hpp"
#include "event_exact/radau.hpp"
#include "model/mirror.hpp"

#include "../benchmarks/contact_chain.hpp"
#include "../benchmarks/integrator_check.hpp"
#include "support.hpp"

using namespace hbf;
using io::read_system_config;
using io::SystemConfig;

namespace {

const std::string liftoff3 = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";

/// Three masses, each pressing a massless contact node onto a rigid wall, whose contacts stick,
/// slip and open at different times (benchmarks/contact_chain.hpp).
System three_contacts(double force) { return bench::contact_chain(3, force); }

}  // namespace

namespace {

/// Law unilateral's time integrator at `samples` steps per period (at least), converged tightly.
PeriodicResponse integrated(const System& system, double omega, int samples, const std::vector<Output>& outputs) {
    TimeIntegrationOptions o;
    o.samples_per_period = samples;
    o.steady_tolerance = 1e-12;
    o.max_periods = 20000;
    o.outputs = outputs;
    return integrate_steady_state(system, omega, o);
}

double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

/// The damping's work over the orbit's period: the integral of v^T C v, trapezoidal on its
/// samples (periodic, C^1 between the events: second order).
double viscous_work(const System& system, const ExactOrbit& orbit, double omega) {
    const Eigen::MatrixXd C(system.damping);
    double viscous = 0.0;
    const auto samples = orbit.velocity.rows();
    for (Eigen::Index j = 0; j < samples; ++j) {
        const Eigen::VectorXd v = orbit.velocity.row(j).transpose();
        viscous += v.dot(C * v);
    }
    return viscous * (2.0 * M_PI / omega) / static_cast<double>(samples);
}

/// The exact orbit against the integrator at S and 2S steps a period: its error falls like
/// dt^2 (the first harmonic by a factor near 4, at least 3; the maximum by at least 2) down
/// to `closest` relative at 2S, in the first output; the contact shares agree to the integrator's step (first order: the steps
/// are counted whole).
void check_against_integrator(const System& system, double omega, const std::vector<Output>& outputs, int samples,
                              double closest) {
    const PeriodicResponse coarse = integrated(system, omega, samples, outputs);
    const PeriodicResponse fine = integrated(system, omega, 2 * samples, outputs);
    REQUIRE(coarse.converged);
    REQUIRE(fine.converged);
    ExactOptions options;
    options.outputs = outputs;
    const ExactOrbit exact = rigid_periodic_orbit(system, omega, fine.state, options);
    INFO("w = " << omega << ": " << exact.message << ", " << exact.switches << " events");
    REQUIRE(exact.converged);
    CHECK(exact.residual <= 1e-12);
    const double e_max_coarse = relative(coarse.output_max[0], exact.output_max[0]);
    const double e_max_fine = relative(fine.output_max[0], exact.output_max[0]);
    const double e_amp_coarse = relative(coarse.output_amp1[0], exact.output_amp1[0]);
    const double e_amp_fine = relative(fine.output_amp1[0], exact.output_amp1[0]);
    INFO("max: exact " << exact.output_max[0] << ", errors " << e_max_coarse << " -> " << e_max_fine);
    INFO("amp1: exact " << exact.output_amp1[0] << ", errors " << e_amp_coarse << " -> " << e_amp_fine);
    CHECK(e_amp_fine <= closest);
    CHECK(e_max_fine <= closest);
    // second order, down to the floor the integrator's own steady-state test leaves (~1e-9);
    // its maximum (a parabola through the samples around the largest) converges more slowly
    CHECK((e_amp_fine <= e_amp_coarse / 3.0 || e_amp_fine <= 1e-8));
    CHECK((e_max_fine <= e_max_coarse / 2.0 || e_max_fine <= 1e-8));
    const double step = 1.0 / (2.0 * samples);
    for (std::size_t c = 0; c < exact.contacts.size(); ++c) {
        INFO("contact " << c + 1);
        CHECK(std::abs(fine.contacts[c].stick_fraction - exact.contacts[c].stick_fraction) <= 3 * step);
        CHECK(std::abs(fine.contacts[c].separated_fraction - exact.contacts[c].separated_fraction) <= 3 * step);
        CHECK(relative(fine.contacts[c].normal_mean, exact.contacts[c].normal_mean) <= 1e-3);
    }
}

}  // namespace

TEST_CASE("rigid exact: liftoff3_rigid's orbits are the time integrator's limit", "[rigid_exact]") {
    const SystemConfig config = read_system_config(liftoff3);
    // stick-slip at 1.2 and 2.0, stick and lift-off at 2.5
    for (double omega : {1.2, 2.0, 2.5}) check_against_integrator(config.system, omega, config.outputs, 512, 1e-6);
}

TEST_CASE("rigid exact: three contacts sticking, slipping and opening at different times", "[rigid_exact]") {
    const System system = three_contacts(0.3);
    std::vector<Output> outputs{Output::dof(0)};
    check_against_integrator(system, 1.0, outputs, 512, 1e-6);
}

TEST_CASE("rigid exact: the energy the force puts in is what friction and damping take out", "[rigid_exact]") {
    for (const auto& [force, omega] : {std::pair<double, double>{0.3, 1.0}, {0.3, 1.8}}) {
        const System system = three_contacts(force);
        ExactOptions options;
        options.samples = 8192;
        const ExactOrbit orbit = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), options);
        INFO("F = " << force << ", w = " << omega << ": " << orbit.message);
        REQUIRE(orbit.converged);
        REQUIRE(orbit.switches > 6);
        const double viscous = viscous_work(system, orbit, omega);
        double friction = 0.0;
        for (const ContactRegime& c : orbit.contacts) friction += c.energy;
        CHECK(std::abs(friction - orbit.energy) <= 1e-15 * orbit.energy);
        CHECK(std::abs(orbit.input_energy - friction - viscous) <= 1e-7 * orbit.input_energy);
        CHECK(friction > 0.1 * orbit.input_energy);
    }
}

namespace {

/// The complex first harmonic of (K - w^2 M + i w C) x = F on the DOFs `keep` (the others held
/// at zero dynamic motion).
Eigen::VectorXd linear_amplitudes(const System& s, double omega, const std::vector<int>& keep) {
    const auto n = static_cast<Eigen::Index>(keep.size());
    Eigen::MatrixXcd A(n, n);
    Eigen::VectorXcd F(n);
    const Eigen::MatrixXd M(s.mass), K(s.stiffness), C(s.damping);
    for (Eigen::Index i = 0; i < n; ++i) {
        F(i) = s.excitation(keep[static_cast<std::size_t>(i)]);
        for (Eigen::Index j = 0; j < n; ++j) {
            const int a = keep[static_cast<std::size_t>(i)], b = keep[static_cast<std::size_t>(j)];
            A(i, j) = std::complex<double>(K(a, b) - omega * omega * M(a, b), omega * C(a, b));
        }
    }
    return A.partialPivLu().solve(F).cwiseAbs();
}

}  // namespace

TEST_CASE("rigid exact: contacts that never close or never slip leave the linear structure", "[rigid_exact]") {
    const SystemConfig config = read_system_config(liftoff3);
    const double omega = 1.1;
    SECTION("a gap the motion never closes: the structure with its nodes free") {
        System open = config.system;
        open.static_load = Eigen::VectorXd::Zero(open.dofs());
        open.contacts[0].values["gap"] = 1.0;
        const ExactOrbit orbit = rigid_periodic_orbit(open, omega, Eigen::VectorXd());
        REQUIRE(orbit.converged);
        CHECK(orbit.switches == 0);
        CHECK(orbit.contacts[0].separated_fraction == 1.0);
        const Eigen::VectorXd linear = linear_amplitudes(open, omega, {0, 1, 2, 3, 4});
        for (int i = 0; i < 5; ++i) CHECK(std::abs(orbit.y_amp1[static_cast<std::size_t>(i)] - linear(i)) <= 1e-10 * linear.maxCoeff());
    }
    SECTION("a friction coefficient nothing overcomes: the structure with its nodes held") {
        System stuck = config.system;
        stuck.contacts[0].values["friction_coefficient"] = 50.0;
        const Eigen::VectorXd linear = linear_amplitudes(stuck, omega, {0, 1, 2});
        // The Floquet multipliers: exp(lambda T) of the held structure's eigenvalues, and 1 for
        // the held node's position (any is periodic).
        const Eigen::MatrixXd M = Eigen::MatrixXd(stuck.mass).topLeftCorner(3, 3),
                              K = Eigen::MatrixXd(stuck.stiffness).topLeftCorner(3, 3),
                              C = Eigen::MatrixXd(stuck.damping).topLeftCorner(3, 3);
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(6, 6);
        a.topRightCorner(3, 3).setIdentity();
        a.bottomLeftCorner(3, 3) = -M.inverse() * K;
        a.bottomRightCorner(3, 3) = -M.inverse() * C;
        const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a).eigenvalues();
        auto check = [&](const ExactOrbit& orbit) {
            INFO(orbit.message);
            REQUIRE(orbit.converged);
            CHECK(orbit.switches == 0);
            CHECK(orbit.contacts[0].stick_fraction == 1.0);
            for (int i = 0; i < 3; ++i)
                CHECK(std::abs(orbit.y_amp1[static_cast<std::size_t>(i)] - linear(i)) <= 1e-10 * linear.maxCoeff());
            REQUIRE(orbit.multipliers.size() == 7);
            int ones = 0;
            for (Eigen::Index k = 0; k < orbit.multipliers.size(); ++k) {
                const std::complex<double> mu = orbit.multipliers(k);
                if (std::abs(mu - 1.0) <= 1e-9) {
                    ++ones;
                    continue;
                }
                double closest = 1.0;
                for (Eigen::Index j = 0; j < lambda.size(); ++j)
                    closest = std::min(closest, std::abs(mu - std::exp(lambda(j) * (2.0 * M_PI / omega))));
                CHECK(closest <= 1e-9);
            }
            CHECK(ones == 1);
        };
        const ExactOrbit from_rest = rigid_periodic_orbit(stuck, omega, Eigen::VectorXd());
        check(from_rest);
        // From its own state the start holds the node stuck: the held start's route (a plain
        // period, one with the monodromy, a recorded one), the same orbit and multipliers.
        const ExactOrbit held = rigid_periodic_orbit(stuck, omega, from_rest.state);
        check(held);
        CHECK(held.permanent_stick);
        CHECK(held.periods <= 3);
    }
}

TEST_CASE("rigid exact: what it cannot take is refused up front, naming the cause", "[rigid_exact]") {
    const SystemConfig config = read_system_config(liftoff3);
    CHECK(rigid_solver_refusal(config.system).empty());
    System heavy = config.system;
    Eigen::MatrixXd M(heavy.mass);
    M(3, 3) = 0.1;
    heavy.mass = M.sparseView();
    CHECK_THAT(rigid_solver_refusal(heavy), Catch::Contains("DOF 4, which has mass"));
    CHECK_THROWS_AS(rigid_periodic_orbit(heavy, 1.0, Eigen::VectorXd()), InvalidInput);
    // a third massless node, tied to y1, as the contact's second tangential direction
    System spatial = config.system;
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(6, 6), M6 = K, C6 = K;
    K.topLeftCorner(5, 5) = Eigen::MatrixXd(config.system.stiffness);
    M6.topLeftCorner(5, 5) = Eigen::MatrixXd(config.system.mass);
    C6.topLeftCorner(5, 5) = Eigen::MatrixXd(config.system.damping);
    K(0, 0) += 3.0;
    K(5, 5) += 3.0;
    K(0, 5) = K(5, 0) = -3.0;
    spatial.stiffness = K.sparseView();
    spatial.mass = M6.sparseView();
    spatial.damping = C6.sparseView();
    for (Eigen::VectorXd* v : {&spatial.excitation, &spatial.static_load}) {
        v->conservativeResize(6);
        (*v)(5) = 0.0;
    }
    spatial.contacts[0].lists["normal_direction"].push_back(0.0);
    spatial.contacts[0].lists["second_direction"] = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
    REQUIRE_NOTHROW(spatial.validate());
    CHECK(rigid_solver_refusal(spatial).empty());  // 3D contacts are taken (the cone engine)
    // more contacts than the bound: refused before any work, naming the bound
    const System many = bench::contact_chain(rigid_solver_max_contacts + 1, 0.3);
    CHECK_THAT(rigid_solver_refusal(many), Catch::Contains("allows at most " + std::to_string(rigid_solver_max_contacts)));
    CHECK_THROWS_AS(rigid_periodic_orbit(many, 1.0, Eigen::VectorXd()), InvalidInput);
    CHECK_THROWS_WITH(rigid_periodic_orbit(config.system, 1.0, Eigen::VectorXd::Zero(3)),
                      Catch::Contains("allowed none (a start at rest) or 10"));
    CHECK_THROWS_WITH(rigid_periodic_orbit(config.system, -1.0, Eigen::VectorXd()), Catch::Contains("omega = -1"));
}

TEST_CASE("rigid exact: the FRF polish makes liftoff3_rigid's points exact and says where it cannot", "[rigid_exact]") {
    const SystemConfig config = read_system_config(liftoff3);
    const FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);  // 0.3 to 3
    REQUIRE(settings.exact);  // on by default
    REQUIRE(settings.exact_automatic);
    const FrfResult frf = compute_frf(config.system, settings);
    REQUIRE(frf.polish);
    const PolishedBranch& polish = *frf.polish;
    INFO(polish.summary());
    CHECK(polish.failed == 0);  // through HB's three branches near w = 2.4 too
    CHECK(polish.unstable > 0);  // the middle one
    // The first lift-off (closed|lift-off), located where the flow does not chatter: on its
    // closed side the orbit grazes, the normal force N = 1 + 5 y2 (the preload 1, the node's
    // spring 5, y5 held at the wall) touching 0, so max |y2| = 1/5; the time integrator stays
    // closed 1e-3 below it and opens 1e-3 above it.
    CHECK(polish.unlocated_transitions == 0);
    int lift_offs = 0;
    for (std::size_t k = 0; k < frf.points.size(); ++k) {
        if (frf.points[k].kind != PointKind::transition || frf.points[k].boundary != Boundary::closed_lift_off) continue;
        ++lift_offs;
        const double w = frf.points[k].omega;
        INFO("closed|lift-off at w = " << w);
        CHECK(frf.metrics[k].contacts[0].separated_fraction == 0.0);
        CHECK(frf.metrics[k].output_max[1] == Approx(0.2).epsilon(1e-7));
        const PeriodicResponse below = integrated(config.system, w * (1.0 - 1e-3), 1024, config.outputs);
        const PeriodicResponse above = integrated(config.system, w * (1.0 + 1e-3), 1024, config.outputs);
        REQUIRE(below.converged);
        REQUIRE(above.converged);
        CHECK(below.contacts[0].separated_fraction == 0.0);
        CHECK(above.contacts[0].separated_fraction > 1e-3);
    }
    CHECK(lift_offs == 1);
    // Exact points near w = 1.2 (stick-slip) and 2.5 (lift-off) against the time integrator
    // converged in the step (independent of the event solver), started from rest: near 2.5 three
    // branches coexist, so the point compared is the nearest stable one on the integrator's
    // attractor (its open share within 0.05).
    for (double target : {1.2, 2.5}) {
        std::vector<std::size_t> candidates;
        for (std::size_t k = 0; k < frf.points.size(); ++k)
            if (frf.exact[k].status == PolishStatus::exact && frf.exact[k].stable) candidates.push_back(k);
        std::sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
            return std::abs(frf.points[a].omega - target) < std::abs(frf.points[b].omega - target);
        });
        bool compared = false;
        for (std::size_t i = 0; i < std::min<std::size_t>(candidates.size(), 6) && !compared; ++i) {
            const std::size_t best = candidates[i];
            const double omega = frf.points[best].omega;
            INFO("w = " << omega);
            REQUIRE(std::abs(omega - target) < 0.05);
            const PeriodicResponse reference = integrated(config.system, omega, 1024, config.outputs);
            REQUIRE(reference.converged);
            const ContactRegime& contact = frf.metrics[best].contacts[0];
            if (std::abs(contact.separated_fraction - reference.contacts[0].separated_fraction) > 0.05) continue;
            compared = true;
            CHECK(relative(frf.metrics[best].output_max[0], reference.output_max[0]) <= 2e-7);
            CHECK(relative(frf.metrics[best].output_amp1[0], reference.output_amp1[0]) <= 2e-7);
            CHECK(std::abs(contact.separated_fraction - reference.contacts[0].separated_fraction) <= 2e-3);
            if (target > 2.0) CHECK(contact.separated_fraction > 0.1);
        }
        CHECK(compared);
    }
}

TEST_CASE("rigid exact: a stop request ends the solve after the period it answers in, and the FRF polish there",
          "[rigid_exact]") {
    // The solve asks after every period it flows and stops at the first answer: the third.
    const System system = three_contacts(1.0);
    const ExactOrbit whole = rigid_periodic_orbit(system, 1.0, Eigen::VectorXd());
    REQUIRE(whole.converged);
    REQUIRE(whole.periods > 3);
    int asked = 0;
    ExactOptions options;
    options.stop = [&asked] { return ++asked >= 3 ? std::string("the time limit") : std::string(); };
    const ExactOrbit stopped = rigid_periodic_orbit(system, 1.0, Eigen::VectorXd(), options);
    CHECK_FALSE(stopped.converged);
    CHECK(stopped.stopped == "the time limit");
    CHECK(stopped.message.find("the time limit") != std::string::npos);
    CHECK(asked == 3);

    // The FRF's polish stopped after 8 orbits: those points are the whole run's exact ones, the
    // later ones harmonic balance's (the FRF without polish), status off; the branch is stopped.
    const SystemConfig config = read_system_config(liftoff3);
    FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);
    REQUIRE(settings.exact);
    const FrfResult exact = compute_frf(config.system, settings);
    FrfSettings plain_settings = settings;
    plain_settings.exact = false;
    const FrfResult plain = compute_frf(config.system, plain_settings);
    bool stop = false;
    settings.polish_progress = [&stop](int done, int) { stop = stop || done >= 8; };
    settings.continuation.stop = [&stop] { return stop ? std::string("interrupted") : std::string(); };
    const FrfResult partial = compute_frf(config.system, settings);
    REQUIRE(partial.polish);
    INFO(partial.polish->summary());
    CHECK(partial.polish->stopped == "interrupted");
    CHECK(partial.branch.status == ContinuationStatus::stopped);
    CHECK(partial.polish->polished >= 6);
    CHECK(partial.polish->polished <= 8);
    const auto at = [](const FrfResult& r, const SolutionPoint& p) {
        for (std::size_t k = 0; k < r.points.size(); ++k)
            if (r.points[k].omega == p.omega && r.points[k].kind == p.kind) return k;
        return r.points.size();
    };
    int off = 0;
    for (std::size_t k = 0; k < partial.points.size(); ++k) {
        const SolutionPoint& p = partial.points[k];
        INFO("w = " << p.omega << ": " << partial.exact[k].message);
        if (partial.exact[k].status == PolishStatus::exact) {
            CHECK(off == 0);  // no exact point after the stop
            const std::size_t j = at(exact, p);
            REQUIRE(j < exact.points.size());
            CHECK(partial.metrics[k].output_max[0] == exact.metrics[j].output_max[0]);
        } else {
            CHECK(partial.exact[k].status == PolishStatus::off);
            ++off;
            const std::size_t j = at(plain, p);
            REQUIRE(j < plain.points.size());
            CHECK(partial.metrics[k].output_max[0] == plain.metrics[j].output_max[0]);
        }
    }
    CHECK(off >= 10);
    CHECK(std::count(partial.verdict.notes.begin(), partial.verdict.notes.end(),
                     "not done after the stop: the exact polish's remaining points") == 1);
}

TEST_CASE("rigid exact: an exception inside an orbit's solve fails that orbit, not the FRF", "[rigid_exact]") {
    // The solver asks the stop request after every period it flows: while the fifth point is
    // polished, every question but the polish's own (asked before the orbit) throws, as a
    // contact model that cannot evaluate a state would. The FRF is written; the other points
    // are the uninterrupted polish's, and the fifth is failed with the exception's message or
    // exact from another start (the polish's second pass; in permanent stick, as there, another
    // member of the family of held positions).
    const SystemConfig config = read_system_config(liftoff3);
    FrfSettings settings = frf_settings(config.system, config.outputs, config.choices);
    REQUIRE(settings.exact);
    const FrfResult exact = compute_frf(config.system, settings);
    REQUIRE(exact.polish);
    REQUIRE(exact.polish->failed == 0);
    int asked = -1, thrown = 0;
    settings.polish_progress = [&asked](int done, int) { asked = done == 4 ? 0 : -1; };
    settings.continuation.stop = [&asked, &thrown]() -> std::string {
        if (asked >= 0 && ++asked >= 2) {
            ++thrown;
            throw std::runtime_error("the contact solve broke down");
        }
        return std::string();
    };
    const FrfResult frf = compute_frf(config.system, settings);
    REQUIRE(frf.polish);
    INFO(frf.polish->summary());
    CHECK(thrown >= 1);
    REQUIRE(frf.points.size() == exact.points.size());
    int failed = 0;
    for (std::size_t k = 0; k < frf.points.size(); ++k) {
        INFO("w = " << frf.points[k].omega << ": " << frf.exact[k].message);
        if (frf.exact[k].status == PolishStatus::failed) {
            ++failed;
            CHECK(k == 4);
            CHECK_THAT(frf.exact[k].message, Catch::Contains("the exact solver failed: the contact solve broke down"));
        } else if (k == 4) {
            CHECK(frf.exact[k].status == PolishStatus::exact);
        } else {
            CHECK(frf.exact[k].status == exact.exact[k].status);
            CHECK(relative(frf.metrics[k].output_max[0], exact.metrics[k].output_max[0]) <= 1e-7);
        }
    }
    CHECK(failed == frf.polish->failed);
    CHECK(failed <= 1);
}

// 3D contacts (a second tangential direction): the slip direction is a state, flowed by Taylor
// series (src/event_exact/cone_engine.hpp), the period map differentiated numerically.

TEST_CASE("rigid exact 3D: a chain whose motion stays in one plane has the 2D chain's orbit", "[rigid_exact]") {
    for (double omega : {1.0, 1.3}) {
        const ExactOrbit planar = rigid_periodic_orbit(bench::contact_chain(3, 1.0), omega, Eigen::VectorXd());
        REQUIRE(planar.converged);
        // started on the planar orbit (several orbits coexist): its DOFs in the 3D numbering
        Eigen::VectorXd start = Eigen::VectorXd::Zero(30);
        for (int half = 0; half < 2; ++half)
            for (int i = 0; i < 9; ++i) {
                const int mapped = i < 3 ? i : 6 + 3 * ((i - 3) / 2) + ((i - 3) % 2 == 0 ? 0 : 2);
                start(15 * half + mapped) = planar.state(9 * half + i);
            }
        const ExactOrbit spatial = rigid_periodic_orbit(bench::contact_chain_3d(3, 1.0, 0.0), omega, start);
        INFO("w = " << omega << ": " << planar.message << " / " << spatial.message);
        REQUIRE(planar.converged);
        REQUIRE(spatial.converged);
        REQUIRE(planar.switches > 6);
        CHECK(spatial.switches == planar.switches);
        for (int i = 0; i < 3; ++i) {  // the masses' x DOFs; their y DOFs stay at rest
            const auto k = static_cast<std::size_t>(i);
            CHECK(std::abs(spatial.y_amp1[k] - planar.y_amp1[k]) <= 1e-9 * planar.y_amp1[k]);
            CHECK(std::abs(spatial.y_max[k] - planar.y_max[k]) <= 1e-9 * planar.y_max[k]);
            CHECK(spatial.y_max[k + 3] <= 1e-12 * planar.y_max[k]);
        }
        for (std::size_t c = 0; c < 3; ++c) {
            CHECK(std::abs(spatial.contacts[c].stick_fraction - planar.contacts[c].stick_fraction) <= 1e-9);
            CHECK(std::abs(spatial.contacts[c].separated_fraction - planar.contacts[c].separated_fraction) <= 1e-9);
            CHECK(std::abs(spatial.contacts[c].energy - planar.contacts[c].energy) <= 1e-9 * planar.energy);
        }
        // the 3D multipliers (central differences of the period map) against the exact monodromy's
        CHECK(std::abs(spatial.max_multiplier - planar.max_multiplier) <= 1e-6);
        CHECK(spatial.stable == planar.stable);
    }
}

TEST_CASE("rigid exact 3D: nodes slipping along curved paths are the time integrator's limit", "[rigid_exact]") {
    // forces along both tangential directions, responses of different phase: the slip turns
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    for (double omega : {0.6, 2.0}) {
        const PeriodicResponse coarse = integrated(system, omega, 512, {});
        const PeriodicResponse fine = integrated(system, omega, 1024, {});
        REQUIRE(coarse.converged);
        REQUIRE(fine.converged);
        const ExactOrbit exact = rigid_periodic_orbit(system, omega, fine.state);
        INFO("w = " << omega << ": " << exact.message << ", " << exact.switches << " events");
        REQUIRE(exact.converged);
        REQUIRE(exact.stable);
        CHECK(exact.residual <= 1e-12);
        // the integrator is first order in the step with a turning slip: its error halves, and
        // its Richardson extrapolation 2 fine - coarse meets the exact orbit
        for (std::size_t i = 0; i < 6; ++i) {
            const double e_coarse = (coarse.y_amp1[i] - exact.y_amp1[i]) / exact.y_amp1[i];
            const double e_fine = (fine.y_amp1[i] - exact.y_amp1[i]) / exact.y_amp1[i];
            const double extrapolated = (2.0 * fine.y_amp1[i] - coarse.y_amp1[i] - exact.y_amp1[i]) / exact.y_amp1[i];
            INFO("DOF " << i + 1 << ": amp1 " << exact.y_amp1[i] << ", errors " << e_coarse << " -> " << e_fine
                        << ", extrapolated " << extrapolated);
            CHECK(std::abs(e_fine) <= 1e-4);
            CHECK(std::abs(extrapolated) <= 1e-6);
            CHECK((std::abs(e_fine) <= 0.6 * std::abs(e_coarse) || std::abs(e_fine) <= 1e-7));
        }
        const double step = 1.0 / 1024;
        for (std::size_t c = 0; c < 3; ++c) {
            INFO("contact " << c + 1);
            CHECK(std::abs(fine.contacts[c].stick_fraction - exact.contacts[c].stick_fraction) <= 3 * step);
            CHECK(std::abs(fine.contacts[c].separated_fraction - exact.contacts[c].separated_fraction) <= 3 * step);
        }
    }
}

TEST_CASE("rigid exact 3D: implicit collocation steps give the Taylor series' orbit", "[rigid_exact]") {
    // The same orbits by two integrations of the slip directions: Taylor series of order 30
    // (steps below rounding) and Radau IIA collocation (steps at a local error of 1e-12).
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    for (double omega : {0.6, 2.0}) {
        const ExactOrbit taylor = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), {}, ConeStepping::taylor);
        const ExactOrbit implicit = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), {}, ConeStepping::collocation);
        INFO("w = " << omega << ": " << taylor.message << " / " << implicit.message);
        REQUIRE(taylor.converged);
        REQUIRE(implicit.converged);
        CHECK(implicit.switches == taylor.switches);
        for (std::size_t i = 0; i < taylor.y_amp1.size(); ++i) {
            INFO("DOF " << i + 1);
            CHECK(std::abs(implicit.y_amp1[i] - taylor.y_amp1[i]) <= 1e-9 * taylor.y_amp1[0]);
            CHECK(std::abs(implicit.y_max[i] - taylor.y_max[i]) <= 1e-9 * taylor.y_max[0]);
        }
        for (std::size_t c = 0; c < 3; ++c) {
            INFO("contact " << c + 1);
            CHECK(std::abs(implicit.contacts[c].stick_fraction - taylor.contacts[c].stick_fraction) <= 1e-8);
            CHECK(std::abs(implicit.contacts[c].separated_fraction - taylor.contacts[c].separated_fraction) <= 1e-8);
        }
        CHECK(std::abs(implicit.energy - taylor.energy) <= 1e-8 * taylor.energy);
        CHECK(std::abs(implicit.max_multiplier - taylor.max_multiplier) <= 1e-5);
    }
}

TEST_CASE("rigid exact 3D: the force's work is what friction and damping take out", "[rigid_exact]") {
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    for (double omega : {0.6, 2.0}) {
        ExactOptions options;
        options.samples = 8192;
        const ExactOrbit orbit = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), options);
        INFO("w = " << omega << ": " << orbit.message);
        REQUIRE(orbit.converged);
        const double viscous = viscous_work(system, orbit, omega);
        CHECK(std::abs(orbit.input_energy - orbit.energy - viscous) <= 1e-7 * orbit.input_energy);
        CHECK(orbit.energy > 0.3 * orbit.input_energy);
    }
}

TEST_CASE("rigid exact 3D: the FRF's polish is off by default, with its reason, and on when asked", "[rigid_exact]") {
    const System spatial = bench::contact_chain_3d(3, 1.0, 0.8);
    CHECK(rigid_contacts_3d(spatial));
    CHECK_FALSE(rigid_contacts_3d(bench::contact_chain(3, 1.0)));
    const FrfSettings automatic = frf_settings(spatial, {Output::dof(0)});
    CHECK_FALSE(automatic.exact);
    CHECK_THAT(automatic.exact_note, Catch::Contains("off by default for 3D rigid contacts"));
    FrfChoices asked;
    asked.exact = true;
    CHECK(frf_settings(spatial, {Output::dof(0)}, asked).exact);
    CHECK(frf_settings(bench::contact_chain(3, 1.0), {Output::dof(0)}).exact);  // 2D: on
}

namespace {

/// The closed-form Jacobian of an implicit step's rates (ConeEngine::rates_jacobian) against
/// central differences of the rates, at the ends of `pieces` stretches of the flow from rest
/// with at least one slip direction moving: with respect to y, y', the moving directions, the
/// held positions of stuck contacts and (a second time, with the first moving direction held)
/// a held direction. Differences carry truncation (delta^2) and rounding (1 / delta): the best
/// of five steps is taken, per column relative to its largest entry. Returns the number of
/// states checked.
int check_rates_jacobian(const System& system, double omega, int pieces, double stretch) {
    using namespace detail::exact;
    ConeEngine e(system, omega);
    Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
    Modes modes = e.initial_modes(zhat);
    const int nm = e.dofs();
    double t = 0.0;
    int checked = 0;
    for (int piece = 0; piece < pieces; ++piece) {
        const PatternEngine::Flow f = e.flow(zhat, modes, t, stretch * e.period(), false, false, 5000);
        REQUIRE(f.ok);
        zhat = f.zhat;
        modes = f.modes;
        t += stretch * e.period();
        std::vector<int> moving, held;
        for (int q = 0; q < e.contacts(); ++q) {
            if (modes[static_cast<std::size_t>(q)] == ConeEngine::slip && e.directions(q) == 2) moving.push_back(q);
            if (modes[static_cast<std::size_t>(q)] == ConeEngine::stuck)
                for (int j = 0; j < e.directions(q); ++j) held.push_back(e.slider(q) + j);
        }
        if (moving.empty()) continue;
        const double size = std::max(zhat.head(nm).cwiseAbs().maxCoeff(), zhat.segment(nm, nm).cwiseAbs().maxCoeff() / omega);
        for (int variant = 0; variant < (moving.size() >= 2 ? 2 : 1); ++variant) {
            std::vector<char> frozen(static_cast<std::size_t>(e.contacts()), 0);
            if (variant == 1) frozen[static_cast<std::size_t>(moving.front())] = 1;
            std::vector<int> dyn;
            for (int k = 0; k < 2 * nm; ++k) dyn.push_back(k);
            for (int q : moving)
                if (!frozen[static_cast<std::size_t>(q)]) dyn.push_back(e.theta(q));
            std::vector<int> wrt = dyn;
            wrt.insert(wrt.end(), held.begin(), held.end());
            if (variant == 1) wrt.push_back(e.theta(moving.front()));
            const auto m = static_cast<Eigen::Index>(dyn.size());
            Eigen::MatrixXd J;
            Eigen::VectorXd rate;
            e.rates_jacobian(zhat, modes, frozen, dyn, wrt, J, rate);
            auto rates = [&](const Eigen::VectorXd& z) {
                const Eigen::MatrixXd c = e.series(z, modes, 0.0, 1, frozen, false, true);
                Eigen::VectorXd out(m);
                for (Eigen::Index k = 0; k < m; ++k) out(k) = c(dyn[static_cast<std::size_t>(k)], 1);
                return out;
            };
            CHECK((rate - rates(zhat)).cwiseAbs().maxCoeff() <= 1e-14 * rate.cwiseAbs().maxCoeff());
            for (std::size_t k = 0; k < wrt.size(); ++k) {
                const int i = wrt[k];
                // y in the state's size, y' in it times omega, held positions in the size,
                // directions in radians
                const double unit = i < nm ? size : i < 2 * nm ? size * omega : i < e.theta(0) ? size : 1.0;
                double best = std::numeric_limits<double>::infinity();
                for (double share : {1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
                    Eigen::VectorXd plus = zhat, minus = zhat;
                    plus(i) += share * unit;
                    minus(i) -= share * unit;
                    const Eigen::VectorXd column = (rates(plus) - rates(minus)) / (2.0 * share * unit);
                    const double scale = column.cwiseAbs().maxCoeff();
                    best = std::min(best, scale > 0.0 ? (J.col(static_cast<Eigen::Index>(k)) - column).cwiseAbs().maxCoeff() / scale
                                                      : J.col(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff());
                }
                INFO("t / T = " << t / e.period() << ", variant " << variant << ", column " << k << " of " << wrt.size()
                                << " (zhat entry " << i << ")");
                CHECK(best <= 1e-6);
            }
            ++checked;
        }
    }
    return checked;
}

}  // namespace

TEST_CASE("rigid exact 3D: the implicit steps' Jacobian in closed form is the rates' derivative", "[rigid_exact]") {
    // the chain (nodes coupled through the masses) and the mitre at 100 N (27 nodes coupled
    // through the interface's flexibility, up to 20 slip directions moving at once)
    CHECK(check_rates_jacobian(bench::contact_chain_3d(3, 1.0, 0.8), 0.6, 12, 1.0 / 12.0) >= 4);
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    mitre.system.excitation *= 10.0;
    CHECK(check_rates_jacobian(mitre.system, 16000.0, 8, 1.0 / 12.0) >= 4);
}

namespace {

/// The worst error of the flow's derivative over (from, pattern) at t for `duration` (the
/// flow f, with monodromy) against central differences of the flow itself, per column of the
/// start's independent entries (best of steps 1e-5, 1e-6, 1e-7 of their units), relative to the
/// rows' units; the differences taken where both perturbed flows meet the same events and end
/// in the same pattern (`compared` columns).
double flow_derivative_error(detail::exact::ConeEngine& e, const Eigen::VectorXd& from, const detail::exact::Modes& pattern,
                             double t, double duration, const detail::exact::PatternEngine::Flow& f, int& compared) {
    using namespace detail::exact;
    const int nm = e.dofs();
    const double omega = 2.0 * M_PI / e.period();
    REQUIRE(f.psi.rows() == e.n());
    const std::vector<int> start = e.independent(pattern), end = e.independent(f.modes);
    const double size = std::max(from.head(nm).cwiseAbs().maxCoeff(), from.segment(nm, nm).cwiseAbs().maxCoeff() / omega);
    auto unit_of = [&](int i) { return i < nm ? size : i < 2 * nm ? size * omega : i < e.theta(0) ? size : 1.0; };
    double worst = 0.0;
    compared = 0;
    for (int j : start) {
        double best = std::numeric_limits<double>::infinity();
        for (double share : {1e-5, 1e-6, 1e-7}) {
            Eigen::VectorXd plus = from, minus = from;
            plus(j) += share * unit_of(j);
            minus(j) -= share * unit_of(j);
            e.make_consistent(plus, pattern, t);
            e.make_consistent(minus, pattern, t);
            const PatternEngine::Flow fp = e.flow(plus, pattern, t, duration, false, false, 5000);
            const PatternEngine::Flow fm = e.flow(minus, pattern, t, duration, false, false, 5000);
            if (!fp.ok || !fm.ok || fp.modes != f.modes || fm.modes != f.modes || fp.events.size() != f.events.size() ||
                fm.events.size() != f.events.size())
                continue;
            double error = 0.0;  // per row of the end, relative to the row's unit
            for (int i : end) {
                const double difference = (fp.zhat(i) - fm.zhat(i)) / (2.0 * share * unit_of(j));
                error = std::max(error, std::abs(f.psi(i, j) - difference) * unit_of(j) / unit_of(i));
            }
            best = std::min(best, error);
        }
        if (!std::isfinite(best)) continue;
        worst = std::max(worst, best);
        ++compared;
    }
    return worst;
}

/// The flow's derivative with respect to its start's independent entries (ConeEngine::flow with
/// monodromy: Radau IIA on the variational equation along the steps, the saltation at events)
/// against central differences of the flow itself (flow_derivative_error), over stretches of
/// `stretch` periods, up to `wanted` of them: without events and with a slip direction moving,
/// or (through_events) with events, where at least half the columns compare. Returns the number
/// checked and adds the event kinds met to `kinds`.
int check_flow_derivative(const System& system, double omega, int pieces, double stretch, int wanted, bool through_events,
                          std::vector<std::pair<int, int>>* kinds = nullptr) {
    using namespace detail::exact;
    ConeEngine e(system, omega);
    Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
    Modes modes = e.initial_modes(zhat);
    const double duration = stretch * e.period();
    double t = 0.0;
    int checked = 0;
    for (int piece = 0; piece < pieces && checked < wanted; ++piece, t += duration) {
        const PatternEngine::Flow f = e.flow(zhat, modes, t, duration, true, false, 5000);
        REQUIRE(f.ok);
        const Eigen::VectorXd from = zhat;
        const Modes pattern = modes;
        zhat = f.zhat;
        modes = f.modes;
        const bool moving = std::any_of(pattern.begin(), pattern.end(), [](int m) { return m == ConeEngine::slip; });
        if (through_events ? f.events.empty() : (!f.events.empty() || !moving)) continue;
        int compared = 0;
        const double worst = flow_derivative_error(e, from, pattern, t, duration, f, compared);
        const int columns = static_cast<int>(e.independent(pattern).size());
        if (compared < columns / 2) continue;  // the perturbed flows met other events
        INFO("t / T = " << t / e.period() << ": " << f.events.size() << " events, " << compared << " of " << columns
                        << " columns compared, worst " << worst);
        CHECK(worst <= 1e-6);
        if (kinds)
            for (const ExactEvent& ev : f.events) kinds->emplace_back(ev.mode_before, ev.mode_after);
        ++checked;
    }
    return checked;
}

}  // namespace

TEST_CASE("rigid exact 3D: the collocation's Newton system split by A's eigenvalues is the whole system's",
          "[rigid_exact]") {
    // (I - h A (x) J) dZ = -G solved whole (size s m) and as s complex systems of size m
    // (radau.hpp), for tables of 2 to 7 stages (odd: a real eigenvalue; even: pairs only) and a
    // stiff J with complex eigenvalues.
    const int m = 7;
    Eigen::MatrixXd J(m, m), G(m, 1);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) J(i, j) = std::sin(1.0 + 3.0 * i + 7.0 * j) * (i == j ? 40.0 : 25.0);
    for (int stages = 2; stages <= 7; ++stages) {
        const detail::exact::RadauTable& R = detail::exact::radau_table(stages);
        const int s = R.stages;
        // A^-1 V = V diag(lambda)
        const Eigen::MatrixXcd a = R.a.cast<std::complex<double>>();
        CHECK((R.vectors - a * R.vectors * R.lambda.asDiagonal()).norm() <= 1e-12 * R.vectors.norm());
        G.resize(m, s);
        for (int i = 0; i < m; ++i)
            for (int k = 0; k < s; ++k) G(i, k) = std::cos(0.3 + i + 2.0 * k);
        for (double h : {1e-3, 0.05, 1.0}) {
            Eigen::MatrixXd M = Eigen::MatrixXd::Identity(s * m, s * m);
            for (int i = 0; i < s; ++i)
                for (int j = 0; j < s; ++j) M.block(i * m, j * m, m, m) -= (h * R.a(i, j)) * J;
            const Eigen::VectorXd whole = M.fullPivLu().solve(-Eigen::Map<const Eigen::VectorXd>(G.data(), G.size()));
            const Eigen::MatrixXcd rhs = -G * R.right;
            Eigen::MatrixXcd w(m, s);
            int solved = 0;
            for (int k = 0; k < s; ++k)
                if (R.partner(k) < 0) {
                    ++solved;
                    const Eigen::MatrixXcd K = R.lambda(k) * Eigen::MatrixXcd::Identity(m, m) - (h * J).cast<std::complex<double>>();
                    w.col(k) = K.fullPivLu().solve(rhs.col(k));
                }
            for (int k = 0; k < s; ++k)
                if (R.partner(k) >= 0) w.col(k) = w.col(R.partner(k)).conjugate();
            const Eigen::MatrixXd split = (w * R.vectors.transpose()).real();
            INFO(s << " stages, h = " << h);
            CHECK(solved == (s + 1) / 2);  // one system per conjugate pair, one per real eigenvalue
            CHECK((Eigen::Map<const Eigen::VectorXd>(split.data(), split.size()) - whole).norm() <= 1e-10 * whole.norm());
        }
    }
}

TEST_CASE("rigid exact 3D: a flow's derivative without events is its central differences", "[rigid_exact]") {
    CHECK(check_flow_derivative(bench::contact_chain_3d(3, 1.0, 0.8), 0.6, 48, 1.0 / 48.0, 3, false) >= 2);
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    mitre.system.excitation *= 10.0;
    CHECK(check_flow_derivative(mitre.system, 16000.0, 96, 1.0 / 192.0, 2, false) >= 1);
}

TEST_CASE("rigid exact 3D: a flow's derivative through events is its central differences", "[rigid_exact]") {
    // slip onsets from stick (1 -> 2), stops (2 -> 1), openings (2 -> 0) and closings into slip
    // along the consistent direction (0 -> 2) on the 3D chain
    std::vector<std::pair<int, int>> kinds;
    const System chain = bench::contact_chain_3d(3, 1.0, 0.8);
    CHECK(check_flow_derivative(chain, 0.6, 24, 1.0 / 24.0, 8, true, &kinds) >= 5);
    CHECK(check_flow_derivative(chain, 2.0, 24, 1.0 / 24.0, 6, true, &kinds) >= 4);
    for (const std::pair<int, int>& kind : {std::pair<int, int>{1, 2}, {2, 1}, {2, 0}, {0, 2}})
        CHECK(std::count(kinds.begin(), kinds.end(), kind) >= 1);
}

TEST_CASE("rigid exact 3D: a period's derivative at the orbit from its longest event-free stretch is its central differences",
          "[rigid_exact]") {
    // The derivative of the period map at the chain's orbit (w = 0.6, collocation steps) from
    // the middle of the longest event-free stretch (a section the Newton solver takes), against
    // central differences of the Taylor flow. That period meets a contact that closes into slip
    // and stops at the same instant (a cascade of two events): the second event's time is the
    // first's, not its own guard's root (its own gave an error of 1e4).
    using namespace detail::exact;
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    const double omega = 0.6;
    const ExactOrbit orbit = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), {}, ConeStepping::collocation);
    REQUIRE(orbit.converged);
    REQUIRE(orbit.events.size() >= 2);
    std::vector<std::pair<double, double>> stretches;  // (length, middle)
    for (std::size_t k = 0; k < orbit.events.size(); ++k) {
        const double from = orbit.events[k].time;
        const double to = k + 1 < orbit.events.size() ? orbit.events[k + 1].time : orbit.events.front().time + 2.0 * M_PI / omega;
        stretches.emplace_back(to - from, std::fmod(from + 0.5 * (to - from), 2.0 * M_PI / omega));
    }
    std::sort(stretches.rbegin(), stretches.rend());
    for (double t0 : {stretches.front().second}) {
        // the derivative of the collocation flow; the differences of the Taylor flow (steps below
        // rounding: the differences of adaptive collocation steps are noisy at 1e-5 .. 1e-3)
        ConeEngine e(system, omega), taylor(system, omega);
        e.set_stepping(ConeEngine::Stepping::collocation);
        taylor.set_stepping(ConeEngine::Stepping::taylor);
        const int N = system.dofs(), nm = e.dofs();
        const detail::MasslessContacts& split = e.split();
        Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
        for (int k = 0; k < nm; ++k) {
            zhat(k) = orbit.state(split.massive[static_cast<std::size_t>(k)]);
            zhat(nm + k) = orbit.state(N + split.massive[static_cast<std::size_t>(k)]);
        }
        const Eigen::VectorXd q = split.W.transpose() * detail::pick(Eigen::VectorXd(orbit.state.head(N)), split.massless);
        for (int c = 0; c < e.contacts(); ++c)
            for (int j = 0; j < e.directions(c); ++j) zhat(e.slider(c) + j) = q(e.tangential(c) + j);
        Modes modes = e.initial_modes(zhat);
        if (t0 > 0.0) {
            const PatternEngine::Flow to = e.flow(zhat, modes, 0.0, t0, false, false, 5000);
            REQUIRE(to.ok);
            zhat = to.zhat;
            modes = to.modes;
        }
        const PatternEngine::Flow f = e.flow(zhat, modes, t0, e.period(), true, false, 5000);
        REQUIRE(f.ok);
        REQUIRE(f.modes == modes);
        REQUIRE(f.psi.rows() == e.n());
        const std::vector<int> x = e.independent(modes);
        const auto nx = static_cast<Eigen::Index>(x.size());
        const double size = std::max(zhat.head(nm).cwiseAbs().maxCoeff(), zhat.segment(nm, nm).cwiseAbs().maxCoeff() / omega);
        auto unit_of = [&](int i) { return i < nm ? size : i < 2 * nm ? size * omega : i < e.theta(0) ? size : 1.0; };
        Eigen::MatrixXd psi(nx, nx), differences(nx, nx);
        double worst = 0.0;
        for (Eigen::Index b = 0; b < nx; ++b) {
            const int j = x[static_cast<std::size_t>(b)];
            for (Eigen::Index a = 0; a < nx; ++a) psi(a, b) = f.psi(x[static_cast<std::size_t>(a)], j);
            double best = std::numeric_limits<double>::infinity();
            for (double share : {1e-5, 1e-6, 1e-7}) {  // the differences' truncation against rounding
                const double delta = share * unit_of(j);
                Eigen::VectorXd plus = zhat, minus = zhat;
                plus(j) += delta;
                minus(j) -= delta;
                e.make_consistent(plus, modes, t0);
                e.make_consistent(minus, modes, t0);
                const PatternEngine::Flow fp = taylor.flow(plus, modes, t0, e.period(), false, false, 5000);
                const PatternEngine::Flow fm = taylor.flow(minus, modes, t0, e.period(), false, false, 5000);
                REQUIRE(fp.ok);
                REQUIRE(fm.ok);
                if (fp.events.size() != f.events.size() || fm.events.size() != f.events.size()) continue;
                Eigen::VectorXd column(nx);
                double error = 0.0;
                for (Eigen::Index a = 0; a < nx; ++a) {
                    const int i = x[static_cast<std::size_t>(a)];
                    column(a) = (fp.zhat(i) - fm.zhat(i)) / (2.0 * delta);
                    error = std::max(error, std::abs(psi(a, b) - column(a)) * unit_of(j) / unit_of(i));
                }
                if (error < best) {
                    best = error;
                    differences.col(b) = column;
                }
            }
            REQUIRE(std::isfinite(best));
            worst = std::max(worst, best);
        }
        INFO("section t / T = " << t0 / e.period() << ": " << f.events.size() << " events");
        CHECK(worst <= 1e-6);
        const double largest = Eigen::EigenSolver<Eigen::MatrixXd>(psi, false).eigenvalues().cwiseAbs().maxCoeff();
        const double reference = Eigen::EigenSolver<Eigen::MatrixXd>(differences, false).eigenvalues().cwiseAbs().maxCoeff();
        CHECK(std::abs(largest - reference) <= 1e-6);
    }
}

namespace {

/// Two masses, mirror images of each other (x_a = x_b, z_a = -z_b), each pressing a massless 3D
/// contact node onto a wall: x along the wall (excited equally), z across it (coupled to x by
/// +/-0.5, so the nodes slip along curved paths), the normal node of each tied to the other
/// mass's x. `asymmetry` scales the second node's tangential spring by 1 + asymmetry.
System mirror_pair(double asymmetry) {
    const int size = 10;  // x_a z_a x_b z_b (mass), then t1 t2 n of node a, of node b
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size), K = M, C = M;
    Eigen::VectorXd F = Eigen::VectorXd::Zero(size), S = F;
    for (int i = 0; i < 4; ++i) {
        M(i, i) = 1.0;
        C(i, i) = 0.02;
    }
    bench::add_spring(K, 0, 4, 3.0);
    bench::add_spring(K, 2, 7, 3.0 * (1.0 + asymmetry));
    bench::add_spring(K, 1, 5, 2.5);
    bench::add_spring(K, 3, 8, 2.5);
    bench::add_spring(K, 0, 2, 1.0);
    bench::add_spring(K, 1, 3, 0.8);
    bench::add_spring(K, 2, 6, 5.0);
    bench::add_spring(K, 0, 9, 5.0);
    K(0, 0) += 2.0;
    K(2, 2) += 2.0;
    K(1, 1) += 1.0;
    K(3, 3) += 1.0;
    K(0, 1) = K(1, 0) = 0.5;
    K(2, 3) = K(3, 2) = -0.5;
    S(6) = S(9) = 1.0;  // the preloads, and the structure pushed back
    S(2) = S(0) = -1.0;
    F(0) = F(2) = 1.0;
    std::vector<Contact> contacts;
    for (int a = 0; a < 2; ++a) {
        Contact k;
        k.law = parse_friction_law("unilateral");
        k.dof = 4 + 3 * a;
        k.values["friction_coefficient"] = 0.3;
        k.lists["second_direction"] = std::vector<double>(size, 0.0);
        k.lists["second_direction"][static_cast<std::size_t>(5 + 3 * a)] = 1.0;
        k.lists["normal_direction"] = std::vector<double>(size, 0.0);
        k.lists["normal_direction"][static_cast<std::size_t>(6 + 3 * a)] = 1.0;
        contacts.push_back(k);
    }
    return bench::assemble_system(M, K, C, F, S, std::move(contacts));
}

}  // namespace

TEST_CASE("rigid exact 3D: where mirror-image nodes change pattern at one instant the multipliers are the period map's",
          "[rigid_exact]") {
    // At w = 0.7 the mirror images' events coincide; with an asymmetry of 1e-9 rounding orders
    // them and the flow's derivative through them is far off (its largest multiplier was 4.8).
    // The check against a central difference sends the multipliers to differences there: they
    // equal the symmetric pair's (from the flow's derivative) and the others' to 1e-7.
    const ExactOrbit symmetric = rigid_periodic_orbit(mirror_pair(0.0), 0.7, Eigen::VectorXd());
    REQUIRE(symmetric.converged);
    REQUIRE(symmetric.switches >= 8);
    CHECK(symmetric.message.find("central differences") == std::string::npos);
    CHECK(std::abs(symmetric.y_amp1[0] - symmetric.y_amp1[2]) <= 1e-12 * symmetric.y_amp1[0]);
    CHECK(std::abs(symmetric.y_amp1[1] - symmetric.y_amp1[3]) <= 1e-12 * symmetric.y_amp1[0]);
    bool differenced = false;
    for (double asymmetry : {1e-10, 1e-9, 1e-8}) {
        const ExactOrbit orbit = rigid_periodic_orbit(mirror_pair(asymmetry), 0.7, Eigen::VectorXd());
        INFO("asymmetry " << asymmetry << ": " << orbit.message);
        REQUIRE(orbit.converged);
        const bool by_differences = orbit.message.find("central differences") != std::string::npos;
        differenced = differenced || by_differences;
        CHECK(std::abs(orbit.y_amp1[0] - symmetric.y_amp1[0]) <= 1e-7 * symmetric.y_amp1[0]);
        CHECK(std::abs(orbit.max_multiplier - symmetric.max_multiplier) <= 1e-7);
        CHECK(orbit.stable == symmetric.stable);
        if (by_differences) {  // Arnoldi's dominant multipliers: each one of the symmetric orbit's
            CHECK(orbit.message.find("Arnoldi") != std::string::npos);
            REQUIRE(orbit.multipliers.size() > 0);
            for (const std::complex<double>& mu : orbit.multipliers) {
                if (std::abs(mu) < 0.05) continue;
                double nearest = std::numeric_limits<double>::infinity();
                for (const std::complex<double>& nu : symmetric.multipliers) nearest = std::min(nearest, std::abs(mu - nu));
                INFO("multiplier " << mu);
                CHECK(nearest <= 1e-6);
            }
        }
    }
    CHECK(differenced);  // the check was met where the flow's derivative is off
    CHECK(symmetric.max_multiplier < 0.5);

    // Solved among the mirror-symmetric states (ExactOptions::mirror_symmetric): the same orbit
    // and multipliers (the flow's derivative, its part that commutes with the mirror); the
    // option says why it does nothing where the pair's symmetry is broken.
    ExactOptions among;
    among.mirror_symmetric = true;
    const ExactOrbit projected = rigid_periodic_orbit(mirror_pair(0.0), 0.7, Eigen::VectorXd(), among);
    INFO(projected.message);
    REQUIRE(projected.converged);
    CHECK(projected.message.find("among the mirror-symmetric states") != std::string::npos);
    CHECK(std::abs(projected.y_amp1[0] - symmetric.y_amp1[0]) <= 1e-10 * symmetric.y_amp1[0]);
    CHECK(std::abs(projected.y_amp1[1] - symmetric.y_amp1[1]) <= 1e-10 * symmetric.y_amp1[0]);
    CHECK(std::abs(projected.max_multiplier - symmetric.max_multiplier) <= 1e-9);
    const ExactOrbit broken = rigid_periodic_orbit(mirror_pair(1e-9), 0.7, Eigen::VectorXd(), among);
    INFO(broken.message);
    REQUIRE(broken.converged);
    CHECK(broken.message.find("not among the mirror-symmetric states: the structure has no mirror symmetry") !=
          std::string::npos);
}

TEST_CASE("rigid exact 3D: central differences on two threads give the one-thread orbit and multipliers",
          "[rigid_exact]") {
    // ExactOptions::threads = 2 flows each difference's two perturbed periods at once, the second
    // on a twin engine that follows the first's run state. Newton by GMRES and the multipliers by
    // Arnoldi, both on differences (forced), must give the one-thread run's orbit to Newton's
    // tolerance and its multipliers to the differences' accuracy, in the same periods.
    struct Case {
        System system;
        double omega;
    };
    for (const Case& c : {Case{bench::contact_chain_3d(3, 1.0, 0.8), 2.0}, Case{mirror_pair(1e-9), 0.7}}) {
        ExactOptions one, two;
        one.threads = 1;
        two.threads = 2;
        const ExactOrbit serial =
            rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), one, ConeStepping::automatic, ConeNewton::differences);
        const ExactOrbit parallel =
            rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), two, ConeStepping::automatic, ConeNewton::differences);
        INFO("w = " << c.omega << ": " << serial.message << " / " << parallel.message);
        REQUIRE(serial.converged);
        REQUIRE(parallel.converged);
        REQUIRE(serial.message.find("Arnoldi") != std::string::npos);
        CHECK(parallel.switches == serial.switches);
        CHECK(parallel.periods == serial.periods);
        CHECK(parallel.iterations == serial.iterations);
        for (std::size_t i = 0; i < serial.y_amp1.size(); ++i) {
            INFO("DOF " << i + 1);
            CHECK(std::abs(parallel.y_amp1[i] - serial.y_amp1[i]) <= 1e-10 * serial.y_amp1[0]);
            CHECK(std::abs(parallel.y_max[i] - serial.y_max[i]) <= 1e-10 * serial.y_max[0]);
        }
        CHECK(std::abs(parallel.max_multiplier - serial.max_multiplier) <= 1e-7);
        REQUIRE(parallel.multipliers.size() == serial.multipliers.size());
        for (const std::complex<double>& mu : parallel.multipliers) {
            double nearest = std::numeric_limits<double>::infinity();
            for (const std::complex<double>& nu : serial.multipliers) nearest = std::min(nearest, std::abs(mu - nu));
            INFO("multiplier " << mu);
            CHECK(nearest <= 1e-7);
        }
    }
    // Newton with the flow's derivative and Broyden's updates (the derivative's check at the
    // orbit by a central difference): the one-thread run's steps and multipliers.
    for (const Case& c : {Case{bench::contact_chain_3d(3, 1.0, 0.8), 0.6}, Case{mirror_pair(1e-9), 0.7}}) {
        ExactOptions one, two;
        one.threads = 1;
        two.threads = 2;
        const ExactOrbit serial = rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), one);
        const ExactOrbit parallel = rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), two);
        INFO("w = " << c.omega << ": " << serial.message << " / " << parallel.message);
        REQUIRE(serial.converged);
        REQUIRE(parallel.converged);
        CHECK(serial.iterations >= 2);
        CHECK(parallel.iterations == serial.iterations);
        CHECK(parallel.periods == serial.periods);
        CHECK(parallel.switches == serial.switches);
        for (std::size_t i = 0; i < serial.y_amp1.size(); ++i)
            CHECK(std::abs(parallel.y_amp1[i] - serial.y_amp1[i]) <= 1e-10 * serial.y_amp1[0]);
        CHECK(std::abs(parallel.max_multiplier - serial.max_multiplier) <= 1e-7);
    }
    ExactOptions three;
    three.threads = 3;
    CHECK_THROWS_WITH(rigid_periodic_orbit(bench::contact_chain_3d(3, 1.0, 0.8), 2.0, Eigen::VectorXd(), three),
                      Catch::Contains("exact threads = 3 is out of range"));
    // The FRF's setting (the polish's and the stability's exact solver), checked before any work.
    FrfSettings frf;
    frf.exact_threads = -1;
    CHECK_THROWS_WITH(frf.validate(), Catch::Contains("exact_threads = -1 is out of range: allowed 0"));
    frf.exact_threads = 1;
    CHECK_NOTHROW(frf.validate());
}

TEST_CASE("rigid exact 3D: Newton's steps by GMRES on central differences reach the flow's derivative's orbit",
          "[rigid_exact]") {
    // The path Newton takes where the flow's derivative is missing or a step with it fails,
    // forced from the first step (unpreconditioned GMRES on the period map minus the identity,
    // products by central differences): the same orbits, both to Newton's tolerance.
    struct Case {
        System system;
        double omega;
    };
    for (const Case& c : {Case{bench::contact_chain_3d(3, 1.0, 0.8), 0.6}, Case{bench::contact_chain_3d(3, 1.0, 0.8), 2.0},
                          Case{mirror_pair(1e-9), 0.7}}) {
        const ExactOrbit reference = rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd());
        const ExactOrbit krylov =
            rigid_periodic_orbit(c.system, c.omega, Eigen::VectorXd(), {}, ConeStepping::automatic, ConeNewton::differences);
        INFO("w = " << c.omega << ": " << reference.message << " / " << krylov.message);
        REQUIRE(reference.converged);
        REQUIRE(krylov.converged);
        CHECK(krylov.switches == reference.switches);
        for (std::size_t i = 0; i < reference.y_amp1.size(); ++i) {
            INFO("DOF " << i + 1);
            CHECK(std::abs(krylov.y_amp1[i] - reference.y_amp1[i]) <= 1e-9 * reference.y_amp1[0]);
            CHECK(std::abs(krylov.y_max[i] - reference.y_max[i]) <= 1e-9 * reference.y_max[0]);
        }
        const std::string tag = "central differences of the period map: ";
        const std::size_t at = krylov.message.find(tag);
        REQUIRE(at != std::string::npos);
        CHECK(std::stoi(krylov.message.substr(at + tag.size())) > 0);
        CHECK(krylov.iterations >= 1);
    }
}

TEST_CASE("rigid exact 3D: Newton's iterations are one budget over all attempts, and no restart is taken without any left",
          "[rigid_exact]") {
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    const double omega = 2.0;
    const ExactOrbit reference = rigid_periodic_orbit(system, omega, Eigen::VectorXd());
    INFO(reference.message);
    REQUIRE(reference.converged);
    REQUIRE(reference.iterations > 1);  // from rest Newton needs more than one step here
    // its own count of iterations is enough
    ExactOptions enough;
    enough.max_iterations = reference.iterations;
    const ExactOrbit exact = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), enough);
    CHECK(exact.converged);
    CHECK(exact.iterations == reference.iterations);
    // one iteration: spent by the first attempt, so the restarts' plain periods are not taken
    // (a restart from then could not iterate): the same periods as with no restart allowed
    ExactOptions one, one_alone;
    one.max_iterations = one_alone.max_iterations = 1;
    one_alone.restarts = 0;
    const ExactOrbit short_of = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), one);
    const ExactOrbit alone = rigid_periodic_orbit(system, omega, Eigen::VectorXd(), one_alone);
    INFO(short_of.message);
    CHECK_FALSE(short_of.converged);
    CHECK(short_of.message.find("Newton reached 1 iteration,") != std::string::npos);
    CHECK(short_of.iterations == 1);
    CHECK(short_of.periods == alone.periods);
}

namespace {

/// A saved exact orbit of the mitre (tests/data, benchmarks/mitre_exact --save-orbit): [y, y'].
/// Such a state is an orbit to the rounding of the machine that saved it; elsewhere the flow's
/// rounding differs (the same code, other bits), so a saved state must also replay from a
/// perturbation of that size: one at a knife-edge (nodes about to stick at the section, say)
/// replays only where it was made. The files here are checked so (relative 1e-12 either way).
Eigen::VectorXd mitre_state(const std::string& name, const System& system) {
    std::ifstream in(std::string(HBF_SOURCE_DIR) + "/tests/data/" + name);
    REQUIRE(in.good());
    std::vector<double> values;
    for (std::string line; std::getline(in, line);)
        if (!line.empty() && line[0] != '#') values.push_back(std::stod(line));
    REQUIRE(static_cast<int>(values.size()) == 2 * system.dofs());
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

/// The exact solver's options for the mitre's tests: its file's outputs, no maxima per DOF.
ExactOptions mitre_options(const SystemConfig& mitre) {
    ExactOptions options;
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    return options;
}

/// The mitre's exact orbit at omega (its file's force) from the state saved in tests/data/`name`,
/// each coordinate times 1 + `perturbation` (k mod 3 - 1) for its index k.
ExactOrbit saved_mitre_orbit(const std::string& name, double omega, double perturbation = 0.0,
                             ConeStepping stepping = ConeStepping::automatic) {
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    Eigen::VectorXd state = mitre_state(name, mitre.system);
    for (Eigen::Index k = 0; k < state.size(); ++k) state(k) *= 1.0 + perturbation * static_cast<double>(k % 3 - 1);
    ExactOptions options;
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    return rigid_periodic_orbit(mitre.system, omega, state, options, stepping);
}

/// An orbit of the mitre whose nodes stuck all period graze their cones: its multipliers are
/// its own events' (the message says so, not central differences), the family's structure
/// their independent reference: each node stuck all period has its held position free (two
/// tangential directions), multipliers at 1 to 1e-9; the rest of the orbit is damped. Stuck
/// all period counts the nodes whose grazes are slips of at most 1e-8 of the period (their
/// trigger a rounding's time before another contact's event): they slip no distance.
void check_grazing_family(const ExactOrbit& orbit) {
    int stuck = 0;
    double open = 0.0;
    for (const ContactRegime& c : orbit.contacts) {
        stuck += c.stick_fraction >= 1.0 - 1e-8;
        open = std::max(open, c.separated_fraction);
    }
    CHECK(stuck >= 10);
    CHECK(open > 0.01);
    CHECK(orbit.message.find("grazes") != std::string::npos);
    CHECK(orbit.message.find("central differences") == std::string::npos);
    int at_one = 0;
    double inside = 0.0;
    for (const std::complex<double>& mu : orbit.multipliers) {
        if (std::abs(mu - 1.0) <= 1e-9)
            ++at_one;
        else
            inside = std::max(inside, std::abs(mu));
    }
    // Nodes whose grazes are slips of up to 1e-4 of the period move their held positions by a
    // graze's slip at most: their multipliers may sit at 1 too.
    int grazing = 0;
    for (const ContactRegime& c : orbit.contacts) grazing += c.stick_fraction >= 1.0 - 1e-4 && c.separated_fraction == 0.0;
    INFO(stuck << " nodes stuck all period, " << grazing << " with grazes of up to 1e-4 of the period");
    CHECK(at_one >= 2 * stuck);
    CHECK(at_one <= 2 * grazing);
    CHECK(inside < 0.999);
    CHECK(orbit.stable);
}

}  // namespace

TEST_CASE("rigid exact 3D: the flow's derivative across a slipping node's lift-off within a Taylor step is its central differences",
          "[rigid_exact]") {
    // Near the mitre's resonance (w = 23,100 rad/s, from its symmetric orbit's y, y') slipping
    // nodes lift off within one Taylor step while their directions still move: at the step's end
    // a direction's rate is 0 / 0 (its node's normal force and the force's turning both zero to
    // rounding). Each lift-off of the first period without another event within 1e-4 of the
    // period: the flow over +-1e-4 of the period about it, its derivative against the flow's
    // central differences (flow_derivative_error: their own accuracy over such a window is a few
    // 1e-6). With the sensitivity's last stage at the step's end, the second of them (contact
    // 5) was 5e-2 off, and the derivative of the whole period along mirror-symmetric directions
    // 1e-1 off at the orbit (now 3e-6).
    using namespace detail::exact;
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const System& system = mitre.system;
    const Eigen::VectorXd state = mitre_state("mitre_orbit_23100.txt", system);
    ConeEngine e(system, 23100.0);
    Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
    {  // the DOFs with mass, and the nodes' tangential places as the contact problem's references
        const int N = system.dofs(), nm = e.dofs();
        const detail::MasslessContacts& split = e.split();
        for (int k = 0; k < nm; ++k) {
            zhat(k) = state(split.massive[static_cast<std::size_t>(k)]);
            zhat(nm + k) = state(N + split.massive[static_cast<std::size_t>(k)]);
        }
        const Eigen::VectorXd q = split.W.transpose() * detail::pick(Eigen::VectorXd(state.head(N)), split.massless);
        for (int c = 0; c < e.contacts(); ++c)
            for (int j = 0; j < e.directions(c); ++j) zhat(e.slider(c) + j) = q(e.tangential(c) + j);
    }
    const Modes modes = e.initial_modes(zhat);
    const double period = e.period(), half = 1e-4 * period;
    const PatternEngine::Flow whole = e.flow(zhat, modes, 0.0, period, false, false, 5000);
    REQUIRE(whole.ok);
    std::vector<double> alone;
    for (const ExactEvent& ev : whole.events) {
        if (ev.mode_before != ConeEngine::slip || ev.mode_after != ConeEngine::open) continue;
        const auto near = std::count_if(whole.events.begin(), whole.events.end(),
                                        [&](const ExactEvent& o) { return std::abs(o.time - ev.time) <= half; });
        if (near == 1 && ev.time > half) alone.push_back(ev.time);
    }
    REQUIRE(alone.size() >= 3);
    for (const double at : alone) {
        const PatternEngine::Flow to = e.flow(zhat, modes, 0.0, at - half, false, false, 5000);
        REQUIRE(to.ok);
        const PatternEngine::Flow across = e.flow(to.zhat, to.modes, at - half, 2.0 * half, true, false, 5000);
        REQUIRE(across.ok);
        REQUIRE(across.events.size() == 1);
        int compared = 0;
        const double worst = flow_derivative_error(e, to.zhat, to.modes, at - half, 2.0 * half, across, compared);
        INFO("lift-off at t / T = " << at / period << " (contact " << across.events.front().contact + 1 << "): " << compared
                                    << " columns compared, worst " << worst);
        CHECK(compared >= static_cast<int>(e.independent(to.modes).size()) / 4);
        CHECK(worst <= 1e-5);
    }
}

TEST_CASE("rigid exact 3D: where a node closes into slip as another sticks, the flow's derivative is the period map's",
          "[rigid_exact]") {
    // The mitre's orbit at 21,550 rad/s (its file's force: stick, slip and lift-off): a node
    // closes into slip (its normal force zero, its direction held) at the instant another one
    // sticks. The saltation of that second event must take the rates after it with the closed
    // node's direction still held, as the flow does (a free direction's rate divides by its zero
    // normal force); with the free rate the derivative's rows of that direction were off by 1e8
    // of their size and the period's derivative by 16 % along the test direction. Checked by the
    // solver itself: its derivative along a fixed direction against a central difference of the
    // period map, which here must agree (else the multipliers come from differences and the
    // message says so). The perturbations of 1e-6 meet other events (nodes within that of a
    // lift-off or a cone's edge): the check's steps of 1e-8 decide.
    const ExactOrbit orbit = saved_mitre_orbit("mitre_orbit_21550.txt", 21550.0);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.iterations <= 1);
    CHECK(orbit.switches >= 20);
    double open = 0.0;
    for (const ContactRegime& c : orbit.contacts) open = std::max(open, c.separated_fraction);
    CHECK(open > 0.1);
    CHECK(orbit.message.find("central differences") == std::string::npos);
    // the held positions of the nodes stuck all period: a family, multipliers at 1
    CHECK(std::abs(orbit.max_multiplier - 1.0) <= 1e-6);
    // The saved state is no knife-edge: from it perturbed by 1e-12 (another machine's rounding),
    // one Newton step to the same orbit (a member of the family 1e-12 away).
    for (double perturbation : {1e-12, -1e-12}) {
        const ExactOrbit moved = saved_mitre_orbit("mitre_orbit_21550.txt", 21550.0, perturbation);
        INFO("perturbed by " << perturbation << ": " << moved.message);
        REQUIRE(moved.converged);
        CHECK(moved.iterations <= 1);
        CHECK(moved.switches == orbit.switches);
        CHECK(std::abs(moved.output_max[0] - orbit.output_max[0]) <= 1e-9 * orbit.output_max[0]);
        CHECK(std::abs(moved.output_amp1[0] - orbit.output_amp1[0]) <= 1e-9 * orbit.output_amp1[0]);
    }
}

TEST_CASE("rigid exact 3D: the mitre's lift-off orbit by implicit collocation steps alone is the automatic stepping's",
          "[rigid_exact]") {
    // In lift-off the slip directions of nodes under small normal forces make some Taylor steps
    // short; the automatic stepping takes implicit steps only where they come in runs (a stiff
    // stretch), so on this orbit almost all its steps are Taylor series. Radau IIA collocation
    // alone (its own local error control, another integration of the same equations) must reach
    // the same orbit from the saved state: the same events, outputs to 1e-9.
    const ExactOrbit automatic = saved_mitre_orbit("mitre_orbit_21550.txt", 21550.0);
    const ExactOrbit implicit = saved_mitre_orbit("mitre_orbit_21550.txt", 21550.0, 0.0, ConeStepping::collocation);
    INFO(automatic.message << " / " << implicit.message);
    REQUIRE(automatic.converged);
    REQUIRE(implicit.converged);
    CHECK(implicit.switches == automatic.switches);
    CHECK(std::abs(implicit.output_max[0] - automatic.output_max[0]) <= 1e-9 * automatic.output_max[0]);
    CHECK(std::abs(implicit.output_amp1[0] - automatic.output_amp1[0]) <= 1e-9 * automatic.output_amp1[0]);
    for (std::size_t c = 0; c < automatic.contacts.size(); ++c) {
        CHECK(std::abs(implicit.contacts[c].stick_fraction - automatic.contacts[c].stick_fraction) <= 1e-9);
        CHECK(std::abs(implicit.contacts[c].separated_fraction - automatic.contacts[c].separated_fraction) <= 1e-9);
    }
}

TEST_CASE("rigid exact 3D: where stuck nodes graze their cones and nodes cascade, the multipliers are the orbit's own",
          "[rigid_exact]") {
    // The mitre's orbit at 21,550 rad/s (its file's force): the nodes stuck all period have
    // settled where their friction force just reaches its cone's edge at an instant (a
    // shakedown), so a perturbation of 1e-8 already makes them slip: the period map has a
    // kink at the orbit, and central differences straddle it. The multipliers are then the
    // orbit's own sequence of events' (the side the orbit is on). Two things must not send them
    // to differences: cascades (a node sticking at the instant another starts to slip or
    // closes: one caused by the other, settled in order) and a grazing node's trigger met with
    // another contact's event (its pattern kept: not an event). The family's structure is the
    // independent reference: each node stuck all period has its held position free (two
    // tangential directions), multipliers at 1 exactly; the rest of the orbit is damped.
    const ExactOrbit orbit = saved_mitre_orbit("mitre_orbit_21550.txt", 21550.0);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.iterations <= 1);
    bool cascade = false;  // events of two contacts at one instant
    for (std::size_t a = 0; a + 1 < orbit.events.size(); ++a)
        cascade = cascade || (orbit.events[a].contact != orbit.events[a + 1].contact &&
                              orbit.events[a].time == orbit.events[a + 1].time);
    CHECK(cascade);
    check_grazing_family(orbit);
}

TEST_CASE("rigid exact 3D: the sweep's step from a grazing orbit keeps the family's multipliers, the orbit's own",
          "[rigid_exact]") {
    // The sweep's step from the mitre's orbit at 21,550 to 21,574.17 rad/s (shakedown first): at
    // the orbit reached, nodes stuck all period graze their cones at the instants other nodes
    // lift off. Grazes at another contact's event are not two contacts' events coinciding
    // independently (where the root finding puts a graze a rounding's time before the lift-off,
    // the node slips for that long and the lift-off's cascade sticks it again: one graze too).
    // The multipliers must be the orbit's own (the family's structure, as above), not Arnoldi's
    // on central differences (about 120 more periods; those differences straddle the kink the
    // grazes make).
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    ExactOptions options = exact_sweep_options(mitre.system, ExactOptions{}, true);
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    const ExactOrbit orbit =
        rigid_periodic_orbit(mitre.system, 21574.1666666667, mitre_state("mitre_orbit_21550.txt", mitre.system), options);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.message.find("grazes") != std::string::npos);
    check_grazing_family(orbit);
    CHECK(orbit.periods <= 60);
}

TEST_CASE("a system's mirror symmetry: the mirror-image pair's and the mitre's, none where it is broken", "[rigid_exact]") {
    // The pair (x_a = x_b, z_a = -z_b): masses, node DOFs and contacts swapped, the z-like DOFs
    // (z, each node's second tangential direction) changing sign; none with the second node's
    // spring 1e-6 stiffer. The mitre (reduced inside hbf: 83 coordinates) mirrored about its
    // mid-plane: face node (j, k) onto (j, 2 - k) by make_block.py's numbering (the generator's
    // geometry, an independent reference), the structure's linear response to its load its own
    // mirror image, and a swept orbit whose face the sweep walked sideways not.
    const std::optional<detail::Mirror> pair = detail::find_mirror(mirror_pair(0.0));
    REQUIRE(pair.has_value());
    const std::vector<int> image = {2, 3, 0, 1, 7, 8, 9, 4, 5, 6};
    const std::vector<double> sign = {1, -1, 1, -1, 1, -1, 1, 1, -1, 1};
    CHECK(pair->image == image);
    CHECK(pair->sign == sign);
    CHECK(pair->contact_image == std::vector<int>({1, 0}));
    CHECK_FALSE(detail::find_mirror(mirror_pair(1e-6)).has_value());

    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const std::optional<detail::Mirror> mirror = detail::find_mirror(mitre.system);
    REQUIRE(mirror.has_value());
    REQUIRE(mirror->contact_image.size() == 27);
    for (int j = 0; j < 9; ++j)
        for (int k = 0; k < 3; ++k) CHECK(mirror->contact_image[static_cast<std::size_t>(3 * j + k)] == 3 * j + 2 - k);
    CHECK(mirror->swapped_pairs() == 27);  // 9 pairs of nodes, 3 DOFs each
    // The structure's linear response to its load (contacts aside) at 10,000 rad/s: symmetric.
    const System& m = mitre.system;
    const double w = 1e4;
    const Eigen::MatrixXcd dynamic = Eigen::MatrixXd(m.stiffness).cast<std::complex<double>>() -
                                     w * w * Eigen::MatrixXd(m.mass).cast<std::complex<double>>() +
                                     std::complex<double>(0.0, w) * Eigen::MatrixXd(m.damping).cast<std::complex<double>>();
    const Eigen::VectorXd linear = dynamic.partialPivLu().solve(m.excitation.cast<std::complex<double>>()).real();
    const double size = linear.cwiseAbs().maxCoeff();
    INFO("linear response " << size << ", offset " << detail::mirror_offset(*mirror, linear));
    CHECK(size > 1e-8);
    CHECK(detail::mirror_offset(*mirror, linear) <= 1e-10 * size);
    const Eigen::VectorXd walked = mitre_state("mitre_orbit_21550.txt", mitre.system).head(mitre.system.dofs());
    CHECK(detail::mirror_offset(*mirror, walked) >= 1e-6);
    // The face's tangential directions by the file's interface: t1 in the face across the bar
    // (kept by the mirror), t2 = n x t1 = z (reversed), the normal kept.
    for (const std::vector<double>& signs : mirror->direction_sign) CHECK(signs == std::vector<double>({1, -1, 1}));
    const std::optional<detail::Mirror> again = detail::find_mirror(mirror_pair(0.0));
    CHECK(again->direction_sign == std::vector<std::vector<double>>({{1, -1, 1}, {1, -1, 1}}));
}

TEST_CASE("rigid exact 3D: the mitre's symmetric orbit, solved among the mirror-symmetric states, is the whole map's",
          "[rigid_exact]") {
    // From the tests' saved orbit at 21,550 rad/s, whose face a sweep walked sideways (its held
    // positions far from mirror images), ExactOptions::mirror_symmetric solves for the family's
    // symmetric member: symmetric to rounding, converged. The independent check is the solver
    // without the option (Newton on every unknown, nothing projected) started from it: it is
    // that solver's orbit at once (at most two Newton iterations), the same to 1e-9 in the
    // output's maximum and first harmonic, and still symmetric. The walked start's own orbit is
    // another member (0.25 % apart in the maximum).
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const System& system = mitre.system;
    const int n = system.dofs();
    const std::optional<detail::Mirror> mirror = detail::find_mirror(system);
    REQUIRE(mirror.has_value());
    auto offset = [&](const Eigen::VectorXd& state) {
        return std::max(detail::mirror_offset(*mirror, state.head(n)), detail::mirror_offset(*mirror, state.segment(n, n)) / 21550.0);
    };
    ExactOptions options;
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    options.mirror_symmetric = true;
    const Eigen::VectorXd walked = mitre_state("mitre_orbit_21550.txt", system);
    const ExactOrbit symmetric = rigid_periodic_orbit(system, 21550.0, walked, options);
    INFO(symmetric.message);
    REQUIRE(symmetric.converged);
    CHECK(symmetric.message.find("among the mirror-symmetric states") != std::string::npos);
    const double size = symmetric.state.head(n).cwiseAbs().maxCoeff();
    CHECK(offset(symmetric.state) <= 1e-12 * size);
    CHECK(offset(walked) >= 1e-6);

    options.mirror_symmetric = false;
    const ExactOrbit whole = rigid_periodic_orbit(system, 21550.0, symmetric.state, options);
    INFO(whole.message);
    REQUIRE(whole.converged);
    CHECK(whole.iterations <= 2);
    CHECK(std::abs(whole.output_max[0] - symmetric.output_max[0]) <= 1e-9 * symmetric.output_max[0]);
    CHECK(std::abs(whole.output_amp1[0] - symmetric.output_amp1[0]) <= 1e-9 * symmetric.output_amp1[0]);
    CHECK(offset(whole.state) <= 1e-10 * size);
    const ExactOrbit other = rigid_periodic_orbit(system, 21550.0, walked, options);
    REQUIRE(other.converged);
    CHECK(std::abs(other.output_max[0] - symmetric.output_max[0]) >= 1e-3 * symmetric.output_max[0]);
    CHECK(offset(other.state) >= 1e-6);
}

TEST_CASE("rigid exact 3D: Arnoldi's multipliers with the nodes stuck all period held are the flow's derivative's",
          "[rigid_exact]") {
    // Where the flow's derivative is unusable (mirror-image events) the multipliers are Arnoldi's
    // on central differences of the period map, with the nodes stuck all period held through
    // them and their held positions left out (multipliers 1 each, not a cluster for Arnoldi to
    // resolve). Asked for on the mitre's orbit at 21,550 rad/s (a dozen nodes stuck all period,
    // the others slipping and lifting off), they must be the flow's derivative's (the other
    // path, independent code: the variational equation and the saltations): the converged
    // Ritz values among its multipliers, as many 1s as held positions, the largest modulus.
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const ExactOptions options = mitre_options(mitre);
    const Eigen::VectorXd state = mitre_state("mitre_orbit_21550.txt", mitre.system);
    const ExactOrbit own = rigid_periodic_orbit(mitre.system, 21550.0, state, options);
    const ExactOrbit arnoldi =
        rigid_periodic_orbit(mitre.system, 21550.0, state, options, ConeStepping::automatic, ConeNewton::differences);
    INFO(own.message << " / " << arnoldi.message);
    REQUIRE(own.converged);
    REQUIRE(arnoldi.converged);
    CHECK(std::abs(arnoldi.output_max[0] - own.output_max[0]) <= 1e-9 * own.output_max[0]);
    const std::string tag = ", with the ";
    const std::size_t at = arnoldi.message.find(tag);
    REQUIRE(at != std::string::npos);
    const int held = std::stoi(arnoldi.message.substr(at + tag.size()));
    int stuck = 0;
    for (const ContactRegime& c : own.contacts) stuck += c.stick_fraction == 1.0;
    CHECK(held == 2 * stuck);
    CHECK(stuck >= 10);
    int ones = 0, compared = 0;
    for (const std::complex<double>& mu : arnoldi.multipliers) {
        if (mu == std::complex<double>(1.0, 0.0)) {
            ++ones;
            continue;
        }
        if (std::abs(mu) < 0.05) continue;
        double nearest = std::numeric_limits<double>::infinity();
        for (const std::complex<double>& nu : own.multipliers) nearest = std::min(nearest, std::abs(mu - nu));
        INFO("multiplier " << mu);
        CHECK(nearest <= 1e-6);
        ++compared;
    }
    CHECK(ones >= held);
    CHECK(compared >= 5);
    CHECK(std::abs(arnoldi.max_multiplier - own.max_multiplier) <= 1e-7);
}

TEST_CASE("rigid exact 3D: a symmetric orbit's multipliers by the mirror's halves are Arnoldi's on the whole map",
          "[rigid_exact]") {
    // The mitre's symmetric orbit at 22,700 rad/s (stick, slip and lift-off; mirror-image nodes
    // change pattern at one instant, so the flow's derivative is off along a generic direction):
    // its period map's derivative commutes with the mirror, and the multipliers are the
    // symmetric changes' (the flow's derivative, confirmed along a symmetric direction) and the
    // antisymmetric changes' (Arnoldi on central differences, about half the free unknowns).
    // The reference is Arnoldi on central differences over all the free unknowns (asked for:
    // ConeNewton::differences), which knows nothing of the mirror: each of its converged
    // multipliers must be one of the halves', the largest the same, in fewer products.
    // Along antisymmetric changes the period map is only piecewise smooth at the orbit (the
    // mirror images' events part either way), and central differences there depend on the
    // direction: on this orbit the whole difference matrix (unit directions, 128 periods) and
    // Arnoldi's two Krylov spaces give those multipliers 1e-4 apart (measured: up to 2.6e-4),
    // while the symmetric changes' agree to 2e-7. The tolerances are set so.
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    ExactOptions options = mitre_options(mitre);
    options.mirror_symmetric = true;
    const Eigen::VectorXd state = mitre_state("mitre_orbit_22700.txt", mitre.system);
    const ExactOrbit halves = rigid_periodic_orbit(mitre.system, 22700.0, state, options);
    INFO(halves.message);
    REQUIRE(halves.converged);
    const std::string tag = "the symmetric changes' ";
    const std::size_t at = halves.message.find(tag);
    REQUIRE(at != std::string::npos);
    const int symmetric = std::stoi(halves.message.substr(at + tag.size()));
    REQUIRE(symmetric > 0);
    const ExactOrbit whole =
        rigid_periodic_orbit(mitre.system, 22700.0, halves.state, options, ConeStepping::automatic, ConeNewton::differences);
    INFO(whole.message);
    REQUIRE(whole.converged);
    REQUIRE(whole.message.find("by differences as asked") != std::string::npos);
    CHECK(std::abs(whole.output_max[0] - halves.output_max[0]) <= 1e-9 * halves.output_max[0]);
    auto products = [](const std::string& message) {
        const std::size_t end = message.find(" products");
        REQUIRE(end != std::string::npos);
        const std::size_t from = message.rfind(' ', end - 1);
        return std::stoi(message.substr(from + 1, end - from - 1));
    };
    CHECK(products(halves.message) < products(whole.message));
    int compared = 0, by_derivative = 0;
    for (const std::complex<double>& mu : whole.multipliers) {
        if (mu == std::complex<double>(1.0, 0.0) || std::abs(mu) < 0.05) continue;
        double nearest = std::numeric_limits<double>::infinity();
        Eigen::Index which = -1;
        for (Eigen::Index k = 0; k < halves.multipliers.size(); ++k)
            if (std::abs(mu - halves.multipliers(k)) < nearest) {
                nearest = std::abs(mu - halves.multipliers(k));
                which = k;
            }
        INFO("multiplier " << mu << ", the halves' " << halves.multipliers(which));
        const bool from_derivative = which < symmetric;
        CHECK(nearest <= (from_derivative ? 1e-6 : 5e-4));
        by_derivative += from_derivative;
        ++compared;
    }
    CHECK(compared >= 10);
    CHECK(by_derivative >= 4);
    CHECK(std::abs(whole.max_multiplier - halves.max_multiplier) <= 1e-6);
}

TEST_CASE("rigid exact 3D: one copy of the contact rows serves every pattern", "[rigid_exact]") {
    // The recorded vector's rows do not depend on the pattern: the engine's memory must not grow
    // with the patterns a flow meets (thousands a period on a meshed interface).
    using namespace detail::exact;
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    ConeEngine e(system, 0.6);
    const ModeData& first = e.mode(Modes{ConeEngine::open, ConeEngine::stuck, ConeEngine::slip});
    const ModeData& second = e.mode(Modes{ConeEngine::slip, ConeEngine::open, ConeEngine::stuck});
    CHECK(&first == &second);
    const PatternEngine::Flow f = [&] {
        Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
        const Modes modes = e.initial_modes(zhat);
        return e.flow(zhat, modes, 0.0, e.period(), false, false, 5000);
    }();
    REQUIRE(f.ok);
    REQUIRE(f.events.size() >= 2);  // patterns met
    CHECK(e.cached(f.modes) == &first);
}

TEST_CASE("rigid exact: the section's norm compares slip directions modulo a turn", "[rigid_exact]") {
    // [y (2), y' (2), a held position, two angles]: a direction that turned by a whole turn has
    // not changed; displacements are judged against the state's size, angles in radians.
    using namespace detail::exact;
    SectionNorm norm{2, 10.0, 0.0};
    norm.angles = 2;
    Eigen::VectorXd start(7), end(7);
    start << 1e-6, -2e-6, 1e-5, 0.0, 3e-7, 0.5, -3.0;
    end = start;
    end(5) += 2.0 * M_PI;
    end(6) -= 4.0 * M_PI;
    CHECK(norm.relative_change(end, start) <= 1e-15);
    CHECK(norm.size(start) == Approx(2e-6));  // y' / omega = 1e-6; the angles left out
    end(0) += 2e-12;  // 1e-6 of the size
    CHECK(norm.relative_change(end, start) == Approx(1e-6));
    end(6) += 1e-3;  // an angle's change in radians, where larger
    CHECK(norm.relative_change(end, start) == Approx(1e-3));
    CHECK(norm.difference(end, start)(6) == Approx(1e-3));
}

namespace {

/// One mass (DOF 0) pressing a massless 3D contact node (DOFs 1, 2 along the wall, 3 across)
/// through a tangential spring k_t and a normal spring k_n, preload p. After a lift-off the
/// node closes with no force, and its stuck force then grows along the ray
/// lambda_T / lambda_N = k_t / k_n: with k_t = mu k_n exactly on the friction cone's edge, where
/// stick and a slip of no speed are the same motion and each pattern's limit is met by rounding.
System cone_edge_node(double mu, double k_t, double k_n) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(4, 4), K = M, C = M;
    M(0, 0) = 1.0;
    C(0, 0) = 0.05;
    K(0, 0) = 1.0;
    bench::add_spring(K, 0, 1, k_t);
    bench::add_spring(K, 0, 3, k_n);
    K(2, 2) = 1.0;  // the second tangential node rests
    Eigen::VectorXd F = Eigen::VectorXd::Zero(4), S = F;
    F(0) = 1.0;
    S(3) = 0.2;  // the node onto the wall
    S(0) = -0.2;
    Contact k;
    k.law = parse_friction_law("unilateral");
    k.dof = 1;
    k.values["friction_coefficient"] = mu;
    k.lists["second_direction"] = {0.0, 0.0, 1.0, 0.0};
    k.lists["normal_direction"] = {0.0, 0.0, 0.0, 1.0};
    return bench::assemble_system(M, K, C, F, S, {k});
}

}  // namespace

TEST_CASE("rigid exact 3D: a node closing onto its friction cone's edge neither chatters nor slips", "[rigid_exact]") {
    // Reference: the same node with twice the friction coefficient, whose stuck force stays
    // strictly inside the cone after each closing; the orbits are the same motion (the lift-off
    // every period erases the start's different history).
    const double omega = 1.3, k_n = 1.7;
    for (double mu : {0.3, 0.36, 0.7}) {
        ExactOptions options;
        options.outputs = {Output::dof(0)};
        const ExactOrbit edge = rigid_periodic_orbit(cone_edge_node(mu, mu * k_n, k_n), omega, Eigen::VectorXd(), options);
        const ExactOrbit inside =
            rigid_periodic_orbit(cone_edge_node(2.0 * mu, mu * k_n, k_n), omega, Eigen::VectorXd(), options);
        INFO("mu = " << mu << ": edge: " << edge.message << ", " << edge.switches << " events; inside: " << inside.message
                     << ", " << inside.switches << " events");
        REQUIRE(inside.converged);
        REQUIRE(edge.converged);
        REQUIRE(inside.contacts.size() == 1);
        CHECK(inside.contacts[0].separated_fraction > 0.1);  // it lifts off every period
        CHECK(inside.contacts[0].stick_fraction > 0.1);
        CHECK(std::abs(edge.output_max[0] - inside.output_max[0]) <= 1e-9 * inside.output_max[0]);
        CHECK(std::abs(edge.output_amp1[0] - inside.output_amp1[0]) <= 1e-9 * inside.output_amp1[0]);
        CHECK(std::abs(edge.contacts[0].separated_fraction - inside.contacts[0].separated_fraction) <= 1e-9);
        CHECK(edge.switches <= 4);
    }
}

TEST_CASE("rigid exact 3D: Newton's matrix over a period that ends in another pattern is its central differences",
          "[rigid_exact]") {
    // Far from the orbit a period ends in another pattern: the held position of a contact no
    // longer stuck is then its tangential displacement (end_derivative: the chain rule through
    // the contact forces), against central differences of the Taylor flow. The direction of a
    // contact no longer slipping is held by convention (its row zero) and not compared.
    using namespace detail::exact;
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    const double omega = 0.6;
    ConeEngine e(system, omega);
    e.set_stepping(ConeEngine::Stepping::taylor);
    const int nm = e.dofs();
    // a transient from rest: the first period whose end pattern differs from its start's
    Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
    Modes modes = e.initial_modes(zhat);
    PatternEngine::Flow f;
    bool found = false;
    for (int p = 0; p < 6 && !found; ++p) {
        zhat(e.cos_index()) = 1.0;
        zhat(e.sin_index()) = 0.0;
        f = e.flow(zhat, modes, 0.0, e.period(), true, false, 5000);
        REQUIRE(f.ok);
        if (f.modes != modes && f.psi.size() > 0) {
            found = true;
            break;
        }
        zhat = f.zhat;
        modes = f.modes;
    }
    REQUIRE(found);
    std::vector<Eigen::Index> unknowns;
    for (int k = 0; k < 2 * nm; ++k) unknowns.push_back(k);
    for (int c = 0; c < e.contacts(); ++c)
        if (modes[static_cast<std::size_t>(c)] == ConeEngine::stuck)
            for (int j = 0; j < e.directions(c); ++j) unknowns.push_back(e.slider(c) + j);
    for (int c = 0; c < e.contacts(); ++c)
        if (modes[static_cast<std::size_t>(c)] == ConeEngine::slip) unknowns.push_back(e.theta(c));
    const Eigen::MatrixXd d = end_derivative(e, f, unknowns);
    const auto nu = static_cast<Eigen::Index>(unknowns.size());
    // the rows compared: all but the directions of contacts no longer slipping
    std::vector<char> compared(static_cast<std::size_t>(nu), 1);
    int released = 0;  // held positions of contacts no longer stuck
    for (Eigen::Index k = 0; k < nu; ++k) {
        const auto i = unknowns[static_cast<std::size_t>(k)];
        for (int c = 0; c < e.contacts(); ++c) {
            if (i == e.theta(c) && f.modes[static_cast<std::size_t>(c)] != ConeEngine::slip) compared[static_cast<std::size_t>(k)] = 0;
            if (i >= e.slider(c) && i < e.slider(c) + e.directions(c) && f.modes[static_cast<std::size_t>(c)] != ConeEngine::stuck)
                ++released;
        }
    }
    // the state's size over the period (a start at rest has none)
    const double size = std::max({zhat.head(nm).cwiseAbs().maxCoeff(), zhat.segment(nm, nm).cwiseAbs().maxCoeff() / omega,
                                  f.zhat.head(nm).cwiseAbs().maxCoeff(), f.zhat.segment(nm, nm).cwiseAbs().maxCoeff() / omega});
    REQUIRE(size > 0.0);
    auto unit_of = [&](Eigen::Index i) { return i < nm ? size : i < 2 * nm ? size * omega : i < e.theta(0) ? size : 1.0; };
    double worst = 0.0;
    for (Eigen::Index b = 0; b < nu; ++b) {
        const auto j = unknowns[static_cast<std::size_t>(b)];
        double best = std::numeric_limits<double>::infinity();
        for (double share : {1e-5, 1e-6, 1e-7}) {
            const double delta = share * unit_of(j);
            Eigen::VectorXd plus = zhat, minus = zhat;
            plus(j) += delta;
            minus(j) -= delta;
            e.make_consistent(plus, modes, 0.0);
            e.make_consistent(minus, modes, 0.0);
            const PatternEngine::Flow fp = e.flow(plus, modes, 0.0, e.period(), false, false, 5000);
            const PatternEngine::Flow fm = e.flow(minus, modes, 0.0, e.period(), false, false, 5000);
            REQUIRE(fp.ok);
            REQUIRE(fm.ok);
            if (fp.events.size() != f.events.size() || fm.events.size() != f.events.size() || fp.modes != f.modes ||
                fm.modes != f.modes)
                continue;
            double error = 0.0;
            for (Eigen::Index a = 0; a < nu; ++a) {
                if (!compared[static_cast<std::size_t>(a)]) continue;
                const auto i = unknowns[static_cast<std::size_t>(a)];
                const double column = (fp.zhat(i) - fm.zhat(i)) / (2.0 * delta);
                REQUIRE(std::isfinite(column));
                error = std::max(error, std::abs(d(a, b) - column) * unit_of(j) / unit_of(i));
            }
            best = std::min(best, error);
        }
        REQUIRE(std::isfinite(best));
        worst = std::max(worst, best);
    }
    INFO(f.events.size() << " events, " << released << " held positions of contacts no longer stuck");
    CHECK(released > 0);
    CHECK(worst <= 1e-6);
}

namespace {

/// The mitre's structure with every contact DOF held (its stuck structure), from M, C, K alone:
/// the DOFs with mass no contact direction touches (`mass_dofs`), the massless ones (the loaded
/// DOF, condensed), the state matrix of the mass DOFs and its eigenvalues.
struct MitreStuck {
    std::vector<int> mass_dofs, massless;
    Eigen::MatrixXd Mm, Cm, Keff, Kmb, Kbb;
    Eigen::VectorXcd lambda;
};

Eigen::MatrixXd mitre_block(const Eigen::MatrixXd& A, const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd out(rows.size(), cols.size());
    for (std::size_t r = 0; r < rows.size(); ++r)
        for (std::size_t c = 0; c < cols.size(); ++c) out(r, c) = A(rows[r], cols[c]);
    return out;
}

MitreStuck mitre_stuck(const System& system) {
    const int N = system.dofs();
    std::vector<char> held(static_cast<std::size_t>(N), 0);
    for (const Contact& c : system.contacts) {
        const Eigen::MatrixXd w = system.contact_directions(c);
        for (int i = 0; i < N; ++i)
            if (w.row(i).cwiseAbs().maxCoeff() > 0.0) held[static_cast<std::size_t>(i)] = 1;
    }
    const Eigen::MatrixXd M(system.mass), K(system.stiffness), C(system.damping);
    MitreStuck s;
    for (int i = 0; i < N; ++i)
        if (!held[static_cast<std::size_t>(i)]) (M.row(i).cwiseAbs().maxCoeff() > 0.0 ? s.mass_dofs : s.massless).push_back(i);
    REQUIRE(s.mass_dofs.size() == 10);
    REQUIRE(s.massless.size() == 1);
    s.Kbb = mitre_block(K, s.massless, s.massless);
    s.Kmb = mitre_block(K, s.mass_dofs, s.massless);
    s.Keff = mitre_block(K, s.mass_dofs, s.mass_dofs) - s.Kmb * s.Kbb.inverse() * s.Kmb.transpose();
    REQUIRE(mitre_block(C, s.massless, s.massless).cwiseAbs().maxCoeff() == 0.0);
    REQUIRE(mitre_block(C, s.mass_dofs, s.massless).cwiseAbs().maxCoeff() == 0.0);
    s.Mm = mitre_block(M, s.mass_dofs, s.mass_dofs);
    s.Cm = mitre_block(C, s.mass_dofs, s.mass_dofs);
    const int m = static_cast<int>(s.mass_dofs.size());
    // the state matrix in [y, y' / w_ref] (w_ref^2 = the largest |K_eff / M|): the same
    // eigenvalues, computed to ~1e-12 of them where in [y, y'] the spread of the entries costs 1e-9
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * m, 2 * m);
    const double scale = std::sqrt((s.Mm.inverse() * s.Keff).cwiseAbs().maxCoeff());
    A.topRightCorner(m, m) = scale * Eigen::MatrixXd::Identity(m, m);
    A.bottomLeftCorner(m, m) = -s.Mm.inverse() * s.Keff / scale;
    A.bottomRightCorner(m, m) = -s.Mm.inverse() * s.Cm;
    s.lambda = Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues();
    return s;
}

/// The orbit's multipliers off the unit circle against exp(Re(lambda) T) of the stuck
/// structure (moduli, sorted) to 1e-9 (both agree to ~1e-11; the multipliers of the period
/// map's derivative unbalanced were 1e-7 off), and the rest within 1e-6 of 1 (the held
/// positions' family).
void check_stuck_multipliers(const MitreStuck& s, const ExactOrbit& orbit) {
    const double period = 2.0 * M_PI / orbit.omega;
    std::vector<double> expected, found, neutral;
    for (Eigen::Index k = 0; k < s.lambda.size(); ++k) expected.push_back(std::exp(s.lambda(k).real() * period));
    for (Eigen::Index k = 0; k < orbit.multipliers.size(); ++k) {
        const double modulus = std::abs(orbit.multipliers(k));
        (std::abs(modulus - 1.0) <= 1e-6 ? neutral : found).push_back(modulus);
    }
    std::sort(expected.begin(), expected.end());
    std::sort(found.begin(), found.end());
    REQUIRE(found.size() == expected.size());
    for (std::size_t k = 0; k < found.size(); ++k) {
        INFO("multiplier modulus " << found[k] << ", the stuck structure's " << expected[k] << ", apart " << found[k] - expected[k]);
        CHECK(std::abs(found[k] - expected[k]) <= 1e-9);
    }
    CHECK(neutral.size() == static_cast<std::size_t>(orbit.multipliers.size()) - expected.size());
}

/// A sweep's step on the mitre (10 N, its outputs' maxima only): the orbit at `to` from the
/// orbit at `from`, solved from rest.
struct MitreStep {
    SystemConfig config;
    ExactOrbit orbit;
};

/// The stuck structure's first harmonic of the file's first output at omega, (K_eff - w^2 M + i w
/// C) y = F with the massless DOF condensed, from M, C, K alone.
double stuck_output_amplitude(const SystemConfig& mitre, const MitreStuck& s, double omega) {
    const System& system = mitre.system;
    const auto m = static_cast<Eigen::Index>(s.mass_dofs.size());
    const std::complex<double> i(0.0, 1.0);
    Eigen::VectorXcd Fm(m), Fb(1);
    for (Eigen::Index k = 0; k < m; ++k) Fm(k) = system.excitation(s.mass_dofs[static_cast<std::size_t>(k)]);
    Fb(0) = system.excitation(s.massless[0]);
    const Eigen::MatrixXcd A = s.Keff.cast<std::complex<double>>() - omega * omega * s.Mm.cast<std::complex<double>>() +
                               i * omega * s.Cm.cast<std::complex<double>>();
    const Eigen::VectorXcd ym = A.partialPivLu().solve(Fm - s.Kmb.cast<std::complex<double>>() * (s.Kbb.inverse() * Fb));
    const Eigen::VectorXcd yb = s.Kbb.inverse() * (Fb - s.Kmb.transpose().cast<std::complex<double>>() * ym);
    Eigen::VectorXcd y = Eigen::VectorXcd::Zero(system.dofs());
    for (Eigen::Index k = 0; k < m; ++k) y(s.mass_dofs[static_cast<std::size_t>(k)]) = ym(k);
    y(s.massless[0]) = yb(0);
    std::complex<double> output = 0.0;
    for (const auto& [dof, c] : mitre.outputs[0].terms()) output += c * y(dof);
    return std::abs(output);
}

MitreStep mitre_step(double from, double to) {
    MitreStep step{read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml"), {}};
    ExactOptions options;
    options.outputs = step.config.outputs;
    options.dof_maxima = false;
    const ExactOrbit first = rigid_periodic_orbit(step.config.system, from, Eigen::VectorXd(), options);
    REQUIRE(first.converged);
    step.orbit = rigid_periodic_orbit(step.config.system, to, first.state, options);
    return step;
}

}  // namespace

TEST_CASE("rigid exact 3D: a node that grazes its cone's edge keeps the orbit's own multipliers: the stuck structure's",
          "[rigid_exact]") {
    // The mitre at 10 N, 11,600 rad/s, from rest: every node sticks all period, and Newton (the
    // general solve: a start at rest holds no nodes) leaves some of them with the friction force
    // touching the cone's edge at an instant: a perturbation of 1e-6 makes them slip, so the
    // period map has a kink at the orbit and central differences straddle it. The multipliers
    // must be those of the stuck structure (every contact DOF held, DOF 365 massless and
    // condensed): exp(lambda T) for its eigenvalues lambda, computed here from M, C, K alone, plus
    // 1 for each held position (a family of orbits); and without differences the solve takes
    // fewer periods than one matrix of them (two periods per unknown: 148 here).
    const SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    ExactOptions options;
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    const ExactOrbit orbit = rigid_periodic_orbit(mitre.system, 11600.0, Eigen::VectorXd(), options);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.switches == 0);
    CHECK(orbit.message.find("grazes") != std::string::npos);
    CHECK(orbit.message.find("central differences") == std::string::npos);
    CHECK(orbit.periods <= 120);
    const MitreStuck stuck = mitre_stuck(mitre.system);
    check_stuck_multipliers(stuck, orbit);
    CHECK(orbit.stable);
}

TEST_CASE("rigid exact 3D: a start whose nodes stay stuck gives the stuck structure's orbit in a few periods",
          "[rigid_exact]") {
    // The mitre at 10 N, 12,000 rad/s, from the orbit at 12,100 (a sweep down: the amplitude
    // falls): every node stays stuck where that orbit holds it, so the orbit is the stuck
    // structure's steady state about those held positions. Its first harmonic of the output y365
    // must be the stuck structure's, (K_eff - w^2 M + i w C) y = F with DOF 365 massless and
    // condensed, from M, C, K alone; its multipliers exp(lambda T) and 1; and four periods (a
    // plain one, a recorded one of the orbit solved in closed form, two perturbed ones for the
    // kink check), not the general solve's dozen with its periods with the flow's derivative.
    const MitreStep step = mitre_step(12100.0, 12000.0);
    const SystemConfig& mitre = step.config;
    const System& system = mitre.system;
    const ExactOrbit& orbit = step.orbit;
    const double omega = orbit.omega;
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.permanent_stick);
    CHECK(orbit.switches == 0);
    CHECK(orbit.periods <= 4);
    CHECK(orbit.residual <= 1e-9);
    const MitreStuck s = mitre_stuck(system);
    const double output = stuck_output_amplitude(mitre, s, omega);
    INFO(mitre.outputs[0].name() << ": exact amp1 " << orbit.output_amp1[0] << ", stuck structure " << output);
    CHECK(std::abs(orbit.output_amp1[0] - output) <= 1e-9 * output);
    check_stuck_multipliers(s, orbit);
}

TEST_CASE("rigid exact 3D: a start whose nodes slip and settle gives the stuck structure's orbit where they settled",
          "[rigid_exact]") {
    // The mitre at 10 N, 11,100 rad/s, from the orbit at 11,000 (a sweep up: the amplitude
    // grows): the friction forces of some nodes pass their cones' edges in the first periods,
    // those nodes slip and settle at new held positions (a shakedown of a few plain periods),
    // and the orbit is the stuck structure's about where they settled. Every member of that
    // family has the stuck structure's first harmonic (the held positions shift the mean only):
    // y365's must be the closed form's from M, C, K alone, the multipliers exp(lambda T) and 1,
    // and the periods a dozen or so, without a period with the flow's derivative.
    const MitreStep step = mitre_step(11000.0, 11100.0);
    const ExactOrbit& orbit = step.orbit;
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.permanent_stick);
    CHECK(orbit.message.find("shakedown") != std::string::npos);
    CHECK(orbit.switches == 0);
    CHECK(orbit.periods <= 20);
    CHECK(orbit.residual <= 1e-9);
    const MitreStuck s = mitre_stuck(step.config.system);
    const double output = stuck_output_amplitude(step.config, s, orbit.omega);
    INFO(step.config.outputs[0].name() << ": exact amp1 " << orbit.output_amp1[0] << ", stuck structure " << output);
    CHECK(std::abs(orbit.output_amp1[0] - output) <= 1e-9 * output);
    check_stuck_multipliers(s, orbit);
}

TEST_CASE("rigid exact 3D: a sweep's shakedown periods before Newton reach the orbit Newton alone reaches",
          "[rigid_exact]") {
    // exact_sweep_options adds plain periods before Newton where a 3D rigid sweep starts from the
    // previous frequency's orbit (and nowhere else). Where the orbit is unique the shaken start
    // must end on the same orbit as Newton from the previous orbit directly: two independent
    // solves from different starts, compared to 1e-9.
    const System flat = three_contacts(2.0);
    CHECK(exact_sweep_options(flat, ExactOptions{}, true).warmup_periods == 1);
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    CHECK(exact_sweep_options(system, ExactOptions{}, false).warmup_periods == 1);
    const ExactOptions shaken = exact_sweep_options(system, ExactOptions{}, true);
    CHECK(shaken.warmup_periods == exact_shakedown_periods);
    const PeriodicResponse cold = integrated(system, 0.6, 256, {});
    REQUIRE(cold.converged);
    const PeriodicResponse first = exact_steady_state(system, 0.6, ExactOptions{}, 200, cold.state);
    REQUIRE(first.converged);
    const double omega = 0.66;
    const Eigen::VectorXd start = exact_sweep_start(system, omega, {first}, cold.state);
    const PeriodicResponse plain = exact_steady_state(system, omega, ExactOptions{}, 200, start);
    const PeriodicResponse shook = exact_steady_state(system, omega, shaken, 200, start);
    INFO(plain.message << " / " << shook.message);
    REQUIRE(plain.converged);
    REQUIRE(shook.converged);
    CHECK(shook.periods >= exact_shakedown_periods + 1);
    for (std::size_t i = 0; i < 6; ++i) {
        INFO("DOF " << i + 1 << ": " << plain.y_amp1[i] << " / " << shook.y_amp1[i]);
        CHECK(std::abs(shook.y_amp1[i] - plain.y_amp1[i]) <= 1e-9 * std::abs(plain.y_amp1[i]));
        CHECK(std::abs(shook.y_max[i] - plain.y_max[i]) <= 1e-9 * std::abs(plain.y_max[i]));
    }
}

TEST_CASE("rigid exact 3D: a start's plain periods take fewer implicit steps, to their looser tolerance", "[rigid_exact]") {
    // set_start_flows: the collocation's local tolerance 1e-10 instead of 1e-12 (the plain
    // periods before Newton). Two periods from rest by collocation alone on the 3D chain: the
    // looser flows take fewer steps (an order-7 estimate: about 100^(1/7) = 1.9 times fewer)
    // and end within their tolerance's reach of the tight ones.
    using namespace detail::exact;
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    auto two_periods = [&](bool start, long& steps) {
        ConeEngine e(system, 0.6);
        e.set_stepping(ConeEngine::Stepping::collocation);
        e.set_start_flows(start);
        Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
        Modes modes = e.initial_modes(zhat);
        steps = 0;
        for (int p = 0; p < 2; ++p) {
            const PatternEngine::Flow f = e.flow(zhat, modes, 0.0, e.period(), false, false, 5000);
            REQUIRE(f.ok);
            steps += e.collocation_steps();
            zhat = f.zhat;
            modes = f.modes;
            zhat(e.cos_index()) = 1.0;
            zhat(e.sin_index()) = 0.0;
        }
        return zhat;
    };
    long tight_steps = 0, loose_steps = 0;
    const Eigen::VectorXd tight = two_periods(false, tight_steps);
    const Eigen::VectorXd loose = two_periods(true, loose_steps);
    const auto dofs = static_cast<Eigen::Index>(system.dofs());
    const double size = tight.head(dofs).cwiseAbs().maxCoeff();
    const double apart = (loose.head(dofs) - tight.head(dofs)).cwiseAbs().maxCoeff();
    INFO("collocation steps " << tight_steps << " tight, " << loose_steps << " loose; ends apart " << apart / size);
    CHECK(loose_steps <= 0.8 * tight_steps);
    CHECK(apart <= 1e-7 * size);
}

TEST_CASE("rigid exact 3D: a held contact stays stuck past its friction limit, the others as without the hold",
          "[rigid_exact]") {
    // ConeEngine::hold_stuck drops a stuck contact's friction limit from its guards (Newton's
    // predictor on orbits whose nodes stick all period). On the 3D chain from rest: contact 0
    // first slips at t1 without the hold; held, it has no slip event and just after t1 its
    // tangential force is past mu lambda_N (the limit really is not enforced), while a flow that
    // ends before t1 is the same with and without the hold (nothing else changes), and so is its
    // derivative, but for the held positions of the held contact, which it leaves out (their
    // columns zero where the flow without the hold depends on them).
    using namespace detail::exact;
    const System system = bench::contact_chain_3d(3, 1.0, 0.8);
    ConeEngine e(system, 0.6);
    Eigen::VectorXd zhat = e.augment(Eigen::VectorXd::Zero(e.nz()), 0.0);
    const Modes modes = e.initial_modes(zhat);
    REQUIRE(modes[0] == ConeEngine::stuck);
    const PatternEngine::Flow free = e.flow(zhat, modes, 0.0, e.period(), false, false, 5000);
    REQUIRE(free.ok);
    double t1 = -1.0;
    for (const ExactEvent& event : free.events)
        if (event.contact == 0 && event.mode_before == ConeEngine::stuck && event.mode_after != ConeEngine::open) {
            t1 = event.time;
            break;
        }
    REQUIRE(t1 > 0.0);
    std::vector<char> held(static_cast<std::size_t>(e.contacts()), 0);
    held[0] = 1;
    const PatternEngine::Flow before = e.flow(zhat, modes, 0.0, 0.9 * t1, true, false, 5000);
    e.hold_stuck(held);
    const PatternEngine::Flow held_before = e.flow(zhat, modes, 0.0, 0.9 * t1, true, false, 5000);
    const PatternEngine::Flow past = e.flow(zhat, modes, 0.0, t1 + 0.02 * e.period(), false, false, 5000);
    e.hold_stuck({});
    REQUIRE(before.ok);
    REQUIRE(held_before.ok);
    REQUIRE(past.ok);
    CHECK((held_before.zhat - before.zhat).cwiseAbs().maxCoeff() <= 1e-12 * before.zhat.cwiseAbs().maxCoeff());
    REQUIRE(before.psi.size() > 0);
    REQUIRE(held_before.psi.size() == before.psi.size());
    const double size = before.psi.cwiseAbs().maxCoeff();
    for (Eigen::Index j = 0; j < before.psi.cols(); ++j) {
        const bool left_out = j >= e.slider(0) && j < e.slider(0) + e.directions(0);
        INFO("column " << j << (left_out ? " (contact 0's held position)" : ""));
        if (left_out) {
            CHECK(held_before.psi.col(j).cwiseAbs().maxCoeff() == 0.0);
            CHECK(before.psi.col(j).head(2 * e.dofs()).cwiseAbs().maxCoeff() > 1e-6 * size);
        } else {
            CHECK((held_before.psi.col(j) - before.psi.col(j)).cwiseAbs().maxCoeff() <= 1e-12 * size);
        }
    }
    for (const ExactEvent& event : past.events) CHECK(!(event.contact == 0 && event.mode_before == ConeEngine::stuck &&
                                                        event.mode_after != ConeEngine::open));
    REQUIRE(past.modes[0] == ConeEngine::stuck);
    const Eigen::MatrixXd u = e.series(past.zhat, past.modes, t1 + 0.02 * e.period(), 0);
    const Eigen::Index lambda = e.n(), T = e.tangential(0), N = e.normal(0);
    const double tangential = std::hypot(u(lambda + T, 0), u(lambda + T + 1, 0));
    const double limit = e.split().blocks[0].mu * u(lambda + N, 0);
    INFO("|lambda_T| " << tangential << ", mu lambda_N " << limit);
    CHECK(tangential > limit * (1.0 + 1e-6));
}

TEST_CASE("rigid exact 3D: Newton with the nodes stuck all period held first ends on the integrator's orbit",
          "[rigid_exact]") {
    // The mitre's sweep step 21,574 -> 21,599 rad/s from the saved orbit (its file's force:
    // stick, slip and lift-off): after the shakedown a dozen nodes stick all period, Newton first
    // solves with them held (their held positions not unknowns), drags those that the new
    // frequency pushes past their cones' edges by a plain period, and ends on all unknowns. The
    // orbit must be a true orbit of the unheld flow, checked by the time integrator (independent
    // code): two periods from its state at 1024 and 2048 samples, whose second period's output
    // maximum and first harmonic approach the exact ones like dt^2.
    SystemConfig mitre = read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/mitre/mitre.toml");
    const System& system = mitre.system;
    const Eigen::VectorXd state = mitre_state("mitre_orbit_21574.txt", system);
    ExactOptions options = exact_sweep_options(system, ExactOptions{}, true);
    options.outputs = mitre.outputs;
    options.dof_maxima = false;
    const double omega = 21599.1666666667;
    const ExactOrbit orbit = rigid_periodic_orbit(system, omega, state, options);
    INFO(orbit.message);
    REQUIRE(orbit.converged);
    CHECK(orbit.residual <= 1e-12);
    CHECK(orbit.message.find("from the orbit with the nodes stuck all period held") != std::string::npos);
    int stuck = 0;
    for (const ContactRegime& c : orbit.contacts) stuck += c.stick_fraction == 1.0;
    CHECK(stuck >= 10);
    double error[2][2] = {};
    for (int k = 0; k < 2; ++k) {
        const TimeIntegrationOptions o = bench::two_periods_from_state(1024 << k, mitre.outputs);
        const PeriodicResponse one = integrate_steady_state(system, omega, o, &orbit.state);
        INFO(one.message);
        REQUIRE(one.converged);
        error[k][0] = relative(one.output_max[0], orbit.output_max[0]);
        error[k][1] = relative(one.output_amp1[0], orbit.output_amp1[0]);
    }
    INFO("max: " << error[0][0] << " -> " << error[1][0] << "; amp1: " << error[0][1] << " -> " << error[1][1]);
    CHECK(error[1][0] <= 1e-5);
    CHECK(error[1][1] <= 1e-5);
    CHECK(error[1][0] <= 0.4 * error[0][0]);
    CHECK(error[1][1] <= 0.4 * error[0][1]);
}
