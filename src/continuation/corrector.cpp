// The Ceres corrector of the continuation and the branch tangent (corrector.hpp).
#include "hbf/corrector.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "base/enum_table.hpp"
#include "base/stopwatch.hpp"
#include "continuation/switch_hold.hpp"

namespace hbf {

constexpr detail::EnumName<TrustRegion> trust_region_names[] = {
    {TrustRegion::levenberg_marquardt, "levenberg_marquardt"}, {TrustRegion::dogleg, "dogleg"}};
constexpr detail::EnumName<DenseSolver> dense_solver_names[] = {
    {DenseSolver::qr, "qr"}, {DenseSolver::normal_cholesky, "normal_cholesky"}};
constexpr detail::EnumName<DenseLibrary> dense_library_names[] = {
    {DenseLibrary::eigen, "eigen"}, {DenseLibrary::lapack, "lapack"}};

std::string to_string(TrustRegion region) { return detail::enum_name(trust_region_names, region, "trust region"); }
std::string to_string(DenseSolver solver) { return detail::enum_name(dense_solver_names, solver, "dense solver"); }
std::string to_string(DenseLibrary library) { return detail::enum_name(dense_library_names, library, "dense library"); }
TrustRegion parse_trust_region(const std::string& name) {
    return detail::parse_enum(trust_region_names, name, "trust_region");
}
DenseSolver parse_dense_solver(const std::string& name) {
    return detail::parse_enum(dense_solver_names, name, "dense_solver");
}
DenseLibrary parse_dense_library(const std::string& name) {
    return detail::parse_enum(dense_library_names, name, "dense_library");
}

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
/// CorrectorOptions::stop, asked after every iteration, aborts the solve.
class ResidualTest final : public ceres::IterationCallback {
public:
    ResidualTest(double tolerance, std::function<std::string()> stop) : tolerance_(tolerance), stop_(std::move(stop)) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
        if (std::sqrt(2.0 * summary.cost) <= tolerance_) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
        return stop_ && !stop_().empty() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
    }

private:
    double tolerance_;
    std::function<std::string()> stop_;
};

/// The dense path: Ceres on the cost above.
struct CeresCorrector {
    std::vector<double> parameters;
    CorrectionCost cost;
    ceres::Problem problem;
    ceres::Solver::Options solver;
    ResidualTest residual_test;

    CeresCorrector(HarmonicBalance& hb, const CorrectorOptions& o)
        : parameters(static_cast<std::size_t>(hb.unknowns() + 1)), cost(hb, parameters.data()),
          problem(problem_options(&cost)), residual_test(o.tolerance, o.stop) {
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

/// The structured path: the last evaluation (x, omega, R, dR/domega and dR/dX in its
/// structure) and the preconditioner.
struct NewtonCorrector {
    StructuredJacobian jacobian;
    Eigen::VectorXd x, r, r_omega;
    double omega = 0;
    bool valid = false;
    std::unique_ptr<BlockPreconditioner> preconditioner;
    int last_krylov = 0;   // GMRES iterations of the last solve
    int fresh_krylov = -1;  // of the first solve after the last factorisation (-1: none yet)
    /// The next solve refactorises the preconditioner when the last one took more than twice the
    /// iterations it took fresh, and more than this many (measured on 100 nodes in 3D at H = 7:
    /// a factorisation costs about 25 GMRES iterations, fresh solves take 30 to 45).
    static constexpr int refresh_iterations = 40;

    void evaluate(HarmonicBalance& hb, const Eigen::VectorXd& at, double w) {
        if (valid && w == omega && at == x) return;
        x = at;
        omega = w;
        hb.evaluate(x, omega, r, jacobian, &r_omega);
        valid = true;
    }
    bool cached(const Eigen::VectorXd& at, double w) const { return valid && w == omega && at == x; }
    void refresh(CorrectorStatistics& statistics) {
        detail::Stopwatch watch;
        preconditioner = std::make_unique<BlockPreconditioner>(jacobian);
        ++statistics.factorizations;
        statistics.factorization_seconds += watch.lap();
        last_krylov = 0;
        fresh_krylov = -1;
    }
    /// Solves [A c; b^T d][u; mu] = [rhs; rho] with the current evaluation's A (refreshing
    /// the preconditioner when the last solve was slow or this one fails).
    bool solve(const Eigen::VectorXd& c, const Eigen::VectorXd& b, double d, const Eigen::VectorXd& rhs, double rho,
               Eigen::VectorXd& u, double& mu, double tolerance, CorrectorStatistics& statistics) {
        for (int attempt = 0; attempt < 2; ++attempt) {
            const bool slow = last_krylov > refresh_iterations && last_krylov > 2 * fresh_krylov;
            if (!preconditioner || slow || attempt > 0) refresh(statistics);
            detail::Stopwatch watch;
            const KrylovReport report = solve_bordered(jacobian, *preconditioner, c, b, d, rhs, rho, u, mu, tolerance);
            statistics.krylov_seconds += watch.lap();
            statistics.krylov_iterations += report.iterations;
            last_krylov = report.iterations;
            if (fresh_krylov < 0) fresh_krylov = report.iterations;
            if (report.converged) return true;
            if (!std::isfinite(report.residual)) return false;
        }
        return false;
    }
    /// The unit tangent of the evaluated point (branch_tangent's bordered system with its
    /// rows 1..n divided by S x_scale: [A, S^-1 dR/domega omega_scale / x_scale; previous^T]).
    Eigen::VectorXd tangent(double x_scale, const Eigen::VectorXd& previous, double omega_scale,
                            CorrectorStatistics& statistics) {
        const auto n = x.size();
        const Eigen::VectorXd c = r_omega.cwiseQuotient(jacobian.row_scale()) * (omega_scale / x_scale);
        Eigen::VectorXd u;
        double mu = 0;
        // To 1e-8 (fold detection reads the sign of its omega-component, away from zero except
        // at the fold itself, which locate_fold brackets). Where GMRES stops short the tangent is its best iterate: a predictor need
        // not be exact (the corrector and the turn test judge the step), but it must be finite.
        solve(c, previous.head(n), previous(n), Eigen::VectorXd::Zero(n), 1.0, u, mu, 1e-8, statistics);
        Eigen::VectorXd t(n + 1);
        t << u, mu;
        if (!t.allFinite() || !(t.norm() > 0.0))
            throw std::runtime_error("the branch tangent at w = " + format_number(omega) +
                                     ": the structured Jacobian's GMRES solve broke down");
        return t / t.norm();
    }
};
}  // namespace

struct Corrector::Impl {
    HarmonicBalance& hb;
    CorrectorOptions options;
    CorrectorStatistics statistics;
    std::unique_ptr<CeresCorrector> ceres;    // dense Jacobian
    std::unique_ptr<NewtonCorrector> newton;  // structured Jacobian

    Impl(HarmonicBalance& h, CorrectorOptions o) : hb(h), options(o) {
        if (h.structured())
            newton = std::make_unique<NewtonCorrector>();
        else
            ceres = std::make_unique<CeresCorrector>(h, o);
    }
    bool correct_newton(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                        int& iterations, double& residual, double omega_scale);
    /// One solve (Corrector::correct without the switches' handling).
    bool correct_once(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                      int& iterations, double& residual, double omega_scale);
    /// The corrector's acceptance of a residual max|R| / force_scale above the tolerance but
    /// within the evaluation's own rounding noise (Corrector::correct).
    bool noise_limited(const Eigen::VectorXd& x, double omega, double x_scale, double residual);
};

Corrector::Corrector(HarmonicBalance& hb, CorrectorOptions options) : impl_(std::make_unique<Impl>(hb, options)) {}
Corrector::~Corrector() = default;
const CorrectorStatistics& Corrector::statistics() const { return impl_->statistics; }

bool Corrector::cached_jacobian(const Eigen::VectorXd& x, double omega, Eigen::MatrixXd& jacobian,
                                Eigen::VectorXd& jacobian_omega) const {
    if (!impl_->ceres || !impl_->ceres->cost.cached(x, omega)) return false;
    jacobian = impl_->ceres->cost.jacobian();
    jacobian_omega = impl_->ceres->cost.jacobian_omega();
    return true;
}

Eigen::VectorXd Corrector::tangent(const Eigen::VectorXd& x, double omega, double x_scale,
                                   const Eigen::VectorXd& previous, double omega_scale) {
    Impl& m = *impl_;
    if (m.newton) {
        m.newton->evaluate(m.hb, x, omega);
        return m.newton->tangent(x_scale, previous, omega_scale, m.statistics);
    }
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd jacobian_omega;
    return cached_jacobian(x, omega, jacobian, jacobian_omega)
               ? branch_tangent(jacobian, jacobian_omega, x_scale, previous, omega_scale)
               : branch_tangent(m.hb, x, omega, x_scale, previous, omega_scale);
}

bool Corrector::Impl::noise_limited(const Eigen::VectorXd& x, double omega, double x_scale, double residual) {
    if (!(residual <= 1e3 * options.tolerance) || !(omega > 0.0)) return false;
    // Near a sharp resonance of a large, lightly damped model the condensed residual holds
    // Z_k^-1, computed to cond(Z_k) * rounding: it cannot fall below that noise. Measured by
    // moving omega by 16 ulp (minus the true change dR/domega * dw): a residual within 8
    // times the noise is converged as far as the evaluation can tell.
    // Likewise the unknowns themselves are resolved to a rounding of the scaled parameters,
    // eps x_scale: the residual cannot be resolved below |dR/dX| eps x_scale (row sums; a
    // stiff term such as LuGre's sigma1 z' with sigma1 = 1e11 makes it large, measured:
    // the absorber at --xi 1e12 stalled at 1.3 tolerance).
    const double dw = 16.0 * std::numeric_limits<double>::epsilon() * omega;
    Eigen::VectorXd r, moved, r_omega;
    double row_sum = 0;
    if (newton) {
        StructuredJacobian jacobian;
        hb.evaluate(x, omega, r, jacobian, &r_omega);
        row_sum = jacobian.abs_row_sums().maxCoeff();
    } else {
        Eigen::MatrixXd jacobian;
        hb.evaluate(x, omega, r, &jacobian, &r_omega);
        row_sum = jacobian.cwiseAbs().rowwise().sum().maxCoeff();
    }
    hb.evaluate(x, omega + dw, moved);
    const double resolution = std::numeric_limits<double>::epsilon() * x_scale * row_sum;
    const double noise = std::max((moved - r - r_omega * dw).cwiseAbs().maxCoeff(), resolution) / hb.force_scale();
    const bool accepted = std::isfinite(noise) && residual <= options.tolerance + 8.0 * noise;
    if (accepted) ++statistics.noise_limited;
    return accepted;
}

bool Corrector::Impl::correct_newton(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent,
                                     double x_scale, int& iterations, double& residual, double omega_scale) {
    NewtonCorrector& nm = *newton;
    const auto n = x.size();
    const double f = hb.force_scale();
    const Eigen::VectorXd tx = tangent.head(n);
    const double tw = tangent(n);
    const Eigen::VectorXd x0 = x;
    const double w0 = omega;
    // The arclength residual t . (p - p_predicted), p = (x / x_scale, omega / omega_scale).
    auto arclength = [&](const Eigen::VectorXd& at, double w) {
        return tx.dot(at - x0) / x_scale + tw * (w - w0) / omega_scale;
    };
    Eigen::VectorXd xk = x;
    double wk = omega;
    iterations = 0;
    residual = INFINITY;
    nm.evaluate(hb, xk, wk);
    auto merit = [&](const Eigen::VectorXd& r, double g) { return (r / f).squaredNorm() + g * g; };
    double g = arclength(xk, wk);
    double phi = merit(nm.r, g);
    Eigen::VectorXd u;
    for (;;) {
        if (!nm.r.allFinite()) return false;
        residual = nm.r.cwiseAbs().maxCoeff() / f;
        if (residual <= options.tolerance) break;
        if (iterations >= options.max_iterations) return noise_limited(xk, wk, x_scale, residual) && (x = xk, omega = wk, true);
        if (options.stop && !options.stop().empty()) return false;  // asked to stop: unconverged
        // Newton on [R; g] in (x, omega): rows 1..n divided by S, the last row times x_scale,
        // omega's step carried as mu = domega x_scale / omega_scale (a displacement, like x).
        const Eigen::VectorXd& s = nm.jacobian.row_scale();
        const Eigen::VectorXd c = nm.r_omega.cwiseQuotient(s) * (omega_scale / x_scale);
        double mu = 0;
        // Inexact Newton: the step to 1e-6 relative (each step then gains at least six digits;
        // the residual test above decides convergence, not the linear solve).
        if (!nm.solve(c, tx, tw, -nm.r.cwiseQuotient(s), -g * x_scale, u, mu, 1e-6, statistics)) return false;
        ++iterations;
        const double dw = mu * omega_scale / x_scale;
        // Backtracking on the merit |R / f|^2 + g^2 (Armijo with a small slope).
        bool moved = false;
        for (double lambda = 1.0; lambda >= 1.0 / 64.0; lambda *= 0.5) {
            const Eigen::VectorXd xt = xk + lambda * u;
            const double wt = wk + lambda * dw;
            if (!(wt > 0.0)) continue;
            nm.evaluate(hb, xt, wt);
            if (!nm.r.allFinite()) continue;
            const double gt = arclength(xt, wt), phit = merit(nm.r, gt);
            if (phit <= (1.0 - 1e-4 * lambda) * phi) {
                xk = xt;
                wk = wt;
                g = gt;
                phi = phit;
                moved = true;
                break;
            }
        }
        if (!moved) return false;
    }
    x = xk;
    omega = wk;
    return true;
}

bool Corrector::correct(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                        int& iterations, double& residual, double omega_scale) {
    Impl& m = *impl_;
    // Laws with a switch between residual forms (FrictionModel::hold_switch) hold it for each
    // solve: the form the predictor is in, then the form each solution is in, at most three
    // solves; a solution counts where the residual with the switch free passes the test.
    const bool switches = m.hb.hold_switches(false);
    if (!switches) return m.correct_once(x, omega, tangent, x_scale, iterations, residual, omega_scale);
    iterations = 0;
    Eigen::VectorXd decided_at;
    double decided_omega = 0.0;
    for (int attempt = 0; attempt < 3; ++attempt) {
        Eigen::VectorXd xs = x, r;
        double ws = omega;
        int it = 0;
        bool solved = false;
        {
            const detail::SwitchHold hold(m.hb);  // freed on leaving, by an exception too
            if (attempt > 0) m.hb.evaluate(decided_at, decided_omega, r);  // the first evaluation decides
            if (m.newton) m.newton->valid = false;
            solved = m.correct_once(xs, ws, tangent, x_scale, it, residual, omega_scale);
        }
        iterations += it;
        if (!solved) return false;
        m.hb.evaluate(xs, ws, r);
        residual = r.allFinite() ? r.cwiseAbs().maxCoeff() / m.hb.force_scale() : INFINITY;
        if (residual <= m.options.tolerance || m.noise_limited(xs, ws, x_scale, residual)) {
            x = xs;
            omega = ws;
            return true;
        }
        decided_at = xs;
        decided_omega = ws;
    }
    return false;
}

bool Corrector::Impl::correct_once(Eigen::VectorXd& x, double& omega, const Eigen::VectorXd& tangent, double x_scale,
                                   int& iterations, double& residual, double omega_scale) {
    Impl& m = *this;
    if (m.newton) {
        const double evaluated_before = evaluation_seconds(m.hb.statistics());
        detail::Stopwatch watch;
        const bool ok = m.correct_newton(x, omega, tangent, x_scale, iterations, residual, omega_scale);
        m.statistics.seconds += watch.lap();
        m.statistics.evaluation_seconds += evaluation_seconds(m.hb.statistics()) - evaluated_before;
        ++m.statistics.solves;
        m.statistics.iterations += iterations;
        return ok;
    }
    CeresCorrector& c = *m.ceres;
    const int n = m.hb.unknowns();
    Eigen::Map<Eigen::VectorXd> p(c.parameters.data(), n + 1);
    p.head(n) = x / x_scale;
    p(n) = omega / omega_scale;
    c.cost.set_target(tangent, p, x_scale, omega_scale);
    ceres::Solver::Summary summary;
    const double evaluated_before = evaluation_seconds(m.hb.statistics());
    detail::Stopwatch watch;
    ceres::Solve(c.solver, &c.problem, &summary);
    m.statistics.seconds += watch.lap();
    m.statistics.evaluation_seconds += evaluation_seconds(m.hb.statistics()) - evaluated_before;
    // summary.iterations[0] is the starting point, not a step.
    iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    ++m.statistics.solves;
    m.statistics.iterations += iterations;
    const Eigen::VectorXd x_new = p.head(n) * x_scale;
    const double omega_new = p(n) * omega_scale;
    Eigen::VectorXd r;
    if (c.cost.cached(x_new, omega_new))
        r = c.cost.residual();
    else
        m.hb.evaluate(x_new, omega_new, r);
    residual = r.allFinite() ? r.cwiseAbs().maxCoeff() / m.hb.force_scale() : INFINITY;
    const bool accepted = residual <= m.options.tolerance || m.noise_limited(x_new, omega_new, x_scale, residual);
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
    if (hb.structured()) {
        NewtonCorrector newton;
        CorrectorStatistics statistics;
        newton.evaluate(hb, x, omega);
        return newton.tangent(x_scale, previous, omega_scale, statistics);
    }
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
