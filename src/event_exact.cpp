// hbfriction — exact periodic orbits with Coulomb/Jenkins contacts (see event_exact.hpp).
#include "hbf/contact.hpp"
#include "hbf/event_exact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "hbf/error.hpp"
#include "time_integration/massless.hpp"

namespace hbf {

namespace {

constexpr double pi = 3.14159265358979323846;
using Modes = std::vector<int>;

/// A guard: positive while the mode of `contact` holds, a linear function row * zhat.
struct Guard {
    int contact = 0;
    Eigen::RowVectorXd row;
};

/// The linear system of one stick/slip pattern.
struct ModeData {
    Eigen::MatrixXd a;       ///< zhat' = a zhat
    Eigen::MatrixXd force;   ///< n_c x n: friction force of each contact as row * zhat
    std::vector<Guard> guards;
    double h = 0;            ///< step length
    Eigen::MatrixXd step_exp;  ///< exp(a h)
};

/// One step of a recorded flow: zhat(t0 + s h) = sum_k u.col(k) s^k for s in [0, s_end].
struct Step {
    double t0 = 0, h = 0, s_end = 0;
    Modes modes;
    Eigen::MatrixXd u;
};

double horner(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 0; --k) p = p * s + c(k);
    return p;
}
double horner_derivative(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 1; --k) p = p * s + static_cast<double>(k) * c(k);
    return p;
}
Eigen::VectorXd evaluate(const Eigen::Ref<const Eigen::MatrixXd>& u, double s) {
    Eigen::VectorXd z = u.col(u.cols() - 1);
    for (Eigen::Index k = u.cols() - 2; k >= 0; --k) z = z * s + u.col(k);
    return z;
}

/// exp(a d) by scaling and squaring of its Taylor series (to rounding).
Eigen::MatrixXd taylor_exp(const Eigen::MatrixXd& a, double d) {
    const double norm = (a * d).cwiseAbs().colwise().sum().maxCoeff();
    int squarings = 0;
    double scale = d;
    while (norm * (scale / d) > 0.5 && squarings < 60) {
        scale *= 0.5;
        ++squarings;
    }
    const Eigen::MatrixXd as = a * scale;
    Eigen::MatrixXd term = Eigen::MatrixXd::Identity(a.rows(), a.cols());
    Eigen::MatrixXd sum = term;
    for (int k = 1; k < 40; ++k) {
        term = as * term / static_cast<double>(k);
        sum += term;
        if (term.cwiseAbs().maxCoeff() <= 1e-18 * sum.cwiseAbs().maxCoeff()) break;
    }
    for (int k = 0; k < squarings; ++k) sum = sum * sum;
    return sum;
}

/// Taylor coefficients of the flow over one step: u_k = (a h)^k z / k!, until they vanish.
/// `buffer` keeps its capacity between steps; returns the number of columns used.
Eigen::Index step_polynomial(const Eigen::MatrixXd& a, const Eigen::VectorXd& z, double h, Eigen::MatrixXd& buffer) {
    constexpr int max_terms = 80;
    if (buffer.rows() != z.size() || buffer.cols() != max_terms) buffer.resize(z.size(), max_terms);
    buffer.col(0) = z;
    const double scale = std::max(1.0, z.cwiseAbs().maxCoeff());
    Eigen::Index used = 1;
    double previous = std::numeric_limits<double>::infinity();
    for (int k = 1; k < max_terms; ++k) {
        buffer.col(k).noalias() = a * buffer.col(k - 1);
        buffer.col(k) *= h / static_cast<double>(k);
        used = k + 1;
        const double size = buffer.col(k).cwiseAbs().maxCoeff();
        if (k >= 4 && size <= 1e-18 * scale && previous <= 1e-16 * scale) break;
        previous = size;
    }
    return used;
}

/// The root of the polynomial c in [lo, hi] where it changes sign (p(lo), p(hi) of opposite
/// signs or zero), by Newton safeguarded with bisection, to rounding.
double refine_root(const Eigen::RowVectorXd& c, double lo, double hi) {
    double p_lo = horner(c, lo);
    if (p_lo == 0.0) return lo;
    double x = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
        const double px = horner(c, x);
        if (px == 0.0) return x;
        if ((px > 0.0) == (p_lo > 0.0)) {
            lo = x;
            p_lo = px;
        } else {
            hi = x;
        }
        if (hi - lo <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(hi))) break;
        const double dp = horner_derivative(c, x);
        double next = dp != 0.0 ? x - px / dp : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool tiny = std::abs(next - x) <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x));
        x = next;
        if (tiny) break;
    }
    return std::min(std::max(x, lo), hi);
}

/// First root of the polynomial c on (0, s_end]: the first of 16 samples where it is below
/// -eta, or the first local minimum below -eta between two samples (a dip both samples miss:
/// a short phase near grazing), refined in the bracket before it. Returns -1 if none.
double first_root(const Eigen::RowVectorXd& c, double s_end, double eta) {
    constexpr int samples = 16;
    Eigen::RowVectorXd d(std::max<Eigen::Index>(1, c.size() - 1));
    d.setZero();
    for (Eigen::Index k = 1; k < c.size(); ++k) d(k - 1) = static_cast<double>(k) * c(k);
    double lo = 0.0, p_lo = c(0), d_lo = d(0);
    for (int j = 1; j <= samples; ++j) {
        const double s = s_end * j / samples;
        const double p = horner(c, s), dp = horner(d, s);
        if (p < -eta) {
            if (p_lo > 0.0) return refine_root(c, lo, s);
            if (j > 1) return lo;
            // Zero at the start (a slip or a stick that begins at the edge of its limit) and
            // negative at the first sample: a phase shorter than one sample, if the guard is
            // positive in between. Its end is the root after the first positive fine sample.
            constexpr int fine = 64;
            for (int k = 1; k < fine; ++k) {
                const double x = s * k / fine;
                if (horner(c, x) > 0.0) return refine_root(c, x, s);
            }
            return lo;
        }
        if (d_lo < 0.0 && dp > 0.0 && p_lo > 0.0) {  // a minimum between the samples
            const double bottom = refine_root(d, lo, s);
            if (horner(c, bottom) < -eta) return refine_root(c, lo, bottom);
        }
        lo = s;
        p_lo = p;
        d_lo = dp;
    }
    return -1.0;
}

int sign_of(double x) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0); }

/// Gauss-Legendre nodes and weights on [0, 1] (10 points: exact for degree 19).
const std::array<std::pair<double, double>, 10>& gauss_legendre() {
    static const std::array<std::pair<double, double>, 10> rule = [] {
        std::array<std::pair<double, double>, 10> r{};
        const int n = 10;
        for (int i = 0; i < n; ++i) {
            double x = std::cos(pi * (i + 0.75) / (n + 0.5));
            double dp = 0.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = x;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (x * p1 - p0) / (x * x - 1.0);
                const double dx = p1 / dp;
                x -= dx;
                if (std::abs(dx) < 1e-16) break;
            }
            r[static_cast<std::size_t>(i)] = {0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp)};
        }
        return r;
    }();
    return rule;
}

/// The flows, events and mode data of one system at one frequency.
class Engine {
public:
    Engine(const System& system, double omega) : system_(system), omega_(omega), period_(2.0 * pi / omega) {
        n_dofs_ = system.dofs();
        n_contacts_ = static_cast<int>(system.contacts.size());
        nz_ = 2 * n_dofs_ + n_contacts_;
        n_ = nz_ + 3;
        mass_inverse_ = Eigen::MatrixXd(system.mass).llt().solve(Eigen::MatrixXd::Identity(n_dofs_, n_dofs_));
        for (const Contact& c : system.contacts) directions_.push_back(system.contact_direction(c));
    }

    int dofs() const { return n_dofs_; }
    int contacts() const { return n_contacts_; }
    int nz() const { return nz_; }
    int n() const { return n_; }
    double period() const { return period_; }
    double omega() const { return omega_; }
    int cos_index() const { return nz_; }
    int sin_index() const { return nz_ + 1; }
    int one_index() const { return nz_ + 2; }
    const Contact& contact(int c) const { return system_.contacts[static_cast<std::size_t>(c)]; }
    const Eigen::VectorXd& direction(int c) const { return directions_[static_cast<std::size_t>(c)]; }
    bool coulomb(int c) const { return contact(c).law == FrictionLaw::coulomb; }
    const Eigen::VectorXd& excitation() const { return system_.excitation; }

    Eigen::VectorXd augment(const Eigen::VectorXd& z, double t) const {
        Eigen::VectorXd zhat(n_);
        zhat.head(nz_) = z;
        zhat(cos_index()) = std::cos(omega_ * t);
        zhat(sin_index()) = std::sin(omega_ * t);
        zhat(one_index()) = 1.0;
        return zhat;
    }

    double velocity(int c, const Eigen::VectorXd& zhat) const { return direction(c).dot(zhat.segment(n_dofs_, n_dofs_)); }
    double relative(int c, const Eigen::VectorXd& zhat) const { return direction(c).dot(zhat.head(n_dofs_)); }

    const ModeData& mode(const Modes& modes) {
        auto it = cache_.find(modes);
        if (it != cache_.end()) return it->second;
        return cache_.emplace(modes, build(modes)).first->second;
    }

    /// Modes after an event of contact `trigger` at zhat (see the header).
    Modes settle(const Eigen::VectorXd& zhat, Modes modes, int trigger) {
        const int c = trigger;
        if (modes[static_cast<std::size_t>(c)] != 0) {
            modes[static_cast<std::size_t>(c)] = 0;  // slip reached v = 0: try stick
        } else {
            const double f = mode(modes).force.row(c).dot(zhat);
            modes[static_cast<std::size_t>(c)] = f >= 0.0 ? 1 : -1;
        }
        return release_overloaded(zhat, modes);
    }

    /// Releases stuck Coulomb contacts that cannot be held, the most overloaded first.
    Modes release_overloaded(const Eigen::VectorXd& zhat, Modes modes) {
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

    /// Modes at the start of a flow from the state (hints: the modes carried with it) and a
    /// consistent state: a Jenkins spring beyond its limit is relaxed to it.
    Modes initial_modes(Eigen::VectorXd& zhat, const Modes& hints) {
        Modes modes(static_cast<std::size_t>(n_contacts_), 0);
        const double v_scale = 1.0 + zhat.segment(n_dofs_, n_dofs_).cwiseAbs().maxCoeff();
        for (int c = 0; c < n_contacts_; ++c) {
            const Contact& k = contact(c);
            const int hint = hints.empty() ? 0 : hints[static_cast<std::size_t>(c)];
            const double v = velocity(c, zhat);
            if (k.law == FrictionLaw::coulomb) {
                modes[static_cast<std::size_t>(c)] = (hint == 0 && std::abs(v) <= 1e-10 * v_scale) ? 0 : sign_of(v);
                if (modes[static_cast<std::size_t>(c)] == 0 && hint != 0 && v == 0.0) modes[static_cast<std::size_t>(c)] = hint;
            } else {
                const int s_index = 2 * n_dofs_ + c;
                const double q = relative(c, zhat);
                const double f = k.stiffness * (q - zhat(s_index));
                if (std::abs(f) >= k.friction_limit * (1.0 - 1e-12)) {
                    const int dir = sign_of(f);
                    zhat(s_index) = q - dir * k.friction_limit / k.stiffness;
                    modes[static_cast<std::size_t>(c)] = (v * dir > 0.0 || (v == 0.0 && hint == dir)) ? dir : 0;
                }
            }
        }
        return release_overloaded(zhat, modes);
    }

    struct Flow {
        bool ok = true;
        std::string message;
        Eigen::VectorXd zhat;
        Modes modes;
        Eigen::MatrixXd psi;  // d zhat(t_end) / d zhat(t0)
        std::vector<ExactEvent> events;  // absolute times
        std::vector<Eigen::VectorXd> event_states;  // zhat at each event
        std::vector<Step> steps;
        bool grazing = false;
    };

    /// Flows zhat from t0 over `duration` (modes: the modes at t0, consistent with zhat).
    Flow flow(Eigen::VectorXd zhat, Modes modes, double t0, double duration, bool monodromy, bool record,
              int max_events) {
        Flow out;
        if (monodromy) out.psi = Eigen::MatrixXd::Identity(n_, n_);
        double t = t0;
        const double t_end = t0 + duration;
        int events = 0;
        Eigen::MatrixXd buffer;
        Eigen::RowVectorXd coefficients;
        while (t < t_end) {
            const ModeData& m = mode(modes);
            const double remaining = t_end - t;
            const bool last = remaining <= m.h * (1.0 + 1e-12);
            const double s_end = last ? remaining / m.h : 1.0;
            const Eigen::Index used = step_polynomial(m.a, zhat, m.h, buffer);
            const auto u = buffer.leftCols(used);
            double best = std::numeric_limits<double>::infinity();
            const Guard* trigger = nullptr;
            for (const Guard& g : m.guards) {
                coefficients.noalias() = g.row * u;
                const double eta = 1e-12 * (g.row.cwiseAbs().array() * zhat.transpose().cwiseAbs().array()).sum();
                const double s = first_root(coefficients, s_end, eta);
                if (s >= 0.0 && s < best) {
                    best = s;
                    trigger = &g;
                }
            }
            if (!trigger) {
                if (record) out.steps.push_back({t, m.h, s_end, modes, u});
                const Eigen::VectorXd next = evaluate(u, s_end);
                if (monodromy) out.psi = (s_end == 1.0 ? m.step_exp : taylor_exp(m.a, s_end * m.h)) * out.psi;
                zhat = next;
                t = last ? t_end : t + m.h;
                continue;
            }
            if (record) out.steps.push_back({t, m.h, best, modes, u});
            zhat = evaluate(u, best);
            if (monodromy) out.psi = taylor_exp(m.a, best * m.h) * out.psi;
            t = std::min(t + best * m.h, t_end);
            const Modes next = settle(zhat, modes, trigger->contact);
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
            for (int c = 0; c < n_contacts_; ++c)
                if (next[static_cast<std::size_t>(c)] != modes[static_cast<std::size_t>(c)]) {
                    out.events.push_back({t, c, modes[static_cast<std::size_t>(c)], next[static_cast<std::size_t>(c)]});
                    out.event_states.push_back(zhat);
                }
            modes = next;
            if (++events > max_events) {
                out.ok = false;
                out.message = "more than " + std::to_string(max_events) + " contact events in one period at t = " +
                              format_number(t) + " (chattering)";
                break;
            }
        }
        out.zhat = zhat;
        out.modes = modes;
        return out;
    }

private:
    ModeData build(const Modes& modes) const {
        const int n = n_, nd = n_dofs_;
        ModeData m;
        m.force = Eigen::MatrixXd::Zero(n_contacts_, n);
        std::vector<int> stuck;
        for (int c = 0; c < n_contacts_; ++c) {
            const Contact& k = contact(c);
            const int mode = modes[static_cast<std::size_t>(c)];
            if (mode != 0) {
                m.force(c, one_index()) = mode * k.friction_limit;
            } else if (k.law == FrictionLaw::jenkins) {
                m.force.row(c).head(nd) = k.stiffness * direction(c).transpose();
                m.force(c, 2 * nd + c) = -k.stiffness;
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
            if (contact(c).law == FrictionLaw::jenkins && modes[static_cast<std::size_t>(c)] != 0)
                m.a.row(2 * nd + c).segment(nd, nd) = direction(c).transpose();
        m.a(cos_index(), sin_index()) = -omega_;
        m.a(sin_index(), cos_index()) = omega_;
        for (int c = 0; c < n_contacts_; ++c) {
            const int mode = modes[static_cast<std::size_t>(c)];
            const double limit = contact(c).friction_limit;
            if (mode != 0) {
                Guard g{c, Eigen::RowVectorXd::Zero(n)};
                g.row.segment(nd, nd) = mode * direction(c).transpose();
                m.guards.push_back(g);
            } else {
                for (int sign : {1, -1}) {
                    Guard g{c, -sign * m.force.row(c)};
                    g.row(one_index()) += limit;
                    m.guards.push_back(g);
                }
            }
        }
        // Step: short against the fastest mode of the pattern (|lambda| h <= 1) and T / 48.
        const Eigen::MatrixXd az = m.a.topLeftCorner(nz_, nz_);
        double rho = omega_;
        if (nz_ > 0) {
            Eigen::EigenSolver<Eigen::MatrixXd> eigen(az, false);
            if (eigen.info() == Eigen::Success) rho = std::max(rho, eigen.eigenvalues().cwiseAbs().maxCoeff());
            else rho = std::max(rho, az.cwiseAbs().rowwise().sum().maxCoeff());
        }
        m.h = std::min(period_ / 24.0, 1.0 / rho);
        m.step_exp = taylor_exp(m.a, m.h);
        return m;
    }

    const System& system_;
    double omega_, period_;
    int n_dofs_ = 0, n_contacts_ = 0, nz_ = 0, n_ = 0;
    Eigen::MatrixXd mass_inverse_;
    std::vector<Eigen::VectorXd> directions_;
    std::map<Modes, ModeData> cache_;
};

/// Values of a recorded flow at time t (inside the recorded range).
const Step& step_at(const std::vector<Step>& steps, double t) {
    std::size_t k = 0;
    while (k + 1 < steps.size() && steps[k + 1].t0 <= t) ++k;
    return steps[k];
}
Eigen::VectorXd state_at(const std::vector<Step>& steps, double t) {
    const Step& s = step_at(steps, t);
    return evaluate(s.u, std::min(std::max((t - s.t0) / s.h, 0.0), s.s_end));
}

/// The flows are dense: at most exact_solver_max_dofs DOFs with mass (those of the static
/// condensation when there are massless DOFs, time_integration/massless.hpp).
void check_dense_size(const System& system, bool condensed) {
    if (system.dofs() > exact_solver_max_dofs)
        throw InvalidInput("the system has " + std::to_string(system.dofs()) + " DOFs" +
                           (condensed ? " with mass" : "") +
                           ": the exact solver is dense (cost ~ N^3 per step, steps as short as the fastest mode) and "
                           "allowed up to " + std::to_string(exact_solver_max_dofs) + " DOFs");
}

/// Throws InvalidInput naming why the exact solver cannot take `system` at omega. Returns the
/// static condensation of its massless DOFs, null when M > 0 (none is needed).
std::unique_ptr<detail::MasslessCondensation> validate_system(const System& system, double omega) {
    system.validate();
    if (system.excitation_harmonic != 1)
        throw InvalidInput("excitation harmonic h = " + std::to_string(system.excitation_harmonic) +
                           ": the exact solver generates the force cos(w t) at the fundamental only (allowed h = 1)");
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const FrictionLaw law = system.contacts[c].law;
        if (!contact_law(law).exact_stick()) {
            std::vector<std::string> covered;
            for (const ContactLaw* l : contact_laws())
                if (l->exact_stick()) covered.emplace_back(l->name());
            std::string list, prose;  // "a, b" and "a and b"
            for (std::size_t i = 0; i < covered.size(); ++i) {
                list += (i == 0 ? "" : ", ") + covered[i];
                prose += (i == 0 ? "" : i + 1 == covered.size() ? " and " : ", ") + covered[i];
            }
            throw InvalidInput("contact " + std::to_string(c + 1) + " has law " + to_string(law) +
                               ": the exact solver covers " + prose + " only (allowed: " + list + ")");
        }
    }
    if (system.has_positive_definite_mass()) {
        check_dense_size(system, false);
        return nullptr;
    }
    try {
        auto condensation = std::make_unique<detail::MasslessCondensation>(system);
        check_dense_size(condensation->reduced(), true);
        return condensation;
    } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("the exact solver runs on the static condensation of the massless DOFs: ") +
                           e.what());
    }
}

void check_state_size(const System& system, const Eigen::VectorXd& state) {
    const int expected = 2 * system.dofs() + 2 * static_cast<int>(system.contacts.size());
    if (state.size() != expected)
        throw InvalidInput("state size = " + std::to_string(state.size()) + " is out of range: allowed " +
                           std::to_string(expected) + " (2 N + 2 n_c)");
}

/// The state at t = 0 in time_integration's convention from zhat and modes.
Eigen::VectorXd full_state(const Engine& e, const Eigen::VectorXd& zhat, const Modes& modes) {
    Eigen::VectorXd state(e.nz() + e.contacts());
    state.head(e.nz()) = zhat.head(e.nz());
    for (int c = 0; c < e.contacts(); ++c) {
        if (e.coulomb(c)) state(2 * e.dofs() + c) = 0.0;
        state(e.nz() + c) = modes[static_cast<std::size_t>(c)];
    }
    return state;
}

/// Mean friction force of every contact over one recorded period (Gauss-Legendre per step).
Eigen::VectorXd mean_forces(Engine& e, const Engine::Flow& flow) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(e.contacts());
    for (const Step& st : flow.steps) {
        const double length = st.s_end * st.h;
        if (length <= 0.0) continue;
        const ModeData& m = e.mode(st.modes);
        for (const auto& [node, weight] : gauss_legendre())
            mean += weight * length * (m.force * evaluate(st.u, node * st.s_end));
    }
    return mean / e.period();
}

/// Linear functions p(t) = L zhat(t) of the flow beyond the DOFs (the massless DOFs of a
/// condensed system, and outputs on them): rows L over zhat, and what fill_metrics finds.
struct Probes {
    Eigen::MatrixXd rows;            ///< n_p x n
    std::vector<double> max;         ///< max over the period of |p(t)| (turning points refined)
    Eigen::VectorXd c1, s1;          ///< first harmonic: p ~ c1 cos + s1 sin
    Eigen::VectorXd value, rate;     ///< p and p' at t = 0
    Eigen::MatrixXd samples, sample_rates;  ///< options.samples x n_p
};

/// Fills the orbit's metrics from one recorded period [t_s, t_s + T], and `probes`' if given.
void fill_metrics(Engine& e, const Engine::Flow& flow, double t_s, const ExactOptions& options, ExactOrbit& out,
                  Probes* probes = nullptr) {
    const int nd = e.dofs(), nc = e.contacts();
    const double period = e.period();
    const auto& rule = gauss_legendre();
    out.y_max.assign(static_cast<std::size_t>(nd), 0.0);
    const std::vector<Output>& outputs = options.outputs;
    out.output_max.assign(outputs.size(), 0.0);
    // First harmonics of the whole zhat (cos and sin are states of zhat, so probes on them too).
    Eigen::VectorXd c1z = Eigen::VectorXd::Zero(e.n()), s1z = Eigen::VectorXd::Zero(e.n());
    const Eigen::Index n_probes = probes ? probes->rows.rows() : 0;
    if (probes) probes->max.assign(static_cast<std::size_t>(n_probes), 0.0);
    double stick_time = 0.0;
    out.energy = 0.0;
    double margin_min = std::numeric_limits<double>::infinity(), margin_max = -margin_min;
    auto margin = [&](const Modes& modes, const Eigen::VectorXd& z) {
        const double value = std::abs(e.mode(modes).force.row(0).dot(z)) / e.contact(0).friction_limit - 1.0;
        margin_min = std::min(margin_min, value);
        margin_max = std::max(margin_max, value);
    };
    for (std::size_t k = 0; k < flow.events.size() && nc > 0; ++k) {
        const ExactEvent& ev = flow.events[k];
        if (ev.contact != 0 || ev.mode_before == 0 || !e.coulomb(0)) continue;
        Modes trial = step_at(flow.steps, ev.time).modes;  // the force that would hold it
        trial[0] = 0;
        margin(trial, flow.event_states[k]);
    }
    for (const Step& st : flow.steps) {
        const double length = st.s_end * st.h;
        if (length <= 0.0) continue;
        if (nc > 0 && (st.modes[0] == 0 || !e.coulomb(0)))
            for (int j = 0; j <= 16; ++j) margin(st.modes, evaluate(st.u, st.s_end * j / 16));
        // Turning points of every DOF and output: roots of y_i' (its polynomial), from 16
        // samples.
        auto turning_points = [&st](const Eigen::RowVectorXd& y, const Eigen::RowVectorXd& v, double& best) {
            constexpr int samples = 16;
            double s_prev = 0.0, v_prev = horner(v, 0.0);
            best = std::max(best, std::abs(horner(y, 0.0)));
            for (int j = 1; j <= samples; ++j) {
                const double s = st.s_end * j / samples;
                const double vs = horner(v, s);
                best = std::max(best, std::abs(horner(y, s)));
                if ((v_prev <= 0.0 && vs >= 0.0) || (v_prev >= 0.0 && vs <= 0.0))
                    best = std::max(best, std::abs(horner(y, refine_root(v, s_prev, s))));
                s_prev = s;
                v_prev = vs;
            }
        };
        for (int i = 0; i < nd; ++i) turning_points(st.u.row(i), st.u.row(nd + i), out.y_max[static_cast<std::size_t>(i)]);
        for (std::size_t o = 0; o < outputs.size(); ++o) {
            Eigen::RowVectorXd y = Eigen::RowVectorXd::Zero(st.u.cols()), v = y;
            for (const auto& [i, c] : outputs[o].terms()) {
                y += c * st.u.row(i);
                v += c * st.u.row(nd + i);
            }
            turning_points(y, v, out.output_max[o]);
        }
        if (n_probes > 0) {  // p = L zhat, p' = L A zhat
            const Eigen::MatrixXd y = probes->rows * st.u, v = (probes->rows * e.mode(st.modes).a) * st.u;
            for (Eigen::Index p = 0; p < n_probes; ++p)
                turning_points(y.row(p), v.row(p), probes->max[static_cast<std::size_t>(p)]);
        }
        // First harmonics by Gauss-Legendre (cos and sin are states of zhat).
        for (const auto& [node, weight] : rule) {
            const Eigen::VectorXd z = evaluate(st.u, node * st.s_end);
            c1z += weight * length * z(e.cos_index()) * z;
            s1z += weight * length * z(e.sin_index()) * z;
        }
        if (nc > 0 && st.modes[0] == 0) stick_time += length;
        const Eigen::VectorXd z0 = st.u.col(0), z1 = evaluate(st.u, st.s_end);
        for (int c = 0; c < nc; ++c) {
            const int mode = st.modes[static_cast<std::size_t>(c)];
            if (mode != 0) out.energy += mode * e.contact(c).friction_limit * (e.relative(c, z1) - e.relative(c, z0));
        }
    }
    c1z *= 2.0 / period;
    s1z *= 2.0 / period;
    const Eigen::VectorXd c1 = c1z.head(nd), s1 = s1z.head(nd);
    if (probes) {
        probes->c1 = probes->rows * c1z;
        probes->s1 = probes->rows * s1z;
    }
    out.harmonic1 = c1.cast<std::complex<double>>() - std::complex<double>(0.0, 1.0) * s1.cast<std::complex<double>>();
    out.y_amp1.resize(static_cast<std::size_t>(nd));
    for (int i = 0; i < nd; ++i) out.y_amp1[static_cast<std::size_t>(i)] = std::hypot(c1(i), s1(i));
    out.output_amp1.clear();
    for (const Output& o : outputs) out.output_amp1.push_back(std::hypot(o.of(c1), o.of(s1)));
    out.input_energy = pi * e.excitation().dot(s1);
    out.stick_fraction = nc > 0 ? std::min(1.0, stick_time / period) : 0.0;
    out.stick_margin_min = std::isfinite(margin_min) ? margin_min : 0.0;
    out.stick_margin_max = std::isfinite(margin_max) ? margin_max : 0.0;
    if (nc == 0) out.regime = "none";
    else if (stick_time >= period * (1.0 - 1e-12)) out.regime = "stick";
    else if (stick_time <= period * 1e-12) out.regime = "slip";
    else out.regime = "stick-slip";
    // Events in [0, T), by time.
    out.events.clear();
    for (ExactEvent ev : flow.events) {
        ev.time = std::fmod(ev.time, period);
        if (ev.time < 0) ev.time += period;
        if (ev.time >= period) ev.time -= period;
        out.events.push_back(ev);
    }
    std::sort(out.events.begin(), out.events.end(),
              [](const ExactEvent& a, const ExactEvent& b) { return a.time < b.time; });
    out.switches = static_cast<int>(out.events.size());
    // The state at t = 0 (= T).
    const double t_zero = t_s > 0.0 ? period : 0.0;
    const Step& at_zero = step_at(flow.steps, t_zero);
    const Eigen::VectorXd z_zero = state_at(flow.steps, t_zero);
    out.state = full_state(e, z_zero, at_zero.modes);
    if (probes) {
        probes->value = probes->rows * z_zero;
        probes->rate = probes->rows * (e.mode(at_zero.modes).a * z_zero);
        probes->samples.resize(options.samples, n_probes);
        probes->sample_rates.resize(options.samples, n_probes);
    }
    if (options.samples > 0) {
        out.time.resize(options.samples);
        out.displacement.resize(options.samples, nd);
        out.velocity.resize(options.samples, nd);
        out.friction_force.resize(options.samples, nc);
        for (int j = 0; j < options.samples; ++j) {
            const double t = period * j / options.samples;
            const double tt = t < t_s ? t + period : t;
            const Step& st = step_at(flow.steps, tt);
            const Eigen::VectorXd z = evaluate(st.u, std::min(std::max((tt - st.t0) / st.h, 0.0), st.s_end));
            out.time(j) = t;
            out.displacement.row(j) = z.head(nd).transpose();
            out.velocity.row(j) = z.segment(nd, nd).transpose();
            const ModeData& m = e.mode(st.modes);
            for (int c = 0; c < nc; ++c) out.friction_force(j, c) = m.force.row(c).dot(z);
            if (probes) {
                probes->samples.row(j) = (probes->rows * z).transpose();
                probes->sample_rates.row(j) = (probes->rows * (m.a * z)).transpose();
            }
        }
    }
}

/// The linear stuck steady state (convention of the header): z at t = 0 and the load
/// max_c |f_c| / F_c; infinity where the stuck structure is singular at omega.
double stuck_steady_state(const System& system, double omega, Eigen::VectorXd& z) {
    const StuckResponse stuck = stuck_linear_response(system, omega);
    if (!stuck.ok) return std::numeric_limits<double>::infinity();
    const int nd = system.dofs(), nc = static_cast<int>(system.contacts.size());
    double load = 0.0;
    for (int c = 0; c < nc; ++c)
        load = std::max(load, std::abs(stuck.force(c)) / system.contacts[static_cast<std::size_t>(c)].friction_limit);
    z = Eigen::VectorXd::Zero(2 * nd + nc);
    z.head(nd) = stuck.amplitude.real();
    z.segment(nd, nd) = -omega * stuck.amplitude.imag();  // Re(i omega Y)
    return load;
}

/// The permanent-stick orbit's state, or false when it does not hold every contact.
bool permanent_stick_state(const System& system, double omega, Eigen::VectorXd& z) {
    return stuck_steady_state(system, omega, z) <= 1.0;
}

/// Orthonormal basis B of the states allowed at the section with `modes`, and the particular
/// state z_p: z = z_p + B xi (coulomb sliders fixed at 0; coulomb stuck: v_c = 0; jenkins
/// slipping: s_c = q_c - mode F_c / k_t).
void section_manifold(const Engine& e, const Modes& modes, Eigen::MatrixXd& basis, Eigen::VectorXd& particular) {
    const int nd = e.dofs(), nz = e.nz();
    std::vector<Eigen::RowVectorXd> rows;
    std::vector<double> values;
    for (int c = 0; c < e.contacts(); ++c) {
        const int mode = modes[static_cast<std::size_t>(c)];
        Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(nz);
        if (e.coulomb(c)) {
            row(2 * nd + c) = 1.0;
            rows.push_back(row);
            values.push_back(0.0);
            if (mode == 0) {
                Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(nz);
                v.segment(nd, nd) = e.direction(c).transpose();
                rows.push_back(v);
                values.push_back(0.0);
            }
        } else if (mode != 0) {
            row.head(nd) = e.direction(c).transpose();
            row(2 * nd + c) = -1.0;
            rows.push_back(row);
            values.push_back(mode * e.contact(c).friction_limit / e.contact(c).stiffness);
        }
    }
    if (rows.empty()) {
        basis = Eigen::MatrixXd::Identity(nz, nz);
        particular = Eigen::VectorXd::Zero(nz);
        return;
    }
    Eigen::MatrixXd constraints(static_cast<Eigen::Index>(rows.size()), nz);
    Eigen::VectorXd d(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k) {
        constraints.row(static_cast<Eigen::Index>(k)) = rows[k];
        d(static_cast<Eigen::Index>(k)) = values[k];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(constraints.transpose());
    const Eigen::Index rank = qr.rank();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(nz, nz);
    basis = q.rightCols(nz - rank);
    particular = constraints.completeOrthogonalDecomposition().solve(d);
}

void fill_stability(const Eigen::MatrixXd& psi, const Eigen::MatrixXd& basis, int nz, const ExactOptions& options,
                    ExactOrbit& out) {
    const Eigen::MatrixXd reduced = basis.transpose() * psi.topLeftCorner(nz, nz) * basis;
    if (reduced.rows() == 0) {
        out.multipliers.resize(0);
        out.max_multiplier = 0;
        out.stable = true;
        return;
    }
    Eigen::EigenSolver<Eigen::MatrixXd> eigen(reduced, false);
    out.multipliers = eigen.eigenvalues();
    out.max_multiplier = out.multipliers.cwiseAbs().maxCoeff();
    out.stable = out.max_multiplier <= 1.0 + options.stability_tolerance;
}

/// Sizes of section states z = [y (N), y' (N), sliders] in units of displacement: velocities
/// divided by omega, so that a problem in other units gives the same numbers.
struct SectionNorm {
    int dofs = 0;
    double omega = 1.0;
    double reference = 0.0;  ///< the size of the caller's start: floors the relative change
    double size(const Eigen::VectorXd& z) const {
        double m = z.head(dofs).cwiseAbs().maxCoeff();
        m = std::max(m, z.segment(dofs, dofs).cwiseAbs().maxCoeff() / omega);
        if (z.size() > 2 * dofs) m = std::max(m, z.tail(z.size() - 2 * dofs).cwiseAbs().maxCoeff());
        return m;
    }
    /// |P(z) - z| / max(reference, |z|): relative, and a state far off is not judged by its
    /// own size alone.
    double relative_change(const Eigen::VectorXd& end, const Eigen::VectorXd& start) const {
        const double scale = std::max(reference, size(start));
        const double change = size(end - start);
        return scale > 0.0 ? change / scale : change;
    }
};

}  // namespace

void ExactOptions::validate() const {
    if (!(tolerance >= 1e-15 && tolerance <= 1e-2))
        throw InvalidInput("exact tolerance = " + format_number(tolerance) + " is out of range: allowed 1e-15..1e-2");
    if (max_iterations < 1)
        throw InvalidInput("exact max_iterations = " + std::to_string(max_iterations) + " is out of range: allowed >= 1");
    if (warmup_periods < 1)
        throw InvalidInput("exact warmup_periods = " + std::to_string(warmup_periods) + " is out of range: allowed >= 1");
    if (restarts < 0)
        throw InvalidInput("exact restarts = " + std::to_string(restarts) + " is out of range: allowed >= 0");
    if (max_events_per_period < 4)
        throw InvalidInput("exact max_events_per_period = " + std::to_string(max_events_per_period) +
                           " is out of range: allowed >= 4");
    if (!(stability_tolerance >= 0.0 && stability_tolerance <= 1.0))
        throw InvalidInput("exact stability_tolerance = " + format_number(stability_tolerance) +
                           " is out of range: allowed 0..1");
    if (samples < 0 || samples > 10000000)
        throw InvalidInput("exact samples = " + std::to_string(samples) + " is out of range: allowed 0..1e7");
}

double permanent_stick_load(const System& system, double omega) {
    validate_system(system, omega);
    Eigen::VectorXd z;
    return stuck_steady_state(system, omega, z);
}

std::string exact_solver_refusal(const System& system) {
    try {
        validate_system(system, 1.0);
        return {};
    } catch (const InvalidInput& e) {
        return e.what();
    }
}

bool exact_solver_supports(const System& system) { return exact_solver_refusal(system).empty(); }

namespace {
/// Steps per period (exact_steps_per_period) and the size of the flows' state.
std::pair<double, int> steps_and_size(const System& system, double omega) {
    const auto condensation = validate_system(system, omega);
    Engine e(condensation ? condensation->reduced() : system, omega);
    double steps = 0.0;
    for (int mode : {0, 1}) {  // every contact stuck, every contact slipping
        const ModeData& m = e.mode(Modes(static_cast<std::size_t>(e.contacts()), mode));
        steps = std::max(steps, e.period() / m.h);
    }
    return {steps, e.n()};
}
}  // namespace

double exact_steps_per_period(const System& system, double omega) { return steps_and_size(system, omega).first; }

double exact_max_steps_per_period(int state_size) {
    return std::min(50000.0, 2e6 / std::max(state_size, 1));
}

std::string exact_cost_refusal(const System& system, double omega_min) {
    std::string why = exact_solver_refusal(system);
    if (!why.empty()) return why;
    require_positive(omega_min, "w", "lowest frequency of the exact solver");
    const auto [steps, size] = steps_and_size(system, omega_min);
    const double bound = exact_max_steps_per_period(size);
    if (steps > bound)
        return "at w = " + format_number(omega_min) + " one period takes " + format_number(std::round(steps)) +
               " Taylor steps (the period 2 pi / w against the fastest mode of the structure), above the bound " +
               format_number(std::round(bound)) + " that keeps the exact solver's time and memory bounded";
    return {};
}

std::string ExactOrbit::summary() const {
    std::ostringstream s;
    s << "w = " << format_number(omega) << ": " << (converged ? "converged" : "not converged") << " (" << message
      << "), " << iterations << " Newton iterations, residual " << format_number(residual);
    if (!y_max.empty()) s << ", y1_max = " << format_number(y_max.front());
    s << ", " << regime << ", " << (stable ? "stable" : "unstable") << " (max |multiplier| "
      << format_number(max_multiplier) << ")";
    return s.str();
}

ExactFlow exact_flow(const System& system, double omega, const Eigen::VectorXd& state, int periods,
                     int max_events_per_period) {
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

namespace {

/// exact_periodic_orbit on a system with M > 0 (validated).
ExactOrbit orbit_of(const System& system, double omega, const Eigen::VectorXd& initial_state,
                    const ExactOptions& options) {
    Engine e(system, omega);
    const double period = e.period();
    ExactOrbit out;
    out.omega = omega;
    SectionNorm norm{e.dofs(), omega, 0.0};
    norm.reference = norm.size(initial_state.head(e.nz()));

    // Plain periods from zhat (at t = 0) with modes; the last one recorded.
    Engine::Flow warm;
    auto plain_periods = [&](Eigen::VectorXd zhat, Modes modes, int periods) {
        for (int p = 0; p < periods; ++p) {
            zhat(e.cos_index()) = 1.0;
            zhat(e.sin_index()) = 0.0;
            warm = e.flow(zhat, modes, 0.0, period, false, p + 1 == periods, options.max_events_per_period);
            ++out.periods;
            if (!warm.ok) return false;
            zhat = warm.zhat;
            modes = warm.modes;
        }
        return true;
    };
    Eigen::VectorXd zhat = e.augment(initial_state.head(e.nz()), 0.0);
    for (int c = 0; c < e.contacts(); ++c)
        if (e.coulomb(c)) zhat(2 * e.dofs() + c) = 0.0;
    Modes hints(static_cast<std::size_t>(e.contacts()));
    for (int c = 0; c < e.contacts(); ++c)
        hints[static_cast<std::size_t>(c)] = static_cast<int>(std::lround(initial_state(e.nz() + c)));
    const Modes modes = e.initial_modes(zhat, hints);
    if (!plain_periods(zhat, modes, options.warmup_periods)) {
        out.message = "warm-up: " + warm.message;
        if (!warm.steps.empty()) fill_metrics(e, warm, 0.0, options, out);  // the period as far as it went
        out.state = initial_state;
        return out;
    }

    Eigen::VectorXd stuck;
    const bool stuck_holds = permanent_stick_state(system, omega, stuck);
    // The permanent-stick orbit (the convention of the header), into `orbit`.
    auto permanent = [&](ExactOrbit& orbit) {
        const Modes stick(static_cast<std::size_t>(e.contacts()), 0);
        Engine::Flow f = e.flow(e.augment(stuck, 0.0), stick, 0.0, period, true, true, options.max_events_per_period);
        ++orbit.periods;
        orbit.permanent_stick = true;
        orbit.residual = norm.relative_change(f.zhat.head(e.nz()), stuck);
        orbit.converged = f.ok && f.events.empty() && orbit.residual <= std::max(options.tolerance, 1e-10);
        orbit.message = orbit.converged ? "permanent stick: the linear stuck steady state with zero mean friction "
                                          "force (convention for the undetermined offset)"
                                        : "the permanent-stick state left stick within the period";
        fill_metrics(e, f, 0.0, options, orbit);
        Eigen::MatrixXd basis;
        Eigen::VectorXd particular;
        section_manifold(e, stick, basis, particular);
        fill_stability(f.psi, basis, e.nz(), options, orbit);
    };

    Engine::Flow f;
    double t_s = 0.0;
    Eigen::MatrixXd basis;
    int restart_periods = 8;
    for (int attempt = 0;; ++attempt) {
        // Permanent stick: no event and every contact stuck over the last plain period.
        bool all_stuck = warm.events.empty();
        for (const Step& st : warm.steps)
            for (int mode : st.modes) all_stuck = all_stuck && mode == 0;
        if (all_stuck && stuck_holds) {
            const int periods = out.periods, iterations = out.iterations;
            out = ExactOrbit{};
            out.omega = omega;
            out.periods = periods;
            out.iterations = iterations;
            permanent(out);
            return out;
        }
        // The section: the middle of the longest event-free stretch of the last plain period.
        t_s = 0.0;
        Modes section_modes = warm.steps.front().modes;
        if (!warm.events.empty()) {
            std::vector<double> times;
            for (const ExactEvent& ev : warm.events) times.push_back(ev.time);
            std::sort(times.begin(), times.end());
            double best_gap = -1.0;
            for (std::size_t k = 0; k < times.size(); ++k) {
                const double next = k + 1 < times.size() ? times[k + 1] : times.front() + period;
                if (next - times[k] > best_gap) {
                    best_gap = next - times[k];
                    t_s = times[k] + 0.5 * (next - times[k]);
                }
            }
            t_s = std::fmod(t_s, period);
            section_modes = step_at(warm.steps, t_s).modes;
        }
        Eigen::VectorXd z = t_s == 0.0 ? Eigen::VectorXd(warm.steps.front().u.col(0).head(e.nz()))
                                       : Eigen::VectorXd(state_at(warm.steps, t_s).head(e.nz()));
        Eigen::VectorXd particular;
        section_manifold(e, section_modes, basis, particular);
        z = particular + basis * (basis.transpose() * (z - particular));

        auto map = [&](const Eigen::VectorXd& start) {
            Eigen::VectorXd zh = e.augment(start, t_s);
            const Modes m = e.initial_modes(zh, section_modes);
            ++out.periods;
            return e.flow(zh, m, t_s, period, true, true, options.max_events_per_period);
        };
        // Newton on B^T (P(z) - z) = 0 from z (f = map(z) on entry); returns whether a restart
        // may help. A singular Jacobian (a multiplier at 1: the undetermined offset of a contact
        // stuck all period, or a fold) takes the minimum-norm step.
        auto newton = [&]() {
            for (int iteration = 0;; ++iteration, ++out.iterations) {
                if (!f.ok) {
                    out.message = "Newton iteration " + std::to_string(iteration) + ": " + f.message;
                    return false;
                }
                const Eigen::VectorXd r = f.zhat.head(e.nz()) - z;
                out.residual = norm.relative_change(f.zhat.head(e.nz()), z);
                if (out.residual <= options.tolerance) {
                    out.converged = true;
                    out.message = "Newton on the period map converged" + std::string(f.grazing ? " (a grazing event)" : "");
                    return false;
                }
                if (out.iterations >= options.max_iterations) {
                    out.message = "Newton reached " + std::to_string(options.max_iterations) + " iterations, residual " +
                                  format_number(out.residual);
                    return false;
                }
                const Eigen::MatrixXd jacobian =
                    basis.transpose() *
                    (f.psi.topLeftCorner(e.nz(), e.nz()) - Eigen::MatrixXd::Identity(e.nz(), e.nz())) * basis;
                Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver;
                solver.setThreshold(1e-11);
                solver.compute(jacobian);
                const Eigen::VectorXd step = -(basis * solver.solve(basis.transpose() * r));
                double alpha = 1.0;
                for (int trial = 0; trial < 12; ++trial, alpha *= 0.5) {
                    const Eigen::VectorXd trial_z = z + alpha * step;
                    Engine::Flow g = map(trial_z);
                    if (!g.ok) continue;
                    const double residual = norm.relative_change(g.zhat.head(e.nz()), trial_z);
                    if (residual < out.residual * (1.0 - 1e-4 * alpha) || residual <= options.tolerance) {
                        z = trial_z;
                        f = std::move(g);
                        alpha = -1.0;
                        break;
                    }
                }
                if (alpha > 0.0) {
                    out.message = "Newton stalled (no decrease along the step) at residual " +
                                  format_number(out.residual) +
                                  ": the stick/slip pattern changes near this frequency, or the start is too far";
                    return true;
                }
            }
        };
        f = map(z);
        bool retry = newton();
        if (out.converged) {
            // Contacts stuck over the whole period (others slipping) have an undetermined offset:
            // the convention of the header, zero mean force. A static shift of the structure
            // K dy = sum_c w_c fbar_c (and of the Jenkins sliders, s_c += w_c^T dy + fbar_c / k_t)
            // removes each such contact's mean force fbar_c and leaves the others' forces and
            // every velocity unchanged; Newton then polishes the shifted orbit.
            Eigen::VectorXd mean = mean_forces(e, f);
            std::vector<int> stuck_all;
            for (int c = 0; c < e.contacts(); ++c) {
                bool stuck_throughout = true;
                for (const Step& st : f.steps)
                    if (st.s_end > 0.0 && st.modes[static_cast<std::size_t>(c)] != 0) stuck_throughout = false;
                if (stuck_throughout && std::abs(mean(c)) > 1e-12 * e.contact(c).friction_limit) stuck_all.push_back(c);
            }
            if (!stuck_all.empty() && static_cast<int>(stuck_all.size()) < e.contacts()) {
                Eigen::VectorXd load = Eigen::VectorXd::Zero(e.dofs());
                for (int c : stuck_all) load += e.direction(c) * mean(c);
                const Eigen::VectorXd dy = Eigen::MatrixXd(system.stiffness).completeOrthogonalDecomposition().solve(load);
                Eigen::VectorXd shifted = z;
                shifted.head(e.dofs()) += dy;
                for (int c : stuck_all)
                    if (!e.coulomb(c))
                        shifted(2 * e.dofs() + c) += e.direction(c).dot(dy) + mean(c) / e.contact(c).stiffness;
                const Eigen::VectorXd kept = z;
                Engine::Flow kept_flow = f;
                z = particular + basis * (basis.transpose() * (shifted - particular));
                f = map(z);
                out.converged = false;
                newton();
                if (!out.converged) {  // keep the orbit found, with its offset, and say so
                    z = kept;
                    f = std::move(kept_flow);
                    out.converged = true;
                    out.residual = norm.relative_change(f.zhat.head(e.nz()), z);
                    out.message = "Newton on the period map converged; a contact stuck all period keeps a nonzero "
                                  "mean force (centring it failed)";
                }
            }
        }
        if (out.converged || !retry || attempt >= options.restarts || out.iterations >= options.max_iterations) break;
        // Restart: plain periods from the last iterate (the exact flow integrates the motion and
        // settles the stick/slip pattern), then a new section and Newton.
        const Eigen::VectorXd at_zero = t_s > 0.0 ? state_at(f.steps, period) : f.zhat;
        const Modes modes_zero = t_s > 0.0 ? step_at(f.steps, period).modes : f.modes;
        if (!plain_periods(at_zero, modes_zero, restart_periods)) {
            out.message += "; restart: " + warm.message;
            break;
        }
        restart_periods *= 4;
    }
    if (!out.converged && stuck_holds) {
        // Newton found no orbit with slip from this start, and the permanent-stick state holds:
        // that is the orbit (the start's slip was a transient).
        ExactOrbit orbit;
        orbit.omega = omega;
        orbit.periods = out.periods;
        orbit.iterations = out.iterations;
        permanent(orbit);
        if (orbit.converged) {
            orbit.message += "; Newton from the start failed: " + out.message;
            return orbit;
        }
    }
    fill_metrics(e, f, t_s, options, out);
    fill_stability(f.psi, basis, e.nz(), options, out);
    // A member of the permanent-stick family with another offset (no slip, or slips of
    // vanishing length at the edge of the friction cone, dissipating nothing) where the
    // conventional one holds: the convention instead.
    double scale = 0.0;
    for (int c = 0; c < e.contacts(); ++c) scale += e.contact(c).friction_limit;
    scale *= 1.0 + *std::max_element(out.y_max.begin(), out.y_max.end());
    if (out.converged && stuck_holds && out.energy <= 1e-9 * scale) {
        ExactOrbit orbit;
        orbit.omega = omega;
        orbit.periods = out.periods;
        orbit.iterations = out.iterations;
        permanent(orbit);
        if (orbit.converged) return orbit;
    }
    return out;
}

/// The orbit of a system with massless DOFs: solved on its static condensation (exact: the
/// massless DOFs follow the massive ones, the load and the sliders linearly), then expressed
/// in the original DOFs. The massless DOFs and the outputs are functions of the reduced
/// state, p = L zhat, whose maxima and harmonics come from one more exact period (Probes).
ExactOrbit massless_orbit(const System& system, const detail::MasslessCondensation& condensation, double omega,
                          const Eigen::VectorXd& initial_state, const ExactOptions& options) {
    const System& reduced = condensation.reduced();
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size()), nr = reduced.dofs();
    ExactOptions reduced_options = options;
    reduced_options.outputs.clear();
    reduced_options.samples = 0;
    ExactOrbit out = orbit_of(reduced, omega, condensation.reduce_state(initial_state), reduced_options);

    Engine e(reduced, omega);
    // Rows over zhat = [y_R, y_R', s, cos, sin, 1]: every original DOF, then every output.
    const detail::MasslessCondensation::MasslessMap map = condensation.massless_map();
    Probes probes;
    probes.rows = Eigen::MatrixXd::Zero(n + static_cast<Eigen::Index>(options.outputs.size()), e.n());
    for (int i = 0; i < n; ++i) {
        const int p = condensation.position(i);
        if (!condensation.massless(i)) {
            probes.rows(i, p) = 1.0;
            continue;
        }
        probes.rows.row(i).head(nr) = map.from_massive.row(p);
        probes.rows.row(i).segment(2 * nr, nc) = map.from_sliders.row(p);
        probes.rows(i, e.cos_index()) = map.load(p);
    }
    for (std::size_t o = 0; o < options.outputs.size(); ++o)
        for (const auto& [i, c] : options.outputs[o].terms())
            probes.rows.row(n + static_cast<Eigen::Index>(o)) += c * probes.rows.row(i);
    // One exact period from the orbit's state at t = 0 (its modes there as the hint).
    Modes modes(static_cast<std::size_t>(nc));
    for (int c = 0; c < nc; ++c) modes[static_cast<std::size_t>(c)] = static_cast<int>(out.state(2 * nr + nc + c));
    const Engine::Flow f =
        e.flow(e.augment(out.state.head(e.nz()), 0.0), modes, 0.0, e.period(), false, true, options.max_events_per_period);
    ExactOrbit period;
    ExactOptions sampled = reduced_options;
    sampled.samples = options.samples;
    if (!f.steps.empty()) fill_metrics(e, f, 0.0, sampled, period, &probes);
    if (f.steps.empty() || !f.ok) {
        out.converged = false;
        out.message += "; the period of the massless DOFs could not be integrated: " + f.message;
        return out;
    }
    // The original's metrics and state.
    out.y_max.assign(probes.max.begin(), probes.max.begin() + n);
    out.y_amp1.resize(static_cast<std::size_t>(n));
    out.harmonic1.resize(n);
    for (int i = 0; i < n; ++i) {
        out.y_amp1[static_cast<std::size_t>(i)] = std::hypot(probes.c1(i), probes.s1(i));
        out.harmonic1(i) = std::complex<double>(probes.c1(i), -probes.s1(i));
    }
    out.output_max.assign(probes.max.begin() + n, probes.max.end());
    out.output_amp1.clear();
    for (std::size_t o = 0; o < options.outputs.size(); ++o) {
        const Eigen::Index row = n + static_cast<Eigen::Index>(o);
        out.output_amp1.push_back(std::hypot(probes.c1(row), probes.s1(row)));
    }
    Eigen::VectorXd state = Eigen::VectorXd::Zero(2 * n + 2 * nc);
    state.head(n) = probes.value.head(n);
    state.segment(n, n) = probes.rate.head(n);
    for (int c = 0; c < nc; ++c) {
        // A Coulomb contact's internal state is 0 by convention (its slider is q itself).
        const bool coulomb = system.contacts[static_cast<std::size_t>(c)].law == FrictionLaw::coulomb;
        state(2 * n + c) = coulomb ? 0.0 : out.state(2 * nr + c);
        state(2 * n + nc + c) = out.state(2 * nr + nc + c);
    }
    out.state = state;
    if (options.samples > 0) {
        out.time = period.time;
        out.displacement = probes.samples.leftCols(n);
        out.velocity = probes.sample_rates.leftCols(n);
        out.friction_force = period.friction_force;
    }
    return out;
}

}  // namespace

ExactOrbit exact_periodic_orbit(const System& system, double omega, const Eigen::VectorXd& initial_state,
                                const ExactOptions& options) {
    const auto condensation = validate_system(system, omega);
    check_state_size(system, initial_state);
    options.validate();
    for (const Output& o : options.outputs) o.validate(system.dofs());
    if (condensation) return massless_orbit(system, *condensation, omega, initial_state, options);
    return orbit_of(system, omega, initial_state, options);
}

}  // namespace hbf
