// hbfriction — internal: the one CVODE wrapper of the library, used by time integration
// (time_integration/integrator.hpp) and by stability's monodromy (stability/monodromy.cpp). It
// owns a SUNDIALS context, the CVODE memory, the state vector, the vectors asked for and the
// solvers, and frees them together. CVODE never prints: its errors come back as return flags
// (handled where they occur), its warnings are counted by diagnostics.hpp or dropped.
#pragma once

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <vector>

namespace hbf::detail {

class CvodeSolver {
public:
    /// What becomes of CVODE's warnings (positive codes, e.g. t + h == t).
    enum class Warnings {
        record,  ///< counted as library messages (detail::record_library_message)
        drop,    ///< ignored
    };

    /// CVODE with the linear multistep method `method` (CV_BDF or CV_ADAMS) on `length` states,
    /// initialised at t = 0 with x = 0 and the right-hand side `rhs`; `user_data` is passed to
    /// every callback. Throws std::runtime_error when SUNDIALS fails.
    CvodeSolver(int length, int method, CVRhsFn rhs, void* user_data, Warnings warnings);
    ~CvodeSolver();
    CvodeSolver(const CvodeSolver&) = delete;
    CvodeSolver& operator=(const CvodeSolver&) = delete;

    /// The CVODE memory, for the CVode* calls.
    void* memory() const { return cvode_; }
    /// The state vector (given to CVodeInit, CVodeReInit and CVode).
    N_Vector state() const { return x_; }
    /// A new vector of the state's length (not initialised), freed with the solver.
    N_Vector vector();

    /// Newton iterations with a dense direct linear solver and the Jacobian `jacobian`
    /// (CVODE's difference quotients when null).
    void dense_newton(CVLsJacFn jacobian = nullptr);
    /// Newton iterations with GMRES (Krylov dimension `krylov`) preconditioned on the left by
    /// `setup` and `solve`, with the Jacobian-vector product `times`.
    void gmres_newton(int krylov, CVLsPrecSetupFn setup, CVLsPrecSolveFn solve, CVLsJacTimesVecFn times);
    /// Fixed-point (functional) iterations, without a linear solver (for Adams).
    void fixed_point();

    /// Throws std::runtime_error naming the call `what` and CVODE's flag when flag < 0.
    void check(int flag, const char* what) const;

private:
    void release();

    SUNContext context_ = nullptr;
    void* cvode_ = nullptr;
    N_Vector x_ = nullptr;
    std::vector<N_Vector> vectors_;
    SUNMatrix matrix_ = nullptr;
    SUNLinearSolver linear_ = nullptr;
    SUNNonlinearSolver nonlinear_ = nullptr;
};

}  // namespace hbf::detail
