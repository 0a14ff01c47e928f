// hbfriction — peaks and stick-slip boundaries followed through a second parameter
// (tracking.hpp).
#include "hbf/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "hbf/error.hpp"
#include "studies/fold_tracking.hpp"
#include "studies/track_locate.hpp"
#include "base/stopwatch.hpp"
#include "base/enum_table.hpp"

namespace hbf {

constexpr detail::EnumName<TrackFeature> track_feature_names[] = {
    {TrackFeature::peak, "peak"}, {TrackFeature::boundary, "boundary"}, {TrackFeature::fold, "fold"}};

std::string to_string(TrackFeature feature) { return detail::enum_name(track_feature_names, feature, "track feature"); }

constexpr detail::EnumName<TrackStatus> track_status_names[] = {
    {TrackStatus::completed, "completed"}, {TrackStatus::vanished, "vanished"},
    {TrackStatus::left_range, "left_range"}, {TrackStatus::amplitude_cap, "amplitude_cap"},
    {TrackStatus::point_budget, "point_budget"}, {TrackStatus::failed, "failed"}, {TrackStatus::stopped, "stopped"}};

std::string to_string(TrackStatus status) { return detail::enum_name(track_status_names, status, "track status"); }

void TrackOptions::validate() const {
    if (!std::isfinite(p_start)) throw InvalidInput("p_start = " + format_number(p_start) + " is out of range: allowed finite");
    if (!std::isfinite(p_end) || std::abs(p_end - p_start) <= 1e-12 * std::max(std::abs(p_start), std::abs(p_end)))
        throw InvalidInput("p_end = " + format_number(p_end) + " is out of range: allowed finite and != p_start = " +
                           format_number(p_start));
    if (!std::isnan(omega) && !(std::isfinite(omega) && omega > 0.0))
        throw InvalidInput("omega = " + format_number(omega) + " is out of range: allowed a finite value > 0 (or unset)");
    if (!(max_step >= 1e-6 && max_step <= 0.5))
        throw InvalidInput("max_step = " + format_number(max_step) + " is out of range: allowed 1e-6..0.5 (relative to the range of p)");
    if (!(min_step >= 1e-12 && min_step <= max_step))
        throw InvalidInput("min_step = " + format_number(min_step) + " is out of range: allowed 1e-12..max_step = " +
                           format_number(max_step));
    if (max_points < 10 || max_points > 1000000)
        throw InvalidInput("max_points = " + std::to_string(max_points) + " is out of range: allowed 10..1000000");
    const double lo = std::min(p_start, p_end), hi = std::max(p_start, p_end);
    for (double v : at)
        if (!(std::isfinite(v) && v >= lo && v <= hi))
            throw InvalidInput("at: p = " + format_number(v) + " is out of range: allowed inside " + format_number(lo) +
                               ".." + format_number(hi));
    if (contact < -1) throw InvalidInput("contact = " + std::to_string(contact) + " is out of range: allowed >= 0 (or -1: every contact)");
}

std::string TrackResult::summary() const {
    std::ostringstream s;
    s << verdict.status() << ": " << curves.size() << ' ' << to_string(feature) << " curve(s) (";
    for (std::size_t k = 0; k < curves.size(); ++k)
        s << (k ? ", " : "") << curves[k].id << ' ' << to_string(curves[k].status) << " at p = "
          << format_number(curves[k].points.empty() ? 0.0 : curves[k].points.back().p);
    int exchanges = 0;
    for (const TrackEvent& e : events) exchanges += e.kind == "exchange";
    s << "), " << exchanges << " exchange(s), " << solves << (exact ? " exact" : " HB") << " solves, " << frfs
      << " FRF(s), " << format_number(seconds) << " s";
    return s.str();
}
namespace {
/// A curve being followed.
struct Live {
    std::size_t curve = 0;        ///< index into the result's curves
    double p0 = 0, w0 = 0;        ///< the point before the last (valid with two)
    double p1 = 0, w1 = 0, value = 0;
    bool two = false;
    Eigen::VectorXd state;
    std::string below, above;     ///< boundary: the regimes below and above it in w
    double spread = 0;            ///< boundary: the last step's change of w
    double predict(double p) const { return two && p1 != p0 ? w1 + (w1 - w0) / (p1 - p0) * (p - p1) : w1; }
};
}  // namespace

namespace detail {
TrackResult track_with(const std::function<System(double)>& system, const FrfSettings& settings,
                       const TrackOptions& options, const FrfResult* known_start, const FrfResult* known_end) {
    options.validate();
    settings.validate();
    detail::Stopwatch watch;
    TrackResult result;
    result.feature = options.feature;
    const bool peaks = options.feature == TrackFeature::peak;
    const System first = system(options.p_start);
    (void)system(options.p_end);  // throws InvalidInput for a value out of range, before any work
    const Output output = settings.outputs.empty() ? Output::dof(0) : settings.outputs.front();
    if (options.feature == TrackFeature::fold) return detail::track_folds(system, settings, options, output);
    if (!peaks) {
        if (first.contacts.empty()) throw InvalidInput("feature boundary: the system has no contact");
        if (options.contact >= static_cast<int>(first.contacts.size()))
            throw InvalidInput("contact = " + std::to_string(options.contact + 1) + " is out of range: allowed 1.." +
                               std::to_string(first.contacts.size()));
    }
    const double wmin = settings.continuation.omega_start, wmax = settings.continuation.omega_end;
    const double w_lo = std::min(wmin, wmax), w_hi = std::max(wmin, wmax);

    // 1. The FRF at p_start: its peaks or transitions are the starts.
    FrfSettings frf = settings;
    frf.peaks = peaks;
    frf.peaks_of_every_output = false;
    frf.continuation.locate_transitions = !peaks;
    frf.stability = false;
    frf.at.clear();
    const FrfResult start = known_start ? *known_start : compute_frf(first, frf);
    result.frfs += known_start ? 0 : 1;
    result.exact = start.polish.has_value();
    result.harmonics = frf.harmonic_balance.harmonics;
    if (start.status() != "completed")
        result.verdict.warning("the FRF at p = " + format_number(options.p_start) + " that gives the starts is " +
                               start.status() + ": " + start.summary());
    // The solves along the curves use the start FRF's N_t (raised there where a law needs more
    // than the automatic one: FrfResult::time_samples).
    FrfSettings along = settings;
    if (along.harmonic_balance.time_samples == 0 && start.time_samples > 0)
        along.harmonic_balance.time_samples = start.time_samples;
    ResponseSolver solver(system, along, result.exact, output);
    const std::string out_name = output.name();

    // The branch point of `start` nearest to w on `branch` (a start state for the solver).
    auto nearest_point = [&](double w, int branch) {
        std::size_t best = 0;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < start.points.size(); ++k) {
            const SolutionPoint& q = start.points[k];
            if (q.kind == PointKind::sample || q.branch != branch) continue;
            if (std::abs(q.omega - w) < d) {
                d = std::abs(q.omega - w);
                best = k;
            }
        }
        return start.points.at(best);
    };

    struct Start {
        double omega;
        int branch;
        int contact;
        Boundary boundary;
    };
    std::vector<Start> starts;
    std::string found;
    if (peaks) {
        for (const Peak& k : start.peaks)
            if (k.output == 0) starts.push_back({k.omega, k.branch, 0, Boundary::none});
    } else {
        for (const SolutionPoint& q : start.points)
            if (q.kind == PointKind::transition && q.boundary != Boundary::closed_lift_off &&
                (options.contact < 0 || q.contact == options.contact))
                starts.push_back({q.omega, q.branch, q.contact, q.boundary});
    }
    for (const Start& s : starts) found += (found.empty() ? "" : ", ") + format_number(s.omega);
    const std::string what = peaks ? "peak of " + out_name : "stick-slip boundary";
    // Found only by the work (the FRF at p_start): a failed result (exit 1) with what to do, not
    // bad input.
    const auto nothing = [&](const std::string& why) {
        result.verdict.error(why);
        result.p_reached = options.p_start;
        result.solves = 0;
        result.seconds = watch.lap();
        return result;
    };
    if (starts.empty())
        return nothing("no " + what + " on the FRF over w = " + format_number(w_lo) + ".." + format_number(w_hi) +
                       " at p = " + format_number(options.p_start) + ": nothing to track (" +
                       (start.status() == "completed" ? std::string("start where the FRF has one, or widen wmin..wmax")
                                                      : "that FRF: " + start.summary()) +
                       ")");
    if (!std::isnan(options.omega)) {
        const auto near = std::min_element(starts.begin(), starts.end(), [&](const Start& a, const Start& b) {
            return std::abs(a.omega - options.omega) < std::abs(b.omega - options.omega);
        });
        if (std::abs(near->omega - options.omega) > 0.1 * options.omega)
            throw InvalidInput("omega = " + format_number(options.omega) + ": no " + what + " within 10 % of it at p = " +
                               format_number(options.p_start) + " (found at w = " + found + ")");
        starts = {*near};
    }

    std::vector<Live> live;
    for (const Start& s : starts) {
        TrackCurve curve;
        curve.id = static_cast<int>(result.curves.size()) + 1;
        curve.contact = s.contact;
        curve.boundary = s.boundary;
        const SolutionPoint& q = nearest_point(s.omega, s.branch);
        Live l;
        l.curve = result.curves.size();
        Fix f;
        Eigen::VectorXd from = solver.start(options.p_start, q);
        if (peaks) {
            curve.label = "peak of " + out_name + " near w = " + short_number(s.omega);
            f = locate_peak(solver, options.p_start, s.omega, from, w_lo, w_hi);
        } else {
            // Which regime lies below and which above: solved just either side.
            const double d = 1e-6 * s.omega;
            ResponseSolver::Solution a = solver.at(options.p_start, s.omega - d, from),
                                     b = solver.at(options.p_start, s.omega + d, from);
            curve.label = "contact " + std::to_string(s.contact + 1) + " " + to_string(s.boundary) + " near w = " +
                          short_number(s.omega);
            if (!a.ok || !b.ok || a.regime(s.contact) == b.regime(s.contact)) {
                f.message = "its regimes could not be told apart at p_start";
            } else {
                l.below = a.regime(s.contact);
                l.above = b.regime(s.contact);
                f = locate_boundary(solver, options.p_start, s.omega, 1e-4 * s.omega, from, s.contact, l.below, l.above,
                                    w_lo, w_hi);
            }
        }
        if (!f.ok) {
            curve.status = TrackStatus::failed;
            curve.message = "could not be located at p_start: " + f.message;
            result.curves.push_back(std::move(curve));
            continue;
        }
        curve.points.push_back(point_of(options.p_start, f, "start"));
        l.p1 = options.p_start;
        l.w1 = f.omega;
        l.value = f.value;
        l.state = f.state;
        result.curves.push_back(std::move(curve));
        live.push_back(std::move(l));
    }

    // 2. Follow every live curve in p, all at the same values of p.
    const double range = std::abs(options.p_end - options.p_start);
    const double dir = options.p_end > options.p_start ? 1.0 : -1.0;
    std::vector<double> at = options.at;
    std::sort(at.begin(), at.end(), [dir](double a, double b) { return dir * a < dir * b; });
    std::size_t next_at = 0;
    while (next_at < at.size() && dir * (at[next_at] - options.p_start) <= 0.0) ++next_at;
    double p = options.p_start;
    double step = 0.25 * options.max_step * range;
    const double smallest = options.min_step * range;
    int points = static_cast<int>(live.size());
    const double cap = settings.continuation.max_amplitude;
    std::string stopped;  // why options.stop ended the curves ("" while they go on)

    auto end_curve = [&](Live& l, TrackStatus status, const std::string& message) {
        TrackCurve& c = result.curves[l.curve];
        c.status = status;
        c.message = message;
        if (!c.points.empty() && c.points.back().kind != "start") c.points.back().kind = c.points.back().kind == "at" ? "at" : "end";
    };
    auto locate = [&](Live& l, double at_p, double w_guess, const Eigen::VectorXd& from) {
        const TrackCurve& c = result.curves[l.curve];
        return peaks ? locate_peak(solver, at_p, w_guess, from, w_lo, w_hi)
                     : locate_boundary(solver, at_p, w_guess, std::max(2.0 * l.spread, 1e-4 * w_guess), from, c.contact,
                                       l.below, l.above, w_lo, w_hi);
    };

    // A located feature at p, or a failure when it lies far from the prediction (another's).
    auto attempt = [&](Live& l, double at_p) {
        const double guess = l.predict(at_p);
        if (!(guess > 0.0)) {
            Fix f;
            f.no_feature = true;
            f.message = "the prediction w = " + format_number(guess) + " is not a frequency";
            return f;
        }
        Fix f = locate(l, at_p, guess, l.state);
        // It must lie nearer its own prediction than any other live curve's at the same p (a
        // curve marched alone may be at another p: its secant prediction brings it to at_p).
        double others = std::numeric_limits<double>::infinity();
        for (const Live& o : live)
            if (&o != &l) others = std::min(others, std::abs(o.predict(at_p) - guess));
        if (f.ok && (std::abs(f.omega - guess) > 0.02 * f.omega || std::abs(f.omega - guess) >= 0.25 * others)) {
            f.ok = false;
            f.no_feature = true;
            f.message = "the feature located at w = " + format_number(f.omega) + " is far from the prediction " +
                        format_number(guess);
        }
        return f;
    };
    auto advance = [](Live& l, double at_p, const Fix& f) {
        l.spread = std::abs(f.omega - l.w1);
        l.p0 = l.p1;
        l.w0 = l.w1;
        l.two = true;
        l.p1 = at_p;
        l.w1 = f.omega;
        l.value = f.value;
        l.state = f.state;
    };

    // The first predictor's slope: each feature located again a small step into the range (not
    // a point of the curve); without it the first step predicts the start's own w, and a feature
    // that moves fast in p is confused with a neighbour.
    for (Live& l : live) {
        const double probe = options.p_start + dir * std::max(options.min_step, 1e-4) * range;
        const Fix f = locate(l, probe, l.w1, l.state);
        if (!f.ok || std::abs(f.omega - l.w1) > 0.02 * l.w1) continue;  // the steps find out
        l.p0 = probe;
        l.w0 = f.omega;
        l.two = true;
    }

    while (!live.empty()) {
        if (std::abs(p - options.p_end) <= 1e-14 * std::max(range, std::abs(p))) break;
        if (points >= options.max_points) {
            for (Live& l : live)
                end_curve(l, TrackStatus::point_budget,
                          "max_points = " + std::to_string(options.max_points) + " reached at p = " + format_number(p));
            live.clear();
            break;
        }
        if (options.stop) {
            stopped = options.stop();
            if (!stopped.empty()) {
                for (Live& l : live) end_curve(l, TrackStatus::stopped, "stopped at p = " + format_number(p) + ": " + stopped);
                live.clear();
                break;
            }
        }
        double target = p + dir * step;
        std::string kind = "step";
        if (next_at < at.size() && dir * (at[next_at] - target) <= 0.0) {
            target = at[next_at];
            kind = "at";
        }
        if (dir * (options.p_end - target) <= 0.0) {
            target = options.p_end;
            if (kind != "at") kind = "step";
        }
        std::vector<Fix> fixes;
        bool all = true;
        int iterations = 0;
        for (Live& l : live) {
            Fix f = attempt(l, target);
            all = all && f.ok;
            iterations = std::max(iterations, f.iterations);
            fixes.push_back(std::move(f));
        }
        // Two curves that reach the same peak: the one that moved farther has lost its own.
        for (std::size_t a = 0; a < live.size(); ++a)
            for (std::size_t b = a + 1; b < live.size(); ++b)
                if (fixes[a].ok && fixes[b].ok && std::abs(fixes[a].omega - fixes[b].omega) <= 1e-6 * fixes[a].omega) {
                    const std::size_t lost = std::abs(fixes[a].omega - live[a].predict(target)) >
                                                     std::abs(fixes[b].omega - live[b].predict(target))
                                                 ? a
                                                 : b;
                    fixes[lost].ok = false;
                    fixes[lost].no_feature = true;
                    fixes[lost].message = "no maximum of its own near the prediction (the search reached curve " +
                                          std::to_string(result.curves[live[a + b - lost].curve].id) + "'s)";
                    all = false;
                }
        if (!all && step > 0.0625 * options.max_step * range && step > smallest * (1.0 + 1e-9)) {
            step = std::max(0.5 * step, smallest);  // a failure at a long step is usually the step's
            continue;
        }
        if (!all) {
            // A curve that still fails is marched alone from its last p towards target with its
            // own step control (a failure halves the step, a success lengthens it and updates the
            // secant predictor): it rejoins the others at target, or ends where the step falls
            // below the smallest one (the feature is no longer near any prediction: it ended).
            // The others go on to target.
            std::vector<Live> kept;
            std::vector<Fix> kept_fixes;
            for (std::size_t k = 0; k < live.size(); ++k) {
                Live& l = live[k];
                if (fixes[k].ok) {
                    kept.push_back(std::move(l));
                    kept_fixes.push_back(std::move(fixes[k]));
                    continue;
                }
                TrackCurve& c = result.curves[l.curve];
                double lo = l.p1, h = 0.5 * (target - l.p1);
                Fix failure = fixes[k];
                double failed_at = target;
                bool arrived = false;
                while (std::abs(h) > smallest && points < options.max_points) {
                    const bool last = std::abs(target - lo) <= std::abs(h) * (1.0 + 1e-12);
                    const double at_p = last ? target : lo + h;
                    Fix f = attempt(l, at_p);
                    if (!f.ok) {
                        h *= 0.5;
                        failed_at = at_p;
                        failure = std::move(f);
                        continue;
                    }
                    if (last) {
                        kept.push_back(std::move(l));
                        kept_fixes.push_back(std::move(f));
                        arrived = true;
                        break;
                    }
                    c.points.push_back(point_of(at_p, f, "search"));
                    ++points;
                    advance(l, at_p, f);
                    lo = at_p;
                    h *= 2.0;
                }
                if (arrived) continue;
                const double hi = failed_at;
                const std::string where = " between p = " + format_number(lo) + " and " + format_number(hi);
                if (failure.no_feature) {
                    end_curve(l, TrackStatus::vanished,
                              std::string(peaks ? "the peak ends (no maximum near its prediction: it merged with a valley, or the "
                                                    "stick/slip corner it sat on stopped being a maximum)"
                                                  : "the boundary ends (no regime change near its prediction)") + where +
                                  ": " + failure.message);
                    result.events.push_back({"vanished", l.p1, l.w1, l.value, c.id, 0, 0});
                } else {
                    const double first = c.points.empty() ? 0.0 : c.points.front().value;
                    const std::string growth =
                        peaks && first > 0.0 && l.value > 5.0 * first
                            ? " (the peak grew from " + format_number(first) + " to " + format_number(l.value) +
                                  ": the resonance may become unbounded there)"
                            : "";
                    end_curve(l, TrackStatus::failed, "the solves failed" + where + ": " + failure.message + growth);
                }
            }
            live = std::move(kept);
            fixes = std::move(kept_fixes);
            if (live.empty()) break;
        }
        // Accepted at `target`: exchanges between live peaks first (their values cross).
        if (peaks)
            for (std::size_t a = 0; a < live.size(); ++a)
                for (std::size_t b = a + 1; b < live.size(); ++b) {
                    const double before = live[a].value - live[b].value, after = fixes[a].value - fixes[b].value;
                    if (!(before * after < 0.0)) continue;
                    // Regula falsi (Illinois) in p on the difference of the two peaks.
                    // (a curve marched alone may have reached a later p than the other: the later)
                    double pa = dir * live[a].p1 > dir * live[b].p1 ? live[a].p1 : live[b].p1;
                    double pb = target, fa = before, fb = after;
                    Eigen::VectorXd sa = live[a].state, sb = live[b].state;
                    Fix ea, eb;
                    bool ok = true;
                    for (int it = 0; it < 80 && std::abs(pb - pa) > 1e-10 * std::max(std::abs(pb), range); ++it) {
                        const double pm = pb - fb * (pb - pa) / (fb - fa);
                        const auto between = [&](std::size_t i) {
                            const double s = target == live[i].p1 ? 1.0 : (pm - live[i].p1) / (target - live[i].p1);
                            return live[i].w1 + s * (fixes[i].omega - live[i].w1);
                        };
                        ea = locate_peak(solver, pm, between(a), sa, w_lo, w_hi);
                        eb = locate_peak(solver, pm, between(b), sb, w_lo, w_hi);
                        if (!ea.ok || !eb.ok) {
                            ok = false;
                            break;
                        }
                        const double fm = ea.value - eb.value;
                        if (fm == 0.0) {
                            pa = pb = pm;
                            break;
                        }
                        if (fm * fb < 0.0) {
                            pa = pb;
                            fa = fb;
                        } else {
                            fa *= 0.5;  // Illinois: the end kept again counts half
                        }
                        pb = pm;
                        fb = fm;
                        sa = ea.state;
                        sb = eb.state;
                    }
                    if (!ok || !ea.ok) {
                        result.verdict.note("the exchange of curves " + std::to_string(result.curves[live[a].curve].id) +
                                            " and " + std::to_string(result.curves[live[b].curve].id) + " between p = " +
                                            format_number(live[a].p1) + " and " + format_number(target) +
                                            " could not be located (a solve failed)");
                        continue;
                    }
                    result.curves[live[a].curve].points.push_back(point_of(pb, ea, "exchange"));
                    result.curves[live[b].curve].points.push_back(point_of(pb, eb, "exchange"));
                    TrackEvent e{"exchange", pb, ea.omega, ea.value, result.curves[live[a].curve].id,
                                 result.curves[live[b].curve].id, eb.omega};
                    result.events.push_back(e);
                    points += 2;
                }
        std::vector<Live> kept;
        double largest = -1.0;
        TrackResult::Largest top;
        for (std::size_t k = 0; k < live.size(); ++k) {
            Live& l = live[k];
            Fix& f = fixes[k];
            TrackCurve& c = result.curves[l.curve];
            c.points.push_back(point_of(target, f, kind));
            ++points;
            if (f.outside) {
                end_curve(l, TrackStatus::left_range,
                          "w = " + format_number(f.omega) + " left the range " + format_number(w_lo) + ".." +
                              format_number(w_hi) + " at p = " + format_number(target));
                continue;
            }
            if (f.value > cap) {
                end_curve(l, TrackStatus::amplitude_cap,
                          "the value " + format_number(f.value) + " exceeds the amplitude cap " + format_number(cap) +
                              " at p = " + format_number(target) + " (an unbounded resonance)");
                continue;
            }
            advance(l, target, f);
            if (f.value > largest) {
                largest = f.value;
                top = {target, f.omega, f.value, c.id, kind};
            }
            kept.push_back(std::move(l));
        }
        if (peaks && largest >= 0.0) result.largest.push_back(top);
        live = std::move(kept);
        p = target;
        if (kind == "at") ++next_at;
        if (options.progress) options.progress(p);
        // Longer steps while the features are found in a few Newton iterations.
        if (iterations <= 6) step = std::min(1.6 * step, options.max_step * range);
    }
    result.p_reached = p;
    result.solves = solver.solves();

    // 3. The check at the end (peaks): an FRF at p_end, whose peaks every completed curve
    //    should reach; one that none reaches was born inside the range.
    if (peaks && !stopped.empty())
        result.verdict.note("not done after the stop: the check FRF at p = " + format_number(options.p_end) +
                            " (peaks born inside the range)");
    if (peaks && stopped.empty()) {
        const FrfResult end = known_end ? *known_end : compute_frf(system(options.p_end), frf);
        result.frfs += known_end ? 0 : 1;
        // A curve reaches a peak of the FRF when its last point is on the same hump: within 1e-4
        // w, or no branch point of the FRF between the two dips below both by more than the
        // resolution of harmonic balance there (the FRF's estimated error, at least 1e-3 of the
        // larger: a flat or kinked peak at few harmonics is a saw-tooth of tiny maxima, located a
        // little differently by the FRF's search and by the tracking's Newton on dY/dw = 0); a
        // peak born inside the range is another hump, behind a real valley.
        const double resolution = std::max(1e-3, std::isfinite(end.hb_error) ? end.hb_error : 0.0);
        auto same_hump = [&](double w1, double v1, double w2, double v2) {
            if (std::abs(w1 - w2) <= 1e-4 * std::max(w1, w2)) return true;
            const double lo = std::min(w1, w2), hi = std::max(w1, w2);
            const double floor = std::min(v1, v2) - resolution * std::max(v1, v2);
            bool between = false;
            for (std::size_t i = 0; i < end.points.size() && i < end.metrics.size(); ++i) {
                const double w = end.points[i].omega;
                if (w <= lo || w >= hi || end.points[i].branch != 1 || end.metrics[i].output_max.empty()) continue;
                between = true;
                if (end.metrics[i].output_max[0] < floor) return false;
            }
            return between || std::abs(w1 - w2) <= 1e-2 * std::max(w1, w2);
        };
        for (const Peak& k : end.peaks) {
            if (k.output != 0) continue;
            bool reached = false;
            for (const TrackCurve& c : result.curves)
                reached = reached || (c.status == TrackStatus::completed && !c.points.empty() &&
                                      same_hump(c.points.back().omega, c.points.back().value, k.omega, k.y_max));
            if (reached || (!std::isnan(options.omega) && starts.size() == 1)) continue;
            result.events.push_back({"born", options.p_end, k.omega, k.y_max, 0, 0, 0});
            result.verdict.warning("the FRF at p = " + format_number(options.p_end) + " has a peak of " + out_name +
                                   " at w = " + format_number(k.omega) + " (" + format_number(k.y_max) +
                                   ") that no tracked curve reaches: it was born inside the range (track it from p_end)");
        }
    }

    // The verdict.
    for (const TrackCurve& c : result.curves) {
        const std::string line = "curve " + std::to_string(c.id) + " (" + c.label + "): " + to_string(c.status) + ": " + c.message;
        switch (c.status) {
            case TrackStatus::completed: break;
            case TrackStatus::vanished: result.verdict.note(line); break;
            case TrackStatus::failed: result.verdict.error(line); break;
            default: result.verdict.warning(line); break;
        }
    }
    for (const TrackEvent& e : result.events)
        if (e.kind == "exchange")
            result.verdict.note("curves " + std::to_string(e.curve) + " and " + std::to_string(e.other) +
                                " exchange at p = " + format_number(e.p) + ": equal peaks " + format_number(e.value) +
                                " at w = " + format_number(e.omega) + " and " + format_number(e.other_omega));
    result.verdict.add(start.messages);
    result.seconds = watch.lap();
    return result;
}

}  // namespace detail

TrackResult track(const std::function<System(double)>& system, const FrfSettings& settings, const TrackOptions& options) {
    return detail::track_with(system, settings, options, nullptr, nullptr);
}
}  // namespace hbf
