// hbfriction — clamped DOFs of an FE model (reduction.hpp: clamp, clamped_outputs, unclamped).
#include <algorithm>
#include <string>

#include "fe/carry_directions.hpp"
#include "hbf/error.hpp"
#include "hbf/reduction.hpp"

namespace hbf {

namespace {

/// The rows and columns `kept` of a square sparse matrix.
SparseMatrix kept_block(const SparseMatrix& a, const std::vector<int>& index, int size) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < a.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
            const int r = index[static_cast<std::size_t>(it.row())], c = index[static_cast<std::size_t>(it.col())];
            if (r >= 0 && c >= 0) entries.emplace_back(r, c, it.value());
        }
    SparseMatrix out(size, size);
    out.setFromTriplets(entries.begin(), entries.end());
    return out;
}

Eigen::VectorXd kept_entries(const Eigen::VectorXd& v, const std::vector<int>& kept) {
    Eigen::VectorXd out(static_cast<Eigen::Index>(kept.size()));
    for (std::size_t i = 0; i < kept.size(); ++i) out(static_cast<Eigen::Index>(i)) = v(kept[i]);
    return out;
}

}  // namespace

ClampedSystem clamp(const System& s, const std::vector<int>& fixed) {
    const int n = s.dofs();
    if (s.cyclic.active())
        throw InvalidInput("structure.fixed: not for a sector model ([cyclic]): clamp the sector's DOFs in the matrices "
                           "given (a DOF of a cut face is also the next sector's)");
    ClampedSystem out;
    out.index.assign(static_cast<std::size_t>(n), 0);
    for (int d : fixed) {
        if (d < 0 || d >= n)
            throw InvalidInput("structure.fixed: DOF " + std::to_string(d + 1) + " is out of range: allowed 1.." +
                               std::to_string(n) + " (1-based)");
        if (out.index[static_cast<std::size_t>(d)] < 0)
            throw InvalidInput("structure.fixed: DOF " + std::to_string(d + 1) + " is listed twice");
        out.index[static_cast<std::size_t>(d)] = -1;
    }
    for (int d = 0; d < n; ++d)
        if (out.index[static_cast<std::size_t>(d)] >= 0) {
            out.index[static_cast<std::size_t>(d)] = static_cast<int>(out.kept.size());
            out.kept.push_back(d);
        }
    if (out.kept.empty()) throw InvalidInput("structure.fixed: clamps every DOF: allowed at least one DOF left free");
    for (int d : fixed) {
        const auto force = [&](const Eigen::VectorXd& f, const char* what) {
            if (f.size() == n && f(d) != 0.0)
                throw InvalidInput("structure.fixed: DOF " + std::to_string(d + 1) + " carries the " + what + " (" +
                                   format_number(f(d)) + "): a clamped DOF does not move, its force goes to the "
                                   "support: allowed a DOF without loads (clamp another DOF, or load it elsewhere)");
        };
        force(s.excitation, "excitation");
        force(s.static_load, "static load");
    }
    const int m = static_cast<int>(out.kept.size());
    System& c = out.system;
    c.mass = kept_block(s.mass, out.index, m);
    c.stiffness = kept_block(s.stiffness, out.index, m);
    c.damping = s.damping.rows() == n ? kept_block(s.damping, out.index, m) : SparseMatrix(m, m);
    c.excitation = kept_entries(s.excitation, out.kept);
    c.excitation_harmonic = s.excitation_harmonic;
    if (s.static_load.size() == n) c.static_load = kept_entries(s.static_load, out.kept);
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        Contact contact = s.contacts[k];
        const std::string name = "contact " + std::to_string(k + 1);
        // A direction carried: the clamped DOFs' entries dropped; one on clamped DOFs only
        // would never move.
        const auto carry = [&](const Eigen::VectorXd& w, const std::string& what) {
            const Eigen::VectorXd v = kept_entries(w, out.kept);
            if (w.cwiseAbs().maxCoeff() > 0.0 && v.cwiseAbs().maxCoeff() == 0.0)
                throw InvalidInput(name + ": its " + what + " acts on clamped DOFs only (structure.fixed): it would never "
                                   "move: allowed a contact on a free DOF");
            return v;
        };
        const int a = contact.dof, b = contact.other_dof;
        const bool by_dofs = contact.direction.size() == 0;
        if (by_dofs && out.index[static_cast<std::size_t>(a)] >= 0 &&
            (b == Contact::ground || out.index[static_cast<std::size_t>(b)] >= 0)) {
            contact.dof = out.index[static_cast<std::size_t>(a)];
            contact.other_dof = b == Contact::ground ? Contact::ground : out.index[static_cast<std::size_t>(b)];
        } else {
            contact.direction = carry(s.contact_direction(s.contacts[k]), "direction");
            contact.dof = 0;
            contact.other_dof = Contact::ground;
        }
        detail::carry_law_directions(contact, k, n, m, carry);
        c.contacts.push_back(std::move(contact));
    }
    return out;
}

std::vector<Output> clamped_outputs(const std::vector<Output>& outputs, const ClampedSystem& clamped) {
    std::vector<Output> out;
    for (const Output& o : outputs) {
        std::vector<Output::Term> terms;
        for (const auto& [i, c] : o.terms()) {
            const int k = i >= 0 && i < static_cast<int>(clamped.index.size()) ? clamped.index[static_cast<std::size_t>(i)] : -1;
            if (k >= 0) terms.emplace_back(k, c);
        }
        if (terms.empty())
            throw InvalidInput("output " + o.name() + ": on clamped DOFs only (structure.fixed): it would be zero: allowed an "
                               "output on a free DOF");
        out.emplace_back(o.name(), std::move(terms));
    }
    return out;
}

ReducedModel unclamped(ReducedModel model, const ClampedSystem& clamped) {
    const int n = static_cast<int>(clamped.index.size());
    Eigen::MatrixXd recovery = Eigen::MatrixXd::Zero(n, model.reduced());
    for (std::size_t i = 0; i < clamped.kept.size(); ++i)
        recovery.row(clamped.kept[i]) = model.recovery.row(static_cast<Eigen::Index>(i));
    model.recovery = std::move(recovery);
    for (int& d : model.retained) d = clamped.kept[static_cast<std::size_t>(d)];
    model.clamped_dofs = n - static_cast<int>(clamped.kept.size());
    return model;
}

}  // namespace hbf
