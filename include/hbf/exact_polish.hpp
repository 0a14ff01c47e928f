// hbfriction — harmonic-balance branches polished by the exact periodic-orbit solvers.
//
// Harmonic balance at a modest H gives the branch (topology, folds, starting guesses) and the
// exact solver of the contacts' law gives each point: exact Coulomb and Jenkins contacts
// (event_exact.hpp, on the structure or its modal form), rigid unilateral contacts
// (rigid_exact.hpp), law elastic (elastic_exact.hpp, to its flow's tolerance). Every branch point
// and sample is re-solved at its frequency by Newton shooting from the HB solution's state at
// t = 0. A point whose polish fails keeps its HB values and is flagged.
// Then, from the exact points:
//   * transitions: wherever the exact regime of a contact changes between two consecutive
//     points of a branch, the frequency where the stick phase appears or vanishes is found by
//     bisection in omega on the exact regime (each trial solved exactly from the nearer
//     side's orbit) to |delta omega| <= 1e-10 omega, and inserted as a point of kind
//     transition, on the stick side (stick|stick-slip) or the stick-slip side
//     (stick-slip|slip); for contacts with a normal direction also where a contact starts to
//     open (closed|lift-off: its separated share leaves 0), the point on the closed side (rigid
//     contacts: to 1e-7 omega where the flow chatters nearer the grazing orbit); HB's
//     own transition points (O(1/H) misplaced) are dropped;
//   * peaks: every exact local maximum of y_max of the reported DOF among the branch points,
//     refined by a search in omega (Brent's method) on exact solves to |delta omega| <= 1e-9 omega.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/post_processing.hpp"

namespace hbf {

struct PolishOptions {
    ExactOptions exact;
    bool transitions = true;  ///< locate the exact transitions (above)
    bool peaks = true;        ///< refine the exact peaks (above)
    /// DOF (0-based) of hb_gap, and of the peaks when exact.outputs is empty; otherwise the
    /// peaks are those of every output in exact.outputs (Peak::output = its index).
    int dof = 0;
    /// With exact.outputs: refine the peaks of every output (false: of the first only).
    bool peaks_of_every_output = true;
    /// Called before each point is polished with (points done, points in all): a progress
    /// display. May be empty; it must not throw.
    std::function<void(int done, int total)> progress;
    /// > 0: the polish is optional (FrfSettings::exact_automatic) and declined before its work
    /// (PolishedBranch::declined) where a modal form's estimated truncation exceeds 1e-6 or
    /// one exact orbit at the probe point (the thread's CPU time, unaffected by the machine's
    /// load) times the points exceeds this many seconds.
    double decline_seconds = 0;
};

/// What the polish did to one point.
enum class PolishStatus { off, exact, failed };
/// "off", "yes", "failed" (the CSV's `exact` column).
std::string to_string(PolishStatus status);

struct ExactPoint {
    PolishStatus status = PolishStatus::off;
    bool stable = false;          ///< Floquet verdict (status exact only)
    /// Largest |Floquet multiplier|; NaN where the orbit's multipliers could not be computed
    /// (stable false, stability unknown: the message says why).
    double max_multiplier = 0;
    /// The largest |multiplier| is above 1 + the stability tolerance but within the multipliers'
    /// accuracy of 1 (ExactOrbit::stability_unresolved): stable false, stability uncertain.
    bool stability_unresolved = false;
    Eigen::VectorXcd multipliers; ///< the exact orbit's Floquet multipliers (status exact only)
    /// |y_max[dof] by HB - y_max[dof] exact| / y_max[dof] exact; NaN where there is no HB
    /// solution at this frequency (an exact transition whose HB correction failed) or no
    /// exact one.
    double hb_gap = 0;
    std::string message;          ///< the exact solver's message (why it failed)
};

struct PolishedBranch {
    /// The HB points in order (HB transition points dropped, exact transitions inserted on
    /// their branch), then the samples.
    std::vector<SolutionPoint> points;
    std::vector<PointMetrics> metrics;  ///< exact metrics where polished, HB otherwise
    std::vector<ExactPoint> exact;
    std::vector<Peak> peaks;            ///< exact peaks of `dof` or of the outputs (refined = the
                                        ///< search in omega converged)
    int polished = 0, failed = 0, unstable = 0, transitions = 0;
    /// Polished points whose multipliers could not be computed (max_multiplier NaN): their
    /// stability is unknown, counted neither stable nor unstable.
    int stability_unknown = 0;
    /// Polished points whose largest multiplier is within the multipliers' accuracy above 1
    /// (ExactPoint::stability_unresolved): stability uncertain, counted neither stable nor unstable.
    int stability_unresolved = 0;
    /// Modes of the modal form the exact solver ran on (modal_exact.hpp: models beyond
    /// exact_solver_max_dofs), 0 where it ran on the structure itself.
    int modes = 0;
    /// With a modal form: its estimated truncation, the relative change of the outputs' maxima
    /// and the friction energy at truncation_omega (the branch's highest frequency) from `modes`
    /// to the next count tried (exact_polish.cpp: choose_modes); NaN where not estimated.
    double modal_truncation = 0;
    double truncation_omega = 0;
    std::vector<int> contact_transitions;  ///< transitions per contact
    /// Regime changes between two exact neighbours whose bisection failed (a solve there did not
    /// converge; rigid contacts next to grazing, where the flow chatters): not inserted.
    int unlocated_transitions = 0;
    double max_hb_gap = 0;              ///< largest hb_gap over the polished points
    double seconds = 0;
    /// Why an optional polish was declined before its work (PolishOptions::decline_seconds;
    /// nothing else is filled), "" where it ran.
    std::string declined;
    /// Why a stop request (exact.stop of PolishOptions) ended the polish, "" where none did:
    /// the point it came during and those after it keep harmonic balance's values (status
    /// off), and no transition or peak is located after it.
    std::string stopped;
    /// One line: polished, failed, unstable, transitions, largest HB gap, time (and the stop).
    std::string summary() const;
};

/// The state at t = 0 of an HB solution, in the convention of the solver that polishes it: y and
/// y' from the coefficients, then (time_integration.hpp's convention, 1D friction) a Jenkins
/// slider from its force sample s = q - f / k_t and modes from the stick indicator; rigid
/// contacts (rigid_exact.hpp) y and y' alone; law elastic (elastic_exact.hpp) each contact's
/// slider and mode from its periodic cycle on the HB orbit's time samples.
Eigen::VectorXd exact_start_state(HarmonicBalance& hb, const SolutionPoint& point);

/// Why the exact polish of `system` cannot run (one sentence), empty when it can: on the
/// structure or on its modal form (exact_solver_modes with `modes`), down to omega_min when
/// omega_min > 0 (exact_cost_refusal); rigid contacts by rigid_solver_refusal, law elastic by
/// elastic_solver_refusal (their cost is measured by the polish's probe instead). Builds the
/// modal form once when it is needed.
std::string exact_polish_refusal(const System& system, double omega_min = 0.0, int modes = 0);

/// Polishes `points` (a branch in order, then samples of kind sample) as described above.
/// `hb_metrics[k]` are the HB metrics of points[k]. A model beyond exact_solver_max_dofs DOFs with
/// mass is polished on its modal form (modal_exact.hpp) with exact_solver_modes(system)
/// modes. Throws InvalidInput when a contact's law is not covered by the exact
/// solver or the modal form cannot be built (exact_polish_refusal says why).
PolishedBranch polish_branch(HarmonicBalance& hb, const std::vector<SolutionPoint>& points,
                             const std::vector<PointMetrics>& hb_metrics, const PolishOptions& options,
                             const CorrectorOptions& corrector);

}  // namespace hbf
