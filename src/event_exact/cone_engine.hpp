// hbfriction — internal to event_exact: the flow engine of rigid unilateral contacts with
// Coulomb friction (law unilateral) on the massless DOFs of a structure, for contacts with two
// tangential directions (3D: a friction cone) as well as one (2D).
//
// As in RigidEngine (rigid_engine.hpp), the massless nodes follow the masses statically and the
// contact forces lambda solve, per contact, the equations of its pattern:
//   open:      lambda = 0;
//   closed:    q_N = g_0                       (q = q0 - G lambda);
//   stuck:     q_T = s                         (s: the held tangential position, d entries);
//   slipping:  lambda_T = mu lambda_N d        (d the unit slip direction, q_T' = |q_T'| d).
// In 2D d = +1 or -1 and every pattern is linear. In 3D d = (cos theta, sin theta) in the
// contact's tangential directions, and theta is a state: the slip direction of a massless node
// is not a function of the positions. Its rate follows from keeping the slip velocity along d,
// d_perp . q_T' = 0, which is linear in theta' (with the coefficient mu lambda_N d_perp^T G_TT
// d_perp, regular while the contact presses). The flow of a pattern with a slipping 3D contact
// is thus nonlinear (lambda_T depends on cos theta, sin theta); it is integrated by Taylor
// series of high order (the coefficients of y, y', lambda and theta order by order, the
// contact equations solved at each order with the pattern's matrix, theta's from the
// direction condition), the step chosen so that the series' last terms are below rounding.
// Every signal of a step is then a polynomial, as in PatternEngine's linear flows, and the
// events are the first roots of the guards' polynomials:
//   open, the gap g_0 - q_N; closed, lambda_N; stuck, the friction margin mu^2 lambda_N^2 -
//   |lambda_T|^2 (2D: mu lambda_N -+ lambda_T); slipping, the slip speed d . q_T'.
// The recorded vector of a step is [zhat, lambda]: the mode data's rows (lambda, relative,
// displacement) are linear in it for every pattern.
//
// The state is zhat = [y_m, y_m', s (the tangential entries of every contact), theta (one per
// contact), cos(w t), sin(w t), 1]; s of a contact not stuck equals q_T, theta is used while
// a 3D contact slips.
//
// The direction equation is singular where lambda_N = 0: a 3D contact that closes into slip
// starts along the direction in which its slip is consistent (q_T' along d with lambda_N
// growing; a scan of the circle), as does one that reaches its friction limit while its normal
// force is still below the hold share (it closed into stick an instant before, and another
// contact's event at that instant changed its forces' rates: the force's own direction is then
// rounding), and a slipping 3D contact whose normal force is below 1e-6 of
// the largest contact force the engine has met holds its direction (the friction force it
// steers is below that share), over steps that end where its normal force has doubled past
// that threshold (at least 1e-8 of the period). Between that and a few per cent of the largest
// force the direction relaxes fast (at |q_T'| / (G mu lambda_N)) and the steps are short; a
// series that overflows ends the flow with that reason.
// Events of several contacts at one instant (symmetric nodes) are settled together: each
// takes its first successor, then those whose successor does not hold (with the others in
// their trial patterns) try their next ones; one none of whose successors holds beyond rounding
// takes the pattern the event leads to.
//
// Stiff stretches: a slipping node's direction relaxes at |q_T'| / (G mu lambda_N), on a
// meshed interface thousands of times a period, and an explicit series must step below that
// time. Where the Taylor step would be shorter than period / stiff_steps (or its series
// overflows), the step is implicit instead: Radau IIA collocation (radau.hpp, collocation_stages
// stages) on y, y' and the moving directions theta, Newton's matrix from the rates' differences,
// the step's length controlled by the collocation polynomial's defect at the midpoints between
// its nodes, filtered by (I - h J)^-1 (so that a stiff direction on its slow manifold does not
// shorten the step), to collocation_tolerance of the state's size (a direction's in radians
// times its contact's normal force over the largest contact force met: the error of the friction
// force mu lambda_N d it steers, as a share of the forces); its recorded vector is the
// polynomial through the nodes' values (order s + 1 inside the step, 2s - 1 at its end), and a
// step in which a guard has its root is repeated ending there, so that the event's state is the
// step's end.
//
// The derivative of a flow with respect to its start (flow(..., monodromy = true)): over the
// independent entries of zhat (independent(): y, y', the held positions of stuck contacts, the
// directions of slipping 3D contacts), by Radau IIA on the variational equation along each
// step's polynomial with the rates' Jacobian in closed form (rates_jacobian), and at each event
// the saltation (event_sensitivity: the event's time moved by the perturbation, the new
// pattern's held positions and directions as functions of the state before). Events of several
// contacts at one instant (symmetric nodes) move each contact's entries with its own event's
// time; where such contacts are coupled the flow is only piecewise differentiable (the order of
// the perturbed events matters) and psi is one of its one-sided derivatives at best. Events
// met at the instant of others, after a step of zero length (a cascade: a contact closing into
// slip that stops at once), move with those (EventTimes); a trigger that meets its guard with
// no slope (grazing) moves no time (Flow::grazing says so). psi is left empty where a
// pattern's equations are singular on the way or it is not finite. The periodic-orbit solver
// (rigid_orbit.cpp) takes it for Newton's matrix and the multipliers (GMRES and Arnoldi on
// central differences of the period map where it is missing or a Newton step with it fails).
// The rates after an event hold the directions the next step holds (closing contacts, and
// slipping ones pressed below hold_share), as the flow does.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <memory>
#include <vector>

#include "contact/massless_contacts.hpp"
#include "event_exact/engine.hpp"

namespace hbf::detail::exact {

class ConeEngine : public PatternEngine {
public:
    /// A contact's pattern: 0 open, 1 stuck; slipping: 2 (3D, along theta), +2 / -2 (2D).
    enum : int { open = 0, stuck = 1, slip = 2 };
    /// How steps are taken: Taylor series where they are long enough, else collocation
    /// (automatic); Taylor series only; collocation only (tests).
    enum class Stepping { automatic, taylor, collocation };
    void set_stepping(Stepping stepping) { stepping_ = stepping; }
    /// Flows that only start Newton (plain periods): collocation to 1e-10 of the state's size
    /// instead of 1e-12, a fifth of the implicit steps on a meshed interface in lift-off (the
    /// directions of slipping nodes under small normal forces set the step there).
    void set_start_flows(bool start) override { start_flows_ = start; }
    /// Contacts held stuck (an entry per contact, 1: held; empty: none): their friction limits
    /// are not guards, so a held contact stays stuck whatever its tangential force (it can still
    /// open). Newton's predictor on orbits whose nodes stick all period (rigid_orbit.cpp): such
    /// a node's held position is free (a family of orbits), and a Newton iterate that pushes its
    /// force past the cone's edge makes it slip for an instant, a kink in the period map. A flow
    /// with the derivative leaves out the held positions of held contacts stuck at its start
    /// (constant over it): psi's columns for them stay zero, and no step differentiates with
    /// respect to them.
    void hold_stuck(std::vector<char> contacts) { held_ = std::move(contacts); }
    /// Takes another engine's run state (of one system at one frequency): its held contacts,
    /// stepping, start flows and the scales its flows met (force_scale_, size_scale_). A twin
    /// that has followed an engine flows a state as that engine would (to rounding: each keeps
    /// its own factorisations); the exact solver flows the two perturbed periods of a central
    /// difference at once on an engine and its twin.
    void follow(const ConeEngine& other) {
        held_ = other.held_;
        stepping_ = other.stepping_;
        start_flows_ = other.start_flows_;
        force_scale_ = other.force_scale_;
        size_scale_ = other.size_scale_;
    }
    /// After flows on a twin: the larger of each scale the two met (as one engine that had
    /// flowed both).
    void merge_scales(const ConeEngine& twin) {
        force_scale_ = std::max(force_scale_, twin.force_scale_);
        size_scale_ = std::max(size_scale_, twin.size_scale_);
    }
    /// Stages of the collocation (order 2s - 1 at a step's end, s + 1 inside: the order of its
    /// local error estimate, which the step control uses).
    static constexpr int collocation_stages = 6;
    /// Where a slipping 3D contact opens at a step's end, the sensitivity's last stage is taken
    /// this share of its substep before the end (step_sensitivity).
    static constexpr double opening_back_off = 1e-5;
    /// Steps of the last flow by kind.
    long taylor_steps() const { return taylor_steps_; }
    long collocation_steps() const { return collocation_steps_; }
    /// Guards (kinds).
    enum : int { guard_gap = 0, guard_normal = 1, guard_limit = 2, guard_limit_negative = 3, guard_slip = 4 };

    /// Throws InvalidInput where split_massless_contacts does and for a force at a harmonic
    /// other than the fundamental.
    ConeEngine(const System& system, double omega);

    const MasslessContacts& split() const { return s_; }
    const System& system() const { return system_; }
    /// Tangential directions of contact c (1 or 2) and its first entries in lambda and zhat.
    int directions(int c) const { return s_.blocks[static_cast<std::size_t>(c)].d; }
    int tangential(int c) const { return s_.blocks[static_cast<std::size_t>(c)].first; }
    int normal(int c) const { return tangential(c) + directions(c); }
    int slider(int c) const { return 2 * n_dofs_ + slider_first_[static_cast<std::size_t>(c)]; }
    /// The contact whose held position has the zhat entry i (slider(c) <= i < slider(c) + d).
    int slider_contact(int i) const {
        int c = 0;
        while (!(i >= slider(c) && i < slider(c) + directions(c))) ++c;
        return c;
    }
    int theta(int c) const { return 2 * n_dofs_ + tangential_entries_ + c; }
    int tangential_entries() const { return tangential_entries_; }
    /// Size of the recorded vector [zhat, lambda].
    int recorded() const { return n_ + s_.lambdas; }

    Modes settle(const Eigen::VectorXd& zhat, Modes modes, const Guard& trigger) override;

    /// The patterns of a state (its y and the held positions s of stuck contacts) from the static
    /// contact problem; sets every slider to the tangential displacement and theta of slipping
    /// 3D contacts to their force's direction.
    Modes initial_modes(Eigen::VectorXd& zhat);

    /// Puts zhat on the pattern's relations at t: the forcing, the sliders of contacts not stuck
    /// at their tangential displacement.
    void make_consistent(Eigen::VectorXd& zhat, const Modes& modes, double t);

    /// Taylor coefficients (in time from t) of the recorded vector [zhat, lambda], orders 0..order.
    /// frozen: contacts whose direction is held over the step (a closing into slip). Also held
    /// (with decide_hold): slipping 3D contacts pressing with less than hold_share of the forces;
    /// without it (an implicit step's stages) `frozen` alone decides, as at the step's start.
    /// rates_only: the last order's terms of y, y' and theta only (its contact forces and sliders
    /// are left zero): the rates of an implicit step at order 1.
    Eigen::MatrixXd series(const Eigen::VectorXd& zhat, const Modes& modes, double t, int order,
                           const std::vector<char>& frozen = {}, bool decide_hold = true, bool rates_only = false) const;

    Flow flow(Eigen::VectorXd zhat, Modes modes, double t0, double duration, bool monodromy, bool record,
              int max_events) override;

private:
    Flow taylor_flow(Eigen::VectorXd zhat, Modes modes, double t0, double duration, bool monodromy, bool record,
                     int max_events);
    /// Newton's Jacobian of the rates and the rates at a step's start. The rates are computed
    /// by a step's first try and shared by its shorter tries; the Jacobian is computed where
    /// there is none (empty: a new pattern, or its refresh) and kept over the following steps of
    /// the pattern while Newton converges fast with it (fresh: computed at this start).
    struct StartJacobian {
        Eigen::MatrixXd J;
        Eigen::VectorXd rate;
        bool fresh = false;
        int iterations = 0;  ///< Newton's iterations in the last try
    };
    /// The previous implicit step's polynomial (u, over h) when the step from its end continues it
    /// (no event, same pattern and held directions): Newton's first guess extrapolates it.
    struct PreviousStep {
        Eigen::MatrixXd u;
        double h = 0.0;
        bool valid() const { return h > 0.0; }
    };
    /// One collocation step of `modes` from zhat over h (cone_collocation.cpp): u, the recorded
    /// vector's coefficients in s in [0, 1] (as series' scaled by h^k); error, the estimated
    /// local error over collocation_tolerance (accept <= 1). False where Newton does not converge.
    bool collocation_step(const Eigen::VectorXd& zhat, const Modes& modes, double h, const std::vector<char>& frozen,
                          StartJacobian& start, const PreviousStep& previous, Eigen::MatrixXd& u, double& error) const;
public:
    /// The rates of an implicit step's components `dyn` (y, y' and the moving directions theta,
    /// in that order, as collocation_step integrates them) at zhat and their Jacobian, in closed
    /// form: the derivatives of the contact forces' equations and of the directions' equation.
    void rates_jacobian(const Eigen::VectorXd& zhat, const Modes& modes, const std::vector<char>& frozen,
                        const std::vector<int>& dyn, Eigen::MatrixXd& J, Eigen::VectorXd& rate) const;
    /// The same rates' derivatives with respect to the entries `wrt` of zhat: y, y', the held
    /// positions of stuck contacts and the directions of slipping 3D contacts (moving or held);
    /// J is dyn x wrt.
    /// The contact forces lambda, the relative displacements q and their rates q' at a state, and
    /// their derivatives with respect to the entries wrt (L x wrt).
    struct ContactDerivatives {
        Eigen::VectorXd lambda, relative, relative_rate;
        Eigen::MatrixXd dlambda, drelative, drelative_rate;
    };
    void rates_jacobian(const Eigen::VectorXd& zhat, const Modes& modes, const std::vector<char>& frozen,
                        const std::vector<int>& dyn, const std::vector<int>& wrt, Eigen::MatrixXd& J,
                        Eigen::VectorXd& rate, ContactDerivatives* more = nullptr) const;

    /// The independent entries of zhat in a pattern: y, y', the held positions of stuck contacts
    /// and the directions of slipping 3D contacts (the other sliders follow from them).
    std::vector<int> independent(const Modes& modes) const;
    /// Multiplies phi (rows: the independent entries of the pattern, in independent()'s order;
    /// any number of columns) by the derivative of a step's end (at s_end) with respect to its
    /// start, along the step's recorded polynomial u over h (implicit: a collocation step).
    /// `opens_at_end`: a slipping 3D contact whose direction moves opens at the step's end (its
    /// normal force is zero there to rounding, and its direction's rate 0 / 0).
    void step_sensitivity(const Eigen::MatrixXd& u, double h, double s_end, bool implicit, const Modes& modes,
                          const std::vector<char>& frozen, bool opens_at_end, Eigen::MatrixXd& phi) const;

    /// y, y' and the moving directions: the entries an implicit step integrates.
    std::vector<int> moving_entries(const Modes& modes, const std::vector<char>& frozen) const;
    /// The events' time changes (rows over the flow's start): per contact, and the first
    /// trigger's. Events met at the same instant after others (a step of zero length: a cascade,
    /// such as a contact closing into slip that stops at once) move with those, not with their
    /// own guards (which are zero there by the cascade, not by the perturbation).
    struct EventTimes {
        std::vector<Eigen::RowVectorXd> of;
        Eigen::RowVectorXd first;
        /// A trigger met its guard with no slope (within 1e-10 of its terms: grazing); its time
        /// change is left out (the flow is not differentiable there).
        bool grazing = false;
        void clear() {
            of.clear();
            first.resize(0);
        }
    };
    /// phi (rows: independent(before)) carried through an event at the end (s_end) of a step of
    /// polynomial u over h: the first trigger's time moved by the perturbation, the new
    /// pattern's independent entries as functions of the state before (rows: independent(after)).
    /// times: the last events' time changes, taken where s_end = 0 and times is not empty (a
    /// cascade), and set to this event's.
    Eigen::MatrixXd event_sensitivity(const Eigen::MatrixXd& u, double h, double s_end, const Modes& before,
                                      const std::vector<char>& frozen, const std::vector<Guard>& triggers,
                                      const Modes& after, const Eigen::VectorXd& zhat_after,
                                      const std::vector<char>& closing, const Eigen::MatrixXd& phi,
                                      EventTimes& times) const;

private:
    /// The state's size for the collocation's error (y, y' / omega; at least its running largest).
    double state_size(const Eigen::VectorXd& zhat);
    /// The pattern's matrix A(theta), the contact forces' equations, factorised (throws where
    /// singular). Within a pattern A depends on the slipping 3D contacts' directions only through
    /// their entries (T, N) and (T + 1, N): A(theta) = A(theta_0) + U V^T of rank k (the number
    /// of those contacts), so it is solved from a kept factorisation at theta_0 by the
    /// Sherman-Morrison-Woodbury formula (k + 1 small solves instead of an L x L LU per call),
    /// refactorised where the pattern changes, a direction has turned by more than
    /// PatternSolve::max_turn since theta_0, or the k x k capacitance matrix is ill-conditioned.
    class PatternSolve {
    public:
        /// Base: A(theta_0)'s LU for one pattern and A(theta_0)^-1 of its direction columns.
        struct Base {
            Modes modes;
            Eigen::VectorXd theta;            ///< theta_0, per slipping 3D contact (in contact order)
            Eigen::PartialPivLU<Eigen::MatrixXd> lu;
            Eigen::MatrixXd on_cos, on_sin;   ///< A0^-1 e_T, A0^-1 e_{T+1} per cone (L x k)
            std::vector<int> normal_rows;     ///< N per cone
            std::vector<int> tangential_rows; ///< T per cone
        };
        static constexpr double max_turn = 0.3;     ///< radians
        static constexpr double min_rcond = 1e-8;  ///< of the capacitance matrix
        PatternSolve() = default;
        PatternSolve(std::shared_ptr<const Base> base, Eigen::MatrixXd w, Eigen::PartialPivLU<Eigen::MatrixXd> capacitance)
            : base_(std::move(base)), w_(std::move(w)), capacitance_(std::move(capacitance)) {}
        /// A(theta)^-1 r (r: L rows, any columns).
        template <class Derived>
        Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime> solve(const Eigen::MatrixBase<Derived>& r) const {
            Eigen::Matrix<double, Eigen::Dynamic, Derived::ColsAtCompileTime> x = base_->lu.solve(r);
            if (w_.cols() > 0) correct(x);
            return x;
        }

        /// The same for an E whose rows other than the slipping 3D contacts' tangential ones are
        /// zero (a direction's turn): from the kept A0^-1 e_T, A0^-1 e_{T+1}, without a
        /// triangular solve (an E with other rows is solved as any).
        Eigen::MatrixXd solve_on_cones(const Eigen::MatrixXd& e) const;

    private:
        /// x = A0^-1 r becomes A^-1 r: x - W S^-1 (V^T x).
        void correct(Eigen::Ref<Eigen::MatrixXd> x) const;
        std::shared_ptr<const Base> base_;
        Eigen::MatrixXd w_;  ///< A0^-1 U (L x k); empty: theta = theta_0
        Eigen::PartialPivLU<Eigen::MatrixXd> capacitance_;  ///< I + V^T A0^-1 U
    };
    PatternSolve pattern_lu(const Eigen::VectorXd& zhat, const Modes& modes) const;
    /// The factorisation pattern_lu keeps (one pattern's).
    mutable std::shared_ptr<const PatternSolve::Base> pattern_base_;
    /// 1 on the rows of those equations whose right side is free_ * zhat (closed contacts' normal
    /// rows, stuck contacts' tangential rows), 0 on the others.
    Eigen::VectorXd kept_rows(const Modes& modes) const;
    /// The recorded vector's rows (lambda, relative, displacement) are the same in every
    /// pattern: one entry serves them all.
    ModeData build(const Modes& modes) const override;
    Modes cache_key(const Modes&) const override { return {}; }
    void restore_constraints(Eigen::VectorXd& zhat, const Modes& modes, double t) const override;

    /// The guards of the pattern over coefficients u (in any time unit) of the recorded vector.
    std::vector<Guard> guards(const Eigen::MatrixXd& u, const Modes& modes, int contact = -1) const;
    /// The size of a guard's quantity, against which its rounding is judged: the largest contact
    /// force (normal force), the largest relative displacement (gap, slip speed times a time
    /// unit), the friction limit's mu^2 force^2 (3D) or mu force (2D).
    double guard_size(const Guard& g, double force, double length) const;

    /// Whether contact c's guards in pattern `modes` are positive at zhat, or zero with a
    /// positive first term of their series beyond rounding. closing: c just closed (lambda = 0),
    /// its slip direction held.
    bool holds(const Eigen::VectorXd& zhat, const Modes& modes, int c, double t, bool closing);
    /// settle for the events of `triggers` (one per contact) at once, and the slip direction of
    /// each 3D contact that starts slipping into zhat; closing (per contact): it closed into
    /// slip (its direction held over the first step).
    Modes settle_state(Eigen::VectorXd& zhat, Modes modes, const std::vector<Guard>& triggers,
                       std::vector<char>& closing);
    /// The patterns of the contact problem a short time after zhat (lookahead: positions held
    /// now, q0 moved on by its rates), and each 3D slip's direction (its force's). False where
    /// the problem does not converge.
    bool lookahead(const Eigen::VectorXd& zhat, const Modes& modes, Modes& ahead, std::vector<double>& angles) const;
    /// The consistent slip direction of contact c closing into slip at zhat.
    double closing_direction(const Eigen::VectorXd& zhat, Modes modes, int c, double t);

    const System& system_;
    MasslessContacts s_;
    std::vector<int> slider_first_;
    std::vector<char> held_;  ///< hold_stuck's contacts
    int tangential_entries_ = 0;
    Eigen::MatrixXd free_;        ///< q0 as rows over zhat
    Eigen::MatrixXd free_nodes_;  ///< y_c without contact forces, rows over zhat
    Eigen::MatrixXd base_;        ///< M^-1 (forces on the masses without contact forces), rows over zhat
    Eigen::MatrixXd transmit_;    ///< M^-1 K_mc B
    /// free_ and base_ as sparse rows (most of their entries are zero: a node's rows see its own
    /// held position, the modes and the load), for the series' products order by order.
    Eigen::SparseMatrix<double, Eigen::RowMajor> free_sparse_, base_sparse_;
    /// The largest contact force the flows have met: the scale against which a slipping 3D
    /// contact's normal force is small enough to hold its direction (hold_share).
    double force_scale_ = 0.0;
    double size_scale_ = 0.0;  ///< the largest state_size met
    Stepping stepping_ = Stepping::automatic;
    bool start_flows_ = false;
    long taylor_steps_ = 0, collocation_steps_ = 0;
};

/// d(the unknowns' entries at a flow's end)/d(the unknowns at its start) from the flow's
/// derivative psi (its rows: the end pattern's independent entries). Where the end's pattern
/// is not the start's (far from the orbit), an unknown that is not independent at the end is a
/// function of the end state: the held position of a contact no longer stuck is its tangential
/// displacement (its derivative by the chain rule through the contact forces); the direction
/// of a contact no longer slipping is the one it kept when it stopped, taken as constant (its
/// row zero: Newton's matrix is then approximate until the patterns agree).
/// `unknowns`: entries of zhat (the section's), in Newton's order.
Eigen::MatrixXd end_derivative(ConeEngine& e, const PatternEngine::Flow& f, const std::vector<Eigen::Index>& unknowns);

}  // namespace hbf::detail::exact
