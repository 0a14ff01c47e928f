// hbfriction — the event-driven flow of law elastic over one period (elastic_integrator.hpp).
#include "time_integration/elastic_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <vector>

#include "time_integration/elastic_contacts.hpp"
#include "time_integration/integrator.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"
#include "hbf/static_state.hpp"

namespace hbf::detail {

namespace {
constexpr double pi = 3.14159265358979323846;
}  // namespace

ElasticIntegrator::ElasticIntegrator(const System& system, double omega, const TimeIntegrationOptions& options,
                                     double scale, bool variational)
    : system_(system), omega_(omega), drive_(system.excitation_harmonic * omega), period_(2.0 * pi / omega),
      options_(options), n_(system.dofs()), variational_(variational) {
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
        if (variational_) {
            e.minv_tangential = minv_ * e.tangential;
            e.minv_normal = minv_ * e.normal;
        }
        sliders_ += e.d;
        elements_.push_back(e);
    }
    m_ = static_cast<int>(elements_.size());
    quad_ = 2 * n_ + sliders_;
    length_ = quad_ + 2 * n_ + 3;  // quadratures: c1, s1 per DOF; friction, viscous, input energy
    phi_ = length_;
    const int c = continuous();
    if (variational_) {
        length_ += c * c;
        minv_stiffness_ = minv_ * stiffness_;
        minv_damping_ = minv_ * damping_;
    }
    mode_.assign(static_cast<std::size_t>(m_), stuck);
    const bool adams = options.method == IntegrationMethod::adams || variational_;
    cvode_ = std::make_unique<CvodeSolver>(length_, adams ? CV_ADAMS : CV_BDF, rhs_callback, this,
                                           CvodeSolver::Warnings::record);
    absolute_ = cvode_->vector();
    dky_ = cvode_->vector();  // the samples' interpolation (one vector for every period)
    double* tol = N_VGetArrayPointer(absolute_);
    const double a = options.absolute_tolerance * scale;
    const double force = std::max(system.excitation.cwiseAbs().maxCoeff(), 1e-300);
    set_absolute_tolerances(tol, n_, sliders_, a, drive_, period_, a * 2.0 * pi * system.excitation_harmonic * force,
                            options.absolute_tolerance);
    if (variational_) {  // Phi_ij in units of x_i / x_j: the state's tolerance over column j's unit
        for (int j = 0; j < c; ++j)
            for (int i = 0; i < c; ++i) tol[phi_ + j * c + i] = tol[i] / (tol[j] / options.absolute_tolerance);
    }
    cvode_->check(CVodeSVtolerances(cvode_->memory(), options.relative_tolerance, absolute_), "CVodeSVtolerances");
    if (adams)
        cvode_->fixed_point();
    else
        cvode_->dense_newton();
    cvode_->check(CVodeSetMaxNumSteps(cvode_->memory(), options.max_steps_per_period), "CVodeSetMaxNumSteps");
    cvode_->check(CVodeRootInit(cvode_->memory(), 2 * m_, root_callback), "CVodeRootInit");
    std::vector<int> direction(static_cast<std::size_t>(2 * m_), -1);  // a mode ends where its root falls
    cvode_->check(CVodeSetRootDirection(cvode_->memory(), direction.data()), "CVodeSetRootDirection");
    cvode_->check(CVodeSetNoInactiveRootWarn(cvode_->memory()), "CVodeSetNoInactiveRootWarn");
}

void ElasticIntegrator::settle(Eigen::VectorXd& state) {
    for (int c = 0; c < m_; ++c) mode_[static_cast<std::size_t>(c)] = static_cast<int>(state(2 * n_ + sliders_ + c));
    double* x = state.data();
    for (int c = 0; c < m_; ++c) settle_contact(c, x);
    for (int c = 0; c < m_; ++c) state(2 * n_ + sliders_ + c) = mode_[static_cast<std::size_t>(c)];
}

ElasticIntegrator::Record ElasticIntegrator::period(const Eigen::VectorXd& start, int samples, long max_steps) {
    const long step_limit = max_steps > 0 ? max_steps : options_.max_steps_per_period;
    Record r;
    r.stuck_time.assign(static_cast<std::size_t>(m_), 0.0);
    r.slip_time = r.open_time = r.stuck_time;
    r.margin_min = std::numeric_limits<double>::infinity();
    r.margin_max = -std::numeric_limits<double>::infinity();
    double* x = N_VGetArrayPointer(cvode_->state());
    std::copy(start.data(), start.data() + 2 * n_ + sliders_, x);
    std::fill(x + quad_, x + length_, 0.0);
    const int c = continuous();
    if (variational_) Eigen::Map<Eigen::MatrixXd>(x + phi_, c, c).setIdentity();
    for (int k = 0; k < m_; ++k) mode_[static_cast<std::size_t>(k)] = static_cast<int>(start(2 * n_ + sliders_ + k));
    reinit(0.0);
    if (samples > 0) {
        r.time = Eigen::VectorXd::LinSpaced(samples, 0.0, period_ * (samples - 1) / samples);
        r.displacement.resize(samples, n_);
        r.velocity.resize(samples, n_);
        r.friction_force.resize(samples, m_);
    }
    std::vector<int> found(static_cast<std::size_t>(2 * m_));
    double t = 0.0, since = 0.0;
    int next = 0, events = 0;
    long& steps = r.steps;
    auto account = [&](double until) {  // the modes' time since the last event
        for (int k = 0; k < m_; ++k) {
            const auto i = static_cast<std::size_t>(k);
            (mode_[i] == stuck ? r.stuck_time : mode_[i] == slipping ? r.slip_time : r.open_time)[i] += until - since;
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
        if (++steps > step_limit) {
            r.ok = false;
            r.failure = "more than " + std::to_string(step_limit) + " steps in one period";
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
            for (int k = 0; k < m_; ++k) r.friction_force(next, k) = local(k, s).T(0);
            ++next;
        }
        if (flag == CV_ROOT_RETURN) {
            cvode_->check(CVodeGetRootInfo(cvode_->memory(), found.data()), "CVodeGetRootInfo");
            account(t);
            int changed = 0;
            for (int k = 0; k < m_; ++k) {
                const auto i = static_cast<std::size_t>(k);
                if (found[2 * i] == 0 && found[2 * i + 1] == 0) continue;
                const int before = mode_[i];
                const bool opening = found[2 * i + 1] != 0;
                const int switched = variational_ ? switch_with_saltation(k, t, x, opening) : switch_mode(k, x, opening);
                if (switched != 0 && t < period_) r.events.push_back({t, k, before, mode_[i]});
                changed += switched;
            }
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
    if (!std::isfinite(r.margin_min)) r.margin_min = r.margin_max = 0.0;
    const double* q = x + quad_;
    r.harmonic1 = Eigen::VectorXcd(n_);
    for (int i = 0; i < n_; ++i) r.harmonic1(i) = std::complex<double>(q[i], -q[n_ + i]) * (omega_ / pi);
    r.energy = q[2 * n_];
    r.viscous = q[2 * n_ + 1];
    r.input = q[2 * n_ + 2];
    r.end.resize(state_size());
    r.end.head(2 * n_ + sliders_) = Eigen::Map<const Eigen::VectorXd>(x, 2 * n_ + sliders_);
    for (int k = 0; k < m_; ++k) r.end(2 * n_ + sliders_ + k) = mode_[static_cast<std::size_t>(k)];
    if (variational_) r.monodromy = Eigen::Map<const Eigen::MatrixXd>(x + phi_, c, c);
    return r;
}

ElasticIntegrator::Local ElasticIntegrator::local(int c, const double* x) const {
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
        // along u - s; where the slider sits at its node (a closing into slip), along u', the
        // direction in which u - s grows
        const double size = r.norm(), speed = l.du.norm();
        if (size > 0.0)
            l.direction = r / size;
        else if (speed > 0.0)
            l.direction = l.du / speed;
        if (l.direction.size() > 0) {
            l.T = e.mu * l.N * l.direction;
            l.lambda = l.direction.dot(l.du) - e.mu * e.kn * l.dv / e.kt;
        }
    }
    return l;
}

double ElasticIntegrator::indicator(int c, const double* x) const {
    const int mode = mode_[static_cast<std::size_t>(c)];
    if (mode == separated) return 1.0;
    if (mode == slipping) return 0.0;
    const Local l = local(c, x);
    const double limit = elements_[static_cast<std::size_t>(c)].mu * l.N;
    return limit > 0.0 ? std::min(l.trial / limit - 1.0, -std::numeric_limits<double>::denorm_min()) : -1.0;
}

void ElasticIntegrator::derivative(double t, const double* x, double* dx) const {
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
                    : mode == stuck || l.direction.size() == 0 ? 0.0
                                                               : l.lambda * l.direction(j);
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

void ElasticIntegrator::variational_derivative(const double* x, double* dx) const {
    const int c = continuous();
    const Eigen::Map<const Eigen::MatrixXd> phi(x + phi_, c, c);
    Eigen::Map<Eigen::MatrixXd> dphi(dx + phi_, c, c);
    const auto py = phi.topRows(n_), pv = phi.middleRows(n_, n_);
    dphi.topRows(n_) = pv;
    dphi.middleRows(n_, n_).noalias() = -minv_stiffness_ * py;
    dphi.middleRows(n_, n_).noalias() -= minv_damping_ * pv;
    for (int k = 0; k < m_; ++k) {
        const Element& e = elements_[static_cast<std::size_t>(k)];
        const int mode = mode_[static_cast<std::size_t>(k)];
        auto ds = dphi.middleRows(2 * n_ + e.first, e.d);
        const auto ps = phi.middleRows(2 * n_ + e.first, e.d);
        if (mode == separated || e.mu == 0.0) {
            ds.noalias() = e.tangential.transpose() * pv;  // s' = u'
            if (mode == separated) continue;
        }
        const Local l = local(k, x);
        // dN = k_n n^T dy where the normal spring is compressed
        const bool pressed = e.offset + e.kn * l.v > 0.0;
        Eigen::RowVectorXd dn = Eigen::RowVectorXd::Zero(c);
        if (pressed) dn.noalias() = e.kn * (e.normal.transpose() * py);
        Eigen::MatrixXd dt = Eigen::MatrixXd::Zero(e.d, c);
        if (e.mu == 0.0) {
            // no tangential force
        } else if (mode == stuck) {
            dt.noalias() = e.kt * (e.tangential.transpose() * py - ps);
            ds.setZero();
        } else {  // slipping: T = mu N t, s' = lambda t
            const double size = (l.u - l.s).norm();
            if (l.direction.size() > 0) {
                const Eigen::VectorXd& dir = l.direction;
                // t = (u - s) / |u - s|; where |u - s| = 0 (the instant of a closing into slip) t
                // is u''s direction and its derivative is left out (zero in 2D)
                const Eigen::MatrixXd project =
                    size > 0.0 ? Eigen::MatrixXd((Eigen::MatrixXd::Identity(e.d, e.d) - dir * dir.transpose()) / size)
                               : Eigen::MatrixXd::Zero(e.d, e.d);
                const Eigen::MatrixXd dr = e.tangential.transpose() * py - ps;  // d (u - s)
                const Eigen::MatrixXd ddir = project * dr;
                dt.noalias() = e.mu * (dir * dn + l.N * ddir);
                const Eigen::RowVectorXd dlambda = l.du.transpose() * ddir +
                                                   dir.transpose() * (e.tangential.transpose() * pv) -
                                                   (e.mu * e.kn / e.kt) * (e.normal.transpose() * pv);
                ds.noalias() = dir * dlambda + l.lambda * ddir;
            } else {
                ds.setZero();
            }
        }
        dphi.middleRows(n_, n_).noalias() -= e.minv_tangential * dt;
        dphi.middleRows(n_, n_).noalias() -= e.minv_normal * dn;
    }
}

void ElasticIntegrator::roots(const double* x, double* g) const {
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

Eigen::VectorXd ElasticIntegrator::root_gradient(int c, const double* x, bool normal) const {
    const Element& e = elements_[static_cast<std::size_t>(c)];
    const int mode = mode_[static_cast<std::size_t>(c)];
    Eigen::VectorXd g = Eigen::VectorXd::Zero(continuous());
    auto gy = g.head(n_);
    auto gv = g.segment(n_, n_);
    auto gs = g.segment(2 * n_ + e.first, e.d);
    if (mode == separated) {  // -(offset + k_n v)
        gy = -e.kn * e.normal;
        return g;
    }
    if (normal) {  // offset + k_n v
        gy = e.kn * e.normal;
        return g;
    }
    const Local l = local(c, x);
    const double size = (l.u - l.s).norm();
    if (mode == stuck) {  // mu N - k_t |u - s|
        if (!(size > 0.0)) return g;
        const Eigen::VectorXd dir = (l.u - l.s) / size;
        gy = e.mu * e.kn * e.normal - e.kt * (e.tangential * dir);
        gs = e.kt * dir;
        return g;
    }
    // slipping: lambda = t . u' - mu k_n v' / k_t
    if (l.direction.size() == 0) return g;
    const Eigen::VectorXd& dir = l.direction;
    const Eigen::VectorXd pdu = size > 0.0 ? Eigen::VectorXd((l.du - dir * dir.dot(l.du)) / size)
                                           : Eigen::VectorXd::Zero(e.d);
    gy = e.tangential * pdu;
    gs = -pdu;
    gv = e.tangential * dir - (e.mu * e.kn / e.kt) * e.normal;
    return g;
}

int ElasticIntegrator::switch_mode(int c, double* x, bool opening) {
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

int ElasticIntegrator::switch_with_saltation(int c, double t, double* x, bool opening) {
    const int k = continuous();
    const Element& e = elements_[static_cast<std::size_t>(c)];
    const int before = mode_[static_cast<std::size_t>(c)];
    const Eigen::VectorXd gradient = root_gradient(c, x, opening && before != separated);
    std::vector<double> field(static_cast<std::size_t>(phi_));  // the state and its quadratures
    derivative(t, x, field.data());
    const Eigen::VectorXd f_before = Eigen::Map<const Eigen::VectorXd>(field.data(), k);
    const int changed = switch_mode(c, x, opening);
    if (changed == 0) return 0;
    derivative(t, x, field.data());
    const Eigen::VectorXd f_after = Eigen::Map<const Eigen::VectorXd>(field.data(), k);
    Eigen::Map<Eigen::MatrixXd> phi(x + phi_, k, k);
    // the event time's shift, -grad g . dx / (grad g . f-), from Phi before the reset
    const double rate = gradient.dot(f_before);
    const Eigen::RowVectorXd shift =
        rate != 0.0 ? Eigen::RowVectorXd(gradient.transpose() * phi / rate) : Eigen::RowVectorXd::Zero(k);
    // the reset R: a slider set to u = W^T y at an opening or a closing
    Eigen::VectorXd reset_f = f_before;
    if (before == separated || mode_[static_cast<std::size_t>(c)] == separated) {
        phi.middleRows(2 * n_ + e.first, e.d) = e.tangential.transpose() * phi.topRows(n_);
        reset_f.segment(2 * n_ + e.first, e.d) = e.tangential.transpose() * f_before.head(n_);
    }
    phi.noalias() += (f_after - reset_f) * shift;
    return changed;
}

void ElasticIntegrator::settle_contact(int c, double* x) {
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
    if (r.norm() > limit || (mode == slipping && r.norm() > 0.0)) {  // beyond the cone, or slipping: onto it
        const Eigen::VectorXd onto = u - r * (limit / r.norm());
        for (int j = 0; j < e.d; ++j) s[j] = onto(j);
        mode = slipping;
    }
    if (mode == slipping && local(c, x).lambda <= 0.0) mode = stuck;
    if (mode != stuck && mode != slipping) mode = stuck;
}

void ElasticIntegrator::reinit(double t) {
    cvode_->check(CVodeReInit(cvode_->memory(), t, cvode_->state()), "CVodeReInit");
    cvode_->check(CVodeSetStopTime(cvode_->memory(), period_), "CVodeSetStopTime");
}

int ElasticIntegrator::rhs_callback(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
    const auto* self = static_cast<const ElasticIntegrator*>(data);
    self->derivative(t, N_VGetArrayPointer(x), N_VGetArrayPointer(dx));
    if (self->variational_) self->variational_derivative(N_VGetArrayPointer(x), N_VGetArrayPointer(dx));
    return 0;
}

int ElasticIntegrator::root_callback(sunrealtype, N_Vector x, sunrealtype* g, void* data) {
    static_cast<const ElasticIntegrator*>(data)->roots(N_VGetArrayPointer(x), g);
    return 0;
}

void elastic_metrics(const System& system, double omega, const ElasticIntegrator::Record& f,
                     const TimeIntegrationOptions& options, PeriodicResponse& out) {
    const int n = system.dofs();
    const auto samples = static_cast<int>(f.time.size());
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
        if (samples > 0) {  // N = max(0, n_0 + k_n v) on the period's equally spaced samples
            const Eigen::MatrixXd w = system.contact_directions(system.contacts[c]);
            const ElasticContact e = elastic_element(system.contacts[c]);
            const Eigen::VectorXd normal =
                ((f.displacement * w.col(w.cols() - 1)).array() * e.normal_stiffness + e.normal_offset).cwiseMax(0.0);
            regime.normal_mean = normal.mean();
            regime.normal_amplitude = 0.5 * (normal.maxCoeff() - normal.minCoeff());
        }
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
}

void check_elastic_system(const System& system) {
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        if (contact_law(system.contacts[c].law).time_integrator() != TimeIntegrator::elastic_contacts)
            throw InvalidInput("contact " + std::to_string(c + 1) + ": law = " + to_string(system.contacts[c].law) +
                               " with contacts of law elastic: time integration takes law elastic alone (allowed: "
                               "every contact elastic, or no elastic contact)");
    if (!system.has_positive_definite_mass())
        throw InvalidInput("mass matrix: singular (massless DOFs) with law elastic: time integration of contacts with "
                           "a normal direction needs M positive definite");
    if (system.dofs() > elastic_max_dofs)
        throw InvalidInput("dofs = " + std::to_string(system.dofs()) + " with law elastic: time integration of "
                           "contacts with a normal direction allows at most " + std::to_string(elastic_max_dofs) +
                           " DOFs");
}

Eigen::VectorXd elastic_rest_state(const System& system) {
    const int n = system.dofs(), size = elastic_state_size(system);
    const auto nc = static_cast<Eigen::Index>(system.contacts.size());
    Eigen::VectorXd x = Eigen::VectorXd::Zero(size);
    x.tail(nc).setConstant(1.0);  // stuck
    if (!system.has_static_load()) return x;
    // At rest in the static state (static_state.hpp): the static load applied before the
    // vibration.
    const StaticState rest = static_state(system);
    if (!rest.ok) throw InvalidInput("static load: " + rest.message);
    x.head(n) = rest.displacement;
    int at = 2 * n;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const StaticContactState& k = rest.contacts[c];
        const auto d = k.slider.size();  // tangential components
        x.segment(at, d) = k.slider;
        x(size - nc + static_cast<Eigen::Index>(c)) = k.state == "open" ? 0.0 : 1.0;  // separated, or stuck
        at += static_cast<int>(d);
    }
    return x;
}

}  // namespace hbf::detail
