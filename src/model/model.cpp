// hbfriction — the structural model (model.hpp): contact directions, outputs, the System's
// validation and warnings, the linear response, and the contact regime of a stick time.
#include "hbf/model.hpp"

#include <algorithm>
#include <Eigen/Eigenvalues>
#include <limits>
#include <complex>

#include <cmath>
#include <string>
#include <utility>

#include "hbf/contact_law.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"

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
    std::vector<const Eigen::MatrixXd*> rows;
    Eigen::Index more = 0;
    for (const LawParameter& p : contact_law(contact.law).parameters())
        if (p.kind == LawParameter::Kind::direction_rows)
            if (const auto at = contact.tables.find(p.key); at != contact.tables.end()) {
                rows.push_back(&at->second);
                more += at->second.rows();
            }
    Eigen::MatrixXd w(dofs(), static_cast<Eigen::Index>(extra.size()) + 1 + more);
    w.col(0) = contact_direction(contact);
    for (std::size_t j = 0; j < extra.size(); ++j) {
        if (static_cast<int>(extra[j]->size()) != dofs())
            throw InvalidInput("contact_directions: a direction has " + std::to_string(extra[j]->size()) +
                               " entries: allowed " + std::to_string(dofs()) + " (the number of DOFs)");
        w.col(static_cast<Eigen::Index>(j) + 1) = Eigen::Map<const Eigen::VectorXd>(extra[j]->data(), dofs());
    }
    Eigen::Index at = static_cast<Eigen::Index>(extra.size()) + 1;
    for (const Eigen::MatrixXd* table : rows) {
        if (table->cols() != dofs())
            throw InvalidInput("contact_directions: a row of directions has " + std::to_string(table->cols()) +
                               " entries: allowed " + std::to_string(dofs()) + " (the number of DOFs)");
        w.middleCols(at, table->rows()) = table->transpose();
        at += table->rows();
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
    validate_cyclic(*this);
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
        for (const LawParameter& p : law.parameters()) {
            if (p.kind != LawParameter::Kind::direction_rows) continue;
            const auto at = k.tables.find(p.key);
            if (at == k.tables.end()) continue;
            const Eigen::MatrixXd& d = at->second;
            if (d.cols() != n)
                throw InvalidInput(where + p.key + " has rows of " + std::to_string(d.cols()) + " entries: allowed " +
                                   std::to_string(n) + " (the number of DOFs)");
            for (Eigen::Index r = 0; r < d.rows(); ++r) {
                const double largest = d.row(r).cwiseAbs().maxCoeff();
                if (!d.row(r).allFinite() || !(largest >= 1e-100 && largest <= 1e100))
                    throw InvalidInput(where + p.key + "[" + std::to_string(r + 1) + "] (" + p.meaning +
                                       ") must be finite and not all zero: allowed entries up to 1e100 with the "
                                       "largest at least 1e-100");
            }
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

}  // namespace hbf
