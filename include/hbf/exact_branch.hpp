// hbfriction — the branch of exact periodic orbits over a frequency band, followed through its
// folds (hbf timeint --method exact --sweep branch).
//
// A sweep in w (time_integration.hpp: sweep, exact_sweep_start) cannot pass a fold: past it the
// branch's orbit does not exist at the next w, and the solver lands on another branch (the jump of
// a slow sweep). Here the branch is followed by its arclength instead. Each point is an exact
// periodic orbit solved at a fixed w (the law's exact solver: exact_steady_state's), from a start
// predicted along the branch: the parabola through the last three points as functions of their
// chord length (w, the first harmonics and the state's y, y' at t = 0 of the DOFs with mass),
// evaluated one step further. Near a
// fold that parabola turns with the branch, so the predicted w itself goes back and the start
// lies on the far side of the fold, where the solver at that w finds the far branch's orbit (the
// two orbits at one w near a fold are about twice the step apart in the state, the start within
// the step's cube of the far one). The state's other entries (massless DOFs' held positions,
// sliders, modes) are the last point's: a slow sweep leaves stuck nodes where they are.
//
// The chord length of two points a, b: sqrt(((w_a - w_b) / (w_max - w_min))^2 + (|h_a - h_b| /
// max(|h_a|, |h_b|))^2), h the first harmonics' cosine and sine parts of the DOFs with mass, |.|
// the max norm: a share of the band and a relative change of the orbit weigh alike (the
// harmonics, integrals over the period, stay smooth in w where an event of the orbit passes t =
// 0; the state at t = 0 does not). A point is taken where it converged, lies within half a step
// of its prediction (in that chord length) and goes on from the last point (not back along the
// branch); the next step is then scaled by sqrt(0.1 step / distance) within [1/2, 2], at most
// options.step. Otherwise the step halves; below 1e-4 of options.step the branch ends (failed).
// A fold is where w turns: its w is the parabola's vertex through the three points about the turn,
// each an exact orbit (the fold itself is estimated, not solved: its error is of the order of the
// steps there). Where the branch is not smooth (a contact's regime changes, e.g. from permanent
// stick to stick-slip: a corner, or a weaker singularity where a slip phase's length grows like a
// root of the distance in w), the parabola's error shrinks slower than the step's square as the
// step halves: the point where that shows (its error at most corner_ratio = 3 steps, at most
// 1.5 times smaller than at twice the step, below 1/16 of options.step) is taken as a corner
// and the prediction restarts from it (the next step from its state, in the direction w moved). The branch ends where it leaves [omega_min, omega_max] (its last point then on
// the bound: completed), after options.max_points points (incomplete) or at a stop request.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"

namespace hbf {

/// hbf timeint --sweep branch and hbfriction.exact_branch take at most this many times --points
/// points (the step of --points on a flat branch): a branch through peaks, corners and folds
/// takes more points than a flat one of the same step.
constexpr int exact_branch_point_factor = 20;

struct ExactBranchOptions {
    double omega_min = 0.0, omega_max = 0.0;  ///< the band, 0 < omega_min < omega_max
    bool up = true;                           ///< from omega_min upwards, else from omega_max down
    /// The largest chord step (the share of the band it would be on a flat branch), (0, 1].
    double step = 0.01;
    int max_points = 1000;   ///< at most this many points, >= 2
    /// The first point as exact_steady_state's (its retry after min(max_periods, 200) plain
    /// periods), >= 1.
    int max_periods = 200;
    ExactOptions exact;      ///< each orbit's solve (tolerance, outputs, stop request)
    /// Called after each point taken (progress lines).
    std::function<void(const PeriodicResponse&, double step)> progress;
    /// Throws InvalidInput naming the offending field and its range.
    void validate() const;
};

/// The options of hbf timeint --sweep branch and hbfriction.exact_branch for `points` points
/// (2..10000, as a sweep's grid): the largest step 1 / (points - 1), at most
/// exact_branch_point_factor points points. Throws InvalidInput naming points out of range.
ExactBranchOptions exact_branch_options(double omega_min, double omega_max, long long points);

/// A turning point of the branch in w.
struct ExactFold {
    double omega = 0.0;  ///< the parabola's vertex through the three points about the turn
    int point = 0;       ///< the point at the turn (0-based: the middle one of the three)
};

struct ExactBranch {
    std::vector<PeriodicResponse> points;  ///< in branch order, each converged
    std::vector<ExactFold> folds;
    /// The w of the points where the branch is not smooth (corners: a contact's regime changes
    /// there, e.g. permanent stick to stick-slip; see above).
    std::vector<double> corners;
    int rejected = 0;  ///< solves not taken (a step halved)
    /// completed (the branch left the band), incomplete (max_points reached), stopped (the
    /// stop request), failed (the first point, or the step collapsed).
    std::string status;
    std::string message;  ///< where and why it ended
};

/// The branch of exact orbits from the band's end (options.up: omega_min) through the band,
/// starting from `start` (time_integration.hpp's convention; empty: rest). Throws InvalidInput
/// where exact_sweep_refusal is not empty or the options are out of range.
ExactBranch exact_branch(const System& system, const ExactBranchOptions& options, const Eigen::VectorXd& start);

}  // namespace hbf
