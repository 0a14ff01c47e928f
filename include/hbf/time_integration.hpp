// hbfriction — periodic steady state by time integration (SUNDIALS CVODE): the reference
// for harmonic balance.
//
// The equations of motion of model.hpp,
//
//     M y'' + C y' + K y + sum_c w_c f_c(t) = F cos(omega t),
//
// are integrated period by period (T = 2 pi / omega, every period restarts at t = 0 with
// CVodeReInit, so the excitation phase is exact) until the Poincare map x_k -> x_{k+1} (the
// state at the start of consecutive periods) converges. Each law is integrated as it is
// defined in model.hpp:
//
// * dahl, lugre: one smooth ODE with the bristle deflection z_c as an extra state;
// * coulomb-reg: f = F_c tanh(v / eps), no extra state;
// * coulomb (set-valued): event-driven. Each contact is in stick (mode 0) or slip (mode +1 or
//   -1, the sign of its velocity v_c). In slip f_c = mode F_c. The stuck set S is held by
//   constraint forces lambda_S solved from w_c^T y'' = 0 (c in S):
//       a0 = M^-1 (F cos - C y' - K y - sum_{c not in S} w_c f_c),
//       lambda_S = (W_S^T M^-1 W_S)^+ W_S^T a0,   y'' = a0 - M^-1 W_S lambda_S
//   (pseudo-inverse: linearly dependent stuck contacts get the minimum-norm forces).
//   Events (CVODE root finding, every root function is positive while its mode holds):
//     stick: F_c - |lambda_c| reaches 0 -> slip with mode sign(lambda_c);
//     slip:  mode v_c reaches 0 -> the contact is tried in stick: it sticks if the force
//            required to hold it (with the other stuck contacts) is |lambda_c| <= F_c, else
//            it slips with mode sign(lambda_c) (a reversal, or a touch without stop).
//   With several contacts the stuck set is settled by releasing the most overloaded contact
//   one at a time. At every event the velocities of the contacts at rest are projected onto
//   the constraint (v_c = 0 exactly, minimum kinetic-energy correction) and CVODE restarts.
// * jenkins: a spring k_t in series with a Coulomb slider s_c (state). Stick (mode 0):
//   s' = 0, f = k_t (q - s), event when F_c - |f| reaches 0 -> slip with mode sign(f) and
//   s = q - mode F_c / k_t. Slip: s' = q', f = mode F_c, event when mode v_c reaches 0 ->
//   stick (unless q'' keeps the direction: a touch without reversal).
// * elastic (contacts with a normal direction, 2D/3D, normal load and lift-off): integrated by
//   their own event-driven CVODE integrator (src/time_integration/elastic_contacts.hpp): each
//   contact separated, stuck or slipping, its slider a state (d components), the stick, slip
//   and separation events found by root finding. Its state is [y, y', sliders, modes] (mode 0
//   separated, 1 stuck, 2 slipping), state_size() long; every contact must be elastic and M
//   positive definite.
// * unilateral (rigid Signorini + Coulomb contacts on massless coordinates): their own
//   fixed-step integrator (src/time_integration/unilateral_contacts.hpp): velocity Verlet on
//   the DOFs with mass and, at every step, the complementarity problem of the massless contact
//   nodes solved exactly (semi-smooth Newton); at least 16 samples_per_period steps per period.
//   Its state is [y, y'] (2N); every contact must be unilateral, on massless undamped DOFs.
//
// A cap on events per period guards against chattering (reported, never a hang).
//
// Massless DOFs (zero rows of M, e.g. the static boundary of a reduced model) are condensed
// out exactly before integrating (src/model/massless.hpp): their equations are
// static, y_S = K_SS^-1 (F_S cos - K_SR y_R - W_S f). A Coulomb contact on them, behind the
// compliance g = w_S^T K_SS^-1 w_S, is integrated as the Jenkins element it is (k_t = 1 / g;
// a Jenkins contact's springs add in series). Required, else InvalidInput with the reason: no
// damping on massless DOFs, K_SS invertible, only coulomb or jenkins on massless DOFs, no two
// of them coupled through K_SS^-1, no excitation on massless DOFs that carry a contact. The
// massless DOFs' y_max is the largest of the period's samples and their velocity samples a
// central difference (the massive DOFs keep the exact turning points).
//
// Stick and slip follow contact_force.hpp (stick_force_ratio): coulomb and jenkins by the mode
// (exact event times), dahl and lugre while |sigma0 z| < ratio g(v), coulomb-reg while
// |tanh(v / eps)| < ratio; the smooth laws' indicator crossings are root functions too, so
// every stick fraction is exact to the integration tolerance.
//
// Metrics of the final period are integrated with the motion (extra quadrature components of
// the ODE, reset every period): the first-harmonic coefficients
// c1_i = (2/T) int y_i cos(omega t) dt, s1_i = (2/T) int y_i sin(omega t) dt, the friction
// energy int sum_c f_c v_c dt, the viscous energy int y'^T C y' dt and the input work
// int F^T y' cos(omega t) dt. y_max uses CVODE root finding on y_i' = 0.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "hbf/event_exact.hpp"
#include "hbf/model.hpp"
#include "hbf/verdict.hpp"

namespace hbf {

/// Linear multistep family of CVODE. Measured on the paper's absorber (README): Adams with
/// fixed-point iteration is faster for these non-stiff problems; BDF with Newton and a dense
/// difference-quotient Jacobian is there for stiff contacts (large wb or k_t).
enum class IntegrationMethod { adams, bdf };

struct TimeIntegrationOptions {
    /// The ranges validate() checks, the one home of those the front ends name in their help.
    static constexpr double smallest_relative_tolerance = 1e-14, largest_relative_tolerance = 1e-3;
    static constexpr double smallest_absolute_tolerance = 1e-16, largest_absolute_tolerance = 1e-3;
    static constexpr double smallest_steady_tolerance = 1e-14, largest_steady_tolerance = 1e-2;
    /// The most periods one frequency may take: bounded time (a period of the absorber takes
    /// about 0.1 ms to 1 ms, so at most minutes a frequency).
    static constexpr int largest_max_periods = 1000000;
    /// CVODE relative tolerance (local error per step), 1e-14..1e-3.
    double relative_tolerance = 1e-10;
    /// CVODE absolute tolerance, 1e-16..1e-3, relative to the response's scale (so the same in
    /// any units and at any frequency): displacements and internal states get
    /// absolute_tolerance * s, velocities absolute_tolerance * h omega s, with s the
    /// displacement scale (displacement_scale, or response_scale(system, omega)); the metrics'
    /// quadratures likewise (s T for the first harmonic, 2 pi h |F| s for the energies).
    double absolute_tolerance = 1e-10;
    /// Displacement scale s of the absolute tolerances and of the physics checks, in the
    /// System's units; 0 (default) = automatic, response_scale(system, omega). >= 0, finite.
    double displacement_scale = 0;
    IntegrationMethod method = IntegrationMethod::adams;
    /// BDF's Newton systems (I - gamma J) dx = r: up to this many DOFs, CVODE's dense LU of a
    /// difference-quotient Jacobian of the whole state. Beyond (finite-element models), GMRES
    /// preconditioned by the structure's exact second-order solve: per step a sparse LU of
    /// M + gamma C + gamma^2 K, bordered by the stuck Coulomb contacts' constraints (friction
    /// slopes and internal states are left to GMRES). 0 uses the sparse route always.
    int dense_newton_max_dofs = 16;
    /// Poincare convergence, relative and independent of the units:
    /// max(|dy|_inf, |dz|_inf, |dy'|_inf / omega) <= steady_tolerance * s with
    /// s = max(|y|_inf, |y'|_inf / omega) of x_{k+1} (dy, dy', dz: changes of the
    /// displacements, velocities and internal states from x_k to x_{k+1}). 1e-14..1e-2.
    double steady_tolerance = 1e-8;
    /// At least this many periods are integrated (>= 1), so a converged answer has seen the
    /// steady state repeat at least once after min_periods - 1 periods of settling.
    int min_periods = 3;
    /// At most this many periods (min_periods..largest_max_periods); then converged = false
    /// (never hangs).
    int max_periods = 3000;
    /// Equally spaced samples per period of the signals kept for the final period (>= 8).
    int samples_per_period = 256;
    /// More contact events (stick/slip switches) than this in one period is treated as
    /// chattering: the integration stops with converged = false.
    int max_events_per_period = 1000;
    /// CVODE internal steps allowed per period before giving up (converged = false).
    long max_steps_per_period = 1000000;
    /// Try the start linear_stuck_state() once: when every contact stayed in stick
    /// (exact stick for coulomb/jenkins, the stick definition of contact_force.hpp for the smooth
    /// laws) during `stick_restart_periods` consecutive periods without Poincare convergence,
    /// or at the first shooting step. It is kept only if its first period changes less than
    /// the current one (else the iteration goes on from where it was). Needed for undamped
    /// structures (C = 0, like the paper's absorber): in stick they are linear oscillators
    /// whose free vibration never decays, so the map cannot converge from other states. Set
    /// false to integrate from the given initial state only.
    bool stick_restart = true;
    int stick_restart_periods = 3;
    /// Newton acceleration of the Poincare map (shooting): every `shooting_interval` periods,
    /// if the change did not drop by a factor 5 over the last period (slow contraction), the
    /// Jacobian J of the map x -> P(x) is built by forward differences (one extra period per
    /// continuous state, counted in `periods`) and the start is moved to
    /// x + (I - J)^-1 (P(x) - x). The step is kept only if the next period's change is smaller
    /// than before it (else reverted and the interval doubled; after a kept step the next
    /// one follows at once if the change is still too large), and convergence is still
    /// decided by plain periods, so it changes where the iteration starts, not the test.
    bool shooting = true;
    int shooting_interval = 5;
    /// Up to this many continuous states the shooting Jacobian is built column by column
    /// (one period per state, as above). Beyond (finite-element models), the Newton step
    /// (I - J) s = P(x) - x is solved matrix-free by GMRES, one period per product J v, to a
    /// relative residual of 1e-4 or at most `shooting_krylov_max` products: a damped
    /// structure has only a few Floquet multipliers that are not small, so GMRES needs about
    /// twice that many periods, not one per state.
    int shooting_dense_max_states = 64;
    int shooting_krylov_max = 60;
    /// Outputs o(t) = c^T y(t) (model.hpp) whose output_max (turning points by root finding
    /// on c^T y' = 0, as y_max) and output_amp1 are computed.
    std::vector<Output> outputs;
    /// Asked after every period: a non-empty answer (why: an interrupt, a time limit) ends the
    /// integration there, with converged = false and stopped = true (PeriodicResponse). Empty:
    /// never asked. sweep() computes no further frequency after a stopped one.
    std::function<std::string()> stop;

    /// Throws InvalidInput naming the first option out of range.
    void validate() const;
    /// stop's answer, "" without one.
    std::string stop_reason() const { return stop ? stop() : std::string(); }
    /// Largest relative error the physics checks of a converged steady state allow (energy
    /// balance, stick kinematics, the permanent-stick convention):
    /// max(1e-6, 100 max(relative_tolerance, steady_tolerance)). Measured at the defaults
    /// (rtol 1e-10, steady-tol 1e-8): energy 1e-10..5e-9 on the absorber (every law, fe = 0.1
    /// and 0.5, 12 frequencies) and chain3.toml (adams and bdf).
    double physics_tolerance() const;
};

/// Periodic steady state at one frequency and the metrics of its final period.
///
/// State vector convention (initial_state and state), size state_size(system) = 2N + 2 n_c
/// for N DOFs and n_c time-domain elements: the contacts, each counted as its law's
/// time_elements (contact_law.hpp; one a contact, except an Iwan joint: one a slider, in order),
/// which are also the contacts of the per-contact results below:
///   [ y (N), y' (N), internal (n_c), mode (n_c) ]
/// internal_c = bristle deflection z (dahl, lugre), slider position s (jenkins), 0 otherwise;
/// mode_c = 0 stick, +1 slip with v_c > 0, -1 slip with v_c < 0 (coulomb, jenkins), 0 for the
/// smooth laws. Inconsistent given states are repaired at t = 0: a stuck coulomb contact gets
/// v_c = 0 (and slips if it cannot be held), a slip mode against the velocity takes the
/// velocity's sign, a jenkins spring beyond F_c is relaxed to the limit.
struct PeriodicResponse {
    double omega = 0;
    bool converged = false;
    /// Why it did (not) converge: the last Poincare change, an event cap, a CVODE failure.
    std::string message;
    int periods = 0;              ///< periods integrated (with the shooting Jacobians' ones)
    double poincare_change = 0;   ///< last relative change of the state (steady_tolerance)
    Eigen::VectorXd state;        ///< state at the start of the final period (convention above)

    // ---- metrics of the final period (columns of `hbf frf`) ----
    std::vector<double> y_max;    ///< per DOF: max over the period of |y_i(t)|
    std::vector<double> y_amp1;   ///< per DOF: sqrt(c1^2 + s1^2)
    /// per DOF: Y_i = c1 - i s1, so that the first harmonic is Re(Y_i e^{i omega t})
    /// (the convention of linear_response).
    Eigen::VectorXcd harmonic1;
    std::vector<double> output_max;   ///< per options.outputs: max over the period of |o(t)|
    std::vector<double> output_amp1;  ///< per options.outputs: first-harmonic amplitude of o(t)
    double stick_fraction = 0;    ///< share of the period contact 1 is in stick (0 if no contact)
    /// "stick" if contact 1 never left stick in the period, "slip" if it never stuck, else
    /// "stick-slip" ("none" without contacts).
    std::string regime;
    std::vector<ContactRegime> contacts;  ///< every contact's, in order (contacts[0]: the two above)
    /// Stick indicator of contact 1 (contact_force.hpp), min and max over the period: coulomb
    /// |lambda|/F_c - 1 in stick and, at each slip -> stick/reversal instant, the required
    /// |lambda|/F_c - 1; jenkins |f|/F_c - 1; dahl, lugre |sigma0 z| / (ratio g(v)) - 1;
    /// coulomb-reg |tanh(v/eps)| / ratio - 1. Stick iff < 0; max < 0 means full stick.
    /// Evaluated at every step, event and sample (not a continuous extremum).
    double stick_margin_min = 0, stick_margin_max = 0;
    int switches = 0;             ///< mode changes of all contacts in the period (stick <-> slip,
                                  ///< reversals; smooth laws: stick-indicator crossings)
    double energy = 0;            ///< friction energy per cycle: int sum_c f_c v_c dt
    double viscous_energy = 0;    ///< int y'^T C y' dt over the period
    double input_energy = 0;      ///< int F^T y' cos(h omega t) dt over the period
    /// Physics checks of the final period (see integrate_steady_state), each relative, against
    /// options.physics_tolerance(): energy_error = energy_imbalance(input, viscous, friction,
    /// pi |F| |Y|) (model.hpp; Y: the first harmonic, or y_max for a force at h omega, h > 1); stick_error = the largest variation over the period of q_c of
    /// a coulomb contact stuck for the whole period, relative to s, and in permanent stick the
    /// distance of the state from linear_stuck_state (y, y' / (h omega), internal states)
    /// relative to that state's size (not below s); 0 if none applies.
    double energy_error = 0;
    double stick_error = 0;
    double displacement_scale = 0;  ///< s of the absolute tolerances (TimeIntegrationOptions)

    // ---- sampled signals of the final period: t_j = j T / samples, j = 0..samples-1 ----
    Eigen::VectorXd time;
    Eigen::MatrixXd displacement;    ///< samples x N
    Eigen::MatrixXd velocity;        ///< samples x N
    Eigen::MatrixXd friction_force;  ///< samples x n_c (constraint force for stuck coulomb)

    // ---- cost ----
    long steps = 0;                  ///< CVODE steps, all periods
    long rhs_evaluations = 0;
    double seconds = 0;

    /// Ended by TimeIntegrationOptions::stop before it converged (then converged = false, the
    /// metrics are those of the last full period if any, and the message says why).
    bool stopped = false;
    /// exact_steady_state only: the orbit's largest |Floquet multiplier| (above 1: unstable, a
    /// time integration leaves it); NaN where not computed, and where a converged orbit's
    /// multipliers could not be (its stability unknown: the message says why).
    double max_multiplier = std::numeric_limits<double>::quiet_NaN();
    /// exact_steady_state only: the multipliers' accuracy (ExactOrbit::multiplier_accuracy). A
    /// max_multiplier above 1 + the stability tolerance but at most 1 + this is a neutral
    /// direction the multipliers cannot place: stability uncertain (stability_unresolved).
    double multiplier_accuracy = 0;
    /// Converged, max_multiplier above 1 + stability_tolerance and within multiplier_accuracy of 1.
    bool stability_unresolved(double stability_tolerance) const {
        return converged && max_multiplier > 1.0 + stability_tolerance && max_multiplier <= 1.0 + multiplier_accuracy;
    }
    /// Marks this response stopped after `periods` periods for `why` (the message says so).
    void stop_after(int periods, const std::string& why);

    /// One line: frequency, converged or why not, periods, y_max, regime.
    std::string summary() const;
};

/// 2N + 2 n_c (see PeriodicResponse); with law elastic 2N + sum_c (d_c + 1) (d_c tangential
/// directions: the sliders, and one mode per contact); with law unilateral 2N.
int state_size(const System& system);

/// The displacement scale of the steady state at omega (units of y), from which the absolute
/// tolerances and the physics checks are scaled: the smaller of |K^-1 F|_inf, the quasi-static
/// response (the response far below the resonances), and |M^-1 F|_inf / (h omega)^2, the mass
/// line (far above them); the other one where one is not finite (a singular K or M), 1 where
/// neither is positive and finite. A K that is singular (a part held only by its contacts,
/// e.g. a massless shoe sliding on the ground) gets each contact held by a spring of its
/// largest diagonal entry for the quasi-static response. Near a resonance the response is larger (the tolerances are
/// then tighter than needed, never looser). Not the stuck linear response: a contact that
/// holds a DOF to the ground makes it vanish while the contact slips.
double response_scale(const System& system, double omega);

/// The state at t = 0 of the linear steady state with every contact stuck: coulomb contacts
/// rigid (exact constraint), jenkins as the spring k_t (s = 0), dahl and lugre as their
/// pre-sliding spring sigma0 and damper sigma1 + sigma2 (z = q), coulomb-reg as the damper
/// F_c / eps; modes 0. It is the exact periodic solution when the contacts really stick
/// (coulomb, jenkins); otherwise a start close to the stick regime. Rest (zeros) at an
/// undamped resonance of that linear system. With law unilateral: rest (zeros). With law
/// elastic: the static state under the static load and preloads with the contacts' normal
/// springs alone (no tangential static force), plus that linear steady state with every pressed
/// contact stuck (static_state.hpp: stuck_elements; pressed by its own preload or by the static
/// load), the sliders centred (at the static state's tangential positions: the stuck force
/// has zero mean, harmonic balance's convention).
Eigen::VectorXd linear_stuck_state(const System& system, double omega);

/// Integrates from `initial_state` (nullptr: rest, modes stick) period by period until the
/// Poincare map converges (after at least min_periods) or max_periods is reached. Throws
/// InvalidInput for an invalid system, omega <= 0, bad options or a state of the wrong size.
///
/// A converged map is `converged` only if the final period passes its physics checks (to
/// options.physics_tolerance(), see energy_error and stick_error): the energy balance (input
/// work = viscous + friction energy per period); every coulomb contact stuck for the whole
/// period keeps q_c constant (the masses it joins move together); and in permanent stick (every
/// contact coulomb or jenkins and stuck for the whole period) the state is linear_stuck_state,
/// the convention of event_exact.hpp (permanent stick is degenerate: any offset of a stuck
/// contact is periodic too; the centred one, mean friction force zero, is the answer). A
/// permanent-stick orbit elsewhere in that family is moved to linear_stuck_state once (with
/// stick_restart) and integrated again. Otherwise converged = false and the message says
/// which check failed. (The Poincare test alone cannot tell: far above the resonances a free
/// vibration of an undamped structure changes by ~2 pi omega_n / omega of itself per period.)
PeriodicResponse integrate_steady_state(const System& system, double omega, const TimeIntegrationOptions& options,
                                        const Eigen::VectorXd* initial_state = nullptr);

/// integrate_steady_state at each omega in the given order (ascending: sweep up;
/// descending: sweep down), each starting from the previous point's final state (the first
/// from `initial_state`, nullptr: rest).
std::vector<PeriodicResponse> sweep(const System& system, const std::vector<double>& omegas,
                                    const TimeIntegrationOptions& options,
                                    const Eigen::VectorXd* initial_state = nullptr);

/// "adams", "bdf"; the parser throws InvalidInput naming the allowed values.
std::string to_string(IntegrationMethod method);
IntegrationMethod parse_integration_method(const std::string& name);

/// The verdict on time-integration steady states (hbf timeint): errors for the points that did
/// not converge (each one's summary, and their count). A converged time-integration point has
/// passed its physics checks (energy balance, stick; integrate_steady_state). With `exact`, the
/// options the exact solver ran with (exact_steady_state; nullptr for time integration): a
/// warning when converged points of an undamped structure fail the energy balance (input work =
/// friction energy per period, relative to the work the force could do on the first harmonic;
/// limit options.physics_tolerance(); the exact solver does not integrate the viscous energy),
/// and notes counting the unstable exact orbits (max_multiplier above 1 +
/// exact->stability_tolerance), those of unknown stability and those Newton left at the flow's
/// rounding (period-map residual above exact->tolerance).
Verdict judge_sweep(const System& system, const std::vector<PeriodicResponse>& responses,
                    const TimeIntegrationOptions& options, const ExactOptions* exact);

/// Why the event-exact solver cannot sweep `system` from omega_min up (hbf timeint --method
/// exact; one sentence), empty when it can: law unilateral's rigid_solver_refusal
/// (rigid_exact.hpp), law elastic's elastic_solver_refusal (elastic_exact.hpp), else
/// exact_cost_refusal (event_exact.hpp).
std::string exact_sweep_refusal(const System& system, double omega_min);

/// The start of a sweep's next exact orbit at omega (hbf timeint --method exact) from the
/// points done (in sweep order): with law unilateral in 2D (states [y, y'], smooth in omega)
/// the secant through the last two for y, y' of the DOFs with mass, where both converged and
/// omega is beyond the last, and the last point's for the massless DOFs (where stuck contacts
/// are held: a slow sweep leaves them there); otherwise the last point's state, or `first`
/// where none is done. Not the secant where a contact is 3D: nodes stuck all period there are
/// held anywhere inside their cones (a family of orbits), the member reached moves from one
/// point to the next, and the secant carries that move on while the held positions stay, which
/// pushes stuck nodes' forces past their cones' edges at the start.
Eigen::VectorXd exact_sweep_start(const System& system, double omega, const std::vector<PeriodicResponse>& done,
                                  const Eigen::VectorXd& first);

/// Plain periods before Newton where a sweep's exact orbit starts from another frequency's
/// orbit on 3D rigid contacts (law unilateral with a second_direction): exact_sweep_options.
constexpr int exact_shakedown_periods = 6;

/// The options of a sweep's next exact orbit (hbf timeint --method exact, the branch) started
/// from another frequency's orbit (`from_orbit`): on 3D rigid contacts at least
/// exact_shakedown_periods plain periods before Newton. Nodes stuck all period there graze the
/// edges of their friction cones (a shakedown leaves them so), and at the next frequency they
/// slip briefly; the period map is not smooth where such a slip starts, and Newton from the
/// previous orbit crept across those switches (100 to 170 periods a point on the mitre in
/// lift-off) where a few plain periods (the structure's own shakedown) first bring it to 30 or
/// so. Otherwise `options` unchanged. (exact_branch skips it after a point known unstable:
/// plain periods would leave that orbit.)
ExactOptions exact_sweep_options(const System& system, ExactOptions options, bool from_orbit);

/// The event-exact periodic orbit at omega (exact_periodic_orbit from `start`; for law
/// unilateral rigid_periodic_orbit, rigid_exact.hpp, and for law elastic
/// elastic_periodic_orbit, elastic_exact.hpp, from rest where `start` is zero) as a
/// time-integration result (hbf timeint --method exact): when it fails, it is tried again
/// after min(max_periods, 200) plain periods; `periods` counts the period maps of both;
/// options.stop's answer ends it (stopped). max_multiplier is the orbit's.
PeriodicResponse exact_steady_state(const System& system, double omega, ExactOptions options, int max_periods,
                                    const Eigen::VectorXd& start);

}  // namespace hbf
