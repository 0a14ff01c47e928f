// hbfriction — a nonlinear mode as one call (modes.hpp: compute_mode): the harmonic-balance
// options it uses, the points' metrics, the backbone's verdict and its tables.
#include "hbf/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"

namespace hbf {

std::vector<double> NonlinearModes::metrics_of(const ModePoint& point, const std::vector<Output>& outputs) {
    return metrics(point, outputs).output_amp1;
}

ModeMetrics NonlinearModes::metrics(const ModePoint& point, const std::vector<Output>& outputs) {
    ModeMetrics m;
    // xi is a Newton unknown, accurate to about the corrector's tolerance (1e-10 of w): a
    // |zeta| below 1e-12 (an undamped stuck structure's rounding, of either sign) is 0.
    m.zeta = std::abs(point.zeta()) < 1e-12 ? 0.0 : point.zeta();
    const Eigen::MatrixXd y = motion(point);  // condensed: the free structure at the point's xi (for the Analyser too)
    Analyser analyse(*hb_, {}, outputs);
    SolutionPoint sp;
    sp.omega = point.omega;
    sp.x = point.x;
    const PointMetrics pm = analyse(sp);
    m.friction_energy = pm.energy;
    m.viscous_energy = pm.viscous_energy;
    m.contacts = pm.contacts;
    m.output_max = pm.output_max;
    m.output_amp1 = pm.output_amp1;
    const int harmonics = hb_->harmonics();
    double kinetic = 0.0;  // sum_k k^2 (c_k^T M c_k + s_k^T M s_k)
    m.harmonic_content.assign(static_cast<std::size_t>(harmonics + 1), 0.0);
    Eigen::VectorXd mean = y.row(0).transpose();
    if (hb_->rest_state() && hb_->rest_state()->ok) mean -= hb_->rest_state()->displacement;  // the static deflection left out
    m.harmonic_content[0] = mean.dot(system_.mass * mean);
    for (int k = 1; k <= harmonics; ++k)
        for (int row : {2 * k - 1, 2 * k}) {
            const Eigen::VectorXd c = y.row(row).transpose();
            const double e = c.dot(system_.mass * c);
            m.harmonic_content[static_cast<std::size_t>(k)] += e;
            kinetic += k * k * e;
        }
    double total = 0.0;
    for (double e : m.harmonic_content) total += e;
    for (double& e : m.harmonic_content) e = total > 0.0 ? std::sqrt(e / total) : 0.0;
    m.injected_energy = point.xi * M_PI * point.omega * kinetic;
    const double dissipated = m.friction_energy + m.viscous_energy;
    const double modal = 2.0 * M_PI * point.omega * point.omega * point.amplitude * point.amplitude;
    const double reference = std::max({std::abs(m.injected_energy), m.viscous_energy + std::abs(m.friction_energy),
                                       1e-8 * modal});
    // The normal forces' work on the AFT grid closes the discrete balance: zero in continuous
    // time, a residue where a contact separates (the corner in N; as in hbf frf's balance).
    double normal_work = 0.0;
    Fourier& aft = hb_->fourier();
    const int n = aft.size(), nt = aft.time_samples();
    Eigen::VectorXd v(nt);
    for (int c = 0; c < static_cast<int>(system_.contacts.size()); ++c) {
        const Eigen::VectorXd q = hb_->relative(point.x, c);
        if (q.size() <= n || !contact_law(system_.contacts[static_cast<std::size_t>(c)].law).friction())
            continue;  // no normal direction (a force element over several coordinates: its work is friction_energy's)
        const Eigen::VectorXd f = hb_->force_samples(point.x, point.omega, c);
        aft.to_time(point.omega * (aft.derivative() * q.tail(n)), v);
        normal_work += 2.0 * M_PI / point.omega * f.tail(nt).dot(v) / nt;
    }
    m.energy_error = std::abs(m.injected_energy - dissipated - normal_work) / reference;
    m.zeta_energy = dissipated / modal;
    return m;
}


Verdict judge_backbone(const Backbone& backbone, const std::vector<ModeMetrics>& metrics, double tolerance) {
    Verdict verdict;
    // The start (NonlinearModes::follow): checked against the linear limit, or not.
    if (!backbone.points.empty()) {
        if (backbone.start == "unchecked")
            verdict.warning(backbone.start_note);
        else if (backbone.start == "given")
            verdict.note("the first point was solved from the given start frequency, not checked against the linear "
                         "limit (w = " + format_number(backbone.linear_omega) + ", xi = " +
                         format_number(backbone.linear_xi) + ")");
        else if (!backbone.start_note.empty())
            verdict.note(backbone.start_note);
    }
    if (backbone.status == ModeStatus::start_failed)
        verdict.error(backbone.message);
    else if (backbone.status != ModeStatus::completed)
        verdict.warning("the backbone is incomplete (" + to_string(backbone.status) + "): " + backbone.message);
    double worst = 0.0;
    std::size_t where = 0;
    for (std::size_t k = 0; k < metrics.size(); ++k)
        if (metrics[k].energy_error > worst) {
            worst = metrics[k].energy_error;
            where = k;
        }
    const double limit = energy_balance_limit(tolerance);
    if (worst > limit && where < backbone.points.size())
        verdict.warning("points fail the energy balance (largest relative error " + format_number(worst) + " at a = " +
                        format_number(backbone.points[where].amplitude) + ", allowed " + format_number(limit) +
                        "; energy_error)");
    return verdict;
}

HarmonicBalanceOptions mode_harmonic_balance(HarmonicBalanceOptions hbo, const System& system) {
    if (hbo.formulation == Formulation::automatic && hbo.modes == 0 &&
        (system.cyclic.active() || static_cast<long long>(system.dofs()) * (2LL * hbo.harmonics + 1) <= mode_full_limit))
        hbo.formulation = Formulation::full;  // a sector's mode: the full formulation (its complex phase row)
    if (hbo.formulation == Formulation::full) hbo.modes = 0;
    hbo.jacobian = JacobianForm::dense;
    return hbo;
}

ModeRun compute_mode(const System& system, HarmonicBalanceOptions hbo, const ModeOptions& options,
                     std::vector<Output> outputs, bool synthesis, bool exact_check) {
    if (outputs.empty())
        for (int i = 0; i < system.dofs(); ++i) outputs.push_back(Output::dof(i));
    for (const Output& o : outputs) o.validate(system.dofs());
    if (synthesis && system.excitation_harmonic != 1)
        throw InvalidInput("synthesis: the response to F cos(w t) is synthesised: the system's excitation harmonic is " +
                           std::to_string(system.excitation_harmonic) + " (allowed 1)");
    NonlinearModes nm(system, hbo, options);
    ModeRun run;
    run.backbone = nm.follow();
    for (const ModePoint& p : run.backbone.points) run.metrics.push_back(nm.metrics(p, outputs));
    std::vector<bool> normal;  // the contacts with a normal direction: a separated_fraction column
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        normal.push_back(!run.metrics.empty() && !std::isnan(run.metrics.front().contacts.at(c).separated_fraction));
    run.harmonics = nm.harmonic_balance().harmonics();
    run.time_samples = nm.harmonic_balance().time_samples();
    run.formulation = nm.formulation();
    run.modes = nm.harmonic_balance().modes();
    run.table = io::backbone_table(run.backbone, run.metrics, outputs, normal, run.harmonics);
    if (synthesis) run.synthesis = nm.synthesize(run.backbone, run.metrics, system.excitation, outputs);
    run.verdict = judge_backbone(run.backbone, run.metrics, options.tolerance);
    if (run.backbone.status != ModeStatus::start_failed) {  // a failed start says them in its message
        const PenaltyDiagnostics penalties = penalty_diagnostics(system, nm.harmonic_balance().rest_state());
        for (const std::string& line : penalties.relieved) run.verdict.warning(line);
        for (const std::string& line : penalties.stiff) run.verdict.note(line);
    }
    if (exact_check) {
        std::vector<io::Column> columns = io::exact_columns();
        std::vector<std::vector<io::Cell>> cells(columns.size());
        double largest = 0.0;
        std::size_t checked = 0, where = 0;
        std::string reason;
        std::string stopped;  // the exact checks stop with the run (the rest unchecked)
        for (std::size_t k = 0; k < run.backbone.points.size(); ++k) {
            if (stopped.empty() && options.stop) stopped = options.stop();
            ExactModeCheck c;
            if (stopped.empty()) c = nm.exact_check(run.backbone.points[k]);
            else c.message = "not checked: " + stopped;
            run.exact.push_back(c);
            cells[0].push_back(c.checked ? io::Cell(c.omega) : io::Cell());
            cells[1].push_back(c.checked ? io::Cell(c.xi) : io::Cell());
            cells[2].push_back(c.checked ? io::Cell(c.gap) : io::Cell());
            if (c.checked) {
                ++checked;
                if (c.gap >= largest) {
                    largest = c.gap;
                    where = k;
                }
            } else if (reason.empty()) {
                reason = c.message + " (first at a = " + format_number(run.backbone.points[k].amplitude) + ")";
            }
        }
        for (std::size_t c = 0; c < columns.size(); ++c) {
            run.table.columns.push_back(columns[c]);
            run.table.cells.push_back(std::move(cells[c]));
        }
        std::string note = "exact check: " + std::to_string(checked) + " of " + std::to_string(run.backbone.points.size()) +
                           " points checked by the event-exact solver";
        if (checked > 0)
            note += ", largest exact_gap " + format_number(largest) + " at a = " +
                    format_number(run.backbone.points[where].amplitude);
        if (checked < run.backbone.points.size()) note += "; not checked: " + reason;
        run.verdict.note(note);
    }
    if (synthesis && !run.backbone.points.empty()) {
        // The synthesis covers the backbone's amplitudes only: a response that reaches its last
        // point has its peak beyond it (the curve is cut, not a peak); none at all means the
        // force sustains no computed amplitude (the response lies below the first point).
        const double last = run.backbone.points.back().amplitude;
        const bool cut = std::any_of(run.synthesis.begin(), run.synthesis.end(),
                                     [&](const SynthesisPoint& q) { return q.amplitude == last; });
        if (cut)
            run.verdict.warning("the synthesised response is cut at the backbone's last point a = " + format_number(last) +
                                ": the excitation sustains that amplitude, so its peak lies beyond the backbone "
                                "(raise the amplitude range's upper end)");
        else if (run.synthesis.empty())
            run.verdict.warning("the synthesised response is empty: the excitation sustains no amplitude of the backbone "
                                "(its response lies below a = " + format_number(run.backbone.points.front().amplitude) +
                                ": lower the amplitude range's lower end)");
    }
    return run;
}


namespace io {

std::vector<Column> backbone_columns(const std::vector<Output>& outputs, const std::vector<bool>& normal, int harmonics) {
    std::vector<Column> c = {
        {"a", "modal amplitude: M-norm of the first harmonic c1 cos + s1 sin of y, sqrt(c1^T M c1 + s1^T M s1) "
              "(units sqrt(mass) x length); in the linear limit the amplitude of q = phi^T M y, phi the stuck "
              "mode with phi^T M phi = 1"},
        {"w", "frequency omega of the nonlinear mode (the periodic motion's fundamental)"},
        {"xi", "artificial damping xi: the term -xi M y' that makes the free motion periodic (feeds in what is dissipated)"},
        {"zeta", "modal damping ratio xi / (2 w) (0 where below 1e-12, the corrector's resolution)"},
        {"zeta_energy", "energy damping ratio (friction_energy + viscous_energy) / (2 pi w^2 a^2); equals zeta when the "
                        "motion is a single harmonic (xi's energy balance), differs with higher harmonics"},
        {"energy", "energy dissipated per cycle by the contacts and the viscous damping C"},
        {"friction_energy", "energy the contacts dissipate per cycle (integral of f q' on the AFT grid)"},
        {"viscous_energy", "energy C dissipates per cycle"},
        {"energy_error", "energy balance |xi-injected - energy - normal forces' work on the AFT grid| relative to the "
                         "larger of xi-injected and energy (floor: 1e-8 2 pi w^2 a^2)"}};
    for (const Output& o : outputs) {
        c.push_back({o.name() + "_max", "max over one period of |" + o.name() + "(t)|"});
        c.push_back({o.name() + "_amp1", "first-harmonic amplitude of " + o.name() + "(t)"});
    }
    for (std::size_t k = 0; k < normal.size(); ++k) {
        const std::string n = std::to_string(k + 1);
        c.push_back({"stick_fraction_c" + n, "share of the period contact " + n + " sticks (its law's definition, as hbf frf)"});
        c.push_back({"regime_c" + n, "stick, slip or stick-slip (contact " + n + ")", ColumnType::text});
        if (normal[k])
            c.push_back({"separated_fraction_c" + n, "share of the period contact " + n + " is open (N = 0)"});
    }
    for (int k = 0; k <= harmonics; ++k)
        c.push_back({"h" + std::to_string(k), "harmonic content: sqrt(Y_k^T M Y_k) over the M-norm of every harmonic (k = " +
                                                  std::to_string(k) + (k == 0 ? ": the mean minus the static deflection)" : ")")});
    c.push_back({"iterations", "Newton iterations of the point", ColumnType::integer});
    c.push_back({"residual", "max |scaled residual| of the point (structure rows relative to a w0^2 |M phi|, "
                             "constraints relative to a)"});
    return c;
}

std::vector<Column> exact_columns() {
    return {{"exact_w", "frequency of the event-exact free orbit with C - xi M (exact Coulomb, Jenkins) at the same "
                        "modal displacement and velocity at a section where every contact slips; empty where not "
                        "checked (permanent stick: the linear mode; laws it does not cover; its shooting failed)"},
            {"exact_xi", "that orbit's artificial damping xi"},
            {"exact_gap", "max(|w - exact_w|, |xi - exact_xi|) / exact_w: harmonic balance's truncation error here"}};
}

}  // namespace io

}  // namespace hbf
