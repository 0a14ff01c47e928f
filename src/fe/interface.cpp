// hbfriction — meshed contact interfaces expanded into contacts (interface.hpp).
#include "hbf/interface.hpp"

#include <cmath>
#include <set>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

std::string label(const ContactInterface& iface) { return iface.name.empty() ? std::string("interface") : iface.name; }

/// Row k of a 1 x d or n x d matrix (one row for every node, or one per node).
Eigen::VectorXd row_of(const Eigen::MatrixXd& m, int k) {
    return m.rows() == 1 ? Eigen::VectorXd(m.row(0).transpose()) : Eigen::VectorXd(m.row(k).transpose());
}

}  // namespace

double ContactInterface::area(int node) const {
    if (areas.size() == 0) return 1.0;
    return areas.size() == 1 ? areas(0) : areas(node);
}

Eigen::MatrixXd ContactInterface::frame(int node) const {
    const int d = dimension();
    const Eigen::VectorXd n = row_of(normals, node);
    Eigen::MatrixXd f(d, d);
    if (d == 2) {
        f.col(0) << n(1), -n(0);
        f.col(1) = n;
        return f;
    }
    Eigen::Vector3d t;
    if (tangents.size() > 0) {
        t = row_of(tangents, node);
    } else {  // the axis least aligned with n, made orthogonal to it
        Eigen::Index axis = 0;
        n.cwiseAbs().minCoeff(&axis);
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
        t = (e - e.dot(n) * n).normalized();
    }
    const Eigen::Vector3d n3 = n;
    f.col(0) = t;
    f.col(1) = n3.cross(t);
    f.col(2) = n3;
    return f;
}

void ContactInterface::validate(int dofs) const {
    const std::string at = label(*this) + ": ";
    if (nodes.empty()) throw InvalidInput(at + "nodes: none given: allowed one or more nodes");
    const int d = dimension();
    if (d != 2 && d != 3)
        throw InvalidInput(at + "nodes: node 1 has " + std::to_string(d) + " DOFs: allowed 2 (x, y) or 3 (x, y, z)");
    const int n = static_cast<int>(nodes.size());
    std::set<int> seen;
    for (int k = 0; k < n; ++k) {
        const std::vector<int>& node = nodes[static_cast<std::size_t>(k)];
        if (static_cast<int>(node.size()) != d)
            throw InvalidInput(at + "nodes: node " + std::to_string(k + 1) + " has " + std::to_string(node.size()) +
                               " DOFs: allowed " + std::to_string(d) + " as node 1");
        for (int dof : node) {
            if (dof < 0 || dof >= dofs)
                throw InvalidInput(at + "nodes: node " + std::to_string(k + 1) + " has DOF " + std::to_string(dof + 1) +
                                   ": allowed 1.." + std::to_string(dofs) + " (1-based FE DOFs)");
            if (!seen.insert(dof).second)
                throw InvalidInput(at + "nodes: DOF " + std::to_string(dof + 1) + " of node " + std::to_string(k + 1) +
                                   " is used twice in the interface: allowed each DOF in one node once");
        }
    }
    auto check_rows = [&](const Eigen::MatrixXd& m, const char* key) {
        if (m.cols() != d || (m.rows() != 1 && m.rows() != n))
            throw InvalidInput(at + key + ": " + std::to_string(m.rows()) + " x " + std::to_string(m.cols()) +
                               ": allowed one vector of " + std::to_string(d) + " components, or one per node (" +
                               std::to_string(n) + " x " + std::to_string(d) + ")");
        for (Eigen::Index k = 0; k < m.rows(); ++k) {
            const double norm = m.row(k).norm();
            if (!m.row(k).allFinite() || std::abs(norm - 1.0) > 1e-6)
                throw InvalidInput(at + key + ": row " + std::to_string(k + 1) + " has length " + format_number(norm) +
                                   ": allowed unit vectors (to 1e-6)");
        }
    };
    check_rows(normals, "normal");
    if (tangents.size() > 0) {
        if (d == 2) throw InvalidInput(at + "tangent: given for 2D nodes: allowed in 3D only (in 2D t1 follows from n)");
        check_rows(tangents, "tangent");
        for (int k = 0; k < (tangents.rows() == 1 && normals.rows() == 1 ? 1 : n); ++k) {
            const double c = row_of(tangents, k).dot(row_of(normals, k));
            if (std::abs(c) > 1e-6)
                throw InvalidInput(at + "tangent: node " + std::to_string(k + 1) + "'s tangent is not orthogonal to its "
                                   "normal (t1 . n = " + format_number(c) + "): allowed |t1 . n| <= 1e-6");
        }
    }
    if (areas.size() != 0 && areas.size() != 1 && areas.size() != n)
        throw InvalidInput(at + "area: " + std::to_string(areas.size()) + " entries: allowed one, or one per node (" +
                           std::to_string(n) + ")");
    for (Eigen::Index k = 0; k < areas.size(); ++k)
        if (!(areas(k) > 0.0 && std::isfinite(areas(k))))
            throw InvalidInput(at + "area: entry " + std::to_string(k + 1) + " = " + format_number(areas(k)) +
                               " is out of range: allowed > 0");
    if (!(preload_pressure >= 0.0 && std::isfinite(preload_pressure)))
        throw InvalidInput(at + "preload_pressure: " + format_number(preload_pressure) +
                           " is out of range: allowed finite and >= 0");
    bool normal_law = false;
    for (const LawParameter& p : contact_law(prototype.law).parameters())
        normal_law = normal_law || (p.kind == LawParameter::Kind::direction && std::string(p.key) == "normal_direction");
    if (!normal_law)
        throw InvalidInput(at + "law: '" + to_string(prototype.law) +
                           "' has no normal direction: allowed elastic or unilateral (the laws with a normal load)");
}

Eigen::VectorXd interface_load(const ContactInterface& iface, int dofs) {
    iface.validate(dofs);
    Eigen::VectorXd load = Eigen::VectorXd::Zero(dofs);
    const int d = iface.dimension();
    for (int k = 0; k < static_cast<int>(iface.nodes.size()); ++k) {
        const Eigen::MatrixXd f = iface.frame(k);
        for (int j = 0; j < d; ++j)
            load(iface.nodes[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]) +=
                iface.preload_pressure * iface.area(k) * f(j, d - 1);
    }
    return load;
}

std::vector<Contact> interface_contacts(const ContactInterface& iface, int dofs, int coordinates,
                                        const std::function<int(int)>& coordinate) {
    iface.validate(dofs);
    const int d = iface.dimension(), n = static_cast<int>(iface.nodes.size());
    const std::vector<LawParameter> parameters = contact_law(iface.prototype.law).parameters();
    std::vector<Contact> out;
    out.reserve(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
        const std::vector<int>& node = iface.nodes[static_cast<std::size_t>(k)];
        std::vector<int> at(static_cast<std::size_t>(d));
        for (int j = 0; j < d; ++j) {
            at[static_cast<std::size_t>(j)] = coordinate(node[static_cast<std::size_t>(j)]);
            if (at[static_cast<std::size_t>(j)] < 0)
                throw InvalidInput(label(iface) + ": nodes: node " + std::to_string(k + 1) + "'s DOF " +
                                   std::to_string(node[static_cast<std::size_t>(j)] + 1) +
                                   " is not a coordinate of the model (not retained by the reduction)");
        }
        const Eigen::MatrixXd f = iface.frame(k);
        auto over = [&](const Eigen::VectorXd& local) {  // a direction on the node's coordinates
            Eigen::VectorXd w = Eigen::VectorXd::Zero(coordinates);
            for (int j = 0; j < d; ++j) w(at[static_cast<std::size_t>(j)]) += local(j);
            return w;
        };
        Contact c = iface.prototype;
        c.dof = 0;
        c.other_dof = Contact::ground;
        c.direction = over(f.col(0));
        const Eigen::VectorXd normal = over(f.col(d - 1));
        c.lists["normal_direction"].assign(normal.data(), normal.data() + normal.size());
        if (d == 3) {
            const Eigen::VectorXd second = over(f.col(1));
            c.lists["second_direction"].assign(second.data(), second.data() + second.size());
        }
        const double area = iface.area(k);
        for (const LawParameter& p : parameters)
            if (p.per_area && (p.field || iface.prototype.values.count(p.key))) p.set(c, p.get(iface.prototype) * area);
        c.label = (iface.name.empty() ? std::string("interface") : "interface '" + iface.name + "'") + " node " +
                  std::to_string(k + 1);
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace hbf
