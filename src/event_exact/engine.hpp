// hbfriction — internal to event_exact: the flow engine. Each stick/slip pattern (the modes
// of the contacts) is an autonomous linear system zhat' = A_m zhat; the engine builds and caches
// them, flows a state over Taylor steps through the contact events (their times the roots of
// the guard polynomials) and multiplies the monodromy with the saltation matrices (see
// event_exact.hpp).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "hbf/contact.hpp"
#include "hbf/event_exact.hpp"

namespace hbf::detail::exact {

/// The mode of each contact: +1 or -1 slipping in that direction, 0 stuck.
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

/// The flows, events and mode data of one system at one frequency.
class Engine {
public:
    Engine(const System& system, double omega);

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
    /// A rigid slider (exact Coulomb); else an elastic slider (Jenkins): contact.hpp.
    bool coulomb(int c) const { return rigid_[static_cast<std::size_t>(c)] != 0; }
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
    /// An elastic slider's spring's far end, q + p cos(omega t) (p: Contact::base_motion, 0 but
    /// for a load on condensed massless DOFs); q for every other contact.
    double spring_end(int c, const Eigen::VectorXd& zhat) const {
        return relative(c, zhat) + contact(c).base_motion * zhat(cos_index());
    }

    /// The linear system of a stick/slip pattern, built on first use and cached.
    const ModeData& mode(const Modes& modes);

    /// Modes after an event of contact `trigger` at zhat (see event_exact.hpp).
    Modes settle(const Eigen::VectorXd& zhat, Modes modes, int trigger);

    /// Releases stuck Coulomb contacts that cannot be held, the most overloaded first.
    Modes release_overloaded(const Eigen::VectorXd& zhat, Modes modes);

    /// Modes at the start of a flow from the state (hints: the modes carried with it) and a
    /// consistent state: a Jenkins spring beyond its limit is relaxed to it.
    Modes initial_modes(Eigen::VectorXd& zhat, const Modes& hints);

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
              int max_events);

private:
    ModeData build(const Modes& modes) const;

    const System& system_;
    double omega_, period_;
    int n_dofs_ = 0, n_contacts_ = 0, nz_ = 0, n_ = 0;
    Eigen::MatrixXd mass_inverse_;
    std::vector<char> rigid_;  // per contact: a rigid slider (coulomb)
    std::vector<Eigen::VectorXd> directions_;
    std::map<Modes, ModeData> cache_;
};

/// Values of a recorded flow at time t (inside the recorded range).
const Step& step_at(const std::vector<Step>& steps, double t);
Eigen::VectorXd state_at(const std::vector<Step>& steps, double t);

/// The state at t = 0 in time_integration's convention from zhat and modes.
Eigen::VectorXd full_state(const Engine& e, const Eigen::VectorXd& zhat, const Modes& modes);

}  // namespace hbf::detail::exact
