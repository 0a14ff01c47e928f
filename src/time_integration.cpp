// Periodic steady state by time integration with CVODE (see time_integration.hpp for the
// model of each law, the events and the state convention).
#include "hbf/time_integration.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hbf/error.hpp"
#include "hbf/friction.hpp"
#include "stopwatch.hpp"

namespace hbf {

std::string to_string(IntegrationMethod method) {
    return method == IntegrationMethod::adams ? "adams" : "bdf";
}

void TimeIntegrationOptions::validate() const {
    auto in_range = [](double value, double low, double high, const char* name, const char* meaning) {
        if (!(value >= low && value <= high))
            throw InvalidInput(std::string(name) + " (" + meaning + ") = " + format_number(value) +
                               " is out of range: allowed " + format_number(low) + ".." + format_number(high));
    };
    in_range(relative_tolerance, 1e-14, 1e-3, "relative_tolerance", "CVODE relative tolerance");
    in_range(absolute_tolerance, 1e-16, 1e-3, "absolute_tolerance", "CVODE absolute tolerance");
    in_range(steady_tolerance, 1e-14, 1e-2, "steady_tolerance", "Poincare convergence tolerance");
    if (min_periods < 1)
        throw InvalidInput("min_periods = " + std::to_string(min_periods) + " is out of range: allowed >= 1");
    if (max_periods < min_periods)
        throw InvalidInput("max_periods = " + std::to_string(max_periods) +
                           " is out of range: allowed >= min_periods = " + std::to_string(min_periods));
    if (samples_per_period < 8)
        throw InvalidInput("samples_per_period = " + std::to_string(samples_per_period) +
                           " is out of range: allowed >= 8");
    if (max_events_per_period < 1)
        throw InvalidInput("max_events_per_period = " + std::to_string(max_events_per_period) +
                           " is out of range: allowed >= 1");
    if (max_steps_per_period < 10)
        throw InvalidInput("max_steps_per_period = " + std::to_string(max_steps_per_period) +
                           " is out of range: allowed >= 10");
    if (stick_restart_periods < 1)
        throw InvalidInput("stick_restart_periods = " + std::to_string(stick_restart_periods) +
                           " is out of range: allowed >= 1");
    if (shooting_interval < 1)
        throw InvalidInput("shooting_interval = " + std::to_string(shooting_interval) +
                           " is out of range: allowed >= 1");
}

std::string PeriodicResponse::summary() const {
    std::ostringstream s;
    s << "w = " << format_number(omega) << ": " << (converged ? "converged" : "not converged") << " after "
      << periods << " periods";
    if (!y_max.empty()) s << ", y1_max = " << format_number(y_max[0]);
    if (!regime.empty()) s << ", " << regime;
    if (!message.empty()) s << "; " << message;
    return s.str();
}

int state_size(const System& system) {
    return 2 * system.dofs() + 2 * static_cast<int>(system.contacts.size());
}

namespace {

constexpr double pi = 3.14159265358979323846;

int sign_of(double x) { return (x > 0.0) - (x < 0.0); }

bool has_internal_state(FrictionLaw law) {
    return law == FrictionLaw::dahl || law == FrictionLaw::lugre || law == FrictionLaw::jenkins;
}
bool event_driven(FrictionLaw law) { return law == FrictionLaw::coulomb || law == FrictionLaw::jenkins; }

/// A contact in the form the integrator evaluates.
struct ContactData {
    FrictionLaw law = FrictionLaw::coulomb;
    int a = 0, b = Contact::ground;
    double limit = 0;        // F_c
    double stiffness = 0;    // sigma0 or k_t
    double damping = 0;      // sigma1
    double viscous = 0;      // sigma2
    double static_limit = 0; // F_s (0: F_c)
    double stribeck = 0;     // v_s (0: none)
    double eps = 0;          // tanh velocity scale

    explicit ContactData(const Contact& c)
        : law(c.law), a(c.dof), b(c.other_dof), limit(c.friction_limit), stiffness(c.stiffness),
          damping(c.damping), viscous(c.viscous), static_limit(c.static_limit), stribeck(c.stribeck_velocity),
          eps(c.regularization) {}

    double relative(const double* y) const { return y[a] - (b == Contact::ground ? 0.0 : y[b]); }
    /// LuGre's sliding limit g(v) (F_c for Dahl and without Stribeck curve).
    double sliding_limit(double v) const {
        if (law != FrictionLaw::lugre || stribeck <= 0.0 || static_limit <= 0.0) return limit;
        const double x = v / stribeck;
        return limit + (static_limit - limit) * std::exp(-x * x);
    }
};

/// The linear stuck system of linear_stuck_state: complex amplitudes Y (N) and forces of the
/// rigid (coulomb) contacts.
Eigen::VectorXcd stuck_amplitude(const System& system, double omega) {
    const int n = system.dofs();
    const std::complex<double> i(0.0, 1.0);
    Eigen::MatrixXcd a = dynamic_stiffness(system.mass, system.damping, system.stiffness, omega);
    std::vector<Eigen::VectorXd> rigid;
    for (const Contact& c : system.contacts) {
        const Eigen::VectorXd w = system.contact_direction(c);
        double k = 0.0, d = 0.0;
        switch (c.law) {
            case FrictionLaw::coulomb: rigid.push_back(w); continue;
            case FrictionLaw::jenkins:
            case FrictionLaw::dahl: k = c.stiffness; break;
            case FrictionLaw::lugre: k = c.stiffness; d = c.damping + c.viscous; break;
            case FrictionLaw::coulomb_regularized: d = c.friction_limit / c.regularization; break;
        }
        a += (k + i * omega * d) * (w * w.transpose()).cast<std::complex<double>>();
    }
    const int m = static_cast<int>(rigid.size());
    Eigen::MatrixXcd kkt = Eigen::MatrixXcd::Zero(n + m, n + m);
    kkt.topLeftCorner(n, n) = a;
    for (int k = 0; k < m; ++k) {
        kkt.block(0, n + k, n, 1) = rigid[static_cast<std::size_t>(k)].cast<std::complex<double>>();
        kkt.block(n + k, 0, 1, n) = rigid[static_cast<std::size_t>(k)].transpose().cast<std::complex<double>>();
    }
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n + m);
    rhs.head(n) = system.excitation.cast<std::complex<double>>();
    Eigen::FullPivLU<Eigen::MatrixXcd> lu(kkt);
    if (!lu.isInvertible()) return Eigen::VectorXcd::Zero(n);
    const Eigen::VectorXcd solution = lu.solve(rhs);
    if (!solution.allFinite()) return Eigen::VectorXcd::Zero(n);
    return solution.head(n);
}

/// Everything measured over one period.
struct PeriodRecord {
    bool ok = true;
    std::string failure;
    Eigen::VectorXd end_state;
    std::vector<double> y_max;
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

void silent_error_handler(int, const char*, const char*, char*, void*) {}

class Integrator {
public:
    Integrator(const System& system, double omega, const TimeIntegrationOptions& options);
    ~Integrator();
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
    double mode_root(int c, const double* x) const;
    void load(const Eigen::VectorXd& state);
    Eigen::VectorXd store() const;
    void reinit(double t);
    void throw_on(int flag, const char* what) const;

    const System& system_;
    const double omega_, period_;
    const TimeIntegrationOptions options_;
    const int n_, nc_, length_, quad_;
    std::vector<ContactData> contacts_;
    Eigen::MatrixXd minv_;               // M^-1
    Eigen::VectorXd excitation_;
    std::vector<int> mode_;
    std::vector<int> stuck_;             // coulomb contacts in mode 0
    Eigen::MatrixXd ws_, minv_ws_, g_;   // W_S, M^-1 W_S, (W_S^T M^-1 W_S)^+
    std::vector<int> ground_stuck_dof_;  // per DOF: 1 if held to ground by a stuck contact
    // scratch of evaluate()
    Eigen::VectorXd f_, zdot_, acc_, load_, lambda_, velocity_c_;

    SUNContext context_ = nullptr;
    N_Vector x_ = nullptr, dky_ = nullptr;
    SUNMatrix matrix_ = nullptr;
    SUNLinearSolver linear_ = nullptr;
    SUNNonlinearSolver nonlinear_ = nullptr;
    void* cvode_ = nullptr;
    long steps_ = 0;
    long rhs_total_ = 0;  // right-hand side evaluations before the last CVodeReInit
    double margin_at_event_ = std::numeric_limits<double>::quiet_NaN();
};

Integrator::Integrator(const System& system, double omega, const TimeIntegrationOptions& options)
    : system_(system), omega_(omega), period_(2.0 * pi / omega), options_(options), n_(system.dofs()),
      nc_(static_cast<int>(system.contacts.size())), length_(4 * n_ + nc_ + 3), quad_(2 * n_ + nc_) {
    for (const Contact& c : system.contacts) contacts_.emplace_back(c);
    minv_ = system.mass.llt().solve(Eigen::MatrixXd::Identity(n_, n_));
    excitation_ = system.excitation;
    mode_.assign(static_cast<std::size_t>(nc_), 0);
    f_ = Eigen::VectorXd::Zero(nc_);
    zdot_ = Eigen::VectorXd::Zero(nc_);
    velocity_c_ = Eigen::VectorXd::Zero(nc_);
    acc_ = Eigen::VectorXd::Zero(n_);
    load_ = Eigen::VectorXd::Zero(n_);
    ground_stuck_dof_.assign(static_cast<std::size_t>(n_), 0);

    if (SUNContext_Create(nullptr, &context_) != 0) throw std::runtime_error("SUNContext_Create failed");
    x_ = N_VNew_Serial(length_, context_);
    dky_ = N_VNew_Serial(length_, context_);
    if (!x_ || !dky_) throw std::runtime_error("N_VNew_Serial failed");
    N_VConst(0.0, x_);
    const bool adams = options_.method == IntegrationMethod::adams;
    cvode_ = CVodeCreate(adams ? CV_ADAMS : CV_BDF, context_);
    if (!cvode_) throw std::runtime_error("CVodeCreate failed");
    throw_on(CVodeInit(cvode_, rhs_callback, 0.0, x_), "CVodeInit");
    throw_on(CVodeSetErrHandlerFn(cvode_, silent_error_handler, nullptr), "CVodeSetErrHandlerFn");
    throw_on(CVodeSetUserData(cvode_, this), "CVodeSetUserData");
    throw_on(CVodeSStolerances(cvode_, options_.relative_tolerance, options_.absolute_tolerance), "CVodeSStolerances");
    if (adams) {
        nonlinear_ = SUNNonlinSol_FixedPoint(x_, 0, context_);
        throw_on(CVodeSetNonlinearSolver(cvode_, nonlinear_), "CVodeSetNonlinearSolver");
    } else {
        matrix_ = SUNDenseMatrix(length_, length_, context_);
        linear_ = SUNLinSol_Dense(x_, matrix_, context_);
        throw_on(CVodeSetLinearSolver(cvode_, linear_, matrix_), "CVodeSetLinearSolver");
    }
    throw_on(CVodeSetMaxNumSteps(cvode_, options_.max_steps_per_period), "CVodeSetMaxNumSteps");
    throw_on(CVodeRootInit(cvode_, nc_ + n_, root_callback), "CVodeRootInit");
    std::vector<int> direction(static_cast<std::size_t>(nc_ + n_), 0);
    for (int c = 0; c < nc_; ++c)
        if (event_driven(contacts_[static_cast<std::size_t>(c)].law)) direction[static_cast<std::size_t>(c)] = -1;
    throw_on(CVodeSetRootDirection(cvode_, direction.data()), "CVodeSetRootDirection");
    throw_on(CVodeSetNoInactiveRootWarn(cvode_), "CVodeSetNoInactiveRootWarn");
    rebuild_stuck_set();
}

Integrator::~Integrator() {
    if (cvode_) CVodeFree(&cvode_);
    if (nonlinear_) SUNNonlinSolFree(nonlinear_);
    if (linear_) SUNLinSolFree(linear_);
    if (matrix_) SUNMatDestroy(matrix_);
    if (x_) N_VDestroy(x_);
    if (dky_) N_VDestroy(dky_);
    if (context_) SUNContext_Free(&context_);
}

void Integrator::throw_on(int flag, const char* what) const {
    if (flag < 0) throw std::runtime_error(std::string(what) + " failed: " + CVodeGetReturnFlagName(flag));
}

long Integrator::rhs_evaluations() const {
    long count = 0;
    CVodeGetNumRhsEvals(cvode_, &count);
    return rhs_total_ + count;
}

int Integrator::rhs_callback(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
    static_cast<Integrator*>(data)->derivative(t, N_VGetArrayPointer(x), N_VGetArrayPointer(dx));
    return 0;
}

int Integrator::root_callback(sunrealtype t, N_Vector x, sunrealtype* g, void* data) {
    static_cast<Integrator*>(data)->roots(t, N_VGetArrayPointer(x), g);
    return 0;
}

void Integrator::rebuild_stuck_set() {
    stuck_.clear();
    std::fill(ground_stuck_dof_.begin(), ground_stuck_dof_.end(), 0);
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (k.law == FrictionLaw::coulomb && mode_[static_cast<std::size_t>(c)] == 0) {
            stuck_.push_back(c);
            if (k.b == Contact::ground) ground_stuck_dof_[static_cast<std::size_t>(k.a)] = 1;
        }
    }
    const int m = static_cast<int>(stuck_.size());
    ws_ = Eigen::MatrixXd::Zero(n_, m);
    for (int k = 0; k < m; ++k) ws_.col(k) = system_.contact_direction(system_.contacts[static_cast<std::size_t>(stuck_[static_cast<std::size_t>(k)])]);
    minv_ws_ = minv_ * ws_;
    if (m > 0) g_ = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(ws_.transpose() * minv_ws_).pseudoInverse();
    lambda_ = Eigen::VectorXd::Zero(m);
}

void Integrator::evaluate(double t, const double* x) {
    const double* y = x;
    const double* v = x + n_;
    const double* z = x + 2 * n_;
    Eigen::Map<const Eigen::VectorXd> ym(y, n_), vm(v, n_);
    load_.noalias() = excitation_ * std::cos(omega_ * t);
    load_.noalias() -= system_.damping * vm;
    load_.noalias() -= system_.stiffness * ym;
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        const double vc = k.relative(v);
        velocity_c_(c) = vc;
        double f = 0.0, zd = 0.0;
        const int mode = mode_[static_cast<std::size_t>(c)];
        switch (k.law) {
            case FrictionLaw::dahl:
                zd = vc - k.stiffness * std::abs(vc) * z[c] / k.limit;
                f = k.stiffness * z[c];
                break;
            case FrictionLaw::lugre:
                zd = vc - k.stiffness * std::abs(vc) * z[c] / k.sliding_limit(vc);
                f = k.stiffness * z[c] + k.damping * zd + k.viscous * vc;
                break;
            case FrictionLaw::coulomb_regularized: f = k.limit * std::tanh(vc / k.eps); break;
            case FrictionLaw::jenkins:
                if (mode == 0) {
                    f = k.stiffness * (k.relative(y) - z[c]);
                } else {
                    f = mode * k.limit;
                    zd = vc;
                }
                break;
            case FrictionLaw::coulomb: f = mode * k.limit; break;  // stuck: lambda below
        }
        f_(c) = f;
        zdot_(c) = zd;
        if (k.law == FrictionLaw::coulomb && mode == 0) continue;
        load_(k.a) -= f;
        if (k.b != Contact::ground) load_(k.b) += f;
    }
    acc_.noalias() = minv_ * load_;
    if (!stuck_.empty()) {
        lambda_.noalias() = g_ * (ws_.transpose() * acc_);
        acc_.noalias() -= minv_ws_ * lambda_;
        for (std::size_t k = 0; k < stuck_.size(); ++k) f_(stuck_[k]) = lambda_(static_cast<Eigen::Index>(k));
    }
}

void Integrator::derivative(double t, const double* x, double* dx) {
    evaluate(t, x);
    const double* y = x;
    const double* v = x + n_;
    for (int i = 0; i < n_; ++i) {
        dx[i] = v[i];
        dx[n_ + i] = acc_(i);
    }
    for (int c = 0; c < nc_; ++c) dx[2 * n_ + c] = zdot_(c);
    const double cs = std::cos(omega_ * t), sn = std::sin(omega_ * t);
    double* q = dx + quad_;
    double friction = 0.0, input = 0.0;
    for (int i = 0; i < n_; ++i) {
        q[i] = y[i] * cs;
        q[n_ + i] = y[i] * sn;
        input += excitation_(i) * v[i];
    }
    for (int c = 0; c < nc_; ++c) friction += f_(c) * velocity_c_(c);
    Eigen::Map<const Eigen::VectorXd> vm(v, n_);
    q[2 * n_] = friction;
    q[2 * n_ + 1] = vm.dot(system_.damping * vm);
    q[2 * n_ + 2] = input * cs;
}

double Integrator::mode_root(int c, const double* x) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    const int mode = mode_[static_cast<std::size_t>(c)];
    if (mode != 0) return mode * velocity_c_(c);
    if (k.law == FrictionLaw::jenkins) return k.limit - std::abs(k.stiffness * (k.relative(x) - x[2 * n_ + c]));
    return k.limit - std::abs(f_(c));  // coulomb: lambda
}

bool Integrator::in_stick(int c, const double* x) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    if (event_driven(k.law)) return mode_[static_cast<std::size_t>(c)] == 0;
    return margin(c, x) < 0.0;
}

double Integrator::margin(int c, const double* x) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    const double vc = velocity_c_(c);
    switch (k.law) {
        case FrictionLaw::coulomb:
        case FrictionLaw::jenkins: return std::abs(f_(c)) / k.limit - 1.0;
        case FrictionLaw::dahl:
        case FrictionLaw::lugre:
            return std::abs(k.stiffness * x[2 * n_ + c]) / (stick_force_ratio * k.sliding_limit(vc)) - 1.0;
        case FrictionLaw::coulomb_regularized: return std::abs(std::tanh(vc / k.eps)) / stick_force_ratio - 1.0;
    }
    return 0.0;
}

void Integrator::roots(double t, const double* x, double* g) {
    evaluate(t, x);
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (event_driven(k.law)) {
            g[c] = mode_root(c, x);
        } else if (k.law == FrictionLaw::coulomb_regularized) {
            g[c] = stick_force_ratio - std::abs(std::tanh(velocity_c_(c) / k.eps));
        } else {
            g[c] = stick_force_ratio * k.sliding_limit(velocity_c_(c)) - std::abs(k.stiffness * x[2 * n_ + c]);
        }
    }
    for (int i = 0; i < n_; ++i) g[nc_ + i] = ground_stuck_dof_[static_cast<std::size_t>(i)] ? 1.0 : x[n_ + i];
}

void Integrator::project_velocities(double* x, const std::vector<int>& set) const {
    if (set.empty()) return;
    const int m = static_cast<int>(set.size());
    Eigen::MatrixXd w(n_, m);
    for (int k = 0; k < m; ++k) w.col(k) = system_.contact_direction(system_.contacts[static_cast<std::size_t>(set[static_cast<std::size_t>(k)])]);
    const Eigen::MatrixXd minv_w = minv_ * w;
    const Eigen::MatrixXd s = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(w.transpose() * minv_w).pseudoInverse();
    Eigen::Map<Eigen::VectorXd> v(x + n_, n_);
    v -= minv_w * (s * (w.transpose() * v));
    // exact zeros on the constraint (the projection leaves rounding of order 1e-16 |v|)
    for (int c : set) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (k.b == Contact::ground) x[n_ + k.a] = 0.0;
    }
}

void Integrator::settle_stuck_set(double t, double* x) {
    for (int round = 0; round <= nc_; ++round) {
        rebuild_stuck_set();
        evaluate(t, x);
        int worst = -1;
        double worst_ratio = 1.0;
        for (int c : stuck_) {
            const double ratio = std::abs(f_(c)) / contacts_[static_cast<std::size_t>(c)].limit;
            if (ratio > worst_ratio) {
                worst_ratio = ratio;
                worst = c;
            }
        }
        if (worst < 0) return;
        mode_[static_cast<std::size_t>(worst)] = sign_of(f_(worst));
    }
}

int Integrator::handle_events(double t, double* x, const std::vector<int>& hits) {
    const std::vector<int> before = mode_;
    evaluate(t, x);
    std::vector<int> at_rest;  // coulomb contacts whose velocity is zero now
    std::vector<int> candidates;
    for (int c : hits) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        int& mode = mode_[static_cast<std::size_t>(c)];
        if (k.law == FrictionLaw::coulomb) {
            if (mode == 0) {
                mode = sign_of(f_(c));  // the limit is reached: slip in the direction of lambda
                if (mode == 0) mode = 1;
                at_rest.push_back(c);
            } else {
                mode = 0;  // tried in stick below
                candidates.push_back(c);
            }
        } else if (k.law == FrictionLaw::jenkins) {
            if (mode == 0) {
                mode = sign_of(f_(c));
                if (mode == 0) mode = 1;
                x[2 * n_ + c] = k.relative(x) - mode * k.limit / k.stiffness;
            } else {
                // reversal unless the relative acceleration keeps the direction (a touch)
                const Eigen::VectorXd w = system_.contact_direction(system_.contacts[static_cast<std::size_t>(c)]);
                if (mode * w.dot(acc_) <= 0.0) mode = 0;
            }
        }
    }
    for (int c = 0; c < nc_; ++c)
        if (contacts_[static_cast<std::size_t>(c)].law == FrictionLaw::coulomb && mode_[static_cast<std::size_t>(c)] == 0)
            at_rest.push_back(c);
    project_velocities(x, at_rest);
    rebuild_stuck_set();
    evaluate(t, x);
    for (int c : candidates)
        if (c == 0) margin_at_event_ = std::abs(f_(0)) / contacts_[0].limit - 1.0;
    settle_stuck_set(t, x);
    int changes = 0;
    for (int c = 0; c < nc_; ++c) changes += mode_[static_cast<std::size_t>(c)] != before[static_cast<std::size_t>(c)];
    return changes;
}

void Integrator::load(const Eigen::VectorXd& state) {
    double* x = N_VGetArrayPointer(x_);
    for (int i = 0; i < 2 * n_ + nc_; ++i) x[i] = state(i);
    for (int i = 2 * n_ + nc_; i < length_; ++i) x[i] = 0.0;
    for (int c = 0; c < nc_; ++c) mode_[static_cast<std::size_t>(c)] = static_cast<int>(state(2 * n_ + nc_ + c));
    rebuild_stuck_set();
}

Eigen::VectorXd Integrator::store() const {
    const double* x = N_VGetArrayPointer(x_);
    Eigen::VectorXd state(2 * n_ + 2 * nc_);
    for (int i = 0; i < 2 * n_ + nc_; ++i) state(i) = x[i];
    for (int c = 0; c < nc_; ++c) state(2 * n_ + nc_ + c) = mode_[static_cast<std::size_t>(c)];
    return state;
}

void Integrator::reinit(double t) {
    long count = 0;
    CVodeGetNumRhsEvals(cvode_, &count);  // CVodeReInit resets the counters
    rhs_total_ += count;
    throw_on(CVodeReInit(cvode_, t, x_), "CVodeReInit");
    throw_on(CVodeSetStopTime(cvode_, period_), "CVodeSetStopTime");
}

void Integrator::settle_initial(Eigen::VectorXd& state) {
    for (int c = 0; c < nc_; ++c) {
        const double m = state(2 * n_ + nc_ + c);
        const FrictionLaw law = contacts_[static_cast<std::size_t>(c)].law;
        state(2 * n_ + nc_ + c) = event_driven(law) ? static_cast<double>(sign_of(m)) : 0.0;
        if (!has_internal_state(law)) state(2 * n_ + c) = 0.0;
    }
    load(state);
    double* x = N_VGetArrayPointer(x_);
    evaluate(0.0, x);
    std::vector<int> at_rest;
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        int& mode = mode_[static_cast<std::size_t>(c)];
        const double vc = velocity_c_(c);
        if (k.law == FrictionLaw::coulomb) {
            if (mode != 0 && mode * vc < 0.0) mode = sign_of(vc);
            if (mode == 0) at_rest.push_back(c);
        } else if (k.law == FrictionLaw::jenkins) {
            double& s = x[2 * n_ + c];
            if (mode != 0 && mode * vc < 0.0) mode = 0;
            if (mode != 0) s = k.relative(x) - mode * k.limit / k.stiffness;
            const double f = k.stiffness * (k.relative(x) - s);
            if (mode == 0 && std::abs(f) > k.limit) {
                s = k.relative(x) - sign_of(f) * k.limit / k.stiffness;
                if (sign_of(f) * vc > 0.0) mode = sign_of(f);
            }
        }
    }
    project_velocities(x, at_rest);
    settle_stuck_set(0.0, x);
    state = store();
}

PeriodRecord Integrator::period(const Eigen::VectorXd& start) {
    PeriodRecord r;
    load(start);
    double* x = N_VGetArrayPointer(x_);
    double* d = N_VGetArrayPointer(dky_);
    reinit(0.0);

    const int samples = options_.samples_per_period;
    r.time = Eigen::VectorXd(samples);
    r.displacement = Eigen::MatrixXd(samples, n_);
    r.velocity = Eigen::MatrixXd(samples, n_);
    r.friction_force = Eigen::MatrixXd(samples, nc_);
    r.y_max.assign(static_cast<std::size_t>(n_), 0.0);
    r.stick_time.assign(static_cast<std::size_t>(nc_), 0.0);
    r.always_stuck.assign(static_cast<std::size_t>(nc_), true);
    r.never_stuck.assign(static_cast<std::size_t>(nc_), true);
    std::vector<bool> stuck(static_cast<std::size_t>(nc_));
    std::vector<double> since(static_cast<std::size_t>(nc_), 0.0);

    auto update_extremes = [&](const double* state) {
        for (int i = 0; i < n_; ++i) r.y_max[static_cast<std::size_t>(i)] = std::max(r.y_max[static_cast<std::size_t>(i)], std::abs(state[i]));
    };
    auto update_margin = [&](double m) {
        r.margin_min = std::min(r.margin_min, m);
        r.margin_max = std::max(r.margin_max, m);
    };
    // contact 1's margin: coulomb only while stuck (slip phases are checked at the events)
    auto contact_margin = [&](const double* state) {
        if (nc_ == 0) return;
        if (contacts_[0].law == FrictionLaw::coulomb && mode_[0] != 0) return;
        update_margin(margin(0, state));
    };
    auto update_stick = [&](double t, const double* state) {
        for (int c = 0; c < nc_; ++c) {
            const bool now = in_stick(c, state);
            const auto k = static_cast<std::size_t>(c);
            if (now == stuck[k]) continue;
            if (stuck[k]) r.stick_time[k] += t - since[k];
            since[k] = t;
            stuck[k] = now;
            if (now) r.never_stuck[k] = false; else r.always_stuck[k] = false;
            if (!event_driven(contacts_[k].law)) ++r.switches;  // event-driven laws count modes
        }
    };
    auto record_sample = [&](int j, double t, const double* state) {
        evaluate(t, state);
        r.time(j) = t;
        for (int i = 0; i < n_; ++i) {
            r.displacement(j, i) = state[i];
            r.velocity(j, i) = state[n_ + i];
        }
        for (int c = 0; c < nc_; ++c) r.friction_force(j, c) = f_(c);
        update_extremes(state);
        contact_margin(state);
    };

    evaluate(0.0, x);
    for (int c = 0; c < nc_; ++c) {
        const auto k = static_cast<std::size_t>(c);
        stuck[k] = in_stick(c, x);
        if (stuck[k]) r.never_stuck[k] = false; else r.always_stuck[k] = false;
    }
    record_sample(0, 0.0, x);
    int next_sample = 1;
    int events = 0;
    long steps = 0;
    std::vector<int> found(static_cast<std::size_t>(nc_ + n_));
    double t = 0.0;
    const double v_guard = 1e-6, f_guard = 1e-6;  // safety net for missed roots (relative)

    while (true) {
        const int flag = CVode(cvode_, period_, x_, &t, CV_ONE_STEP);
        if (flag < 0) {
            r.ok = false;
            r.failure = std::string("CVODE failed at t = ") + format_number(t) + " in the period: " +
                        CVodeGetReturnFlagName(flag);
            return r;
        }
        ++steps;
        ++steps_;
        if (steps > options_.max_steps_per_period) {
            r.ok = false;
            r.failure = "more than " + std::to_string(options_.max_steps_per_period) + " steps in one period";
            return r;
        }
        while (next_sample < samples) {
            const double ts = period_ * next_sample / samples;
            if (ts > t) break;
            throw_on(CVodeGetDky(cvode_, ts, 0, dky_), "CVodeGetDky");
            record_sample(next_sample, ts, d);
            ++next_sample;
        }
        evaluate(t, x);
        update_extremes(x);
        contact_margin(x);

        std::vector<int> hits;
        if (flag == CV_ROOT_RETURN) {
            throw_on(CVodeGetRootInfo(cvode_, found.data()), "CVodeGetRootInfo");
            for (int c = 0; c < nc_; ++c)
                if (found[static_cast<std::size_t>(c)] != 0 && event_driven(contacts_[static_cast<std::size_t>(c)].law))
                    hits.push_back(c);
        } else {
            double vscale = 1.0;
            for (int i = 0; i < n_; ++i) vscale = std::max(vscale, std::abs(x[n_ + i]));
            for (int c = 0; c < nc_; ++c) {
                const ContactData& k = contacts_[static_cast<std::size_t>(c)];
                if (!event_driven(k.law)) continue;
                const double g = mode_root(c, x);
                const double guard = mode_[static_cast<std::size_t>(c)] != 0 ? v_guard * vscale : f_guard * k.limit;
                if (g < -guard) hits.push_back(c);
            }
        }
        update_stick(t, x);
        if (!hits.empty()) {
            margin_at_event_ = std::numeric_limits<double>::quiet_NaN();
            r.switches += handle_events(t, x, hits);
            if (!std::isnan(margin_at_event_)) update_margin(margin_at_event_);
            evaluate(t, x);
            update_extremes(x);
            contact_margin(x);
            update_stick(t, x);
            if (++events > options_.max_events_per_period) {
                r.ok = false;
                r.failure = "more than " + std::to_string(options_.max_events_per_period) +
                            " stick/slip events in one period (chattering?) at t = " + format_number(t);
                return r;
            }
            if (period_ - t <= 1e-12 * period_) break;  // the event closes the period
            reinit(t);
        }
        if (flag == CV_TSTOP_RETURN || t >= period_) break;
    }
    for (int c = 0; c < nc_; ++c) {
        const auto k = static_cast<std::size_t>(c);
        if (stuck[k]) r.stick_time[k] += period_ - since[k];
    }
    const double* q = x + quad_;
    r.harmonic1 = Eigen::VectorXcd(n_);
    for (int i = 0; i < n_; ++i)
        r.harmonic1(i) = std::complex<double>(q[i], -q[n_ + i]) * (omega_ / pi);
    r.energy = q[2 * n_];
    r.viscous_energy = q[2 * n_ + 1];
    r.input_energy = q[2 * n_ + 2];
    r.end_state = store();
    return r;
}

double poincare_change(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int continuous) {
    const double scale = std::max(1.0, b.head(continuous).cwiseAbs().maxCoeff());
    return (a.head(continuous) - b.head(continuous)).cwiseAbs().maxCoeff() / scale;
}

void fill_metrics(PeriodicResponse& out, const PeriodRecord& r, const Eigen::VectorXd& start, double period) {
    out.state = start;
    out.y_max = r.y_max;
    out.harmonic1 = r.harmonic1;
    out.y_amp1.resize(static_cast<std::size_t>(r.harmonic1.size()));
    for (Eigen::Index i = 0; i < r.harmonic1.size(); ++i) out.y_amp1[static_cast<std::size_t>(i)] = std::abs(r.harmonic1(i));
    if (r.stick_time.empty()) {
        out.stick_fraction = 0.0;
        out.regime = "none";
        out.stick_margin_min = out.stick_margin_max = 0.0;
    } else {
        out.stick_fraction = r.always_stuck[0] ? 1.0 : r.never_stuck[0] ? 0.0 : std::clamp(r.stick_time[0] / period, 0.0, 1.0);
        out.regime = r.always_stuck[0] ? "stick" : r.never_stuck[0] ? "slip" : "stick-slip";
        out.stick_margin_min = std::isfinite(r.margin_min) ? r.margin_min : 0.0;
        out.stick_margin_max = std::isfinite(r.margin_max) ? r.margin_max : 0.0;
    }
    out.switches = r.switches;
    out.energy = r.energy;
    out.viscous_energy = r.viscous_energy;
    out.input_energy = r.input_energy;
    out.time = r.time;
    out.displacement = r.displacement;
    out.velocity = r.velocity;
    out.friction_force = r.friction_force;
}

}  // namespace

Eigen::VectorXd linear_stuck_state(const System& system, double omega) {
    system.validate();
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    const Eigen::VectorXcd y = stuck_amplitude(system, omega);
    Eigen::VectorXd state = Eigen::VectorXd::Zero(state_size(system));
    state.head(n) = y.real();
    state.segment(n, n) = -omega * y.imag();  // Re(i omega Y)
    for (int c = 0; c < nc; ++c) {
        const Contact& k = system.contacts[static_cast<std::size_t>(c)];
        if (k.law == FrictionLaw::dahl || k.law == FrictionLaw::lugre)
            state(2 * n + c) = system.contact_direction(k).dot(state.head(n));  // z = q
    }
    return state;
}

PeriodicResponse integrate_steady_state(const System& system, double omega, const TimeIntegrationOptions& options,
                                        const Eigen::VectorXd* initial_state) {
    system.validate();
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    options.validate();
    const int size = state_size(system);
    if (initial_state && (initial_state->size() != size || !initial_state->allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state->size()) +
                           " entries or non-finite values: allowed " + std::to_string(size) +
                           " finite values (2 N + 2 contacts)");
    detail::Stopwatch clock;
    const int continuous = 2 * system.dofs() + static_cast<int>(system.contacts.size());
    const double period = 2.0 * pi / omega;
    PeriodicResponse out;
    out.omega = omega;
    Integrator integrator(system, omega, options);
    Eigen::VectorXd x = initial_state ? *initial_state : Eigen::VectorXd::Zero(size);
    integrator.settle_initial(x);
    bool restarted = false, have_metrics = false;
    int stuck_periods = 0;
    std::string note;
    // Newton (shooting) acceleration of the Poincare map: see TimeIntegrationOptions::shooting.
    int next_shooting = options.shooting_interval, shooting_interval = options.shooting_interval;
    int newton_steps = 0, newton_rejected = 0;
    bool pending_check = false, candidate_is_linear = false;
    int linear_tried_at = 0;
    Eigen::VectorXd saved;  // P(x) before a Newton step, to revert to
    double saved_change = 0, previous_change = std::numeric_limits<double>::infinity();
    int k = 0;
    while (k < options.max_periods) {
        PeriodRecord record = integrator.period(x);
        ++k;
        out.periods = k;
        if (!record.ok) {
            out.converged = false;
            out.message = record.failure + " (period " + std::to_string(k) + ", w = " + format_number(omega) + ")";
            if (!have_metrics) out.state = x;
            break;
        }
        const double change = poincare_change(record.end_state, x, continuous);
        if (pending_check) {  // the first period from a candidate start: keep it only if it helped
            pending_check = false;
            if (change > saved_change) {
                if (candidate_is_linear) {
                    note += "; the linear stuck start was tried after " + std::to_string(linear_tried_at) +
                            " periods and rejected";
                } else {
                    ++newton_rejected;
                    shooting_interval *= 2;
                    next_shooting = k + shooting_interval;
                }
                x = saved;
                previous_change = saved_change;
                continue;
            }
            if (candidate_is_linear)
                note += "; restarted from the linear stuck steady state after " + std::to_string(linear_tried_at) +
                        " periods";
            else {
                ++newton_steps;
                next_shooting = k;  // Newton converges fast: go on with it while it helps
            }
        }
        out.poincare_change = change;
        fill_metrics(out, record, x, period);
        have_metrics = true;
        if (k >= options.min_periods && change <= options.steady_tolerance) {
            out.converged = true;
            break;
        }
        const bool all_stuck = !record.always_stuck.empty() &&
                               std::all_of(record.always_stuck.begin(), record.always_stuck.end(), [](bool b) { return b; });
        stuck_periods = all_stuck ? stuck_periods + 1 : 0;
        const Eigen::VectorXd start = x;
        x = record.end_state;
        const bool shooting_due = options.shooting && k >= next_shooting && change > 0.2 * previous_change;
        if (options.stick_restart && !restarted && (stuck_periods >= options.stick_restart_periods || shooting_due)) {
            // candidate start: the linear stuck steady state (kept only if its first period
            // changes less than the current one)
            restarted = true;
            candidate_is_linear = true;
            linear_tried_at = k;
            saved = x;
            saved_change = change;
            pending_check = true;
            x = linear_stuck_state(system, omega);
            integrator.settle_initial(x);
        } else if (shooting_due &&
                   k + continuous + 1 < options.max_periods) {
            // Jacobian of the map by forward differences (one period per continuous state),
            // then x <- x + (I - J)^-1 (P(x) - x).
            next_shooting = k + shooting_interval;
            const double h = 1e-6 * std::max(1.0, start.head(continuous).cwiseAbs().maxCoeff());
            Eigen::MatrixXd jacobian(continuous, continuous);
            bool ok = true;
            for (int j = 0; j < continuous && ok; ++j) {
                Eigen::VectorXd perturbed = start;
                perturbed(j) += h;
                integrator.settle_initial(perturbed);
                const PeriodRecord column = integrator.period(perturbed);
                ++k;
                ok = column.ok;
                if (ok) jacobian.col(j) = (column.end_state.head(continuous) - x.head(continuous)) / h;
            }
            if (ok) {
                const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(continuous, continuous) - jacobian;
                const Eigen::VectorXd step =
                    a.fullPivLu().solve(x.head(continuous) - start.head(continuous));
                if (step.allFinite()) {
                    saved = x;
                    saved_change = change;
                    pending_check = true;
                    candidate_is_linear = false;
                    x.head(continuous) = start.head(continuous) + step;
                    integrator.settle_initial(x);
                }
            }
            out.periods = k;
        }
        previous_change = change;
    }
    if (!out.converged && out.message.empty())
        out.message = "Poincare map not converged after " + std::to_string(out.periods) + " periods: change " +
                      format_number(out.poincare_change) + " > " + format_number(options.steady_tolerance) +
                      " (w = " + format_number(omega) + ")";
    else if (out.converged)
        out.message = "Poincare change " + format_number(out.poincare_change) + " <= " +
                      format_number(options.steady_tolerance);
    if (newton_steps + newton_rejected > 0)
        note += "; " + std::to_string(newton_steps) + " Newton (shooting) steps accepted, " +
                std::to_string(newton_rejected) + " rejected";
    out.message += note;
    out.steps = integrator.steps();
    out.rhs_evaluations = integrator.rhs_evaluations();
    out.seconds = clock.lap();
    return out;
}

std::vector<PeriodicResponse> sweep(const System& system, const std::vector<double>& omegas,
                                    const TimeIntegrationOptions& options, const Eigen::VectorXd* initial_state) {
    std::vector<PeriodicResponse> responses;
    responses.reserve(omegas.size());
    Eigen::VectorXd state;
    if (initial_state) state = *initial_state;
    for (double omega : omegas) {
        responses.push_back(integrate_steady_state(system, omega, options, state.size() ? &state : nullptr));
        state = responses.back().state;
    }
    return responses;
}

}  // namespace hbf
