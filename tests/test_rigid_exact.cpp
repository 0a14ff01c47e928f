// Exact periodic orbits of rigid unilateral contacts with Coulomb friction on massless nodes
// (law unilateral, include/hbf/rigid_exact.hpp). The references are independent of the event
// solver: law unilateral's time integrator (velocity Verlet with a complementarity solve per
// step, second order), whose error against the exact orbit must fall like dt^2; the energy
// balance (the force's work equals the friction's plus the viscous one, over the exact period);
// the Floquet multipliers against the growth of a perturbation under the exact flow; and
// limits where the contacts never slip or never close (the linear structure's steady state).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/model.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/time_integration.hpp"

#include "support.hpp"

using namespace hbf;

namespace {

const std::string liftoff3 = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";

/// Three masses in a chain, each pressing a massless contact node onto a rigid wall: the node
/// of contact c is tied to mass c along the wall (k_t) and to mass c + 1 (cyclically) across
/// it (k_n), with preloads that differ, so that the contacts stick, slip and open at different
/// times. DOFs: y1..y3 the masses, then per contact its tangential and normal node.
System three_contacts(double force) {
    const int nm = 3, nc = 3, n = nm + 2 * nc;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n), K = M, C = M;
    const double masses[] = {1.0, 0.7, 0.4}, kt[] = {3.0, 2.0, 4.0}, kn[] = {5.0, 6.0, 4.0}, preload[] = {1.0, 0.6, 0.8};
    for (int i = 0; i < nm; ++i) M(i, i) = masses[i];
    auto spring = [&K](int a, int b, double k) {
        K(a, a) += k;
        K(b, b) += k;
        K(a, b) -= k;
        K(b, a) -= k;
    };
    auto ground = [&K](int a, double k) { K(a, a) += k; };
    spring(0, 1, 1.5);
    spring(1, 2, 1.0);
    ground(0, 2.0);
    ground(2, 0.5);
    for (int i = 0; i < nm; ++i) C(i, i) = 0.02 * masses[i];
    C(0, 1) = C(1, 0) = -0.01;
    C(0, 0) += 0.01;
    C(1, 1) += 0.01;
    Eigen::VectorXd F = Eigen::VectorXd::Zero(n), S = Eigen::VectorXd::Zero(n);
    F(0) = 0.3 * force;
    F(1) = force;
    F(2) = -0.5 * force;
    System s;
    for (int c = 0; c < nc; ++c) {
        const int t = nm + 2 * c, v = t + 1, across = (c + 1) % nm;
        spring(c, t, kt[c]);
        spring(across, v, kn[c]);
        S(v) += preload[c];       // the node onto the wall
        S(across) -= preload[c];  // and the structure away from it: N = preload at rest
        Contact k;
        k.law = parse_friction_law("unilateral");
        k.dof = t;
        k.values["friction_coefficient"] = 0.3;
        k.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(n), 0.0);
        k.lists["normal_direction"][static_cast<std::size_t>(v)] = 1.0;
        s.contacts.push_back(k);
    }
    s.mass = M.sparseView();
    s.stiffness = K.sparseView();
    s.damping = C.sparseView();
    s.excitation = F;
    s.static_load = S;
    return s;
}

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

/// The exact orbit against the integrator at S and 2S steps a period: its error falls like
/// dt^2 (a ratio near 4) down to `closest` relative at 2S, in the first output's maximum and
/// first harmonic; the contact shares agree to the integrator's step (first order: the steps
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
    CHECK(e_amp_coarse / e_amp_fine > 3.0);
    CHECK(e_amp_coarse / e_amp_fine < 5.5);
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
    for (double omega : {1.2, 2.0}) check_against_integrator(config.system, omega, config.outputs, 1024, 1e-5);
}

TEST_CASE("rigid exact: three contacts sticking, slipping and opening at different times", "[rigid_exact]") {
    const System system = three_contacts(0.6);
    std::vector<Output> outputs{Output::dof(0)};
    check_against_integrator(system, 1.3, outputs, 1024, 1e-5);
}
