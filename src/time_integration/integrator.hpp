// hbfriction — internal: the CVODE integrator of one period (see time_integration.hpp for the
// model of each law, the events and the state convention). Not installed.
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "numerics/cvode_solver.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::detail {

/// A time-domain element (contact_law.hpp: time_elements) in the form the integrator evaluates:
/// a rigid slider (exact Coulomb), an elastic slider (Jenkins: a spring in series with a rigid
/// slider, its position the state) or a smooth law (its own time_force and time_margin).
/// The absolute tolerances of a state laid out as [y (n), y' (n), `internal` states, the
/// first-harmonic quadratures c1, s1 (n each), 3 energies]: a for y and the internal states, a
/// `drive` (h omega) for y', a `period` for the quadratures, `energy` for the energies;
/// `fallback` where one is not > 0 (a zero scale).
void set_absolute_tolerances(double* tol, int n, int internal, double a, double drive, double period, double energy,
                             double fallback);

struct ContactData {
    enum class Kind { smooth, rigid_slider, elastic_slider };
    Kind kind = Kind::smooth;
    const ContactLaw* law = nullptr;
    bool has_state = false;  // an internal state (bristle deflection, slider position)
    int a = 0, b = Contact::ground;
    double limit = 0;        // F_c
    double stiffness = 0;    // k_t of an elastic slider
    double base = 0;         // its spring's far end moves by base cos(h omega t) (Contact::base_motion)
    Eigen::VectorXd w;       // a general force direction (empty: the DOF pair a, b)
    Contact parameters;      // the law and its parameters (its direction left empty: w)
    std::shared_ptr<const BoundLaw> bound;  // smooth laws: the law bound to `parameters`
    // An element over several coordinates (BoundLaw::directions() > 1): its directions, N x m
    // (System::contact_directions); empty otherwise.
    Eigen::MatrixXd directions;

    explicit ContactData(const Contact& c)
        : kind(rigid_slider(c) ? Kind::rigid_slider : elastic_slider(c) ? Kind::elastic_slider : Kind::smooth),
          law(&contact_law(c.law)), has_state(law->time_state() != TimeState::none), a(c.dof), b(c.other_dof),
          limit(c.friction_limit), stiffness(c.stiffness), base(c.base_motion), w(c.direction), parameters(c) {
        parameters.direction.resize(0);
        if (kind == Kind::smooth) bound = law->bind(parameters);
    }
    bool rigid() const { return kind == Kind::rigid_slider; }
    bool elastic() const { return kind == Kind::elastic_slider; }
    /// Stick and slip are modes switched at events (the sliders), not a smooth law's margin.
    bool event_driven() const { return kind != Kind::smooth; }

    double relative(const double* y) const {
        if (w.size() > 0) return w.dot(Eigen::Map<const Eigen::VectorXd>(y, w.size()));
        return y[a] - (b == Contact::ground ? 0.0 : y[b]);
    }
};

/// Everything measured over one period.
struct PeriodRecord {
    bool ok = true;
    std::string failure;
    Eigen::VectorXd end_state;
    std::vector<double> y_max;
    std::vector<double> output_max;   // per options.outputs
    Eigen::VectorXcd harmonic1;
    std::vector<double> stick_time;   // per contact
    std::vector<bool> always_stuck;   // per contact: never left stick
    std::vector<bool> never_stuck;    // per contact: never in stick
    double margin_min = std::numeric_limits<double>::infinity();
    double margin_max = -std::numeric_limits<double>::infinity();
    int switches = 0;
    double energy = 0, viscous_energy = 0, input_energy = 0;
    Eigen::VectorXd time;
    Eigen::MatrixXd displacement, velocity, friction_force;
};

/// Integrates one period at a time; owns the CVODE memory (created once per frequency).
class Integrator {
public:
    /// `scale`: the displacement scale s of the absolute tolerances (TimeIntegrationOptions).
    Integrator(const System& system, double omega, const TimeIntegrationOptions& options, double scale);
    Integrator(const Integrator&) = delete;
    Integrator& operator=(const Integrator&) = delete;

    /// Makes a public state consistent (modes, projections) at t = 0.
    void settle_initial(Eigen::VectorXd& state);
    /// Integrates one period from `start` (public layout, already consistent).
    PeriodRecord period(const Eigen::VectorXd& start);

    long steps() const { return steps_; }
    long rhs_evaluations() const;

private:
    static int rhs_callback(sunrealtype t, N_Vector x, N_Vector dx, void* data);
    static int root_callback(sunrealtype t, N_Vector x, sunrealtype* g, void* data);
    static int preconditioner_setup(sunrealtype t, N_Vector x, N_Vector fx, sunbooleantype jok,
                                    sunbooleantype* jcur, sunrealtype gamma, void* data);
    static int preconditioner_solve(sunrealtype t, N_Vector x, N_Vector fx, N_Vector r, N_Vector z,
                                    sunrealtype gamma, sunrealtype delta, int lr, void* data);
    /// J v by a difference of right-hand sides with an increment from the unweighted norms
    /// (CVODE's own uses the error weights: where a stuck contact holds a velocity at 0 they
    /// are ~1/atol, and the increment drowns in rounding).
    static int jacobian_times(N_Vector v, N_Vector jv, sunrealtype t, N_Vector x, N_Vector fx, void* data,
                              N_Vector tmp);
    /// BDF on large models: factorises M + gamma C + gamma^2 K (see dense_newton_max_dofs).
    int setup_newton(double gamma);
    /// Solves the structural part of (I - gamma J) z = r (states y, y'), identity elsewhere.
    int solve_newton(const double* r, double* z);
    /// out = M^-1 in (dense inverse for small models, sparse LDL^T beyond).
    void apply_minv(const Eigen::Ref<const Eigen::MatrixXd>& in, Eigen::Ref<Eigen::MatrixXd> out) const;

    /// Forces f_ (all contacts, lambda for stuck coulomb), internal rates zdot_ and
    /// accelerations acc_ at (t, x) with the current modes.
    void evaluate(double t, const double* x);
    void derivative(double t, const double* x, double* dx);
    void roots(double t, const double* x, double* g);
    /// Rebuilds the stuck-set matrices of the coulomb contacts in mode 0.
    void rebuild_stuck_set();
    /// Projects y' so that the coulomb contacts in `set` have v_c = 0 exactly.
    void project_velocities(double* x, const std::vector<int>& set) const;
    /// Coulomb: releases the most overloaded stuck contacts until every |lambda| <= F_c.
    void settle_stuck_set(double t, double* x);
    /// Handles the mode events of the contacts in `hits` at (t, x); returns mode changes.
    int handle_events(double t, double* x, const std::vector<int>& hits);
    /// Stick indicator of contact c at the last evaluate(): > 0 in stick (root function of
    /// the smooth laws), and the margin of time_integration.hpp.
    bool in_stick(int c, const double* x) const;
    double margin(int c, const double* x) const;
    double mode_root(int c) const;
    void load(const Eigen::VectorXd& state);
    Eigen::VectorXd store() const;
    void reinit(double t);

    const System& system_;
    const double omega_, drive_, period_;  // drive_: the force's frequency h omega
    const double scale_;                   // displacement scale s (absolute tolerances)
    const TimeIntegrationOptions options_;
    const int n_, nc_, length_, quad_;
    std::vector<ContactData> contacts_;
    Eigen::MatrixXd minv_;               // M^-1 (small models)
    Eigen::SimplicialLDLT<SparseMatrix> mass_factor_;  // M = L D L^T (large models)
    bool sparse_ = false;                // large model: sparse M^-1 and the GMRES Newton solver
    // BDF Newton preconditioner of large models
    SparseMatrix newton_matrix_;         // M + gamma C + gamma^2 K
    Eigen::SparseLU<SparseMatrix> newton_lu_;
    bool newton_analysed_ = false, newton_ok_ = false;
    double newton_gamma_ = 0;
    int stuck_version_ = 0, bordered_version_ = -1;
    Eigen::MatrixXd newton_ws_;          // (M + gamma C + gamma^2 K)^-1 W_S
    Eigen::MatrixXd newton_border_;      // (W_S^T newton_ws_)^+
    Eigen::VectorXd newton_rhs_, newton_zv_;
    Eigen::VectorXd excitation_;
    std::vector<int> mode_;
    std::vector<int> stuck_;             // coulomb contacts in mode 0
    Eigen::MatrixXd ws_, minv_ws_, g_;   // W_S, M^-1 W_S, (W_S^T M^-1 W_S)^+
    std::vector<int> ground_stuck_dof_;  // per DOF: 1 if held to ground by a stuck contact
    std::vector<const Output*> combined_outputs_;  // options_.outputs that combine DOFs (own roots)
    // scratch of evaluate()
    Eigen::VectorXd f_, zdot_, acc_, load_, lambda_, velocity_c_;
    Eigen::VectorXd power_;  // each contact's force times its velocity (every direction's)
    mutable Eigen::VectorXd several_q_, several_v_, several_f_;  // an element over several coordinates
    // Per contact, at the last evaluate(): the base motion of an elastic slider's spring end
    // (displacement, velocity, acceleration); velocity_c_ includes its velocity.
    Eigen::VectorXd end_, end_rate_, end_acc_;

    CvodeSolver cvode_;                  // its state, solvers and the vectors below
    N_Vector dky_ = nullptr, absolute_ = nullptr;
    long steps_ = 0;
    long rhs_total_ = 0;  // right-hand side evaluations before the last CVodeReInit
    double margin_at_event_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace hbf::detail
