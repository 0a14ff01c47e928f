// hbfriction — contact elements: one law per file (src/contact/<law>.cpp), listed in one
// registry table (src/contact/contact_law.cpp).
//
// A law's file holds everything the solvers and the front ends need to know of it:
//   * its definition (the equation, the variables, the sign convention: model.hpp's Contact);
//   * its parameters beyond friction_limit (the Contact field, which is also the config key,
//     what it means and its allowed range);
//   * its periodic force by AFT with the exact Jacobian (contact_force.hpp: FrictionModel);
//   * its local linearisation (smooth laws: stability.hpp);
//   * what it is while it sticks (a rigid constraint, or a spring and a damper);
//   * whether it is smooth, whether its stick is exact (the event-exact solver covers it),
//     what internal state it carries in time, and its default H.
// Everything else asks the registry (contact_law(law)) instead of switching on the law, so that
// a law is added by adding its file and a line of the table.
//
// A contact sees one relative displacement q = w^T y (the laws along one direction), or several
// (the elements with a normal direction: their extra directions are parameters of
// Kind::direction, and System::contact_directions stacks them after the contact's own).
#pragma once

#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "hbf/contact_force.hpp"
#include "hbf/model.hpp"

namespace hbf {

struct AbsorberParameters;  // absorber.hpp: the paper's preset, which each law maps onto its own parameters

/// One parameter of a law besides friction_limit (which every law has, > 0). `key` is its name
/// in a system file's contact table (config.hpp), in Python's Contact and in the studies'
/// `contact.<key>`. The five first laws keep their values in Contact's fields (`field`); a law
/// added in its own file leaves `field` null and keeps them in Contact::values / Contact::lists
/// under `key`, so that adding it touches no other file.
struct LawParameter {
    /// positive: > 0; non_negative: >= 0; finite: any finite number (a coefficient of either
    /// sign); interval: between `low` and `high`, each end open or closed as given.
    enum class Range { positive, non_negative, finite, interval };
    /// number: one finite number; integer: one whole number; pairs: a table of rows of two
    /// numbers (stored row by row in Contact::lists), checked by the law's validate();
    /// direction: a vector over the model's coordinates (N entries in Contact::lists, finite,
    /// not all zero: System::validate), one more relative displacement the contact sees
    /// (System::contact_directions); optional unless the law's validate() requires it.
    /// rows: a table of numbers with rows of equal width (Contact::tables), its width and
    /// values checked by the law's validate(); direction_rows: a table of directions, one row of
    /// N entries each (Contact::tables, finite, no row all zero: System::validate), the further
    /// relative displacements the contact sees, after its own direction and the `direction`
    /// parameters.
    enum class Kind { number, integer, pairs, direction, rows, direction_rows };
    /// Whether the parameter is a single number (Kind number or integer): the studies' and
    /// maps' `contact.<key>`, the defaults' checks.
    bool scalar() const { return kind == Kind::number || kind == Kind::integer; }
    const char* key;
    double Contact::*field;
    const char* meaning;  ///< what it is, with its symbol ("contact stiffness sigma0")
    Range range;
    /// What 0 means where 0 is allowed and special ("F_s = F_c"); nullptr otherwise.
    const char* zero_means = nullptr;
    Kind kind = Kind::number;
    double low = 0, high = 0;                 ///< Range::interval
    bool low_open = false, high_open = false;  ///< Range::interval
    /// The value of a parameter kept in Contact::values when the contact has none.
    double default_value = 0;
    /// A force or stiffness that a meshed interface (interface.hpp) gives per unit area: each
    /// node's value is the interface's times the node's area.
    bool per_area = false;

    /// The contact's value (number and integer kinds).
    double get(const Contact& contact) const;
    void set(Contact& contact, double value) const;
    /// Whether `value` is in the range (finite; whole for Kind::integer).
    bool allows(double value) const;
    /// "finite and > 0", "finite and >= 0", "in (-1, 0]", "an integer in 1..1000".
    std::string allowed() const;
};

/// What a contact is while it sticks, as a linear element along its direction: rigid (exact
/// Coulomb: w^T y is held, the force is a constraint's multiplier), or a spring `stiffness` and a
/// damper `damping` (force per velocity), i.e. the complex stiffness stiffness + i Omega damping
/// at the frequency Omega. Used by the linear limits (stuck_linear_response, linear_resonances)
/// and by harmonic balance's first guesses.
struct StuckElement {
    bool rigid = false;
    double stiffness = 0;
    double damping = 0;
    /// The force at zero displacement (a preload: the elements with a normal direction), which
    /// harmonic balance's first guess carries on harmonic 0.
    double offset = 0;
    std::complex<double> at(double frequency) const { return {stiffness, frequency * damping}; }
};

/// A contact's force under a static load (static_state.hpp), along each of its directions
/// (System::contact_directions) at the static relative displacements q, for the contact loaded
/// monotonically from its unloaded state (sliders and internal states at 0, a preload acting
/// at q = 0): ContactLaw::static_force.
struct StaticForce {
    Eigen::VectorXd force;     ///< per direction
    Eigen::MatrixXd jacobian;  ///< d force / d q
    /// "open" (law elastic: N = 0), "stuck", "slipping" (at the friction limit), or
    /// "presliding" (Dahl, LuGre: below the limit, no exact stick).
    std::string state;
    /// Law elastic: where the tangential slider rests (u - T / k_t; u where open), one entry per
    /// tangential direction (time integration starts from it); empty for the other laws.
    Eigen::VectorXd slider;
};

/// The structure as a contact sees it along its direction w, for the laws' automatic parameters.
struct DirectionScale {
    double stiffness = 0;     ///< w^T K w (the contact's DOFs alone, the rest of the structure held)
    double mass = 0;          ///< w^T M w
    double largest_mass = 0;  ///< the largest diagonal entry of M
    /// The structure's static deflection under a unit load along w, u = K^-1 w, as a one-DOF
    /// model seen by the contact: static_stiffness = 1 / (w^T u) and static_mass = phi^T M phi
    /// for phi = u / (w^T u) (the Rayleigh mass of that shape). Both converge with mesh
    /// refinement, unlike w^T K w and w^T M w. 0 where K is singular along w.
    double static_stiffness = 0;
    double static_mass = 0;
};

/// The internal state a law carries in time (time integration, the event-exact solver and the
/// stability analysis; one per contact):
///   none:    memoryless (coulomb-reg), or set-valued without a state (coulomb: stick is a mode);
///   bristle: the bristle deflection z (dahl, lugre), which starts from z = q;
///   slider:  the slider position s of a spring in series with a Coulomb slider (jenkins).
enum class TimeState { none, bristle, slider };

/// The time integrator of a law: the general one (with the event-exact solver: time_domain()),
/// or a law's own: elastic_contacts (law elastic: CVODE with the contact modes as events),
/// unilateral_contacts (law unilateral: a complementarity solve per step on the massless
/// contact coordinates); time_integration.hpp.
enum class TimeIntegrator { general, elastic_contacts, unilateral_contacts };

/// What the time-domain solvers (time integration, the event-exact solver) integrate. A law
/// with exact stick is made of event-driven elements, each a contact whose law is one of the
/// two primitives below (time_elements); a smooth law is integrated as itself, by its
/// time_force and time_margin.
///   rigid slider:   exact Coulomb (stuck().rigid): stuck, q is held by a constraint's force;
///   elastic slider: Jenkins: a spring `stiffness` in series with a rigid slider (its position
///                   the element's state).
bool rigid_slider(const Contact& element);
bool elastic_slider(const Contact& element);

/// A smooth law bound to one contact's parameters (ContactLaw::bind), for the solvers that
/// evaluate it at every instant: time integration's right-hand side and roots, the variational
/// equation of the stability analysis. Its functions are ContactLaw::time_force, time_margin and
/// linearize at the bound contact.
class BoundLaw {
public:
    virtual ~BoundLaw() = default;
    virtual double force(double q, double v, double z, double& rate) const = 0;
    virtual double margin(double q, double v, double z) const = 0;
    virtual LocalLinearization linearize(double q, double v, double z) const = 0;
    /// The number of relative displacements the force depends on: 1, or m for an element over
    /// several coordinates without internal state (a polynomial of several coordinates), whose
    /// solvers call `forces` instead of force and linearize.
    virtual int directions() const { return 1; }
    /// An element over several coordinates: the forces f (m) along its directions at the
    /// relative displacements q and velocities v (m each), and where asked their slopes
    /// f_q(i, j) = d f_i / d q_j and f_v(i, j) = d f_i / d v_j. The default (one direction)
    /// forwards to force and linearize.
    virtual void forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& f,
                        Eigen::MatrixXd* f_q, Eigen::MatrixXd* f_v) const;
};

/// A contact law: a stateless descriptor, one per law (see the top of this file).
class ContactLaw {
public:
    virtual ~ContactLaw() = default;
    FrictionLaw id() const { return id_; }
    /// The name in files, flags and outputs ("coulomb", "coulomb-reg").
    const char* name() const { return name_; }
    /// The law in one line, for --help and messages ("f = F_c tanh(v / eps)").
    const char* definition() const { return definition_; }
    /// Its parameters besides friction_limit.
    virtual std::vector<LawParameter> parameters() const = 0;
    /// H of harmonic balance without the exact polish, measured (frf.hpp: default_harmonics).
    virtual int default_harmonics() const = 0;
    /// The force is a differentiable function of the state: local linearisation (linearize),
    /// stability by Hill's method and the monodromy of the variational equations.
    virtual bool smooth() const = 0;
    /// Stick is exact (a mode with events, not a pre-sliding approximation): the event-exact
    /// solver covers the law, time integration switches modes at events, and permanent stick has
    /// the centred stuck state as its solution.
    virtual bool exact_stick() const = 0;
    virtual TimeState time_state() const = 0;
    /// The linear element while the contact sticks (along its first direction).
    virtual StuckElement stuck(const Contact& contact) const = 0;
    /// The linear element along each of the contact's directions (System::contact_directions),
    /// uncoupled: the default is {stuck(contact)} for the laws along one direction.
    virtual std::vector<StuckElement> stuck_directions(const Contact& contact) const { return {stuck(contact)}; }
    /// The same about a static state in which the contact carries the normal force `normal`
    /// (static_state.hpp: a static load may press a contact that has no preload of its own):
    /// the laws with a normal direction stick with their springs (rigid) where normal > 0.
    /// The default, and any law where normal <= 0: stuck_directions(contact).
    virtual std::vector<StuckElement> stuck_directions_at(const Contact& contact, double normal) const {
        (void)normal;
        return stuck_directions(contact);
    }
    /// Whether the law has the parameter friction_limit (> 0, required). The elements with a
    /// normal direction have a friction coefficient instead (their limit follows the normal load).
    virtual bool has_friction_limit() const { return true; }
    /// Whether the paper's absorber (model.hpp: friction_absorber, hbf --law) can carry the law:
    /// not the elements with a normal direction (the absorber has none).
    virtual bool has_preset() const { return true; }
    /// Whether the event-exact solver, the general time integrator (time_integration.hpp: the
    /// laws' time-domain elements) and the stability analysis take the law; the default is true.
    /// For a law without them, each refuses the system up front, naming the law
    /// (refuse_time_domain). Law elastic: false (time integration has its own integrator for it).
    virtual bool time_domain() const { return true; }
    /// The integrator time integration uses for the law (TimeIntegrator above); the default is
    /// the general one, which needs time_domain().
    virtual TimeIntegrator time_integrator() const { return TimeIntegrator::general; }
    /// The periodic force by AFT (harmonic balance). Throws InvalidInput for parameters the
    /// model cannot take (exact Coulomb: lagrangian_penalty must be > 0).
    virtual std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const = 0;
    /// The static force (StaticForce above) at q, one entry per direction. False when the law
    /// has no single-valued static force (exact Coulomb: the stuck force is set-valued). The
    /// default covers the laws made of elastic sliders (jenkins, iwan: each slider's k (q - s)
    /// clamped at its slip force, stuck while every slider is), and is false otherwise.
    virtual bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const;
    /// The local linearisation at relative displacement q, velocity v and state z (smooth laws);
    /// the default throws InvalidInput.
    virtual LocalLinearization linearize(const Contact& contact, double q, double v, double z) const;
    /// Harmonic balance's first guess of the law's state signals (laws whose periodic_model has
    /// state_signals() > 0: z stacks them, 2H+1 coefficients each), on the load harmonic's rows
    /// cos_row, cos_row + 1 (and row 0) of each, given the relative displacements' coefficients
    /// q: sliding, the state of a force at its limit in phase with the velocity; stuck, the state
    /// of the stuck linear response, whose complex force amplitudes along the contact's
    /// directions are `stuck_forces` and whose mean forces (harmonic 0, where a static load or a
    /// preload is solved; else 0) are `mean_forces`. The default leaves z at zero.
    virtual void guess_state(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                             const Eigen::VectorXcd& stuck_forces, const Eigen::VectorXd& mean_forces,
                             Eigen::Ref<Eigen::VectorXd> z) const;
    /// Fills the parameters harmonic balance chooses when they are 0 (exact Coulomb's
    /// lagrangian_penalty), and refuses a chosen one outside the range measured to converge,
    /// naming it after `where` ("contact 1: "); `scales` are the structure along each of the
    /// contact's directions (System::contact_directions' order). The default does nothing.
    virtual void complete(Contact& contact, const std::vector<DirectionScale>& scales, const std::string& where) const;
    /// Whether the automatic Jacobian (JacobianForm::automatic) keeps the dense form up to
    /// HarmonicBalance::max_unknowns for the law's state signals (its trust-region corrector is
    /// the more forgiving on their nonsmooth residuals); false: structured from
    /// structured_threshold on, as for laws without states. The default is true.
    virtual bool states_prefer_dense() const { return true; }
    /// The paper's absorber preset (absorber.hpp: friction_absorber, PresetParameter): the symbols
    /// of the preset parameters the law reads ("wb", "xi", ...), in the order they are checked.
    virtual std::vector<std::string> preset_parameters() const { return {}; }
    /// Sets the law's parameters on the preset's contact from the nondimensional parameters
    /// (friction_limit = mu is set by the preset). The default sets none.
    virtual void from_preset(const AbsorberParameters&, Contact&) const {}
    /// Throws InvalidInput naming the parameter (prefixed by `where`, e.g. "contact 1: ") when a
    /// parameter is out of its range. The default checks parameters() (kinds number, integer).
    virtual void validate(const Contact& contact, const std::string& where) const;

    // ---- the time domain (time integration, the event-exact solver) ----
    /// The elements the time-domain solvers integrate for this contact (see rigid_slider): the
    /// contact itself (the default), or several contacts of the primitive laws along the same
    /// direction (a parallel Iwan joint: its sliders). Their internal states and modes are the
    /// entries of the time-domain state (time_integration.hpp: one per element), in this order.
    virtual std::vector<Contact> time_elements(const Contact& contact) const { return {contact}; }
    /// Smooth laws: the force at relative displacement q and velocity v with internal state z
    /// (time_state(): the bristle deflection; 0 without a state), and the state's rate z' in
    /// `rate` (0 without a state). The default throws: laws with exact stick are integrated by
    /// their elements' modes.
    virtual double time_force(const Contact& contact, double q, double v, double z, double& rate) const;
    /// Smooth laws: the stick margin of time integration (time_integration.hpp), < 0 while the
    /// contact (pre-)sticks; its sign changes are the stick/slip events (the elements without
    /// friction: where their force has a corner, e.g. a gap's closing). The default throws.
    virtual double time_margin(const Contact& contact, double q, double v, double z) const;

    /// The law bound to `contact` (a copy of it is kept). The default forwards to time_force,
    /// time_margin and linearize; a law whose parameters take work to read (the force elements'
    /// polynomial terms) reads them once here.
    virtual std::unique_ptr<BoundLaw> bind(const Contact& contact) const;

    // ---- elements without friction (springs, dampers) ----
    /// Whether the element is friction (stick and slip, a regime per period), or a force element
    /// without friction (polynomial stiffness, gap spring, damper): regime "none" in every
    /// result, no stick-slip transition, and its linear part present in every linear limit.
    virtual bool friction() const { return true; }
    /// A force element that acts only while closed (law gap): the share of the period it is
    /// open is reported as the separated fraction, and its force's mean and half range as the
    /// normal load's (ContactRegime). The linear limits take it closed while stuck, open while
    /// released.
    virtual bool unilateral() const { return false; }

protected:
    ContactLaw(FrictionLaw id, const char* name, const char* definition)
        : id_(id), name_(name), definition_(definition) {}

private:
    FrictionLaw id_;
    const char* name_;
    const char* definition_;
};

/// The regimes of the elements without friction (ContactLaw::friction) set to "none" (stick
/// fraction 0), and the point's regime and stick fraction taken from the first friction contact
/// ("none" and 0 without one): `contacts` one per contact of `system`, in order.
void mark_force_elements(const System& system, std::vector<ContactRegime>& contacts, std::string& regime,
                         double& stick_fraction);
/// Whether every contact of the system is a force element without friction (or there is none).
bool without_friction(const System& system);

/// Throws InvalidInput naming the first contact whose law the time-domain solvers do not
/// integrate (ContactLaw::time_domain), and `what` ("time integration").
void refuse_time_domain(const System& system, const std::string& what);

/// The registry: every law, in the order of their names in messages.
const std::vector<const ContactLaw*>& contact_laws();
/// The law's descriptor.
const ContactLaw& contact_law(FrictionLaw law);
/// The laws' names joined ("coulomb, dahl, lugre, coulomb-reg, jenkins" with ", ").
std::string contact_law_names(const std::string& separator = ", ");
/// The names of the laws whose parameters include `key`, joined by ", " (for messages).
std::string laws_with_parameter(const std::string& key);

/// The names of the laws that read the absorber preset's parameter `symbol` (absorber.hpp:
/// PresetParameter), joined by ", "; and whether `law` reads it.
std::string laws_reading(const std::string& symbol);
bool law_reads(FrictionLaw law, const std::string& symbol);

/// The system the time-domain solvers integrate: every contact replaced by its law's
/// time_elements, in order (the same system when no law splits a contact).
System time_domain_system(const System& system);
/// Whether some contact's law lowers it to other elements (several, or one of another law:
/// time_domain_system differs).
bool splits_contacts(const System& system);
/// The number of time-domain elements of the system (its contacts when none is split).
int time_domain_elements(const System& system);
/// Every contact's regime from its time-domain elements' (time_domain_system's order): a
/// contact split into several sliders (iwan) sticks while all of them do. Its sliders share
/// one displacement and each sticks from a reversal of it until its own spring force reaches
/// its limit (Masing), so their stick phases nest: the contact's stick fraction is the
/// smallest of theirs, its regime stick if all stick throughout, slip if one never sticks.
std::vector<ContactRegime> contact_regimes(const System& system, const std::vector<ContactRegime>& elements);

/// The system as the time-domain solvers see it, copied only when a law splits a contact:
///     const TimeDomainView view(system); const System& s = view.system();
/// Throws InvalidInput for a law outside them (refuse_time_domain) and for a static load (which
/// only harmonic balance and the time integration of laws elastic and unilateral carry).
class TimeDomainView {
public:
    explicit TimeDomainView(const System& system);
    const System& system() const { return split_ ? lowered_ : original_; }

private:
    const System& original_;
    bool split_;
    System lowered_;
};

/// LuGre's sliding limit g(v) = F_c + (F_s - F_c) exp(-(v / v_s)^2) (paper eq. 17) and its slope
/// dg/dv: F_c (slope 0) for Dahl, and for LuGre without a Stribeck curve (v_s = 0, F_s = 0 or
/// F_s = F_c). The one home of g, for the AFT, the linearisation and time integration.
double sliding_limit(const Contact& contact, double v, double* slope = nullptr);

}  // namespace hbf
