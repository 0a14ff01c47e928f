// The Ceres corrector of the continuation and the branch tangent (declared in continuation.hpp).
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hbf/continuation.hpp"
#include "stopwatch.hpp"

namespace hbf {

// ---- corrector --------------------------------------------------------------------------

namespace {
/// Residual [R(x, omega) / force_scale; t . (p - p_predicted)] of the scaled unknowns
/// p = (x / x_scale, omega / omega_scale), with its exact Jacobian (Ceres wants it row-major).
///
/// It is also the problem's EvaluationCallback: Ceres announces each evaluation point first
/// (and has written it into the parameter block), so one HarmonicBalance pass computes the
/// residual and the Jacobian together and caches them. Ceres evaluates a candidate step's
/// residual, then, when it accepts it, the Jacobian at the same point: that second request
/// costs nothing, and neither do the final residual check and the next tangent, which ask
/// for the converged point (see Corrector::cached_jacobian).
class CorrectionCost final : public ceres::CostFunction, public ceres::EvaluationCallback {
public:
    CorrectionCost(HarmonicBalance& hb, const double* parameters)
        : hb_(hb), n_(hb.unknowns()), parameters_(parameters) {
        set_num_residuals(n_ + 1);
        mutable_parameter_block_sizes()->push_back(n_ + 1);
    }
    void set_target(const Eigen::VectorXd& tangent, const Eigen::VectorXd& predicted, double x_scale,
                    double omega_scale) {
        tangent_ = tangent;
        predicted_ = predicted;
        x_scale_ = x_scale;
        omega_scale_ = omega_scale;
        valid_ = false;
    }
    void PrepareForEvaluation(bool, bool new_evaluation_point) override {
        if (valid_ && !new_evaluation_point) return;
        const Eigen::Map<const Eigen::VectorXd> p(parameters_, n_ + 1);
        x_ = p.head(n_) * x_scale_;
        omega_ = p(n_) * omega_scale_;
        hb_.evaluate(x_, omega_, r_, &j_, &j_omega_);
        valid_ = true;
    }
    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        if (!valid_ || !r_.allFinite()) return false;
        const Eigen::Map<const Eigen::VectorXd> p(parameters[0], n_ + 1);
        const double f = hb_.force_scale();
        Eigen::Map<Eigen::VectorXd> r(residuals, n_ + 1);
        r.head(n_) = r_ / f;
        r(n_) = tangent_.dot(p - predicted_);
        if (jacobians && jacobians[0]) {
            using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
            Eigen::Map<RowMajor> J(jacobians[0], n_ + 1, n_ + 1);
            J.topLeftCorner(n_, n_) = j_ * (x_scale_ / f);
            J.topRightCorner(n_, 1) = j_omega_ * (omega_scale_ / f);
            J.row(n_) = tangent_.transpose();
        }
        return true;
    }
    /// Whether the cached evaluation was made exactly at (x, omega).
    bool cached(const Eigen::VectorXd& x, double omega) const { return valid_ && omega == omega_ && x == x_; }
    const Eigen::VectorXd& residual() const { return r_; }
    const Eigen::MatrixXd& jacobian() const { return j_; }
    const Eigen::VectorXd& jacobian_omega() const { return j_omega_; }

private:
    HarmonicBalance& hb_;
    int n_;
    const double* parameters_;
    Eigen::VectorXd tangent_, predicted_;
    double x_scale_ = 1.0, omega_scale_ = 1.0;
    bool valid_ = false;
    Eigen::VectorXd x_, r_, j_omega_;
    double omega_ = 0.0;
    Eigen::MatrixXd j_;
};
double evaluation_seconds(const EvaluationStatistics& s) {
    return s.aft_seconds + s.jacobian_seconds + s.structure_seconds;
}

/// Ceres has no absolute residual test: stop as soon as |r|_2 = sqrt(2 cost) is below the
/// tolerance (which implies |r|_inf below it), instead of iterating on at round-off level.
class ResidualTest final : public ceres::IterationCallback {
public:
    explicit ResidualTest(double tolerance) : tolerance_(tolerance) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
        return std::sqrt(2.0 * summary.cost) <= tolerance_ ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                                           : ceres::SOLVER_CONTINUE;
    }

private:
    double tolerance_;
};
}  // namespace

struct Corrector::Impl {
    HarmonicBalance& hb;
    CorrectorOptions options;
    std::vector<double> parameters;
    CorrectionCost cost;
    ceres::Problem problem;
    ceres::Solver::Options solver;
    ResidualTest residual_test;
    CorrectorStatistics statistics;

    Impl(HarmonicBalance& h, CorrectorOptions o)
        : hb(h), options(o), parameters(static_cast<std::size_t>(h.unknowns() + 1)), cost(h, parameters.data()),
          problem(problem_options(&cost)), residual_test(o.tolerance) {
        problem.AddResidualBlock(&cost, nullptr, parameters.data());
        // Chosen by measurement (benchmarks/hb_branch, README): the dense normal-equations
        // Cholesky is twice as fast as QR at these sizes with identical results on a scan of
        // 84 parameter sets; Levenberg-Marquardt with a huge initial radius is Gauss-Newton
        // near the solution and still damps bad predictions (dogleg: same speed). Ceres'
        // tolerances are pushed to round-off because convergence is judged by our own
        // absolute residual test (ResidualTest, and the check after Solve).
        solver.linear_solver_type =
            o.dense_solver == DenseSolver::qr ? ceres::DENSE_QR : ceres::DENSE_NORMAL_CHOLESKY;
        solver.trust_region_strategy_type =
            o.trust_region == TrustRegion::dogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
        solver.dense_linear_algebra_library_type =
            o.dense_library == DenseLibrary::lapack ? ceres::LAPACK : ceres::EIGEN;
        solver.initial_trust_region_radius = 1e12;
        solver.max_num_iterations = o.max_iterations;
        solver.function_tolerance = 1e-20;
        solver.gradient_tolerance = 1e-30;
        solver.parameter_tolerance = 1e-15;
        solver.logging_type = ceres::SILENT;
        solver.minimizer_progress_to_stdout = false;
        solver.num_threads = 1;
        solver.callbacks.push_back(&residual_test);
    }
    static ceres::Problem::Options problem_options(CorrectionCost* cost) {
        ceres::Problem::Options p;
        p.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        p.evaluation_callback = cost;
        return p;
    }
};

Corrector::Corrector(HarmonicBalance& hb, CorrectorOptions options) : impl_(std::make_unique<Impl>(hb, options)) {}
Corrector::~Corrector() = default;
const CorrectorStatistics& Corrector::statistics() const { return impl_->statistics; }

bool Corrector::cached_jacobian(const Eigen::VectorXd& x, double omega, Eigen::MatrixXd& jacobian,
                                Eigen::VectorXd& jacobian_omega) const {
    if (!impl_->cost.cached(x, omega)) return false;
    jacobian = impl_->cost.jacobian();
    jacobian_omega = impl_->cost.jacobian_omega();
    return true;
}

bool Corrector::correct(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                        int& iterations, double& residual, double omega_scale) {
    Impl& m = *impl_;
    const int n = m.hb.unknowns();
    Eigen::Map<Eigen::VectorXd> p(m.parameters.data(), n + 1);
    p.head(n) = x / x_scale;
    p(n) = omega / omega_scale;
    m.cost.set_target(tangent, p, x_scale, omega_scale);
    ceres::Solver::Summary summary;
    const double evaluated_before = evaluation_seconds(m.hb.statistics());
    detail::Stopwatch watch;
    ceres::Solve(m.solver, &m.problem, &summary);
    m.statistics.seconds += watch.lap();
    m.statistics.evaluation_seconds += evaluation_seconds(m.hb.statistics()) - evaluated_before;
    // summary.iterations[0] is the starting point, not a step.
    iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    ++m.statistics.solves;
    m.statistics.iterations += iterations;
    const Eigen::VectorXd x_new = p.head(n) * x_scale;
    const double omega_new = p(n) * omega_scale;
    Eigen::VectorXd r;
    if (m.cost.cached(x_new, omega_new))
        r = m.cost.residual();
    else
        m.hb.evaluate(x_new, omega_new, r);
    residual = r.allFinite() ? r.cwiseAbs().maxCoeff() / m.hb.force_scale() : INFINITY;
    bool accepted = residual <= m.options.tolerance;
    if (!accepted && residual <= 1e3 * m.options.tolerance && omega_new > 0.0) {
        // Near a sharp resonance of a large, lightly damped model the condensed residual holds
        // Z_k^-1, computed to cond(Z_k) * rounding: it cannot fall below that noise. Measured by
        // moving omega by 16 ulp (minus the true change dR/domega * dw): a residual within 8
        // times the noise is converged as far as the evaluation can tell.
        // Likewise the unknowns themselves are resolved to a rounding of the scaled parameters,
        // eps x_scale: the residual cannot be resolved below |dR/dX| eps x_scale (row sums; a
        // stiff term such as LuGre's sigma1 z' with sigma1 = 1e11 makes it large, measured:
        // the absorber at --xi 1e12 stalled at 1.3 tolerance).
        const double dw = 16.0 * std::numeric_limits<double>::epsilon() * omega_new;
        Eigen::VectorXd moved, r_omega;
        Eigen::MatrixXd jacobian;
        m.hb.evaluate(x_new, omega_new, r, &jacobian, &r_omega);
        m.hb.evaluate(x_new, omega_new + dw, moved);
        const double resolution = std::numeric_limits<double>::epsilon() * x_scale *
                                  jacobian.cwiseAbs().rowwise().sum().maxCoeff();
        const double noise =
            std::max((moved - r - r_omega * dw).cwiseAbs().maxCoeff(), resolution) / m.hb.force_scale();
        accepted = std::isfinite(noise) && residual <= m.options.tolerance + 8.0 * noise;
        if (accepted) ++m.statistics.noise_limited;
    }
    if (!accepted || !(omega_new > 0.0)) return false;
    x = x_new;
    omega = omega_new;
    return true;
}

bool Corrector::solve_at(Eigen::VectorXd& x, double omega, double x_scale, int& iterations, double& residual) {
    Eigen::VectorXd tangent = Eigen::VectorXd::Zero(x.size() + 1);
    tangent(x.size()) = 1.0;
    double w = omega;
    return correct(x, w, tangent, x_scale, iterations, residual);
}

Eigen::VectorXd branch_tangent(HarmonicBalance& hb, const Eigen::VectorXd& x, double omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale) {
    Eigen::VectorXd r, r_omega;
    Eigen::MatrixXd J;
    hb.evaluate(x, omega, r, &J, &r_omega);
    return branch_tangent(J, r_omega, x_scale, previous, omega_scale);
}

Eigen::VectorXd branch_tangent(const Eigen::MatrixXd& J, const Eigen::VectorXd& r_omega, double x_scale,
                               const Eigen::VectorXd& previous, double omega_scale) {
    const auto n = J.rows();
    Eigen::MatrixXd A(n + 1, n + 1);
    A.topLeftCorner(n, n) = J * x_scale;
    A.topRightCorner(n, 1) = r_omega * omega_scale;
    A.row(n) = previous.transpose();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
    rhs(n) = 1.0;
    // The bordered matrix is regular also at folds (where dR/dX alone is singular).
    Eigen::VectorXd t = A.partialPivLu().solve(rhs);  // t . previous = 1 > 0: same orientation
    return t / t.norm();
}

}  // namespace hbf
