// hbfriction — the design searches over FRFs (frf.hpp): the largest peak minimised over one
// parameter (a log scan on threads, then golden section) and over two (nested searches).
#include "hbf/optimize.hpp"

#include <algorithm>
#include <cmath>

#include "hbf/error.hpp"
#include "hbf/frf.hpp"
#include "base/stopwatch.hpp"
#include "base/enum_table.hpp"

namespace hbf {

constexpr detail::EnumName<OptimizeStatus> optimize_status_names[] = {
    {OptimizeStatus::converged, "converged"}, {OptimizeStatus::at_bound, "at_bound"},
    {OptimizeStatus::budget, "budget"}, {OptimizeStatus::unbounded, "unbounded"}, {OptimizeStatus::failed, "failed"}};

std::string to_string(OptimizeStatus status) {
    return detail::enum_name(optimize_status_names, status, "optimize status");
}

std::string OptimizeResult::summary(const std::string& name) const {
    // (no optimum found: no value to give)
    std::string s = to_string(status) + ": " +
                    (std::isfinite(parameter) ? name + " = " + format_number(parameter) + ", largest peak " +
                                                    format_number(peak.value) + " at w = " + format_number(peak.omega) +
                                                    " (" + to_string(peak.state) + "), "
                                              : std::string("no optimum, ")) +
                    std::to_string(trace.size()) + " FRFs";
    if (!message.empty()) s += "; " + message;
    return s;
}

namespace {
/// The search's status as a verdict (its summary line `line`).
void judge_status(OptimizeStatus status, const std::string& line, Verdict& v) {
    switch (status) {
        case OptimizeStatus::converged: break;
        case OptimizeStatus::at_bound:
        case OptimizeStatus::budget: v.warning(line); break;
        case OptimizeStatus::unbounded:
        case OptimizeStatus::failed: v.error(line); break;
    }
}
/// The failed evaluations of a search (`noun` names them) inside and outside its final bracket.
void judge_failures(const OptimizeResult& r, const std::string& noun, Verdict& v) {
    if (r.failed_in_bracket > 0)
        v.warning(std::to_string(r.failed_in_bracket) + " " + noun + " inside the final bracket " +
                  format_number(r.bracket_lower) + ".." + format_number(r.bracket_upper) +
                  " failed or stayed incomplete: the optimum is doubtful there (the trace CSV has them)");
    else if (r.failed > 0)
        v.note(std::to_string(r.failed) + " " + noun + " failed or stayed incomplete, all outside "
               "the final bracket (peak_state in the trace)");
}
}  // namespace

Verdict OptimizeResult::verdict(const std::string& name, const LibraryMessages& also) const {
    Verdict v;
    judge_status(status, summary(name), v);
    judge_failures(*this, "FRF(s)", v);
    LibraryMessages all = messages;
    all.add(also);
    v.add(all);
    return v;
}

Verdict JointOptimizeResult::verdict(const std::string& p_name, const std::string& q_name,
                                     const LibraryMessages& also) const {
    Verdict v;
    judge_status(outer.status, summary(p_name, q_name), v);
    if (best < inner.size()) {
        const OptimizeResult& at_best = inner[best];
        if (at_best.status != OptimizeStatus::converged)
            v.warning("the search in " + p_name + " at the best " + q_name + " did not converge: " + at_best.summary(p_name));
        else if (at_best.failed_in_bracket > 0)
            v.warning("at the best " + q_name + ", " + std::to_string(at_best.failed_in_bracket) +
                      " FRF(s) inside the final bracket of " + p_name +
                      " failed or stayed incomplete: the optimum is doubtful there (the trace CSV has them)");
        else if (inner_not_converged > 0)
            v.note(std::to_string(inner_not_converged) + " of " + std::to_string(inner.size()) + " searches in " +
                   p_name + " did not converge, none at the best " + q_name);
    }
    judge_failures(outer, "search(es) in " + p_name, v);
    LibraryMessages all = outer.messages;
    all.add(also);
    v.add(all);
    return v;
}

namespace {
void validate(const OptimizeOptions& o) {
    if (!(std::isfinite(o.lower) && o.lower > 0.0))
        throw InvalidInput("lower = " + format_number(o.lower) + " is out of range: allowed a finite value > 0");
    if (!(std::isfinite(o.upper) && o.upper > o.lower * (1.0 + 1e-9)))
        throw InvalidInput("upper = " + format_number(o.upper) + " is out of range: allowed finite and > lower = " +
                           format_number(o.lower));
    if (o.scan_points < 3 || o.scan_points > 10000)
        throw InvalidInput("scan_points = " + std::to_string(o.scan_points) + " is out of range: allowed 3..10000");
    if (!(o.tolerance >= 1e-12 && o.tolerance <= 0.1))
        throw InvalidInput("tolerance = " + format_number(o.tolerance) + " is out of range: allowed 1e-12..0.1");
    if (o.max_evaluations < o.scan_points + 1 || o.max_evaluations > 100000)
        throw InvalidInput("max_evaluations = " + std::to_string(o.max_evaluations) + " is out of range: allowed " +
                           std::to_string(o.scan_points + 1) + "..100000 (more than scan_points)");
    if (o.threads < 0) throw InvalidInput("threads = " + std::to_string(o.threads) + " is out of range: allowed >= 0");
}

OptimizeEvaluation evaluation(double p, const FrfResult& r, const char* phase) {
    OptimizeEvaluation e;
    e.parameter = p;
    e.peak = r.peak;
    for (const Peak& peak : r.peaks)
        if (peak.output == 0) e.peaks.push_back(peak);
    e.status = r.branch.status;
    e.phase = phase;
    e.seconds = r.seconds;
    e.messages = r.messages;
    return e;
}
}  // namespace

namespace {
/// Evaluates the objective at the parameters p (a batch: the scan) and returns one evaluation
/// each, in order.
using BatchObjective = std::function<std::vector<OptimizeEvaluation>(const std::vector<double>& p, const char* phase)>;

/// The search of optimize_parameter on any objective: a log-spaced scan, then golden section
/// in log p around the best scan point.
OptimizeResult minimise(const BatchObjective& objective, const OptimizeOptions& options) {
    validate(options);
    detail::Stopwatch watch;
    OptimizeResult result;
    // Evaluates the objective at the log-parameters u and appends the evaluations to the trace.
    auto evaluate = [&](const std::vector<double>& u, const char* phase) {
        std::vector<double> p(u.size());
        std::transform(u.begin(), u.end(), p.begin(), [](double x) { return std::exp(x); });
        std::vector<double> values;
        for (OptimizeEvaluation& e : objective(p, phase)) {
            values.push_back(e.peak.objective());
            result.messages.add(e.messages);
            result.trace.push_back(std::move(e));
        }
        if (options.progress) {
            double smallest = std::numeric_limits<double>::infinity();
            for (const OptimizeEvaluation& e : result.trace) smallest = std::min(smallest, e.peak.objective());
            options.progress(std::string(phase) + ": " + std::to_string(result.trace.size()) +
                             " FRFs, smallest peak " + format_number(smallest));
        }
        return values;
    };
    const double a0 = std::log(options.lower), b0 = std::log(options.upper);
    const int n = options.scan_points;
    std::vector<double> grid(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) grid[static_cast<std::size_t>(k)] = a0 + (b0 - a0) * k / (n - 1);
    grid.back() = b0;
    const std::vector<double> scan = evaluate(grid, "scan");
    const auto best_scan = static_cast<int>(std::min_element(scan.begin(), scan.end()) - scan.begin());

    // The best evaluation so far (the trace's smallest objective; ties keep the first).
    auto best = [&result]() {
        std::size_t b = 0;
        for (std::size_t k = 1; k < result.trace.size(); ++k)
            if (result.trace[k].peak.objective() < result.trace[b].peak.objective()) b = k;
        return b;
    };
    auto finish = [&](OptimizeStatus status, double lo, double hi, std::string message) {
        const OptimizeEvaluation& b = result.trace[best()];
        result.status = status;
        result.parameter = b.parameter;
        result.peak = b.peak;
        result.peaks = b.peaks;
        result.bracket_lower = lo;
        result.bracket_upper = hi;
        result.message = std::move(message);
        for (const OptimizeEvaluation& e : result.trace) {
            const bool bad = e.peak.state == PeakState::failed || e.peak.state == PeakState::incomplete;
            if (!bad) continue;
            ++result.failed;
            if (e.parameter >= lo && e.parameter <= hi) ++result.failed_in_bracket;
        }
        result.seconds = watch.lap();
        return result;
    };
    if (!std::isfinite(scan[static_cast<std::size_t>(best_scan)])) {
        const bool any_unbounded = std::any_of(result.trace.begin(), result.trace.end(), [](const OptimizeEvaluation& e) {
            return e.peak.state == PeakState::unbounded;
        });
        return finish(any_unbounded ? OptimizeStatus::unbounded : OptimizeStatus::failed, options.lower, options.upper,
                      any_unbounded ? "no scanned value gives a bounded response (every FRF capped or failed): widen "
                                      "the range or lower the excitation"
                                    : "every FRF of the scan failed");
    }
    if (best_scan == 0 || best_scan == n - 1) {
        const double lo = std::exp(grid[static_cast<std::size_t>(std::max(0, best_scan - 1))]);
        const double hi = std::exp(grid[static_cast<std::size_t>(std::min(n - 1, best_scan + 1))]);
        return finish(OptimizeStatus::at_bound, lo, hi,
                      std::string("the smallest peak of the scan is at the ") + (best_scan == 0 ? "lower" : "upper") +
                          " end of the range: the optimum may lie outside it");
    }
    // Golden section in u = log p over the scan intervals around the best scan point.
    const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = grid[static_cast<std::size_t>(best_scan - 1)], b = grid[static_cast<std::size_t>(best_scan + 1)];
    double c = b - golden * (b - a), d = a + golden * (b - a);
    const std::vector<double> first = evaluate({c, d}, "golden");
    double fc = first[0], fd = first[1];
    while (b - a > options.tolerance) {
        if (static_cast<int>(result.trace.size()) >= options.max_evaluations)
            return finish(OptimizeStatus::budget, std::exp(a), std::exp(b),
                          "max_evaluations = " + std::to_string(options.max_evaluations) +
                              " reached with the bracket " + format_number(std::exp(a)) + ".." +
                              format_number(std::exp(b)));
        // Keep the side of the smaller value; on a tie (two unbounded trials) the side of the
        // best point found so far.
        const double u_best = std::log(result.trace[best()].parameter);
        const bool left = fc < fd || (fc == fd && u_best < d);
        if (left) {
            b = d;
            d = c;
            fd = fc;
            c = b - golden * (b - a);
            fc = evaluate({c}, "golden")[0];
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + golden * (b - a);
            fd = evaluate({d}, "golden")[0];
        }
    }
    return finish(OptimizeStatus::converged, std::exp(a), std::exp(b), "");
}
}  // namespace

OptimizeResult optimize_parameter(const std::function<System(double)>& system, const FrfSettings& settings,
                                  const OptimizeOptions& options) {
    return minimise(
        [&](const std::vector<double>& p, const char* phase) {
            const auto frfs = compute_frfs(
                static_cast<int>(p.size()), [&](int k) { return system(p[static_cast<std::size_t>(k)]); }, settings,
                options.threads);
            std::vector<OptimizeEvaluation> out;
            for (std::size_t k = 0; k < p.size(); ++k) out.push_back(evaluation(p[k], frfs[k], phase));
            return out;
        },
        options);
}

int JointOptimizeResult::frfs() const {
    int n = 0;
    for (const OptimizeResult& r : inner) n += static_cast<int>(r.trace.size());
    return n;
}

std::string JointOptimizeResult::summary(const std::string& p_name, const std::string& q_name) const {
    std::string s = to_string(outer.status) + ": " + q_name + " = " + format_number(outer.parameter) + ", " + p_name + " = " +
                    format_number(parameter) + ", largest peak " + format_number(outer.peak.value) + " at w = " +
                    format_number(outer.peak.omega) + " (" + to_string(outer.peak.state) + "), " +
                    std::to_string(outer.trace.size()) + " searches in " + p_name + ", " + std::to_string(frfs()) + " FRFs";
    if (!outer.message.empty()) s += "; " + outer.message;
    if (inner_not_converged > 0)
        s += "; " + std::to_string(inner_not_converged) + " of the searches in " + p_name + " did not converge (at a bound, out of "
             "budget, unbounded or failed)";
    return s;
}

JointOptimizeResult optimize_two_parameters(const std::function<System(double, double)>& system,
                                            const FrfSettings& settings, const OptimizeOptions& inner,
                                            const OptimizeOptions& outer) {
    validate(inner);
    JointOptimizeResult result;
    result.outer = minimise(
        [&](const std::vector<double>& q, const char* phase) {
            std::vector<OptimizeEvaluation> out;
            for (double value : q) {  // sequential: each inner search runs its scan on threads
                OptimizeOptions in = inner;
                if (inner.progress)
                    in.progress = [&inner, value, n = result.inner.size() + 1](const std::string& text) {
                        inner.progress("search " + std::to_string(n) + " (second parameter " + format_number(value) +
                                       "): " + text);
                    };
                OptimizeResult r = optimize_parameter([&](double p) { return system(p, value); }, settings, in);
                OptimizeEvaluation e;
                e.parameter = value;
                e.peak = r.peak;
                e.peaks = r.peaks;
                e.status = ContinuationStatus::start_failed;  // the status of the best FRF
                for (const OptimizeEvaluation& t : r.trace)
                    if (t.parameter == r.parameter) {
                        e.status = t.status;
                        break;
                    }
                e.phase = phase;
                e.seconds = r.seconds;
                e.messages = r.messages;
                result.inner.push_back(std::move(r));
                out.push_back(std::move(e));
            }
            return out;
        },
        outer);
    for (std::size_t k = 0; k < result.outer.trace.size(); ++k)
        if (result.outer.trace[k].parameter == result.outer.parameter) result.best = k;
    result.parameter = result.inner.empty() ? 0.0 : result.inner[result.best].parameter;
    for (const OptimizeResult& r : result.inner) result.inner_not_converged += r.status != OptimizeStatus::converged;
    return result;
}

}  // namespace hbf
