// hbfriction — the one CVODE wrapper (solver.hpp).
#include "numerics/cvode_solver.hpp"

#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <stdexcept>
#include <string>

#include "hbf/diagnostics.hpp"

namespace hbf::detail {

namespace {

/// CVODE's warnings (positive codes, e.g. t + h == t) are counted, not printed; its errors
/// come back as return flags, handled where they occur.
void record_warnings(int code, const char* module, const char* function, char* message, void*) {
    if (code > 0)
        detail::record_library_message("cvode", std::string(module ? module : "") + " " + (function ? function : "") +
                                                    ": " + (message ? message : ""));
}

/// Nothing printed, nothing counted.
void drop_messages(int, const char*, const char*, char*, void*) {}

}  // namespace

CvodeSolver::CvodeSolver(int length, int method, CVRhsFn rhs, void* user_data, Warnings warnings) {
    try {
        if (SUNContext_Create(nullptr, &context_) != 0) throw std::runtime_error("SUNContext_Create failed");
        x_ = N_VNew_Serial(length, context_);
        if (!x_) throw std::runtime_error("N_VNew_Serial failed");
        N_VConst(0.0, x_);
        cvode_ = CVodeCreate(method, context_);
        if (!cvode_) throw std::runtime_error("CVodeCreate failed");
        check(CVodeInit(cvode_, rhs, 0.0, x_), "CVodeInit");
        check(CVodeSetErrHandlerFn(cvode_, warnings == Warnings::record ? record_warnings : drop_messages, nullptr),
              "CVodeSetErrHandlerFn");
        check(CVodeSetUserData(cvode_, user_data), "CVodeSetUserData");
    } catch (...) {
        release();
        throw;
    }
}

CvodeSolver::~CvodeSolver() { release(); }

void CvodeSolver::release() {
    if (cvode_) CVodeFree(&cvode_);
    if (nonlinear_) SUNNonlinSolFree(nonlinear_);
    if (linear_) SUNLinSolFree(linear_);
    if (matrix_) SUNMatDestroy(matrix_);
    if (x_) N_VDestroy(x_);
    for (N_Vector v : vectors_) N_VDestroy(v);
    if (context_) SUNContext_Free(&context_);
    nonlinear_ = nullptr;
    linear_ = nullptr;
    matrix_ = nullptr;
    x_ = nullptr;
    vectors_.clear();
}

N_Vector CvodeSolver::vector() {
    N_Vector v = N_VClone(x_);
    if (!v) throw std::runtime_error("N_VClone failed");
    vectors_.push_back(v);
    return v;
}

void CvodeSolver::dense_newton(CVLsJacFn jacobian) {
    const auto length = N_VGetLength(x_);
    matrix_ = SUNDenseMatrix(length, length, context_);
    if (!matrix_) throw std::runtime_error("SUNDenseMatrix failed");
    linear_ = SUNLinSol_Dense(x_, matrix_, context_);
    if (!linear_) throw std::runtime_error("SUNLinSol_Dense failed");
    check(CVodeSetLinearSolver(cvode_, linear_, matrix_), "CVodeSetLinearSolver");
    if (jacobian) check(CVodeSetJacFn(cvode_, jacobian), "CVodeSetJacFn");
}

void CvodeSolver::gmres_newton(int krylov, CVLsPrecSetupFn setup, CVLsPrecSolveFn solve, CVLsJacTimesVecFn times) {
    linear_ = SUNLinSol_SPGMR(x_, SUN_PREC_LEFT, krylov, context_);
    if (!linear_) throw std::runtime_error("SUNLinSol_SPGMR failed");
    check(CVodeSetLinearSolver(cvode_, linear_, nullptr), "CVodeSetLinearSolver");
    check(CVodeSetPreconditioner(cvode_, setup, solve), "CVodeSetPreconditioner");
    check(CVodeSetJacTimes(cvode_, nullptr, times), "CVodeSetJacTimes");
}

void CvodeSolver::fixed_point() {
    nonlinear_ = SUNNonlinSol_FixedPoint(x_, 0, context_);
    if (!nonlinear_) throw std::runtime_error("SUNNonlinSol_FixedPoint failed");
    check(CVodeSetNonlinearSolver(cvode_, nonlinear_), "CVodeSetNonlinearSolver");
}

void CvodeSolver::check(int flag, const char* what) const {
    if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + CVodeGetReturnFlagName(flag));
}

}  // namespace hbf::detail
