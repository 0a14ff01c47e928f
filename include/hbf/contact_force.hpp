// hbfriction — the periodic force of a contact law by AFT (alternating frequency/time).
//
// A contact sees the relative displacement q(theta) (coefficients, see fourier.hpp) and
// produces the friction force f(theta). Each law (one file per law in src/contact/, listed in
// contact_law.hpp's registry) decides how it evaluates the periodic force:
//   * memoryless laws map velocity samples to force samples pointwise: f = P f(E D q)
//     (coulomb-reg);
//   * state laws carry an internal state signal z, one more harmonic unknown balanced like the
//     equations of motion, and return the residual of its equation besides the force (Dahl and
//     LuGre: the bristle deflection; exact Coulomb by the dynamic Lagrangian: the force itself);
//   * hysteretic laws without unknowns march their state over the sampled period (Jenkins).
// Here E and P are the synthesis/analysis matrices of Fourier and D = omega D1 the derivative
// with respect to tau. The Jacobians are exact: the chain rule through E and P (on each
// stick/slip pattern for the set-valued and hysteretic laws).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <string>

#include "hbf/fourier.hpp"
#include "hbf/model.hpp"

namespace hbf {

/// Stick and slip, per law, from the law's own state (used for the stick fraction, the regime
/// and the transitions by harmonic balance and by time integration alike):
///   coulomb:      stick while the relative velocity is zero and |f| <= F_c (in harmonic
///                 balance: the samples with |lambda + eps v| < F_c);
///   jenkins:      stick while the slider does not move (|k_t (q - s)| < F_c);
///   dahl, lugre:  stick (pre-sliding) while the bristle force is below stick_force_ratio of
///                 its sliding limit: |sigma0 z| < stick_force_ratio g(v);
///   coulomb-reg:  stick while |f| < stick_force_ratio F_c, i.e. |v| < eps atanh(ratio).
/// The smooth laws never reach their limit, hence the ratio below 1.
constexpr double stick_force_ratio = 0.95;

/// Force (and state residual) coefficients of one contact with their Jacobians.
struct FrictionEvaluation {
    Eigen::VectorXd force;           ///< f coefficients (2H+1)
    Eigen::VectorXd state_residual;  ///< r_z coefficients (empty for memoryless laws)
    Eigen::MatrixXd force_q, force_z, state_q, state_z;  ///< d(force, r_z)/d(q, z)
    Eigen::VectorXd force_omega, state_omega;            ///< d(force, r_z)/d omega
    double jacobian_seconds = 0;  ///< time the last evaluate spent on the Jacobians
};

class FrictionModel {
public:
    virtual ~FrictionModel() = default;
    /// Number of internal-state signals this law adds to the unknowns, 2H+1 coefficients each
    /// (0; 1 for exact Coulomb's multiplier and the bristle; one per direction for law
    /// unilateral's multipliers). z and state_residual stack them; force_z is
    /// (signals x state_signals) blocks, state_q (state_signals x signals) blocks.
    virtual int state_signals() const = 0;
    /// Number of relative displacements the contact sees (System::contact_directions): 1 for
    /// the laws along one direction; 2 or 3 for the elements with a normal direction (the
    /// tangential ones, then the normal one). q and force stack their coefficients, 2H+1 each,
    /// in that order, and force_q is (signals (2H+1)) square.
    virtual int signals() const { return 1; }
    /// Fills `out` from the coefficients of q and z (z is empty when state_signals() == 0).
    /// Jacobians are computed only when `jacobian` is true.
    virtual void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                          FrictionEvaluation& out, bool jacobian) const = 0;
    /// Force samples f(theta_j) on the time grid of `fourier` (for post-processing): the law's
    /// own force in time (exact Coulomb: the projected multiplier, |f| <= F_c; Jenkins: the
    /// marched force), whose H-harmonic series is what the balance equations see. With several
    /// signals, the samples of each force stacked (signals N_t).
    virtual Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                          const Eigen::VectorXd& z) const = 0;
    /// Stick indicator phi(theta_j) on the time grid of `fourier`: the sample sticks iff
    /// phi < 0 (definitions at the top of this file). phi is a continuous measure of the
    /// distance to the friction limit: coulomb |lambda + eps v| / F_c - 1; dahl, lugre
    /// |sigma0 z| / (ratio g(v)) - 1; coulomb-reg |tanh(v / eps)| / ratio - 1; jenkins
    /// |f| / F_c - 1 where the slider rests and 0 where it moves; the elements with a normal
    /// direction |T| / (mu N) - 1 where stuck, 0 where slipping, 1 where separated.
    virtual Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                            const Eigen::VectorXd& z) const = 0;
    /// The number of time samples N_t the law needs at this motion for its AFT to resolve its
    /// own time scale (0: none beyond the harmonics'): coulomb-reg's tanh turns from -F_c to F_c
    /// while |v| < eps, a phase of about eps / max|v|, which the samples must not step over
    /// (under-resolved, the force's coefficients jump whenever a zero of v passes a sample: the
    /// FRF wiggles with spurious peaks), so 2 pi max|v| / eps.
    virtual double time_samples_needed(Fourier& fourier, double omega, const Eigen::VectorXd& q) const {
        (void)fourier;
        (void)omega;
        (void)q;
        return 0.0;
    }
    /// Why the law needs time_samples_needed samples, for messages ("to resolve its regularised
    /// friction law's turn (2 pi max|v| / eps)").
    virtual std::string time_samples_reason() const {
        return "to resolve its regularised friction law's turn (2 pi max|v| / eps)";
    }
    /// Laws whose residual switches between two forms (law unilateral's permanent stick) hold
    /// the form while `on`: the first evaluation after hold_switch(true) decides it, every later
    /// one keeps it, until hold_switch(false). A corrector holds it for one Newton solve (the
    /// residual is discontinuous across the switch away from a solution, and Newton may cycle
    /// across it) and judges the solution with the switch free. Returns whether the law has such
    /// a switch (default: none, nothing held).
    virtual bool hold_switch(bool on) const {
        (void)on;
        return false;
    }
};

/// A smooth law's local linearisation at one instant, in time t (not tau): the force
/// f(q, v, z) and the state rate z' = g(v, z) (v = q', z the internal state; model.hpp) moved by
/// small changes of q, v and z (the friction laws depend on v and z only, the springs on q):
///   df = f_q dq + f_v dv + f_z dz,   d(z') = g_v dv + g_z dz.
///   dahl, lugre: z' = v - sigma0 |v| z / g(v), f = sigma0 z + sigma1 z' + sigma2 v, so
///                g_v = 1 - sigma0 z (sign(v) g - |v| g') / g^2, g_z = -sigma0 |v| / g,
///                f_v = sigma1 g_v + sigma2, f_z = sigma0 + sigma1 g_z
///                (at v = 0 the one-sided slopes of |v| differ; sign(0) = 0 takes their mean);
///   coulomb-reg: f = F_c tanh(v / eps): f_v = F_c (1 - tanh^2) / eps, no state;
///   polynomial, gap, damper: f_q = f'(q), or f_v = f'(v) (the gap: k where closed, 0 open,
///   the one-sided slope's mean at the corner).
/// The stability analysis (stability.hpp) builds the variational equations from it.
struct LocalLinearization {
    double f_q = 0, f_v = 0, f_z = 0, g_v = 0, g_z = 0;
};
/// The linearisation above at (q, v, z) for a smooth law's contact (contact_law(law).linearize);
/// throws InvalidInput for the others (set-valued or hysteretic: not differentiable).
LocalLinearization linearize(const Contact& contact, double q, double v, double z);

/// The model for a contact's law (contact_law(contact.law).periodic_model). Throws InvalidInput
/// for invalid parameters (exact Coulomb: lagrangian_penalty must be > 0; HarmonicBalance fills
/// in the automatic value).
std::unique_ptr<FrictionModel> make_friction_model(const Contact& contact);

}  // namespace hbf
