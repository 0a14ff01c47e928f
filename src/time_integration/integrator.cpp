// The CVODE integrator of one period: right-hand side, root functions, events (see
// time_integration.hpp).
// Just over 600 lines: one CVODE problem (right-hand side, roots, events) whose callbacks share
// the integrator's state.
#include "time_integration/integrator.hpp"

#include <algorithm>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/contact_force.hpp"

namespace hbf::detail {

namespace {
constexpr double pi = 3.14159265358979323846;

int sign_of(double x) { return (x > 0.0) - (x < 0.0); }
}  // namespace

Integrator::Integrator(const System& system, double omega, const TimeIntegrationOptions& options, double scale)
    : system_(system), omega_(omega), drive_(system.excitation_harmonic * omega), period_(2.0 * pi / omega),
      scale_(scale), options_(options), n_(system.dofs()),
      nc_(static_cast<int>(system.contacts.size())), length_(4 * n_ + nc_ + 3), quad_(2 * n_ + nc_),
      cvode_(length_, options.method == IntegrationMethod::adams ? CV_ADAMS : CV_BDF, rhs_callback, this,
             CvodeSolver::Warnings::record) {
    for (const Contact& c : system.contacts) {
        contacts_.emplace_back(c);
        ContactData& k = contacts_.back();
        if (k.bound && k.bound->directions() > 1) k.directions = system.contact_directions(c);
    }
    sparse_ = n_ > options_.dense_newton_max_dofs;
    if (sparse_) {
        mass_factor_.compute(system.mass);
        if (mass_factor_.info() != Eigen::Success)
            throw InvalidInput("time integration needs a positive definite mass matrix (its LDL^T factorisation failed)");
    } else {
        minv_ = Eigen::MatrixXd(system.mass).llt().solve(Eigen::MatrixXd::Identity(n_, n_));
    }
    excitation_ = system.excitation;
    mode_.assign(static_cast<std::size_t>(nc_), 0);
    f_ = Eigen::VectorXd::Zero(nc_);
    zdot_ = Eigen::VectorXd::Zero(nc_);
    velocity_c_ = Eigen::VectorXd::Zero(nc_);
    power_ = Eigen::VectorXd::Zero(nc_);
    end_ = end_rate_ = end_acc_ = Eigen::VectorXd::Zero(nc_);
    acc_ = Eigen::VectorXd::Zero(n_);
    load_ = Eigen::VectorXd::Zero(n_);
    ground_stuck_dof_.assign(static_cast<std::size_t>(n_), 0);

    dky_ = cvode_.vector();
    // Absolute tolerances relative to the response's scale s (time_integration.hpp): y and the
    // internal states (lengths) a s, y' a h omega s, the first-harmonic quadratures a s T, the
    // energies a 2 pi h max(|F|, F_c) s (the work of a force of that size over the period).
    absolute_ = cvode_.vector();
    {
        const double a = options_.absolute_tolerance * scale_;
        double force = system.excitation.cwiseAbs().maxCoeff();
        for (const ContactData& c : contacts_) force = std::max(force, c.limit);
        set_absolute_tolerances(N_VGetArrayPointer(absolute_), n_, nc_, a, drive_, period_,
                                a * 2.0 * pi * system.excitation_harmonic * force, options_.absolute_tolerance);
    }
    cvode_.check(CVodeSVtolerances(cvode_.memory(), options_.relative_tolerance, absolute_), "CVodeSVtolerances");
    if (options_.method == IntegrationMethod::adams) {
        cvode_.fixed_point();
    } else if (sparse_) {
        cvode_.gmres_newton(20, preconditioner_setup, preconditioner_solve, jacobian_times);
        newton_matrix_ = system.mass + system.damping + system.stiffness;  // the union pattern
        newton_rhs_.resize(n_);
    } else {
        cvode_.dense_newton();
    }
    cvode_.check(CVodeSetMaxNumSteps(cvode_.memory(), options_.max_steps_per_period), "CVodeSetMaxNumSteps");
    for (const Output& o : options_.outputs)
        if (o.single_dof() < 0) combined_outputs_.push_back(&o);
    const int roots = nc_ + n_ + static_cast<int>(combined_outputs_.size());
    cvode_.check(CVodeRootInit(cvode_.memory(), roots, root_callback), "CVodeRootInit");
    std::vector<int> direction(static_cast<std::size_t>(roots), 0);
    for (int c = 0; c < nc_; ++c)
        if (contacts_[static_cast<std::size_t>(c)].event_driven()) direction[static_cast<std::size_t>(c)] = -1;
    cvode_.check(CVodeSetRootDirection(cvode_.memory(), direction.data()), "CVodeSetRootDirection");
    cvode_.check(CVodeSetNoInactiveRootWarn(cvode_.memory()), "CVodeSetNoInactiveRootWarn");
    rebuild_stuck_set();
}

long Integrator::rhs_evaluations() const {
    long count = 0;
    CVodeGetNumRhsEvals(cvode_.memory(), &count);
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

void Integrator::apply_minv(const Eigen::Ref<const Eigen::MatrixXd>& in, Eigen::Ref<Eigen::MatrixXd> out) const {
    if (sparse_)
        out = mass_factor_.solve(in);
    else
        out.noalias() = minv_ * in;
}

int Integrator::preconditioner_setup(sunrealtype, N_Vector, N_Vector, sunbooleantype, sunbooleantype* jcur,
                                     sunrealtype gamma, void* data) {
    *jcur = SUNTRUE;
    return static_cast<Integrator*>(data)->setup_newton(gamma);
}

int Integrator::preconditioner_solve(sunrealtype, N_Vector, N_Vector, N_Vector r, N_Vector z, sunrealtype,
                                     sunrealtype, int, void* data) {
    return static_cast<Integrator*>(data)->solve_newton(N_VGetArrayPointer(r), N_VGetArrayPointer(z));
}

int Integrator::jacobian_times(N_Vector v, N_Vector jv, sunrealtype t, N_Vector x, N_Vector fx, void* data,
                               N_Vector tmp) {
    Integrator& self = *static_cast<Integrator*>(data);
    const double v_norm = std::sqrt(N_VDotProd(v, v));
    if (!(v_norm > 0.0)) {
        N_VConst(0.0, jv);
        return 0;
    }
    const double sigma = 1.4901161193847656e-08 * (1.0 + std::sqrt(N_VDotProd(x, x))) / v_norm;  // sqrt(eps)
    N_VLinearSum(1.0, x, sigma, v, tmp);
    self.derivative(t, N_VGetArrayPointer(tmp), N_VGetArrayPointer(jv));
    N_VLinearSum(1.0 / sigma, jv, -1.0 / sigma, fx, jv);
    return 0;
}

int Integrator::setup_newton(double gamma) {
    // the pattern of M + gamma C + gamma^2 K is that of M + C + K for every gamma: analysed once
    newton_matrix_ = system_.mass + gamma * system_.damping + (gamma * gamma) * system_.stiffness;
    if (!newton_analysed_) {
        newton_lu_.analyzePattern(newton_matrix_);
        newton_analysed_ = true;
    }
    newton_lu_.factorize(newton_matrix_);
    newton_ok_ = newton_lu_.info() == Eigen::Success;
    newton_gamma_ = gamma;
    bordered_version_ = -1;
    return newton_ok_ ? 0 : 1;  // > 0: recoverable, CVODE retries with a smaller step
}

int Integrator::solve_newton(const double* r, double* z) {
    // (I - gamma J) z = r with y' = v, v' = P M^-1 (-K y - C v) (P: the stuck contacts'
    // constraint). With z_y = r_y + gamma z_v, multiplying the v-rows by M gives
    //   (M + gamma C + gamma^2 K) z_v = M r_v - gamma K r_y + W_S mu,   W_S^T z_v = W_S^T r_v.
    if (!newton_ok_) return 1;
    const double gamma = newton_gamma_;
    Eigen::Map<const Eigen::VectorXd> ry(r, n_), rv(r + n_, n_);
    newton_rhs_.noalias() = system_.mass * rv;
    newton_rhs_.noalias() -= gamma * (system_.stiffness * ry);
    Eigen::VectorXd& zv = newton_zv_;  // scratch: no allocation per GMRES iteration
    zv = newton_lu_.solve(newton_rhs_);
    if (!stuck_.empty()) {
        if (bordered_version_ != stuck_version_) {
            newton_ws_ = newton_lu_.solve(ws_);
            newton_border_ =
                Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(ws_.transpose() * newton_ws_).pseudoInverse();
            bordered_version_ = stuck_version_;
        }
        const Eigen::VectorXd mu = newton_border_ * (ws_.transpose() * (rv - zv));
        zv.noalias() += newton_ws_ * mu;
    }
    for (int i = 0; i < n_; ++i) {
        z[n_ + i] = zv(i);
        z[i] = r[i] + gamma * zv(i);
    }
    for (int i = 2 * n_; i < length_; ++i) z[i] = r[i];
    return zv.allFinite() ? 0 : 1;
}

void Integrator::rebuild_stuck_set() {
    stuck_.clear();
    std::fill(ground_stuck_dof_.begin(), ground_stuck_dof_.end(), 0);
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (k.rigid() && mode_[static_cast<std::size_t>(c)] == 0) {
            stuck_.push_back(c);
            if (k.w.size() == 0 && k.b == Contact::ground) ground_stuck_dof_[static_cast<std::size_t>(k.a)] = 1;
        }
    }
    const int m = static_cast<int>(stuck_.size());
    ws_ = Eigen::MatrixXd::Zero(n_, m);
    for (int k = 0; k < m; ++k) ws_.col(k) = system_.contact_direction(system_.contacts[static_cast<std::size_t>(stuck_[static_cast<std::size_t>(k)])]);
    minv_ws_.resize(n_, m);
    apply_minv(ws_, minv_ws_);
    ++stuck_version_;
    if (m > 0) g_ = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(ws_.transpose() * minv_ws_).pseudoInverse();
    lambda_ = Eigen::VectorXd::Zero(m);
}

void Integrator::evaluate(double t, const double* x) {
    const double* y = x;
    const double* v = x + n_;
    const double* z = x + 2 * n_;
    Eigen::Map<const Eigen::VectorXd> ym(y, n_), vm(v, n_);
    load_.noalias() = excitation_ * std::cos(drive_ * t);
    load_.noalias() -= system_.damping * vm;
    load_.noalias() -= system_.stiffness * ym;
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (k.base != 0.0) {
            const double drive_cos = std::cos(drive_ * t), drive_sin = std::sin(drive_ * t);
            end_(c) = k.base * drive_cos;
            end_rate_(c) = -k.base * drive_ * drive_sin;
            end_acc_(c) = -k.base * drive_ * drive_ * drive_cos;
        }
        if (k.directions.cols() > 0) {  // an element over several coordinates: -W f on the structure
            several_q_.noalias() = k.directions.transpose() * ym;
            several_v_.noalias() = k.directions.transpose() * vm;
            k.bound->forces(several_q_, several_v_, several_f_, nullptr, nullptr);
            load_.noalias() -= k.directions * several_f_;
            f_(c) = several_f_(0);  // along its first direction (the recorded force)
            velocity_c_(c) = several_v_(0);
            power_(c) = several_f_.dot(several_v_);
            zdot_(c) = 0.0;
            continue;
        }
        const double vc = k.relative(v) + end_rate_(c);  // the moving end's velocity
        velocity_c_(c) = vc;
        double f = 0.0, zd = 0.0;
        const int mode = mode_[static_cast<std::size_t>(c)];
        switch (k.kind) {
            case ContactData::Kind::smooth:
                f = k.bound->force(k.relative(y) + end_(c), vc, z[c], zd);
                break;
            case ContactData::Kind::elastic_slider:
                if (mode == 0) {
                    f = k.stiffness * (k.relative(y) + end_(c) - z[c]);
                } else {
                    f = mode * k.limit;
                    zd = vc;
                }
                break;
            case ContactData::Kind::rigid_slider: f = mode * k.limit; break;  // stuck: lambda below
        }
        f_(c) = f;
        power_(c) = f * vc;
        zdot_(c) = zd;
        if (k.rigid() && mode == 0) continue;
        if (k.w.size() > 0) {  // a force direction: -w f on the structure
            load_ -= k.w * f;
        } else {
            load_(k.a) -= f;
            if (k.b != Contact::ground) load_(k.b) += f;
        }
    }
    apply_minv(load_, acc_);
    if (!stuck_.empty()) {
        lambda_.noalias() = g_ * (ws_.transpose() * acc_);
        acc_.noalias() -= minv_ws_ * lambda_;
        for (std::size_t k = 0; k < stuck_.size(); ++k) {
            f_(stuck_[k]) = lambda_(static_cast<Eigen::Index>(k));
            power_(stuck_[k]) = f_(stuck_[k]) * velocity_c_(stuck_[k]);
        }
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
    // The sliders' base motion is the work of a load on condensed massless DOFs: input.
    double base_input = 0.0;
    for (int c = 0; c < nc_; ++c) {
        friction += power_(c);
        base_input += f_(c) * end_rate_(c);
    }
    Eigen::Map<const Eigen::VectorXd> vm(v, n_);
    q[2 * n_] = friction;
    q[2 * n_ + 1] = vm.dot(system_.damping * vm);
    q[2 * n_ + 2] = input * (drive_ == omega_ ? cs : std::cos(drive_ * t)) + base_input;
}

double Integrator::mode_root(int c) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    const int mode = mode_[static_cast<std::size_t>(c)];
    if (mode != 0) return mode * velocity_c_(c);
    return k.limit - std::abs(f_(c));  // the spring's force (elastic slider) or lambda (rigid)
}

bool Integrator::in_stick(int c, const double* x) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    if (k.event_driven()) return mode_[static_cast<std::size_t>(c)] == 0;
    return margin(c, x) < 0.0;
}

double Integrator::margin(int c, const double* x) const {
    const ContactData& k = contacts_[static_cast<std::size_t>(c)];
    if (k.event_driven()) return std::abs(f_(c)) / k.limit - 1.0;
    return k.bound->margin(k.relative(x) + end_(c), velocity_c_(c), k.has_state ? x[2 * n_ + c] : 0.0);
}

void Integrator::roots(double t, const double* x, double* g) {
    evaluate(t, x);
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        g[c] = k.event_driven() ? mode_root(c) : -margin(c, x);  // > 0 in stick
        // A smooth margin crossing zero slowly (a gap's q - g, whose rounding is constant over
        // several ulps of t) can be exactly 0 at t and at t + CVODE's small probe step, which
        // CVODE refuses (CV_ILL_INPUT, "root found at and very near t"): an exact zero counts as
        // the smallest positive number, which moves no root.
        if (g[c] == 0.0 && !k.event_driven()) g[c] = std::numeric_limits<double>::min();
    }
    for (int i = 0; i < n_; ++i) g[nc_ + i] = ground_stuck_dof_[static_cast<std::size_t>(i)] ? 1.0 : x[n_ + i];
    // Turning points of the outputs that combine DOFs: c^T y' = 0.
    for (std::size_t o = 0; o < combined_outputs_.size(); ++o) {
        double rate = 0.0;
        for (const auto& [i, c] : combined_outputs_[o]->terms()) rate += c * x[n_ + i];
        g[nc_ + n_ + static_cast<int>(o)] = rate;
    }
}

void Integrator::project_velocities(double* x, const std::vector<int>& set) const {
    if (set.empty()) return;
    const int m = static_cast<int>(set.size());
    Eigen::MatrixXd w(n_, m);
    for (int k = 0; k < m; ++k) w.col(k) = system_.contact_direction(system_.contacts[static_cast<std::size_t>(set[static_cast<std::size_t>(k)])]);
    Eigen::MatrixXd minv_w(n_, m);
    apply_minv(w, minv_w);
    const Eigen::MatrixXd s = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(w.transpose() * minv_w).pseudoInverse();
    Eigen::Map<Eigen::VectorXd> v(x + n_, n_);
    v -= minv_w * (s * (w.transpose() * v));
    // exact zeros on the constraint (the projection leaves rounding of order 1e-16 |v|)
    for (int c : set) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        if (k.w.size() == 0 && k.b == Contact::ground) x[n_ + k.a] = 0.0;
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
        if (k.rigid()) {
            if (mode == 0) {
                mode = sign_of(f_(c));  // the limit is reached: slip in the direction of lambda
                if (mode == 0) mode = 1;
                at_rest.push_back(c);
            } else {
                mode = 0;  // tried in stick below
                candidates.push_back(c);
            }
        } else if (k.elastic()) {
            if (mode == 0) {
                mode = sign_of(f_(c));
                if (mode == 0) mode = 1;
                x[2 * n_ + c] = k.relative(x) + end_(c) - mode * k.limit / k.stiffness;
            } else {
                // reversal unless the relative acceleration keeps the direction (a touch)
                const Eigen::VectorXd w = system_.contact_direction(system_.contacts[static_cast<std::size_t>(c)]);
                if (mode * (w.dot(acc_) + end_acc_(c)) <= 0.0) mode = 0;
            }
        }
    }
    for (int c = 0; c < nc_; ++c)
        if (contacts_[static_cast<std::size_t>(c)].rigid() && mode_[static_cast<std::size_t>(c)] == 0)
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
    double* x = N_VGetArrayPointer(cvode_.state());
    for (int i = 0; i < 2 * n_ + nc_; ++i) x[i] = state(i);
    for (int i = 2 * n_ + nc_; i < length_; ++i) x[i] = 0.0;
    for (int c = 0; c < nc_; ++c) mode_[static_cast<std::size_t>(c)] = static_cast<int>(state(2 * n_ + nc_ + c));
    rebuild_stuck_set();
}

Eigen::VectorXd Integrator::store() const {
    const double* x = N_VGetArrayPointer(cvode_.state());
    Eigen::VectorXd state(2 * n_ + 2 * nc_);
    for (int i = 0; i < 2 * n_ + nc_; ++i) state(i) = x[i];
    for (int c = 0; c < nc_; ++c) state(2 * n_ + nc_ + c) = mode_[static_cast<std::size_t>(c)];
    return state;
}

void Integrator::reinit(double t) {
    long count = 0;
    CVodeGetNumRhsEvals(cvode_.memory(), &count);  // CVodeReInit resets the counters
    rhs_total_ += count;
    cvode_.check(CVodeReInit(cvode_.memory(), t, cvode_.state()), "CVodeReInit");
    cvode_.check(CVodeSetStopTime(cvode_.memory(), period_), "CVodeSetStopTime");
}

void Integrator::settle_initial(Eigen::VectorXd& state) {
    for (int c = 0; c < nc_; ++c) {
        const double m = state(2 * n_ + nc_ + c);
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        state(2 * n_ + nc_ + c) = k.event_driven() ? static_cast<double>(sign_of(m)) : 0.0;
        if (!k.has_state) state(2 * n_ + c) = 0.0;
    }
    load(state);
    double* x = N_VGetArrayPointer(cvode_.state());
    evaluate(0.0, x);
    std::vector<int> at_rest;
    for (int c = 0; c < nc_; ++c) {
        const ContactData& k = contacts_[static_cast<std::size_t>(c)];
        int& mode = mode_[static_cast<std::size_t>(c)];
        const double vc = velocity_c_(c);
        if (k.rigid()) {
            if (mode != 0 && mode * vc < 0.0) mode = sign_of(vc);
            if (mode == 0) at_rest.push_back(c);
        } else if (k.elastic()) {
            double& s = x[2 * n_ + c];
            if (mode != 0 && mode * vc < 0.0) mode = 0;
            const double end = k.relative(x) + end_(c);  // the spring's far end at t = 0
            if (mode != 0) s = end - mode * k.limit / k.stiffness;
            const double f = k.stiffness * (end - s);
            if (mode == 0 && std::abs(f) > k.limit) {
                s = end - sign_of(f) * k.limit / k.stiffness;
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
    double* x = N_VGetArrayPointer(cvode_.state());
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

    const std::vector<Output>& outputs = options_.outputs;
    r.output_max.assign(outputs.size(), 0.0);
    auto update_extremes = [&](const double* state) {
        for (int i = 0; i < n_; ++i) r.y_max[static_cast<std::size_t>(i)] = std::max(r.y_max[static_cast<std::size_t>(i)], std::abs(state[i]));
        for (std::size_t o = 0; o < outputs.size(); ++o) {
            double value = 0.0;
            for (const auto& [i, c] : outputs[o].terms()) value += c * state[i];
            r.output_max[o] = std::max(r.output_max[o], std::abs(value));
        }
    };
    auto update_margin = [&](double m) {
        r.margin_min = std::min(r.margin_min, m);
        r.margin_max = std::max(r.margin_max, m);
    };
    // contact 1's margin: coulomb only while stuck (slip phases are checked at the events)
    auto contact_margin = [&](const double* state) {
        if (nc_ == 0) return;
        if (contacts_[0].rigid() && mode_[0] != 0) return;
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
            if (!contacts_[k].event_driven()) ++r.switches;  // event-driven laws count modes
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
    std::vector<int> found(static_cast<std::size_t>(nc_ + n_) + combined_outputs_.size());
    double t = 0.0;
    const double v_guard = 1e-6, f_guard = 1e-6;  // safety net for missed roots (relative)

    while (true) {
        const int flag = CVode(cvode_.memory(), period_, cvode_.state(), &t, CV_ONE_STEP);
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
            cvode_.check(CVodeGetDky(cvode_.memory(), ts, 0, dky_), "CVodeGetDky");
            record_sample(next_sample, ts, d);
            ++next_sample;
        }
        evaluate(t, x);
        update_extremes(x);
        contact_margin(x);

        std::vector<int> hits;
        if (flag == CV_ROOT_RETURN) {
            cvode_.check(CVodeGetRootInfo(cvode_.memory(), found.data()), "CVodeGetRootInfo");
            for (int c = 0; c < nc_; ++c)
                if (found[static_cast<std::size_t>(c)] != 0 && contacts_[static_cast<std::size_t>(c)].event_driven())
                    hits.push_back(c);
        } else {
            double vscale = scale_ * drive_;  // the response's velocity scale
            for (int i = 0; i < n_; ++i) vscale = std::max(vscale, std::abs(x[n_ + i]));
            for (int c = 0; c < nc_; ++c) {
                const ContactData& k = contacts_[static_cast<std::size_t>(c)];
                if (!k.event_driven()) continue;
                const double g = mode_root(c);
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

void set_absolute_tolerances(double* tol, int n, int internal, double a, double drive, double period, double energy,
                             double fallback) {
    const int quad = 2 * n + internal;
    for (int i = 0; i < n; ++i) {
        tol[i] = a;
        tol[n + i] = a * drive;
        tol[quad + i] = tol[quad + n + i] = a * period;
    }
    for (int j = 0; j < internal; ++j) tol[2 * n + j] = a;
    for (int k = 0; k < 3; ++k) tol[quad + 2 * n + k] = energy;
    for (int i = 0; i < quad + 2 * n + 3; ++i)
        if (!(tol[i] > 0.0) || !std::isfinite(tol[i])) tol[i] = fallback;  // F = 0: no scale
}

}  // namespace hbf::detail
