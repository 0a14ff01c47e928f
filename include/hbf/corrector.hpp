// hbfriction — the corrector of the continuation (Ceres) and the branch tangent.
//
// The corrector solves the square system
//     R(X, omega) / force_scale = 0,   t . (u - u_predicted) = 0
// with Ceres (Levenberg-Marquardt, dense normal Cholesky, analytic Jacobian; see README). A point is accepted only when
// |R|_inf / force_scale <= tolerance — checked by us, since Ceres has no absolute test — or,
// within 1000 times the tolerance, when the residual is within 8 times its own rounding noise
// (measured by moving omega by 16 ulp; the condensed residual near a sharp resonance of a
// large model carries cond(Z_k) times the rounding): counted in noise_limited.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <string>

#include "hbf/harmonic_balance.hpp"

namespace hbf {

/// Ceres configurations of the corrector (measured in benchmarks/hb_branch; see README).
enum class TrustRegion { levenberg_marquardt, dogleg };
enum class DenseSolver { qr, normal_cholesky };
enum class DenseLibrary { eigen, lapack };
/// "levenberg_marquardt", "dogleg"; "qr", "normal_cholesky"; "eigen", "lapack" (Python's option
/// values). The parsers throw InvalidInput naming the allowed values.
std::string to_string(TrustRegion region);
std::string to_string(DenseSolver solver);
std::string to_string(DenseLibrary library);
TrustRegion parse_trust_region(const std::string& name);
DenseSolver parse_dense_solver(const std::string& name);
DenseLibrary parse_dense_library(const std::string& name);

struct CorrectorOptions {
    int max_iterations = 20;  ///< Ceres iterations per correction
    /// Accept when |R|_inf <= tolerance * force_scale; smallest_tolerance..largest_tolerance
    /// (below 1e-14 the residual's rounding noise decides; above 1e-2 a point is not a solution).
    double tolerance = 1e-9;
    static constexpr double smallest_tolerance = 1e-14, largest_tolerance = 1e-2;
    TrustRegion trust_region = TrustRegion::levenberg_marquardt;  ///< Ceres trust-region strategy
    DenseSolver dense_solver = DenseSolver::normal_cholesky;                 ///< Ceres dense linear solver
    DenseLibrary dense_library = DenseLibrary::eigen;            ///< Ceres dense linear algebra
    /// Asked after each iteration (Ceres) or before each Newton step (structured): a non-empty
    /// answer ends the correction unconverged, so that an interrupt or a time limit is heard
    /// within one iteration (a correction with many unknowns can take minutes). Empty: never
    /// asked. The continuation sets it to ContinuationOptions::stop.
    std::function<std::string()> stop;
};

/// Work counters of a Corrector.
struct CorrectorStatistics {
    long long solves = 0;           ///< Ceres Solve calls (corrections, including failed ones)
    long long iterations = 0;       ///< Ceres iterations (successful and unsuccessful steps)
    double seconds = 0;             ///< wall time inside Ceres' Solve, evaluations included
    double evaluation_seconds = 0;  ///< of which in HarmonicBalance::evaluate
    long long noise_limited = 0;    ///< corrections accepted above the tolerance but within 8
                                    ///< times the residual's own rounding noise (Corrector::correct)
    // The structured Jacobian (HarmonicBalance::structured()): Newton steps by GMRES instead of Ceres.
    long long krylov_iterations = 0;   ///< GMRES products with I + Gr Df (corrections and tangents)
    long long factorizations = 0;      ///< preconditioner factorisations (H + 1 complex LUs each)
    double factorization_seconds = 0;  ///< their time
    double krylov_seconds = 0;         ///< time in GMRES (products and preconditioner solves)
};

/// Corrects u = (x, omega) onto R = 0: with Ceres (dense Jacobian; keeps the Ceres problem
/// between calls), or with the structured Jacobian (HarmonicBalance::structured()) by Newton
/// steps solved by preconditioned GMRES (structured_jacobian.hpp) with a backtracking line
/// search on |R|^2 + (arclength residual)^2, the preconditioner kept between steps and
/// corrections while GMRES converges in few iterations.
class Corrector {
public:
    Corrector(HarmonicBalance& hb, CorrectorOptions options);
    ~Corrector();
    Corrector(const Corrector&) = delete;
    Corrector& operator=(const Corrector&) = delete;
    /// Solves R(x, omega) = 0 together with tangent . (scaled(u) - scaled(u_predicted)) = 0,
    /// scaled(u) = (x / x_scale, omega / omega_scale). `x` and `omega` hold the prediction on
    /// entry and the result on exit. Returns whether the residual tolerance was met;
    /// iterations and residual are reported.
    bool correct(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                 int& iterations, double& residual, double omega_scale = 1.0);
    /// Solves at fixed omega (tangent = e_omega).
    bool solve_at(Eigen::VectorXd& x, double omega, double x_scale, int& iterations, double& residual);
    /// Counters accumulated over all calls.
    const CorrectorStatistics& statistics() const;
    /// dR/dX and dR/domega at (x, omega) if the last evaluation was made exactly there (as
    /// after a successful correction) and the Jacobian is dense; false otherwise.
    bool cached_jacobian(const Eigen::VectorXd& x, double omega, Eigen::MatrixXd& jacobian,
                         Eigen::VectorXd& jacobian_omega) const;
    /// branch_tangent at (x, omega), from the last evaluation when it was made there (dense or
    /// structured Jacobian; the structured one by GMRES with the corrector's preconditioner).
    Eigen::VectorXd tangent(const Eigen::VectorXd& x, double omega, double x_scale, const Eigen::VectorXd& previous,
                            double omega_scale = 1.0);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Unit tangent of the branch R(x, omega) = 0 at a solution, in the scaled coordinates
/// (x / x_scale, omega / omega_scale): the null vector of [dR/dX x_scale, dR/domega
/// omega_scale], oriented so that its dot product with `previous` (any vector of size
/// unknowns + 1 not orthogonal to it) is > 0.
Eigen::VectorXd branch_tangent(HarmonicBalance& hb, const Eigen::VectorXd& x, double omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale = 1.0);

/// The same from given dR/dX (J) and dR/domega (r_omega) at the point.
Eigen::VectorXd branch_tangent(const Eigen::MatrixXd& J, const Eigen::VectorXd& r_omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale = 1.0);

}  // namespace hbf
