// hbfriction — the event-exact solver's modal form of a finite-element model (modal_exact.hpp).
#include "hbf/modal_exact.hpp"
#include "hbf/rigid_exact.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/receptance.hpp"

namespace hbf {

ModalExactModel::ModalExactModel(const System& system, int modes) {
    system.validate();
    const int most = largest_exact_modes(system);
    if (modes < 1 || modes > most)
        throw InvalidInput("exact solver modes = " + std::to_string(modes) + " is out of range: allowed 1.." +
                           std::to_string(most) + " (the modal form adds one Ritz vector per contact and one for the "
                           "load: at most " + std::to_string(exact_solver_max_dofs) + " DOFs)");
    if (system.excitation_harmonic != 1)
        throw InvalidInput("excitation harmonic h = " + std::to_string(system.excitation_harmonic) +
                           ": the exact solver generates the force cos(w t) at the fundamental only (allowed h = 1)");
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    dofs_ = n;
    directions_.resize(n, nc);
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        if (contact.base_motion != 0.0)
            throw InvalidInput("contact " + std::to_string(c + 1) +
                               ": base_motion is the static condensation's (allowed 0 in the modal form)");
        directions_.col(c) = system.contact_direction(contact);
    }
    Receptance receptance(system.mass, system.damping, system.stiffness, directions_, system.excitation,
                          Eigen::MatrixXd(0, n));
    try {
        receptance.use_modes(modes, Eigen::VectorXd::Zero(nc), Eigen::VectorXd::Zero(nc));
    } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("the exact solver's modal form: ") + e.what());
    }
    const Receptance::ModalBasis basis = receptance.modal_basis();
    const int m = static_cast<int>(basis.lambda.size());
    lambda_ = basis.lambda;
    phi_ = basis.phi;
    to_modal_ = phi_.transpose() * system.mass;
    p_ = phi_.transpose() * directions_;
    const Eigen::MatrixXd r_c = directions_.transpose() * basis.residual_w;
    // The contacts with an attachment mode: a residual compliance above rounding.
    std::vector<int> kept;
    r_index_.assign(static_cast<std::size_t>(nc), -1);
    for (int c = 0; c < nc; ++c) {
        const double total = p_.col(c).dot(lambda_.cwiseInverse().cwiseProduct(p_.col(c))) + r_c(c, c);
        if (r_c(c, c) > 1e-12 * total) {
            r_index_[static_cast<std::size_t>(c)] = m + static_cast<int>(kept.size());
            kept.push_back(c);
        }
    }
    const int nr = static_cast<int>(kept.size());
    Eigen::MatrixXd rc(nr, nr), residual_w(dofs_, nr);
    Eigen::VectorXd contact_load(nr);
    for (int a = 0; a < nr; ++a) {
        residual_w.col(a) = basis.residual_w.col(kept[static_cast<std::size_t>(a)]);
        contact_load(a) = directions_.col(kept[static_cast<std::size_t>(a)]).dot(basis.residual_load);
        for (int b = 0; b < nr; ++b) rc(a, b) = r_c(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]);
    }
    rc = 0.5 * (rc + rc.transpose()).eval();
    const Eigen::LDLT<Eigen::MatrixXd> rc_ldlt(rc);
    const double rc_scale = nr > 0 ? rc.diagonal().maxCoeff() : 0.0;
    if (nr > 0 && (rc_ldlt.info() != Eigen::Success || !rc_ldlt.isPositive() ||
                   !(rc_ldlt.vectorD().minCoeff() > 1e-12 * rc_scale)))
        throw InvalidInput("the exact solver's modal form: the contacts' residual flexibility W^T R W beyond the " +
                           std::to_string(m) + " modes kept is singular (two contacts move the truncated modes "
                           "alike): allowed contacts with independent residual motion (more modes, or exact off)");
    const Eigen::MatrixXd k_r = rc_ldlt.solve(Eigen::MatrixXd::Identity(nr, nr));
    const Eigen::MatrixXd k_rr = 0.5 * (k_r + k_r.transpose());
    // The residual Ritz vectors: Psi = R W R_c^-1 (W^T Psi = I) and the load's d = R F - Psi W^T R F,
    // K-orthogonal to Psi (Psi^T K d = R_c^-1 (W^T R F - W^T R F) = 0), kept when its
    // stiffness d^T K d = F^T R F - (W^T R F)^T R_c^-1 W^T R F is above rounding.
    const double load_flexibility = system.excitation.dot(basis.residual_load);
    const double load_stiffness = load_flexibility - contact_load.dot(k_rr * contact_load);
    const Eigen::VectorXd modal_load = phi_.transpose() * system.excitation;
    const double load_total = modal_load.dot(lambda_.cwiseInverse().cwiseProduct(modal_load)) + load_flexibility;
    const bool load_mode = load_stiffness > 1e-12 * load_total;
    const int extra = nr + (load_mode ? 1 : 0);
    Eigen::MatrixXd basis_r(dofs_, extra);
    basis_r.leftCols(nr) = residual_w * k_rr;
    if (load_mode) basis_r.col(nr) = basis.residual_load - basis_r.leftCols(nr) * contact_load;
    Eigen::MatrixXd stiffness_r = Eigen::MatrixXd::Zero(extra, extra);
    stiffness_r.topLeftCorner(nr, nr) = k_rr;
    Eigen::VectorXd load_r(extra);
    load_r.head(nr) = k_rr * contact_load;
    if (load_mode) stiffness_r(nr, nr) = load_r(nr) = load_stiffness;
    // Each Ritz vector scaled to unit modal mass (as the modes): a residual shape's mass is
    // tiny (~ R_c^-1 / lambda_{m+1}) and would read as a massless DOF against the modes' 1.
    Eigen::VectorXd scale(extra);
    for (int j = 0; j < extra; ++j) {
        const double mass_j = basis_r.col(j).dot(system.mass * basis_r.col(j));
        if (!(mass_j > 0.0))
            throw InvalidInput("the exact solver's modal form: a residual Ritz vector has no mass (M not positive "
                               "definite on it)");
        scale(j) = 1.0 / std::sqrt(mass_j);
    }
    basis_r = basis_r * scale.asDiagonal();
    stiffness_r = scale.asDiagonal() * stiffness_r * scale.asDiagonal();
    load_r = scale.cwiseProduct(load_r);
    residual_basis_ = basis_r;
    residual_scale_ = scale;
    load_index_ = load_mode ? m + nr : -1;
    const Eigen::MatrixXd mass_r = basis_r.transpose() * (system.mass * basis_r);
    const Eigen::MatrixXd damping_r = basis_r.transpose() * (system.damping * basis_r);
    const int size = m + extra;
    Eigen::MatrixXd mass = Eigen::MatrixXd::Zero(size, size), damping = mass, stiffness = mass;
    Eigen::VectorXd load = Eigen::VectorXd::Zero(size);
    // [Phi, R ...] are M- and K-orthogonal (Phi^T M R = 0, Phi^T K R = 0), and so C-orthogonal for
    // a C diagonal in the modal basis: those blocks are set, not formed from rounding; so is
    // B^T K B = diag(R_c^-1, d^T K d) (the identity R K R = R).
    mass.topLeftCorner(m, m).setIdentity();
    mass.bottomRightCorner(extra, extra) = 0.5 * (mass_r + mass_r.transpose());
    damping.topLeftCorner(m, m) = basis.damping.asDiagonal();
    damping.bottomRightCorner(extra, extra) = 0.5 * (damping_r + damping_r.transpose());
    stiffness.topLeftCorner(m, m) = lambda_.asDiagonal();
    stiffness.bottomRightCorner(extra, extra) = stiffness_r;
    load.head(m) = modal_load;
    load.tail(extra) = load_r;
    modal_.mass = sparse(mass);
    modal_.damping = sparse(damping);
    modal_.stiffness = sparse(stiffness);
    modal_.excitation = load;
    modal_.excitation_harmonic = 1;
    for (int c = 0; c < nc; ++c) {
        Contact contact = system.contacts[static_cast<std::size_t>(c)];
        contact.direction = Eigen::VectorXd::Zero(size);
        contact.direction.head(m) = p_.col(c);  // u_c = p_c^T q + r_c
        const int i = r_index_[static_cast<std::size_t>(c)];
        if (i >= 0) contact.direction(i) = residual_scale_(i - m);
        modal_.contacts.push_back(std::move(contact));
    }
    modal_.validate();
}

Output ModalExactModel::output(const Output& original) const {
    original.validate(dofs_);
    const int m = modes(), size = modal_.dofs();
    // c^T y = c^T Phi q + c^T [Psi, d] r
    Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(size);
    for (const auto& [i, a] : original.terms()) {
        coefficients.head(m) += a * phi_.row(i).transpose();
        coefficients.tail(size - m) += a * residual_basis_.row(i).transpose();
    }
    std::vector<Output::Term> terms;
    for (int j = 0; j < size; ++j)
        if (coefficients(j) != 0.0) terms.emplace_back(j, coefficients(j));
    return Output(original.name(), terms);
}

Eigen::VectorXd ModalExactModel::reduce_state(const Eigen::VectorXd& state) const {
    const int n = dofs_, nc = static_cast<int>(r_index_.size()), m = modes(), size = modal_.dofs();
    if (state.size() != 2 * n + 2 * nc)
        throw InvalidInput("state size = " + std::to_string(state.size()) + " is out of range: allowed " +
                           std::to_string(2 * n + 2 * nc) + " (2 N + 2 n_c)");
    Eigen::VectorXd reduced = Eigen::VectorXd::Zero(2 * size + 2 * nc);
    reduced.head(m) = to_modal_ * state.head(n);
    reduced.segment(size, m) = to_modal_ * state.segment(n, n);
    for (int c = 0; c < nc; ++c) {
        const int i = r_index_[static_cast<std::size_t>(c)];
        if (i < 0) continue;
        const auto col = static_cast<Eigen::Index>(c);
        const double scale = residual_scale_(i - m);
        reduced(i) = (directions_.col(col).dot(state.head(n)) - p_.col(col).dot(reduced.head(m))) / scale;
        reduced(size + i) =
            (directions_.col(col).dot(state.segment(n, n)) - p_.col(col).dot(reduced.segment(size, m))) / scale;
    }
    if (load_index_ >= 0) reduced(load_index_) = 1.0 / residual_scale_(load_index_ - m);  // static under F cos(0)
    reduced.tail(2 * nc) = state.tail(2 * nc);
    return reduced;
}

int exact_solver_modes(const System& system, int modes) {
    if (rigid_contacts_only(system) || exact_solver_supports(system) || !system.has_positive_definite_mass() || system.excitation_harmonic != 1)
        return 0;
    for (const Contact& c : system.contacts)
        if (!contact_law(c.law).exact_stick() || c.base_motion != 0.0) return 0;
    return std::min(modes > 0 ? modes : automatic_exact_modes, largest_exact_modes(system));
}

int largest_exact_modes(const System& system) {
    return std::max(1, std::min(system.dofs(), exact_solver_max_dofs - static_cast<int>(system.contacts.size()) - 1));
}

}  // namespace hbf
