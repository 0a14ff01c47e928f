// Tests of the branch of exact orbits followed through its folds (include/hbf/exact_branch.hpp).
// The references are independent of the continuation: the saddle-node's Floquet multiplier
// (a fold is where a real multiplier passes +1: the orbit's stability changes there), the jumps
// of plain fixed-w sweeps (a sweep cannot follow a branch past its fold: it jumps within a grid
// step of it), law unilateral's time integrator (both stable branches where they coexist), and
// the fold's estimate as the steps shrink.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/exact_branch.hpp"
#include "hbf/time_integration.hpp"

#include "../benchmarks/contact_chain.hpp"
#include "cli_support.hpp"

using namespace hbf;
using io::SystemConfig;
using namespace hbf::test;

namespace {

const std::string branch_system = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3_rigid.toml";

/// liftoff3_rigid's branch over [2.2, 2.8] at the given largest step.
ExactBranch liftoff3_branch(const System& system, double step) {
    ExactBranchOptions o;
    o.omega_min = 2.2;
    o.omega_max = 2.8;
    o.step = step;
    o.max_points = 5000;
    o.exact.outputs = {Output::dof(0)};
    return exact_branch(system, o, Eigen::VectorXd());
}

/// The state of the branch's point next after it crosses w, of the crossings the one of the
/// largest (highest) or smallest y1_max.
Eigen::VectorXd crossing_state(const ExactBranch& b, double w, bool highest) {
    const PeriodicResponse* best = nullptr;
    for (std::size_t k = 1; k < b.points.size(); ++k)
        if ((b.points[k - 1].omega - w) * (b.points[k].omega - w) <= 0.0 &&
            (best == nullptr || (b.points[k].output_max[0] > best->output_max[0]) == highest))
            best = &b.points[k];
    REQUIRE(best != nullptr);
    return best->state;
}

/// A plain exact sweep over `grid` from `first` (each point from the sweep's predictor, as hbf
/// timeint --method exact): the first grid index whose y1_max differs from the one before by
/// more than 10 % (a jump to another branch), or -1.
int first_jump(const System& system, const std::vector<double>& grid, const Eigen::VectorXd& first) {
    ExactOptions options;
    options.outputs = {Output::dof(0)};
    std::vector<PeriodicResponse> done;
    for (std::size_t k = 0; k < grid.size(); ++k) {
        const Eigen::VectorXd start = exact_sweep_start(system, grid[k], done, first);
        done.push_back(exact_steady_state(system, grid[k], options, 200, start));
        REQUIRE(done.back().converged);
        if (k > 0 && std::abs(done[k].output_max[0] / done[k - 1].output_max[0] - 1.0) > 0.1) return static_cast<int>(k);
    }
    return -1;
}

}  // namespace

TEST_CASE("exact branch: liftoff3_rigid through both folds of its lift-off resonance", "[exact][branch]") {
    // The rigid contact's lift-off softens the resonance: the branch bends over (a fold near 2.61),
    // back down to a second fold near 2.40 and up again; between them three orbits coexist.
    const SystemConfig config = io::read_system_config(branch_system);
    const System& system = config.system;
    const ExactBranch b = liftoff3_branch(system, 1.0 / 60.0);
    INFO(b.message);
    REQUIRE(b.status == "completed");
    REQUIRE(b.points.size() >= 60);
    CHECK(b.points.front().omega == 2.2);
    CHECK(b.points.back().omega == 2.8);
    for (const PeriodicResponse& r : b.points) REQUIRE(r.converged);
    REQUIRE(b.folds.size() == 2);
    const ExactFold upper = b.folds[0], lower = b.folds[1];
    CHECK(upper.omega > lower.omega);

    // Each fold is a saddle-node: the largest multiplier is below 1 on one side and above on the
    // other (a real multiplier passes +1). Two points either side, away from the fold's rounding.
    for (const ExactFold& fold : b.folds) {
        INFO("fold at w = " << fold.omega);
        const PeriodicResponse& before = b.points[static_cast<std::size_t>(fold.point - 2)];
        const PeriodicResponse& after = b.points[static_cast<std::size_t>(fold.point + 2)];
        CHECK((before.max_multiplier - 1.0) * (after.max_multiplier - 1.0) < 0.0);
    }

    // Plain sweeps jump where the branch turns: up along the lower branch past the upper fold,
    // down along the upper branch past the lower fold, on grids of 0.002.
    std::vector<double> up, down;
    for (int k = 0; k <= 40; ++k) up.push_back(2.56 + 0.002 * k);
    for (int k = 0; k <= 40; ++k) down.push_back(2.45 - 0.002 * k);
    const int jump_up = first_jump(system, up, crossing_state(b, up.front(), false)),
              jump_down = first_jump(system, down, crossing_state(b, down.front(), true));
    REQUIRE(jump_up > 0);
    REQUIRE(jump_down > 0);
    CHECK(up[static_cast<std::size_t>(jump_up - 1)] < upper.omega);
    CHECK(up[static_cast<std::size_t>(jump_up)] > upper.omega);
    CHECK(down[static_cast<std::size_t>(jump_down - 1)] > lower.omega);
    CHECK(down[static_cast<std::size_t>(jump_down)] < lower.omega);

    // At w = 2.45 the branch crosses it three times: two stable orbits, each the integrator's
    // steady state from the exact state (law unilateral's Verlet integrator at 1024 steps a period,
    // second order: 2e-6), and an unstable one between them in amplitude.
    std::vector<const PeriodicResponse*> at;
    for (std::size_t k = 1; k < b.points.size(); ++k)
        if ((b.points[k - 1].omega - 2.45) * (b.points[k].omega - 2.45) <= 0.0) at.push_back(&b.points[k]);
    REQUIRE(at.size() == 3);
    std::sort(at.begin(), at.end(), [](auto* a, auto* c) { return a->output_max[0] < c->output_max[0]; });
    CHECK(at[0]->max_multiplier < 1.0);
    CHECK(at[1]->max_multiplier > 1.0);
    CHECK(at[2]->max_multiplier < 1.0);
    for (const PeriodicResponse* p : {at[0], at[2]}) {
        ExactOptions options;
        options.outputs = {Output::dof(0)};
        const PeriodicResponse exact = exact_steady_state(system, 2.45, options, 200, p->state);
        REQUIRE(exact.converged);
        TimeIntegrationOptions o;
        o.samples_per_period = 1024;
        o.steady_tolerance = 1e-12;
        o.max_periods = 20000;
        o.outputs = {Output::dof(0)};
        Eigen::VectorXd state = exact.state;
        const PeriodicResponse integrated = integrate_steady_state(system, 2.45, o, &state);
        REQUIRE(integrated.converged);
        INFO("exact " << exact.output_max[0] << ", integrated " << integrated.output_max[0]);
        CHECK(std::abs(integrated.output_max[0] / exact.output_max[0] - 1.0) <= 2e-6);
    }

    // The folds' estimates converge as the steps shrink (a quarter of the step: within 1e-5, measured 8e-7).
    const ExactBranch fine = liftoff3_branch(system, 1.0 / 240.0);
    REQUIRE(fine.status == "completed");
    REQUIRE(fine.folds.size() == 2);
    CHECK(std::abs(fine.folds[0].omega - upper.omega) <= 1e-5);
    CHECK(std::abs(fine.folds[1].omega - lower.omega) <= 1e-5);
}

TEST_CASE("exact branch: liftoff3_rigid's corners where its contact starts and stops slipping", "[exact][branch]") {
    // Below the folds the branch passes points where the contact's regime changes (permanent
    // stick to stick-slip and back): the branch is not smooth there. Each is taken as a corner,
    // and the exact orbits either side of it have the two regimes.
    const SystemConfig config = io::read_system_config(branch_system);
    ExactBranchOptions o;
    o.omega_min = 0.9;
    o.omega_max = 1.4;
    o.step = 1.0 / 40.0;
    o.max_points = 5000;
    o.exact.outputs = {Output::dof(0)};
    const ExactBranch b = exact_branch(config.system, o, Eigen::VectorXd());
    INFO(b.message);
    REQUIRE(b.status == "completed");
    REQUIRE(b.corners.size() == 2);
    for (const double w : b.corners) {
        INFO("corner at w = " << w);
        std::size_t k = 0;
        while (k < b.points.size() && b.points[k].omega != w) ++k;
        REQUIRE(k >= 2);
        REQUIRE(k + 2 < b.points.size());
        const std::string before = b.points[k - 2].regime, after = b.points[k + 2].regime;
        CHECK(before != after);
        CHECK(((before == "stick" && after == "stick-slip") || (before == "stick-slip" && after == "stick")));
    }
}

TEST_CASE("exact branch: law elastic's solver finds the same folds on liftoff3.toml", "[exact][branch]") {
    // liftoff3.toml is liftoff3_rigid.toml's structure with law elastic's element (the massless
    // node tied by springs is that element's slider): the same physics by another exact solver
    // (law elastic's event-driven CVODE flow at 1e-11, its own Newton): the same folds.
    const SystemConfig rigid = io::read_system_config(branch_system);
    const SystemConfig elastic = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml");
    const ExactBranch a = liftoff3_branch(rigid.system, 1.0 / 30.0), b = liftoff3_branch(elastic.system, 1.0 / 30.0);
    REQUIRE(a.status == "completed");
    REQUIRE(b.status == "completed");
    REQUIRE(a.folds.size() == 2);
    REQUIRE(b.folds.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) CHECK(std::abs(a.folds[k].omega - b.folds[k].omega) <= 1e-8);
}

TEST_CASE("exact branch: the paper's absorber turns vertical, and the branch says so", "[exact][branch]") {
    // The Coulomb absorber's branch (defaults, [0.5, 1.6]) rises through stick-slip to a stretch
    // where w stands still (to 1e-12) while the orbit goes on changing (the stick share grows):
    // a solver at a fixed w cannot follow it. The branch ends there (failed) and says why.
    const System system = friction_absorber(AbsorberParameters{}, FrictionLaw::coulomb);
    ExactBranchOptions o;
    o.omega_min = 0.5;
    o.omega_max = 1.6;
    o.step = 0.01;
    o.max_points = 5000;
    const ExactBranch b = exact_branch(system, o, linear_stuck_state(system, 0.5));
    INFO(b.message);
    REQUIRE(b.status == "failed");
    CHECK_THAT(b.message, Catch::Contains("turns vertical"));
    REQUIRE(b.points.size() > 20);
    const PeriodicResponse& last = b.points.back();
    const PeriodicResponse& earlier = b.points[b.points.size() - 12];
    CHECK(std::abs(last.omega - earlier.omega) <= 1e-8 * last.omega);
    CHECK(std::abs(last.y_max[0] / earlier.y_max[0] - 1.0) >= 1e-5);
    CHECK(std::abs(last.contacts[0].stick_fraction - earlier.contacts[0].stick_fraction) >= 1e-4);
}

TEST_CASE("exact branch: bounded, stoppable, and bad options refused", "[exact][branch]") {
    const SystemConfig config = io::read_system_config(branch_system);
    ExactBranchOptions o;
    o.omega_min = 2.2;
    o.omega_max = 2.8;
    o.max_points = 5;
    const ExactBranch capped = exact_branch(config.system, o, Eigen::VectorXd());
    CHECK(capped.status == "incomplete");
    CHECK(capped.points.size() == 5);
    int asked = 0;
    o.max_points = 1000;
    o.exact.stop = [&asked] { return ++asked >= 4 ? std::string("the time limit") : std::string(); };
    const ExactBranch stopped = exact_branch(config.system, o, Eigen::VectorXd());
    CHECK(stopped.status == "stopped");
    CHECK_THAT(stopped.message, Catch::Contains("the time limit"));
    CHECK(stopped.points.size() < 4);
    o.exact.stop = nullptr;
    auto refused = [&](ExactBranchOptions bad, const std::string& field) {
        INFO(field);
        CHECK_THROWS_WITH(exact_branch(config.system, bad, Eigen::VectorXd()), Catch::Contains(field + " = "));
    };
    ExactBranchOptions bad = o;
    bad.step = 0.0;
    refused(bad, "step");
    bad = o;
    bad.omega_max = 2.2;
    refused(bad, "omega_max");
    bad = o;
    bad.max_points = 1;
    refused(bad, "max_points");
    bad = o;
    bad.max_periods = 0;
    refused(bad, "max_periods");
}

TEST_CASE("exact sweep start: the secant for the DOFs with mass, the held positions kept", "[exact][branch]") {
    // Two converged points (w = 1, 1.1), the second's state twice the first's: the start at 1.15
    // by the secant is 2.5 times the first's state where it extrapolates, the second's elsewhere.
    auto start_at = [](const System& system) {
        const int n = system.dofs();
        std::vector<PeriodicResponse> done(2);
        done[0].omega = 1.0;
        done[1].omega = 1.1;
        for (PeriodicResponse& r : done) r.converged = true;
        done[0].state = Eigen::VectorXd::LinSpaced(2 * n, 1.0, 2.0 * n);
        done[1].state = 2.0 * done[0].state;
        return std::make_pair(done[0].state, exact_sweep_start(system, 1.15, done, Eigen::VectorXd()));
    };
    // liftoff3_rigid (2D): y4, y5 massless (the contact nodes, held where stuck).
    const SystemConfig config = io::read_system_config(branch_system);
    const int n = config.system.dofs();
    const auto [first, next] = start_at(config.system);
    for (int i = 0; i < n; ++i) {
        INFO("DOF " << i + 1);
        const bool massless = i >= 3;
        for (const int k : {i, n + i}) CHECK(next(k) == Approx((massless ? 2.0 : 2.5) * first(k)).epsilon(1e-14));
    }
    // 3D contacts: the last orbit as it is (nodes stuck all period are held anywhere inside their
    // cones, and the secant would carry the move from one member of that family to another on).
    const auto [first_3d, next_3d] = start_at(bench::contact_chain_3d(3, 1.0, 0.8));
    CHECK((next_3d - 2.0 * first_3d).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("hbf timeint --sweep branch: the exact branch through its folds, in branch order", "[cli][exact][branch]") {
    TempDir dir;
    const std::string base = "timeint --config '" + branch_system + "' --wmin 2.2 --wmax 2.8 --points 61 --sweep branch";
    const Result r = run_hbf(base + " --method exact", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.err, Catch::Contains("2 fold(s)") && Catch::Contains("a fold at w = 2.61"));
    const auto rows = parse_csv(r.out);
    REQUIRE(rows.size() > 62);
    CHECK(rows[1][0] == "2.2");
    CHECK(rows.back()[0] == "2.8");
    int turns = 0;
    for (std::size_t k = 3; k < rows.size(); ++k)
        turns += (std::stod(rows[k - 1][0]) - std::stod(rows[k - 2][0])) * (std::stod(rows[k][0]) - std::stod(rows[k - 1][0])) < 0.0;
    CHECK(turns == 2);
    // each orbit's largest multiplier, as the note counts the unstable ones
    const auto at = std::find(rows[0].begin(), rows[0].end(), "max_multiplier");
    REQUIRE(at != rows[0].end());
    const auto column = static_cast<std::size_t>(at - rows[0].begin());
    int unstable = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) unstable += std::stod(rows[k][column]) > 1.0 + 1e-6;
    CHECK(unstable > 0);
    CHECK_THAT(r.err, Catch::Contains(std::to_string(unstable) + " of " + std::to_string(rows.size() - 1) +
                                      " exact orbits are unstable"));
    const Result time_stepping = run_hbf(base, dir);
    CHECK(time_stepping.exit_code == 2);
    CHECK_THAT(time_stepping.err, Catch::Contains("--sweep branch") && Catch::Contains("--method exact"));
}
