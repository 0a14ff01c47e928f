// hbfriction — internal to event_exact: what one recorded period of an orbit reports (maxima,
// first harmonics, energies, regime, events, samples) and the mean contact forces.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "event_exact/engine.hpp"
#include "hbf/event_exact.hpp"

namespace hbf::detail::exact {

/// Mean friction force of every contact over one recorded period (Gauss-Legendre per step).
Eigen::VectorXd mean_forces(Engine& e, const Engine::Flow& flow);
/// Energy every contact dissipates over one recorded period: over its slip steps, F_c times
/// the travel of its slider (an elastic slider's: its spring's far end).
Eigen::VectorXd slip_work(Engine& e, const Engine::Flow& flow);

/// The largest |y(t)| of signals over recorded steps, each kept in the caller's `best`: the
/// turning points of each step's polynomial between 16 samples, refined by Newton on the slope.
/// A step with fast exponentials is first bounded (the polynomial part's largest |value| plus
/// the exponentials' largest sizes); the signal's values there raise the best so far, and the
/// fine sampling is deferred to finish(), done only if the bound still exceeds the best once
/// every step has been seen (the maximum is the same; most steps are never sampled finely).
class Maxima {
public:
    /// Takes y over step st into best (which must outlive finish()).
    void add(const Step& st, const Signal& y, double& best);
    /// The deferred steps: samples resolving every exponential above rounding of |y|.
    void finish();

private:
    struct Deferred {
        Signal y;
        double s_end, bound;
        double* best;
    };
    std::vector<Deferred> deferred_;
};

/// The events of one recorded period (absolute times) into out.events: times in [0, T), by
/// time; out.switches their count.
void period_events(const std::vector<ExactEvent>& events, double period, ExactOrbit& out);

/// Linear functions p(t) = L zhat(t) of the flow beyond the DOFs (the massless DOFs of a
/// condensed system, and outputs on them): rows L over zhat, and what fill_metrics finds.
struct Probes {
    Eigen::MatrixXd rows;            ///< n_p x n
    std::vector<double> max;         ///< max over the period of |p(t)| (turning points refined)
    Eigen::Index first_max = 0;      ///< rows before it get no maximum (NaN): DOFs not asked for
    Eigen::VectorXd c1, s1;          ///< first harmonic: p ~ c1 cos + s1 sin
    Eigen::VectorXd value, rate;     ///< p and p' at t = 0
    Eigen::MatrixXd samples, sample_rates;  ///< options.samples x n_p
};

/// Fills the orbit's metrics from one recorded period [t_s, t_s + T], and `probes`' if given
/// (then not the DOFs' maxima y_max: the probes' rows include them).
void fill_metrics(Engine& e, const Engine::Flow& flow, double t_s, const ExactOptions& options, ExactOrbit& out,
                  Probes* probes = nullptr);

/// Where the orbit's largest multiplier is within its multipliers' accuracy of 1
/// (ExactOrbit::stability_unresolved), says so in its message.
void note_unresolved_stability(ExactOrbit& out);

}  // namespace hbf::detail::exact
