// hbfriction — the static contact problem (static_state.hpp).
#include "hbf/static_state.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"

namespace hbf {

bool has_static_problem(const System& system) {
    if (system.has_static_load()) return true;
    for (const Contact& c : system.contacts)
        for (const StuckElement& e : contact_law(c.law).stuck_directions(c))
            if (e.offset != 0.0) return true;
    return false;
}

std::vector<std::vector<StuckElement>> stuck_elements(const System& system) {
    std::vector<std::vector<StuckElement>> out;
    bool normal = false;
    for (const Contact& c : system.contacts) {
        out.push_back(contact_law(c.law).stuck_directions(c));
        normal = normal || (contact_law(c.law).friction() && system.contact_directions(c).cols() > 1);
    }
    if (!normal || !system.has_static_load()) return out;
    const StaticState rest = static_state(system);
    if (!rest.ok) return out;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Eigen::VectorXd& force = rest.contacts[c].force;
        if (contact_law(system.contacts[c].law).friction() && system.contact_directions(system.contacts[c]).cols() > 1 &&
            force.size() > 0)
            out[c] = contact_law(system.contacts[c].law).stuck_directions_at(system.contacts[c], force(force.size() - 1));
    }
    return out;
}

namespace {

struct Evaluation {
    Eigen::VectorXd residual;
    std::vector<StaticForce> forces;
    double size = 0;  // |residual|_inf
};

/// The static state of rigid unilateral contacts (law unilateral): the complementarity problem
/// of normal_contact.hpp on the whole structure, G = W^T K^-1 W, q0 = W^T K^-1 F_s, loaded in
/// one increment from rest (tangential reference 0: the holonomic solution).
StaticState rigid_static_state(const System& system, const Eigen::VectorXd& load,
                               const std::vector<Eigen::MatrixXd>& directions, double scale) {
    StaticState out;
    const int n = system.dofs();
    out.displacement = Eigen::VectorXd::Zero(n);
    std::vector<RigidContact> contacts;
    int entries = 0;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Contact& k = system.contacts[c];
        if (contact_law(k.law).time_integrator() != TimeIntegrator::unilateral_contacts) {
            out.message = "contact " + std::to_string(c + 1) + ": law " + to_string(k.law) +
                          " with rigid contacts (law unilateral): the static state of such a mix is not computed";
            return out;
        }
        contacts.push_back(rigid_contact(k, entries));
        entries += static_cast<int>(directions[c].cols());
    }
    Eigen::MatrixXd w(n, entries);
    for (std::size_t c = 0; c < contacts.size(); ++c) w.middleCols(contacts[c].first, directions[c].cols()) = directions[c];
    Eigen::SparseLU<SparseMatrix> lu(system.stiffness);
    Eigen::MatrixXd u;
    Eigen::VectorXd y0;
    if (lu.info() == Eigen::Success) {
        u = lu.solve(w);
        y0 = lu.solve(load);
    }
    if (lu.info() != Eigen::Success || !u.allFinite() || !y0.allFinite()) {
        out.message = "the stiffness matrix is singular: the static state of rigid contacts needs K regular (a structure "
                      "that holds itself without its contacts)";
        return out;
    }
    RigidContactSolution solution;
    const bool solved = solve_rigid_contacts(contacts, w.transpose() * u, w.transpose() * y0,
                                             Eigen::VectorXd::Zero(entries), solution);
    out.iterations = solution.iterations;
    out.displacement = y0 - u * solution.lambda;
    const Eigen::VectorXd residual = system.stiffness * out.displacement + w * solution.lambda - load;
    const double size = std::max(scale, solution.lambda.size() > 0 ? solution.lambda.cwiseAbs().maxCoeff() : 0.0);
    out.residual = size > 0.0 ? residual.cwiseAbs().maxCoeff() / size : 0.0;
    if (!solved) {
        out.message = "the rigid contacts' complementarity problem did not converge (residual " +
                      format_number(solution.residual) + " of the contact forces)";
        return out;
    }
    static const char* names[] = {"open", "stuck", "slipping"};
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        StaticContactState k;
        k.state = names[solution.state[c]];
        k.relative = solution.q.segment(contacts[c].first, directions[c].cols());
        k.force = solution.lambda.segment(contacts[c].first, directions[c].cols());
        out.contacts.push_back(k);
    }
    out.ok = true;
    return out;
}

}  // namespace

StaticState static_state(const System& system) {
    system.validate();
    StaticState out;
    if (system.cyclic.active()) {
        out.message = "the static state of a sector model (cyclic symmetry) is not solved";
        return out;
    }
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    const Eigen::VectorXd load = system.static_load.size() > 0 ? system.static_load : Eigen::VectorXd::Zero(n);
    std::vector<Eigen::MatrixXd> directions;
    for (const Contact& c : system.contacts) directions.push_back(system.contact_directions(c));
    out.displacement = Eigen::VectorXd::Zero(n);
    out.contacts.resize(static_cast<std::size_t>(nc));

    // The force scale: the load and every contact's force at rest (its preload).
    double scale = load.size() > 0 ? load.cwiseAbs().maxCoeff() : 0.0;
    for (const Contact& c : system.contacts)
        for (const StuckElement& e : contact_law(c.law).stuck_directions(c)) scale = std::max(scale, std::abs(e.offset));
    if (std::any_of(system.contacts.begin(), system.contacts.end(), [](const Contact& c) {
            return contact_law(c.law).time_integrator() == TimeIntegrator::unilateral_contacts;
        }))
        return rigid_static_state(system, load, directions, scale);
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        StaticForce probe;
        if (!contact_law(contact.law).static_force(contact, Eigen::VectorXd::Zero(directions[static_cast<std::size_t>(c)].cols()),
                                                   probe)) {
            out.message = "contact " + std::to_string(c + 1) + ": law " + to_string(contact.law) +
                          " has no single-valued static force (its stuck force is set-valued): the static contact state "
                          "is not computed";
            return out;
        }
    }
    auto evaluate = [&](const Eigen::VectorXd& y, Evaluation& e) {
        e.residual = system.stiffness * y - load;
        e.forces.resize(static_cast<std::size_t>(nc));
        for (int c = 0; c < nc; ++c) {
            const auto cc = static_cast<std::size_t>(c);
            const Contact& contact = system.contacts[cc];
            contact_law(contact.law).static_force(contact, directions[cc].transpose() * y, e.forces[cc]);
            e.residual += directions[cc] * e.forces[cc].force;
        }
        e.size = e.residual.cwiseAbs().maxCoeff();
    };
    // The Jacobian K + sum_c W_c J_c W_c^T, the products on the directions' nonzeros only.
    auto jacobian = [&](const Evaluation& e) {
        std::vector<Eigen::Triplet<double>> entries;
        for (int c = 0; c < nc; ++c) {
            const auto cc = static_cast<std::size_t>(c);
            const Eigen::MatrixXd& w = directions[cc];
            std::vector<int> support;
            for (int i = 0; i < n; ++i)
                if (w.row(i).cwiseAbs().maxCoeff() > 0.0) support.push_back(i);
            const Eigen::MatrixXd block = e.forces[cc].jacobian;
            for (int i : support)
                for (int j : support) {
                    const double value = w.row(i).dot(block * w.row(j).transpose());
                    if (value != 0.0) entries.emplace_back(i, j, value);
                }
        }
        SparseMatrix j(n, n);
        j.setFromTriplets(entries.begin(), entries.end());
        j += system.stiffness;
        return j;
    };

    constexpr int max_iterations = 100;
    constexpr double tolerance = 1e-10;
    Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
    Evaluation current;
    evaluate(y, current);
    Eigen::SparseLU<SparseMatrix> lu;
    bool analysed = false;
    for (int it = 0; it < max_iterations && current.size > tolerance * scale; ++it) {
        out.iterations = it + 1;
        const SparseMatrix j = jacobian(current);
        if (!analysed) {
            lu.analyzePattern(j);  // the pattern of K plus every direction's support: fixed
            analysed = true;
        }
        lu.factorize(j);
        Eigen::VectorXd step;
        if (lu.info() == Eigen::Success) step = lu.solve(-current.residual);
        if (lu.info() != Eigen::Success || !step.allFinite()) {
            out.message = "the static problem is singular at Newton step " + std::to_string(it + 1) +
                          " (a part of the structure held only by contacts that open or slip: no static equilibrium "
                          "under this load)";
            out.displacement = y;
            return out;
        }
        // Backtracking on |residual|_inf: piecewise-smooth forces (stick/slip, open/closed)
        // can send a full step across a kink.
        double t = 1.0;
        Evaluation trial;
        for (int halving = 0; halving < 40; ++halving, t *= 0.5) {
            evaluate(y + t * step, trial);
            if (trial.size < current.size) break;
        }
        if (!(trial.size < current.size)) {
            out.message = "Newton's method stalls at step " + std::to_string(it + 1) + " with a residual of " +
                          format_number(current.size / scale) +
                          " of the force scale (no static equilibrium under this load, or none near the unloaded state)";
            out.displacement = y;
            out.residual = scale > 0.0 ? current.size / scale : 0.0;
            return out;
        }
        y += t * step;
        current = std::move(trial);
    }
    out.displacement = y;
    out.residual = scale > 0.0 ? current.size / scale : 0.0;
    if (current.size > tolerance * scale) {
        out.message = "Newton's method did not reach " + format_number(tolerance) + " of the force scale in " +
                      std::to_string(max_iterations) + " steps (residual " + format_number(out.residual) + ")";
        return out;
    }
    for (int c = 0; c < nc; ++c) {
        const auto cc = static_cast<std::size_t>(c);
        out.contacts[cc].state = current.forces[cc].state;
        out.contacts[cc].force = current.forces[cc].force;
        out.contacts[cc].relative = directions[cc].transpose() * y;
        out.contacts[cc].slider = current.forces[cc].slider;
    }
    out.ok = true;
    return out;
}

PenaltyDiagnostics penalty_diagnostics(const System& system, const StaticState* rest, double penalty_ratio) {
    std::vector<std::string> stiff, relieved;
    std::vector<std::size_t> elastic;
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        if (system.contacts[c].law == FrictionLaw::elastic && system.contacts[c].values.count("normal_stiffness"))
            elastic.push_back(c);
    if (elastic.empty()) return {};
    Eigen::SparseLU<SparseMatrix> lu;
    lu.compute(system.stiffness);
    const bool regular = lu.info() == Eigen::Success;
    for (std::size_t c : elastic) {
        const Contact& k = system.contacts[c];
        const std::string name = "contact " + std::to_string(c + 1);
        const double k_n = k.values.at("normal_stiffness");
        if (regular) {
            const Eigen::MatrixXd w = system.contact_directions(k);
            const Eigen::MatrixXd u = lu.solve(w);
            // the structure's static stiffness along direction j: 1 / (w_j^T K^-1 w_j)
            const auto along = [&](Eigen::Index j) { return 1.0 / w.col(j).dot(u.col(j)); };
            const double k_normal = along(w.cols() - 1), k_tangent = along(0);
            std::string what;
            if (std::isfinite(k_normal) && k_normal > 0.0 && k_n > penalty_ratio * k_normal)
                what = "k_n = " + format_number(k_n) + " is " + format_number(k_n / k_normal) +
                       " times the structure's stiffness along its normal (" + format_number(k_normal) + ")";
            if (std::isfinite(k_tangent) && k_tangent > 0.0 && k.stiffness > penalty_ratio * k_tangent)
                what += (what.empty() ? "" : ", ") + std::string("k_t = ") + format_number(k.stiffness) + " is " +
                        format_number(k.stiffness / k_tangent) + " times its stiffness along the tangent (" +
                        format_number(k_tangent) + ")";
            if (!what.empty()) stiff.push_back(name + ": " + what);
        }
        const auto preload = k.values.find("preload");
        if (rest && rest->ok && c < rest->contacts.size() && preload != k.values.end() && preload->second > 0.0) {
            const Eigen::VectorXd& f = rest->contacts[c].force;
            const double n = f.size() > 0 ? f(f.size() - 1) : 0.0;
            if (n < 1e-2 * preload->second)
                relieved.push_back(name + ": its preload N_0 = " + format_number(preload->second) +
                                   " is relieved at rest to N = " + format_number(n) +
                                   " (the preload is the normal force at zero displacement; the structure yields to "
                                   "it, N = N_0 k / (k + k_n) with k the stiffness the normal spring sees and k_n = " +
                                   format_number(k_n) + "): a force that stays is a static load (structure.static_load)");
        }
    }
    const auto shorten = [](const std::vector<std::string>& lines, const std::string& tail) {
        std::vector<std::string> out;
        if (lines.size() <= 8) {
            for (const std::string& l : lines) out.push_back(l + tail);
        } else {
            out.push_back(lines.front() + tail + " (and " + std::to_string(lines.size() - 1) + " more contacts)");
        }
        return out;
    };
    PenaltyDiagnostics out;
    out.stiff = shorten(stiff, ": a penalty this stiff makes impacts and stick-slip kinks sharper than harmonic "
                               "balance's harmonics resolve (it converges slowly in H, or not at all); a rigid contact "
                               "is law unilateral, and hbf timeint integrates either");
    out.relieved = shorten(relieved, "");
    return out;
}

std::string describe(const StaticState& state) {
    if (!state.ok) return state.message;
    std::ostringstream s;
    if (state.contacts.size() > 8) {
        // A meshed interface: counts per state and the ranges of the forces (each contact's
        // in the --summary JSON), not a line per node.
        std::map<std::string, int> count;
        double n_low = std::numeric_limits<double>::infinity(), n_high = -n_low, t_high = 0.0;
        bool normal = false;
        for (const StaticContactState& k : state.contacts) {
            ++count[k.state];
            if (k.force.size() < 2) continue;
            normal = true;
            const double n = k.force(k.force.size() - 1);
            n_low = std::min(n_low, n);
            n_high = std::max(n_high, n);
            t_high = std::max(t_high, k.force.head(k.force.size() - 1).norm());
        }
        s << state.contacts.size() << " contacts:";
        const char* separator = " ";
        for (const auto& [name, number] : count) {
            s << separator << number << " " << name;
            separator = ", ";
        }
        if (normal)
            s << " (N from " << format_number(n_low) << " to " << format_number(n_high) << ", |T| up to "
              << format_number(t_high) << ")";
        return s.str();
    }
    for (std::size_t c = 0; c < state.contacts.size(); ++c) {
        const StaticContactState& k = state.contacts[c];
        s << (c > 0 ? ", " : "") << "contact " << c + 1 << ": " << k.state;
        if (k.force.size() > 1)
            s << " (N = " << format_number(k.force(k.force.size() - 1))
              << ", |T| = " << format_number(k.force.head(k.force.size() - 1).norm()) << ")";
        else if (k.force.size() == 1)
            s << " (f = " << format_number(k.force(0)) << ")";
    }
    return s.str();
}

}  // namespace hbf
