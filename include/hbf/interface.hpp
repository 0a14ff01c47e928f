// hbfriction — a meshed contact interface (a damper platform, a blade root, a flange) as one
// description instead of one contact per node: its nodes (the FE DOFs of each: x, y in 2D;
// x, y, z in 3D), their contact frames, their areas, and one contact law with its parameters.
// It expands into one contact per node against the ground (a rigid counter-face), with
//   the normal n: the closing direction (moving the node along n presses it into the contact;
//               law elastic's and unilateral's normal_direction, v = n^T y),
//   the tangent t1 (the contact's own direction: u = t1^T y) and, in 3D, t2 = n x t1
//               (second_direction),
// each a unit vector over the node's DOFs. In 2D, t1 is n turned by -90 degrees
// (t1 = (n_y, -n_x)); in 3D it is given, or chosen as the coordinate axis least aligned with n,
// made orthogonal to n. The law must have a normal direction (elastic, unilateral). Its
// parameters marked per_area (contact_law.hpp: law elastic's k_t, k_n and its own preload N_0) are
// per unit area: each node gets the interface's value times its area, so that an interface
// moved as a rigid patch is one contact with the summed stiffnesses. The others (mu, g_0, the
// penalties) are copied to every node. A preload pressure p presses the nodes into the
// contact: a static load p A_k n on node k (interface_load), which the contacts carry.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

struct ContactInterface {
    std::string name;                     ///< for messages ("interface 1" when empty)
    std::vector<std::vector<int>> nodes;  ///< each node's DOFs (0-based), 2 or 3, all nodes alike
    Eigen::MatrixXd normals;              ///< 1 x d (every node) or n x d: unit closing directions
    Eigen::MatrixXd tangents;             ///< 3D: empty (automatic), 1 x 3 or n x 3: unit t1 _|_ n
    Eigen::VectorXd areas;                ///< empty (1 each), 1 (every node) or n entries, > 0
    /// The law and its parameters as for one contact (the per_area ones per unit area); its
    /// directions are set by the expansion.
    Contact prototype;
    /// p >= 0: the static load p A_k n on node k (interface_load).
    double preload_pressure = 0;

    int dimension() const { return nodes.empty() ? 0 : static_cast<int>(nodes.front().size()); }
    double area(int node) const;
    /// Node k's frame as a d x d matrix, columns t1, (t2,) n.
    Eigen::MatrixXd frame(int node) const;
    /// Throws InvalidInput naming the interface and the field: no node, nodes of other than 2 or
    /// 3 DOFs or of different sizes, a DOF outside 0..dofs-1 or used twice in the interface, a
    /// normal or tangent of the wrong size, not unit (to 1e-6) or a tangent not orthogonal to
    /// its normal (to 1e-6), an area not > 0, a preload pressure not finite and >= 0, a law
    /// without a normal direction.
    void validate(int dofs) const;
};

/// One contact per node of `iface` (validated first, against `coordinates` DOFs unless
/// `coordinate` maps DOFs elsewhere), in node order. `coordinate(dof)` gives the coordinate a
/// DOF's motion is (the DOF itself without reduction, its retained coordinate after one:
/// reduction.hpp), or -1 when it has none (InvalidInput naming the node). The directions have
/// `coordinates` entries.
/// The preload pressure's static load on the FE DOFs (`dofs` entries): p A_k n_k on node k.
Eigen::VectorXd interface_load(const ContactInterface& iface, int dofs);

/// Where an interface's contacts are in a System: contacts first .. first + count - 1, one per
/// node in node order (hbf frf's per-contact columns _c<first + 1> .. and Python's
/// Branch.interface_states read them back per node).
struct InterfaceContacts {
    std::string name;   ///< the interface's name ("interface k" when it has none)
    int first = 0;      ///< 0-based index of its first node's contact
    int count = 0;      ///< its nodes
    int dimension = 0;  ///< 2 or 3
};

std::vector<Contact> interface_contacts(const ContactInterface& iface, int dofs, int coordinates,
                                        const std::function<int(int)>& coordinate);

}  // namespace hbf
