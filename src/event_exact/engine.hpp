// hbfriction — internal to event_exact: the flow engine. Each stick/slip pattern (the modes
// of the contacts) is an autonomous linear system zhat' = A_m zhat; the engine builds and caches
// them, flows a state over steps through the contact events (their times the roots of the
// guards) and multiplies the monodromy with the saltation matrices (see event_exact.hpp).
// The pattern's fast modes (eigenvalues far above the forcing's) are split off by their
// spectral projector: on them the flow is a closed-form sum of exponentials, so the Taylor
// steps of the rest follow the slow modes and the forcing, not the stiffest mode.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <map>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/event_exact.hpp"
#include "event_exact/polynomial.hpp"

namespace hbf::detail::exact {

/// The mode of each contact: 1D friction (Engine) +1 or -1 slipping in that direction, 0
/// stuck; other engines number their own.
using Modes = std::vector<int>;

/// A guard: positive while the mode of `contact` holds, a linear function row * zhat; `kind`
/// tells an engine's guards of one contact apart (0 where a contact has one kind).
struct Guard {
    int contact = 0;
    Eigen::RowVectorXd row;
    Eigen::RowVectorXcd fast;  ///< row * FastModes::right
    int kind = 0;
};

/// The fast modes of a pattern: eigenvalues lambda_j of a beyond the slow ones, right and left
/// eigenvectors with left * right = I (n_f of them). Their part of zhat is
/// right * (left * zhat), and it flows as right * diag(exp(lambda t)) * (left * zhat).
struct FastModes {
    Eigen::VectorXcd lambda;
    Eigen::MatrixXcd right;  ///< n x n_f
    Eigen::MatrixXcd left;   ///< n_f x n
    Eigen::VectorXd right_size;  ///< max |right(i, j)| per column
    Eigen::Index size() const { return lambda.size(); }
};

/// The linear system of one stick/slip pattern.
struct ModeData {
    Eigen::MatrixXd a;       ///< zhat' = a zhat
    Eigen::MatrixXd force;   ///< n_c x n: friction force of each contact as row * zhat
    std::vector<Guard> guards;
    /// Rigid contacts (rigid_engine.hpp): the contact forces lambda, the relative displacements
    /// q and every DOF's displacement (the massless ones follow the pattern), as rows * zhat.
    Eigen::MatrixXd lambda, relative, displacement;
    FastModes fast;          ///< none when every mode is slow
    /// The slow flow in coordinates xi = slow_coordinates * zhat_slow, zhat_slow = slow_basis * xi
    /// (a basis of the slow invariant subspace, n x n_s, orthonormal in balanced coordinates):
    /// xi' = a_slow xi. In these coordinates the stiff modes' rounding (K y with K ~ the fastest
    /// eigenvalue squared) is not integrated over the long step. With no fast modes: a, and no
    /// basis. slow_restrict = slow_coordinates (I - projector).
    Eigen::MatrixXd a_slow, slow_basis, slow_coordinates, slow_restrict;
    double h = 0;            ///< step length (against the slow modes and the period)
    Eigen::MatrixXd step_exp;  ///< exp(a h)
    /// exp(a t): exp(a_slow t) on the slow part, closed form on the fast one.
    Eigen::MatrixXd exponential(double t) const;
};

/// One step of a recorded flow: zhat(t0 + s h) = sum_k u.col(k) s^k
/// + Re sum_j right.col(active_j) d_j exp(lambda_j h s) for s in [0, s_end] (the fast modes
/// present at the step's start: `data`'s FastModes).
struct Step {
    double t0 = 0, h = 0, s_end = 0;
    Modes modes;
    Eigen::MatrixXd u;
    const ModeData* data = nullptr;
    std::vector<Eigen::Index> active;
    Eigen::VectorXcd d;  ///< their coordinates at t0 (left * zhat)
    bool fast() const { return !active.empty(); }
    /// zhat at s.
    Eigen::VectorXd state(double s) const;
    /// d zhat / dt at s.
    Eigen::VectorXd rate(double s) const;
    /// The signal row * zhat over the step (polynomial.hpp).
    Signal signal(const Eigen::RowVectorXd& row) const;
    Signal signal(Eigen::Index i) const;  ///< of zhat(i)
    /// int_0^{s_end h} zhat_fast(t0 + t) exp(mu t) dt (complex mu; the fast part zhat_fast is
    /// real, so its integrals against cos and sin are the real and imaginary parts at mu = i w).
    Eigen::VectorXcd fast_integral(std::complex<double> mu) const;
};

/// The flow through the events of a piecewise-linear system zhat' = A_m zhat, zhat = [z (nz),
/// cos(w t), sin(w t), 1], z = [y (dofs), y' (dofs), internal states], whose pattern m (the
/// modes of its contacts) changes where a guard of the pattern reaches zero. An engine says
/// what a pattern's linear system and guards are (build), which pattern follows an event
/// (settle) and which relations of the pattern a split flow restores (restore_constraints);
/// this base class caches the patterns, splits their fast modes and flows a state through
/// the events with its monodromy (the segment exponentials and the saltation matrices).
class PatternEngine {
public:
    PatternEngine(double omega, bool split, int dofs, int contacts, int nz);
    virtual ~PatternEngine() = default;
    PatternEngine(const PatternEngine&) = delete;
    PatternEngine& operator=(const PatternEngine&) = delete;

    int dofs() const { return n_dofs_; }
    int contacts() const { return n_contacts_; }
    int nz() const { return nz_; }
    int n() const { return n_; }
    double period() const { return period_; }
    double omega() const { return omega_; }
    int cos_index() const { return nz_; }
    int sin_index() const { return nz_ + 1; }
    int one_index() const { return nz_ + 2; }

    Eigen::VectorXd augment(const Eigen::VectorXd& z, double t) const {
        Eigen::VectorXd zhat(n_);
        zhat.head(nz_) = z;
        zhat(cos_index()) = std::cos(omega_ * t);
        zhat(sin_index()) = std::sin(omega_ * t);
        zhat(one_index()) = 1.0;
        return zhat;
    }

    /// The linear system of a pattern, built on first use and cached.
    const ModeData& mode(const Modes& modes);
    /// The pattern's linear system if it is cached, else null.
    const ModeData* cached(const Modes& modes) const {
        const auto it = cache_.find(cache_key(modes));
        return it == cache_.end() ? nullptr : &it->second;
    }

    /// Modes after the event of guard `trigger` (of the pattern `modes`) at zhat.
    virtual Modes settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) = 0;

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
        /// Events of two contacts met at one instant independently (both triggers of one step
        /// change their contacts' patterns, or an event comes within 1e-9 of the period of the
        /// last by a step: mirror-image nodes of a symmetric interface), not one caused by the
        /// other (a cascade, settled at the instant of an event): the order the flow settles
        /// them in, and its derivative, follow rounding (ConeEngine).
        bool simultaneous = false;
    };

    /// Whether the next flows only start Newton (plain periods before it): an engine may take
    /// them to a looser local tolerance (ConeEngine); by default nothing changes.
    virtual void set_start_flows(bool start) { (void)start; }

    /// Flows zhat from t0 over `duration` (modes: the modes at t0, consistent with zhat).
    virtual Flow flow(Eigen::VectorXd zhat, Modes modes, double t0, double duration, bool monodromy, bool record,
              int max_events);

protected:
    /// The pattern's a and guards (and anything else of the engine's); finish() completes it.
    virtual ModeData build(const Modes& modes) const = 0;
    /// The cache's key of a pattern: the pattern, or one key for all where build does not
    /// depend on it (the cache then holds one entry however many patterns a flow meets).
    virtual Modes cache_key(const Modes& modes) const { return modes; }
    /// Puts zhat back on the pattern's invariant relations where a split flow (its fast modes
    /// in closed form) left it off them by rounding of the eigenvectors; the forcing's states
    /// at cos(w t), sin(w t), 1 (restore_forcing).
    virtual void restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const = 0;
    void restore_forcing(Eigen::VectorXd& zhat, double t) const;
    /// Records in out the contacts whose modes change from `before` to `after` at t (state zhat)
    /// and counts the event; false (out failed: chattering) past max_events.
    bool record_events(Flow& out, double t, const Modes& before, const Modes& after, const Eigen::VectorXd& zhat,
                       int& events, int max_events) const;
    /// Splits off the fast modes of m.a (and sets each guard's fast row), chooses the step
    /// (short against the slow modes and T / 24) and its exponential.
    void finish(ModeData& m) const;

    double omega_, period_;
    bool split_ = true;
    int n_dofs_ = 0, n_contacts_ = 0, nz_ = 0, n_ = 0;

private:
    std::map<Modes, ModeData> cache_;
};

/// The flows, events and mode data of one system with 1D friction contacts (exact Coulomb and
/// Jenkins) at one frequency.
class Engine : public PatternEngine {
public:
    /// split: flow the patterns' fast modes in closed form (fast_modes.hpp); false: every mode
    /// in the Taylor steps, short against the fastest.
    Engine(const System& system, double omega, bool split = true);

    const Contact& contact(int c) const { return system_.contacts[static_cast<std::size_t>(c)]; }
    const Eigen::VectorXd& direction(int c) const { return directions_[static_cast<std::size_t>(c)]; }
    /// A rigid slider (exact Coulomb); else an elastic slider (Jenkins): contact_law.hpp.
    bool coulomb(int c) const { return rigid_[static_cast<std::size_t>(c)] != 0; }
    const Eigen::VectorXd& excitation() const { return system_.excitation; }

    double velocity(int c, const Eigen::VectorXd& zhat) const { return direction(c).dot(zhat.segment(n_dofs_, n_dofs_)); }
    double relative(int c, const Eigen::VectorXd& zhat) const { return direction(c).dot(zhat.head(n_dofs_)); }
    /// An elastic slider's spring's far end, q + p cos(omega t) (p: Contact::base_motion, 0 but
    /// for a load on condensed massless DOFs); q for every other contact.
    double spring_end(int c, const Eigen::VectorXd& zhat) const {
        return relative(c, zhat) + contact(c).base_motion * zhat(cos_index());
    }

    /// Modes after an event (see event_exact.hpp).
    Modes settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) override;

    /// Releases stuck Coulomb contacts that cannot be held, the most overloaded first.
    Modes release_overloaded(const Eigen::VectorXd& zhat, Modes modes);

    /// Modes at the start of a flow from the state (hints: the modes carried with it) and a
    /// consistent state: a Jenkins spring beyond its limit is relaxed to it.
    Modes initial_modes(Eigen::VectorXd& zhat, const Modes& hints);

private:
    ModeData build(const Modes& modes) const override;
    /// Coulomb sliders at 0, stuck Coulomb contacts at rest (w^T v = 0), slipping Jenkins
    /// sliders at their limit, and the forcing.
    void restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const override;

    const System& system_;
    Eigen::MatrixXd mass_inverse_;
    std::vector<char> rigid_;  // per contact: a rigid slider (coulomb)
    std::vector<Eigen::VectorXd> directions_;
};

/// Sizes of section states z = [y (N), y' (N), sliders] in units of displacement: velocities
/// divided by omega, so that a problem in other units gives the same numbers.
struct SectionNorm {
    int dofs = 0;
    double omega = 1.0;
    double reference = 0.0;  ///< the size of the caller's start: floors the relative change
    /// The vectors' last `angles` entries are angles (a 3D contact's slip direction, radians):
    /// left out of the size, compared modulo 2 pi and absolutely.
    int angles = 0;
    /// The largest displacement-like entry: y, y' / omega, the rest but the angles.
    double size(const Eigen::VectorXd& z) const {
        double m = z.head(dofs).cwiseAbs().maxCoeff();
        m = std::max(m, z.segment(dofs, dofs).cwiseAbs().maxCoeff() / omega);
        const Eigen::Index rest = z.size() - 2 * dofs - angles;
        if (rest > 0) m = std::max(m, z.segment(2 * dofs, rest).cwiseAbs().maxCoeff());
        return m;
    }
    /// end - start, the angles' differences wrapped into [-pi, pi].
    Eigen::VectorXd difference(const Eigen::VectorXd& end, const Eigen::VectorXd& start) const {
        Eigen::VectorXd d = end - start;
        for (Eigen::Index k = d.size() - angles; k < d.size(); ++k) d(k) = std::remainder(d(k), 2.0 * pi);
        return d;
    }
    /// |P(z) - z| / max(reference, |z|): relative, and a state far off is not judged by its
    /// own size alone; the angles' change (radians) where larger.
    double relative_change(const Eigen::VectorXd& end, const Eigen::VectorXd& start) const {
        const double scale = std::max(reference, size(start));
        const Eigen::VectorXd d = difference(end, start);
        const double change = size(d);
        double turned = 0.0;
        if (angles > 0) turned = d.tail(angles).cwiseAbs().maxCoeff();
        return std::max(scale > 0.0 ? change / scale : change, turned);
    }
};

/// Values of a recorded flow at time t (inside the recorded range).
const Step& step_at(const std::vector<Step>& steps, double t);
Eigen::VectorXd state_at(const std::vector<Step>& steps, double t);

/// The state at t = 0 in time_integration's convention from zhat and modes.
Eigen::VectorXd full_state(const Engine& e, const Eigen::VectorXd& zhat, const Modes& modes);

}  // namespace hbf::detail::exact
