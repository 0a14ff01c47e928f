// hbfriction — the post-processing of a branch: the metrics of each solution point (maxima,
// harmonics, stick fractions and regimes, energy balance), the signals of a point, and the
// peaks of an output with their refinement.
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <limits>
#include <string>
#include <vector>

#include "hbf/continuation.hpp"

namespace hbf {

/// Quantities derived from one solution point.
struct PointMetrics {
    std::vector<double> y_max;   ///< per DOF: max over one period of |y_i(t)| (fine grid,
                                 ///< polished by Newton on y_i' = 0: exact to rounding);
                                 ///< NaN for a DOF the Analyser was not asked to report
    std::vector<double> y_amp1;  ///< per DOF: first-harmonic amplitude sqrt(c1^2 + s1^2)
    std::vector<double> output_max;   ///< per Analyser output (model.hpp), in order: max over
                                      ///< one period of |o(t)| (polished as y_max)
    std::vector<double> output_amp1;  ///< per output: first-harmonic amplitude of o(t)
    double stick_fraction = 0;   ///< share of the AFT samples of contact 1 in stick phases, by
                                 ///< the law's own definition (stick_pattern below)
    std::string regime;          ///< "stick", "slip" or "stick-slip" (stick_pattern below) of
                                 ///< contact 1; "none" without contacts
    std::vector<ContactRegime> contacts;  ///< every contact's, in order (contacts[0]: the two above)
    double stick_indicator_max = 0;  ///< max over the samples of contact 1's stick indicator
                                     ///< (< 0: permanent stick)
    double stick_indicator_min = 0;  ///< min over the samples (>= 0: permanent slip)
    double energy = 0;           ///< friction energy dissipated per cycle, all contacts
    double input_energy = 0;     ///< work of the excitation per cycle, pi h sum_i F_i s_h,i (h: excitation harmonic)
    double viscous_energy = 0;   ///< energy dissipated per cycle by C: pi w sum_k k^2 (c_k' C c_k + s_k' C s_k)
    /// Energy balance of the harmonic-balance solution: |input - viscous - friction| per cycle,
    /// relative to max(pi h |F| |(c_h, s_h)|, input, viscous + |friction|), the first being the
    /// work the force could do on the response's harmonic h (0 when nothing moves). At a converged HB
    /// point it is at the level of the residual tolerance; above energy_balance_tolerance the
    /// point is suspect (flagged by hbf frf).
    double energy_error = 0;
    /// Harmonic balance's estimated truncation error of outputs[0]'s max |o(t)| at this point,
    /// relative to its largest value on the FRF (FrfSettings::error_points); NaN where not
    /// estimated.
    double hb_error = std::numeric_limits<double>::quiet_NaN();
};
/// Largest energy_error of an accepted point (PointMetrics) for a corrector tolerance:
/// max(1e-6, 100 tolerance). Measured at the default 1e-9: 1e-10..1e-9 on the paper's absorber
/// (every law) and the chain examples.
double energy_balance_limit(double tolerance);
// energy_imbalance (shared with time integration): model.hpp.
/// The displacement below which a response of `system` at `omega` is rounding, not motion:
/// 1e-9 |F|_inf / max(max|K_ii|, omega^2 max M_ii) (1e-9 of the quasi-static or mass-line
/// response). Floors the energy balance's reach (pi h |F| response_floor: a response held at
/// exactly zero by a stuck contact has no meaningful relative imbalance) and the peaks (a
/// maximum below |c|_1 response_floor is noise, not a peak).
double response_floor(const System& system, double omega);
/// Stick fraction and regime of a contact from its stick indicator samples phi (contact_force.hpp:
/// a sample sticks iff phi < 0). A stick phase is a run of cyclically consecutive sticking
/// samples at least `min_run` long. H harmonics cannot resolve shorter phases: at an
/// instantaneous stop (a velocity reversal in continuous slip) the dynamic Lagrangian's force
/// passes from -F_c to F_c within about one resolution cell 2 pi / (2H + 1), and those
/// samples stick; measured, such runs last 0.8-1.7 cells. So HB uses min_run = two cells,
/// ceil(2 N_t / (2H + 1)) samples (stick_phase_samples): shorter runs count as slip. regime:
/// "stick" (every sample sticks), "slip" (no stick phase) or "stick-slip"; fraction: share
/// of the samples in stick phases.
ContactRegime stick_pattern(const Eigen::VectorXd& phi, int min_run);
/// Shortest stick phase, in samples, that H harmonics on N_t samples resolve (see above).
int stick_phase_samples(int harmonics, int time_samples);

/// Samples per period of the fine reconstruction used for y_max and the stick fraction.
int fine_time_samples(int harmonics);

/// Computes PointMetrics; holds the fine-grid transform (planned once) for many points.
class Analyser {
public:
    /// `report`: the DOFs (0-based) whose y_max is computed (empty: all DOFs). y_amp1 and the
    /// input work are computed for every DOF (cheap).
    explicit Analyser(HarmonicBalance& hb, std::vector<int> report = {});
    /// y_max of the DOFs `report` only (none when empty), and output_max, output_amp1 of every
    /// output (validated against the system: InvalidInput).
    Analyser(HarmonicBalance& hb, std::vector<int> report, std::vector<Output> outputs);
    PointMetrics operator()(const SolutionPoint& point);

private:
    HarmonicBalance& hb_;
    Fourier fine_;
    std::vector<int> report_;
    std::vector<Output> outputs_;
};

/// The time signals of one solution over one period, on the AFT grid theta_j = 2 pi j / N_t
/// (t = theta / omega): every DOF, and contact `contact`'s relative displacement q, relative
/// velocity v = dq/dt, friction force f and stick indicator phi (contact_force.hpp: sticks iff
/// phi < 0). f against v is the friction loop (paper Figs. 5-6).
struct PointSignals {
    Eigen::VectorXd time;       ///< t_j = theta_j / omega
    Eigen::MatrixXd y;          ///< N_t x N: y_i(t_j)
    Eigen::VectorXd q, v, f, phi;  ///< f: the law's own force (FrictionModel::force_samples)
    Eigen::VectorXd f_series;      ///< f's H-harmonic Fourier series (what the balance sees)
    /// Every direction of the contact (System::contact_directions; q, f are the first column):
    /// N_t x s relative displacements and forces (laws elastic, unilateral: the tangential
    /// ones, then the normal displacement v and force N).
    Eigen::MatrixXd q_directions, f_directions;
};
/// A contact with several directions (contact_force.hpp: signals): q, v and f along its first
/// (tangential) direction, and every direction in q_directions, f_directions.
PointSignals point_signals(HarmonicBalance& hb, const SolutionPoint& point, int contact);

/// A resonance peak: a local maximum of max_t |y_dof(t)| (or of an output's |o(t)|) along a
/// branch.
struct Peak {
    double omega = 0;
    double y_max = 0;        ///< max over one period of |y_dof(t)| (|o(t)|) at the peak
    int branch = 1;
    bool refined = false;    ///< located by the search below (false: the best branch point)
    int output = 0;          ///< which of the outputs asked for (0-based; 0 for a single DOF)
    std::string why;         ///< refined = false: why not (refine_peak)
    /// The peak stands less above its valleys (its prominence along the branch, relative to
    /// the FRF's largest value) than harmonic balance's estimated error there
    /// (FrfSettings::error_points): not resolved at this H, possibly an artefact of it.
    bool within_error = false;
};

/// Whether a local maximum y of an output is a peak, not rounding: above `floor` (its weight
/// |c|_1 times response_floor) and above 1e-8 of the output's largest value on the branch (a
/// response held at zero by a stuck contact wiggles at the solver's tolerance).
bool is_peak_value(double y, double largest, double floor);
/// Refines `peak`, found at branch point m between its neighbours a and b (same branch, y(m)
/// = peak.y_max above both), by Brent's search in omega over the neighbours' interval with
/// value(omega, ok) (ok = false where the solve fails), until its bracket is below 1e-9 omega
/// (values locate a maximum in omega only to about sqrt(dy / c) relative, dy the values'
/// rounding relative to y and c = y'' omega^2 / (2 y) the peak's curvature: 1e-8 to 1e-7 on
/// sharp exact resonances; y_max itself is flat there, exact to its rounding). Not
/// refined, with the reason in peak.why: a fold among a, m, b, or omega not monotone through
/// them (y is not a function of omega there); a failed solve (its omega named); no value
/// above y(m) found (a corner of the curve, such as a stick/slip switch between two points).
/// A peak at a located transition (m of kind transition: a corner, located to 1e-10) is that
/// point, refined.
void refine_peak(Peak& peak, const SolutionPoint& a, const SolutionPoint& m, const SolutionPoint& b,
                 const std::function<double(double, bool&)>& value);
/// "N peak(s) not refined: <output> at w = W (why); ..." for the unrefined peaks (their
/// outputs' names in `names`, by Peak::output), or "" when every peak is refined.
std::string unrefined_peaks(const std::vector<Peak>& peaks, const std::vector<std::string>& names);

/// Peaks of DOF `dof` (0-based): every branch point whose y_max exceeds both neighbours on
/// the same branch, refined by a search in omega (Brent: parabolic steps, golden-section fallback) over the neighbours'
/// interval, solving exactly at each trial frequency (from the branch interpolation), to
/// |delta omega| <= 1e-9 omega (refine_peak; where it cannot, the branch point itself, with
/// refined = false and why).
std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, int dof, const CorrectorOptions& options);
/// The same for each output in turn (model.hpp): the peaks of outputs[0], then of outputs[1],
/// ..., each marked with its index in Peak::output.
std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, const std::vector<Output>& outputs,
                             const CorrectorOptions& options);

}  // namespace hbf
