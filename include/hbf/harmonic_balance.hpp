// hbfriction — the harmonic-balance residual R(X, omega) and its Jacobians.
//
// Unknowns X: the coefficients (fourier.hpp layout, 2H+1 each) of every DOF y_i, then of the
// internal state z_c of every state-law contact. With Y the (2H+1) x N matrix whose column i
// holds the coefficients of y_i, D = omega D1 the derivative with respect to tau, the
// structure's rows are (M, C, K symmetric)
//
//     R_Y = D^2 Y M + D Y C + Y K + sum_c f_c w_c^T - e_cos1 F^T,
//
// i.e. the Galerkin projection of M y'' + C y' + K y + sum_c w_c f_c - F cos(omega tau) on
// 1, cos k theta, sin k theta; f_c are the friction force coefficients of contact c computed
// from q_c = Y w_c (and z_c) by the AFT (friction.hpp), and each state-law contact adds its
// state residual r_z. Both Jacobians are exact (no finite differences).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "hbf/fourier.hpp"
#include "hbf/friction.hpp"
#include "hbf/model.hpp"

namespace hbf {

struct HarmonicBalanceOptions {
    int harmonics = 10;    ///< H >= 1: harmonics 0..H are balanced
    int time_samples = 0;  ///< N_t > 2H; 0 chooses Fourier::default_time_samples(H)
};

/// Work counters of HarmonicBalance::evaluate, for benchmarks and summaries.
struct EvaluationStatistics {
    long long residuals = 0;        ///< calls of evaluate
    long long jacobians = 0;        ///< of them, calls that asked for dR/dX
    double aft_seconds = 0;         ///< AFT: transforms and friction laws on the time samples
    double jacobian_seconds = 0;    ///< chain rule through the AFT and assembly of dR/dX, dR/domega
    double structure_seconds = 0;   ///< the linear structure's part of the residual
};
/// The work done between two snapshots of the counters.
EvaluationStatistics operator-(const EvaluationStatistics& later, const EvaluationStatistics& earlier);

class HarmonicBalance {
public:
    /// Validates the system; throws InvalidInput for bad options or an unsupported law.
    HarmonicBalance(System system, HarmonicBalanceOptions options);

    const System& system() const { return system_; }
    int harmonics() const { return fourier_.harmonics(); }
    int time_samples() const { return fourier_.time_samples(); }
    int coefficients() const { return fourier_.size(); }  ///< 2H + 1
    int unknowns() const { return unknowns_; }
    Fourier& fourier() { return fourier_; }

    /// R(X, omega); with non-null pointers also dR/dX (unknowns x unknowns) and dR/domega.
    void evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& residual,
                  Eigen::MatrixXd* jacobian = nullptr, Eigen::VectorXd* jacobian_omega = nullptr);

    /// Coefficients of DOF i (0-based), of the relative displacement q_c of contact c, and of
    /// its internal state (empty for memoryless laws).
    Eigen::VectorXd dof(const Eigen::VectorXd& x, int i) const;
    Eigen::VectorXd relative(const Eigen::VectorXd& x, int contact) const;
    Eigen::VectorXd state(const Eigen::VectorXd& x, int contact) const;
    /// Friction force samples of contact c on the AFT time grid.
    Eigen::VectorXd force_samples(const Eigen::VectorXd& x, double omega, int contact);
    /// Stick indicator of contact c on the AFT time grid (sticks where < 0; friction.hpp).
    Eigen::VectorXd stick_indicator(const Eigen::VectorXd& x, double omega, int contact);

    /// A starting point at omega: the linear response with each Dahl/LuGre contact replaced by
    /// its pre-sliding spring and damper (z = q), each Jenkins contact by its spring k_t, each regularised Coulomb contact by its
    /// slope at zero velocity (a damper F_c / eps), and each exact Coulomb contact held rigid
    /// (q = 0; its force is the constraint's multiplier: the exact permanent-stick solution).
    /// With `sliding`, the slipping limit instead: every contact removed (friction forces
    /// start at their limit, in phase with the relative velocity).
    Eigen::VectorXd linear_guess(double omega, bool sliding = false) const;
    /// Force scale against which residuals are judged: the excitation amplitude |F|_inf.
    double force_scale() const { return force_scale_; }

    /// Counters accumulated since construction or the last reset_statistics().
    const EvaluationStatistics& statistics() const { return statistics_; }
    void reset_statistics() { statistics_ = EvaluationStatistics{}; }

private:
    System system_;
    Fourier fourier_;
    std::vector<std::unique_ptr<FrictionModel>> models_;
    std::vector<int> state_offset_;  // start of each contact's state block, -1 if none
    std::vector<Eigen::VectorXd> directions_;
    int unknowns_ = 0;
    double force_scale_ = 1.0;
    FrictionEvaluation scratch_;
    EvaluationStatistics statistics_;
};

}  // namespace hbf
