// hbfriction tests — law elastic's contacts as law unilateral's massless nodes on springs.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/model.hpp"

namespace hbf::test {

/// The structure of `s` (every contact of law elastic) with each contact replaced by massless
/// nodes, one per direction, tied to it by the element's springs (k_t along the tangential
/// directions, k_n along the normal one) and touching a rigid obstacle: a contact of law
/// unilateral on the nodes, with the gap g_0 and the preload as a static load, N_0 on the normal
/// node (onto the obstacle) and -N_0 along the normal direction on the structure, so that the
/// structure feels N = N_0 + k_n v while closed and nothing while open, as with law elastic.
inline System nodes_model(const System& s) {
    const int n = s.dofs();
    int added = 0;
    for (const Contact& c : s.contacts) added += static_cast<int>(s.contact_directions(c).cols());
    const int total = n + added;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(total, total), C = M, K = M;
    M.topLeftCorner(n, n) = Eigen::MatrixXd(s.mass);
    if (s.damping.nonZeros() > 0) C.topLeftCorner(n, n) = Eigen::MatrixXd(s.damping);
    K.topLeftCorner(n, n) = Eigen::MatrixXd(s.stiffness);
    Eigen::VectorXd F = Eigen::VectorXd::Zero(total), S = Eigen::VectorXd::Zero(total);
    F.head(n) = s.excitation;
    if (s.has_static_load()) S.head(n) = s.static_load;
    System out;
    int node = n;
    for (const Contact& c : s.contacts) {
        const Eigen::MatrixXd w = s.contact_directions(c);
        const int d = static_cast<int>(w.cols()) - 1;
        Contact u;
        u.law = parse_friction_law("unilateral");
        u.values["friction_coefficient"] = c.values.at("friction_coefficient");
        if (c.values.count("gap")) u.values["gap"] = c.values.at("gap");
        for (int a = 0; a <= d; ++a, ++node) {
            Eigen::VectorXd v = Eigen::VectorXd::Zero(total);
            v.head(n) = w.col(a);
            v(node) = -1.0;  // the spring k (w^T y - y_node)
            K += (a < d ? c.stiffness : c.values.at("normal_stiffness")) * v * v.transpose();
            std::vector<double> e(static_cast<std::size_t>(total), 0.0);
            e[static_cast<std::size_t>(node)] = 1.0;
            if (a == 0) u.dof = node;
            if (a > 0 && a < d) u.lists["second_direction"] = e;
            if (a == d) {
                u.lists["normal_direction"] = e;
                const double preload = c.values.count("preload") ? c.values.at("preload") : 0.0;
                S(node) += preload;
                S.head(n) -= preload * w.col(a);
            }
        }
        out.contacts.push_back(u);
    }
    out.mass = sparse(M);
    out.damping = sparse(C);
    out.stiffness = sparse(K);
    out.excitation = F;
    if (S.cwiseAbs().maxCoeff() > 0.0) out.static_load = S;
    return out;
}

}  // namespace hbf::test
