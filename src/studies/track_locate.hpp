// hbfriction — internal to studies: what tracking (tracking.cpp) and the optimiser by tracking
// (track_optimum.cpp) share: the periodic response at (w, p) from a start (event-exact or
// harmonic balance), and a peak or a stick-slip boundary located at fixed p.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/tracking.hpp"

namespace hbf::detail {

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
                   ResponseSolver::Solution& hi, double& w_hi, double tol);

/// The peak of Y(w) at p near w0 (peak_newton.hpp), or the stick/slip corner it sits on.
Fix locate_peak(ResponseSolver& solver, double p, double w0, const Eigen::VectorXd& start, double wmin, double wmax);

/// Contact `contact`'s boundary between the regimes below and above it near w0 at p.
Fix locate_boundary(ResponseSolver& solver, double p, double w0, double spread, const Eigen::VectorXd& start,
                    int contact, const std::string& below, const std::string& above, double wmin, double wmax);

/// A frequency for a label: 4 significant digits.
std::string short_number(double v);
/// The track point of a located feature.
TrackPoint point_of(double p, const Fix& f, const std::string& kind);
/// track() with the FRFs at p_start and p_end when already computed (the optimizer's scan; with
/// the same settings and peaks): null computes them.
TrackResult track_with(const std::function<System(double)>& system, const FrfSettings& settings,
                       const TrackOptions& options, const FrfResult* known_start, const FrfResult* known_end);

}  // namespace hbf::detail
