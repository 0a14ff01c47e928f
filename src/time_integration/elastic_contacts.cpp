// hbfriction — time integration of contacts with a normal direction (elastic_contacts.hpp).
#include "time_integration/elastic_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "numerics/cvode_solver.hpp"
#include "time_integration/integrator.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/linear_limits.hpp"
#include "hbf/normal_contact.hpp"
#include "hbf/static_state.hpp"

namespace hbf::detail {

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr int max_dofs = 2000;  // dense M^-1 and state
enum Mode : int { separated = 0, stuck = 1, slipping = 2 };

/// One contact: its directions and the element's parameters.
struct Element {
    Eigen::MatrixXd tangential;  // N x d
    Eigen::VectorXd normal;      // N
    double kt = 0, kn = 0, mu = 0, offset = 0;  // offset: the normal force at v = 0
    int d = 1, first = 0;        // slider components; their first index in the slider block
};

/// The integrator of one frequency: CVODE over one period at a time.
class ElasticIntegrator {
public:
    ElasticIntegrator(const System& system, double omega, const TimeIntegrationOptions& options, double scale)
        : system_(system), omega_(omega), drive_(system.excitation_harmonic * omega), period_(2.0 * pi / omega),
          options_(options), n_(system.dofs()) {
        const Eigen::MatrixXd m(system.mass);
        minv_ = m.llt().solve(Eigen::MatrixXd::Identity(n_, n_));
        damping_ = Eigen::MatrixXd(system.damping);
        if (damping_.size() == 0) damping_ = Eigen::MatrixXd::Zero(n_, n_);
        stiffness_ = Eigen::MatrixXd(system.stiffness);
        static_load_ = system.static_load.size() > 0 ? system.static_load : Eigen::VectorXd::Zero(n_);
        for (const Contact& c : system.contacts) {
            const Eigen::MatrixXd w = system.contact_directions(c);
            Element e;
            e.d = static_cast<int>(w.cols()) - 1;
            e.tangential = w.leftCols(e.d);
            e.normal = w.col(e.d);
            const ElasticContact element = elastic_element(c);  // the law's parameters
            e.kt = element.tangential_stiffness;
            e.kn = element.normal_stiffness;
            e.mu = element.friction_coefficient;
            e.offset = element.normal_offset;
            e.first = sliders_;
            sliders_ += e.d;
            elements_.push_back(e);
        }
        m_ = static_cast<int>(elements_.size());
        quad_ = 2 * n_ + sliders_;
        length_ = quad_ + 2 * n_ + 3;  // quadratures: c1, s1 per DOF; friction, viscous, input energy
        mode_.assign(static_cast<std::size_t>(m_), stuck);
        cvode_ = std::make_unique<CvodeSolver>(length_, options.method == IntegrationMethod::adams ? CV_ADAMS : CV_BDF,
                                               rhs_callback, this, CvodeSolver::Warnings::record);
        absolute_ = cvode_->vector();
        dky_ = cvode_->vector();  // the samples' interpolation (one vector for every period)
        double* tol = N_VGetArrayPointer(absolute_);
        const double a = options.absolute_tolerance * scale;
        const double force = std::max(system.excitation.cwiseAbs().maxCoeff(), 1e-300);
        set_absolute_tolerances(tol, n_, sliders_, a, drive_, period_, a * 2.0 * pi * system.excitation_harmonic * force,
                                options.absolute_tolerance);
        cvode_->check(CVodeSVtolerances(cvode_->memory(), options.relative_tolerance, absolute_), "CVodeSVtolerances");
        if (options.method == IntegrationMethod::adams)
            cvode_->fixed_point();
        else
            cvode_->dense_newton();
        cvode_->check(CVodeSetMaxNumSteps(cvode_->memory(), options.max_steps_per_period), "CVodeSetMaxNumSteps");
        cvode_->check(CVodeRootInit(cvode_->memory(), 2 * m_, root_callback), "CVodeRootInit");
        std::vector<int> direction(static_cast<std::size_t>(2 * m_), -1);  // a mode ends where its root falls
        cvode_->check(CVodeSetRootDirection(cvode_->memory(), direction.data()), "CVodeSetRootDirection");
        cvode_->check(CVodeSetNoInactiveRootWarn(cvode_->memory()), "CVodeSetNoInactiveRootWarn");
    }

    int state_size() const { return 2 * n_ + sliders_ + m_; }

    /// Makes a public state consistent at t = 0 (modes from N and the cone, sliders on it).
    void settle(Eigen::VectorXd& state) {
        for (int c = 0; c < m_; ++c) mode_[static_cast<std::size_t>(c)] = static_cast<int>(state(2 * n_ + sliders_ + c));
        double* x = state.data();
        for (int c = 0; c < m_; ++c) settle_contact(c, x);
        for (int c = 0; c < m_; ++c) state(2 * n_ + sliders_ + c) = mode_[static_cast<std::size_t>(c)];
    }

    struct Record {
        bool ok = true;
        std::string failure;
        Eigen::VectorXd end;
        std::vector<double> stuck_time, slip_time, open_time;
        Eigen::VectorXcd harmonic1;
        double energy = 0, viscous = 0, input = 0;
        int switches = 0;
        // contact 1's stick indicator over the steps: |T| / (mu N) - 1 stuck, 0 slipping, 1 open
        double margin_min = std::numeric_limits<double>::infinity();
        double margin_max = -std::numeric_limits<double>::infinity();
        Eigen::VectorXd time;
        Eigen::MatrixXd displacement, velocity;
    };

    /// One period from `start` (consistent); samples the motion when `samples` > 0.
    Record period(const Eigen::VectorXd& start, int samples) {
        Record r;
        r.stuck_time.assign(static_cast<std::size_t>(m_), 0.0);
        r.slip_time = r.open_time = r.stuck_time;
        double* x = N_VGetArrayPointer(cvode_->state());
        std::copy(start.data(), start.data() + 2 * n_ + sliders_, x);
        std::fill(x + quad_, x + length_, 0.0);
        for (int c = 0; c < m_; ++c) mode_[static_cast<std::size_t>(c)] = static_cast<int>(start(2 * n_ + sliders_ + c));
        reinit(0.0);
        if (samples > 0) {
            r.time = Eigen::VectorXd::LinSpaced(samples, 0.0, period_ * (samples - 1) / samples);
            r.displacement.resize(samples, n_);
            r.velocity.resize(samples, n_);
        }
        std::vector<int> found(static_cast<std::size_t>(2 * m_));
        double t = 0.0, since = 0.0;
        int next = 0, events = 0;
        long steps = 0;
        auto account = [&](double until) {  // the modes' time since the last event
            for (int c = 0; c < m_; ++c) {
                const auto k = static_cast<std::size_t>(c);
                (mode_[k] == stuck ? r.stuck_time : mode_[k] == slipping ? r.slip_time : r.open_time)[k] += until - since;
            }
            since = until;
        };
        while (true) {
            const int flag = CVode(cvode_->memory(), period_, cvode_->state(), &t, CV_ONE_STEP);
            if (flag < 0) {
                r.ok = false;
                r.failure = std::string("CVODE failed at t = ") + format_number(t) + ": " + CVodeGetReturnFlagName(flag);
                return r;
            }
            if (++steps > options_.max_steps_per_period) {
                r.ok = false;
                r.failure = "more than " + std::to_string(options_.max_steps_per_period) + " steps in one period";
                return r;
            }
            if (m_ > 0) {
                const double margin = indicator(0, x);
                r.margin_min = std::min(r.margin_min, margin);
                r.margin_max = std::max(r.margin_max, margin);
            }
            while (next < samples && r.time(next) <= t) {
                cvode_->check(CVodeGetDky(cvode_->memory(), r.time(next), 0, dky_), "CVodeGetDky");
                const double* s = N_VGetArrayPointer(dky_);
                r.displacement.row(next) = Eigen::Map<const Eigen::VectorXd>(s, n_).transpose();
                r.velocity.row(next) = Eigen::Map<const Eigen::VectorXd>(s + n_, n_).transpose();
                ++next;
            }
            if (flag == CV_ROOT_RETURN) {
                cvode_->check(CVodeGetRootInfo(cvode_->memory(), found.data()), "CVodeGetRootInfo");
                account(t);
                int changed = 0;
                for (int c = 0; c < m_; ++c)
                    if (found[static_cast<std::size_t>(2 * c)] != 0 || found[static_cast<std::size_t>(2 * c + 1)] != 0)
                        changed += switch_mode(c, x, found[static_cast<std::size_t>(2 * c + 1)] != 0);
                r.switches += changed;
                if (++events > options_.max_events_per_period) {
                    r.ok = false;
                    r.failure = "more than " + std::to_string(options_.max_events_per_period) +
                                " contact events in one period (chattering?) at t = " + format_number(t);
                    return r;
                }
                if (period_ - t <= 1e-12 * period_) break;
                reinit(t);
            }
            if (flag == CV_TSTOP_RETURN || t >= period_) break;
        }
        account(period_);
        const double* q = x + quad_;
        r.harmonic1 = Eigen::VectorXcd(n_);
        for (int i = 0; i < n_; ++i) r.harmonic1(i) = std::complex<double>(q[i], -q[n_ + i]) * (omega_ / pi);
        r.energy = q[2 * n_];
        r.viscous = q[2 * n_ + 1];
        r.input = q[2 * n_ + 2];
        r.end.resize(state_size());
        r.end.head(2 * n_ + sliders_) = Eigen::Map<const Eigen::VectorXd>(x, 2 * n_ + sliders_);
        for (int c = 0; c < m_; ++c) r.end(2 * n_ + sliders_ + c) = mode_[static_cast<std::size_t>(c)];
        return r;
    }

private:
    /// The contact's quantities at state x (current mode): u, u', v, v', N, T, lambda.
    struct Local {
        Eigen::VectorXd u, du, T, s;
        double v = 0, dv = 0, N = 0, lambda = 0, trial = 0;  // trial: |k_t (u - s)|
    };
    Local local(int c, const double* x) const {
        const Element& e = elements_[static_cast<std::size_t>(c)];
        const Eigen::Map<const Eigen::VectorXd> y(x, n_), dy(x + n_, n_);
        Local l;
        l.u = e.tangential.transpose() * y;
        l.du = e.tangential.transpose() * dy;
        l.v = e.normal.dot(y);
        l.dv = e.normal.dot(dy);
        l.s = Eigen::Map<const Eigen::VectorXd>(x + 2 * n_ + e.first, e.d);
        const Eigen::VectorXd r = l.u - l.s;
        l.trial = e.kt * r.norm();
        const int mode = mode_[static_cast<std::size_t>(c)];
        l.N = mode == separated ? 0.0 : std::max(e.offset + e.kn * l.v, 0.0);
        l.T = Eigen::VectorXd::Zero(e.d);
        if (mode == stuck) l.T = e.kt * r;
        if (mode == slipping) {
            const double size = r.norm();
            if (size > 0.0) {
                const Eigen::VectorXd direction = r / size;
                l.T = e.mu * l.N * direction;
                l.lambda = direction.dot(l.du) - e.mu * e.kn * l.dv / e.kt;
            }
        }
        return l;
    }

    /// Contact c's stick indicator at x (contact_force.hpp: < 0 while it sticks).
    double indicator(int c, const double* x) const {
        const int mode = mode_[static_cast<std::size_t>(c)];
        if (mode == separated) return 1.0;
        if (mode == slipping) return 0.0;
        const Local l = local(c, x);
        const double limit = elements_[static_cast<std::size_t>(c)].mu * l.N;
        return limit > 0.0 ? std::min(l.trial / limit - 1.0, -std::numeric_limits<double>::denorm_min()) : -1.0;
    }

    void derivative(double t, const double* x, double* dx) const {
        const Eigen::Map<const Eigen::VectorXd> y(x, n_), dy(x + n_, n_);
        Eigen::VectorXd force = system_.excitation * std::cos(drive_ * t) + static_load_ - damping_ * dy - stiffness_ * y;
        double friction = 0.0;
        for (int c = 0; c < m_; ++c) {
            const Element& e = elements_[static_cast<std::size_t>(c)];
            const Local l = local(c, x);
            force -= e.tangential * l.T + e.normal * l.N;
            friction += l.T.dot(l.du) + l.N * l.dv;
            double* ds = dx + 2 * n_ + e.first;
            const int mode = mode_[static_cast<std::size_t>(c)];
            for (int j = 0; j < e.d; ++j)
                ds[j] = mode == separated || e.mu == 0.0 ? l.du(j)  // mu = 0: no tangential force
                        : mode == stuck   ? 0.0
                        : l.trial > 0.0   ? l.lambda * (l.u(j) - l.s(j)) * e.kt / l.trial
                                          : 0.0;
        }
        Eigen::Map<Eigen::VectorXd>(dx, n_) = dy;
        Eigen::Map<Eigen::VectorXd>(dx + n_, n_) = minv_ * force;
        double* q = dx + quad_;
        for (int i = 0; i < n_; ++i) {
            q[i] = y(i) * std::cos(omega_ * t);
            q[n_ + i] = y(i) * std::sin(omega_ * t);
        }
        q[2 * n_] = friction;
        q[2 * n_ + 1] = dy.dot(damping_ * dy);
        q[2 * n_ + 2] = system_.excitation.dot(dy) * std::cos(drive_ * t);
    }

    void roots(const double* x, double* g) const {
        for (int c = 0; c < m_; ++c) {
            const Element& e = elements_[static_cast<std::size_t>(c)];
            const Local l = local(c, x);
            const double closing = e.offset + e.kn * (l.v);
            switch (mode_[static_cast<std::size_t>(c)]) {
                case separated:
                    g[2 * c] = -closing;
                    g[2 * c + 1] = 1.0;
                    break;
                case stuck:
                    g[2 * c] = e.mu * l.N - l.trial;
                    g[2 * c + 1] = closing;
                    break;
                default:
                    g[2 * c] = e.mu == 0.0 ? 1.0 : l.lambda;  // mu = 0 slips freely while closed
                    g[2 * c + 1] = closing;
            }
        }
    }

    /// The mode after an event of contact c at x (`opening`: its normal root fell); returns
    /// 1 when the mode changed.
    int switch_mode(int c, double* x, bool opening) {
        const Element& e = elements_[static_cast<std::size_t>(c)];
        int& mode = mode_[static_cast<std::size_t>(c)];
        const int before = mode;
        double* s = x + 2 * n_ + e.first;
        const Eigen::Map<const Eigen::VectorXd> y(x, n_);
        const Eigen::VectorXd u = e.tangential.transpose() * y;
        if (mode == separated) {
            // closing with an unloaded spring: it sticks unless the trial force k_t |u'| grows
            // faster than the cone mu k_n v' (then it slips at once: the stick margin, 0 at
            // closing, would fall without a sign change, which root finding cannot see)
            const Local l = local(c, x);
            mode = e.kt * l.du.norm() > e.mu * e.kn * l.dv ? slipping : stuck;
            for (int j = 0; j < e.d; ++j) s[j] = u(j);
        } else if (opening) {
            mode = separated;
            for (int j = 0; j < e.d; ++j) s[j] = u(j);
        } else if (mode == stuck) {
            mode = slipping;
            if (local(c, x).lambda <= 0.0) mode = stuck;  // a graze: the cone is reached, not crossed
        } else {
            mode = stuck;
        }
        return mode != before ? 1 : 0;
    }

    /// Consistent mode and slider of contact c at t = 0.
    void settle_contact(int c, double* x) {
        const Element& e = elements_[static_cast<std::size_t>(c)];
        int& mode = mode_[static_cast<std::size_t>(c)];
        double* s = x + 2 * n_ + e.first;
        const Eigen::Map<const Eigen::VectorXd> y(x, n_);
        const Eigen::VectorXd u = e.tangential.transpose() * y;
        const double normal = e.offset + e.kn * e.normal.dot(y);
        if (normal <= 0.0) {
            mode = separated;
            for (int j = 0; j < e.d; ++j) s[j] = u(j);
            return;
        }
        if (mode == separated) mode = stuck;
        if (e.mu == 0.0) {  // no tangential force: the slider follows u
            mode = slipping;
            for (int j = 0; j < e.d; ++j) s[j] = u(j);
            return;
        }
        const Eigen::VectorXd r = u - Eigen::Map<const Eigen::VectorXd>(s, e.d);
        const double limit = e.mu * normal / e.kt;
        if (r.norm() > limit) {  // beyond the cone: onto it
            const Eigen::VectorXd onto = u - r * (limit / r.norm());
            for (int j = 0; j < e.d; ++j) s[j] = onto(j);
            mode = slipping;
        }
        if (mode == slipping && local(c, x).lambda <= 0.0) mode = stuck;
        if (mode != stuck && mode != slipping) mode = stuck;
    }

    void reinit(double t) {
        cvode_->check(CVodeReInit(cvode_->memory(), t, cvode_->state()), "CVodeReInit");
        cvode_->check(CVodeSetStopTime(cvode_->memory(), period_), "CVodeSetStopTime");
    }

    static int rhs_callback(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
        static_cast<const ElasticIntegrator*>(data)->derivative(t, N_VGetArrayPointer(x), N_VGetArrayPointer(dx));
        return 0;
    }
    static int root_callback(sunrealtype, N_Vector x, sunrealtype* g, void* data) {
        static_cast<const ElasticIntegrator*>(data)->roots(N_VGetArrayPointer(x), g);
        return 0;
    }

    const System& system_;
    Eigen::VectorXd static_load_;  // F_s (zero without one)
    const double omega_, drive_, period_;
    const TimeIntegrationOptions options_;
    const int n_;
    int m_ = 0, sliders_ = 0, quad_ = 0, length_ = 0;
    Eigen::MatrixXd minv_, damping_, stiffness_;
    std::vector<Element> elements_;
    std::vector<int> mode_;
    std::unique_ptr<CvodeSolver> cvode_;
    N_Vector absolute_ = nullptr, dky_ = nullptr;
};

}  // namespace

void summarise_contacts(PeriodicResponse& out) {
    if (out.contacts.empty()) {
        out.regime = "none";
        return;
    }
    out.stick_fraction = out.contacts.front().stick_fraction;
    out.regime = out.contacts.front().regime;
}

double refined_max(const Eigen::VectorXd& y) {
    const Eigen::Index n = y.size();
    Eigen::Index j = 0;
    y.cwiseAbs().maxCoeff(&j);
    const double a = std::abs(y((j + n - 1) % n)), b = std::abs(y(j)), c = std::abs(y((j + 1) % n));
    const double curvature = a - 2.0 * b + c;
    if (!(curvature < 0.0)) return b;
    const double offset = 0.5 * (a - c) / curvature;
    return b - 0.25 * (a - c) * offset;
}


bool has_elastic_contacts(const System& system) {
    return std::any_of(system.contacts.begin(), system.contacts.end(),
                       [](const Contact& c) { return contact_law(c.law).time_integrator() == TimeIntegrator::elastic_contacts; });
}

int elastic_state_size(const System& system) {
    int size = 2 * system.dofs();
    for (const Contact& c : system.contacts) size += static_cast<int>(system.contact_directions(c).cols());
    return size;
}

Eigen::VectorXd elastic_linear_stuck_state(const System& system, double omega) {
    const int n = system.dofs();
    Eigen::VectorXd state = Eigen::VectorXd::Zero(elastic_state_size(system));
    Eigen::MatrixXd k(system.stiffness);
    Eigen::VectorXd load = Eigen::VectorXd::Zero(n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    for (std::size_t i = 0; i < system.contacts.size(); ++i) {
        const Contact& c = system.contacts[i];
        const StuckElement normal = elements[i].back();
        const Eigen::VectorXd w = system.contact_directions(c).rightCols(1);
        k += normal.stiffness * w * w.transpose();
        load -= normal.offset * w;
    }
    if (system.static_load.size() > 0) load += system.static_load;
    const Eigen::VectorXd rest = k.fullPivLu().solve(load);
    const StuckResponse stuck = stuck_linear_response(system, omega);
    const Eigen::VectorXcd y = stuck.ok ? stuck.amplitude : Eigen::VectorXcd::Zero(n);
    state.head(n) = rest.allFinite() ? rest : Eigen::VectorXd::Zero(n);
    // The sliders where the static state puts no tangential force: centred, the stuck force
    // k_t (u - s) is the linear response's alone, of zero mean (not zero at t = 0).
    int at = 2 * n;
    for (const Contact& c : system.contacts) {
        const Eigen::MatrixXd w = system.contact_directions(c);
        const Eigen::VectorXd s = w.leftCols(w.cols() - 1).transpose() * state.head(n);
        state.segment(at, s.size()) = s;
        at += static_cast<int>(s.size());
    }
    state.head(n) += y.real();
    state.segment(n, n) = -system.excitation_harmonic * omega * y.imag();
    state.tail(static_cast<Eigen::Index>(system.contacts.size())).setConstant(1.0);  // stuck
    return state;
}

PeriodicResponse integrate_elastic_contacts(const System& system, double omega, const TimeIntegrationOptions& options,
                                            const Eigen::VectorXd* initial_state) {
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        if (contact_law(system.contacts[c].law).time_integrator() != TimeIntegrator::elastic_contacts)
            throw InvalidInput("contact " + std::to_string(c + 1) + ": law = " + to_string(system.contacts[c].law) +
                               " with contacts of law elastic: time integration takes law elastic alone (allowed: "
                               "every contact elastic, or no elastic contact)");
    if (!system.has_positive_definite_mass())
        throw InvalidInput("mass matrix: singular (massless DOFs) with law elastic: time integration of contacts with "
                           "a normal direction needs M positive definite");
    if (system.dofs() > max_dofs)
        throw InvalidInput("dofs = " + std::to_string(system.dofs()) + " with law elastic: time integration of "
                           "contacts with a normal direction allows at most " + std::to_string(max_dofs) + " DOFs");
    const int size = elastic_state_size(system);
    if (initial_state && (initial_state->size() != size || !initial_state->allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state->size()) +
                           " entries or non-finite values: allowed " + std::to_string(size) +
                           " finite values (2 N + the contacts' sliders and modes)");
    const double scale = options.displacement_scale > 0.0 ? options.displacement_scale : response_scale(system, omega);
    ElasticIntegrator integrator(system, omega, options, scale);
    Eigen::VectorXd x = initial_state ? *initial_state : Eigen::VectorXd::Zero(size);
    if (!initial_state) x.tail(static_cast<Eigen::Index>(system.contacts.size())).setConstant(1.0);  // stuck
    if (!initial_state && system.has_static_load()) {
        // At rest in the static state (static_state.hpp): the static load applied before the
        // vibration.
        const StaticState rest = static_state(system);
        if (!rest.ok) throw InvalidInput("static load: " + rest.message);
        x.head(system.dofs()) = rest.displacement;
        int at = 2 * system.dofs();
        for (std::size_t c = 0; c < system.contacts.size(); ++c) {
            const StaticContactState& k = rest.contacts[c];
            const auto d = k.slider.size();  // tangential components
            x.segment(at, d) = k.slider;
            x(size - static_cast<Eigen::Index>(system.contacts.size()) + static_cast<Eigen::Index>(c)) =
                k.state == "open" ? 0.0 : 1.0;  // separated, or stuck (on the cone where slipping)
            at += static_cast<int>(d);
        }
    }
    integrator.settle(x);
    PeriodicResponse out;
    out.omega = omega;
    out.displacement_scale = scale;
    const int n = system.dofs();
    const int samples = std::max(16 * options.samples_per_period, 4096);
    for (int k = 1; k <= options.max_periods; ++k) {
        if (const std::string why = k > 1 ? options.stop_reason() : std::string(); !why.empty()) {
            out.stop_after(k - 1, why);
            out.state = x;
            return out;
        }
        ElasticIntegrator::Record r = integrator.period(x, 0);
        out.periods = k;
        if (!r.ok) {
            out.message = r.failure + " (period " + std::to_string(k) + ", w = " + format_number(omega) + ")";
            out.state = x;
            return out;
        }
        // the Poincare change: displacements, sliders and velocities / omega, relative
        const Eigen::VectorXd& e = r.end;
        const int continuous = 2 * n + (size - 2 * n - static_cast<int>(system.contacts.size()));
        double size_now = 0.0, change = 0.0;
        for (int i = 0; i < continuous; ++i) {
            const double w = i >= n && i < 2 * n ? 1.0 / omega : 1.0;
            size_now = std::max(size_now, w * std::abs(e(i)));
            change = std::max(change, w * std::abs(e(i) - x(i)));
        }
        out.poincare_change = size_now > 0.0 ? change / size_now : change;
        x = e;
        if (k < options.min_periods || out.poincare_change > options.steady_tolerance) continue;
        // converged: the final period again, with its samples and metrics
        ElasticIntegrator::Record f = integrator.period(x, samples);
        if (!f.ok) {
            out.message = f.failure + " (the final period, w = " + format_number(omega) + ")";
            out.state = x;
            return out;
        }
        out.converged = true;
        out.state = x;
        out.message = "converged after " + std::to_string(k) + " periods (Poincare change " +
                      format_number(out.poincare_change) + ")";
        for (int i = 0; i < n; ++i) out.y_max.push_back(refined_max(f.displacement.col(i)));
        out.harmonic1 = f.harmonic1;
        for (int i = 0; i < n; ++i) out.y_amp1.push_back(std::abs(f.harmonic1(i)));
        for (const Output& o : options.outputs) {
            Eigen::VectorXd series(samples);
            for (int j = 0; j < samples; ++j) series(j) = o.of(f.displacement.row(j).transpose());
            out.output_max.push_back(refined_max(series));
            std::complex<double> h(0.0, 0.0);
            for (int i = 0; i < n; ++i) h += o.of(Eigen::VectorXd::Unit(n, i)) * f.harmonic1(i);
            out.output_amp1.push_back(std::abs(h));
        }
        const double period = 2.0 * pi / omega;
        for (std::size_t c = 0; c < system.contacts.size(); ++c) {
            ContactRegime regime = contact_regime(f.stuck_time[c], period);
            regime.separated_fraction = f.open_time[c] / period;
            regime.energy = std::numeric_limits<double>::quiet_NaN();
            out.contacts.push_back(regime);
        }
        summarise_contacts(out);
        out.switches = f.switches;
        out.stick_margin_min = std::isfinite(f.margin_min) ? f.margin_min : 0.0;
        out.stick_margin_max = std::isfinite(f.margin_max) ? f.margin_max : 0.0;
        out.energy = f.energy;
        out.viscous_energy = f.viscous;
        out.input_energy = f.input;
        const double reach = pi * system.excitation_harmonic * system.excitation.norm() * f.harmonic1.norm();
        out.energy_error = energy_imbalance(f.input, f.viscous, f.energy, reach);
        const int kept = options.samples_per_period;
        out.time.resize(kept);
        out.displacement.resize(kept, n);
        out.velocity.resize(kept, n);
        for (int j = 0; j < kept; ++j) {
            const int at = j * (samples / kept);
            out.time(j) = f.time(at);
            out.displacement.row(j) = f.displacement.row(at);
            out.velocity.row(j) = f.velocity.row(at);
        }
        if (out.energy_error > options.physics_tolerance()) {
            out.converged = false;
            out.message += "; but the energy balance fails: " + format_number(out.energy_error) + " > " +
                           format_number(options.physics_tolerance());
        }
        return out;
    }
    out.state = x;
    out.message = "no steady state within " + std::to_string(options.max_periods) + " periods (Poincare change " +
                  format_number(out.poincare_change) + ")";
    return out;
}

}  // namespace hbf::detail
