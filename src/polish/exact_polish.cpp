// hbfriction — harmonic-balance branches polished by the event-exact solver (exact_polish.hpp).
// Over 600 lines: the polish, its cost estimate and its modal-form choice decide together which
// points are exact; split, each would need the others' internals.
#include "hbf/exact_polish.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/rigid_exact.hpp"
#include "time_integration/law_orbit.hpp"
#include "base/stopwatch.hpp"
#include "base/enum_table.hpp"

namespace hbf {

namespace {

/// The HB point's metrics with the exact orbit's values. The energy balance is the orbit's own
/// where the structure is undamped (the exact solver integrates no viscous energy; with damping
/// the HB point's balance stays): an exact transition whose HB correction failed must not be
/// judged by that HB solution.
PointMetrics exact_metrics(const ExactOrbit& orbit, const PointMetrics& hb, const System& system) {
    PointMetrics m = hb;
    m.y_max = orbit.y_max;
    m.y_amp1 = orbit.y_amp1;
    m.output_max = orbit.output_max;
    m.output_amp1 = orbit.output_amp1;
    m.stick_fraction = orbit.stick_fraction;
    m.regime = orbit.regime;
    m.contacts = orbit.contacts;
    m.energy = orbit.energy;
    m.input_energy = orbit.input_energy;
    if (system.damping.nonZeros() == 0) {
        double amplitude = 0.0;
        for (double a : orbit.y_amp1) amplitude += a * a;
        m.viscous_energy = 0.0;
        m.energy_error = energy_imbalance(orbit.input_energy, 0.0, orbit.energy,
                                          M_PI * system.excitation.norm() *
                                              std::max(std::sqrt(amplitude), response_floor(system, orbit.omega)));
    }
    return m;
}

/// The HB gap above which a normal-contact polish's exact orbit (laws unilateral and elastic) is
/// taken for another orbit.
constexpr double another_orbit_gap = 0.25;

/// Rigid contacts (law unilateral): within about 1e-8 of w from a grazing orbit (a node's normal
/// force touching zero at an instant) the flow chatters and the solve fails. A first lift-off
/// whose bisection stops there is taken on its closed side where the bracket is below this
/// (relative to w), instead of not at all.
constexpr double grazing_bracket = 1e-7;

/// hb_gap of DOF `dof`, or of output 0 when the orbit has outputs.
ExactPoint exact_point(const ExactOrbit& orbit, const PointMetrics& hb, int dof) {
    ExactPoint e;
    e.message = orbit.message;
    if (!orbit.stopped.empty()) {  // a stop request before or during its solve: not polished
        e.hb_gap = std::numeric_limits<double>::quiet_NaN();
        return e;
    }
    if (!orbit.converged) {
        e.status = PolishStatus::failed;
        e.hb_gap = std::numeric_limits<double>::quiet_NaN();
        return e;
    }
    e.status = PolishStatus::exact;
    e.stable = orbit.stable;
    e.max_multiplier = orbit.max_multiplier;
    e.stability_unresolved = orbit.stability_unresolved();
    e.multipliers = orbit.multipliers;
    const bool output = !orbit.output_max.empty();
    const double exact = output ? orbit.output_max.front() : orbit.y_max[static_cast<std::size_t>(dof)];
    const std::vector<double>& hb_values = output ? hb.output_max : hb.y_max;
    const double approximate = hb_values.empty() ? std::numeric_limits<double>::quiet_NaN()
                                                 : hb_values[output ? 0 : static_cast<std::size_t>(dof)];
    e.hb_gap = std::abs(approximate - exact) / exact;
    return e;
}

/// The structure the exact solver runs on: the system itself, or its modal form (modal_exact.hpp)
/// for models beyond exact_solver_max_dofs. Orbits come back in the structure's terms: y_max
/// and y_amp1 per DOF of the structure (NaN for a DOF no output reports), the outputs as asked;
/// their `state` stays the model's (a start for the next solve).
class ExactModel {
public:
    ExactModel(const System& structure, int modes, const ExactOptions& options, int dof)
        : structure_(structure),
          original_(options.outputs),
          rigid_(rigid_contacts_only(structure)),
          elastic_(elastic_contacts_only(structure)) {
        options_ = options;
        // Normal contacts: no restarts by plain periods, which settle on an attractor (another
        // orbit where the point's is unstable or HB's branch folds elsewhere than the exact one).
        if (rigid_ || elastic_) options_.restarts = 0;
        if (modes > 0 && !rigid_ && !elastic_) {
            modal_.emplace(structure, modes);
            if (options_.outputs.empty()) {  // the DOF of hb_gap and the peaks, as an output of the model
                options_.outputs = {Output::dof(dof)};
                dof_output_ = dof;
            }
            for (Output& o : options_.outputs) o = modal_->output(o);
            options_.dof_maxima = false;
        } else if (!options_.outputs.empty()) {
            // Maxima of what is reported only, as harmonic balance's Analyser finds them (the
            // outputs, DOF 1 and the DOF of hb_gap): the others' turning points cost most of a
            // polished orbit's metrics on a model with many DOFs (they stay NaN, as in HB's).
            for (int i : {dof, 0}) {
                bool present = false;
                for (const Output& o : options_.outputs) present = present || o.single_dof() == i;
                if (!present) {
                    options_.outputs.push_back(Output::dof(i));
                    ++extra_outputs_;
                }
            }
            options_.dof_maxima = false;
        }
    }
    const System& system() const { return modal_ ? modal_->system() : structure_; }
    int modes() const { return modal_ ? modal_->modes() : 0; }
    /// Entries of a model state before its stick/slip hints: y, y' and the sliders (rigid
    /// contacts: y and y' only, no hints; law elastic: a slider component per tangential
    /// direction, the hints its contacts' modes).
    Eigen::Index state_dofs() const {
        const System& s = system();
        if (elastic_) return elastic_continuous_states(s);
        return 2 * s.dofs() + (rigid_ ? 0 : time_domain_elements(s));
    }
    /// A state of the structure (exact_start_state) as a start of the model.
    Eigen::VectorXd start(const Eigen::VectorXd& state) const { return modal_ ? modal_->reduce_state(state) : state; }
    bool rigid() const { return rigid_; }
    /// Contacts with a normal direction (laws unilateral and elastic).
    bool normal() const { return rigid_ || elastic_; }
    /// Replaces the stop request of the solves (ExactOptions::stop).
    void set_stop(std::function<std::string()> stop) { options_.stop = std::move(stop); }
    const std::function<std::string()>& stop() const { return options_.stop; }
    /// The solver's own refusal of the model, empty when it takes it.
    std::string refusal() const {
        return rigid_     ? rigid_solver_refusal(system())
               : elastic_ ? elastic_solver_refusal(system())
                          : exact_solver_refusal(system());
    }
    /// The orbit at omega from `start`. An exception of the solver (not bad input) is an orbit
    /// not converged, its message saying why: that point fails, the polish goes on.
    ExactOrbit orbit(double omega, const Eigen::VectorXd& start) const {
        ExactOrbit o;
        try {
            o = detail::law_periodic_orbit(system(), omega, start, options_);
        } catch (const InvalidInput&) {
            throw;
        } catch (const std::exception& e) {
            ExactOrbit failed;
            failed.omega = omega;
            failed.message = std::string("the exact solver failed: ") + e.what();
            return failed;
        }
        if (!modal_) {
            if (options_.dof_maxima || o.output_max.size() != options_.outputs.size()) return o;
            for (std::size_t k = 0; k < options_.outputs.size(); ++k)
                if (options_.outputs[k].single_dof() >= 0)
                    o.y_max[static_cast<std::size_t>(options_.outputs[k].single_dof())] = o.output_max[k];
            o.output_max.resize(o.output_max.size() - static_cast<std::size_t>(extra_outputs_));
            o.output_amp1.resize(o.output_amp1.size() - static_cast<std::size_t>(extra_outputs_));
            return o;
        }
        const auto n = static_cast<std::size_t>(structure_.dofs());
        const double nan = std::numeric_limits<double>::quiet_NaN();
        o.y_max.assign(n, nan);
        o.y_amp1.assign(n, nan);
        o.harmonic1.resize(0);
        for (std::size_t k = 0; k < options_.outputs.size(); ++k) {
            const int i = dof_output_ >= 0 ? dof_output_ : original_dofs_(k);
            if (i < 0) continue;
            o.y_max[static_cast<std::size_t>(i)] = o.output_max[k];
            o.y_amp1[static_cast<std::size_t>(i)] = o.output_amp1[k];
        }
        if (dof_output_ >= 0) {
            o.output_max.clear();
            o.output_amp1.clear();
        }
        return o;
    }

private:
    int original_dofs_(std::size_t k) const { return k < original_.size() ? original_[k].single_dof() : -1; }
    const System& structure_;
    std::vector<Output> original_;  // the outputs as asked (of the structure)
    std::optional<ModalExactModel> modal_;
    bool rigid_ = false;    // rigid unilateral contacts (rigid_exact.hpp)
    bool elastic_ = false;  // law elastic (elastic_exact.hpp)
    ExactOptions options_;
    int dof_output_ = -1;
    int extra_outputs_ = 0;  // DOFs appended to the outputs for their maxima (structure only)
};

/// The modal form's modes (modal_exact.hpp) chosen by their effect: at the highest frequency of
/// the branch (where the contact forces' harmonics reach the truncated modes first), the exact
/// orbit with 10, 20, 40 and largest_exact_modes modes in turn, from the HB point's state,
/// until two consecutive counts agree to modal_truncation_tolerance (the change of the outputs'
/// maxima relative to the largest, of the friction energy relative to the excitation's work);
/// the smaller of the two is used and the change is
/// its estimated truncation. A count whose cost per period is refused at the lowest frequency
/// ends the search. truncation is NaN where no two counts could be compared.
struct ModalChoice {
    int modes = 0;
    double truncation = std::numeric_limits<double>::quiet_NaN();
    double omega = 0;  ///< the probe frequency
};
ModalChoice choose_modes(HarmonicBalance& hb, const SolutionPoint& probe, double omega_min, const ExactOptions& options,
                         int dof) {
    const System& structure = hb.system();
    ModalChoice choice;
    choice.omega = probe.omega;
    const int largest = largest_exact_modes(structure);
    std::vector<int> counts;
    for (int m : {10, 20, 40, largest})
        if (m <= largest && (counts.empty() || m > counts.back())) counts.push_back(m);
    const Eigen::VectorXd state = exact_start_state(hb, probe);
    std::vector<double> previous;
    for (int m : counts) {
        const ExactModel model(structure, m, options, dof);
        if (choice.modes > 0 && !exact_cost_refusal(model.system(), omega_min).empty()) break;
        const ExactOrbit o = model.orbit(probe.omega, model.start(state));
        if (!o.converged) break;
        // the outputs' maxima, then the friction energy and the excitation's work
        std::vector<double> values = o.output_max.empty() ? std::vector<double>{o.y_max[static_cast<std::size_t>(dof)]}
                                                          : o.output_max;
        values.push_back(o.energy);
        values.push_back(o.input_energy);
        if (!previous.empty()) {
            // relative to the largest output (an output held at rest by a stuck contact is
            // rounding) and to the excitation's work (no friction energy in permanent stick)
            const std::size_t outputs = values.size() - 2;
            double largest = 0.0, change = 0.0;
            for (std::size_t k = 0; k < outputs; ++k) largest = std::max(largest, previous[k]);
            for (std::size_t k = 0; k < outputs; ++k)
                change = std::max(change, std::abs(values[k] - previous[k]) / std::max(largest, 1e-300));
            change = std::max(change, std::abs(values[outputs] - previous[outputs]) /
                                          std::max(std::abs(previous[outputs + 1]), 1e-300));
            choice.truncation = change;
            if (change <= modal_truncation_tolerance) return choice;
        }
        choice.modes = m;
        previous = values;
    }
    if (choice.modes == 0) choice.modes = exact_solver_modes(structure);
    return choice;
}

/// An exact solve from one or two starts (the second tried when the first fails).
ExactOrbit solve(const ExactModel& model, double omega, const Eigen::VectorXd& first, const Eigen::VectorXd* second) {
    ExactOrbit orbit = model.orbit(omega, first);
    if (!orbit.converged && orbit.stopped.empty() && second) {
        ExactOrbit other = model.orbit(omega, *second);
        if (other.converged) return other;
    }
    return orbit;
}

struct Polished {
    SolutionPoint point;
    PointMetrics metrics;
    ExactPoint exact;
    ExactOrbit orbit;
};

Boundary boundary_between(const std::string& a, const std::string& b) {
    if ((a == "stick" && b == "stick-slip") || (a == "stick-slip" && b == "stick")) return Boundary::stick_stick_slip;
    if ((a == "slip" && b == "stick-slip") || (a == "stick-slip" && b == "slip")) return Boundary::stick_slip_slip;
    return Boundary::none;
}

}  // namespace

constexpr detail::EnumName<PolishStatus> polish_status_names[] = {
    {PolishStatus::off, "off"}, {PolishStatus::exact, "yes"}, {PolishStatus::failed, "failed"}};

std::string to_string(PolishStatus status) { return detail::enum_name(polish_status_names, status, "polish status"); }

std::string PolishedBranch::summary() const {
    std::ostringstream s;
    s << "exact polish";
    if (modes > 0)
        s << " (on the modal form: " << modes << " modes + residual Ritz vectors, truncation "
          << (std::isfinite(modal_truncation) ? format_number(modal_truncation) : std::string("not estimated"))
          << " at w = " << format_number(truncation_omega) << ")";
    s << ": " << polished << " points exact, " << failed << " failed (HB values kept), " << unstable
      << " unstable, "
      << (stability_unknown > 0 ? std::to_string(stability_unknown) + " of unknown stability, " : std::string())
      << (stability_unresolved > 0 ? std::to_string(stability_unresolved) + " of uncertain stability, " : std::string())
      << transitions << " transitions" << per_contact_counts(contact_transitions)
      << (unlocated_transitions > 0 ? " (" + std::to_string(unlocated_transitions) + " more not located)" : std::string())
      << ", largest HB gap " << format_number(max_hb_gap) << ", "
      << format_number(seconds) << " s";
    if (!stopped.empty()) s << "; stopped (" << stopped << "): the points after it are harmonic balance's";
    return s.str();
}

PolishedBranch polish_branch(HarmonicBalance& hb, const std::vector<SolutionPoint>& points,
                             const std::vector<PointMetrics>& hb_metrics, const PolishOptions& options,
                             const CorrectorOptions& corrector_options) {
    detail::Stopwatch watch;
    const System& structure = hb.system();
    options.exact.validate();
    // A stop request (ExactOptions::stop): asked before every orbit; once answered, the points
    // after it keep harmonic balance's values (status off) and nothing more is solved.
    std::string stopped;
    const auto stop_now = [&] {
        if (stopped.empty()) stopped = options.exact.stop_reason();
        return !stopped.empty();
    };
    if (options.dof < 0 || options.dof >= structure.dofs())
        throw InvalidInput("polish dof = " + std::to_string(options.dof) + " is out of range: allowed 0.." +
                           std::to_string(structure.dofs() - 1));
    const int dof = options.dof;
    const auto unbounded = [](const PointMetrics& m) {
        for (double a : m.y_amp1)
            if (!std::isfinite(a)) return true;
        return false;
    };
    int modes = exact_solver_modes(structure);
    ModalChoice modal;
    // The probe: the highest bounded branch point (where the contact forces' harmonics reach
    // the truncated modes first, and the period is shortest).
    const SolutionPoint* probe = nullptr;
    double omega_min = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (points[k].kind == PointKind::transition || points[k].kind == PointKind::sample) continue;
        omega_min = std::min(omega_min, points[k].omega);
        if (!unbounded(hb_metrics[k]) && (!probe || points[k].omega > probe->omega)) probe = &points[k];
    }
    if (modes > 0 && probe) {
        try {
            modal = choose_modes(hb, *probe, omega_min, options.exact, dof);
            modes = modal.modes;
        } catch (const InvalidInput&) {  // the model's own refusal, given below
        }
    }
    const bool optional = options.decline_seconds > 0.0;
    if (optional && modes > 0 && !(modal.truncation <= modal_truncation_warning)) {
        PolishedBranch declined;
        declined.declined = "the exact solver would run on the modal form (" + std::to_string(modes) +
                            " modes), whose estimated truncation at w = " + format_number(modal.omega) + " is " +
                            (std::isfinite(modal.truncation) ? format_number(modal.truncation) : std::string("unknown")) +
                            ", above " + format_number(modal_truncation_warning) + ": not exact";
        declined.modes = modes;
        declined.modal_truncation = modal.truncation;
        declined.truncation_omega = modal.omega;
        declined.seconds = watch.lap();
        return declined;
    }
    std::optional<ExactModel> made;
    try {
        made.emplace(structure, modes, options.exact, dof);
    } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("exact polish: ") + e.what() + " (use --exact off)");
    }
    ExactModel& model = *made;
    const System& system = model.system();  // the structure, or its modal form
    if (const std::string why = model.refusal(); !why.empty())
        throw InvalidInput("exact polish: " + why + " (use --exact off)");
    if (optional && probe) {
        // The cost: one exact orbit at the probe, times the points. Measured in the thread's CPU
        // time (a preemption during a sub-millisecond orbit must not decline the polish), and
        // measured again when over the budget but cheap (the first orbit also fills the caches
        // the next ones reuse): the smaller of the two.
        // The probe stops once it alone exceeds the budget (an orbit of a large model may take
        // minutes): the polish is then declined without waiting for it.
        bool over_budget = false;
        const auto orbit_seconds = [&] {
            detail::ThreadCpuStopwatch orbit_watch;
            const std::function<std::string()> outer = model.stop();
            model.set_stop([&]() -> std::string {
                if (std::string why = outer ? outer() : std::string(); !why.empty()) return why;
                if (orbit_watch.seconds() <= options.decline_seconds) return {};
                over_budget = true;
                return "the probe's budget";
            });
            (void)model.orbit(probe->omega, model.start(exact_start_state(hb, *probe)));
            model.set_stop(outer);
            return orbit_watch.lap();
        };
        double each = orbit_seconds();
        if (over_budget) each = std::max(each, options.decline_seconds);
        if (each * static_cast<double>(points.size()) > options.decline_seconds && each < 0.1 * options.decline_seconds)
            each = std::min(each, orbit_seconds());
        const double estimate = each * static_cast<double>(points.size());
        if (estimate > options.decline_seconds) {
            PolishedBranch declined;
            declined.declined = "one exact orbit at w = " + format_number(probe->omega) +
                                (over_budget ? " was stopped after " : " took ") + format_number(each) +
                                " s of CPU: " + (over_budget ? "more than " : "about ") +
                                format_number(std::round(estimate)) + " s for the " +
                                std::to_string(points.size()) + " points, above the budget of " +
                                format_number(options.decline_seconds) +
                                " s (max(2 s, 10 times the harmonic-balance branch))";
            declined.modes = modes;
            declined.seconds = watch.lap();
            return declined;
        }
    }

    // 1. Every branch point and sample at its own frequency, from its HB state, else from the
    //    previous exact point of its branch (where HB is too far off, e.g. near a transition
    //    it misplaces), else (second pass) from the next one.
    std::vector<Polished> branch, samples;
    std::vector<PointMetrics> branch_hb;
    Eigen::VectorXd previous_start;  // the model's start from HB at the last branch point
    Eigen::VectorXd before_previous, before_previous_exact;  // HB's and the exact state one point earlier
    // A point whose HB response is infinite (a branch capped exactly on an undamped resonance the
    // contacts do not see: Receptance's limit) has no periodic orbit to polish: it stays HB
    // (status off), the branch's amplitude_cap says why.
    const auto keep_hb = [&](Polished& q) {
        if (!unbounded(q.metrics)) return false;
        q.exact.status = PolishStatus::off;
        q.exact.hb_gap = std::numeric_limits<double>::quiet_NaN();
        q.exact.message = "unbounded harmonic-balance response (an undamped resonance): not polished";
        return true;
    };
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (options.progress) options.progress(static_cast<int>(k), static_cast<int>(points.size()));
        const SolutionPoint& p = points[k];
        if (p.kind == PointKind::transition) continue;
        Polished q{p, hb_metrics[k], {}, {}};
        if (unbounded(q.metrics) || stop_now()) {
            if (!stopped.empty()) {
                q.orbit.stopped = stopped;
                q.orbit.message = "not polished: the polish stopped before this point (" + stopped + ")";
            }
            (p.kind == PointKind::sample ? samples : branch).push_back(std::move(q));
            if (p.kind != PointKind::sample) branch_hb.push_back(hb_metrics[k]);
            continue;
        }
        const Polished* previous = p.kind != PointKind::sample && !branch.empty() &&
                                           branch.back().point.branch == p.branch && branch.back().orbit.converged
                                       ? &branch.back()
                                       : nullptr;
        const Eigen::VectorXd hb_start = model.start(exact_start_state(hb, p));
        const Eigen::Index hints = hb_start.size() - model.state_dofs();
        if (previous && previous_start.size() == hb_start.size() && previous->orbit.state.size() == hb_start.size()) {
            // A start on the exact branch: the secant through the last two exact states, scaled
            // by the ratio of HB's displacement steps (so that it follows the branch through
            // folds as HB's points do); with one exact state, that state moved as HB's moved.
            // Either is closer than HB's own state (whose velocities carry its Gibbs error):
            // fewer Newton iterations. The stick/slip hints (the last entries) are HB's here.
            Eigen::VectorXd predicted;
            const Eigen::Index nd = model.system().dofs();
            const double step = (hb_start - previous_start).head(nd).norm();
            const double last_step = before_previous.size() == hb_start.size() && before_previous_exact.size() == hb_start.size()
                                         ? (previous_start - before_previous).head(nd).norm()
                                         : 0.0;
            if (last_step > 0.0 && step <= 4.0 * last_step) {  // no far extrapolation
                predicted = previous->orbit.state + (step / last_step) * (previous->orbit.state - before_previous_exact);
            } else {
                predicted = previous->orbit.state + (hb_start - previous_start);
            }
            predicted.tail(hints) = hb_start.tail(hints);
            // Normal contacts: HB's own start first (rigid: the secant along the exact branch
            // carries the polish past an exact fold onto another orbit where HB's branch folds
            // elsewhere; elastic: where a contact sticks all period the orbits form a family in
            // its slider, and the secant moves the slider to another member than HB's).
            q.orbit = model.normal() ? solve(model, p.omega, hb_start, &predicted) : solve(model, p.omega, predicted, &hb_start);
        } else {
            q.orbit = solve(model, p.omega, hb_start, previous ? &previous->orbit.state : nullptr);
        }
        if (stopped.empty()) stopped = q.orbit.stopped;
        if (p.kind != PointKind::sample) {
            before_previous = previous ? previous_start : Eigen::VectorXd();
            before_previous_exact = previous ? previous->orbit.state : Eigen::VectorXd();
            previous_start = hb_start;
        }
        if (p.kind == PointKind::sample) {
            samples.push_back(std::move(q));
        } else {
            branch.push_back(std::move(q));
            branch_hb.push_back(hb_metrics[k]);
        }
    }
    for (std::size_t k = branch.size(); k-- > 1 && !stop_now();) {
        Polished &q = branch[k - 1], &next = branch[k];
        if (q.orbit.converged || !next.orbit.converged || q.point.branch != next.point.branch || unbounded(q.metrics))
            continue;
        ExactOrbit retry = model.orbit(q.point.omega, next.orbit.state);
        if (retry.converged) q.orbit = std::move(retry);
    }
    // Third: marched in w from an exact neighbour of the branch (before, else after) in 4, 16,
    // then 64 sub-steps, each started from the last (a long step of the branch across a change
    // of the stick/slip pattern that no start reaches directly; a fold between them defeats it).
    const auto march = [&](const ExactOrbit& from, double w_from, double w_to) {
        for (int steps = 4; steps <= 64; steps *= 4) {
            ExactOrbit at = from;
            bool ok = true;
            for (int m = 1; m <= steps && ok; ++m) {
                if (stop_now()) return ExactOrbit{};
                ExactOrbit next_orbit = model.orbit(w_from + (w_to - w_from) * m / steps, at.state);
                ok = next_orbit.converged;
                if (ok) at = std::move(next_orbit);
            }
            if (ok) return at;
        }
        return ExactOrbit{};
    };
    for (std::size_t k = 0; k < branch.size(); ++k) {
        Polished& q = branch[k];
        if (q.orbit.converged || unbounded(q.metrics)) continue;
        for (const std::size_t j : {k - 1, k + 1}) {  // k - 1 wraps past 0: out of range
            if (j >= branch.size() || !branch[j].orbit.converged || branch[j].point.branch != q.point.branch) continue;
            ExactOrbit marched = march(branch[j].orbit, branch[j].point.omega, q.point.omega);
            if (marched.converged) {
                q.orbit = std::move(marched);
                break;
            }
        }
    }
    // Normal contacts: an exact orbit far from the HB point's (its y_max gap above
    // another_orbit_gap) is another orbit (a branch whose exact fold lies elsewhere than HB's, or
    // an HB branch without an exact counterpart): the point keeps HB's values, marked failed.
    const auto another_orbit = [&](ExactOrbit& orbit, const PointMetrics& hb_point) {
        if (!model.normal() || !orbit.converged) return;
        const double gap = exact_point(orbit, hb_point, dof).hb_gap;
        if (!(gap > another_orbit_gap)) return;
        orbit.converged = false;
        orbit.message = "the exact solve from this point's starts reached another orbit (y_max " +
                        format_number(gap * 100.0) + " % from HB's, above " + format_number(another_orbit_gap * 100.0) +
                        " %): HB's values kept";
    };
    for (std::size_t k = 0; k < branch.size(); ++k) {
        Polished& q = branch[k];
        if (keep_hb(q)) continue;
        another_orbit(q.orbit, branch_hb[k]);
        q.exact = exact_point(q.orbit, branch_hb[k], dof);
        if (q.orbit.converged) q.metrics = exact_metrics(q.orbit, branch_hb[k], structure);
    }
    for (Polished& q : samples) {
        if (keep_hb(q)) continue;
        another_orbit(q.orbit, q.metrics);
        q.exact = exact_point(q.orbit, q.metrics, dof);
        if (q.orbit.converged) q.metrics = exact_metrics(q.orbit, q.metrics, structure);
    }

    // 2. Exact transitions between consecutive exact points of a branch: for every contact
    //    whose regime differs between them, where it changes (to 1e-10 in omega), in branch order.
    std::vector<Polished> with_transitions;
    Corrector corrector(hb, corrector_options);
    Analyser analyse(hb, {dof}, options.exact.outputs);
    int transitions = 0, unlocated = 0;
    const int contacts = static_cast<int>(system.contacts.size());
    const auto all_stuck = [](const ExactOrbit& o) {
        for (const ContactRegime& r : o.contacts)
            if (r.regime != "stick") return false;
        return true;
    };
    for (std::size_t k = 0; k < branch.size(); ++k) {
        with_transitions.push_back(branch[k]);
        if (!options.transitions || k + 1 >= branch.size() || stop_now()) continue;
        const Polished &a = branch[k], &b = branch[k + 1];
        if (a.point.branch != b.point.branch || !a.orbit.converged || !b.orbit.converged) continue;
        if (a.point.omega == b.point.omega) continue;
        std::vector<Polished> found;
        // A transition at w (its orbit `side`) of `boundary`, with HB's gap there.
        const auto transition = [&](const ExactOrbit& side, Boundary boundary, int c) {
            Polished t;
            t.point.omega = side.omega;
            t.point.kind = PointKind::transition;
            t.point.boundary = boundary;
            t.point.contact = c;
            t.point.branch = a.point.branch;
            t.orbit = side;
            // The HB solution at that frequency, for the HB gap.
            const double s = (side.omega - a.point.omega) / (b.point.omega - a.point.omega);
            t.point.x = a.point.x + s * (b.point.x - a.point.x);
            const double x_scale = hb.unknown_scale(t.point.x);
            const bool hb_ok = corrector.solve_at(t.point.x, side.omega, x_scale, t.point.iterations, t.point.residual);
            PointMetrics hb_m = analyse(t.point);
            t.exact = exact_point(side, hb_m, dof);
            if (!hb_ok) t.exact.hb_gap = std::numeric_limits<double>::quiet_NaN();
            t.metrics = exact_metrics(side, hb_m, hb.system());
            found.push_back(std::move(t));
        };
        // Normal contacts: where a contact starts to open (its separated share leaves 0), by
        // bisection in w on that share, the point on the closed side (the grazing orbit).
        for (int c = 0; c < contacts && model.normal(); ++c) {
            const auto opens = [c](const ExactOrbit& o) { return o.contacts[static_cast<std::size_t>(c)].separated_fraction > 0.0; };
            if (opens(a.orbit) == opens(b.orbit)) continue;
            ExactOrbit lo = a.orbit, hi = b.orbit;
            bool ok = true;
            while (ok && std::abs(hi.omega - lo.omega) > 1e-10 * std::abs(hi.omega)) {
                ExactOrbit o = solve(model, 0.5 * (lo.omega + hi.omega), lo.state, &hi.state);
                ok = o.converged;
                if (ok) (opens(o) == opens(lo) ? lo : hi) = std::move(o);
            }
            if (ok || std::abs(hi.omega - lo.omega) <= grazing_bracket * std::abs(hi.omega))
                transition(opens(lo) ? hi : lo, Boundary::closed_lift_off, c);
            else
                ++unlocated;
        }
        for (int c = 0; c < contacts; ++c) {
            const auto regime = [c](const ExactOrbit& o) { return o.contacts[static_cast<std::size_t>(c)].regime; };
            const Boundary boundary = boundary_between(regime(a.orbit), regime(b.orbit));
            if (boundary == Boundary::none) continue;
            const std::string stuck_side = boundary == Boundary::stick_stick_slip ? "stick" : "stick-slip";
            ExactOrbit lo = a.orbit, hi = b.orbit;
            bool ok = true, closed_form = false;
            const bool a_stuck = regime(a.orbit) == "stick";
            const ExactOrbit& stick_end = (a_stuck ? a : b).orbit;
            if (boundary == Boundary::stick_stick_slip && all_stuck(stick_end) && !model.normal()) {
                // From full stick: where the permanent-stick state's load crosses 1 (closed
                // form), if contact c is the one at its limit there (another contact may break
                // away first: then c's boundary lies on a stick-slip orbit, found below).
                double w_stick = stick_end.omega, w_slip = (a_stuck ? b : a).point.omega;
                if (permanent_stick_load(system, w_stick) <= 1.0 && permanent_stick_load(system, w_slip) > 1.0) {
                    while (std::abs(w_slip - w_stick) > 1e-12 * std::abs(w_slip)) {
                        const double mid = 0.5 * (w_stick + w_slip);
                        (permanent_stick_load(system, mid) <= 1.0 ? w_stick : w_slip) = mid;
                    }
                    if (permanent_stick_load(system, w_stick, c) >= (1.0 - 1e-9) * permanent_stick_load(system, w_stick)) {
                        lo = model.orbit(w_stick, stick_end.state);
                        hi = lo;
                        ok = lo.converged && all_stuck(lo);
                        closed_form = true;
                    }
                }
            }
            while (ok && std::abs(hi.omega - lo.omega) > 1e-10 * std::abs(hi.omega)) {
                const double mid = 0.5 * (lo.omega + hi.omega);
                ExactOrbit o = solve(model, mid, lo.state, &hi.state);
                if (!o.converged) {
                    ok = false;
                    break;
                }
                (regime(o) == regime(lo) ? lo : hi) = std::move(o);
            }
            if (!ok) {
                ++unlocated;
                continue;
            }
            transition(closed_form || regime(lo) == stuck_side ? lo : hi, boundary, c);
        }
        // In branch order (omega runs monotonically between two neighbouring points).
        const bool rising = b.point.omega > a.point.omega;
        std::sort(found.begin(), found.end(), [rising](const Polished& p, const Polished& q) {
            return rising ? p.point.omega < q.point.omega : p.point.omega > q.point.omega;
        });
        transitions += static_cast<int>(found.size());
        for (Polished& t : found) with_transitions.push_back(std::move(t));
    }

    PolishedBranch out;
    out.modes = model.modes();
    out.modal_truncation = modal.truncation;
    out.truncation_omega = modal.omega;
    out.transitions = transitions;
    out.unlocated_transitions = unlocated;
    out.contact_transitions.assign(static_cast<std::size_t>(contacts), 0);
    for (const Polished& q : with_transitions)
        if (q.point.kind == PointKind::transition) ++out.contact_transitions[static_cast<std::size_t>(q.point.contact)];
    for (const auto* list : {&with_transitions, &samples})
        for (const Polished& q : *list) {
            out.points.push_back(q.point);
            out.metrics.push_back(q.metrics);
            out.exact.push_back(q.exact);
            if (q.exact.status == PolishStatus::exact) {
                ++out.polished;
                if (!std::isfinite(q.exact.max_multiplier)) ++out.stability_unknown;
                else if (q.exact.stability_unresolved) ++out.stability_unresolved;
                else if (!q.exact.stable) ++out.unstable;
                if (std::isfinite(q.exact.hb_gap)) out.max_hb_gap = std::max(out.max_hb_gap, q.exact.hb_gap);
            } else if (q.exact.status == PolishStatus::failed) {
                ++out.failed;
            }
        }

    // 3. Exact peaks of `dof` (or of each output) among the branch points (transitions included).
    const std::size_t quantities =
        options.exact.outputs.empty() || !options.peaks_of_every_output ? 1 : options.exact.outputs.size();
    for (std::size_t o = 0; options.peaks && o < quantities && !stop_now(); ++o) {
        const bool of_dof = options.exact.outputs.empty();
        auto value_of = [&](const std::vector<double>& y_max, const std::vector<double>& output_max) {
            return of_dof ? y_max[static_cast<std::size_t>(dof)] : output_max[o];
        };
        const auto& p = with_transitions;
        auto y = [&](std::size_t k) { return value_of(p[k].metrics.y_max, p[k].metrics.output_max); };
        double largest = 0.0;
        for (std::size_t k = 0; k < p.size(); ++k)
            if (std::isfinite(y(k))) largest = std::max(largest, y(k));
        for (std::size_t k = 1; k + 1 < p.size(); ++k) {
            const Polished &a = p[k - 1], &m = p[k], &b = p[k + 1];
            if (a.point.branch != m.point.branch || b.point.branch != m.point.branch) continue;
            if (!a.orbit.converged || !m.orbit.converged || !b.orbit.converged) continue;
            if (!(y(k) > y(k - 1) && y(k) >= y(k + 1))) continue;
            double weight = 1.0;  // |c|_1 of the output
            if (!of_dof) {
                weight = 0.0;
                for (const auto& term : options.exact.outputs[o].terms()) weight += std::abs(term.second);
            }
            if (!is_peak_value(y(k), largest, weight * response_floor(structure, m.point.omega))) continue;
            Peak peak{m.point.omega, y(k), m.point.branch, false, static_cast<int>(o), {}};
            // Each solve starts from the last converged one (Brent's points close in, so the
            // start is nearly the orbit: fewer Newton iterations), else from the branch point.
            Eigen::VectorXd last = m.orbit.state;
            refine_peak(peak, a.point, m.point, b.point, [&](double omega, bool& good) {
                const ExactOrbit e = solve(model, omega, last, &m.orbit.state);
                if (!e.converged) good = false;
                if (e.converged) last = e.state;
                return e.converged ? value_of(e.y_max, e.output_max) : 0.0;
            });
            out.peaks.push_back(peak);
        }
    }
    out.stopped = stopped;
    out.seconds = watch.lap();
    return out;
}

}  // namespace hbf
