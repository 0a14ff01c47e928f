// hbfriction — stability of harmonic-balance solutions: Floquet multipliers by Hill's method
// and by the monodromy matrix, and the verdict of every branch point.
//
// A periodic solution s*(t) = (y, y', z) of period T = 2 pi / omega is perturbed, s = s* + ds.
// For the smooth laws (dahl, lugre, coulomb-reg) the perturbation obeys the variational
// equation ds' = A(t) ds, in first-order form (N DOFs, S internal states, d = 2N + S):
//
//     dy'  = dv
//     M dv' = -K dy - C dv - sum_c w_c (f_v,c w_c^T dv + f_z,c dz_c)
//     dz_c' = g_v,c w_c^T dv + g_z,c dz_c
//
// with the laws' local slopes f_v, f_z, g_v, g_z (contact_force.hpp: linearize) evaluated along the
// HB solution (v_c = q_c', z_c from its coefficients); the springs (polynomial, gap) add
// -w_c f_q,c w_c^T dy, and an element over several coordinates (a polynomial of several: its
// directions W_c) -W_c (F_q,c W_c^T dy + F_v,c W_c^T dv) with its m x m slopes
// (BoundLaw::forces). M must be positive definite. Its
// Floquet multipliers mu (eigenvalues of the monodromy Phi(T), Phi' = A Phi, Phi(0) = I)
// decide: the solution is stable when every |mu| <= 1 + tolerance. Two independent routes:
//
// * Hill (the classical route): the perturbation e^{lambda t} p(t) with p periodic gives the
//   eigenproblem (A - d/dt) p = lambda p; on the HB's harmonics 0..H (all of them, even with
//   odd-harmonic HB: a symmetric orbit may lose stability to any perturbation) it is the real
//   matrix  [P diag(A_ij) E]_ij - omega D1 (x) I  of size d (2H + 1): the HB Jacobian's
//   linearisation with the internal states, in first-order form. Its eigenvalues come in
//   families lambda + i k omega, of which truncation corrupts the outer ones; the classical
//   selection keeps the d eigenvalues with the smallest |Im lambda| and mu = exp(lambda T).
//   This sorting is what fails for friction ("fragmented" spectra).
// * monodromy (sorting-free): Phi(T) by integrating the variational equation over one period
//   with CVODE (BDF, the exact Jacobian A(t)), all d columns as one system, A(t) evaluated at
//   any t from the HB coefficients.
// Where both run and their verdicts differ, the point is `uncertain`, never guessed.
//
// Exact Coulomb and Jenkins contacts are not differentiable: their verdict comes from the
// event-exact solver (event_exact.hpp: exact monodromy with saltation matrices), started from
// the HB solution's state at t = 0; it is `uncertain` when that exact orbit is not the HB one
// (Newton failed, or y_max differs by more than exact_gap). Rigid unilateral contacts (law
// unilateral on massless nodes) likewise from the rigid-contact exact solver (rigid_exact.hpp:
// in 2D the exact monodromy, in 3D the flow's derivative or the period map's central
// differences where that derivative fails its check). Law elastic (contacts with a normal
// direction and mass) likewise from its periodic-orbit solver (elastic_exact.hpp: the flow's
// derivative with the saltation at the events), started from the HB orbit's state, sliders and
// modes at t = 0.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/exact_polish.hpp"

namespace hbf {

/// The verdict on one solution.
enum class Stability { not_computed, stable, unstable, uncertain };
/// "", "true", "false", "uncertain" (the CSV's `stable` column).
std::string to_string(Stability stability);

enum class StabilityMethod { hill, monodromy, both };
/// "hill", "monodromy", "both".
std::string to_string(StabilityMethod method);
/// Inverse of to_string; throws InvalidInput naming the allowed values.
StabilityMethod parse_stability_method(const std::string& name);

struct StabilityOptions {
    /// Smooth laws: which route decides (both: uncertain where they disagree).
    StabilityMethod method = StabilityMethod::both;
    /// Unstable when the largest |multiplier| > 1 + tolerance (undamped stuck structures sit on
    /// the unit circle: neutrally stable). 0..1.
    double tolerance = 1e-6;
    /// A route is confident when |largest |mu| - 1| > confidence: the statistics of
    /// disagreements count only points where both are confident. > 0.
    double confidence = 1e-3;
    /// CVODE relative tolerance of the monodromy (absolute: this times 1e-2), 1e-13..1e-4.
    double integration_tolerance = 1e-8;
    /// Hill's matrix is dense, d (2H + 1) square: larger ones are not built (the monodromy
    /// route alone decides; `hill` alone: not computed). 10..20000.
    int max_hill_size = 2000;
    /// Exact Coulomb and Jenkins: largest relative gap in y_max between the HB and the exact
    /// orbit for which the exact multipliers are taken as the HB point's (HB's own error at
    /// H = 10 reaches ~10 % near a Jenkins resonance; a different orbit differs by far more). > 0.
    double exact_gap = 0.25;
    /// The exact solver's threads for rigid 3D contacts (ExactOptions::threads): 0 two where the
    /// hardware has two cores, 1 or 2.
    int exact_threads = 0;
    /// analyse_branch_stability's progress: called after each point with the points done and
    /// their total; must not throw. May be empty.
    std::function<void(int done, int total)> progress;
    /// Asked by analyse_branch_stability before every point (and by the exact routes' solvers
    /// after every period): a non-empty answer (why: an interrupt, a time limit) leaves that point
    /// and the rest not_computed with that answer as message (BranchStability::stopped). Empty:
    /// never asked.
    std::function<std::string()> stop;
    /// Throws InvalidInput naming the first option out of range.
    void validate() const;
};

/// The Floquet analysis of one solution.
struct FloquetResult {
    Stability stability = Stability::not_computed;
    /// Largest |multiplier| of the deciding route (monodromy, else Hill, else exact); NaN when
    /// not computed.
    double margin = std::numeric_limits<double>::quiet_NaN();
    Eigen::VectorXcd multipliers;   ///< of the deciding route
    Eigen::VectorXcd hill_multipliers, monodromy_multipliers;  ///< each route's (empty: not run)
    double hill_margin = std::numeric_limits<double>::quiet_NaN();
    double monodromy_margin = std::numeric_limits<double>::quiet_NaN();
    std::string route;    ///< "hill", "monodromy", "hill+monodromy", "exact" (empty: none)
    std::string message;  ///< why not computed or uncertain (empty otherwise)
};

/// Why the stability of this system cannot be analysed (one sentence), empty when it can:
/// every contact smooth (dahl, lugre, coulomb-reg) with M positive definite, every contact
/// exact coulomb/jenkins where the exact polish can run (exact_polish_refusal: on the structure,
/// or on its modal form beyond exact_solver_max_dofs, whose verdicts then come from the polish
/// only: a point it did not polish has none), or every contact of law unilateral where the
/// rigid-contact exact solver can run (rigid_solver_refusal).
std::string stability_refusal(const System& system);

/// Analyses points of one HarmonicBalance (its system and harmonics).
class StabilityAnalyser {
public:
    /// Throws InvalidInput for bad options.
    StabilityAnalyser(HarmonicBalance& hb, StabilityOptions options = {});
    /// The verdict on a solution point (any kind); not_computed with the refusal as message
    /// when the system is not supported.
    FloquetResult operator()(const SolutionPoint& point);
    /// Hill's multipliers alone (the classical sorted selection) and the monodromy alone, for
    /// tests and benchmarks (smooth laws; empty when not supported).
    Eigen::VectorXcd hill(const SolutionPoint& point);
    Eigen::MatrixXd monodromy(const SolutionPoint& point);
    /// The state at t = 0 of an HB solution in time_integration.hpp's convention ([y, y',
    /// internal, mode]: z for dahl/lugre, the slider for jenkins, modes from the stick indicator).
    Eigen::VectorXd start_state(const SolutionPoint& point);

private:
    HarmonicBalance& hb_;
    StabilityOptions options_;
    std::string refusal_;
    bool smooth_ = false;
    Eigen::MatrixXd minv_;  // M^-1
    Eigen::MatrixXd w_;     // every contact's directions (System::contact_directions), in order
};

/// The stability of every point of a branch (the samples too), and the bifurcations between
/// consecutive points of one branch where the count of multipliers outside the unit circle
/// changes: a real multiplier through +1 (a fold where the branch turns, else a branch point),
/// through -1 (period doubling), a complex pair (Neimark-Sacker).
struct BranchStability {
    std::vector<FloquetResult> points;  ///< one per point
    struct Interval {
        double omega_from = 0, omega_to = 0;  ///< the unstable points' range (in branch order)
        int branch = 1;
    };
    std::vector<Interval> unstable;    ///< maximal runs of consecutive unstable points
    struct Bifurcation {
        std::size_t after = 0;         ///< between points[after] and points[at], the next point of its
        std::size_t at = 0;            ///< branch with a verdict (uncertain points are skipped)
        double omega = 0;              ///< where the crossing multiplier's modulus is 1 (linear interpolation)
        std::string kind;              ///< "fold" (a real multiplier through +1 where the branch turns:
                                       ///< a fold point between), "branch-point" (through +1 without a
                                       ///< turn: symmetry breaking, or a jump at a stick-slip transition),
                                       ///< "period-doubling" (through -1), "neimark-sacker" (a complex pair)
        int branch = 1;
    };
    std::vector<Bifurcation> bifurcations;
    int stable = 0, unstable_points = 0, uncertain = 0, not_computed = 0;
    /// Points where Hill's sorted selection and the monodromy were both confident and disagreed
    /// (located folds, where a multiplier is 1 by definition, are not counted).
    int sorting_disagreements = 0;
    int both_confident = 0;           ///< points where both routes ran and were confident
    double seconds = 0;
    /// Why StabilityOptions::stop ended the analysis ("" where it did not): the points from
    /// there on are not_computed.
    std::string stopped;
    /// One line: counts, disagreements, unstable intervals, time.
    std::string summary() const;
};

/// Fills b.unstable and b.bifurcations from the verdicts b.points (one per point, as
/// analyse_branch_stability computed them): runs of unstable points per branch, and between
/// consecutive points of a branch with a verdict (stable or unstable; uncertain ones skipped)
/// each change in the count of multipliers beyond 1 + tolerance of one kind.
void find_bifurcations(const std::vector<SolutionPoint>& points, double tolerance, BranchStability& b);

/// Marks the bifurcations of `b` other than folds (which are points already) on the points: the
/// point past each crossing (Bifurcation::at) becomes of kind branch_point, period_doubling or
/// neimark_sacker if it is regular.
void mark_bifurcations(const BranchStability& b, std::vector<SolutionPoint>& points);

/// Analyses `points` (a branch in order, then samples of kind sample). With `polish` (the
/// exact polish of these very points, same order), the verdicts of the points it polished
/// (coulomb, jenkins, unilateral) are read from it.
BranchStability analyse_branch_stability(HarmonicBalance& hb, const std::vector<SolutionPoint>& points,
                                         const StabilityOptions& options,
                                         const std::vector<ExactPoint>* polish = nullptr);

}  // namespace hbf
