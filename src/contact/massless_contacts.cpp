// hbfriction — the split of a structure with rigid contacts on massless DOFs
// (massless_contacts.hpp).
#include "contact/massless_contacts.hpp"

#include <string>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf::detail {

MasslessRows massless_rows(const MasslessContacts& s, Eigen::Index n, Eigen::Index cos_index, Eigen::Index one_index) {
    const auto nm = static_cast<Eigen::Index>(s.massive.size());
    const auto nc = static_cast<Eigen::Index>(s.massless.size());
    MasslessRows r;
    r.free_nodes = Eigen::MatrixXd::Zero(nc, n);
    r.free_nodes.leftCols(nm) = -s.Kcc_inverse * s.Kcm;
    r.free_nodes.col(cos_index) = s.Kcc_inverse * s.Fc;
    r.free_nodes.col(one_index) = s.Kcc_inverse * s.Sc;
    r.free = s.W.transpose() * r.free_nodes;
    const Eigen::MatrixXd minv = s.Mmm.llt().solve(Eigen::MatrixXd::Identity(nm, nm));
    Eigen::MatrixXd forces = Eigen::MatrixXd::Zero(nm, n);
    forces.leftCols(nm) = -s.Kmm;
    forces.middleCols(nm, nm) = -s.Cmm;
    forces.col(cos_index) = s.Fm;
    forces.col(one_index) = s.Sm;
    forces -= s.Kmc * r.free_nodes;
    r.base = minv * forces;
    r.transmit = minv * (s.Kmc * s.B);
    return r;
}

Eigen::MatrixXd pick(const Eigen::MatrixXd& a, const std::vector<int>& rows, const std::vector<int>& cols) {
    Eigen::MatrixXd out(rows.size(), cols.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (std::size_t j = 0; j < cols.size(); ++j)
            out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a(rows[i], cols[j]);
    return out;
}

Eigen::VectorXd pick(const Eigen::VectorXd& v, const std::vector<int>& rows) {
    Eigen::VectorXd out(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) out(static_cast<Eigen::Index>(i)) = v.size() ? v(rows[i]) : 0.0;
    return out;
}

MasslessContacts split_massless_contacts(const System& system, const char* what) {
    using Eigen::MatrixXd;
    MasslessContacts s;
    const int n = system.dofs();
    const MatrixXd M(system.mass), K(system.stiffness);
    MatrixXd C = MatrixXd(system.damping);
    if (C.size() == 0) C = MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) (M.col(i).cwiseAbs().maxCoeff() > 0.0 ? s.massive : s.massless).push_back(i);
    std::vector<MatrixXd> directions;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Contact& k = system.contacts[c];
        const std::string where = "contact " + std::to_string(c + 1) + ": ";
        if (contact_law(k.law).time_integrator() != TimeIntegrator::unilateral_contacts)
            throw InvalidInput(where + "law = " + to_string(k.law) + " with contacts of law unilateral: " + what +
                               " takes law unilateral alone (allowed: every contact unilateral, or none)");
        const MatrixXd w = system.contact_directions(k);
        for (int i : s.massive)
            if (w.row(i).cwiseAbs().maxCoeff() > 0.0)
                throw InvalidInput(where + "a direction of the contact is on DOF " + std::to_string(i + 1) +
                                   ", which has mass: " + what +
                                   " of law unilateral needs the contact directions on massless DOFs (a row and "
                                   "column of M that are zero)");
        s.blocks.push_back(rigid_contact(k, s.lambdas));
        directions.push_back(w);
        s.lambdas += static_cast<int>(w.cols());
    }
    for (int i : s.massless)
        if (C.row(i).cwiseAbs().maxCoeff() > 0.0 || C.col(i).cwiseAbs().maxCoeff() > 0.0)
            throw InvalidInput("damping matrix: DOF " + std::to_string(i + 1) + " is massless and damped: " + what +
                               " of law unilateral needs the massless DOFs undamped (their positions then follow "
                               "the masses statically)");
    s.Mmm = pick(M, s.massive, s.massive);
    s.Cmm = pick(C, s.massive, s.massive);
    s.Kmm = pick(K, s.massive, s.massive);
    s.Kmc = pick(K, s.massive, s.massless);
    s.Kcm = pick(K, s.massless, s.massive);
    const MatrixXd Kcc = pick(K, s.massless, s.massless);
    s.Fm = pick(system.excitation, s.massive);
    s.Fc = pick(system.excitation, s.massless);
    s.Sm = pick(system.static_load, s.massive);
    s.Sc = pick(system.static_load, s.massless);
    const Eigen::LLT<MatrixXd> mass(s.Mmm);
    if (s.massive.empty() || mass.info() != Eigen::Success)
        throw InvalidInput(std::string("mass matrix: its part on the DOFs with mass is not positive definite (or "
                                       "there is none): ") +
                           what + " of law unilateral needs M_mm > 0");
    const Eigen::FullPivLU<MatrixXd> stiffness(Kcc);
    if (s.massless.empty() || !stiffness.isInvertible())
        throw InvalidInput(std::string("stiffness matrix: singular on the massless DOFs (K_cc): ") + what +
                           " of law unilateral solves the massless contact nodes statically, which needs K_cc "
                           "regular");
    s.Kcc_inverse = stiffness.inverse();
    s.W = MatrixXd::Zero(static_cast<Eigen::Index>(s.massless.size()), s.lambdas);
    for (std::size_t c = 0; c < s.blocks.size(); ++c)
        for (std::size_t i = 0; i < s.massless.size(); ++i)
            s.W.block(static_cast<Eigen::Index>(i), s.blocks[c].first, 1, directions[c].cols()) =
                directions[c].row(s.massless[i]);
    s.B = s.Kcc_inverse * s.W;
    s.G = s.W.transpose() * s.B;
    for (int a = 0; a < s.lambdas; ++a)
        if (!(s.G(a, a) > 0.0))
            throw InvalidInput("stiffness matrix: the massless nodes have no flexibility along contact direction " +
                               std::to_string(a + 1) + " (w^T K_cc^-1 w = " + format_number(s.G(a, a)) +
                               "): allowed a positive definite K_cc");
    return s;
}

}  // namespace hbf::detail
