// hbfriction — cyclic symmetry (cyclic.hpp): the sector's checks, the phase transform T, the
// merged sector and the wheel's nodal-diameter families.
#include "hbf/cyclic.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <set>
#include <string>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {
constexpr double two_pi = 6.283185307179586476925286766559;

std::string dof_name(int i) { return "DOF " + std::to_string(i + 1); }
}  // namespace

double CyclicSymmetry::phase() const { return sectors > 0 ? two_pi * engine_order / sectors : 0.0; }

void validate_cyclic(const System& system) {
    const CyclicSymmetry& c = system.cyclic;
    if (!c.active()) {
        if (!c.neighbours.empty() || c.engine_order != 0)
            throw InvalidInput("cyclic symmetry: neighbours or an engine order given without the number of sectors "
                               "(allowed: sectors >= 2)");
        return;
    }
    if (c.sectors < 2)
        throw InvalidInput("cyclic symmetry: sectors = " + std::to_string(c.sectors) + " is out of range: allowed >= 2");
    if (c.engine_order < 0 || c.engine_order >= c.sectors)
        throw InvalidInput("cyclic symmetry: engine_order = " + std::to_string(c.engine_order) +
                           " is out of range: allowed 0.." + std::to_string(c.sectors - 1));
    if (system.excitation_harmonic != 1)
        throw InvalidInput("cyclic symmetry: the excitation harmonic h = " + std::to_string(system.excitation_harmonic) +
                           " is not allowed with a sector model (allowed: h = 1)");
    const int n = system.dofs();
    std::set<int> dependent;
    for (const auto& [d, m] : c.neighbours) {
        if (d < 0 || d >= n || m < 0 || m >= n)
            throw InvalidInput("cyclic symmetry: the pair (" + std::to_string(d + 1) + ", " + std::to_string(m + 1) +
                               ") names a DOF outside the model: allowed 1.." + std::to_string(n));
        if (d == m)
            throw InvalidInput("cyclic symmetry: " + dof_name(d) +
                               " is paired with itself: a DOF of the next sector is another DOF of the model");
        if (!dependent.insert(d).second)
            throw InvalidInput("cyclic symmetry: " + dof_name(d) + " is listed twice as a DOF of the next sector");
    }
    if (dependent.size() == static_cast<std::size_t>(n))
        throw InvalidInput("cyclic symmetry: every DOF is a DOF of the next sector: the sector has none of its own");
    for (const auto& [d, m] : c.neighbours) {
        if (dependent.count(m) > 0)
            throw InvalidInput("cyclic symmetry: " + dof_name(m) + " is the next sector's image of " + dof_name(d) +
                               " and itself a DOF of the next sector: allowed a DOF of this sector");
        if (system.excitation(d) != 0.0)
            throw InvalidInput("cyclic symmetry: the excitation loads " + dof_name(d) +
                               ", a DOF of the next sector: put the load of a shared DOF on its own sector's DOF " +
                               std::to_string(m + 1));
        if (system.static_load.size() == n && system.static_load(d) != 0.0)
            throw InvalidInput("cyclic symmetry: the static load acts on " + dof_name(d) +
                               ", a DOF of the next sector: put it on its own sector's DOF " + std::to_string(m + 1));
    }
}

void refuse_cyclic(const System& system, const std::string& what) {
    if (system.cyclic.active())
        throw InvalidInput(what + ": not available for a sector model (cyclic symmetry, " +
                           std::to_string(system.cyclic.sectors) +
                           " sectors); a sector is solved by harmonic balance (hbf frf, the full formulation)");
}

std::vector<int> independent_dofs(const System& system) {
    std::vector<bool> dependent(static_cast<std::size_t>(system.dofs()), false);
    for (const auto& pair : system.cyclic.neighbours) dependent[static_cast<std::size_t>(pair.first)] = true;
    std::vector<int> out;
    for (int i = 0; i < system.dofs(); ++i)
        if (!dependent[static_cast<std::size_t>(i)]) out.push_back(i);
    return out;
}

Eigen::MatrixXcd cyclic_transform(const System& system, double angle) {
    const std::vector<int> independent = independent_dofs(system);
    std::vector<int> column(static_cast<std::size_t>(system.dofs()), -1);
    for (std::size_t j = 0; j < independent.size(); ++j) column[static_cast<std::size_t>(independent[j])] = static_cast<int>(j);
    Eigen::MatrixXcd t = Eigen::MatrixXcd::Zero(system.dofs(), static_cast<Eigen::Index>(independent.size()));
    for (std::size_t j = 0; j < independent.size(); ++j) t(independent[j], static_cast<Eigen::Index>(j)) = 1.0;
    const std::complex<double> turn = std::polar(1.0, -angle);
    for (const auto& [d, m] : system.cyclic.neighbours) t(d, column[static_cast<std::size_t>(m)]) = turn;
    return t;
}

SparseMatrix cyclic_merge(const System& system) {
    const std::vector<int> independent = independent_dofs(system);
    std::vector<int> column(static_cast<std::size_t>(system.dofs()), -1);
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t j = 0; j < independent.size(); ++j) {
        column[static_cast<std::size_t>(independent[j])] = static_cast<int>(j);
        entries.emplace_back(independent[j], static_cast<int>(j), 1.0);
    }
    for (const auto& [d, m] : system.cyclic.neighbours) entries.emplace_back(d, column[static_cast<std::size_t>(m)], 1.0);
    SparseMatrix t(system.dofs(), static_cast<Eigen::Index>(independent.size()));
    t.setFromTriplets(entries.begin(), entries.end());
    return t;
}

int nodal_diameter(const CyclicSymmetry& cyclic, int harmonic) {
    if (!cyclic.active()) return 0;
    const int p = static_cast<int>((static_cast<long long>(harmonic) * cyclic.engine_order) % cyclic.sectors);
    return std::min(p, cyclic.sectors - p);
}

std::string cyclic_label(const CyclicSymmetry& cyclic) {
    if (!cyclic.active()) return {};
    return ", engine order " + std::to_string(cyclic.engine_order) + " (nodal diameter " +
           std::to_string(nodal_diameter(cyclic, 1)) + ") of " + std::to_string(cyclic.sectors) + " sectors";
}

namespace {

void require_sector(const System& system, const std::string& what) {
    system.validate();
    if (!system.cyclic.active())
        throw InvalidInput(what + ": the model is not a sector (allowed: a model with cyclic symmetry)");
    const int m = static_cast<int>(independent_dofs(system).size());
    if (m > nodal_diameter_dof_limit)
        throw InvalidInput(what + ": the sector has " + std::to_string(m) + " DOFs of its own: allowed up to " +
                           std::to_string(nodal_diameter_dof_limit) +
                           " (dense eigenproblems, one per nodal diameter; reduce the sector first)");
}

// The sector's modes at one phase (sector_modes); `vectors` false: the frequencies alone (the
// shapes and damping ratios left empty). `where` names the phase in messages.
std::vector<SectorMode> solve_sector(const System& system, double angle, bool stuck, bool vectors,
                                     const std::string& where) {
    using Complex = std::complex<double>;
    const Eigen::MatrixXcd t = cyclic_transform(system, angle);
    const auto m = t.cols();
    Eigen::MatrixXcd k = t.adjoint() * Eigen::MatrixXd(system.stiffness).cast<Complex>() * t;
    const Eigen::MatrixXcd mass = t.adjoint() * Eigen::MatrixXd(system.mass).cast<Complex>() * t;
    Eigen::MatrixXcd damping;
    if (vectors)
        damping = system.damping.rows() == system.dofs() ? Eigen::MatrixXcd(t.adjoint() * Eigen::MatrixXd(system.damping).cast<Complex>() * t)
                                                         : Eigen::MatrixXcd::Zero(m, m);
    // The stuck elements along every contact direction: springs (and dampers) added, rigid ones
    // as constraints d^T u = 0 (d = T^T w: a direction across the cut turns with the phase).
    std::vector<Eigen::VectorXcd> rigid;
    if (stuck)
        for (const Contact& contact : system.contacts) {
            const Eigen::MatrixXd directions = system.contact_directions(contact);
            const std::vector<StuckElement> along = contact_law(contact.law).stuck_directions(contact);
            for (Eigen::Index j = 0; j < directions.cols() && j < static_cast<Eigen::Index>(along.size()); ++j) {
                const StuckElement& e = along[static_cast<std::size_t>(j)];
                const Eigen::VectorXcd dir = t.transpose() * directions.col(j).cast<Complex>();  // q = dir^T u
                if (e.rigid) {
                    rigid.push_back(dir);
                    continue;
                }
                k += e.stiffness * dir.conjugate() * dir.transpose();
                if (vectors) damping += e.damping * dir.conjugate() * dir.transpose();
            }
        }
    // Rigid constraints: the eigenproblem on the null space B of the constraints' rows.
    Eigen::MatrixXcd basis = Eigen::MatrixXcd::Identity(m, m);
    if (!rigid.empty()) {
        Eigen::MatrixXcd rows(static_cast<Eigen::Index>(rigid.size()), m);
        for (std::size_t r = 0; r < rigid.size(); ++r) rows.row(static_cast<Eigen::Index>(r)) = rigid[r].transpose();
        Eigen::FullPivLU<Eigen::MatrixXcd> lu(rows);
        if (lu.rank() == m) return {};  // every DOF held: no mode at this phase
        basis = lu.kernel();
    }
    const Eigen::MatrixXcd kr = basis.adjoint() * k * basis, mr = basis.adjoint() * mass * basis;
    Eigen::LLT<Eigen::MatrixXcd> llt((mr + mr.adjoint()) / 2.0);
    if (llt.info() != Eigen::Success)
        throw InvalidInput("the sector's mass matrix is not positive definite on its own DOFs at " + where +
                           " (massless DOFs: condense them first; allowed M > 0)");
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> solver(
        (kr + kr.adjoint()) / 2.0, (mr + mr.adjoint()) / 2.0, vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
    if (solver.info() != Eigen::Success) throw InvalidInput("the sector's eigensolver failed at " + where);
    std::vector<SectorMode> modes;
    const Eigen::VectorXd lambda = solver.eigenvalues();
    for (Eigen::Index j = 0; j < lambda.size(); ++j) {
        SectorMode mode;
        mode.index = static_cast<int>(j) + 1;
        mode.omega = std::sqrt(std::max(lambda(j), 0.0));
        if (vectors) {
            mode.own = basis * solver.eigenvectors().col(j);
            mode.own /= std::sqrt(std::real(mode.own.dot(mass * mode.own)));
            // Reproducible phase: the first entry of largest modulus real and positive.
            Eigen::Index largest = 0;
            const double top = mode.own.cwiseAbs().maxCoeff();
            while (std::abs(mode.own(largest)) < (1.0 - 1e-9) * top) ++largest;
            mode.own *= std::abs(mode.own(largest)) / mode.own(largest);
            mode.shape = t * mode.own;
            mode.zeta = mode.omega > 0.0 ? std::real(mode.own.dot(damping * mode.own)) / (2.0 * mode.omega) : 0.0;
        }
        modes.push_back(std::move(mode));
    }
    return modes;
}

}  // namespace

std::vector<SectorMode> sector_modes(const System& system, double angle, bool stuck) {
    require_sector(system, "the sector's modes");
    if (!std::isfinite(angle)) throw InvalidInput("the sector's modes: the phase is not finite");
    return solve_sector(system, angle, stuck, true, "the phase " + format_number(angle));
}

NodalDiameterFamily nodal_diameter_family(const System& system, bool stuck) {
    require_sector(system, "nodal-diameter family");
    const int sectors = system.cyclic.sectors, diameters = sectors / 2 + 1;
    const auto m = static_cast<Eigen::Index>(independent_dofs(system).size());
    NodalDiameterFamily family;
    family.sectors = sectors;
    family.stuck = stuck;
    family.frequencies = Eigen::MatrixXd::Constant(diameters, m, std::numeric_limits<double>::quiet_NaN());
    for (int d = 0; d < diameters; ++d) {
        const std::vector<SectorMode> modes =
            solve_sector(system, two_pi * d / sectors, stuck, false, "nodal diameter " + std::to_string(d));
        for (std::size_t j = 0; j < modes.size(); ++j) family.frequencies(d, static_cast<Eigen::Index>(j)) = modes[j].omega;
    }
    return family;
}

}  // namespace hbf
