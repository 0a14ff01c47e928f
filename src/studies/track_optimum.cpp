// hbfriction — the optimiser by tracking (tracking.hpp: optimize_by_tracking): the largest peak
// minimised over p from the tracked peak curves, their upper envelope and its exchanges.
#include <algorithm>
#include <cmath>
#include <optional>

#include "hbf/error.hpp"
#include "hbf/tracking.hpp"
#include "base/stopwatch.hpp"
#include "numerics/golden_section.hpp"
#include "studies/track_locate.hpp"

namespace hbf {

using detail::Fix;
using detail::ResponseSolver;
using detail::locate_peak;
using detail::track_with;

std::string TrackOptimum::summary(const std::string& name) const {
    // (no optimum found: no value to give)
    std::string s = to_string(status) + ": " +
                    (std::isfinite(parameter) ? name + " = " + format_number(parameter) + ", largest peak " +
                                                    format_number(value) + " at w = " + format_number(omega) +
                                                    (kind.empty() ? "" : " (" + kind + ")") + ", "
                                              : std::string("no optimum, ")) +
                    std::to_string(solves) + " solves, " + std::to_string(frfs) + " FRFs, " + format_number(seconds) + " s";
    if (!message.empty()) s += "; " + message;
    return s;
}

Verdict TrackOptimum::verdict(const std::string& name) const {
    Verdict v;
    if (status == OptimizeStatus::at_bound || status == OptimizeStatus::budget) v.warning(summary(name));
    if (status == OptimizeStatus::unbounded || status == OptimizeStatus::failed) v.error(summary(name));
    for (const std::string& c : failed_curves)
        v.note("a tracked peak failed (the largest peak beyond it counts as unknown; the FRF at the optimum confirmed "
               "it): " + c);
    for (const TrackResult& t : tracks)
        for (const std::string& n : t.verdict.notes) v.note(n);
    if (restarts > 0)
        v.note("the FRF at an optimum found had a larger peak than the tracked ones (born after the start): the tracks "
               "started again there " + std::to_string(restarts) + " time(s)");
    return v;
}

namespace {
/// The value of curve `c`'s peak at `p` interpolated linearly between its two nearest solved
/// points on either side (-infinity where p lies outside the p it was solved over).
double interpolated_value(const TrackCurve& c, double p) {
    const TrackPoint *below = nullptr, *above = nullptr;
    for (const TrackPoint& q : c.points) {
        if (q.kind == "search") continue;
        if (q.p <= p && (!below || q.p > below->p)) below = &q;
        if (q.p >= p && (!above || q.p < above->p)) above = &q;
    }
    if (!below || !above) return -std::numeric_limits<double>::infinity();
    if (above->p == below->p) return std::max(above->value, below->value);
    const double s = (p - below->p) / (above->p - below->p);
    return below->value + s * (above->value - below->value);
}

/// One round of optimize_by_tracking: the tracks from `start` to both ends and the minimum of
/// the largest peak along them (result's fields).
void search_tracks(TrackOptimum& result, const std::function<System(double)>& system, const FrfSettings& settings,
                   double lower, double upper, double start, double tolerance,
                   const std::vector<std::pair<double, const FrfResult*>>& known,
                   const std::function<void(const std::string&)>& progress) {
    const auto frf_at = [&](double p) -> const FrfResult* {
        for (const auto& [x, r] : known)
            if (x == p) return r;
        return nullptr;
    };
    result.tracks.clear();
    result.kind.clear();
    result.message.clear();
    result.other_omega = std::numeric_limits<double>::quiet_NaN();
    for (double end : {lower, upper}) {
        TrackOptions o;
        o.p_start = start;
        o.p_end = end;
        if (progress) o.progress = [&progress](double p) { progress("tracking: p = " + format_number(p)); };
        result.tracks.push_back(track_with(system, settings, o, frf_at(start), frf_at(end)));
        result.solves += result.tracks.back().solves;
        result.frfs += result.tracks.back().frfs;
        if (result.tracks.back().curves.empty()) {  // no peak to follow at the start
            result.status = OptimizeStatus::failed;
            result.message = "tracking from p = " + format_number(start) + ": " +
                             (result.tracks.back().verdict.errors.empty() ? std::string("no curve")
                                                                          : result.tracks.back().verdict.errors.front()) +
                             " (use the golden-section method)";
            return;
        }
    }
    // The largest peak at each value of p every live curve was solved at (+infinity beyond a
    // curve's amplitude cap), from lower to upper.
    struct Sample {
        double p, value, omega, other_omega;
        const TrackCurve* top;
        const TrackPoint* point;
        bool exchange;
    };
    std::vector<Sample> samples;
    for (std::size_t t = 0; t < result.tracks.size(); ++t) {
        const TrackResult& r = result.tracks[t];
        std::vector<double> ps;
        for (const TrackCurve& c : r.curves)
            for (const TrackPoint& q : c.points)
                if (q.kind != "search") ps.push_back(q.p);
        std::sort(ps.begin(), ps.end());
        ps.erase(std::unique(ps.begin(), ps.end()), ps.end());
        const double dir = t == 0 ? -1.0 : 1.0;
        for (double p : ps) {
            if (t == 1 && p == start) continue;  // the start is in both tracks
            Sample s{p, -1.0, 0.0, std::numeric_limits<double>::quiet_NaN(), nullptr, nullptr, false};
            std::vector<double> exchanged;  // the frequencies of the exchange points at p
            for (const TrackCurve& c : r.curves) {
                if (c.points.empty()) continue;
                const bool unknown_beyond = c.status == TrackStatus::amplitude_cap || c.status == TrackStatus::failed;
                if (unknown_beyond && dir * (p - c.points.back().p) > 0.0) {
                    s.value = std::numeric_limits<double>::infinity();
                    s.top = &c;
                    break;
                }
                for (const TrackPoint& q : c.points) {
                    if (q.p != p || q.kind == "search") continue;
                    if (q.kind == "exchange") {
                        exchanged.push_back(q.omega);
                        s.exchange = true;
                    }
                    if (q.value > s.value) {
                        s.value = q.value;
                        s.omega = q.omega;
                        s.top = &c;
                        s.point = &q;
                    }
                }
            }
            for (double w : exchanged)
                if (w != s.omega) s.other_omega = w;
            // A curve solved at other values of p (an exchange point belongs to two curves
            // only; a curve marched alone steps on its own) may still be above the largest
            // point here: the sample is then not on the upper envelope and is left out.
            bool below = false;
            for (const TrackCurve& c : r.curves)
                if (s.top && &c != s.top && interpolated_value(c, p) > s.value * (1.0 + 1e-12)) below = true;
            if (s.top && !below) samples.push_back(s);
        }
    }
    std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.p < b.p; });
    const auto best = std::min_element(samples.begin(), samples.end(),
                                       [](const Sample& a, const Sample& b) { return a.value < b.value; });
    if (best == samples.end() || !std::isfinite(best->value)) {
        result.status = OptimizeStatus::unbounded;
        result.message = "no bounded peak along the tracks";
        return;
    }
    result.parameter = best->p;
    result.value = best->value;
    result.omega = best->omega;
    result.status = OptimizeStatus::converged;
    const std::size_t k = static_cast<std::size_t>(best - samples.begin());
    if (best->exchange) {
        result.kind = "equal peaks";
        result.other_omega = best->other_omega;
    } else if (k == 0 || k + 1 == samples.size()) {
        result.kind = "bound";
        result.status = OptimizeStatus::at_bound;
        result.message = "the smallest largest peak is at the " + std::string(k == 0 ? "lower" : "upper") +
                         " end of the range: the optimum may lie outside it";
    } else if (samples[k - 1].top != best->top || samples[k + 1].top != best->top) {
        result.kind = "peak end";
        result.message = "the largest peak changes from one curve to another there without an exchange (a peak ends)";
    } else {
        // An interior minimum of one curve: Brent in p on the peak located at each trial value.
        result.kind = "minimum";
        const Sample &a = samples[k - 1], &b = samples[k + 1];
        const Output output = settings.outputs.empty() ? Output::dof(0) : settings.outputs.front();
        ResponseSolver solver(system, settings, result.tracks.front().exact, output);
        const double lo_w = std::min(settings.continuation.omega_start, settings.continuation.omega_end),
                     hi_w = std::max(settings.continuation.omega_start, settings.continuation.omega_end);
        Fix last;
        bool ok = true;
        std::string why;
        const detail::GoldenMaximum m = detail::brent_maximum(
            [&](double p, bool& good) {
                const double s = (p - a.p) / (b.p - a.p);
                const double guess = s < 0.5 ? a.omega + 2.0 * s * (best->omega - a.omega)
                                             : best->omega + (2.0 * s - 1.0) * (b.omega - best->omega);
                Fix f = locate_peak(solver, p, guess, best->point->state, lo_w, hi_w);
                if (!f.ok) {  // no peak there (near a cap): not the minimum
                    why = f.message;
                    (void)good;
                    return -std::numeric_limits<double>::max();
                }
                last = f;
                return -f.value;
            },
            a.p, b.p, tolerance, ok);
        if (!ok) {
            result.status = OptimizeStatus::failed;
            result.message = "the search for the curve's minimum failed: " + why;
        } else {
            result.parameter = m.x;
            result.value = -m.value;
            // the peak at the optimum itself (Brent's last evaluation may be elsewhere)
            const Fix f = locate_peak(solver, m.x, last.omega, last.state, lo_w, hi_w);
            if (f.ok) {
                result.value = f.value;
                result.omega = f.omega;
            }
        }
        result.solves += solver.solves();
    }
}
}  // namespace

TrackOptimum optimize_by_tracking(const std::function<System(double)>& system, const FrfSettings& settings,
                                  const OptimizeOptions& options) {
    if (!(std::isfinite(options.lower) && options.lower > 0.0 && std::isfinite(options.upper) &&
          options.upper > options.lower * (1.0 + 1e-9)))
        throw InvalidInput("lower = " + format_number(options.lower) + ", upper = " + format_number(options.upper) +
                           " are out of range: allowed finite, 0 < lower < upper");
    if (options.scan_points < 3 || options.scan_points > 10000)
        throw InvalidInput("scan_points = " + std::to_string(options.scan_points) + " is out of range: allowed 3..10000");
    if (!(options.tolerance >= 1e-14 && options.tolerance <= 0.1))
        throw InvalidInput("tolerance = " + format_number(options.tolerance) + " is out of range: allowed 1e-14..0.1");
    detail::Stopwatch watch;
    TrackOptimum result;
    // 1. The scan (as optimize_parameter's): which valley, and the bracket around its best value.
    const int n = options.scan_points;
    std::vector<double> grid(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k)
        grid[static_cast<std::size_t>(k)] =
            std::exp(std::log(options.lower) + (std::log(options.upper) - std::log(options.lower)) * k / (n - 1));
    grid.front() = options.lower;
    grid.back() = options.upper;
    FrfSettings frf = settings;
    frf.peaks = true;
    const std::vector<FrfResult> scan = compute_frfs(
        n, [&](int k) { return system(grid[static_cast<std::size_t>(k)]); }, frf, options.threads);
    result.frfs += n;
    if (options.progress) options.progress("scan: " + std::to_string(n) + " FRFs");
    std::size_t best = 0;
    for (std::size_t k = 1; k < scan.size(); ++k)
        if (scan[k].peak.objective() < scan[best].peak.objective()) best = k;
    result.scan = grid;
    for (const FrfResult& r : scan) result.scan_values.push_back(r.peak.objective());
    const auto finish = [&]() {
        for (const TrackResult& t : result.tracks)
            for (const TrackCurve& c : t.curves)
                if (c.status == TrackStatus::failed)
                    result.failed_curves.push_back("curve " + std::to_string(c.id) + " (" + c.label + "): " + c.message);
        result.seconds = watch.lap();
        return result;
    };
    if (!std::isfinite(scan[best].peak.objective())) {
        result.status = OptimizeStatus::unbounded;
        result.message = "no scanned value gives a bounded response: widen the range or lower the excitation";
        return finish();
    }
    if (best == 0 || best + 1 == scan.size()) {
        result.status = OptimizeStatus::at_bound;
        result.kind = "bound";
        result.parameter = grid[best];
        result.value = scan[best].peak.value;
        result.omega = scan[best].peak.omega;
        result.message = std::string("the smallest peak of the scan is at the ") + (best == 0 ? "lower" : "upper") +
                         " end of the range: the optimum may lie outside it";
        return finish();
    }
    // 2. The peaks followed from the best scan value to its neighbours; an FRF at the minimum
    //    found checks it (a peak born between the start and it, or a resonance that became
    //    unbounded there, is invisible to tracking): a larger bounded peak starts the tracks
    //    again from there (at most 3 times), an unbounded one fails the search.
    const double lower = grid[best - 1], upper = grid[best + 1];
    double from = grid[best];
    for (int round = 0; round < 4; ++round) {
        search_tracks(result, system, settings, lower, upper, from, 1e-2 * options.tolerance,
                      {{grid[best - 1], &scan[best - 1]}, {grid[best], &scan[best]}, {grid[best + 1], &scan[best + 1]}},
                      options.progress);
        if (result.status != OptimizeStatus::converged) break;
        const FrfResult check = compute_frf(system(result.parameter), frf);
        ++result.frfs;
        result.check_value = check.peak.value;
        if (check.peak.state != PeakState::bounded) {
            result.status = OptimizeStatus::failed;
            result.message = "the FRF at the tracked minimum " + format_number(result.parameter) + " is " +
                             to_string(check.peak.state) + " (a resonance the tracked peaks do not include): use --method golden";
            break;
        }
        if (!(check.peak.value > result.value * (1.0 + 1e-7))) break;
        if (round == 3) {
            result.status = OptimizeStatus::failed;
            result.message = "the FRF at the minimum found still has a larger peak than the tracked ones after 3 restarts";
            break;
        }
        ++result.restarts;
        from = result.parameter;
    }
    if (result.status == OptimizeStatus::at_bound) {
        // an end of the bracket: the scan's neighbour was larger, so the tracks missed a peak
        result.status = OptimizeStatus::failed;
        result.message = "the tracked minimum lies at the end of the scan's bracket, where the scan's FRF is larger: "
                         "a peak the tracks do not include; use --method golden";
    }
    return finish();
}
}  // namespace hbf
