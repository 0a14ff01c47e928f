// hbfriction — the monodromy of the variational equation by CVODE (monodromy.hpp).
#include "monodromy.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <stdexcept>

#include "hbf/error.hpp"

namespace hbf::detail {

namespace {

void quiet_handler(int, const char*, const char*, char*, void*) {}

/// Phi(T) of ds' = A(t) ds by CVODE (BDF, dense, exact Jacobian). Small systems (d <= 12)
/// integrate Phi' = A Phi as one system of d^2 states (one step sequence; Jacobian I (x) A),
/// larger ones one column at a time (d LU factorisations of d x d instead of one of d^2).
class MonodromyIntegrator {
public:
    MonodromyIntegrator(const Variational& v, double tolerance)
        : v_(v), d_(v.size()), columns_(v.size() <= 12 ? v.size() : 1), length_(d_ * columns_) {
        if (SUNContext_Create(nullptr, &context_) != 0) throw std::runtime_error("SUNContext_Create failed");
        x_ = N_VNew_Serial(length_, context_);
        matrix_ = SUNDenseMatrix(length_, length_, context_);
        linear_ = SUNLinSol_Dense(x_, matrix_, context_);
        cvode_ = CVodeCreate(CV_BDF, context_);
        if (!x_ || !matrix_ || !linear_ || !cvode_) throw std::runtime_error("CVODE allocation failed");
        N_VConst(0.0, x_);
        check(CVodeInit(cvode_, rhs, 0.0, x_), "CVodeInit");
        check(CVodeSetErrHandlerFn(cvode_, quiet_handler, nullptr), "CVodeSetErrHandlerFn");
        check(CVodeSetUserData(cvode_, this), "CVodeSetUserData");
        check(CVodeSStolerances(cvode_, tolerance, tolerance * 1e-2), "CVodeSStolerances");
        check(CVodeSetLinearSolver(cvode_, linear_, matrix_), "CVodeSetLinearSolver");
        check(CVodeSetJacFn(cvode_, jacobian), "CVodeSetJacFn");
        check(CVodeSetMaxNumSteps(cvode_, 200000), "CVodeSetMaxNumSteps");
    }
    ~MonodromyIntegrator() {
        if (cvode_) CVodeFree(&cvode_);
        if (linear_) SUNLinSolFree(linear_);
        if (matrix_) SUNMatDestroy(matrix_);
        if (x_) N_VDestroy(x_);
        if (context_) SUNContext_Free(&context_);
    }
    MonodromyIntegrator(const MonodromyIntegrator&) = delete;
    MonodromyIntegrator& operator=(const MonodromyIntegrator&) = delete;

    /// False (and `failure`) when CVODE failed.
    bool run(Eigen::MatrixXd& phi, std::string& failure) {
        const double period = 2.0 * M_PI / v_.omega();
        phi.resize(d_, d_);
        for (int first = 0; first < d_; first += columns_) {
            N_VConst(0.0, x_);
            Eigen::Map<Eigen::MatrixXd> start(N_VGetArrayPointer(x_), d_, columns_);
            for (int j = 0; j < columns_; ++j) start(first + j, j) = 1.0;
            check(CVodeReInit(cvode_, 0.0, x_), "CVodeReInit");
            check(CVodeSetStopTime(cvode_, period), "CVodeSetStopTime");
            sunrealtype t = 0.0;
            const int flag = CVode(cvode_, period, x_, &t, CV_NORMAL);
            if (flag < 0) {
                failure = "CVODE failed on the variational equation (flag " + std::to_string(flag) + ") at t = " +
                          format_number(t) + " of T = " + format_number(period);
                return false;
            }
            phi.middleCols(first, columns_) = Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x_), d_, columns_);
        }
        return true;
    }

private:
    static int rhs(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(dx), self->d_, self->columns_).noalias() =
            self->a_ * Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x), self->d_, self->columns_);
        return 0;
    }
    static int jacobian(sunrealtype t, N_Vector, N_Vector, SUNMatrix j, void* data, N_Vector, N_Vector, N_Vector) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        SUNMatZero(j);
        const int d = self->d_;
        for (int b = 0; b < self->columns_; ++b)  // I (x) A: one block of A per column of Phi
            for (int c = 0; c < d; ++c)
                Eigen::Map<Eigen::VectorXd>(SUNDenseMatrix_Column(j, b * d + c) + b * d, d) = self->a_.col(c);
        return 0;
    }
    void check(int flag, const char* what) const {
        if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed (flag " + std::to_string(flag) + ")");
    }

    const Variational& v_;
    int d_, columns_, length_;
    Eigen::MatrixXd a_;
    SUNContext context_ = nullptr;
    N_Vector x_ = nullptr;
    SUNMatrix matrix_ = nullptr;
    SUNLinearSolver linear_ = nullptr;
    void* cvode_ = nullptr;
};

}  // namespace

bool integrate_monodromy(const Variational& v, double tolerance, Eigen::MatrixXd& phi, std::string& failure) {
    return MonodromyIntegrator(v, tolerance).run(phi, failure);
}

}  // namespace hbf::detail
