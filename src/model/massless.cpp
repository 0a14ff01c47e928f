// Exact static condensation of massless DOFs (massless.hpp).
#include "model/massless.hpp"

#include <cmath>
#include <complex>
#include <string>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf::detail {

namespace {

/// The rows `rows` and columns `cols` of a sparse matrix (dense: the blocks are small or thin).
Eigen::MatrixXd block(const SparseMatrix& a, const std::vector<int>& rows, const std::vector<int>& cols,
                      const std::vector<int>& position, const std::vector<bool>& in_rows,
                      const std::vector<bool>& in_cols) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
    for (int j = 0; j < a.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
            const auto r = static_cast<std::size_t>(it.row()), c = static_cast<std::size_t>(it.col());
            if (in_rows[r] && in_cols[c]) out(position[r], position[c]) += it.value();
        }
    return out;
}

/// The rows and columns in `set` of a sparse matrix, kept sparse.
SparseMatrix sparse_block(const SparseMatrix& a, const std::vector<int>& set, const std::vector<int>& position,
                          const std::vector<bool>& in_set) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < a.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
            const auto r = static_cast<std::size_t>(it.row()), c = static_cast<std::size_t>(it.col());
            if (in_set[r] && in_set[c]) entries.emplace_back(position[r], position[c], it.value());
        }
    const auto n = static_cast<Eigen::Index>(set.size());
    SparseMatrix out(n, n);
    out.setFromTriplets(entries.begin(), entries.end());
    return out;
}

}  // namespace

MasslessCondensation::MasslessCondensation(const System& system) : system_(system) {
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    const Eigen::VectorXd diagonal = system.mass.diagonal();
    std::vector<bool> is_massless(static_cast<std::size_t>(n)), is_massive(static_cast<std::size_t>(n));
    position_.assign(static_cast<std::size_t>(n), -1);
    for (int i = 0; i < n; ++i) {
        const bool zero = diagonal(i) == 0.0;
        is_massless[static_cast<std::size_t>(i)] = zero;
        is_massive[static_cast<std::size_t>(i)] = !zero;
        auto& set = zero ? massless_ : massive_;
        position_[static_cast<std::size_t>(i)] = static_cast<int>(set.size());
        set.push_back(i);
    }
    const std::string why = "time integration of a singular mass matrix: ";
    if (massive_.empty()) throw InvalidInput(why + "every DOF is massless (allowed: at least one DOF with mass)");
    // C must vanish on massless DOFs (their equations are static).
    for (int j = 0; j < system.damping.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(system.damping, j); it; ++it)
            if (it.value() != 0.0 && (is_massless[static_cast<std::size_t>(it.row())] ||
                                      is_massless[static_cast<std::size_t>(it.col())]))
                throw InvalidInput(why + "massless DOF " + std::to_string((is_massless[static_cast<std::size_t>(it.row())] ? it.row() : it.col()) + 1) +
                                   " has damping (allowed: C zero in the rows and columns of massless DOFs, "
                                   "whose equations are then static)");
    reduced_.mass = sparse_block(system.mass, massive_, position_, is_massive);
    reduced_.damping = sparse_block(system.damping, massive_, position_, is_massive);
    {
        System check;
        check.mass = reduced_.mass;
        if (!check.has_positive_definite_mass())
            throw InvalidInput(why + "M is singular other than by massless DOFs (zero rows): allowed a positive "
                               "definite M once the zero rows are removed");
    }
    // K_SS, K_SR and the condensed stiffness.
    const Eigen::MatrixXd k_ss = block(system.stiffness, massless_, massless_, position_, is_massless, is_massless);
    const Eigen::MatrixXd k_sr = block(system.stiffness, massless_, massive_, position_, is_massless, is_massive);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(k_ss);
    if (!lu.isInvertible() || !(std::abs(lu.determinant()) > 0.0))
        throw InvalidInput(why + "the stiffness among the massless DOFs (K_SS) is singular: a massless DOF is not "
                           "held by springs (allowed: K_SS invertible)");
    x_ = lu.solve(k_sr);
    Eigen::MatrixXd correction = k_sr.transpose() * x_;  // K_RS K_SS^-1 K_SR
    reduced_.stiffness = sparse_block(system.stiffness, massive_, position_, is_massive);
    reduced_.stiffness -= correction.sparseView(0.0, 0.0);
    Eigen::VectorXd f_s(static_cast<Eigen::Index>(massless_.size())), f_r(static_cast<Eigen::Index>(massive_.size()));
    for (int i = 0; i < n; ++i)
        (is_massless[static_cast<std::size_t>(i)] ? f_s : f_r)(position_[static_cast<std::size_t>(i)]) = system.excitation(i);
    g_f_ = lu.solve(f_s);
    reduced_.excitation = f_r - k_sr.transpose() * g_f_;
    reduced_.excitation_harmonic = system.excitation_harmonic;
    // Contacts.
    g_w_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(massless_.size()), nc);
    converted_.assign(static_cast<std::size_t>(nc), false);
    std::vector<double> compliance(static_cast<std::size_t>(nc), 0.0);
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        const Eigen::VectorXd w = system.contact_direction(contact);
        Eigen::VectorXd w_s(static_cast<Eigen::Index>(massless_.size())), w_r(static_cast<Eigen::Index>(massive_.size()));
        for (int i = 0; i < n; ++i)
            (is_massless[static_cast<std::size_t>(i)] ? w_s : w_r)(position_[static_cast<std::size_t>(i)]) = w(i);
        Contact reduced = contact;
        const std::string name = "contact " + std::to_string(c + 1) + " (" + to_string(contact.law) + ")";
        if (w_s.cwiseAbs().maxCoeff() > 0.0) {
            if (!rigid_slider(contact) && !elastic_slider(contact))
                throw InvalidInput(why + name + " moves massless DOFs: allowed there coulomb and jenkins (a " +
                                   "spring in series with them is a Jenkins element); give the DOF a mass");
            g_w_.col(c) = lu.solve(w_s);
            const double g = w_s.dot(g_w_.col(c));
            if (!(g > 0.0))
                throw InvalidInput(why + name + ": the massless DOFs it moves have no compliance along it");
            compliance[static_cast<std::size_t>(c)] = g;
            for (int other = 0; other < c; ++other)
                if (converted_[static_cast<std::size_t>(other)] &&
                    std::abs(w_s.dot(g_w_.col(other))) > 1e-12 * std::sqrt(g * compliance[static_cast<std::size_t>(other)]))
                    throw InvalidInput(why + name + " and contact " + std::to_string(other + 1) +
                                       " are coupled through the massless DOFs: allowed at most one such contact "
                                       "per group of connected massless DOFs");
            reduced.law = FrictionLaw::jenkins;  // the elastic slider (contact_law.hpp)
            reduced.stiffness = rigid_slider(contact) ? 1.0 / g : 1.0 / (1.0 / contact.stiffness + g);
            reduced.lagrangian_penalty = 0.0;
            // The load on the massless DOFs moves the spring's far end: q gains w_S^T K_SS^-1 F_S cos.
            reduced.base_motion = w_s.dot(g_f_);
            w_r -= k_sr.transpose() * g_w_.col(c);
            if (!(w_r.cwiseAbs().maxCoeff() > 0.0))
                throw InvalidInput(why + name + " moves massless DOFs that no massive DOF feels: allowed a contact "
                                   "whose force reaches a DOF with mass");
            converted_[static_cast<std::size_t>(c)] = true;
        }
        reduced.direction = w_r;
        // An element's further coordinates (a polynomial of several): on massive DOFs only.
        for (const LawParameter& p : contact_law(contact.law).parameters()) {
            if (p.kind != LawParameter::Kind::direction_rows || reduced.tables.count(p.key) == 0) continue;
            const std::string key = p.key;
            Eigen::MatrixXd& table = reduced.tables[key];
            Eigen::MatrixXd rows(table.rows(), static_cast<Eigen::Index>(massive_.size()));
            for (Eigen::Index r = 0; r < table.rows(); ++r)
                for (int i = 0; i < n; ++i) {
                    if (!is_massless[static_cast<std::size_t>(i)]) {
                        rows(r, position_[static_cast<std::size_t>(i)]) = table(r, i);
                    } else if (table(r, i) != 0.0) {
                        throw InvalidInput(why + name + ": its " + key + " move massless DOFs: allowed there "
                                           "coulomb and jenkins; give the DOF a mass");
                    }
                }
            table = rows;
        }
        reduced_.contacts.push_back(reduced);
    }
    reduced_.validate();
}

Eigen::VectorXd MasslessCondensation::reduce_state(const Eigen::VectorXd& state) const {
    const int n = system_.dofs(), nr = static_cast<int>(massive_.size()), nc = static_cast<int>(converted_.size());
    Eigen::VectorXd out(2 * nr + 2 * nc);
    for (int k = 0; k < nr; ++k) {
        out(k) = state(massive_[static_cast<std::size_t>(k)]);
        out(nr + k) = state(n + massive_[static_cast<std::size_t>(k)]);
    }
    for (int c = 0; c < nc; ++c) {
        double internal = state(2 * n + c);
        // A Coulomb contact's slider is its own relative displacement q = w^T y.
        if (converted_[static_cast<std::size_t>(c)] && rigid_slider(system_.contacts[static_cast<std::size_t>(c)]))
            internal = system_.contact_direction(system_.contacts[static_cast<std::size_t>(c)]).dot(state.head(n));
        out(2 * nr + c) = internal;
        out(2 * nr + nc + c) = state(2 * n + nc + c);
    }
    return out;
}

MasslessCondensation::MasslessMap MasslessCondensation::massless_map() const {
    MasslessMap m;
    m.load = g_f_;
    m.from_massive = -x_;
    m.from_sliders = Eigen::MatrixXd::Zero(g_w_.rows(), g_w_.cols());
    for (int c = 0; c < static_cast<int>(converted_.size()); ++c) {
        if (!converted_[static_cast<std::size_t>(c)]) continue;
        const Contact& k = reduced_.contacts[static_cast<std::size_t>(c)];
        m.from_massive -= k.stiffness * g_w_.col(c) * k.direction.transpose();
        m.from_sliders.col(c) = k.stiffness * g_w_.col(c);
        m.load -= k.stiffness * k.base_motion * g_w_.col(c);  // f's share of the base motion
    }
    return m;
}

Eigen::VectorXd MasslessCondensation::massless_displacement(const Eigen::VectorXd& y_r, const Eigen::VectorXd& f,
                                                            double cosine) const {
    return g_f_ * cosine - x_ * y_r - g_w_ * f;
}

Eigen::VectorXcd MasslessCondensation::massless_harmonic(const Eigen::VectorXcd& y_r1, const Eigen::VectorXcd& f1) const {
    const auto ns = static_cast<Eigen::Index>(massless_.size());
    return (system_.excitation_harmonic == 1 ? g_f_ : Eigen::VectorXd::Zero(ns)).cast<std::complex<double>>() -
           x_.cast<std::complex<double>>() * y_r1 - g_w_.cast<std::complex<double>>() * f1;
}

}  // namespace hbf::detail
