// hbfriction — the optimisation of the largest peak (the paper's Section 4: the friction
// coefficient that makes the absorber most effective): a scan and a golden-section search in
// one parameter, and nested searches in two.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "hbf/frf.hpp"
#include "hbf/verdict.hpp"

namespace hbf {

struct OptimizeOptions {
    double lower = 0;          ///< search range of the parameter p, 0 < lower < upper
    double upper = 0;
    /// Points of the first scan, log-spaced over [lower, upper] (>= 3): it brackets the best
    /// value before the golden-section search, and finds the right valley when the peak is not
    /// unimodal in p over the whole range (unbounded at both ends, as for a friction damper).
    int scan_points = 13;
    /// The golden-section search in log p stops when the bracket's width is below
    /// tolerance * p (relative; 1e-12..0.1).
    double tolerance = 1e-4;
    int max_evaluations = 200;  ///< FRFs in all (scan included), >= scan_points + 1
    int threads = 0;            ///< for the scan (compute_frfs); the search is sequential
    /// Called after each batch of FRFs (the scan, then each FRF of the search) with a line on
    /// where the search is (a progress display); may be empty.
    std::function<void(const std::string& text)> progress;
};

enum class OptimizeStatus {
    converged,   ///< the bracket shrank to the tolerance around an interior optimum
    at_bound,    ///< the best value is at lower or upper: widen the range
    budget,      ///< max_evaluations reached before the tolerance
    unbounded,   ///< no p in the scan gives a bounded FRF
    failed       ///< nothing usable (every FRF failed)
};
std::string to_string(OptimizeStatus status);

/// One FRF of the search.
struct OptimizeEvaluation {
    double parameter = 0;
    PeakValue peak;
    std::vector<Peak> peaks;       ///< the refined peaks of outputs[0] (every one, not just the largest)
    ContinuationStatus status = ContinuationStatus::completed;
    std::string phase;             ///< "scan" or "golden"
    double seconds = 0;
    LibraryMessages messages;      ///< what the numerical libraries reported during its FRF(s)
};

struct OptimizeResult {
    OptimizeStatus status = OptimizeStatus::failed;
    double parameter = 0;          ///< the best p evaluated
    PeakValue peak;                ///< its largest peak
    std::vector<Peak> peaks;       ///< its peaks of outputs[0]
    double bracket_lower = 0, bracket_upper = 0;  ///< final bracket of the search
    std::vector<OptimizeEvaluation> trace;        ///< in the order evaluated
    int failed = 0;                ///< evaluations whose FRF failed or stayed incomplete
    int failed_in_bracket = 0;     ///< of which inside the final bracket (a doubtful optimum)
    std::string message;
    double seconds = 0;
    LibraryMessages messages;      ///< of every evaluation (each FRF counts its own, on its thread)
    /// One line: status, the parameter (named `name`), peak, evaluations.
    std::string summary(const std::string& name = "p") const;
    /// The verdict of the search (hbf optimize's exit code, Python's warning): converged is
    /// completed; at_bound and budget a warning, unbounded and failed an error (the summary
    /// line); FRFs that failed or stayed incomplete inside the final bracket a warning (the
    /// optimum is doubtful), outside it a note; the libraries' messages of the search and of
    /// `also` (computations beside it, e.g. a comparison FRF) one warning.
    Verdict verdict(const std::string& name = "p", const LibraryMessages& also = {}) const;
};

/// Minimises the largest peak of the FRF of system(p) over p in [lower, upper]: a log-spaced
/// scan (on threads), then a golden-section search in log p over the two scan intervals
/// around the best scan point. The peak as a function of p is continuous but not smooth (the
/// largest of several peaks switches); golden section needs only unimodality in the bracket.
/// Ties (two unbounded trial points) keep the side of the best point found so far. Throws
/// InvalidInput for bad options.
OptimizeResult optimize_parameter(const std::function<System(double)>& system, const FrfSettings& settings,
                                  const OptimizeOptions& options);

/// A joint search in two parameters (p, q), e.g. the friction coefficient and the tuning.
struct JointOptimizeResult {
    /// The search in q: each evaluation is a whole search in p at that q (optimize_parameter),
    /// whose best peak is the objective; outer.parameter is the best q.
    OptimizeResult outer;
    std::vector<OptimizeResult> inner;  ///< inner[k]: the search in p at outer.trace[k].parameter
    std::size_t best = 0;               ///< index of the best q in outer.trace and inner
    double parameter = 0;               ///< the best p (at the best q)
    int inner_not_converged = 0;        ///< inner searches whose status is not converged
    int frfs() const;                   ///< FRFs computed in all
    /// One line: status, both parameters (named p_name, q_name), peak, searches and FRFs.
    std::string summary(const std::string& p_name = "p", const std::string& q_name = "q") const;
    /// As OptimizeResult::verdict for the search in q (its summary line, its searches in p that
    /// failed inside or outside the final bracket), and the search in p at the best q: a warning
    /// when it did not converge or has failed FRFs inside its bracket, a note when other
    /// searches in p did not converge.
    Verdict verdict(const std::string& p_name = "p", const std::string& q_name = "q",
                    const LibraryMessages& also = {}) const;
};

/// Minimises the largest peak of system(p, q) over both: P(q) = min over p of the peak
/// (optimize_parameter with `inner` options) is minimised over q by the same scan and golden
/// section (`outer` options; its threads are unused: each inner scan runs on inner.threads).
/// Nested 1-D searches, not a 2-D simplex: the optimum of a tuned damper lies on a ridge of
/// equal peaks that is oblique to the axes, where alternating (coordinate) searches stall,
/// while P(q) stays a function of one variable with a (non-smooth) minimum. Costs about
/// (outer evaluations) x (inner evaluations) FRFs. Throws InvalidInput for bad options.
JointOptimizeResult optimize_two_parameters(const std::function<System(double, double)>& system,
                                            const FrfSettings& settings, const OptimizeOptions& inner,
                                            const OptimizeOptions& outer);

}  // namespace hbf
