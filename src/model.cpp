#include "hbf/model.hpp"

#include <algorithm>
#include <Eigen/Eigenvalues>
#include <limits>
#include <complex>

#include <cmath>
#include <string>
#include <utility>

#include "hbf/contact.hpp"
#include "hbf/error.hpp"
#include "hbf/static_state.hpp"

namespace hbf {

namespace {
/// Held rigid while it sticks (exact Coulomb): its stuck force is a constraint's multiplier.
bool rigid_in_stick(const Contact& contact) { return contact_law(contact.law).stuck(contact).rigid; }
}  // namespace

Eigen::VectorXd System::contact_direction(const Contact& contact) const {
    if (contact.direction.size() > 0) return contact.direction;
    Eigen::VectorXd w = Eigen::VectorXd::Zero(dofs());
    w(contact.dof) = 1.0;
    if (contact.other_dof != Contact::ground) w(contact.other_dof) = -1.0;
    return w;
}

Eigen::MatrixXd System::contact_directions(const Contact& contact) const {
    std::vector<const std::vector<double>*> extra;
    for (const LawParameter& p : contact_law(contact.law).parameters())
        if (p.kind == LawParameter::Kind::direction)
            if (const auto at = contact.lists.find(p.key); at != contact.lists.end()) extra.push_back(&at->second);
    Eigen::MatrixXd w(dofs(), static_cast<Eigen::Index>(extra.size()) + 1);
    w.col(0) = contact_direction(contact);
    for (std::size_t j = 0; j < extra.size(); ++j) {
        if (static_cast<int>(extra[j]->size()) != dofs())
            throw InvalidInput("contact_directions: a direction has " + std::to_string(extra[j]->size()) +
                               " entries: allowed " + std::to_string(dofs()) + " (the number of DOFs)");
        w.col(static_cast<Eigen::Index>(j) + 1) = Eigen::Map<const Eigen::VectorXd>(extra[j]->data(), dofs());
    }
    return w;
}

Output::Output(std::string name, std::vector<Term> terms) : name_(std::move(name)), terms_(std::move(terms)) {}

Output Output::dof(int i) { return Output("y" + std::to_string(i + 1), {{i, 1.0}}); }

int Output::single_dof() const { return terms_.size() == 1 && terms_.front().second == 1.0 ? terms_.front().first : -1; }

double Output::of(const Eigen::Ref<const Eigen::VectorXd>& y) const {
    double sum = 0.0;
    for (const auto& [i, c] : terms_) sum += c * y(i);
    return sum;
}

Eigen::VectorXd Output::combine(const Eigen::Ref<const Eigen::MatrixXd>& y) const {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(y.rows());
    for (const auto& [i, c] : terms_) sum += c * y.col(i);
    return sum;
}

void Output::validate(int dofs) const {
    bool nonzero = false;
    for (const auto& [i, c] : terms_) {
        if (i < 0 || i >= dofs)
            throw InvalidInput("output '" + name_ + "': DOF " + std::to_string(i + 1) + " is out of range: allowed 1.." +
                               std::to_string(dofs));
        if (!std::isfinite(c))
            throw InvalidInput("output '" + name_ + "': the coefficient of DOF " + std::to_string(i + 1) +
                               " is not finite");
        nonzero = nonzero || c != 0.0;
    }
    if (!nonzero) throw InvalidInput("output '" + name_ + "': every coefficient is zero (allowed: at least one nonzero)");
}

SparseMatrix sparse(const Eigen::MatrixXd& dense) { return dense.sparseView(0.0, 0.0); }

namespace {
/// Square N x N, finite, symmetric (compares stored entries only: never densified).
void require_square(const SparseMatrix& matrix, int n, const char* name) {
    if (matrix.rows() != n || matrix.cols() != n)
        throw InvalidInput(std::string(name) + " is " + std::to_string(matrix.rows()) + "x" +
                           std::to_string(matrix.cols()) + ": allowed " + std::to_string(n) +
                           "x" + std::to_string(n) + " (the number of DOFs)");
    double scale = 0.0;
    for (int j = 0; j < matrix.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(matrix, j); it; ++it) {
            if (!std::isfinite(it.value())) throw InvalidInput(std::string(name) + " has non-finite entries");
            // Its products (K y, w^T K w, the dynamic stiffness's squares in the solvers) must
            // neither overflow nor lose the other entries entirely: well inside 1e-154..1e154.
            if (std::abs(it.value()) > 1e100)
                throw InvalidInput(std::string(name) + " entry (" + std::to_string(it.row() + 1) + ", " +
                                   std::to_string(it.col() + 1) + ") = " + format_number(it.value()) +
                                   ": allowed |entry| <= 1e100 (its products must be representable: change the "
                                   "units, or hold a DOF by removing it rather than by a huge stiffness)");
            scale = std::max(scale, std::abs(it.value()));
        }
    const SparseMatrix asymmetry = matrix - SparseMatrix(matrix.transpose());
    for (int j = 0; j < asymmetry.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(asymmetry, j); it; ++it)
            if (std::abs(it.value()) > 1e-12 * scale) {
                const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
                throw InvalidInput(std::string(name) + " is not symmetric: entry (" + std::to_string(r + 1) + ", " +
                                   std::to_string(c + 1) + ") = " + format_number(matrix.coeff(r, c)) + " but (" +
                                   std::to_string(c + 1) + ", " + std::to_string(r + 1) + ") = " +
                                   format_number(matrix.coeff(c, r)) + " (1-based): allowed symmetric M, C and K");
            }
}

/// LDL^T of a symmetric matrix (AMD ordering): the pivots' signs tell definiteness.
Eigen::VectorXd ldlt_pivots(const SparseMatrix& matrix, bool& ok) {
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(matrix);
    ok = ldlt.info() == Eigen::Success;
    return ok ? Eigen::VectorXd(ldlt.vectorD()) : Eigen::VectorXd();
}

double largest_diagonal(const SparseMatrix& matrix) {
    return matrix.rows() > 0 ? matrix.diagonal().cwiseAbs().maxCoeff() : 0.0;
}
}  // namespace

bool System::has_positive_definite_mass() const {
    bool ok = false;
    const Eigen::VectorXd d = ldlt_pivots(mass, ok);
    return ok && d.size() > 0 && d.minCoeff() > 1e-13 * largest_diagonal(mass);
}

std::string contact_name(const std::vector<Contact>& contacts, std::size_t c) {
    const std::string name = "contact " + std::to_string(c + 1);
    return c < contacts.size() && !contacts[c].label.empty() ? name + " (" + contacts[c].label + ")" : name;
}

void System::validate() const {
    const int n = dofs();
    if (n < 1) throw InvalidInput("mass matrix is empty: a system needs at least 1 DOF");
    require_square(mass, n, "mass matrix");
    require_square(damping, n, "damping matrix");
    require_square(stiffness, n, "stiffness matrix");
    {
        // Positive semi-definite: M + delta I (delta a rounding-level shift of the largest
        // mass) has positive pivots; a negative pivot is a negative mass.
        const double m = largest_diagonal(mass);
        if (!(m > 0.0)) throw InvalidInput("mass matrix is zero: allowed a positive semi-definite M with at least one mass");
        SparseMatrix shifted(n, n);
        shifted.setIdentity();
        shifted = mass + 1e-12 * m * shifted;
        bool ok = false;
        const Eigen::VectorXd d = ldlt_pivots(shifted, ok);
        if (!ok || d.minCoeff() <= 0.0)
            throw InvalidInput("mass matrix is not positive semi-definite (a negative mass): allowed M >= 0, "
                               "with massless DOFs");
    }
    if (excitation.size() != n)
        throw InvalidInput("excitation vector has " + std::to_string(excitation.size()) +
                           " entries: allowed " + std::to_string(n) + " (the number of DOFs)");
    if (!excitation.allFinite()) throw InvalidInput("excitation vector has non-finite entries");
    if (static_load.size() != 0 && static_load.size() != n)
        throw InvalidInput("static load vector has " + std::to_string(static_load.size()) + " entries: allowed " +
                           std::to_string(n) + " (the number of DOFs), or none");
    if (!static_load.allFinite()) throw InvalidInput("static load vector has non-finite entries");
    if (excitation_harmonic < 1 || excitation_harmonic > max_excitation_harmonic)
        throw InvalidInput("excitation harmonic h = " + std::to_string(excitation_harmonic) +
                           " is out of range: allowed 1.." + std::to_string(max_excitation_harmonic) +
                           " (the force F cos(h w t))");
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& k = contacts[c];
        const std::string where = contact_name(contacts, c) + ": ";
        if (k.direction.size() > 0) {
            if (k.direction.size() != n)
                throw InvalidInput(where + "force_direction has " + std::to_string(k.direction.size()) +
                                   " entries: allowed " + std::to_string(n) + " (the number of DOFs)");
            if (!k.direction.allFinite() || !(k.direction.cwiseAbs().maxCoeff() > 0.0))
                throw InvalidInput(where + "force_direction must be finite and not all zero");
            // Its products (w^T K w, w^T M w, the automatic lagrangian_penalty) must neither
            // underflow nor overflow a double: bounded well inside 1e-154..1e154.
            const double largest = k.direction.cwiseAbs().maxCoeff();
            if (!(largest >= 1e-100 && largest <= 1e100))
                throw InvalidInput(where + "force_direction has largest entry " + format_number(largest) +
                                   ": allowed 1e-100..1e100 (its products with M and K must be representable; "
                                   "scale the direction, and divide friction_limit by the same factor)");
        } else {
            if (k.dof < 0 || k.dof >= n)
                throw InvalidInput(where + "dof = " + std::to_string(k.dof) + " is out of range: allowed 0.." +
                                   std::to_string(n - 1));
            if (k.other_dof != Contact::ground && (k.other_dof < 0 || k.other_dof >= n || k.other_dof == k.dof))
                throw InvalidInput(where + "other_dof = " + std::to_string(k.other_dof) +
                                   " is out of range: allowed ground (-1) or 0.." + std::to_string(n - 1) +
                                   " other than dof");
        }
        const ContactLaw& law = contact_law(k.law);
        if (law.has_friction_limit())
            require_positive(k.friction_limit, (where + "friction_limit").c_str(), "slip force mu N");
        else if (k.friction_limit != 0.0)
            throw InvalidInput(where + "friction_limit = " + format_number(k.friction_limit) + " does not apply to law " +
                               law.name() + " (its slip force is mu times the normal force): allowed 0 (not given)");
        for (const LawParameter& p : law.parameters()) {
            if (p.kind != LawParameter::Kind::direction) continue;
            const auto at = k.lists.find(p.key);
            if (at == k.lists.end()) continue;
            const Eigen::Map<const Eigen::VectorXd> d(at->second.data(), static_cast<Eigen::Index>(at->second.size()));
            if (d.size() != n)
                throw InvalidInput(where + p.key + " has " + std::to_string(d.size()) + " entries: allowed " +
                                   std::to_string(n) + " (the number of DOFs)");
            const double largest = d.size() > 0 ? d.cwiseAbs().maxCoeff() : 0.0;
            if (!d.allFinite() || !(largest >= 1e-100 && largest <= 1e100))
                throw InvalidInput(where + p.key + " (" + p.meaning + ") must be finite and not all zero: allowed "
                                   "entries up to 1e100 with the largest at least 1e-100");
        }
        if (k.base_motion != 0.0 && (!std::isfinite(k.base_motion) || !elastic_slider(k)))
            throw InvalidInput(where + "base_motion = " + format_number(k.base_motion) +
                               " is not allowed: allowed 0, or a finite value on an elastic slider (jenkins) of the "
                               "time domain");
        law.validate(k, where);
    }
    // Two exact Coulomb contacts along the same direction share one relative velocity: in stick
    // their two forces are indeterminate (only the sum is defined), and harmonic balance's
    // Jacobian is singular there. One contact with the summed friction_limit is the same law.
    for (std::size_t a = 0; a < contacts.size(); ++a)
        for (std::size_t b = a + 1; b < contacts.size(); ++b) {
            if (!rigid_in_stick(contacts[a]) || !rigid_in_stick(contacts[b])) continue;
            const Eigen::VectorXd u = contact_direction(contacts[a]), v = contact_direction(contacts[b]);
            if (std::abs(std::abs(u.dot(v)) - u.norm() * v.norm()) <= 1e-12 * u.norm() * v.norm()) {
                // v = alpha u: contact b's force f_b v = (alpha f_b) u, so along u the two slip at
                // |f_a + alpha f_b| <= F_a + |alpha| F_b.
                const double alpha = std::abs(u.dot(v)) / u.squaredNorm();
                throw InvalidInput("contact " + std::to_string(b + 1) + ": exact Coulomb along the same direction as "
                                   "contact " + std::to_string(a + 1) + " (the same DOF pair): in stick their two "
                                   "forces are indeterminate; allowed one exact Coulomb contact per direction "
                                   "(merge them: one contact along contact " + std::to_string(a + 1) +
                                   "'s direction with friction_limit = " + format_number(contacts[a].friction_limit) +
                                   (alpha == 1.0 ? " + " : " + " + format_number(alpha) + " * ") +
                                   format_number(contacts[b].friction_limit) + " = " +
                                   format_number(contacts[a].friction_limit + alpha * contacts[b].friction_limit) + ")");
            }
        }
    // More generally, exact Coulomb directions that are linearly dependent (1-ground, 2-ground
    // and 1-2: w3 = w1 - w2) leave the stuck forces indeterminate (only their resultant W f is
    // defined), and whether they stick depends on how that resultant is shared: refused, naming
    // the dependent contacts. Dependent: w_b within the pairwise check's angle (sqrt(2e-12))
    // of the span of the earlier exact Coulomb directions (Gram-Schmidt, twice; cost N m^2).
    {
        std::vector<std::size_t> earlier;
        Eigen::MatrixXd basis(n, 0);
        for (std::size_t b = 0; b < contacts.size(); ++b) {
            if (!rigid_in_stick(contacts[b])) continue;
            const Eigen::VectorXd w = contact_direction(contacts[b]);
            Eigen::VectorXd r = w;
            for (int pass = 0; pass < 2; ++pass) r -= basis * (basis.transpose() * r);
            if (r.norm() > std::sqrt(2e-12) * w.norm()) {
                basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
                basis.col(basis.cols() - 1) = r / r.norm();
                earlier.push_back(b);
                continue;
            }
            // w_b = sum_a alpha_a w_a over the earlier ones (least squares); name those it uses.
            Eigen::MatrixXd a(n, static_cast<Eigen::Index>(earlier.size()));
            for (std::size_t j = 0; j < earlier.size(); ++j)
                a.col(static_cast<Eigen::Index>(j)) = contact_direction(contacts[earlier[j]]);
            const Eigen::VectorXd alpha = a.colPivHouseholderQr().solve(w);
            const double largest = alpha.cwiseAbs().maxCoeff();
            std::string names, relation = "w" + std::to_string(b + 1) + " =";
            int named = 0;
            for (std::size_t j = 0; j < earlier.size(); ++j) {
                const double c = alpha(static_cast<Eigen::Index>(j));
                if (!(std::abs(c) > 1e-9 * largest)) continue;
                const std::string index = std::to_string(earlier[j] + 1);
                names += (named > 0 ? ", " : "") + index;
                const double rounded = std::abs(std::abs(c) - 1.0) <= 1e-12 ? 1.0 : std::abs(c);
                relation += std::string(named == 0 ? (c < 0.0 ? " -" : " ") : (c < 0.0 ? " - " : " + ")) +
                            (rounded == 1.0 ? "" : format_number(rounded) + " ") + "w" + index;
                ++named;
            }
            throw InvalidInput("contact " + std::to_string(b + 1) +
                               ": exact Coulomb along a direction that depends linearly on those of exact Coulomb "
                               "contacts " + names + " (" + relation + ", w_i the direction of contact i): the " +
                               std::to_string(named + 1) + " directions have rank " + std::to_string(named) +
                               ", so in stick their forces are indeterminate (only their resultant is defined); "
                               "allowed linearly independent exact Coulomb directions (remove one of these contacts, "
                               "or give it a compliant law such as jenkins)");
        }
    }
}

std::vector<std::string> System::warnings() const {
    std::vector<std::string> out;
    auto indefinite = [](const SparseMatrix& matrix) {
        const double scale = largest_diagonal(matrix);
        if (!(scale > 0.0)) return false;
        // Shifted by a rounding-level multiple of I, so that a singular semi-definite matrix
        // (free-free K, C acting on a few DOFs) has no zero pivot; a negative one stays.
        SparseMatrix shifted(matrix.rows(), matrix.cols());
        shifted.setIdentity();
        shifted = matrix + 1e-12 * scale * shifted;
        bool ok = false;
        const Eigen::VectorXd d = ldlt_pivots(shifted, ok);
        return ok && d.size() > 0 && d.minCoeff() < -1e-10 * scale;
    };
    if (indefinite(stiffness))
        out.push_back("the stiffness matrix K is indefinite (a negative pivot): the structure alone is statically "
                      "unstable; only its contacts can hold it");
    if (indefinite(damping))
        out.push_back("the damping matrix C is indefinite (negative damping): some motions gain energy from it");
    return out;
}

Eigen::VectorXcd linear_response(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                 const Eigen::MatrixXd& stiffness,
                                 const Eigen::VectorXd& excitation, double omega) {
    return dynamic_stiffness(mass, damping, stiffness, omega).fullPivLu().solve(excitation.cast<std::complex<double>>());
}

Eigen::MatrixXcd dynamic_stiffness(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& damping,
                                   const Eigen::MatrixXd& stiffness, double omega) {
    const std::complex<double> i(0.0, 1.0);
    return stiffness.cast<std::complex<double>>() - omega * omega * mass.cast<std::complex<double>>() +
           i * omega * damping.cast<std::complex<double>>();
}

const std::vector<PresetParameter>& preset_parameters() {
    using P = AbsorberParameters;
    static const std::vector<PresetParameter> table = {
        {"wb", "--wb", "wb", "contact_stiffness_ratio", &P::contact_stiffness_ratio,
         "contact stiffness ratio omega3/omega1",
         "contact stiffness ratio wb = sqrt(sigma0/m2)/omega1, > 0; jenkins: k_t = r wb^2", false, false, false},
        {"xi", "--xi", "xi", "contact_damping_ratio", &P::contact_damping_ratio, "contact damping ratio",
         "contact damping ratio xi = sigma1/(2 m2 sqrt(sigma0/m2)), >= 0", true, false, false},
        {"eps", "--eps", "eps", "regularization", &P::regularization, "regularisation velocity of tanh",
         "regularisation velocity of tanh, > 0", false, true, false},
        {"mu_s", "--mu-static", "mu_static", "static_friction_coefficient", &P::static_friction_coefficient,
         "static friction coefficient",
         "static friction coefficient mu_s of the Stribeck curve, >= 0; 0 means mu_s = mu", true, true, false},
        {"vs", "--stribeck-velocity", "stribeck_velocity", "stribeck_velocity", &P::stribeck_velocity,
         "Stribeck velocity",
         "Stribeck velocity v_s (nondimensional: x_s omega1), >= 0; 0 means no Stribeck curve", true, true, false},
        {"sigma2", "--viscous", "viscous", "viscous_coefficient", &P::viscous_coefficient,
         "viscous friction coefficient", "viscous friction coefficient sigma2 / (N / (x_s omega1)), >= 0", true, true, false},
        {"lagrangian_penalty", "--dlft-eps", "dlft_eps", "lagrangian_penalty", &P::lagrangian_penalty,
         "dynamic Lagrangian parameter",
         "dynamic Lagrangian parameter epsilon of exact Coulomb, force per velocity, allowed 1/30 to 4 times the "
         "automatic value (measured to converge; outside it the iteration stalls or follows spurious branches); "
         "within it the results converge to the same solution as H grows; 0 means automatic: sqrt(k m) of the "
         "contact direction, at most 30 times the structure's static impedance; 1.24 for the paper's absorber: "
         "allowed 0.0413..4.96",
         true, true, true},
    };
    return table;
}

void check_given_preset_parameters(FrictionLaw law, const AbsorberParameters& p,
                                   const std::vector<std::string>& keywords) {
    for (const std::string& keyword : keywords)
        for (const PresetParameter& q : preset_parameters()) {
            if (keyword != q.keyword) continue;
            if (!law_reads(law, q.symbol))
                throw InvalidInput(keyword + " does not apply to law " + to_string(law) + ": allowed with " +
                                   laws_reading(q.symbol) + " (" + q.meaning + ")");
            if (q.zero_only_by_default && !(p.*(q.field) > 0.0))
                throw InvalidInput(keyword + " (" + q.meaning + ") = " + format_number(p.*(q.field)) +
                                   " is out of range: allowed > 0 when given (0, the default, means automatic)");
        }
}

void AbsorberParameters::validate(FrictionLaw law) const {
    if (!contact_law(law).has_preset())
        throw InvalidInput("law = " + to_string(law) + " has no preset: the paper's absorber has no normal direction "
                           "(allowed: a system file, --config, with the contact's normal_direction)");
    require_positive(mass_ratio, "r", "mass ratio m2/m1");
    require_positive(tuning_ratio, "wa", "tuning ratio omega2/omega1");
    require_positive(friction_coefficient, "mu", "friction coefficient");
    require_positive(excitation, "fe", "excitation amplitude F0/N");
    // the law's own (contact.hpp), in the order it lists them
    for (const std::string& symbol : contact_law(law).preset_parameters())
        for (const PresetParameter& p : preset_parameters()) {
            if (symbol != p.symbol) continue;
            if (p.zero_allowed)
                require_non_negative(this->*(p.field), p.symbol, p.meaning);
            else
                require_positive(this->*(p.field), p.symbol, p.meaning);
        }
    // Nondimensional ratios, of order 0.01..10 in the paper: bounded to 1e-12..1e12, so that
    // products like r wa^2 stay finite and resolvable next to 1 (r = 1e300 overflowed into a
    // non-finite matrix, reported as such; the linear-limit tests use mu = 1e9).
    const std::pair<const char*, double> ratios[] = {
        {"r (mass ratio m2/m1)", mass_ratio},
        {"wa (tuning ratio omega2/omega1)", tuning_ratio},
        {"mu (friction coefficient)", friction_coefficient},
        {"fe (excitation amplitude F0/N)", excitation},
        {"wb (contact stiffness ratio omega3/omega1)", contact_stiffness_ratio},
        {"xi (contact damping ratio)", contact_damping_ratio},
        {"eps (regularisation velocity of tanh)", regularization},
        {"mu_s (static friction coefficient)", static_friction_coefficient},
        {"vs (Stribeck velocity)", stribeck_velocity},
        {"sigma2 (viscous friction coefficient)", viscous_coefficient}};
    for (const auto& [name, value] : ratios)
        if (value > 1e12 || (value > 0.0 && value < 1e-12))
            throw InvalidInput(std::string(name) + " = " + format_number(value) +
                               " is out of range: allowed 1e-12..1e12 (a nondimensional ratio; products of "
                               "two such must stay finite and resolvable next to 1)");
}

System friction_absorber(const AbsorberParameters& p, FrictionLaw law) {
    p.validate(law);
    const double r = p.mass_ratio;
    const double ka = r * p.tuning_ratio * p.tuning_ratio;  // r wa^2: absorber spring
    System system;
    Eigen::Matrix2d stiffness;
    stiffness << 1.0 + ka, -ka, -ka, ka;
    system.mass = sparse(Eigen::Vector2d(1.0, r).asDiagonal());
    system.damping = SparseMatrix(2, 2);
    system.stiffness = sparse(stiffness);
    system.excitation = Eigen::Vector2d(p.excitation, 0.0);
    Contact contact;
    contact.dof = 0;
    contact.other_dof = 1;
    contact.law = law;
    contact.friction_limit = p.friction_coefficient;
    contact_law(law).from_preset(p, contact);
    system.contacts.push_back(contact);
    return system;
}

void PhysicalAbsorber::validate() const {
    require_positive(m1, "m1", "main mass");
    require_positive(k1, "k1", "main stiffness");
    require_positive(m2, "m2", "absorber mass");
    require_positive(k2, "k2", "absorber stiffness");
    require_positive(normal_force, "N", "normal load");
    require_positive(force_amplitude, "F0", "excitation force amplitude");
    require_positive(friction_coefficient, "mu", "friction coefficient");
    require_non_negative(sigma0, "sigma0", "contact stiffness");
    require_non_negative(sigma1, "sigma1", "contact damping");
    if (sigma0 == 0.0 && sigma1 != 0.0)
        throw InvalidInput("sigma1 (contact damping) = " + format_number(sigma1) +
                           " needs a contact stiffness: allowed sigma1 = 0 when sigma0 = 0");
}

Scales scales_of(const PhysicalAbsorber& physical) {
    physical.validate();
    Scales s;
    s.frequency = std::sqrt(physical.k1 / physical.m1);
    s.time = 1.0 / s.frequency;
    s.displacement = physical.normal_force / physical.k1;
    s.force = physical.normal_force;
    return s;
}

AbsorberParameters to_nondimensional(const PhysicalAbsorber& physical) {
    const Scales s = scales_of(physical);  // validates
    AbsorberParameters p;
    p.mass_ratio = physical.m2 / physical.m1;
    p.tuning_ratio = std::sqrt(physical.k2 / physical.m2) / s.frequency;
    p.friction_coefficient = physical.friction_coefficient;
    p.excitation = physical.force_amplitude / physical.normal_force;
    const double omega3 = std::sqrt(physical.sigma0 / physical.m2);
    p.contact_stiffness_ratio = omega3 / s.frequency;
    p.contact_damping_ratio = omega3 > 0.0 ? physical.sigma1 / (2.0 * physical.m2 * omega3) : 0.0;
    return p;
}

PhysicalAbsorber to_physical(const AbsorberParameters& p, double m1, double k1, double normal_force) {
    require_positive(m1, "m1", "main mass");
    require_positive(k1, "k1", "main stiffness");
    require_positive(normal_force, "N", "normal load");
    p.validate(FrictionLaw::coulomb);
    require_non_negative(p.contact_stiffness_ratio, "wb", "contact stiffness ratio");
    require_non_negative(p.contact_damping_ratio, "xi", "contact damping ratio");
    const double omega1 = std::sqrt(k1 / m1);
    PhysicalAbsorber a;
    a.m1 = m1;
    a.k1 = k1;
    a.normal_force = normal_force;
    a.m2 = p.mass_ratio * m1;
    a.k2 = a.m2 * std::pow(p.tuning_ratio * omega1, 2);  // omega2^2 m2
    a.force_amplitude = p.excitation * normal_force;
    a.friction_coefficient = p.friction_coefficient;
    const double omega3 = p.contact_stiffness_ratio * omega1;
    a.sigma0 = a.m2 * omega3 * omega3;
    a.sigma1 = 2.0 * p.contact_damping_ratio * a.m2 * omega3;
    return a;
}

ContactRegime contact_regime(double stick_time, double period) {
    ContactRegime r;
    r.regime = stick_time >= period * (1.0 - 1e-12) ? "stick" : stick_time <= period * 1e-12 ? "slip" : "stick-slip";
    r.stick_fraction = r.regime == "stick" ? 1.0 : r.regime == "slip" ? 0.0 : std::clamp(stick_time / period, 0.0, 1.0);
    return r;
}

double energy_imbalance(double input, double viscous, double friction, double reach) {
    const double scale = std::max({reach, std::abs(input), std::abs(viscous) + std::abs(friction)});
    return scale > 0.0 ? std::abs(input - viscous - friction) / scale : 0.0;
}

StuckResponse stuck_linear_response(const System& system, double fundamental) {
    using Complex = std::complex<double>;
    const double omega = system.excitation_harmonic * fundamental;  // the force's frequency
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    Eigen::MatrixXcd a = dynamic_stiffness(Eigen::MatrixXd(system.mass), Eigen::MatrixXd(system.damping),
                                           Eigen::MatrixXd(system.stiffness), omega);
    std::vector<int> rigid;
    std::vector<Complex> element(static_cast<std::size_t>(nc), Complex(0.0, 0.0));
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        const std::vector<StuckElement>& along = elements[static_cast<std::size_t>(c)];
        const StuckElement stuck = along.front();
        if (stuck.rigid) {
            rigid.push_back(c);
            continue;
        }
        element[static_cast<std::size_t>(c)] = stuck.at(omega);
        // every direction's spring and damper (one for the laws along one direction)
        const Eigen::MatrixXd w = system.contact_directions(contact);
        for (Eigen::Index j = 0; j < w.cols(); ++j)
            a += along[static_cast<std::size_t>(j)].at(omega) * (w.col(j) * w.col(j).transpose()).cast<Complex>();
    }
    const int m = static_cast<int>(rigid.size());
    Eigen::MatrixXcd kkt = Eigen::MatrixXcd::Zero(n + m, n + m);
    kkt.topLeftCorner(n, n) = a;
    // The constraint rows and columns scaled to the size of A's entries (a finite-element K
    // has entries ~1e10 against w's ~1: unscaled, the LU judged the KKT matrix singular); the
    // multipliers are scaled back below.
    const double scale = std::max(a.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    for (int j = 0; j < m; ++j) {
        const Eigen::VectorXd w = system.contact_direction(system.contacts[static_cast<std::size_t>(rigid[static_cast<std::size_t>(j)])]);
        kkt.block(0, n + j, n, 1) = (scale * w).cast<Complex>();
        kkt.block(n + j, 0, 1, n) = (scale * w.transpose()).cast<Complex>();
    }
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n + m);
    rhs.head(n) = system.excitation.cast<Complex>();
    // An elastic slider whose spring's far end moves (Contact::base_motion p): its stuck force
    // k (w^T Y + p) loads the structure by -k p w.
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        if (contact.base_motion != 0.0)
            rhs.head(n) -= element[static_cast<std::size_t>(c)] * contact.base_motion *
                           system.contact_direction(contact).cast<Complex>();
    }
    StuckResponse out;
    Eigen::FullPivLU<Eigen::MatrixXcd> lu(kkt);
    if (!lu.isInvertible()) return out;
    const Eigen::VectorXcd x = lu.solve(rhs);
    if (!x.allFinite()) return out;
    out.ok = true;
    out.amplitude = x.head(n);
    out.force = Eigen::VectorXcd::Zero(nc);
    for (int j = 0; j < m; ++j) out.force(rigid[static_cast<std::size_t>(j)]) = scale * x(n + j);
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        if (elements[static_cast<std::size_t>(c)].front().rigid) continue;
        out.force(c) = element[static_cast<std::size_t>(c)] *
                       (system.contact_direction(contact).cast<Complex>().dot(out.amplitude) + contact.base_motion);
    }
    return out;
}

std::string to_string(LinearResonance::Limit limit) {
    switch (limit) {
        case LinearResonance::Limit::released: return "released";
        case LinearResonance::Limit::stuck: return "stuck";
        case LinearResonance::Limit::rigid: return "rigid";
    }
    return "?";
}

namespace {
/// The natural frequencies sqrt(lambda) of K phi = lambda M phi (finite, real, lambda > 0).
std::vector<double> natural_frequencies(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass) {
    std::vector<double> out;
    if (stiffness.rows() == 0) return out;
    Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> qz(stiffness, mass, false);
    if (qz.info() != Eigen::Success) return out;
    const double scale = std::max(stiffness.cwiseAbs().maxCoeff(), mass.cwiseAbs().maxCoeff());
    for (Eigen::Index j = 0; j < qz.alphas().size(); ++j) {
        const std::complex<double> alpha = qz.alphas()(j);
        const double beta = qz.betas()(j);
        // Infinite (a massless direction: beta at rounding) or complex (rounding of a symmetric
        // pencil; a real pair otherwise cannot occur for M >= 0): not a resonance.
        if (!(std::abs(beta) > 1e-13 * scale) || std::abs(alpha.imag()) > 1e-8 * std::abs(alpha)) continue;
        const double lambda = alpha.real() / beta;
        if (lambda > 0.0 && std::isfinite(lambda)) out.push_back(std::sqrt(lambda));
    }
    return out;
}
}  // namespace

std::vector<LinearResonance> linear_resonances(const System& system, double omega_low, double omega_high) {
    std::vector<LinearResonance> out;
    const int n = system.dofs();
    if (n == 0 || n > linear_resonance_dof_limit) return out;
    const Eigen::MatrixXd mass(system.mass), stiffness(system.stiffness);
    const double h = std::max(1, system.excitation_harmonic);
    auto add = [&](const std::vector<double>& natural, LinearResonance::Limit limit) {
        for (const double w : natural) {
            const double fundamental = w / h;
            if (fundamental >= omega_low && fundamental <= omega_high) out.push_back({fundamental, limit});
        }
    };
    add(natural_frequencies(stiffness, mass), LinearResonance::Limit::released);
    Eigen::MatrixXd stuck = stiffness;
    bool springs = false;
    Eigen::MatrixXd directions(n, 0);  // every direction of every contact
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Contact& contact = system.contacts[c];
        const Eigen::MatrixXd w = system.contact_directions(contact);
        directions.conservativeResize(Eigen::NoChange, directions.cols() + w.cols());
        directions.rightCols(w.cols()) = w;
        const std::vector<StuckElement>& along = elements[c];
        for (Eigen::Index j = 0; j < w.cols(); ++j) {
            const StuckElement& element = along[static_cast<std::size_t>(j)];
            if (!element.rigid && element.stiffness != 0.0) {  // a stuck spring (jenkins, dahl, lugre, elastic)
                stuck += element.stiffness * w.col(j) * w.col(j).transpose();
                springs = springs || element.stiffness > 0.0;
            }
        }
    }
    if (springs) add(natural_frequencies(stuck, mass), LinearResonance::Limit::stuck);
    if (directions.cols() > 0) {
        // y = B z with B an orthonormal basis of the null space of W^T: the rigid contacts' subspace.
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(directions);
        const Eigen::Index rank = qr.rank();
        if (rank < n) {
            const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
            const Eigen::MatrixXd basis = q.rightCols(n - rank);
            add(natural_frequencies(basis.transpose() * stiffness * basis, basis.transpose() * mass * basis),
                LinearResonance::Limit::rigid);
        }
    }
    std::sort(out.begin(), out.end(), [](const LinearResonance& a, const LinearResonance& b) { return a.omega < b.omega; });
    return out;
}

}  // namespace hbf
