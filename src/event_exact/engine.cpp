// hbfriction — the flow engine of the event-exact solver (engine.hpp), and exact_flow.
#include "event_exact/engine.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "event_exact/fast_modes.hpp"
#include "hbf/error.hpp"
#include "event_exact/polynomial.hpp"
#include "event_exact/validation.hpp"

namespace hbf::detail::exact {

namespace {
int sign_of(double x) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0); }

}  // namespace

Eigen::VectorXd Step::state(double s) const {
    Eigen::VectorXd z = evaluate(u, s);
    if (!fast()) return z;
    const FastModes& f = data->fast;
    for (std::size_t k = 0; k < active.size(); ++k) {
        const Eigen::Index j = active[k];
        const std::complex<double> c = d(static_cast<Eigen::Index>(k)) * std::exp(f.lambda(j) * (h * s));
        z += (f.right.col(j) * c).real();
    }
    return z;
}

Eigen::VectorXd Step::rate(double s) const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(u.rows());
    for (Eigen::Index k = u.cols() - 1; k >= 1; --k) {
        z *= s;
        z += static_cast<double>(k) * u.col(k);
    }
    z /= h;
    if (!fast()) return z;
    const FastModes& f = data->fast;
    for (std::size_t k = 0; k < active.size(); ++k) {
        const Eigen::Index j = active[k];
        const std::complex<double> c = d(static_cast<Eigen::Index>(k)) * f.lambda(j) * std::exp(f.lambda(j) * (h * s));
        z += (f.right.col(j) * c).real();
    }
    return z;
}

namespace {
/// g with the step's fast exponentials: amplitude weight(j) d_j and rate lambda_j h for each
/// active fast mode j (weight(j): the signal's row times the mode's right eigenvector).
template <class Weight>
Signal with_exponentials(const Step& st, Signal g, const Weight& weight) {
    if (!st.fast()) return g;
    const FastModes& f = st.data->fast;
    const Eigen::Index na = static_cast<Eigen::Index>(st.active.size());
    g.amp.resize(na);
    g.rate.resize(na);
    for (Eigen::Index k = 0; k < na; ++k) {
        const Eigen::Index j = st.active[static_cast<std::size_t>(k)];
        g.amp(k) = weight(j) * st.d(k);
        g.rate(k) = f.lambda(j) * st.h;
    }
    return g;
}
}  // namespace

Signal Step::signal(const Eigen::RowVectorXd& row) const {
    Signal g;
    g.poly.noalias() = row * u;
    const Eigen::RowVectorXcd complex_row = row.cast<std::complex<double>>();
    return with_exponentials(*this, std::move(g), [&](Eigen::Index j) { return complex_row.dot(data->fast.right.col(j)); });
}

Signal Step::signal(Eigen::Index i) const {
    Signal g;
    g.poly = u.row(i);
    return with_exponentials(*this, std::move(g), [&](Eigen::Index j) { return data->fast.right(i, j); });
}

Eigen::VectorXcd Step::fast_integral(std::complex<double> mu) const {
    Eigen::VectorXcd sum = Eigen::VectorXcd::Zero(u.rows());
    if (!fast()) return sum;
    const FastModes& f = data->fast;
    for (std::size_t k = 0; k < active.size(); ++k) {
        const Eigen::Index j = active[k];
        sum += f.right.col(j) * (d(static_cast<Eigen::Index>(k)) * exp_integral(f.lambda(j) + mu, s_end * h));
    }
    return sum;
}

PatternEngine::PatternEngine(double omega, bool split, int dofs, int contacts, int nz)
    : omega_(omega), period_(2.0 * pi / omega), split_(split), n_dofs_(dofs), n_contacts_(contacts), nz_(nz),
      n_(nz + 3) {}

const ModeData& PatternEngine::mode(const Modes& modes) {
    const Modes key = cache_key(modes);
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    return cache_.emplace(key, build(modes)).first->second;
}

void PatternEngine::restore_forcing(Eigen::VectorXd& zhat, double t) const {
    zhat(cos_index()) = std::cos(omega_ * t);
    zhat(sin_index()) = std::sin(omega_ * t);
    zhat(one_index()) = 1.0;
}

bool PatternEngine::record_events(Flow& out, double t, const Modes& before, const Modes& after,
                                  const Eigen::VectorXd& zhat, int& events, int max_events) const {
    for (int c = 0; c < n_contacts_; ++c) {
        const int from = before[static_cast<std::size_t>(c)], to = after[static_cast<std::size_t>(c)];
        if (to == from) continue;
        // A phase of no length (the contact's event at this instant led here): one event.
        std::size_t k = out.events.size();
        while (k > 0 && std::abs(out.events[k - 1].time - t) <= 1e-12 * period_ && out.events[k - 1].contact != c) --k;
        if (k > 0 && std::abs(out.events[k - 1].time - t) <= 1e-12 * period_ && out.events[k - 1].mode_after == from) {
            ExactEvent& e = out.events[k - 1];
            e.mode_after = to;
            out.event_states[k - 1] = zhat;
            if (e.mode_before == to) {  // back where it was
                out.events.erase(out.events.begin() + static_cast<std::ptrdiff_t>(k - 1));
                out.event_states.erase(out.event_states.begin() + static_cast<std::ptrdiff_t>(k - 1));
            }
            continue;
        }
        out.events.push_back({t, c, from, to});
        out.event_states.push_back(zhat);
    }
    if (++events <= max_events) return true;
    out.ok = false;
    out.message = "more than " + std::to_string(max_events) + " contact events in one period at t = " + format_number(t) +
                  " (chattering)";
    return false;
}

void PatternEngine::finish(ModeData& m) const {
    // The fast modes split off; the step short against the slow ones (|lambda| h <= 1) and T / 24.
    double rho = omega_;
    m.a_slow = m.a;
    if (split_ && split_fast_modes(m.a, nz_, n_dofs_, omega_, m, rho)) {
        for (Guard& g : m.guards) g.fast = g.row.cast<std::complex<double>>() * m.fast.right;
    } else {
        m.fast = FastModes{};
        m.a_slow = m.a;
        if (!split_ && nz_ > 0) {  // the step against the fastest mode
            Eigen::EigenSolver<Eigen::MatrixXd> eigen(m.a.topLeftCorner(nz_, nz_), false);
            rho = std::max(omega_, eigen.info() == Eigen::Success
                                       ? eigen.eigenvalues().cwiseAbs().maxCoeff()
                                       : m.a.topLeftCorner(nz_, nz_).cwiseAbs().rowwise().sum().maxCoeff());
        }
    }
    m.h = std::min(period_ / 24.0, 1.0 / rho);
    m.step_exp = m.exponential(m.h);
}

Engine::Engine(const System& system, double omega, bool split)
    : PatternEngine(omega, split, system.dofs(), static_cast<int>(system.contacts.size()),
                    2 * system.dofs() + static_cast<int>(system.contacts.size())),
      system_(system) {
    mass_inverse_ = Eigen::MatrixXd(system.mass).llt().solve(Eigen::MatrixXd::Identity(n_dofs_, n_dofs_));
    for (const Contact& c : system.contacts) {
        directions_.push_back(system.contact_direction(c));
        rigid_.push_back(rigid_slider(c) ? 1 : 0);
    }
}

Modes Engine::settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) {
    const int c = trigger.contact;
    if (modes[static_cast<std::size_t>(c)] != 0) {
        modes[static_cast<std::size_t>(c)] = 0;  // slip reached v = 0: try stick
    } else {
        const double f = mode(modes).force.row(c).dot(zhat);
        modes[static_cast<std::size_t>(c)] = f >= 0.0 ? 1 : -1;
    }
    return release_overloaded(zhat, modes);
}

Modes Engine::release_overloaded(const Eigen::VectorXd& zhat, Modes modes) {
    for (int round = 0; round <= n_contacts_; ++round) {
        const ModeData& m = mode(modes);
        int worst = -1;
        double overload = 1.0 + 1e-12;
        for (int c = 0; c < n_contacts_; ++c) {
            if (!coulomb(c) || modes[static_cast<std::size_t>(c)] != 0) continue;
            const double ratio = std::abs(m.force.row(c).dot(zhat)) / contact(c).friction_limit;
            if (ratio > overload) {
                overload = ratio;
                worst = c;
            }
        }
        if (worst < 0) break;
        modes[static_cast<std::size_t>(worst)] = m.force.row(worst).dot(zhat) >= 0.0 ? 1 : -1;
    }
    return modes;
}

Modes Engine::initial_modes(Eigen::VectorXd& zhat, const Modes& hints) {
    Modes modes(static_cast<std::size_t>(n_contacts_), 0);
    const double v_scale = 1.0 + zhat.segment(n_dofs_, n_dofs_).cwiseAbs().maxCoeff();
    for (int c = 0; c < n_contacts_; ++c) {
        const Contact& k = contact(c);
        const int hint = hints.empty() ? 0 : hints[static_cast<std::size_t>(c)];
        const double v = velocity(c, zhat);
        if (coulomb(c)) {
            modes[static_cast<std::size_t>(c)] = (hint == 0 && std::abs(v) <= 1e-10 * v_scale) ? 0 : sign_of(v);
            if (modes[static_cast<std::size_t>(c)] == 0 && hint != 0 && v == 0.0) modes[static_cast<std::size_t>(c)] = hint;
        } else {
            const int s_index = 2 * n_dofs_ + c;
            // The spring's far end: q + p cos(omega t), moving at v - p omega sin(omega t).
            const double q = spring_end(c, zhat);
            const double end_velocity = v - k.base_motion * omega_ * zhat(sin_index());
            const double f = k.stiffness * (q - zhat(s_index));
            if (std::abs(f) >= k.friction_limit * (1.0 - 1e-12)) {
                const int dir = sign_of(f);
                zhat(s_index) = q - dir * k.friction_limit / k.stiffness;
                modes[static_cast<std::size_t>(c)] =
                    (end_velocity * dir > 0.0 || (end_velocity == 0.0 && hint == dir)) ? dir : 0;
            }
        }
    }
    return release_overloaded(zhat, modes);
}

PatternEngine::Flow PatternEngine::flow(Eigen::VectorXd zhat, Modes modes, double t0, double duration, bool monodromy,
                          bool record, int max_events) {
    Flow out;
    if (monodromy) out.psi = Eigen::MatrixXd::Identity(n_, n_);
    double t = t0;
    const double t_end = t0 + duration;
    int events = 0;
    Eigen::MatrixXd buffer;
    Step st;
    const int nd = n_dofs_;
    while (t < t_end) {
        const ModeData& m = mode(modes);
        const double remaining = t_end - t;
        const bool last = remaining <= m.h * (1.0 + 1e-12);
        const double s_end = last ? remaining / m.h : 1.0;
        // The fast modes present (above rounding in the displacements or the velocities); the
        // Taylor polynomial carries the rest.
        st.active.clear();
        Eigen::VectorXd slow = zhat;
        if (m.fast.size() > 0) {
            const Eigen::VectorXcd d = m.fast.left * zhat;
            const double y_size = std::max(zhat.head(nd).cwiseAbs().maxCoeff(),
                                           zhat.segment(2 * nd, nz_ - 2 * nd).cwiseAbs().maxCoeff());
            const double v_size = zhat.segment(nd, nd).cwiseAbs().maxCoeff();
            for (Eigen::Index j = 0; j < m.fast.size(); ++j) {
                const double size = std::abs(d(j)) * m.fast.right_size(j);
                if (size > 1e-16 * y_size || size > 1e-16 * v_size) st.active.push_back(j);
            }
            st.d.resize(static_cast<Eigen::Index>(st.active.size()));
            for (std::size_t k = 0; k < st.active.size(); ++k) {
                const Eigen::Index j = st.active[k];
                st.d(static_cast<Eigen::Index>(k)) = d(j);
                slow -= (m.fast.right.col(j) * d(j)).real();
            }
        }
        if (m.fast.size() > 0) {
            const Eigen::Index used = step_polynomial(m.a_slow, m.slow_coordinates * slow, m.h, buffer);
            st.u.noalias() = m.slow_basis * buffer.leftCols(used);
        } else {
            const Eigen::Index used = step_polynomial(m.a_slow, slow, m.h, buffer);
            st.u = buffer.leftCols(used);
        }
        st.t0 = t;
        st.h = m.h;
        st.data = &m;
        double best = std::numeric_limits<double>::infinity();
        const Guard* trigger = nullptr;
        for (const Guard& g : m.guards) {
            const double eta = 1e-12 * (g.row.cwiseAbs().array() * zhat.transpose().cwiseAbs().array()).sum();
            const double s = first_root(st.signal(g.row), s_end, eta);
            if (s >= 0.0 && s < best) {
                best = s;
                trigger = &g;
            }
        }
        if (!trigger) {
            st.s_end = s_end;
            if (record) out.steps.push_back({st.t0, st.h, s_end, modes, st.u, &m, st.active, st.d});
            const Eigen::VectorXd next = st.state(s_end);
            if (monodromy) out.psi = (s_end == 1.0 ? m.step_exp : m.exponential(s_end * m.h)) * out.psi;
            zhat = next;
            t = last ? t_end : t + m.h;
            if (m.fast.size() > 0) restore_constraints(zhat, modes, t);
            continue;
        }
        st.s_end = best;
        if (record) out.steps.push_back({st.t0, st.h, best, modes, st.u, &m, st.active, st.d});
        zhat = st.state(best);
        if (monodromy) out.psi = m.exponential(best * m.h) * out.psi;
        t = std::min(t + best * m.h, t_end);
        if (m.fast.size() > 0) restore_constraints(zhat, modes, t);
        const Modes next = settle(zhat, modes, *trigger);
        if (monodromy) {
            const Eigen::MatrixXd& a_after = mode(next).a;
            const ModeData& before = mode(modes);  // the cache may have grown: look up again
            const Eigen::VectorXd f_minus = before.a * zhat, f_plus = a_after * zhat;
            const Eigen::RowVectorXd row = before.guards[static_cast<std::size_t>(trigger - m.guards.data())].row;
            const double denominator = row.dot(f_minus);
            const double scale = (row.cwiseAbs().array() * f_minus.transpose().cwiseAbs().array()).sum();
            if (std::abs(denominator) > 1e-10 * scale && scale > 0.0) {
                out.psi = (Eigen::MatrixXd::Identity(n_, n_) + (f_plus - f_minus) * row / denominator) * out.psi;
            } else {
                out.grazing = true;
            }
        }
        const bool counted = record_events(out, t, modes, next, zhat, events, max_events);
        modes = next;
        if (!counted) break;
    }
    out.zhat = zhat;
    out.modes = modes;
    return out;
}

void Engine::restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const {
    const int nd = n_dofs_;
    restore_forcing(zhat, t);
    std::vector<int> stuck;
    for (int c = 0; c < n_contacts_; ++c) {
        const int mode = modes[static_cast<std::size_t>(c)];
        if (coulomb(c)) {
            zhat(2 * nd + c) = 0.0;
            if (mode == 0) stuck.push_back(c);
        } else if (mode != 0) {
            zhat(2 * nd + c) = spring_end(c, zhat) - mode * contact(c).friction_limit / contact(c).stiffness;
        }
    }
    if (stuck.empty()) return;
    // v on w_c^T v = 0 (the stuck contacts), the M-orthogonal projection the pattern's flow keeps.
    const int s = static_cast<int>(stuck.size());
    Eigen::MatrixXd w(nd, s);
    for (int j = 0; j < s; ++j) w.col(j) = direction(stuck[static_cast<std::size_t>(j)]);
    const Eigen::MatrixXd mw = mass_inverse_ * w;
    const Eigen::VectorXd slip = w.transpose() * zhat.segment(nd, nd);
    zhat.segment(nd, nd) -= mw * (w.transpose() * mw).completeOrthogonalDecomposition().solve(slip);
}

ModeData Engine::build(const Modes& modes) const {
    const int n = n_, nd = n_dofs_;
    ModeData m;
    m.force = Eigen::MatrixXd::Zero(n_contacts_, n);
    std::vector<int> stuck;
    for (int c = 0; c < n_contacts_; ++c) {
        const Contact& k = contact(c);
        const int mode = modes[static_cast<std::size_t>(c)];
        if (mode != 0) {
            m.force(c, one_index()) = mode * k.friction_limit;
        } else if (!coulomb(c)) {  // an elastic slider's spring: k (w^T y + p cos - s)
            m.force.row(c).head(nd) = k.stiffness * direction(c).transpose();
            m.force(c, 2 * nd + c) = -k.stiffness;
            m.force(c, cos_index()) = k.stiffness * k.base_motion;
        } else {
            stuck.push_back(c);
        }
    }
    // Acceleration without the stuck Coulomb contacts' forces: M^-1 (F cos - C y' - K y - sum w f).
    Eigen::MatrixXd base = Eigen::MatrixXd::Zero(nd, n);
    base.col(cos_index()) = system_.excitation;
    base.leftCols(nd) = -Eigen::MatrixXd(system_.stiffness);
    base.middleCols(nd, nd) = -Eigen::MatrixXd(system_.damping);
    for (int c = 0; c < n_contacts_; ++c)
        if (std::find(stuck.begin(), stuck.end(), c) == stuck.end()) base -= direction(c) * m.force.row(c);
    Eigen::MatrixXd acceleration = mass_inverse_ * base;
    if (!stuck.empty()) {
        const int s = static_cast<int>(stuck.size());
        Eigen::MatrixXd w(nd, s);
        for (int j = 0; j < s; ++j) w.col(j) = direction(stuck[static_cast<std::size_t>(j)]);
        const Eigen::MatrixXd g = w.transpose() * mass_inverse_ * w;
        const Eigen::MatrixXd lambda =
            g.completeOrthogonalDecomposition().pseudoInverse() * (w.transpose() * acceleration);
        acceleration -= mass_inverse_ * w * lambda;
        for (int j = 0; j < s; ++j) m.force.row(stuck[static_cast<std::size_t>(j)]) = lambda.row(j);
    }
    m.a = Eigen::MatrixXd::Zero(n, n);
    m.a.block(0, nd, nd, nd).setIdentity();
    m.a.middleRows(nd, nd) = acceleration;
    for (int c = 0; c < n_contacts_; ++c)
        if (!coulomb(c) && modes[static_cast<std::size_t>(c)] != 0) {  // s' = w^T v - p omega sin
            m.a.row(2 * nd + c).segment(nd, nd) = direction(c).transpose();
            m.a(2 * nd + c, sin_index()) = -omega_ * contact(c).base_motion;
        }
    m.a(cos_index(), sin_index()) = -omega_;
    m.a(sin_index(), cos_index()) = omega_;
    for (int c = 0; c < n_contacts_; ++c) {
        const int mode = modes[static_cast<std::size_t>(c)];
        const double limit = contact(c).friction_limit;
        if (mode != 0) {
            Guard g{c, Eigen::RowVectorXd::Zero(n), {}};
            g.row.segment(nd, nd) = mode * direction(c).transpose();
            g.row(sin_index()) = -mode * omega_ * contact(c).base_motion;  // the spring's far end
            m.guards.push_back(g);
        } else {
            for (int sign : {1, -1}) {
                Guard g{c, -sign * m.force.row(c), {}};
                g.row(one_index()) += limit;
                m.guards.push_back(g);
            }
        }
    }
    finish(m);
    return m;
}

const Step& step_at(const std::vector<Step>& steps, double t) {
    std::size_t k = 0;
    while (k + 1 < steps.size() && steps[k + 1].t0 <= t) ++k;
    return steps[k];
}
Eigen::VectorXd state_at(const std::vector<Step>& steps, double t) {
    const Step& s = step_at(steps, t);
    return s.state(std::min(std::max((t - s.t0) / s.h, 0.0), s.s_end));
}

Eigen::VectorXd full_state(const Engine& e, const Eigen::VectorXd& zhat, const Modes& modes) {
    Eigen::VectorXd state(e.nz() + e.contacts());
    state.head(e.nz()) = zhat.head(e.nz());
    for (int c = 0; c < e.contacts(); ++c) {
        if (e.coulomb(c)) state(2 * e.dofs() + c) = 0.0;
        state(e.nz() + c) = modes[static_cast<std::size_t>(c)];
    }
    return state;
}

}  // namespace hbf::detail::exact

namespace hbf {

ExactFlow exact_flow(const System& given, double omega, const Eigen::VectorXd& state, int periods,
                     int max_events_per_period) {
    using namespace detail::exact;
    given.validate();
    const TimeDomainView view(given);  // the contacts as time-domain elements (contact_law.hpp)
    const System& system = view.system();
    if (validate_system(system, omega))
        throw InvalidInput("the mass matrix is singular (massless DOFs): exact_flow integrates M y'' = ... and needs M "
                           "positive definite (exact_periodic_orbit condenses massless DOFs)");
    check_state_size(system, state);
    if (periods < 1) throw InvalidInput("periods = " + std::to_string(periods) + " is out of range: allowed >= 1");
    Engine e(system, omega);
    Eigen::VectorXd zhat = e.augment(state.head(e.nz()), 0.0);
    Modes hints(static_cast<std::size_t>(e.contacts()));
    for (int c = 0; c < e.contacts(); ++c) hints[static_cast<std::size_t>(c)] = static_cast<int>(std::lround(state(e.nz() + c)));
    Modes modes = e.initial_modes(zhat, hints);
    ExactFlow out;
    for (int p = 0; p < periods; ++p) {
        zhat(e.cos_index()) = 1.0;  // exact phase at every period start
        zhat(e.sin_index()) = 0.0;
        Engine::Flow f = e.flow(zhat, modes, 0.0, e.period(), p + 1 == periods, false, max_events_per_period);
        if (!f.ok) {
            out.ok = false;
            out.message = f.message;
        }
        zhat = f.zhat;
        modes = f.modes;
        if (p + 1 == periods) {
            out.monodromy = f.psi.topLeftCorner(e.nz(), e.nz());
            for (ExactEvent ev : f.events) out.events.push_back(ev);
        }
        if (!f.ok) break;
    }
    out.state = full_state(e, zhat, modes);
    return out;
}

}  // namespace hbf
