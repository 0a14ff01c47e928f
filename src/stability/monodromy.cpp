// hbfriction — the monodromy of the variational equation by CVODE (monodromy.hpp).
#include "stability/monodromy.hpp"

#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>

#include "numerics/cvode_solver.hpp"
#include "hbf/error.hpp"

namespace hbf::detail {

namespace {

/// Phi(T) of ds' = A(t) ds by CVODE (BDF, exact Jacobian I (x) A), all d columns as one system
/// of d^2 states (one step sequence for the whole matrix). Small systems (d <= 12) solve its
/// Newton systems densely; larger ones by GMRES preconditioned with the exact inverse of one
/// block, (I - gamma A)^-1 applied to each column (one LU of d x d per Jacobian update instead
/// of one of d^2 x d^2: GMRES converges in an iteration or two, the preconditioner lagging
/// A(t) by at most CVODE's Jacobian age).
class MonodromyIntegrator {
public:
    MonodromyIntegrator(const Variational& v, double tolerance)
        : v_(v), d_(v.size()), cvode_(d_ * d_, CV_BDF, rhs, this, CvodeSolver::Warnings::drop) {
        cvode_.check(CVodeSStolerances(cvode_.memory(), tolerance, tolerance * 1e-2), "CVodeSStolerances");
        if (d_ <= dense_limit)
            cvode_.dense_newton(jacobian);
        else
            cvode_.gmres_newton(8, preconditioner_setup, preconditioner_solve, jacobian_times);
        cvode_.check(CVodeSetMaxNumSteps(cvode_.memory(), 200000), "CVodeSetMaxNumSteps");
    }
    MonodromyIntegrator(const MonodromyIntegrator&) = delete;
    MonodromyIntegrator& operator=(const MonodromyIntegrator&) = delete;

    /// False (and `failure`) when CVODE failed.
    bool run(Eigen::MatrixXd& phi, std::string& failure) {
        const double period = 2.0 * M_PI / v_.omega();
        N_Vector x = cvode_.state();
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(x), d_, d_).setIdentity();  // Phi(0) = I
        cvode_.check(CVodeReInit(cvode_.memory(), 0.0, x), "CVodeReInit");
        cvode_.check(CVodeSetStopTime(cvode_.memory(), period), "CVodeSetStopTime");
        sunrealtype t = 0.0;
        const int flag = CVode(cvode_.memory(), period, x, &t, CV_NORMAL);
        if (flag < 0) {
            failure = "CVODE failed on the variational equation (flag " + std::to_string(flag) + ") at t = " +
                      format_number(t) + " of T = " + format_number(period);
            return false;
        }
        phi = Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x), d_, d_);
        return true;
    }

private:
    static constexpr int dense_limit = 12;

    static int rhs(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(dx), self->d_, self->d_).noalias() =
            self->a_ * Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x), self->d_, self->d_);
        return 0;
    }
    static int jacobian(sunrealtype t, N_Vector, N_Vector, SUNMatrix j, void* data, N_Vector, N_Vector, N_Vector) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        SUNMatZero(j);
        const int d = self->d_;
        for (int b = 0; b < self->d_; ++b)  // I (x) A: one block of A per column of Phi
            for (int c = 0; c < d; ++c)
                Eigen::Map<Eigen::VectorXd>(SUNDenseMatrix_Column(j, b * d + c) + b * d, d) = self->a_.col(c);
        return 0;
    }

    static int preconditioner_setup(sunrealtype t, N_Vector, N_Vector, sunbooleantype, sunbooleantype* jcur,
                                    sunrealtype gamma, void* data) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_precondition_);
        self->lu_.compute(Eigen::MatrixXd::Identity(self->d_, self->d_) - gamma * self->a_precondition_);
        *jcur = SUNTRUE;
        return 0;
    }
    static int preconditioner_solve(sunrealtype, N_Vector, N_Vector, N_Vector r, N_Vector z, sunrealtype,
                                    sunrealtype, int, void* data) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(z), self->d_, self->d_) =
            self->lu_.solve(Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(r), self->d_, self->d_));
        return 0;
    }
    /// J v = (I (x) A(t)) v: A times v's columns.
    static int jacobian_times(N_Vector v, N_Vector jv, sunrealtype t, N_Vector, N_Vector, void* data, N_Vector) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_times_);
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(jv), self->d_, self->d_).noalias() =
            self->a_times_ * Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(v), self->d_, self->d_);
        return 0;
    }

    const Variational& v_;
    int d_;
    Eigen::MatrixXd a_, a_precondition_, a_times_;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
    CvodeSolver cvode_;
};

}  // namespace

bool integrate_monodromy(const Variational& v, double tolerance, Eigen::MatrixXd& phi, std::string& failure) {
    return MonodromyIntegrator(v, tolerance).run(phi, failure);
}

}  // namespace hbf::detail
