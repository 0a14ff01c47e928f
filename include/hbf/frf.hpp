// hbfriction — the FRF as one call: continuation of every branch (restarts past an amplitude cap
// included), the metrics of each point, the exact polish where it applies, stability, and the
// peaks of the outputs refined by a golden-section search in w, with the verdict; many FRFs on
// threads (maps); the solution at one frequency.
//
// The objective of a design study (optimize.hpp, tracking.hpp) is the largest max over one
// period of |o(t)| of the first output along the FRF (PeakValue): it comes from the full
// branches, so folds and coexisting solutions count.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/stability.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"
#include "hbf/verdict.hpp"

namespace hbf {

/// How one FRF is computed.
struct FrfSettings {
    HarmonicBalanceOptions harmonic_balance;
    ContinuationOptions continuation;
    /// Polish by the event-exact solver (exact_polish.hpp; coulomb and jenkins contacts only:
    /// exact_solver_supports).
    bool exact = false;
    /// exact is the automatic choice (frf_settings), not the user's: the polish is declined
    /// before its work where it would not be certain (a modal form whose estimated truncation
    /// exceeds 1e-6) or not affordable (one exact orbit at the highest point, times the points,
    /// above max(2 s, 10 times the harmonic-balance branch's time)); the FRF is then harmonic
    /// balance's, and a note says why.
    bool exact_automatic = false;
    /// Why the automatic choice left the polish off where the exact solver could have run
    /// (more exact elements than max_automatic_exact_elements): a note of the FRF.
    std::string exact_note;
    /// Why the automatic H is below automatic_harmonics (frf_settings: the largest H whose
    /// unknowns fit HarmonicBalance::max_unknowns): a note of the FRF.
    std::string harmonics_note;
    /// Reported outputs (model.hpp); the peaks and the objective are those of outputs[0].
    /// Empty: DOF 1 alone.
    std::vector<Output> outputs;
    /// Frequencies where every solution of the branch is solved and appended (kind sample).
    std::vector<double> at;
    /// Locate and refine the peaks (of outputs[0]; of every output with peaks_of_every_output).
    bool peaks = true;
    bool peaks_of_every_output = false;
    /// Floquet stability of every point (stability.hpp): Hill and/or the monodromy for the
    /// smooth laws, the event-exact solver for coulomb and jenkins (the polish's verdicts
    /// when it ran).
    bool stability = false;
    StabilityOptions stability_options;
    /// Harmonic balance's truncation error estimated where the FRF is not polished: the branch
    /// points where outputs[0] has its largest local maxima and points spread over the branch
    /// (error_points of each, at most) are solved again with twice the harmonics (fewer where
    /// the dense Jacobian's bound stops it), and PointMetrics::hb_error = 2 |y(H) - y(2H)| /
    /// max y, y = outputs[0]'s max |o(t)| and max y its largest on the FRF (harmonic balance of
    /// a nonsmooth law converges like 1/H: the change is half the error). 0: no estimate; 0..1000.
    int error_points = 12;
    /// An estimate above this (relative) is a warning: the FRF is doubtful (exit code 3).
    /// > 0; infinity: never.
    double error_limit = 1e-2;
    /// The exact solver's threads for rigid 3D contacts in the polish and the stability
    /// (ExactOptions::threads; stability_options.exact_threads is set to it): 0 two where the
    /// hardware has two cores, 1 or 2. compute_frfs running several FRFs at once takes 1 (each
    /// FRF on one core).
    int exact_threads = 0;
    /// The exact polish's progress (PolishOptions::progress); the continuation's is
    /// continuation.progress. May be empty.
    std::function<void(int done, int total)> polish_progress;

    /// The ranges every front end applies (hbf frf, Python's frf(), the studies), checked
    /// before any work: throws InvalidInput naming the first field out of range, its value and
    /// the allowed range: harmonic_balance.validate() (H, N_t, modes); the continuation's
    /// options (validate(ContinuationOptions): wmin < wmax, tolerance, max_step, ...); `at`
    /// distinct finite frequencies > 0; stability_options with stability.
    void validate() const;
};

/// Default H of harmonic balance for a law without the exact polish, measured (README,
/// benchmarks/hb_branch, tests/test_verification.cpp): Dahl, LuGre and Jenkins (continuous
/// force) converge fast (H = 10: the peak within 6e-5 of H = 40; Jenkins within 4e-6 of time
/// integration); exact Coulomb like 1/H (H = 20: about 1% at the peak); regularised Coulomb's
/// steep tanh (eps = 0.05) wiggles at H = 10 (13 spurious peaks on the default FRF), not at
/// H = 20.
int default_harmonics(FrictionLaw law);
/// The automatic H of `hbf frf` and of the Python frf(): 10 with the exact polish (harmonic
/// balance then only supplies the branch and the starting guesses: the same exact branch, peaks
/// and transitions as H = 20, 3 times faster); otherwise the largest default_harmonics of the
/// contacts' laws (10 without contacts); either times the excitation harmonic h, at most max_harmonics (100).
int automatic_harmonics(const System& system, bool exact);
/// The most exact elements (contacts as the exact solver sees them: an Iwan joint's sliders one
/// each) for which the polish is on by default: a period's cost grows about as their cube
/// (measured: 20 sliders 0.03 s an orbit, 50 sliders 0.34 s, 100 sliders 2.6 s).
constexpr int max_automatic_exact_elements = 32;

/// The choices a user made for an FRF, each unset where not made: a system file's [frequency]
/// and [solver] (io::SystemConfig::choices), then hbf frf's flags or Python's keyword arguments
/// over them. frf_settings makes the automatic choices for the others.
struct FrfChoices {
    std::optional<double> omega_start, omega_end;
    std::optional<int> harmonics;  ///< as given (FrfSettings::validate checks it); unset: automatic
    std::optional<int> time_samples, modes;
    std::optional<bool> odd_harmonics;
    std::optional<JacobianForm> jacobian;  ///< harmonic_balance.hpp (automatic when unset)
    std::optional<Formulation> formulation;  ///< harmonic_balance.hpp (automatic when unset)
    std::optional<bool> exact;     ///< unset: automatic
    /// Which peaks are located and refined: those of outputs[0] (peaks), of every output
    /// (peaks_of_every_output). Unset: both. The exact polish refines the peaks of outputs[0]
    /// whatever peaks says (its exact peaks are part of its result).
    std::optional<bool> peaks, peaks_of_every_output;
};

/// The settings of an FRF of `system` with the choices made: the one home of hbf frf's and
/// Python's automatic choices. Where not chosen:
///  - exact: the polish where the exact solver covers the system at the lowest frequency
///    (exact_cost_refusal at omega_start; exact_solver_supports if omega_start is not > 0)
///    with at most max_automatic_exact_elements elements (else off, exact_note says why, as it
///    does where the solver refuses a model whose laws it covers),
///    marked exact_automatic (declined at run time where not certain or not affordable);
///  - H: automatic_harmonics(system, exact), lowered to the largest H whose unknowns fit the
///    dense Jacobian's bound where the structured one does not apply (harmonics_note says so);
///  - locate_transitions: by harmonic balance only without the polish (the exact ones replace
///    them);
///  - peaks: of every output (and of outputs[0] with the polish, whatever is chosen);
/// and `outputs`. Every other option keeps its default; ranges are FrfSettings::validate's.
FrfSettings frf_settings(const System& system, const std::vector<Output>& outputs, const FrfChoices& choices = {});
/// frf_settings without choices: `hbf frf` without flags.
FrfSettings default_frf_settings(const System& system, const std::vector<Output>& outputs);

/// What the largest peak of an FRF means.
enum class PeakState {
    bounded,     ///< the branch spans [wmin, wmax]: value is the largest peak
    unbounded,   ///< amplitude_cap, or the largest peak of a single-DOF output above
                 ///< max_amplitude: a resonance grows past the cap (value = +infinity)
    incomplete,  ///< left_range or point_budget: value is the largest over the part computed
    failed       ///< min_step, start_failed, or a failed exact polish: value is a lower bound
};
/// "bounded", "unbounded", "incomplete", "failed".
std::string to_string(PeakState state);

/// The objective of a design study: the largest max over one period of |o(t)| of outputs[0]
/// over the FRF, at the frequency omega.
struct PeakValue {
    double value = std::numeric_limits<double>::quiet_NaN();
    double omega = std::numeric_limits<double>::quiet_NaN();
    PeakState state = PeakState::failed;
    /// The value a minimiser compares: value when bounded, +infinity otherwise (an unbounded
    /// resonance, and an FRF that is incomplete or failed, can never be the optimum).
    double objective() const;
};

struct FrfResult {
    BranchResult branch;                    ///< the continuation as it ran
    std::vector<SolutionPoint> points;      ///< the branch points (polished: the exact ones), then samples
    std::vector<PointMetrics> metrics;      ///< one per point
    std::vector<ExactPoint> exact;          ///< one per point with the polish, else empty
    std::optional<PolishedBranch> polish;   ///< with the polish
    std::vector<Peak> peaks;                ///< with FrfSettings::peaks
    std::vector<double> missed;             ///< `at` frequencies without a solution
    std::optional<BranchStability> stability;  ///< with FrfSettings::stability (one per point)
    PeakValue peak;                         ///< the largest peak of outputs[0]
    int time_samples = 0;                   ///< N_t of the AFT (raised from the automatic one
                                            ///< where a law needs more: FrictionModel::time_samples_needed)
    /// Harmonic balance's estimated truncation error (FrfSettings::error_points): the
    /// larger H it compared with (0: not estimated), the largest estimate and where.
    int error_harmonics = 0;
    double hb_error = std::numeric_limits<double>::quiet_NaN();
    double hb_error_omega = std::numeric_limits<double>::quiet_NaN();
    double seconds = 0;                     ///< wall time of compute_frf
    /// What Ceres and CVODE reported while this FRF was computed (on its thread).
    LibraryMessages messages;
    /// judge_frf of this result with the settings it was computed with (compute_frf sets it).
    Verdict verdict;
    /// verdict.status(): "completed", "incomplete" or "failed".
    std::string status() const { return verdict.status(); }
    /// One line: the branch (BranchResult::summary), the largest peak and the verdict.
    std::string summary() const;
};

/// The verdict on an FRF computed with `settings`:
///  - errors: a continuation that stalled or failed to start (min_step, start_failed); a failed
///    exact polish; an `at` frequency without a solution;
///  - warnings: a branch capped, out of range or out of points (with its coverage);
///    transitions that could not be located; a resonance of the linear structure crossed
///    unresolved (BranchResult::unresolved_resonances); a peak of a single-DOF output above
///    the amplitude cap (max_amplitude); an `at` sample above every branch point and peak of
///    its output (the branch stepped over a resonance); points that fail the energy balance
///    (energy_balance_limit); warnings of the numerical libraries during the FRF (frf.messages);
///  - notes: unrefined peaks, stability verdicts that are uncertain or missing.
Verdict judge_frf(const FrfResult& frf, const FrfSettings& settings);

/// The FRF of hb's system with these settings (hb's own options; settings.harmonic_balance
/// is not used). Throws InvalidInput for bad options or outputs.
FrfResult compute_frf(HarmonicBalance& hb, const FrfSettings& settings);
/// The same, building the HarmonicBalance from settings.harmonic_balance.
FrfResult compute_frf(const System& system, const FrfSettings& settings);

/// The harmonic-balance solution at omega reached by following the branch from omega_from
/// (from 0.9 omega when omega <= omega_from) with `options`' corrector and limits: what
/// `hbf loop` writes. Where branch 1 stops at an amplitude cap on the way, the point is where
/// branch 2 starts. found = false (branch says why) when no branch reaches omega.
struct SolutionAt {
    bool found = false;
    SolutionPoint point;
    BranchResult branch;
};
SolutionAt solve_at(HarmonicBalance& hb, double omega, double omega_from, ContinuationOptions options = {});
/// Permanent stick on the centred member (the convention of event_exact.hpp and contact_force.hpp):
/// when every contact is coulomb or jenkins and sticks on every AFT sample of `point`, the
/// solution is the linear stuck response (HarmonicBalance::linear_guess), whose means vanish;
/// the continuation's point differs from it by an offset of the stuck family at the corrector's
/// tolerance, which far above the resonances (a response ~ |F| / (m w^2), a force error ~
/// tolerance |F| held by a static stiffness) dwarfs the response. Replaces point.x by it when
/// its residual passes `tolerance` (or the point's own) and it sticks too; true if replaced.
/// solve_at applies it.
bool centre_permanent_stick(HarmonicBalance& hb, SolutionPoint& point, double tolerance);

/// FRFs of many systems, `threads` at a time (0: the hardware's concurrency), one FRF per
/// task; result k belongs to systems(k) and equals what compute_frf gives alone (every task
/// has its own solver state; settings.continuation.stop, asked from every thread, stops the FRFs
/// running and leaves those not started uncomputed: no point, status stopped, "not computed: ..."
/// in the branch's message). `done(finished, total)` is called after each FRF (from the
/// calling thread's lock, never concurrently); may be empty. A task that throws InvalidInput
/// stops nothing: its result has an empty branch, status start_failed and the message.
std::vector<FrfResult> compute_frfs(int count, const std::function<System(int)>& systems, const FrfSettings& settings,
                                    int threads, const std::function<void(int, int)>& done = {});

/// The tally of a map of FRFs (hbf map, Python's map()) and its verdict: a warning for the FRFs
/// that failed, those that are incomplete (left_range, point_budget), those with an unbounded
/// resonance (amplitude_cap), for the `at` frequencies that got no row, and one for the
/// libraries' messages of all the FRFs. Each FRF is added once (from any process).
struct MapTally {
    int frfs = 0, failed = 0, incomplete = 0, unbounded = 0, missed_at = 0;
    LibraryMessages messages;
    /// FRFs whose harmonic balance's estimated error (FrfResult::hb_error) exceeds the limit,
    /// and the largest estimate of all.
    int doubtful = 0;
    double error_limit = std::numeric_limits<double>::infinity();
    double largest_error = 0.0;
    /// Adds one FRF: its peak state ("failed", "incomplete", "unbounded", else complete), its
    /// missed `at` frequencies and its libraries' messages.
    void add(const std::string& peak_state, int missed, const LibraryMessages& frf_messages);
    /// Adds one FRF's estimated error (NaN: not estimated) against `limit` (FrfSettings::error_limit).
    void add_error(double hb_error, double limit);
    Verdict verdict() const;
};

}  // namespace hbf
