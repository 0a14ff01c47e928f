// hbfriction — internal: a structure whose rigid unilateral contacts (law unilateral) sit on
// massless DOFs, split into the DOFs with mass and the massless ones. The time integrator of
// law unilateral (time_integration/unilateral_contacts.cpp) and its exact periodic orbits
// (event_exact/rigid_engine.cpp) both solve it in this form. Not installed.
//
// The DOFs split into those with mass (a row of M not zero), y_m, and the massless ones, y_c,
// which carry every contact direction, have no damping and a regular stiffness K_cc:
//   M_mm y_m'' + C_mm y_m' + K_mm y_m + K_mc y_c = F_m cos(h w t) + S_m     (the structure)
//   K_cm y_m + K_cc y_c + W lambda = F_c cos(h w t) + S_c                    (the massless nodes)
// (S the static load). The contacts' relative displacements are q = W^T y_c = q0 - G lambda,
// q0 = W^T K_cc^-1 (F_c cos + S_c - K_cm y_m) those without contact forces and
// G = W^T K_cc^-1 W the Delassus matrix; lambda stacks per contact its d tangential entries,
// then the normal one (normal_contact.hpp: RigidContact).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "hbf/model.hpp"
#include "hbf/normal_contact.hpp"

namespace hbf::detail {

struct MasslessContacts {
    std::vector<int> massive, massless;  ///< DOF indices (0-based) of y_m and y_c
    std::vector<RigidContact> blocks;    ///< per contact: its entries of lambda
    int lambdas = 0;                     ///< size of lambda
    Eigen::MatrixXd Mmm, Cmm, Kmm, Kmc, Kcm, Kcc_inverse;
    Eigen::MatrixXd W;  ///< massless DOFs x lambdas: the contact directions
    Eigen::MatrixXd B;  ///< K_cc^-1 W
    Eigen::MatrixXd G;  ///< W^T K_cc^-1 W
    Eigen::VectorXd Fm, Fc, Sm, Sc;

    int dofs() const { return static_cast<int>(massive.size() + massless.size()); }
};

/// The massless nodes' static response and the masses' accelerations as rows over a state
/// vector of n entries whose first ones are y_m (then anything), with cos(h w t) at `cos_index`
/// and 1 at `one_index`: without contact forces, the nodes' positions y_c = free_nodes * state,
/// the contacts' relative displacements q0 = free * state, the masses' accelerations
/// y_m'' = base * state; transmit (masses x lambdas) adds the contact forces' effect on y_m''.
struct MasslessRows {
    Eigen::MatrixXd free_nodes, free, base, transmit;
};
MasslessRows massless_rows(const MasslessContacts& s, Eigen::Index n, Eigen::Index cos_index, Eigen::Index one_index);

/// The split of `system` (validated by the caller). Throws InvalidInput, naming the cause and
/// what is allowed, for: a contact of another law than unilateral, a contact direction on a DOF
/// with mass, damping on a massless DOF, M_mm not positive definite (or no DOF with mass),
/// K_cc singular, a contact direction along which the massless nodes have no flexibility.
/// `what` names the computation in the messages ("time integration", "the exact solver").
MasslessContacts split_massless_contacts(const System& system, const char* what);

/// The rows (indices) of a sub-matrix and of a sub-vector (empty: zeros).
Eigen::MatrixXd pick(const Eigen::MatrixXd& a, const std::vector<int>& rows, const std::vector<int>& cols);
Eigen::VectorXd pick(const Eigen::VectorXd& v, const std::vector<int>& rows);

}  // namespace hbf::detail
