// hbfriction — peaks and stick-slip boundaries followed through a second parameter
// (tracking.hpp).
#include "hbf/tracking.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <sstream>

#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_polish.hpp"
#include "studies/fold_tracking.hpp"
#include "numerics/golden_section.hpp"
#include "numerics/peak_newton.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

std::string to_string(TrackFeature feature) {
    switch (feature) {
        case TrackFeature::peak: return "peak";
        case TrackFeature::boundary: return "boundary";
        case TrackFeature::fold: return "fold";
    }
    return "?";
}

std::string to_string(TrackStatus status) {
    switch (status) {
        case TrackStatus::completed: return "completed";
        case TrackStatus::vanished: return "vanished";
        case TrackStatus::left_range: return "left_range";
        case TrackStatus::amplitude_cap: return "amplitude_cap";
        case TrackStatus::point_budget: return "point_budget";
        case TrackStatus::failed: return "failed";
    }
    return "?";
}

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

/// Periodic responses of system(p) at (w, p), each from a given start: the event-exact orbit or
/// a harmonic-balance correction. Keeps the system (and its HB objects) of the last p.
class ResponseSolver {
public:
    struct Solution {
        bool ok = false;
        double y = 0;                      ///< max over one period of |o(t)| of the output
        std::vector<std::string> regimes;  ///< per contact
        Eigen::VectorXd state;             ///< exact: the orbit's state at t = 0; HB: X
        std::string message;
        std::string regime(int c) const {
            return regimes.empty() ? "none" : regimes[static_cast<std::size_t>(std::max(0, c))];
        }
    };

    ResponseSolver(const std::function<System(double)>& system, const FrfSettings& settings, bool exact, Output output)
        : factory_(system), settings_(settings), exact_(exact), output_(std::move(output)) {
        exact_options_.tolerance = 1e-13;
        exact_options_.outputs = {output_};
        exact_options_.dof_maxima = false;
        corrector_options_ = settings.continuation.corrector;
        corrector_options_.tolerance = std::min(corrector_options_.tolerance, 1e-10);
    }
    bool exact() const { return exact_; }
    long long solves() const { return solves_; }
    const System& system(double p) {
        set(p);
        return system_;
    }

    Solution at(double p, double w, const Eigen::VectorXd& start) {
        set(p);
        ++solves_;
        Solution s;
        if (exact_) {
            const auto good = [](const ExactOrbit& o) {
                return o.converged && !o.output_max.empty() && std::isfinite(o.output_max.front());
            };
            ExactOrbit o = exact_periodic_orbit(system_, w, start, exact_options_);
            // Where the stick/slip pattern changes near w a start from another w or p may fail:
            // march from the last orbit of this p in 4, then 16 sub-steps; then start from the
            // harmonic-balance solution at (w, p), as the polish does.
            for (int pieces : {4, 16}) {
                if (good(o) || last_x_.size() == 0 || last_w_ == w) break;
                ExactOrbit q;
                q.state = last_x_;
                q.converged = true;
                q.output_max = {0.0};
                for (int k = 1; k <= pieces && good(q); ++k)
                    q = exact_periodic_orbit(system_, last_w_ + (w - last_w_) * k / pieces, q.state, exact_options_);
                if (good(q)) o = std::move(q);
            }
            if (!good(o)) {
                ensure_hb();
                SolutionPoint point;
                point.omega = w;
                point.x = hb_->linear_guess(w);
                if (corrector_->solve_at(point.x, w, hb_->unknown_scale(point.x), point.iterations, point.residual)) {
                    ExactOrbit q = exact_periodic_orbit(system_, w, exact_start_state(*hb_, point), exact_options_);
                    if (good(q)) o = std::move(q);
                }
            }
            s.ok = good(o);
            s.message = o.message;
            if (!s.ok) return s;
            last_x_ = o.state;
            last_w_ = w;
            s.y = o.output_max.front();
            for (const ContactRegime& r : o.contacts) s.regimes.push_back(r.regime);
            s.state = o.state;
            return s;
        }
        SolutionPoint point;
        point.omega = w;
        point.x = start.size() == static_cast<Eigen::Index>(hb_->unknowns()) ? start : hb_->linear_guess(w);
        const auto solve = [&](Eigen::VectorXd& x, double at_w) {
            return corrector_->solve_at(x, at_w, hb_->unknown_scale(x), point.iterations, point.residual);
        };
        bool ok = solve(point.x, w);
        // Near a sharp resonance a start from another w may be too far: march from the last
        // solution of this p in 4, then 16 sub-steps, then try the linear response.
        for (int pieces : {4, 16}) {
            if (ok || last_x_.size() == 0) break;
            point.x = last_x_;
            ok = true;
            for (int k = 1; k <= pieces && ok; ++k) ok = solve(point.x, last_w_ + (w - last_w_) * k / pieces);
        }
        if (!ok) {
            point.x = hb_->linear_guess(w);
            ok = solve(point.x, w);
        }
        if (!ok) {
            s.message = "the HB corrector did not converge at w = " + format_number(w) + " (residual " +
                        format_number(point.residual) + ")";
            return s;
        }
        last_x_ = point.x;
        last_w_ = w;
        const PointMetrics m = (*analyser_)(point);
        s.ok = !m.output_max.empty() && std::isfinite(m.output_max.front());
        s.y = s.ok ? m.output_max.front() : 0.0;
        for (const ContactRegime& r : m.contacts) s.regimes.push_back(r.regime);
        s.state = point.x;
        return s;
    }

    /// A start for at() from a point of an HB branch of system(p).
    Eigen::VectorXd start(double p, const SolutionPoint& point) {
        set(p);
        if (!exact_) return point.x;
        HarmonicBalance hb(system_, settings_.harmonic_balance);
        return exact_start_state(hb, point);
    }

private:
    void set(double p) {
        if (has_ && p == p_) return;
        // The HB objects hold references to the system and to each other: rebuilt in order.
        analyser_.reset();
        corrector_.reset();
        hb_.reset();
        system_ = factory_(p);
        p_ = p;
        last_x_.resize(0);
        has_ = true;
        if (exact_) return;
        ensure_hb();
        analyser_ = std::make_unique<Analyser>(*hb_, std::vector<int>{}, std::vector<Output>{output_});
    }
    /// The HB objects of the current system (built once per p; the exact solver's fallback too).
    void ensure_hb() {
        if (hb_) return;
        hb_ = std::make_unique<HarmonicBalance>(system_, settings_.harmonic_balance);
        corrector_ = std::make_unique<Corrector>(*hb_, corrector_options_);
    }

    std::function<System(double)> factory_;
    FrfSettings settings_;
    bool exact_;
    Output output_;
    ExactOptions exact_options_;
    CorrectorOptions corrector_options_;
    System system_;
    double p_ = 0;
    bool has_ = false;
    std::unique_ptr<HarmonicBalance> hb_;
    std::unique_ptr<Corrector> corrector_;
    std::unique_ptr<Analyser> analyser_;
    long long solves_ = 0;
    Eigen::VectorXd last_x_;  ///< the last solution at this p (exact state or HB X), at last_w_
    double last_w_ = 0;
};

/// One located feature at fixed p.
struct Fix {
    bool ok = false;
    bool no_feature = false;  ///< no maximum (or no boundary) near the prediction
    bool outside = false;     ///< it lies outside [wmin, wmax]
    double omega = 0, value = 0, curvature = std::numeric_limits<double>::quiet_NaN();
    bool corner = false;
    int iterations = 0;
    std::string regime, message;
    Eigen::VectorXd state;
};

/// Bisection in w between lo (regime a) and hi (another regime) to |hi - lo| <= tol w: returns
/// the solutions at both ends.
bool bisect_regime(ResponseSolver& solver, double p, int contact, ResponseSolver::Solution& lo, double& w_lo,
                   ResponseSolver::Solution& hi, double& w_hi, double tol) {
    const std::string a = lo.regime(contact);
    for (int it = 0; it < 200 && std::abs(w_hi - w_lo) > tol * std::abs(w_hi); ++it) {
        const double mid = 0.5 * (w_lo + w_hi);
        ResponseSolver::Solution s = solver.at(p, mid, lo.state);
        if (!s.ok) s = solver.at(p, mid, hi.state);
        if (!s.ok) return false;
        if (s.regime(contact) == a) {
            lo = std::move(s);
            w_lo = mid;
        } else {
            hi = std::move(s);
            w_hi = mid;
        }
    }
    return true;
}

/// The peak of Y(w) at p near w0 (peak_newton.hpp), or the stick/slip corner it sits on.
Fix locate_peak(ResponseSolver& solver, double p, double w0, const Eigen::VectorXd& start, double wmin, double wmax) {
    Fix f;
    ResponseSolver::Solution last;
    last.state = start;
    std::string failure;
    std::vector<std::pair<double, ResponseSolver::Solution>> recent;  // the stencil's solutions
    const auto value = [&](double w, bool& good) {
        if (!(w > 0.0 && std::isfinite(w))) {  // a Newton step past w = 0: no maximum there
            good = false;
            failure = "a step reached w = " + format_number(w);
            return 0.0;
        }
        ResponseSolver::Solution s = solver.at(p, w, last.state);
        if (!s.ok) {
            good = false;
            failure = s.message;
            return 0.0;
        }
        last = std::move(s);
        if (recent.size() == 6) recent.erase(recent.begin());
        recent.emplace_back(w, last);
        return last.y;
    };
    const auto solution_at = [&](double w) {
        for (const auto& [x, s] : recent)
            if (x == w) return s;
        return solver.at(p, w, last.state);
    };
    ResponseSolver::Solution lo, hi;
    double w_lo = 0, w_hi = 0;
    const auto corner = [&](double a, double b) {
        lo = solution_at(a);
        hi = solution_at(b);
        w_lo = a;
        w_hi = b;
        return lo.ok && hi.ok && lo.regimes != hi.regimes;
    };
    const detail::PeakNewton r = detail::peak_newton(value, w0, solver.exact() ? 1e-5 : 1e-4, 0.05, corner);
    f.iterations = r.iterations;
    if (!r.ok) {
        f.no_feature = r.no_maximum;
        f.message = r.message + (failure.empty() ? "" : ": " + failure);
        return f;
    }
    if (r.corner) {
        // The maximum is the transition between the two sides: located by bisection.
        int changed = 0;
        for (std::size_t k = 0; k < lo.regimes.size(); ++k)
            if (lo.regimes[k] != hi.regimes[k]) {
                changed = static_cast<int>(k);
                break;
            }
        if (!bisect_regime(solver, p, changed, lo, w_lo, hi, w_hi, 1e-12)) {
            f.message = "a solve failed while locating the corner near w = " + format_number(r.omega);
            return f;
        }
        const bool low_side = lo.y >= hi.y;
        last = low_side ? lo : hi;
        f.corner = true;
        f.omega = low_side ? w_lo : w_hi;
    } else {
        f.omega = r.omega;
        f.curvature = r.curvature;
        f.corner = r.kink;
    }
    f.ok = true;
    f.value = last.y;
    f.regime = last.regime(0);
    f.state = last.state;
    f.outside = f.omega < wmin || f.omega > wmax;
    return f;
}

/// Contact `contact`'s boundary between the regimes below and above it near w0 at p.
Fix locate_boundary(ResponseSolver& solver, double p, double w0, double spread, const Eigen::VectorXd& start,
                    int contact, const std::string& below, const std::string& above, double wmin, double wmax) {
    Fix f;
    // The regime at the prediction says on which side the boundary lies; steps outward from it
    // (the first a tenth of the last step's change of w, growing 4 times) until the other
    // regime shows: the bracket [lo, hi] keeps the last two solves.
    ResponseSolver::Solution near = solver.at(p, w0, start);
    if (!near.ok) {
        f.message = "the solve at w = " + format_number(w0) + " failed: " + near.message;
        return f;
    }
    const std::string r0 = near.regime(contact);
    if (r0 != below && r0 != above) {
        f.no_feature = true;
        f.message = "the regime at w = " + format_number(w0) + " is " + r0 + ", neither " + below + " nor " + above;
        return f;
    }
    const bool up = r0 == below;  // the boundary lies above w0
    const std::string& wanted = up ? above : below;
    double d = std::clamp(0.1 * spread, 1e-6 * w0, 1e-3 * w0), w_near = w0, w_far = w0;
    ResponseSolver::Solution far;
    bool found = false;
    for (int it = 0; it < 12 && !found; ++it) {
        w_far = w0 + (up ? d : -d);
        far = solver.at(p, w_far, near.state);
        if (!far.ok) {
            f.message = "the solve at w = " + format_number(w_far) + " failed: " + far.message;
            return f;
        }
        if (far.regime(contact) == wanted) {
            found = true;
            break;
        }
        if (far.regime(contact) != r0) break;  // a third regime: another boundary came first
        near = far;
        w_near = w_far;
        d *= 4.0;
        if (d > 0.05 * w0) break;
    }
    f.iterations = 1;
    if (!found) {
        f.no_feature = true;
        f.message = "no " + below + "|" + above + " boundary of contact " + std::to_string(contact + 1) +
                    " within 5 % of w = " + format_number(w0);
        return f;
    }
    ResponseSolver::Solution lo = up ? near : far, hi = up ? far : near;
    double w_lo = up ? w_near : w_far, w_hi = up ? w_far : w_near;
    const System& system = solver.system(p);
    bool closed_form = false;
    if (solver.exact() && (below == "stick" || above == "stick")) {
        // From full stick: where the permanent-stick load crosses 1 (closed form), if every
        // contact sticks on the stuck side and contact `contact` is the one at its limit.
        const bool low_stuck = below == "stick";
        const ResponseSolver::Solution& stuck = low_stuck ? lo : hi;
        bool all = true;
        for (const std::string& r : stuck.regimes) all = all && r == "stick";
        double ws = low_stuck ? w_lo : w_hi, wx = low_stuck ? w_hi : w_lo;
        if (all && permanent_stick_load(system, ws) <= 1.0 && permanent_stick_load(system, wx) > 1.0) {
            for (int it = 0; it < 200 && std::abs(wx - ws) > 1e-13 * std::abs(wx); ++it) {
                const double mid = 0.5 * (ws + wx);
                (permanent_stick_load(system, mid) <= 1.0 ? ws : wx) = mid;
            }
            if (permanent_stick_load(system, ws, contact) >= (1.0 - 1e-9) * permanent_stick_load(system, ws)) {
                ResponseSolver::Solution s = solver.at(p, ws, stuck.state);
                if (s.ok && s.regime(contact) == "stick") {
                    (low_stuck ? lo : hi) = s;
                    (low_stuck ? w_lo : w_hi) = ws;
                    closed_form = true;
                }
            }
        }
    }
    if (!closed_form && !bisect_regime(solver, p, contact, lo, w_lo, hi, w_hi, solver.exact() ? 1e-12 : 1e-10)) {
        f.message = "a solve failed while bisecting the boundary near w = " + format_number(w0);
        return f;
    }
    // The point on the stick side of the boundary (stick, else stick-slip).
    const bool low_side = closed_form ? below == "stick" : (below == "stick" || (below == "stick-slip" && above == "slip"));
    const ResponseSolver::Solution& side = low_side ? lo : hi;
    f.ok = true;
    f.omega = low_side ? w_lo : w_hi;
    f.value = side.y;
    f.regime = side.regime(contact);
    f.state = side.state;
    f.outside = f.omega < wmin || f.omega > wmax;
    return f;
}

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

/// A frequency for a label: 4 significant digits.
std::string short_number(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
}

TrackPoint point_of(double p, const Fix& f, const std::string& kind) {
    TrackPoint t;
    t.p = p;
    t.omega = f.omega;
    t.value = f.value;
    t.kind = kind;
    t.regime = f.regime;
    t.curvature = f.curvature;
    t.corner = f.corner;
    t.state = f.state;
    return t;
}

}  // namespace

namespace {
/// track() with the FRFs at p_start and p_end when already computed (the optimizer's scan; with
/// the same settings and peaks): null computes them.
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
            if (q.kind == PointKind::transition && (options.contact < 0 || q.contact == options.contact))
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
    if (peaks) {
        const FrfResult end = known_end ? *known_end : compute_frf(system(options.p_end), frf);
        result.frfs += known_end ? 0 : 1;
        for (const Peak& k : end.peaks) {
            if (k.output != 0) continue;
            bool reached = false;
            for (const TrackCurve& c : result.curves)
                reached = reached || (c.status == TrackStatus::completed && !c.points.empty() &&
                                      std::abs(c.points.back().omega - k.omega) <= 1e-4 * k.omega);
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

}  // namespace

TrackResult track(const std::function<System(double)>& system, const FrfSettings& settings, const TrackOptions& options) {
    return track_with(system, settings, options, nullptr, nullptr);
}

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
