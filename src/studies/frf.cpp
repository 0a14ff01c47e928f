// hbfriction — one FRF as a study (frf.hpp): its settings and their ranges, the automatic
// choices, compute_frf (continuation, samples, metrics, exact polish, peaks, stability) and
// its verdict; FRFs on threads (compute_frfs); one solution (solve_at); time-domain sweeps'
// verdicts (judge_sweep). The searches over FRFs are in optimize.cpp.

#include "hbf/frf.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "hbf/contact_law.hpp"
#include "hbf/diagnostics.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/static_state.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/rigid_exact.hpp"
#include "base/enum_table.hpp"
#include "studies/hb_error.hpp"

namespace hbf {

namespace {
double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Whether output `index` of `outputs` (DOF 1 when empty) is a single DOF, whose amplitude the
/// cap max_amplitude bounds.
bool capped_output(const std::vector<Output>& outputs, int index) {
    if (outputs.empty()) return index == 0;
    return index >= 0 && index < static_cast<int>(outputs.size()) &&
           outputs[static_cast<std::size_t>(index)].single_dof() >= 0;
}

/// The largest peak of output 0 over the points and the refined peaks, and what it means: a
/// value above the amplitude cap (a single-DOF output) is an unbounded resonance as far as the
/// cap goes, as if the continuation had stopped there.
PeakValue largest_peak(const FrfResult& r, const FrfSettings& settings) {
    PeakValue p;
    double best = -1.0, at = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < r.points.size(); ++k) {
        if (r.metrics[k].output_max.empty()) continue;
        const double y = r.metrics[k].output_max.front();
        if (std::isfinite(y) && y > best) {
            best = y;
            at = r.points[k].omega;
        }
    }
    for (const Peak& peak : r.peaks)
        if (peak.output == 0 && std::isfinite(peak.y_max) && peak.y_max > best) {
            best = peak.y_max;
            at = peak.omega;
        }
    if (best >= 0.0) {
        p.value = best;
        p.omega = at;
    }
    switch (r.branch.status) {
        case ContinuationStatus::completed: p.state = PeakState::bounded; break;
        case ContinuationStatus::amplitude_cap: p.state = PeakState::unbounded; break;
        case ContinuationStatus::left_range:
        case ContinuationStatus::point_budget:
        case ContinuationStatus::stopped: p.state = PeakState::incomplete; break;
        case ContinuationStatus::min_step:
        case ContinuationStatus::solver_error:
        case ContinuationStatus::start_failed: p.state = PeakState::failed; break;
    }
    if (r.polish && r.polish->failed > 0) p.state = PeakState::failed;
    if (best < 0.0 && p.state == PeakState::bounded) p.state = PeakState::failed;  // no finite point
    if (p.state == PeakState::bounded && capped_output(settings.outputs, 0) &&
        best > settings.continuation.max_amplitude)
        p.state = PeakState::unbounded;
    if (p.state == PeakState::unbounded) p.value = std::numeric_limits<double>::infinity();
    return p;
}
}  // namespace

constexpr detail::EnumName<PeakState> peak_state_names[] = {
    {PeakState::bounded, "bounded"}, {PeakState::unbounded, "unbounded"}, {PeakState::incomplete, "incomplete"},
    {PeakState::failed, "failed"}};

std::string to_string(PeakState state) { return detail::enum_name(peak_state_names, state, "peak state"); }

double PeakValue::objective() const {
    return state == PeakState::bounded ? value : std::numeric_limits<double>::infinity();
}

int default_harmonics(FrictionLaw law) {
    return contact_law(law).default_harmonics();
}

int automatic_harmonics(const System& system, bool exact) {
    int h = 10;
    if (!exact)
        for (const Contact& c : system.contacts) h = std::max(h, default_harmonics(c.law));
    return std::min(max_harmonics, h * std::max(1, system.excitation_harmonic));
}

namespace {
void check_study_options(const FrfSettings& s);
}

void FrfSettings::validate() const {
    harmonic_balance.validate();
    check_study_options(*this);
    check_start_harmonics(continuation.start_harmonics, harmonic_balance.harmonics);  // the force's harmonic: continue_branch
}

namespace {
/// FrfSettings::validate but for harmonic_balance (compute_frf(hb, ...) uses hb's own).
void check_study_options(const FrfSettings& s) {
    hbf::validate(s.continuation);
    const std::vector<double>& at = s.at;
    for (std::size_t k = 0; k < at.size(); ++k) {
        if (!(at[k] > 0.0) || !std::isfinite(at[k]))
            throw InvalidInput("at = " + format_number(at[k]) + " is out of range: allowed frequencies > 0");
        if (std::find(at.begin(), at.begin() + static_cast<std::ptrdiff_t>(k), at[k]) != at.begin() + static_cast<std::ptrdiff_t>(k))
            throw InvalidInput("at lists w = " + format_number(at[k]) +
                               " more than once: allowed distinct frequencies (each is one solved row)");
    }
    if (s.stability) s.stability_options.validate();
    check_exact_threads(s.exact_threads, "exact_threads");
    if (s.error_points < 0 || s.error_points > 1000)
        throw InvalidInput("error_points = " + std::to_string(s.error_points) +
                           " is out of range: allowed 0..1000 (0: no estimate of harmonic balance's error)");
    if (!(s.error_limit > 0.0))
        throw InvalidInput("error_limit = " + format_number(s.error_limit) + " is out of range: allowed > 0 (a large value: never a warning)");
}
}  // namespace

FrfSettings frf_settings(const System& system, const std::vector<Output>& outputs, const FrfChoices& choices) {
    FrfSettings s;
    s.outputs = outputs;
    ContinuationOptions& co = s.continuation;
    if (choices.omega_start) co.omega_start = *choices.omega_start;
    if (choices.omega_end) co.omega_end = *choices.omega_end;
    // the polish's cost per period is set by the lowest frequency (exact_cost_refusal)
    if (choices.exact) {
        s.exact = *choices.exact;
    } else {
        // The element count first: the refusal's cost estimate builds the exact solver's flows,
        // itself costly for a thousand sliders.
        bool exact_laws = !system.contacts.empty();
        for (const Contact& c : system.contacts) exact_laws = exact_laws && contact_law(c.law).exact_stick();
        const std::size_t elements = exact_laws ? time_domain_system(system).contacts.size() : 0;
        const std::string refusal =
            elements <= static_cast<std::size_t>(max_automatic_exact_elements)
                ? exact_polish_refusal(system, co.omega_start > 0.0 && std::isfinite(co.omega_start) ? co.omega_start : 0.0, 0)
                : std::string();
        s.exact = elements <= static_cast<std::size_t>(max_automatic_exact_elements) && refusal.empty();
        // A model the exact solver cannot take, whose laws it covers: said, with the reason.
        if (!refusal.empty() && (exact_laws || rigid_contacts_only(system) || elastic_contacts_only(system)))
            s.exact_note = refusal.rfind("the exact polish", 0) == 0
                               ? refusal
                               : "the exact polish is off here (" + refusal +
                                     "): the FRF is harmonic balance's, its error against the exact orbit not measured";
        if (s.exact && rigid_contacts_3d(system)) {
            s.exact = false;
            s.exact_note = "the exact polish is off by default for 3D rigid contacts (law unilateral with a "
                           "second_direction: near a resonance of a meshed interface one exact orbit can take minutes, "
                           "where nodes graze their friction cones or mirror-image nodes switch at one instant and the "
                           "period map is only piecewise smooth): the FRF is harmonic balance's, its error against the "
                           "exact orbit not measured (exact on polishes anyway; hbf timeint --method exact sweeps the "
                           "exact orbits)";
        }
        if (s.exact && elastic_contacts_only(system)) {
            s.exact = false;
            s.exact_note = "the exact polish is off by default for law elastic (its penalty contacts make harmonic "
                           "balance converge fast, and its estimated error is given instead; the exact orbit is not "
                           "found at harmonic balance's own fold points where the exact fold lies elsewhere, nor "
                           "always exactly at a grazing change of the contact state): the FRF is harmonic balance's "
                           "(exact on polishes)";
        }
        if (elements > static_cast<std::size_t>(max_automatic_exact_elements)) {
            s.exact = false;
            s.exact_note = "the exact polish is off by default for " + std::to_string(elements) +
                           " exact elements (an Iwan joint's sliders count one each; more than " +
                           std::to_string(max_automatic_exact_elements) +
                           ": its cost grows as their cube): the FRF is harmonic balance's, its error against the exact "
                           "orbit not measured (exact on polishes anyway)";
        }
        s.exact_automatic = s.exact;
    }
    HarmonicBalanceOptions& hbo = s.harmonic_balance;
    hbo.harmonics = choices.harmonics ? *choices.harmonics : automatic_harmonics(system, s.exact);
    if (choices.time_samples) hbo.time_samples = *choices.time_samples;
    if (choices.modes) hbo.modes = *choices.modes;
    if (choices.odd_harmonics) hbo.odd_harmonics = *choices.odd_harmonics;
    if (choices.jacobian) hbo.jacobian = *choices.jacobian;
    if (choices.formulation) hbo.formulation = *choices.formulation;
    if (!choices.harmonics) {
        // The automatic H within the dense Jacobian's bound (HarmonicBalance::max_unknowns),
        // said in a note; a cheap bound first spares the probe's static solve on small models.
        const std::size_t per_coefficient_bound = static_cast<std::size_t>(system.dofs()) + 8 * system.contacts.size();
        if (per_coefficient_bound * static_cast<std::size_t>(2 * hbo.harmonics + 1) >
            static_cast<std::size_t>(HarmonicBalance::max_unknowns)) {
            try {
                const int fits = HarmonicBalance::fitting_harmonics(system, hbo, hbo.harmonics);
                if (fits < hbo.harmonics && fits >= std::max(1, system.excitation_harmonic)) {
                    s.harmonics_note = "H = " + std::to_string(fits) + " instead of the automatic " +
                                       std::to_string(hbo.harmonics) + ": the largest whose unknowns fit the dense "
                                       "Jacobian's bound of " + std::to_string(HarmonicBalance::max_unknowns) +
                                       " (a larger H: fewer contacts, or jacobian = structured)";
                    hbo.harmonics = fits;
                }
            } catch (const InvalidInput&) {
                // the system's own error: the FRF's validation reports it
            }
        }
    }
    // Each located stick-slip transition is a bisection of some thirty corrections: an
    // interface of many nodes has hundreds of them (measured: the 25-node block example at H = 3
    // had not finished in 10 minutes). Beyond max_located_contacts the regimes are reported per
    // point (the columns and the shares of nodes) but their boundaries are not located.
    constexpr std::size_t max_located_contacts = 8;
    co.locate_transitions = !s.exact && system.contacts.size() <= max_located_contacts;
    s.peaks = choices.peaks.value_or(true) || s.exact;
    s.peaks_of_every_output = choices.peaks_of_every_output.value_or(true);
    return s;
}

FrfSettings default_frf_settings(const System& system, const std::vector<Output>& outputs) {
    return frf_settings(system, outputs);
}

Verdict judge_frf(const FrfResult& frf, const FrfSettings& settings) {
    Verdict v;
    const BranchResult& branch = frf.branch;
    if (branch.status == ContinuationStatus::min_step || branch.status == ContinuationStatus::solver_error ||
        branch.status == ContinuationStatus::start_failed)
        v.errors.push_back(branch.summary() + " (the points computed so far are written)");
    else if (branch.status != ContinuationStatus::completed)
        v.warnings.push_back(branch.summary() + "; the branch spans " + format_number(100.0 * branch.coverage) +
                             " % of [wmin, wmax]");
    else if (branch.unlocated_transitions > 0)
        v.warnings.push_back(branch.message + " (the branch points are right; the CSV lacks those transition rows)");
    if (branch.location_errors > 0)
        v.warnings.push_back(std::to_string(branch.location_errors) +
                             " fold or transition location(s) ended by the solver (not marked): " + branch.message);
    if (branch.status == ContinuationStatus::completed && branch.unresolved_resonances > 0)
        v.warnings.push_back(branch.message + " (the branch may jump across an unbounded resonance there)");
    // A point whose exact polish failed is HB's value, flagged exact = failed: a doubtful result.
    if (frf.polish && frf.polish->failed > 0)
        v.errors.push_back(frf.polish->summary() +
                           "; the failed rows keep their harmonic-balance values (column exact = failed)");
    // Regime changes between exact neighbours whose location failed: the CSV lacks their rows
    // (harmonic balance's own transitions are dropped by the polish), as for the branch's.
    if (frf.polish && frf.polish->unlocated_transitions > 0)
        v.warnings.push_back(std::to_string(frf.polish->unlocated_transitions) +
                             " exact transition(s) not located (a solve near it did not converge): the points are "
                             "exact; the CSV lacks those transition rows");
    // A polish on the modal form of a large model (modal_exact.hpp) is exact for that form: its
    // estimated truncation is said, and flagged where it is large or could not be estimated.
    if (frf.polish && frf.polish->modes > 0) {
        const PolishedBranch& p = *frf.polish;
        const std::string what = "the exact polish ran on the modal form (" + std::to_string(p.modes) +
                                 " modes + residual Ritz vectors; modal_exact.hpp): estimated truncation ";
        if (!std::isfinite(p.modal_truncation))
            v.warnings.push_back(what + "not available (no two mode counts converged at w = " +
                                 format_number(p.truncation_omega) + "): the exact values carry an unknown truncation");
        else if (p.modal_truncation > modal_truncation_warning)
            v.warnings.push_back(what + format_number(p.modal_truncation) + " at w = " +
                                 format_number(p.truncation_omega) + ", above 1e-6 (the largest mode count the exact "
                                 "solver takes)");
        else
            v.notes.push_back(what + format_number(p.modal_truncation) + " at w = " + format_number(p.truncation_omega));
    }
    // The energy balance of every harmonic-balance point (column energy_error).
    std::size_t unbalanced = 0, worst = 0;
    const double limit = energy_balance_limit(settings.continuation.corrector.tolerance);
    for (std::size_t k = 0; k < frf.metrics.size(); ++k) {
        if (frf.metrics[k].energy_error > limit) ++unbalanced;
        if (frf.metrics[k].energy_error > frf.metrics[worst].energy_error) worst = k;
    }
    if (unbalanced > 0)
        v.warnings.push_back(std::to_string(unbalanced) + " point(s) fail the energy balance (column energy_error > " +
                             format_number(limit) + ", max(1e-6, 100 --tolerance); the largest, " +
                             format_number(frf.metrics[worst].energy_error) + ", at w = " +
                             format_number(frf.points[worst].omega) +
                             "): the residual is small but the solution is not; a tighter --tolerance or more "
                             "harmonics may help");
    std::vector<std::string> names;
    for (const Output& o : settings.outputs) names.push_back(o.name());
    const std::string unrefined = unrefined_peaks(frf.peaks, names);
    if (!unrefined.empty())
        v.notes.push_back(unrefined + "; the JSON gives the branch point (refined = false, why)");
    if (frf.stability && (frf.stability->uncertain > 0 || frf.stability->not_computed > 0)) {
        const BranchStability& b = *frf.stability;
        std::string example;
        for (std::size_t k = 0; k < b.points.size() && k < frf.points.size() && example.empty(); ++k)
            if (!b.points[k].message.empty())
                example = "; e.g. at w = " + format_number(frf.points[k].omega) + ": " + b.points[k].message;
        v.notes.push_back(b.summary() + ": the points with stable = uncertain (or empty) have no verdict" + example);
    }
    // Without --stability the polish's own verdicts stand in the CSV: exact orbits whose
    // multipliers could not be computed (max_multiplier NaN, stable = uncertain) are said.
    if (!frf.stability && frf.polish && frf.polish->stability_unknown > 0) {
        std::string first;
        for (std::size_t k = 0; k < frf.exact.size() && k < frf.points.size() && first.empty(); ++k)
            if (frf.exact[k].status == PolishStatus::exact && !std::isfinite(frf.exact[k].max_multiplier))
                first = "; the first at w = " + format_number(frf.points[k].omega) + ": " + frf.exact[k].message;
        v.notes.push_back(std::to_string(frf.polish->stability_unknown) +
                          " exact point(s) of unknown stability (their Floquet multipliers could not be computed): "
                          "stable = uncertain in the CSV" + first);
    }
    if (!frf.stability && frf.polish && frf.polish->stability_unresolved > 0) {
        std::string first;
        for (std::size_t k = 0; k < frf.exact.size() && k < frf.points.size() && first.empty(); ++k)
            if (frf.exact[k].status == PolishStatus::exact && frf.exact[k].stability_unresolved)
                first = " (the first at w = " + format_number(frf.points[k].omega) + ", largest multiplier " +
                        format_number(frf.exact[k].max_multiplier) + ")";
        v.notes.push_back(std::to_string(frf.polish->stability_unresolved) +
                          " exact point(s) of uncertain stability" + first +
                          ": their largest multiplier, from central differences of the period map, is above 1 by less "
                          "than the differences' accuracy (" + format_number(difference_multiplier_accuracy) +
                          "), a neutral direction they cannot place: stable = uncertain in the CSV");
    }
    // A refined peak between two branch points may climb past the amplitude cap the branch
    // points respect: a resonance unbounded as far as the cap goes, never a completed FRF.
    const double cap = settings.continuation.max_amplitude;
    for (const Peak& peak : frf.peaks)
        if (capped_output(settings.outputs, peak.output) && !(peak.y_max <= cap))
            v.warnings.push_back("the peak at w = " + format_number(peak.omega) + " reaches " +
                                 format_number(peak.y_max) + ", above the amplitude cap " + format_number(cap) +
                                 " (--max-amplitude): an unbounded resonance as far as the cap goes");
    // An --at sample above every branch point and every peak of the same output: the branch
    // stepped over a resonance between two points (its peak is missing or understated).
    std::vector<double> highest;  // per output: the largest over branch points and peaks
    for (std::size_t k = 0; k < frf.points.size() && k < frf.metrics.size(); ++k) {
        if (frf.points[k].kind == PointKind::sample) continue;
        const std::vector<double>& o = frf.metrics[k].output_max;
        if (highest.size() < o.size()) highest.resize(o.size(), 0.0);
        for (std::size_t j = 0; j < o.size(); ++j)
            if (std::isfinite(o[j])) highest[j] = std::max(highest[j], o[j]);
    }
    for (const Peak& peak : frf.peaks)
        if (peak.output >= 0 && static_cast<std::size_t>(peak.output) < highest.size() && std::isfinite(peak.y_max))
            highest[static_cast<std::size_t>(peak.output)] = std::max(highest[static_cast<std::size_t>(peak.output)], peak.y_max);
    for (std::size_t k = 0; k < frf.points.size() && k < frf.metrics.size(); ++k) {
        if (frf.points[k].kind != PointKind::sample) continue;
        const std::vector<double>& o = frf.metrics[k].output_max;
        for (std::size_t j = 0; j < o.size() && j < highest.size(); ++j)
            if (o[j] > highest[j] * (1.0 + 1e-9)) {
                v.warnings.push_back("the --at sample at w = " + format_number(frf.points[k].omega) + " reaches " +
                                     format_number(o[j]) + ", above every branch point and peak (the largest " +
                                     format_number(highest[j]) + "): the branch steps over a resonance there; a "
                                     "smaller --max-step may resolve it");
                break;
            }
    }
    // An --at frequency without a row is a failure too.
    for (double w : frf.missed)
        v.errors.push_back("--at w = " + format_number(w) + ": no solution written (outside the computed branch, or "
                           "the solve failed from the branch and after a retry)");
    v.add(frf.messages);
    return v;
}

bool centre_permanent_stick(HarmonicBalance& hb, SolutionPoint& point, double tolerance) {
    const System& system = hb.system();
    const int contacts = static_cast<int>(system.contacts.size());
    if (contacts == 0) return false;
    const auto stuck = [&](const Eigen::VectorXd& x) {
        for (int c = 0; c < contacts; ++c) {
            const FrictionLaw law = system.contacts[static_cast<std::size_t>(c)].law;
            if (!contact_law(law).exact_stick()) return false;
            if (!(hb.stick_indicator(x, point.omega, c).maxCoeff() < 0.0)) return false;
        }
        return true;
    };
    if (!stuck(point.x)) return false;
    const Eigen::VectorXd centred = hb.linear_guess(point.omega);
    Eigen::VectorXd r;
    hb.evaluate(centred, point.omega, r, nullptr);
    const double residual = r.allFinite() ? r.cwiseAbs().maxCoeff() / hb.force_scale() : INFINITY;
    if (!(residual <= std::max(tolerance, point.residual)) || !stuck(centred)) return false;
    point.x = centred;
    point.residual = residual;
    return true;
}

SolutionAt solve_at(HarmonicBalance& hb, double omega, double omega_from, ContinuationOptions options) {
    require_positive(omega, "w", "frequency of the solution");
    require_positive(omega_from, "wmin", "frequency the branch starts from");
    options.omega_start = omega > omega_from ? omega_from : 0.9 * omega;
    options.omega_end = omega;
    options.locate_transitions = false;
    SolutionAt r;
    r.branch = continue_branch(hb, options);
    const SolutionPoint* at = nullptr;
    for (const SolutionPoint& point : r.branch.points)
        if (point.omega == omega && (at == nullptr || point.branch < at->branch)) at = &point;
    if (at != nullptr) {
        r.found = true;
        r.point = *at;
        centre_permanent_stick(hb, r.point, options.corrector.tolerance);
    }
    return r;
}

namespace {
/// The largest N_t resolve_time_samples chooses: AFT costs grow as N_t log N_t per evaluation.
constexpr int max_automatic_time_samples = 16384;

struct Resolution {
    std::string message;  ///< what was done or what is wrong ("" when N_t was enough)
    bool doubtful = false;
};

/// The laws' own time scales (FrictionModel::time_samples_needed): where the branch's motion
/// needs more time samples than hb has, an automatic N_t (settings: 0) is raised to the power
/// of two that covers it (at most max_automatic_time_samples) and the branch computed again (the
/// motion, hence the need, changes a little: at most three times); a chosen N_t is kept, and
/// the result is doubtful.
Resolution resolve_time_samples(HarmonicBalance& hb, const FrfSettings& settings, BranchResult& branch) {
    Resolution out;
    const int first = hb.time_samples();
    for (int pass = 0; pass < 3; ++pass) {
        double needed = 0.0, where = 0.0;
        std::string why;
        for (const SolutionPoint& p : branch.points) {
            std::string reason;
            const double n = hb.time_samples_needed(p.x, p.omega, &reason);
            if (n > needed) {
                needed = n;
                where = p.omega;
                why = reason;
            }
        }
        if (needed <= hb.time_samples()) break;
        const std::string need = "the motion at w = " + format_number(where) + " needs N_t >= " +
                                 format_number(std::ceil(needed)) + " time samples: " + why;
        if (settings.harmonic_balance.time_samples > 0 || hb.time_samples() >= max_automatic_time_samples) {
            out.doubtful = true;
            out.message = need + ", the AFT has " + std::to_string(hb.time_samples()) +
                          ": the force is under-resolved (aliased) and the branch may be wrong or wiggle with spurious peaks (" +
                          (settings.harmonic_balance.time_samples > 0
                               ? "allowed: time_samples >= " + format_number(std::ceil(needed)) + ", or 0 (automatic)"
                               : "at most " + std::to_string(max_automatic_time_samples) +
                                     " are chosen automatically: a smoother law, or time_samples") +
                          ")";
            return out;
        }
        int n = hb.time_samples();
        while (n < needed && n < max_automatic_time_samples) n *= 2;
        hb.set_time_samples(n);
        out.message = need + ": the automatic N_t was raised from " + std::to_string(first) + " to " +
                      std::to_string(n) + " and the branch computed again";
        branch = continue_branch(hb, settings.continuation);
    }
    return out;
}
}  // namespace

/// A contact with a normal direction that is open at rest and stays open at every point: the
/// FRF is the linear structure's without it. Meant where the contact has a gap; without one,
/// the static load or the preload pulled it off (often a sign): a warning that says so.
void judge_open_contacts(const HarmonicBalance& hb, FrfResult& r) {
    const StaticState* rest = hb.rest_state();
    if (!rest || !rest->ok || r.metrics.empty()) return;
    const System& system = hb.system();
    for (std::size_t c = 0; c < system.contacts.size() && c < rest->contacts.size(); ++c) {
        if (rest->contacts[c].state != "open") continue;
        bool open = true;
        for (const PointMetrics& m : r.metrics)
            open = open && c < m.contacts.size() && m.contacts[c].separated_fraction >= 1.0 - 1e-12;
        if (!open) continue;
        const Contact& k = system.contacts[c];
        const auto gap = k.values.find("gap");
        const std::string line =
            "contact " + std::to_string(c + 1) + " is open at rest and stays open at every point: the FRF is the "
            "linear structure's without it";
        if (gap != k.values.end() && gap->second > 0.0)
            r.verdict.note(line + " (its gap " + format_number(gap->second) + " never closes)");
        else
            r.verdict.warning(line + "; it has no gap, so the static load or the preload pulls it off (normal force 0 "
                                     "at rest): check their signs (the normal gap normal_direction^T y grows as the "
                                     "contact closes)");
    }
}

/// What the truncation estimate says of the FRF: a warning above error_limit (or where no
/// point could be solved with more harmonics), a note otherwise.
void judge_hb_error(const detail::HbErrorSummary& e, const FrfSettings& settings, int harmonics, const Output& output,
                    Verdict& verdict) {
    if (settings.error_points <= 0 || (e.harmonics == 0 && e.why_not.empty())) return;
    const std::string h = std::to_string(harmonics), h2 = std::to_string(e.harmonics);
    if (e.harmonics == 0) {
        verdict.note("harmonic balance's truncation error is not estimated (H = " + h + "): " + e.why_not);
        return;
    }
    const std::string how = " (2 |y(H) - y(2H)| / max y, y = max |" + output.name() + "(t)| and max y its largest on the FRF, H = " + h + " against " + h2 +
                            ", at " + std::to_string(e.estimated) + " points: the branch's maxima and points spread over it" +
                            (e.failed > 0 ? "; " + std::to_string(e.failed) + " more did not converge at H = " + h2 : "") +
                            ")";
    if (e.estimated == 0) {
        verdict.warning("harmonic balance's truncation error could not be estimated: no point converged at H = " + h2 +
                        " (" + std::to_string(e.failed) + " tried): the FRF's accuracy is unknown");
        return;
    }
    const std::string line = "harmonic balance's estimated error is " + format_number(e.largest) + " at w = " +
                             format_number(e.omega) + how;
    if (e.largest > settings.error_limit)
        verdict.warning(line + ": above the error limit " + format_number(settings.error_limit) +
                        "; raise the harmonics (the column hb_error gives the estimate per point)");
    else
        verdict.note(line);
}

FrfResult compute_frf(HarmonicBalance& hb, const FrfSettings& settings) {
    const auto started = std::chrono::steady_clock::now();
    check_study_options(settings);
    MessageCollector collector;  // what Ceres and CVODE report during this FRF, on this thread
    if (settings.exact) {  // before the work: the polish must be possible at the branch's lowest w
        const double lowest = std::min(settings.continuation.omega_start, settings.continuation.omega_end);
        const std::string refusal = lowest > 0.0 ? exact_polish_refusal(hb.system(), lowest) : std::string();
        if (!refusal.empty()) throw InvalidInput("exact polish: " + refusal + " (use exact off)");
    }
    const std::vector<Output> outputs = settings.outputs.empty() ? std::vector<Output>{Output::dof(0)} : settings.outputs;
    const CorrectorOptions& corrector = settings.continuation.corrector;
    FrfResult r;
    std::string declined;  // why an automatic polish did not run
    r.branch = continue_branch(hb, settings.continuation);
    // A stop (an interrupt, a time limit: ContinuationOptions::stop) skips the phases after it;
    // the points computed so far are the result, its status stopped.
    std::string stopped;
    std::vector<std::string> skipped;
    auto stop_before = [&](const char* phase) {
        if (stopped.empty() && r.branch.status == ContinuationStatus::stopped) stopped = r.branch.message;
        if (stopped.empty() && settings.continuation.stop) stopped = settings.continuation.stop();
        if (stopped.empty()) return false;
        skipped.emplace_back(phase);
        return true;
    };
    const Resolution resolution =
        stop_before("the check of the AFT's time samples") ? Resolution{} : resolve_time_samples(hb, settings, r.branch);
    r.time_samples = hb.time_samples();
    r.points = r.branch.points;
    if (!settings.at.empty() && !stop_before("the --at samples")) {
        const auto samples = sample_branch(hb, r.branch, settings.at, corrector, &r.missed);
        r.points.insert(r.points.end(), samples.begin(), samples.end());
    }
    // y_max of DOF 1 (the folds and transitions of a summary) and every output; on a large
    // model only these are synthesised in time.
    Analyser analyse(hb, {0}, outputs);
    r.metrics.reserve(r.points.size());
    for (const SolutionPoint& point : r.points) r.metrics.push_back(analyse(point));
    if (settings.exact && !stop_before("the exact polish")) {
        PolishOptions po;
        po.dof = std::max(0, outputs.front().single_dof());
        po.exact.outputs = outputs;
        po.peaks = settings.peaks;
        po.peaks_of_every_output = settings.peaks_of_every_output;
        po.progress = settings.polish_progress;
        po.exact.stop = settings.continuation.stop;
        po.exact.threads = settings.exact_threads;
        if (settings.exact_automatic) po.decline_seconds = std::max(2.0, 10.0 * seconds_since(started));
        r.polish = polish_branch(hb, r.points, r.metrics, po, corrector);
        if (!r.polish->declined.empty()) {
            declined = "the exact polish was declined: " + r.polish->declined +
                       "; the FRF is harmonic balance's (H = " + std::to_string(hb.harmonics()) +
                       "), its error against the exact orbit not measured (exact on polishes anyway)";
            r.polish.reset();
        } else {
            r.points = r.polish->points;
            r.metrics = r.polish->metrics;
            r.exact = r.polish->exact;
            r.peaks = r.polish->peaks;
            if (!r.polish->stopped.empty() && stopped.empty()) {  // its points from there on stay HB's
                stopped = r.polish->stopped;
                skipped.emplace_back("the exact polish's remaining points");
            }
        }
    }
    if (!r.polish && settings.peaks && !stop_before("the peaks' refinement")) {
        r.peaks = settings.peaks_of_every_output ? find_peaks(hb, r.branch, outputs, corrector)
                                                 : find_peaks(hb, r.branch, {outputs.front()}, corrector);
    }
    detail::HbErrorSummary error;
    if (!r.polish && settings.error_points > 0 && !r.points.empty() &&
        !stop_before("the estimate of harmonic balance's error"))
        error = detail::estimate_hb_error(hb, settings, outputs, r);
    r.error_harmonics = error.harmonics;
    const int within = error.estimated > 0 ? detail::mark_peaks_within_error(r) : 0;
    r.hb_error = error.largest;
    r.hb_error_omega = error.omega;
    if (settings.stability && !stop_before("the stability analysis")) {
        StabilityOptions so = settings.stability_options;
        if (!so.stop) so.stop = settings.continuation.stop;
        so.exact_threads = settings.exact_threads;
        r.stability = analyse_branch_stability(hb, r.points, so, r.polish ? &r.exact : nullptr);
        mark_bifurcations(*r.stability, r.points);
        if (!r.stability->stopped.empty() && stopped.empty()) {
            stopped = r.stability->stopped;
            skipped.emplace_back("the stability analysis of the remaining points");
        }
    }
    if (!skipped.empty() && r.branch.status < ContinuationStatus::stopped) {
        // the branch was complete (or capped); what followed it was not
        r.branch.status = ContinuationStatus::stopped;
        r.branch.message += (r.branch.message.empty() ? "" : "; ") + std::string("stopped after the branch: ") + stopped;
    }
    r.peak = largest_peak(r, settings);
    r.messages = collector.messages();
    r.verdict = judge_frf(r, settings);
    if (!resolution.message.empty()) {
        if (resolution.doubtful) r.verdict.warning(resolution.message);
        else r.verdict.note(resolution.message);
    }
    judge_open_contacts(hb, r);
    const PenaltyDiagnostics penalties = penalty_diagnostics(hb.system(), hb.rest_state());
    for (const std::string& line : penalties.stiff) r.verdict.note(line);
    for (const std::string& line : penalties.relieved) r.verdict.warning(line);
    judge_hb_error(error, settings, hb.harmonics(), outputs.front(), r.verdict);
    if (within > 0) {
        int peaks = 0;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const Peak& p : r.peaks) {
            if (p.output != 0) continue;
            ++peaks;
            if (!p.within_error) continue;
            lo = std::min(lo, p.omega);
            hi = std::max(hi, p.omega);
        }
        r.verdict.note(std::to_string(within) + " of the " + std::to_string(peaks) + " peaks of " + outputs.front().name() +
                       " (w = " + format_number(lo) + " .. " + format_number(hi) +
                       ") stand less above their valleys than harmonic balance's estimated error there: not resolved "
                       "at H = " + std::to_string(hb.harmonics()) +
                       ", possibly its artefacts (raise the harmonics; within_hb_error in the JSON peaks)");
    }
    if (!skipped.empty()) {
        std::string list;
        for (std::size_t k = 0; k < skipped.size(); ++k)
            list += (k == 0 ? "" : k + 1 == skipped.size() ? " and " : ", ") + skipped[k];
        r.verdict.note("not done after the stop: " + list);
    }
    if (!declined.empty()) r.verdict.note(declined);
    if (!settings.exact_note.empty()) r.verdict.note(settings.exact_note);
    if (!settings.harmonics_note.empty()) r.verdict.note(settings.harmonics_note);
    r.seconds = seconds_since(started);
    return r;
}

std::string FrfResult::summary() const {
    std::string line = branch.summary();
    if (std::isfinite(peak.value))
        line += "; largest peak " + format_number(peak.value) + " at w = " + format_number(peak.omega);
    return line + "; " + verdict.summary();
}

FrfResult compute_frf(const System& system, const FrfSettings& settings) {
    settings.validate();
    HarmonicBalance hb(system, settings.harmonic_balance);
    return compute_frf(hb, settings);
}

std::vector<FrfResult> compute_frfs(int count, const std::function<System(int)>& systems, const FrfSettings& settings,
                                    int threads, const std::function<void(int, int)>& done) {
    if (count < 0) throw InvalidInput("count = " + std::to_string(count) + " is out of range: allowed >= 0");
    if (threads < 0) throw InvalidInput("threads = " + std::to_string(threads) + " is out of range: allowed >= 0");
    settings.validate();  // once, before any work (a bad system is that FRF's start_failed)
    if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::max(1, std::min(threads, count));
    // Several FRFs at once: each one's exact solver on its own thread (no second thread each).
    FrfSettings each = settings;
    if (threads > 1) each.exact_threads = 1;
    std::vector<FrfResult> results(static_cast<std::size_t>(count));
    std::atomic<int> next{0};
    std::mutex lock;
    int finished = 0;
    std::exception_ptr error;
    auto work = [&]() {
        for (int k = next++; k < count; k = next++) {
            FrfResult r;
            // After a stop request (settings.continuation.stop: the FRF running stops by itself),
            // an FRF not started is not computed: no point, status stopped.
            const std::string stopped = settings.continuation.stop ? settings.continuation.stop() : std::string();
            if (!stopped.empty()) {
                r.branch.status = ContinuationStatus::stopped;
                r.branch.message = "not computed: " + stopped;
                r.peak.state = PeakState::incomplete;
                r.verdict = judge_frf(r, settings);
                const std::lock_guard<std::mutex> guard(lock);
                results[static_cast<std::size_t>(k)] = std::move(r);
                ++finished;
                if (done) done(finished, count);
                continue;
            }
            try {
                System system;
                {
                    const std::lock_guard<std::mutex> guard(lock);
                    if (error) return;
                    system = systems(k);
                }
                r = compute_frf(system, each);
            } catch (const InvalidInput& e) {
                r = FrfResult{};
                r.branch.status = ContinuationStatus::start_failed;
                r.branch.message = e.what();
                r.peak.state = PeakState::failed;
                r.verdict = judge_frf(r, settings);
            } catch (...) {
                const std::lock_guard<std::mutex> guard(lock);
                if (!error) error = std::current_exception();
                return;
            }
            const std::lock_guard<std::mutex> guard(lock);
            results[static_cast<std::size_t>(k)] = std::move(r);
            ++finished;
            if (done) done(finished, count);
        }
    };
    if (threads == 1) {
        work();
    } else {
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work);
        for (std::thread& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
    return results;
}

void MapTally::add(const std::string& peak_state, int missed, const LibraryMessages& frf_messages) {
    ++frfs;
    if (peak_state == "failed") ++failed;
    else if (peak_state == "incomplete") ++incomplete;
    else if (peak_state == "unbounded") ++unbounded;
    missed_at += missed;
    messages.add(frf_messages);
}

void MapTally::add_error(double hb_error, double limit) {
    error_limit = limit;
    if (!std::isfinite(hb_error)) return;
    largest_error = std::max(largest_error, hb_error);
    if (hb_error > limit) ++doubtful;
}

Verdict MapTally::verdict() const {
    Verdict v;
    if (doubtful > 0)
        v.warning(std::to_string(doubtful) + " of " + std::to_string(frfs) + " FRFs have an estimated harmonic-balance "
                  "error above the error limit " + format_number(error_limit) + " (largest " + format_number(largest_error) +
                  "): raise the harmonics (hb_error in the CSV and the JSON)");
    if (failed > 0)
        v.warning(std::to_string(failed) + " of " + std::to_string(frfs) + " FRFs failed (a stall, a "
                  "failed start or a failed exact polish; their rows say frf_status, the JSON says why)");
    if (incomplete > 0)
        v.warning(std::to_string(incomplete) + " FRFs are incomplete (left_range, point_budget, or stopped by --time-limit "
                  "or an interrupt)");
    if (unbounded > 0)
        v.warning(std::to_string(unbounded) + " FRFs have an unbounded resonance (amplitude_cap: capped at "
                  "--max-amplitude)");
    if (missed_at > 0)
        v.warning(std::to_string(missed_at) + " --at frequencies got no row (outside an FRF's branch, or the solve "
                  "failed; missed_at in the JSON)");
    v.add(messages);
    return v;
}

}  // namespace hbf
