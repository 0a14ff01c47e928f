// hbfriction — a pair of folds (limit points) of a harmonic-balance FRF followed through a
// second parameter until they merge in a cusp (tracking.hpp, feature fold).
//
// At each value of p the folds are located on a local branch: the continuation of hbf frf over
// a window around the predicted folds (their distance three times over on each side, at least
// 0.2 % of w), with its own fold location (the zero of the tangent's omega-component by regula
// falsi, continuation.hpp: 1e-10 of arclength). The pair is followed in p with a secant
// predictor of both folds; where the window holds no fold any more, the S-shape has closed:
// the cusp lies between the last p with folds and that one, and is located by bisection in p to
// the smallest step (each trial a local branch). At the cusp both folds end (status vanished,
// event cusp at the mean of the two folds' frequencies at the last p with folds).
//
// A Moore-Spence system (R = 0, J v = 0, l.v = 1) followed by arclength through the cusp was
// tried first: on the Dahl example its Jacobian (second derivatives of the AFT forces by
// differences) was not smooth enough, and the null vector turned abruptly (a second small
// singular value); the local branches use the FRF's proven corrector instead.
#include "studies/fold_tracking.hpp"

#include <algorithm>
#include <cmath>

#include "hbf/error.hpp"
#include "base/stopwatch.hpp"

namespace hbf::detail {

namespace {

/// The folds of the branch of system(p) over [wa, wb] (local continuation), with the branch's
/// status; `metrics` gives each fold's value of `output`.
struct LocalFolds {
    bool ok = false;
    std::string message;
    std::vector<double> omega, value;
};

LocalFolds local_folds(const std::function<System(double)>& system, const FrfSettings& settings, double p, double wa,
                       double wb, double max_step, const Output& output) {
    LocalFolds out;
    try {
        HarmonicBalance hb(system(p), settings.harmonic_balance);
        ContinuationOptions c = settings.continuation;
        c.omega_start = wa;
        c.omega_end = wb;
        c.locate_folds = true;
        c.locate_transitions = false;
        c.restart_past_cap = false;
        c.max_step = std::min(c.max_step, max_step);
        c.progress = nullptr;
        c.fold_progress = nullptr;
        BranchResult b = continue_branch(hb, c);
        // Near a cusp the window's start lies where the response is far from the linear guess
        // (Newton's start may fail there): started lower, where it is closer to linear, down to
        // the FRF's own start. The folds below the window the wider branch may find are
        // discarded by the caller (the pair nearest the prediction).
        const double lowest = std::min(settings.continuation.omega_start, settings.continuation.omega_end);
        for (double widen = 4.0; b.status == ContinuationStatus::start_failed && c.omega_start > lowest; widen *= 4.0) {
            c.omega_start = std::max(lowest, wa - widen * (wb - wa));
            b = continue_branch(hb, c);
        }
        if (b.status != ContinuationStatus::completed) {
            out.message = "the local branch over w = " + format_number(wa) + ".." + format_number(wb) + " at p = " +
                          format_number(p) + " did not complete: " + b.summary();
            return out;
        }
        Analyser analyse(hb, {}, {output});
        for (const SolutionPoint& q : b.points)
            if (q.kind == PointKind::fold) {
                out.omega.push_back(q.omega);
                const PointMetrics m = analyse(q);
                out.value.push_back(m.output_max.empty() ? std::numeric_limits<double>::quiet_NaN() : m.output_max.front());
            }
        out.ok = true;
    } catch (const InvalidInput& e) {
        out.message = e.what();
    }
    return out;
}

}  // namespace

TrackResult track_folds(const std::function<System(double)>& system, const FrfSettings& settings,
                        const TrackOptions& options, const Output& output) {
    Stopwatch watch;
    TrackResult result;
    result.feature = TrackFeature::fold;
    const double wmin = std::min(settings.continuation.omega_start, settings.continuation.omega_end),
                 wmax = std::max(settings.continuation.omega_start, settings.continuation.omega_end);
    FrfSettings frf = settings;
    frf.exact = false;  // folds of the harmonic-balance branch
    frf.peaks = false;
    frf.stability = false;
    frf.at.clear();
    frf.continuation.locate_folds = true;
    frf.continuation.locate_transitions = false;
    const FrfResult start = compute_frf(system(options.p_start), frf);
    result.frfs = 1;
    result.harmonics = frf.harmonic_balance.harmonics;
    if (start.status() != "completed")
        result.verdict.warning("the FRF at p = " + format_number(options.p_start) + " that gives the starts is " +
                               start.status() + ": " + start.summary());
    std::vector<const SolutionPoint*> folds;
    std::string found;
    for (const SolutionPoint& q : start.points)
        if (q.kind == PointKind::fold) {
            folds.push_back(&q);
            found += (found.empty() ? "" : ", ") + format_number(q.omega);
        }
    if (folds.size() < 2)
        throw InvalidInput("feature fold follows a pair of folds (an S-shaped stretch of the FRF): the FRF over w = " +
                           format_number(wmin) + ".." + format_number(wmax) + " at p = " + format_number(options.p_start) +
                           " has " + std::to_string(folds.size()) + (folds.empty() ? "" : " (at w = " + found + ")"));
    // The pair: the two neighbouring folds nearest options.omega (or the first two).
    std::size_t first = 0;
    if (!std::isnan(options.omega)) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k + 1 < folds.size(); ++k) {
            const double d = std::abs(0.5 * (folds[k]->omega + folds[k + 1]->omega) - options.omega);
            if (d < best) {
                best = d;
                first = k;
            }
        }
        if (best > 0.1 * options.omega)
            throw InvalidInput("omega = " + format_number(options.omega) + ": no pair of folds within 10 % of it at p = " +
                               format_number(options.p_start) + " (folds at w = " + found + ")");
    }
    TrackCurve a, b;
    a.id = 1;
    b.id = 2;
    a.label = "fold near w = " + format_number(std::round(folds[first]->omega * 1e5) / 1e5);
    b.label = "fold near w = " + format_number(std::round(folds[first + 1]->omega * 1e5) / 1e5);
    auto point = [](double p, double w, double value, const std::string& kind) {
        TrackPoint t;
        t.p = p;
        t.omega = w;
        t.value = value;
        t.kind = kind;
        return t;
    };
    // The starts as the local branch gives them (the same corrector as the later steps).
    double w1 = folds[first]->omega, w2 = folds[first + 1]->omega;
    // Within the FRF's own range: a wide S (a Duffing oscillator's folds far apart) would put
    // the window's lower end below 0.
    const auto window = [&](double u1, double u2) {
        const double mid = 0.5 * (u1 + u2), half = std::max(4.0 * std::abs(u1 - u2), 5e-3 * mid);
        return std::make_pair(std::max(mid - half, frf.continuation.omega_start),
                              std::min(mid + half, frf.continuation.omega_end));
    };
    // Near a cusp the S-shape shrinks (its height like sqrt(p - p_c), its width like
    // (p - p_c)^(3/2)): the local branch must step finely enough to see both folds.
    auto pair_at = [&](double p, double u1, double u2, LocalFolds& f) {
        const auto [wa, wb] = window(u1, u2);
        const double gap = std::abs(u1 - u2) / (0.5 * (u1 + u2));
        f = local_folds(system, frf, p, wa, wb, std::clamp(2.0 * std::cbrt(gap), 1e-3, 0.05), output);
        if (f.ok && f.omega.size() > 2) {
            // More sign changes near a cusp (the S is tiny there): the neighbouring pair nearest
            // the prediction.
            std::size_t k = 0;
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i + 1 < f.omega.size(); ++i) {
                const double d = std::abs(f.omega[i] - u1) + std::abs(f.omega[i + 1] - u2);
                const double e = std::abs(f.omega[i] - u2) + std::abs(f.omega[i + 1] - u1);
                if (std::min(d, e) < best) {
                    best = std::min(d, e);
                    k = i;
                }
            }
            f.omega = {f.omega[k], f.omega[k + 1]};
            f.value = {f.value[k], f.value[k + 1]};
        }
        ++result.solves;
        return f.ok && f.omega.size() == 2;
    };
    LocalFolds f;
    if (!pair_at(options.p_start, w1, w2, f))
        throw InvalidInput("the folds at w = " + format_number(w1) + " and " + format_number(w2) +
                           " could not be located again on a local branch at p = " + format_number(options.p_start) +
                           (f.message.empty() ? "" : ": " + f.message));
    // Order the pair by frequency, as found at the start.
    const bool ascending = w1 < w2;
    auto sorted = [&](LocalFolds& g) {
        if ((g.omega[0] < g.omega[1]) != ascending) {
            std::swap(g.omega[0], g.omega[1]);
            std::swap(g.value[0], g.value[1]);
        }
    };
    sorted(f);
    a.points.push_back(point(options.p_start, f.omega[0], f.value[0], "start"));
    b.points.push_back(point(options.p_start, f.omega[1], f.value[1], "start"));
    const double range = std::abs(options.p_end - options.p_start), dir = options.p_end > options.p_start ? 1.0 : -1.0;
    const double smallest = options.min_step * range;
    double p = options.p_start, step = 0.25 * options.max_step * range;
    double p0 = p, a0 = f.omega[0], b0 = f.omega[1];  // the previous point (secant)
    bool two = false;
    a.status = b.status = TrackStatus::completed;
    int points = 2;
    while (std::abs(p - options.p_end) > 1e-14 * std::max(range, std::abs(p))) {
        if (points >= options.max_points) {
            a.status = b.status = TrackStatus::point_budget;
            a.message = b.message = "max_points = " + std::to_string(options.max_points) + " reached at p = " + format_number(p);
            break;
        }
        if (options.stop) {
            const std::string why = options.stop();
            if (!why.empty()) {
                a.status = b.status = TrackStatus::stopped;
                a.message = b.message = "stopped at p = " + format_number(p) + ": " + why;
                break;
            }
        }
        double target = p + dir * step;
        if (dir * (options.p_end - target) <= 0.0) target = options.p_end;
        const double a1 = a.points.back().omega, b1 = b.points.back().omega;
        const double s = two && p != p0 ? (target - p) / (p - p0) : 0.0;
        LocalFolds g;
        if (pair_at(target, a1 + s * (a1 - a0), b1 + s * (b1 - b0), g)) {
            sorted(g);
            p0 = p;
            a0 = a1;
            b0 = b1;
            two = true;
            p = target;
            a.points.push_back(point(p, g.omega[0], g.value[0], "step"));
            b.points.push_back(point(p, g.omega[1], g.value[1], "step"));
            points += 2;
            if (options.progress) options.progress(p);
            if (g.omega[0] < wmin || g.omega[1] > wmax || g.omega[1] < wmin || g.omega[0] > wmax) {
                a.status = b.status = TrackStatus::left_range;
                a.message = b.message = "the folds left the range " + format_number(wmin) + ".." + format_number(wmax) +
                                        " at p = " + format_number(p);
                break;
            }
            step = std::min(1.5 * step, options.max_step * range);
            continue;
        }
        if (!g.ok || (!g.omega.empty() && g.omega.size() != 2)) {
            // A failed local branch, or a window that caught a third fold: a shorter step.
            if (step > smallest * (1.0 + 1e-9)) {
                step = std::max(0.5 * step, smallest);
                continue;
            }
            a.status = b.status = TrackStatus::failed;
            a.message = b.message = "the folds could not be located beyond p = " + format_number(p) + ": " +
                                    (g.message.empty() ? std::to_string(g.omega.size()) + " folds in the window" : g.message);
            break;
        }
        // No fold in the window: the S-shape closed between p and target. Bisection in p.
        double lo = p, hi = target;
        double wa_lo = a.points.back().omega, wb_lo = b.points.back().omega;
        bool failed = false;
        std::string why;
        while (std::abs(hi - lo) > smallest) {
            const double mid = 0.5 * (lo + hi);
            LocalFolds m;
            if (pair_at(mid, wa_lo, wb_lo, m)) {
                sorted(m);
                lo = mid;
                wa_lo = m.omega[0];
                wb_lo = m.omega[1];
                a.points.push_back(point(mid, m.omega[0], m.value[0], "search"));
                b.points.push_back(point(mid, m.omega[1], m.value[1], "search"));
                points += 2;
            } else if (m.ok && m.omega.empty()) {
                hi = mid;
            } else if (m.ok) {
                lo = mid;  // an odd count: a fold the local branch did not resolve, the S still there
            } else {
                failed = true;
                why = m.message;
                break;
            }
        }
        if (failed) {
            a.status = b.status = TrackStatus::failed;
            a.message = b.message = "a local branch failed while locating the cusp between p = " + format_number(lo) +
                                    " and " + format_number(hi) + (why.empty() ? "" : ": " + why);
            break;
        }
        const double pc = 0.5 * (lo + hi), wc = 0.5 * (wa_lo + wb_lo);
        const double vc = 0.5 * (a.points.back().value + b.points.back().value);
        a.points.push_back(point(pc, wc, vc, "cusp"));
        b.points.push_back(point(pc, wc, vc, "cusp"));
        a.status = b.status = TrackStatus::vanished;
        a.message = b.message = "the two folds merge in a cusp at p = " + format_number(pc) + ", w = " + format_number(wc) +
                                " (between p = " + format_number(lo) + ", two folds, and " + format_number(hi) + ", none)";
        result.events.push_back({"cusp", pc, wc, vc, 1, 2, wc});
        break;
    }
    result.curves = {a, b};
    const TrackCurve& c = result.curves.front();
    const std::string line = "folds " + a.label + " and " + b.label + ": " + to_string(c.status) + ": " + c.message;
    if (c.status == TrackStatus::failed) result.verdict.error(line);
    else if (c.status == TrackStatus::vanished) result.verdict.note(line);
    else if (c.status != TrackStatus::completed) result.verdict.warning(line);
    result.p_reached = p;
    result.seconds = watch.lap();
    return result;
}

}  // namespace hbf::detail
