// hbfriction — the structural model: linear structure plus friction contacts.
//
// Equations of motion (N degrees of freedom, time t, fundamental frequency omega):
//
//     M y'' + C y' + K y + sum_c w_c f_c(t) = F cos(h omega t),
//
// h >= 1 the excitation harmonic (System::excitation_harmonic, 1 by default): the steady state
// is sought with period 2 pi / omega, so h > 1 drives it at its h-th harmonic (subharmonic
// responses of order 1/h: a force at h omega answered at omega). The columns' w is omega.
//
// where contact c sees the relative displacement q_c = w_c^T y, with
// w_c = e_a - e_b (two DOFs a, b), w_c = e_a (DOF a against the ground), or any direction
// vector (a contact's force direction, e.g. a tangential direction at an FE node), and
// produces the friction force f_c(t) from its law. The force -w_c f_c acts on the structure:
// for a DOF pair, -f_c on DOF a (it opposes the relative motion q_c) and +f_c on DOF b.
//
// M, C and K are sparse (finite-element models with thousands of DOFs are never densified
// by the model). M may be singular: massless DOFs (the static boundary of a reduced model)
// are allowed where the problem stays well posed; harmonic balance checks that the dynamic
// stiffness of every balanced harmonic is invertible, and time integration needs M > 0.
//
// The model holds data only; the friction layer turns a Contact into a force evaluator.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <complex>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hbf {

/// Friction laws a contact can carry; each is described, and evaluated, in its own file
/// src/contact/`<law>.cpp`, listed in the registry of contact_law.hpp. Definitions (f = friction force, q = relative
/// displacement, v = q', F_c = friction_limit, sigma0/sigma1 = contact stiffness/damping):
///   coulomb: f = F_c sign(v) in slip, |f| <= F_c in stick (set-valued)     (paper eq. 3)
///   dahl:    f = sigma0 z,              z' = v - sigma0 |v| z / F_c         (paper eq. 16)
///   lugre:   f = sigma0 z + sigma1 z' + sigma2 v,  z' = v - sigma0 |v| z / g(v),
///            g(v) = F_c + (F_s - F_c) exp(-(v / v_s)^2)   (paper eq. 17: v_s = 0, F_s = F_c,
///            sigma2 = 0, so g = F_c)
///   coulomb-reg: f = F_c tanh(v / eps), a smooth (regularised) Coulomb law
///   jenkins: f = k_t (q - s), a tangential spring k_t (= stiffness) in series with a Coulomb
///            slider at s: s' = 0 while |k_t (q - s)| < F_c (stick), else the slider moves
///            with q and f = F_c sign(q') (slip); the elastic-contact variant of Coulomb
///   iwan, elastic, unilateral: the parallel Iwan joint, and the contacts with a normal
///            direction (elastic penalty, rigid by the dynamic Lagrangian); defined in their files
///   polynomial, gap, damper: force elements without friction (a polynomial spring, a
///            unilateral spring with a gap, a power-law damper); defined in their files
///   (a law added in its own file takes the next id here and names it)
enum class FrictionLaw : int {
    coulomb, dahl, lugre, coulomb_regularized, jenkins, iwan, elastic, unilateral, polynomial, gap, damper
};

/// "coulomb", "dahl", "lugre", "coulomb-reg", "jenkins", "iwan", "elastic", "unilateral" (the
/// registry's names: contact_law.hpp).
std::string to_string(FrictionLaw law);
/// Inverse of to_string; throws InvalidInput naming the allowed values.
FrictionLaw parse_friction_law(const std::string& name);

/// One friction contact. Units are those of the System (nondimensional for the presets).
struct Contact {
    static constexpr int ground = -1;
    int dof = 0;                ///< DOF a (0-based)
    int other_dof = ground;     ///< DOF b (0-based), or Contact::ground
    /// w_c, the force direction (N entries, finite, not all zero); when given it replaces
    /// dof / other_dof (which are then ignored): q_c = w_c^T y.
    Eigen::VectorXd direction;
    FrictionLaw law = FrictionLaw::coulomb;
    double friction_limit = 0;  ///< F_c = mu N, the sliding friction force (> 0)
    double stiffness = 0;       ///< sigma0, contact (bristle) stiffness (Dahl, LuGre; > 0);
                                ///< k_t, tangential stiffness (Jenkins; > 0)
    double damping = 0;         ///< sigma1, contact (bristle) damping (LuGre; >= 0)
    double viscous = 0;         ///< sigma2, viscous friction (LuGre; >= 0)
    double static_limit = 0;    ///< F_s, static friction force (LuGre; 0 means F_s = F_c)
    double stribeck_velocity = 0;  ///< v_s (LuGre; 0 means no Stribeck curve: g = F_c)
    double regularization = 0;  ///< eps, velocity scale of tanh (coulomb-reg; > 0)
    /// epsilon of the dynamic Lagrangian (exact coulomb in harmonic balance; >= 0, force per
    /// velocity; 0 chooses sqrt((w^T K w)(w^T M w)), the contact direction's impedance).
    double lagrangian_penalty = 0;
    /// The parameters of the laws added in their own files, which have no field above, by key
    /// (contact_law.hpp: LawParameter reads and writes them, and knows their defaults): numbers in
    /// `values`, lists of numbers (a table of pairs, row by row) in `lists`.
    std::map<std::string, double> values;
    std::map<std::string, std::vector<double>> lists;
    /// Tables of rows of equal width (LawParameter::Kind::rows and direction_rows: a polynomial's
    /// exponents and coefficients, its further coordinates), by key.
    std::map<std::string, Eigen::MatrixXd> tables;
    /// Time-domain elements only (contact_law.hpp: an elastic slider): the far end of the slider's
    /// spring moves by base_motion cos(h omega t) along w, so that its elongation is
    /// w^T y + base_motion cos(h omega t) - s. The static condensation of massless DOFs sets it
    /// (a load on the massless DOFs a contact moves reaches the slider so); 0 for every contact
    /// a user gives: System::validate allows it on jenkins contacts only, and harmonic balance
    /// refuses it.
    double base_motion = 0;
    /// Where the contact comes from, for messages ("interface[1] node 3"); empty for one given
    /// by itself. Messages name a contact "contact c" (1-based, in System::contacts) and this.
    std::string label;
};

/// The cyclic symmetry of a sector model (cyclic.hpp: the model is sector 0 of a wheel of N
/// identical sectors under an engine-order excitation). `sectors` = 0: the model is not a sector.
struct CyclicSymmetry {
    int sectors = 0;       ///< N >= 2 (0: the model is not a sector)
    int engine_order = 0;  ///< EO, 0..N-1 (a system file's larger EO is taken as EO mod N)
    /// (dependent, master), 0-based DOFs of the model: `dependent` is DOF `master` of the next
    /// sector. A master is never itself dependent; each dependent DOF appears once.
    std::vector<std::pair<int, int>> neighbours;

    bool active() const { return sectors > 0; }
    /// phi = 2 pi EO / N, the phase lag from one sector to the next at the fundamental.
    double phase() const;
};

/// "contact 3" or "contact 3 (interface[1] node 3)": how messages name contacts[c] (0-based c).
std::string contact_name(const std::vector<Contact>& contacts, std::size_t c);

using SparseMatrix = Eigen::SparseMatrix<double>;

/// The largest H the front ends (hbf, system files, Python) accept. The branch's cost grows
/// like H^4 for exact Coulomb: its points like N_t (each time sample that switches between
/// stick and slip turns the branch of the discretised problem) and each correction like the
/// cube of the 2H + 1 unknowns per signal. Measured on the paper's absorber (exact Coulomb,
/// --exact off): H = 50 4.5 s (700 points), 100 34 s (1667), 200 524 s (4101 points).
constexpr int max_harmonics = 100;

/// A linear structure with friction contacts under harmonic excitation F cos(h omega t).
struct System {
    /// Largest excitation harmonic h that validate() accepts (harmonic balance needs H >= h, and
    /// the front ends allow H <= max_harmonics).
    static constexpr int max_excitation_harmonic = max_harmonics;
    SparseMatrix mass;           ///< M, symmetric positive semi-definite (massless DOFs allowed)
    SparseMatrix damping;        ///< C, symmetric (may be empty: zero)
    SparseMatrix stiffness;      ///< K, symmetric
    Eigen::VectorXd excitation;  ///< F, amplitude of the force F cos(h omega t)
    /// h, 1..max_excitation_harmonic: the force acts at h omega, omega being the fundamental
    /// frequency of the periodic response sought (harmonic balance needs H >= h).
    int excitation_harmonic = 1;
    /// F_s, a constant load (bolt preload, centrifugal or pressure loads): empty or N finite
    /// entries, M y'' + C y' + K y + sum_c w_c f_c = F_s + F cos(h omega t). Harmonic balance
    /// carries it on harmonic 0 (so not with odd harmonics only); the contacts' static state
    /// under it alone is static_state.hpp's.
    Eigen::VectorXd static_load;
    std::vector<Contact> contacts;
    /// One sector of a cyclically symmetric wheel (cyclic.hpp), or none (sectors = 0).
    CyclicSymmetry cyclic;

    int dofs() const { return static_cast<int>(mass.rows()); }
    /// Whether static_load is given with a non-zero entry.
    bool has_static_load() const { return static_load.size() > 0 && static_load.cwiseAbs().maxCoeff() > 0.0; }
    /// w_c: the relative displacement of contact c is q_c = w_c^T y.
    Eigen::VectorXd contact_direction(const Contact& contact) const;
    /// Every direction of contact c, N x s: w_c first, then the law's direction parameters the
    /// contact has (contact_law.hpp: LawParameter::Kind::direction), in the law's order (the
    /// elements with a normal direction: the second tangential one if given, then the normal).
    Eigen::MatrixXd contact_directions(const Contact& contact) const;
    /// Throws InvalidInput when dimensions, symmetry or contact parameters are wrong. M must be
    /// positive semi-definite (checked by a sparse LDL^T); see has_positive_definite_mass.
    void validate() const;
    /// What validate() accepts but physics rarely wants: an indefinite K (statically unstable
    /// without its contacts) or C (negative damping). One sentence each; empty if none.
    std::vector<std::string> warnings() const;
    /// True when M is positive definite (no massless DOF): required by time integration and the
    /// event-exact solver, which integrate M y'' = ...
    bool has_positive_definite_mass() const;
};

/// A reported response o(t) = c^T y(t): one DOF (c = e_i, named "y<i+1>") or any linear
/// combination of DOFs (a tip displacement T q of a reduced model, a relative displacement, a
/// strain), named by the user. Columns and peaks are written for o as for a DOF: `<name>`_max =
/// max over one period of |o(t)|, `<name>`_amp1 = its first-harmonic amplitude.
class Output {
public:
    using Term = std::pair<int, double>;  ///< (0-based DOF, coefficient)
    Output(std::string name, std::vector<Term> terms);
    /// DOF i (0-based), named "y<i+1>".
    static Output dof(int i);
    const std::string& name() const { return name_; }
    const std::vector<Term>& terms() const { return terms_; }
    /// i when this output is exactly DOF i (one term, coefficient 1), else -1.
    int single_dof() const;
    /// c^T y for one vector y (N entries).
    double of(const Eigen::Ref<const Eigen::VectorXd>& y) const;
    /// The rows of a matrix whose columns are DOFs combined: Y c (Y: rows x N).
    Eigen::VectorXd combine(const Eigen::Ref<const Eigen::MatrixXd>& y) const;
    /// Throws InvalidInput when a DOF is outside 0..dofs-1, a coefficient is not finite, or
    /// every coefficient is zero.
    void validate(int dofs) const;

private:
    std::string name_;
    std::vector<Term> terms_;
};

/// A dense matrix as the model's sparse type (exact zeros are not stored).
SparseMatrix sparse(const Eigen::MatrixXd& dense);

/// The dynamic stiffness K - omega^2 M + i omega C.
Eigen::MatrixXcd dynamic_stiffness(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                   const Eigen::MatrixXd& stiffness, double omega);

/// Complex amplitude Y of the steady state y(t) = Re(Y e^{i omega t}) of the linear system
/// M y'' + C y' + K y = F cos(omega t), i.e. the solution of (K - omega^2 M + i omega C) Y = F.
Eigen::VectorXcd linear_response(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                 const Eigen::MatrixXd& stiffness,
                                 const Eigen::VectorXd& excitation, double omega);


/// Relative energy imbalance of a periodic response, shared by harmonic balance (PointMetrics)
/// and time integration (its physics check, hbf timeint): |input - viscous - friction| /
/// max(reach, |input|, |viscous| + |friction|), all per period; `reach` is the work the force
/// could do on the response's excited harmonic (0 when unknown). 0 when every term vanishes
/// (nothing moves).
double energy_imbalance(double input, double viscous, double friction, double reach);

/// One contact over a period: the share of the period it sticks and its regime, "stick"
/// (stuck throughout), "slip" (never stuck) or "stick-slip". Each solver says how it decides
/// (harmonic balance: the law's stick samples, continuation.hpp stick_pattern; the exact
/// solver and time integration: the event times). Reported for every contact, in order
/// (PointMetrics, ExactOrbit, PeriodicResponse::contacts).
struct ContactRegime {
    double stick_fraction = 0;
    std::string regime;
    /// Contacts with a normal direction (contact_law.hpp: laws elastic, unilateral): the share
    /// of the period separated (N = 0; stick_fraction + separated_fraction <= 1, the rest
    /// slips), the normal force's mean over the period and half its range (max - min) / 2, on
    /// the AFT samples (time integration: its events or steps). NaN for the other laws.
    double separated_fraction = std::numeric_limits<double>::quiet_NaN();
    double normal_mean = std::numeric_limits<double>::quiet_NaN();
    double normal_amplitude = std::numeric_limits<double>::quiet_NaN();
    /// The friction energy the contact dissipates per cycle (harmonic balance, and law
    /// unilateral's time integration; NaN elsewhere): along its tangential directions only, the
    /// normal force doing no work over a period (post_processing.cpp).
    double energy = std::numeric_limits<double>::quiet_NaN();
};
/// The regime of a contact stuck for `stick_time` of `period`: stick within 1e-12 of the
/// period, slip within 1e-12 of 0, else stick-slip (event-exact times); the fraction is then
/// exactly 1, 0, or stick_time / period.
ContactRegime contact_regime(double stick_time, double period);


}  // namespace hbf
