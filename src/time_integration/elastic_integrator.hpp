// hbfriction — internal: the event-driven flow of law elastic over one period (CVODE), used by
// the steady state of elastic_contacts.hpp and the periodic orbit of hbf/elastic_exact.hpp. Not
// installed.
//
// The modes, the sliders and the events are those of elastic_contacts.hpp. The state CVODE
// integrates is [y (N), y' (N), sliders (S), quadratures (2 N + 3)] and, when the flow's
// derivative is asked for (`variational`), the matrix Phi (c x c, c = 2 N + S, column-major) of
// the variational equation Phi' = J(x) Phi with Phi(0) = I, J the vector field's derivative in
// the contacts' current modes. At each event Phi jumps by the saltation matrix
//   Phi+ = D R Phi- + (f+ - D R f-) (grad g^T Phi-) / (grad g^T f-),
// g the root function that fell, f-/f+ the vector fields before and after the mode switch and R
// the switch's reset (a slider set to its node's displacement at an opening or a closing). Phi(T)
// is the period map's derivative, the monodromy, to the integrator's tolerance. With the
// variational part CVODE uses Adams with fixed-point iterations whatever the options say (a
// dense Newton matrix of c^2 states is out of reach); Phi's absolute tolerances are the state's
// scaled by the columns' units.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "numerics/cvode_solver.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::detail {

class ElasticIntegrator {
public:
    enum Mode : int { separated = 0, stuck = 1, slipping = 2 };

    /// The flow at omega; `scale` the displacement scale of the absolute tolerances.
    ElasticIntegrator(const System& system, double omega, const TimeIntegrationOptions& options, double scale,
                      bool variational = false);

    int state_size() const { return 2 * n_ + sliders_ + m_; }
    /// The continuous part of the state: y, y', the sliders.
    int continuous() const { return 2 * n_ + sliders_; }

    /// Makes a public state consistent at t = 0 (modes from N and the cone, sliders on it).
    void settle(Eigen::VectorXd& state);

    struct Record {
        bool ok = true;
        std::string failure;
        Eigen::VectorXd end;
        Eigen::MatrixXd monodromy;  ///< Phi(T) (variational only)
        std::vector<double> stuck_time, slip_time, open_time;
        Eigen::VectorXcd harmonic1;
        double energy = 0, viscous = 0, input = 0;
        int switches = 0;
        long steps = 0;  ///< CVODE steps
        std::vector<ExactEvent> events;  ///< the mode changes (modes as in the state: 0, 1, 2)
        // contact 1's stick indicator over the steps: |T| / (mu N) - 1 stuck, 0 slipping, 1 open
        double margin_min = 0, margin_max = 0;
        Eigen::VectorXd time;
        Eigen::MatrixXd displacement, velocity;
        Eigen::MatrixXd friction_force;  ///< samples x contacts: the first tangential component
    };

    /// One period from `start` (consistent); samples the motion when `samples` > 0. More than
    /// `max_steps` CVODE steps (0: options.max_steps_per_period) fail it.
    Record period(const Eigen::VectorXd& start, int samples, long max_steps = 0);

private:
    /// One contact: its directions and the element's parameters.
    struct Element {
        Eigen::MatrixXd tangential;  // N x d
        Eigen::VectorXd normal;      // N
        Eigen::MatrixXd minv_tangential;  // M^-1 W (variational)
        Eigen::VectorXd minv_normal;      // M^-1 n (variational)
        double kt = 0, kn = 0, mu = 0, offset = 0;  // offset: the normal force at v = 0
        int d = 1, first = 0;        // slider components; their first index in the slider block
    };
    /// The contact's quantities at state x (current mode): u, u', v, v', N, T, lambda.
    struct Local {
        Eigen::VectorXd u, du, T, s;
        Eigen::VectorXd direction;  // slipping: the slip direction t (empty where undefined)
        double v = 0, dv = 0, N = 0, lambda = 0, trial = 0;  // trial: |k_t (u - s)|
    };
    Local local(int c, const double* x) const;
    double indicator(int c, const double* x) const;
    void derivative(double t, const double* x, double* dx) const;
    /// Phi' = J Phi (the variational part of dx).
    void variational_derivative(const double* x, double* dx) const;
    void roots(const double* x, double* g) const;
    /// The gradient of contact c's root function (`normal`: its normal root, else its first)
    /// over the continuous state, in the current mode.
    Eigen::VectorXd root_gradient(int c, const double* x, bool normal) const;
    /// The mode after an event of contact c at x (`opening`: its normal root fell); returns
    /// 1 when the mode changed.
    int switch_mode(int c, double* x, bool opening);
    /// switch_mode with Phi's saltation (variational).
    int switch_with_saltation(int c, double t, double* x, bool opening);
    void settle_contact(int c, double* x);
    void reinit(double t);

    static int rhs_callback(sunrealtype t, N_Vector x, N_Vector dx, void* data);
    static int root_callback(sunrealtype, N_Vector x, sunrealtype* g, void* data);

    const System& system_;
    Eigen::VectorXd static_load_;  // F_s (zero without one)
    const double omega_, drive_, period_;
    const TimeIntegrationOptions options_;
    const int n_;
    const bool variational_;
    int m_ = 0, sliders_ = 0, quad_ = 0, length_ = 0, phi_ = 0;  // phi_: Phi's first entry
    Eigen::MatrixXd minv_, damping_, stiffness_;
    Eigen::MatrixXd minv_stiffness_, minv_damping_;  // variational
    std::vector<Element> elements_;
    std::vector<int> mode_;
    std::unique_ptr<CvodeSolver> cvode_;
    N_Vector absolute_ = nullptr, dky_ = nullptr;
};

/// The metrics of a recorded period in `out`: maxima (refined_max), first harmonics, outputs, contact regimes, energies and the kept
/// samples.
void elastic_metrics(const System& system, double omega, const ElasticIntegrator::Record& f,
                     const TimeIntegrationOptions& options, PeriodicResponse& out);

/// The state at rest for law elastic: the static state under the preloads (sliders where it
/// holds them, modes from it), or zero without a static load; settled by the caller.
Eigen::VectorXd elastic_rest_state(const System& system);

/// Law elastic's integration is refused up front (InvalidInput) for a system mixing law elastic
/// with other laws, massless DOFs, or more than elastic_max_dofs DOFs.
void check_elastic_system(const System& system);
constexpr int elastic_max_dofs = 2000;  // dense M^-1 and state

/// How elastic_orbit builds Newton's matrix and the multipliers: automatic (the variational
/// equation up to elastic_variational_max_states continuous states, central differences where
/// it is stiff; Newton-Krylov beyond), or one route forced (for tests and comparisons).
enum class ElasticRoute { automatic, variational, differences, krylov };

/// elastic_periodic_orbit (elastic_exact.hpp) by the given route.
ExactOrbit elastic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                         const ExactOptions& options, ElasticRoute route);

}  // namespace hbf::detail
