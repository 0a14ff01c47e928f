// hbfriction — reduction of an FE model onto its interface (reduction.hpp).
#include "hbf/reduction.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "fe/carry_directions.hpp"
#include "hbf/error.hpp"
#include "hbf/receptance.hpp"
#include "base/enum_table.hpp"

namespace hbf {

constexpr detail::EnumName<ReductionMethod> reduction_method_names[] = {
    {ReductionMethod::craig_bampton, "craig-bampton"}, {ReductionMethod::massless_boundary, "massless-boundary"},
    {ReductionMethod::macneal, "macneal"}};

std::string to_string(ReductionMethod method) {
    return detail::enum_name(reduction_method_names, method, "reduction method");
}

ReductionMethod parse_reduction_method(const std::string& name) {
    return detail::parse_enum(reduction_method_names, name, "reduction.method");
}

void ReductionOptions::validate(int dofs, int retained) const {
    std::set<int> seen;
    for (std::size_t k = 0; k < interface_dofs.size(); ++k) {
        const int d = interface_dofs[k];
        if (d < 0 || d >= dofs)
            throw InvalidInput("reduction.interface: DOF " + std::to_string(d + 1) + " (entry " + std::to_string(k + 1) +
                               ") is out of range: allowed 1.." + std::to_string(dofs) + " (1-based FE DOFs)");
        if (!seen.insert(d).second)
            throw InvalidInput("reduction.interface: DOF " + std::to_string(d + 1) + " is listed twice (entry " +
                               std::to_string(k + 1) + "): allowed distinct DOFs");
    }
    const int interior = dofs - retained;
    const int lowest = method == ReductionMethod::macneal ? 1 : 0;
    if (modes < lowest || modes > interior)
        throw InvalidInput("reduction.modes = " + std::to_string(modes) + " is out of range: allowed " +
                           std::to_string(lowest) + ".." + std::to_string(interior) + " (the " + std::to_string(interior) +
                           " DOFs of " + std::to_string(dofs) + " not retained" +
                           (method == ReductionMethod::macneal ? "; macneal needs at least one mode" : "") + ")");
    if (retained + modes > max_reduced)
        throw InvalidInput("reduction: " + std::to_string(retained) + " retained DOFs + " + std::to_string(modes) +
                           " modes make a dense reduced model of " + std::to_string(retained + modes) +
                           " coordinates: allowed at most " + std::to_string(max_reduced));
    if (static_cast<long long>(dofs) * (retained + modes) > max_recovery_entries)
        throw InvalidInput("reduction: the recovery matrix T would hold " + std::to_string(dofs) + " x " +
                           std::to_string(retained + modes) + " entries: allowed at most " +
                           std::to_string(max_recovery_entries) + " (1 GB): retain fewer DOFs or keep fewer modes");
    if (!(rayleigh_mass >= 0.0 && std::isfinite(rayleigh_mass)) ||
        !(rayleigh_stiffness >= 0.0 && std::isfinite(rayleigh_stiffness)))
        throw InvalidInput("reduction.rayleigh = [" + std::to_string(rayleigh_mass) + ", " +
                           std::to_string(rayleigh_stiffness) + "] is out of range: allowed [a, b] with a, b >= 0");
    if (damping == Damping::modal) {
        if (modal_ratios.empty())
            throw InvalidInput("reduction.damping_ratios: empty: allowed one or more ratios in [0, 1)");
        for (double z : modal_ratios)
            if (!(z >= 0.0 && z < 1.0))
                throw InvalidInput("reduction.damping_ratios: " + std::to_string(z) + " is out of range: allowed [0, 1)");
    }
}

int ReducedModel::coordinate(int dof) const {
    const auto at = std::find(retained.begin(), retained.end(), dof);
    return at == retained.end() ? -1 : static_cast<int>(at - retained.begin());
}

std::string ReducedModel::summary() const {
    std::ostringstream out;
    out << "reduction " << to_string(method) << ": " << dofs() - clamped_dofs << " FE DOFs";
    if (clamped_dofs > 0) out << " (" << clamped_dofs << " more clamped)";
    out << " to " << reduced() << " coordinates (" << retained.size() << " retained DOFs";
    if (mode_frequencies.size() > 0)
        out << ", " << mode_frequencies.size() << (method == ReductionMethod::macneal ? " free" : " fixed")
            << "-interface modes, w " << mode_frequencies(0) << " to " << mode_frequencies(mode_frequencies.size() - 1);
    if (dropped_mass.size() > 0) out << "; dropped mass " << format_number(100.0 * dropped_mass_fraction) << " % of trace(M)";
    if (projected_load_dofs > 0)
        out << "; loads on " << projected_load_dofs << " interior DOFs projected onto the modes (retain_loads = false)";
    out << ")";
    return out.str();
}

std::vector<std::string> ReducedModel::warnings() const {
    if (dropped_mass.size() == 0 || !(dropped_mass_fraction > dropped_mass_warning)) return {};
    Eigen::Index largest = 0;
    dropped_mass.maxCoeff(&largest);
    return {"reduction " + to_string(method) + " drops " + format_number(100.0 * dropped_mass_fraction) +
            " % of the FE model's mass (trace of M; the retained DOFs' own mass M_bb - M_bi M_ii^-1 M_ib and what the "
            "truncated modes carried), most at FE DOF " + std::to_string(retained[static_cast<std::size_t>(largest)] + 1) +
            " (" + format_number(dropped_mass(largest)) +
            "): its frequencies and amplitudes differ from the FE model's; craig-bampton keeps that mass (massless "
            "boundaries suit interfaces whose nodes carry little mass)"};
}

namespace {

/// The rows `rows` and columns `cols` of a sparse matrix (positions: -1 where not selected).
SparseMatrix block(const SparseMatrix& a, const std::vector<int>& row_position, int rows,
                   const std::vector<int>& col_position, int cols) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < a.outerSize(); ++j) {
        const int c = col_position[static_cast<std::size_t>(j)];
        if (c < 0) continue;
        for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
            const int r = row_position[static_cast<std::size_t>(it.row())];
            if (r >= 0) entries.emplace_back(r, c, it.value());
        }
    }
    SparseMatrix out(rows, cols);
    out.setFromTriplets(entries.begin(), entries.end());
    return out;
}

Eigen::MatrixXd symmetric(const Eigen::MatrixXd& a) { return 0.5 * (a + a.transpose()); }

/// The m lowest normal modes of (K, M) (M-normalised, ascending), by receptance.hpp's modal
/// basis (dense or Spectra shift-invert, refined); `what` names the structure in messages.
Receptance::ModalBasis lowest_modes(const SparseMatrix& mass, const SparseMatrix& stiffness, int m,
                                    const Eigen::MatrixXd& attachments, const std::string& what) {
    const Eigen::Index n = stiffness.rows();
    Receptance r(mass, SparseMatrix(n, n), stiffness, attachments, Eigen::VectorXd::Zero(n), Eigen::MatrixXd(0, n));
    try {
        r.use_modes(m, Eigen::VectorXd::Zero(attachments.cols()), Eigen::VectorXd::Zero(attachments.cols()));
    } catch (const InvalidInput& e) {
        std::string why = e.what();
        if (why.rfind("modes: ", 0) == 0) why = why.substr(7);
        // The modal basis's advice is [solver] modes' (the direct solve): not an option here.
        const std::string advice = "use modes = 0, the direct solve";
        if (const auto at = why.find(advice); at != std::string::npos) {
            const auto separator = why.find_last_of(";:", at);
            if (separator != std::string::npos) why.erase(separator, at + advice.size() - separator);
        }
        throw InvalidInput("reduction.modes: the normal modes of " + what + " cannot be computed: " + why);
    }
    return r.modal_basis();
}

}  // namespace

ReducedModel reduce(const SparseMatrix& mass, const SparseMatrix& damping, const SparseMatrix& stiffness,
                    const ReductionOptions& options, const std::vector<int>& loaded_dofs) {
    const int n = static_cast<int>(stiffness.rows());
    if (mass.rows() != n || mass.cols() != n || stiffness.cols() != n)
        throw InvalidInput("reduction: M and K must be N x N matrices of the same size");
    const bool has_damping = damping.rows() > 0 && damping.nonZeros() > 0;
    if (has_damping && (damping.rows() != n || damping.cols() != n))
        throw InvalidInput("reduction: C must be N x N as M and K");
    if (has_damping && options.damping != ReductionOptions::Damping::projected)
        throw InvalidInput("reduction.damping: the structure has a damping matrix and reduction." +
                           std::string(options.damping == ReductionOptions::Damping::rayleigh ? "rayleigh" : "damping_ratios") +
                           " is given as well: allowed one of them");
    ReducedModel out;
    out.method = options.method;
    out.retained = options.interface_dofs;
    {
        const std::set<int> interface(options.interface_dofs.begin(), options.interface_dofs.end());
        std::set<int> extra;
        for (int d : loaded_dofs)
            if (d >= 0 && d < n && !interface.count(d)) extra.insert(d);
        out.retained.insert(out.retained.end(), extra.begin(), extra.end());
    }
    // Range checks on the interface as given, then the sizes with the loaded DOFs.
    options.validate(n, static_cast<int>(out.retained.size()));
    const int nb = static_cast<int>(out.retained.size()), ni = n - nb, m = options.modes, nr = nb + m;
    if (nb == 0) throw InvalidInput("reduction.interface: no DOF retained (no interface DOF, contact or load)");

    std::vector<int> b_position(static_cast<std::size_t>(n), -1), i_position(static_cast<std::size_t>(n), -1);
    std::vector<int> interior;
    for (int k = 0; k < nb; ++k) b_position[static_cast<std::size_t>(out.retained[static_cast<std::size_t>(k)])] = k;
    for (int d = 0; d < n; ++d)
        if (b_position[static_cast<std::size_t>(d)] < 0) {
            i_position[static_cast<std::size_t>(d)] = static_cast<int>(interior.size());
            interior.push_back(d);
        }

    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, nr);  // T, rows in FE order
    for (int k = 0; k < nb; ++k) t(out.retained[static_cast<std::size_t>(k)], k) = 1.0;
    Eigen::MatrixXd k_r = Eigen::MatrixXd::Zero(nr, nr), m_r = Eigen::MatrixXd::Zero(nr, nr);
    Eigen::VectorXd lambda;

    if (options.method == ReductionMethod::macneal) {
        // Free-interface modes of the whole structure and its residual flexibility at b.
        Eigen::MatrixXd e_b = Eigen::MatrixXd::Zero(n, nb);
        for (int k = 0; k < nb; ++k) e_b(out.retained[static_cast<std::size_t>(k)], k) = 1.0;
        const Receptance::ModalBasis basis = lowest_modes(mass, stiffness, m, e_b, "the structure (macneal: free interface)");
        lambda = basis.lambda;
        Eigen::MatrixXd phi_b(nb, m), g(nb, nb);
        for (int k = 0; k < nb; ++k) {
            phi_b.row(k) = basis.phi.row(out.retained[static_cast<std::size_t>(k)]);
            g.row(k) = basis.residual_w.row(out.retained[static_cast<std::size_t>(k)]);
        }
        g = symmetric(g);
        const Eigen::LDLT<Eigen::MatrixXd> g_ldlt(g);
        const double g_scale = g.diagonal().cwiseAbs().maxCoeff();
        if (g_ldlt.info() != Eigen::Success || !(g_ldlt.vectorD().minCoeff() > 1e-12 * g_scale))
            throw InvalidInput("reduction.modes = " + std::to_string(m) +
                               ": the residual flexibility at the retained DOFs is singular (the modes kept already "
                               "span their motion): allowed fewer modes for macneal");
        const Eigen::MatrixXd g_inv = symmetric(g_ldlt.solve(Eigen::MatrixXd::Identity(nb, nb)));
        const Eigen::MatrixXd g_inv_phi = g_inv * phi_b;
        k_r.topLeftCorner(nb, nb) = g_inv;
        k_r.topRightCorner(nb, m) = -g_inv_phi;
        k_r.bottomLeftCorner(m, nb) = -g_inv_phi.transpose();
        k_r.bottomRightCorner(m, m) = symmetric(Eigen::MatrixXd(lambda.asDiagonal()) + phi_b.transpose() * g_inv_phi);
        m_r.bottomRightCorner(m, m).setIdentity();
        const Eigen::MatrixXd attachment = basis.residual_w * g_inv;  // R E_b G^-1
        t.leftCols(nb) = attachment;
        t.rightCols(m) = basis.phi - attachment * phi_b;
        for (int k = 0; k < nb; ++k) {  // rows b are [I 0] (exactly, not to rounding)
            t.row(out.retained[static_cast<std::size_t>(k)]).setZero();
            t(out.retained[static_cast<std::size_t>(k)], k) = 1.0;
        }
    } else if (ni > 0) {
        const SparseMatrix k_ii = block(stiffness, i_position, ni, i_position, ni);
        const SparseMatrix k_ib = block(stiffness, i_position, ni, b_position, nb);
        const SparseMatrix m_ii = block(mass, i_position, ni, i_position, ni);
        const SparseMatrix m_ib = block(mass, i_position, ni, b_position, nb);
        const SparseMatrix k_bb = block(stiffness, b_position, nb, b_position, nb);
        const SparseMatrix m_bb = block(mass, b_position, nb, b_position, nb);
        const Eigen::SimplicialLDLT<SparseMatrix> k_ii_ldlt(k_ii);
        const double k_scale = k_ii.nonZeros() > 0 ? k_ii.diagonal().cwiseAbs().maxCoeff() : 0.0;
        if (k_ii_ldlt.info() != Eigen::Success || !(k_ii_ldlt.vectorD().minCoeff() > 1e-13 * k_scale))
            throw InvalidInput(
                "reduction.interface: the structure with its retained DOFs held is singular or not positive definite "
                "(K_ii: a rigid-body mode or mechanism the interface does not hold, as in an unconstrained structure): "
                "the constraint modes do not exist; hold the structure (boundary conditions in K) or retain the DOFs "
                "that hold it");
        // Psi = -K_ii^-1 K_ib, one step of refinement (FE stiffnesses span many decades).
        const Eigen::MatrixXd rhs = -Eigen::MatrixXd(k_ib);
        Eigen::MatrixXd psi = k_ii_ldlt.solve(rhs);
        psi += k_ii_ldlt.solve(Eigen::MatrixXd(rhs - k_ii * psi));
        Eigen::MatrixXd theta(ni, m);
        if (m > 0) {
            const Receptance::ModalBasis basis =
                lowest_modes(m_ii, k_ii, m, Eigen::MatrixXd(ni, 0), "the structure with its interface held");
            lambda = basis.lambda;
            theta = basis.phi;
        }
        // T^T M T blocks: the constraint modes' (b, b) and their coupling to the modes (b, eta).
        const Eigen::MatrixXd m_psi = m_ii * psi + m_ib;  // M_ii Psi + M_ib
        const Eigen::MatrixXd m_bb_hat =
            symmetric(Eigen::MatrixXd(m_bb) + Eigen::MatrixXd(m_ib.transpose()) * psi + psi.transpose() * m_psi);
        const Eigen::MatrixXd alpha = theta.transpose() * m_psi;  // m x nb
        const Eigen::MatrixXd k_bb_hat = symmetric(Eigen::MatrixXd(k_bb) + Eigen::MatrixXd(k_ib.transpose()) * psi);
        if (options.method == ReductionMethod::craig_bampton) {
            k_r.topLeftCorner(nb, nb) = k_bb_hat;
            k_r.bottomRightCorner(m, m) = lambda.asDiagonal();
            m_r.topLeftCorner(nb, nb) = m_bb_hat;
            m_r.topRightCorner(nb, m) = alpha.transpose();
            m_r.bottomLeftCorner(m, nb) = alpha;
            m_r.bottomRightCorner(m, m).setIdentity();
        } else {  // massless boundary: Psi' = Psi - Theta alpha, its mass dropped
            out.dropped_mass = (m_bb_hat - alpha.transpose() * alpha).diagonal();
            psi -= theta * alpha;
            const Eigen::MatrixXd lambda_alpha = lambda.asDiagonal() * alpha;
            k_r.topLeftCorner(nb, nb) = symmetric(k_bb_hat + alpha.transpose() * lambda_alpha);
            k_r.topRightCorner(nb, m) = -lambda_alpha.transpose();
            k_r.bottomLeftCorner(m, nb) = -lambda_alpha;
            k_r.bottomRightCorner(m, m) = lambda.asDiagonal();
            m_r.bottomRightCorner(m, m).setIdentity();
        }
        for (int r = 0; r < ni; ++r) {
            t.row(interior[static_cast<std::size_t>(r)]).head(nb) = psi.row(r);
            t.row(interior[static_cast<std::size_t>(r)]).tail(m) = theta.row(r);
        }
    } else {  // every DOF retained: the FE model, reordered
        k_r = Eigen::MatrixXd(block(stiffness, b_position, nb, b_position, nb));
        m_r = options.method == ReductionMethod::craig_bampton ? Eigen::MatrixXd(block(mass, b_position, nb, b_position, nb))
                                                               : Eigen::MatrixXd::Zero(nb, nb);
        if (options.method == ReductionMethod::massless_boundary)
            out.dropped_mass = Eigen::MatrixXd(block(mass, b_position, nb, b_position, nb)).diagonal();
    }
    if (out.dropped_mass.size() > 0) {
        const double total = Eigen::VectorXd(mass.diagonal()).sum();
        out.dropped_mass_fraction = total > 0.0 ? out.dropped_mass.sum() / total : 0.0;
    }
    out.mode_frequencies = lambda.size() > 0 ? Eigen::VectorXd(lambda.cwiseSqrt()) : Eigen::VectorXd();

    Eigen::MatrixXd c_r = Eigen::MatrixXd::Zero(nr, nr);
    switch (options.damping) {
        case ReductionOptions::Damping::projected:
            if (has_damping) c_r = symmetric(t.transpose() * (damping * t));
            break;
        case ReductionOptions::Damping::rayleigh:
            c_r = options.rayleigh_mass * m_r + options.rayleigh_stiffness * k_r;
            break;
        case ReductionOptions::Damping::modal: {
            // The reduced model's normal modes: its massless coordinates (zero rows of M_r)
            // condensed statically, the rest a generalised symmetric eigenproblem.
            std::vector<int> inert, heavy;
            for (int k = 0; k < nr; ++k) (m_r.row(k).cwiseAbs().maxCoeff() > 0.0 ? heavy : inert).push_back(k);
            const int nh = static_cast<int>(heavy.size()), nz = static_cast<int>(inert.size());
            Eigen::MatrixXd khh(nh, nh), mhh(nh, nh), kzz(nz, nz), kzh(nz, nh);
            for (int a = 0; a < nh; ++a)
                for (int b = 0; b < nh; ++b) {
                    khh(a, b) = k_r(heavy[static_cast<std::size_t>(a)], heavy[static_cast<std::size_t>(b)]);
                    mhh(a, b) = m_r(heavy[static_cast<std::size_t>(a)], heavy[static_cast<std::size_t>(b)]);
                }
            for (int a = 0; a < nz; ++a) {
                for (int b = 0; b < nz; ++b) kzz(a, b) = k_r(inert[static_cast<std::size_t>(a)], inert[static_cast<std::size_t>(b)]);
                for (int b = 0; b < nh; ++b) kzh(a, b) = k_r(inert[static_cast<std::size_t>(a)], heavy[static_cast<std::size_t>(b)]);
            }
            if (nz > 0) {
                const Eigen::LDLT<Eigen::MatrixXd> kzz_ldlt(kzz);
                if (kzz_ldlt.info() != Eigen::Success)
                    throw InvalidInput("reduction.damping_ratios: the reduced model's massless coordinates are singular");
                khh = symmetric(khh - kzh.transpose() * kzz_ldlt.solve(kzh));
            }
            const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(khh, symmetric(mhh));
            if (modes.info() != Eigen::Success || !(modes.eigenvalues().minCoeff() > 0.0))
                throw InvalidInput("reduction.damping_ratios: the reduced model's normal modes are not all elastic "
                                   "(a rigid-body mode or negative stiffness): allowed rayleigh or a damping matrix");
            // C_hh = M_hh Phi diag(2 zeta_j w_j) Phi^T M_hh (Phi M-normalised), zero elsewhere.
            Eigen::VectorXd d(nh);
            for (int j = 0; j < nh; ++j) {
                const double zeta = options.modal_ratios[std::min<std::size_t>(static_cast<std::size_t>(j), options.modal_ratios.size() - 1)];
                d(j) = 2.0 * zeta * std::sqrt(modes.eigenvalues()(j));
            }
            const Eigen::MatrixXd mphi = symmetric(mhh) * modes.eigenvectors();
            const Eigen::MatrixXd chh = symmetric(mphi * d.asDiagonal() * mphi.transpose());
            for (int a = 0; a < nh; ++a)
                for (int b = 0; b < nh; ++b) c_r(heavy[static_cast<std::size_t>(a)], heavy[static_cast<std::size_t>(b)]) = chh(a, b);
            break;
        }
    }
    out.stiffness = sparse(k_r);
    out.mass = sparse(m_r);
    out.damping = sparse(c_r);
    out.recovery = std::move(t);
    return out;
}

ReducedSystem reduce(const System& fe, const ReductionOptions& options) {
    const int n = fe.dofs();
    std::vector<int> loaded;
    for (int i = 0; i < n; ++i)
        if (fe.excitation(i) != 0.0 || (fe.static_load.size() == n && fe.static_load(i) != 0.0)) loaded.push_back(i);
    std::vector<int> projected;  // loaded DOFs left interior (retain_loads false)
    if (!options.retain_loads) projected.swap(loaded);
    // A sector (cyclic.hpp): the DOFs shared with the next sector (its cut faces, a contact's
    // neighbour DOFs) and their masters stay physical, after the interface: each sector a
    // component of the wheel, joined to the next at retained DOFs (the reduced wheel is the
    // wheel of reduced sectors).
    ReductionOptions chosen = options;
    if (fe.cyclic.active()) {
        if (options.method == ReductionMethod::macneal)
            throw InvalidInput("reduction.method = macneal: not for a sector model (its free-interface modes "
                               "would not keep the cut faces physical): allowed craig-bampton or massless-boundary");
        std::set<int> kept(chosen.interface_dofs.begin(), chosen.interface_dofs.end());
        for (const auto& [d, m] : fe.cyclic.neighbours)
            for (int dof : {m, d})
                if (dof >= 0 && dof < n && kept.insert(dof).second) chosen.interface_dofs.push_back(dof);
    }
    ReducedSystem out;
    out.model = reduce(fe.mass, fe.damping, fe.stiffness, chosen, loaded);
    out.model.projected_load_dofs = static_cast<int>(
        std::count_if(projected.begin(), projected.end(), [&](int d) { return out.model.coordinate(d) < 0; }));
    const ReducedModel& model = out.model;
    System& s = out.system;
    s.mass = model.mass;
    s.damping = model.damping;
    s.stiffness = model.stiffness;
    s.excitation = model.project(fe.excitation);
    s.excitation_harmonic = fe.excitation_harmonic;
    if (fe.static_load.size() == n) s.static_load = model.project(fe.static_load);
    // A direction on the FE DOFs as one on the reduced coordinates: its retained entries (T's
    // rows b are [I 0]); an entry on an interior DOF has no coordinate to act on.
    auto carry = [&](const Eigen::VectorXd& w, std::size_t c) {
        Eigen::VectorXd out_w = Eigen::VectorXd::Zero(model.reduced());
        for (int i = 0; i < n; ++i) {
            if (w(i) == 0.0) continue;
            const int k = model.coordinate(i);
            if (k < 0)
                throw InvalidInput("contact " + std::to_string(c + 1) + ": acts on FE DOF " + std::to_string(i + 1) +
                                   ", which the reduction does not retain: allowed the DOFs of reduction.interface "
                                   "(list it there)");
            out_w(k) = w(i);
        }
        return out_w;
    };
    for (std::size_t c = 0; c < fe.contacts.size(); ++c) {
        Contact contact = fe.contacts[c];
        contact.direction = carry(fe.contact_direction(contact), c);
        contact.dof = 0;
        contact.other_dof = Contact::ground;
        detail::carry_law_directions(contact, c, n, model.reduced(),
                                     [&](const Eigen::VectorXd& w, const std::string&) { return carry(w, c); });
        s.contacts.push_back(std::move(contact));
    }
    if (fe.cyclic.active()) {
        s.cyclic = fe.cyclic;
        for (auto& [d, m] : s.cyclic.neighbours) {
            d = model.coordinate(d);
            m = model.coordinate(m);
        }
    }
    return out;
}

std::vector<Output> reduced_outputs(const std::vector<Output>& fe_outputs, const ReducedModel& model) {
    std::vector<Output> out;
    for (const Output& o : fe_outputs) {
        Eigen::VectorXd row = Eigen::VectorXd::Zero(model.reduced());
        for (const auto& [i, c] : o.terms()) row += c * model.recovery.row(i).transpose();
        std::vector<Output::Term> terms;
        for (int k = 0; k < model.reduced(); ++k)
            if (row(k) != 0.0) terms.emplace_back(k, row(k));
        if (terms.empty())
            throw InvalidInput("output " + o.name() + ": the reduced model does not move it (its row of T is zero): "
                               "allowed an output on a DOF the structure moves");
        out.emplace_back(o.name(), std::move(terms));
    }
    return out;
}

}  // namespace hbf
