// hbfriction — friction contacts whose normal load follows the motion and which separate:
// the elastic element in 2D (one tangential direction) and 3D (two), on the
// samples of one period, with the exact Jacobian of its AFT force.
//
// Definition. Relative displacements u (tangential, d = 1 or 2 components) and v (normal,
// positive closing), normal stiffness k_n > 0, tangential stiffness k_t > 0, friction
// coefficient mu >= 0, and n_0, the normal force at v = 0 (a preload N_0 >= 0, or -k_n g_0 for
// an initial gap g_0 >= 0):
//   N = max(0, n_0 + k_n v)                 normal force; separated where it is 0;
//   T = k_t (u - s),  |T| <= mu N           tangential force (|.| the Euclidean norm: a
//                                           circular cone in 3D); the slider s moves only
//                                           where |T| = mu N, in the direction of T;
//   separated: T = 0, s = u                 (the tangential spring unloads).
// With v = 0 and n_0 = N_0 the 2D element is the Jenkins element with F_c = mu N_0 (contact_law.hpp).
//
// Time discretisation. On the samples (u_j, v_j), j = 0..N_t-1, of one period the slider is
// marched by the return map: the trial force t = k_t (u_j - s) either stays within mu N_j
// (stuck: s kept) or is scaled back onto the cone, T = mu N_j t / |t|, and the slider moves to
// s = u_j - T / k_t (slipping); a separated sample sets s = u_j, and the first closed sample
// after it starts from the slider where u was at the closing instant, interpolated linearly
// between the two samples by g = n_0 + k_n v (g crosses 0 there), so that the spring is
// unloaded at closing whatever the sample spacing. The periodic cycle is the
// slider s_0 before sample 0 that one period maps onto itself, s_0 = Phi(s_0):
//   * a separation forgets s_0, and so does a slip in 2D: the second period is periodic;
//   * a 3D slip keeps the part of a change of s_0 normal to the slip direction, scaled by
//     mu N_j / |t_j| < 1: the fixed point is found by Newton's method on Phi, whose derivative
//     the march carries (it converges geometrically only, slowly near the stick limit of a
//     circular motion, if merely iterated);
//   * a period without slip or separation (permanent stick) leaves a set of periodic slider
//     positions, {s : |s - u_j| <= r_j for all j}, r_j = mu N_j / k_t: the one with the largest
//     margin is taken, argmin_s max_j (|s - u_j| - r_j) (2D: the midpoint of the interval
//     max_j (u_j - r_j) .. min_j (u_j + r_j), for a constant N Jenkins' centred slider
//     (max u + min u) / 2; 3D: the centre of the smallest circle enclosing the circles of
//     radii -r_j about u_j, by Welzl's algorithm, rotation-equivariant like the element).
// The return map is exact at the samples where the slip direction does not turn between them
// (2D, and 3D motion along a line: the in-phase loop's samples equal its closed form); where it
// turns, it is first order in the sample spacing (circular sliding: the energy per cycle errs
// by 1.1 %, 0.28 %, 0.07 % at 128, 512, 2048 samples; tests/test_normal_contact.cpp).
// The Jacobian is exact on the stick/slip/separation pattern: the slider's derivative with
// respect to the coefficients is carried along the march (forward mode), started from the
// periodic fixed point's (I - Phi')^-1 or from the permanent-stick centre's active constraints.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <utility>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/fourier.hpp"
#include "hbf/model.hpp"

namespace hbf {

/// The state of a contact at one time sample.
enum class ContactState : unsigned char { separated, stuck, slipping };

/// The elastic friction element with a normal direction (see the top of this file).
struct ElasticContact {
    double normal_stiffness = 0;      ///< k_n > 0
    double tangential_stiffness = 0;  ///< k_t > 0
    double friction_coefficient = 0;  ///< mu >= 0
    double normal_offset = 0;         ///< n_0: the normal force at v = 0 (N_0, or -k_n g_0)
    int tangential_directions = 1;    ///< d: 1 (the 2D element) or 2 (3D)
};

/// The periodic cycle on the samples.
struct NormalContactCycle {
    Eigen::MatrixXd tangential;  ///< T_j (N_t x d)
    Eigen::VectorXd normal;      ///< N_j
    std::vector<ContactState> state;
    bool permanent_stick = false;
    /// The slider before sample 0 (the periodic s_0).
    Eigen::VectorXd slider;
};

/// The periodic cycle of `element` on the samples u (N_t x d) and v (N_t). Throws InvalidInput
/// for parameters out of range or samples of mismatched sizes, and std::runtime_error, naming
/// the residual, when Newton's method does not reach a 3D cycle's fixed point (to 1e-13 of the
/// motion's size within 50 steps).
NormalContactCycle march(const ElasticContact& element, const Eigen::MatrixXd& u, const Eigen::VectorXd& v);

/// The AFT forces and their exact Jacobian. q stacks the coefficients (2H+1 each) of
/// u_1, .., u_d, v; force stacks those of T_1, .., T_d, N; jacobian = d force / d q.
struct NormalContactEvaluation {
    Eigen::VectorXd force;
    Eigen::MatrixXd jacobian;
};
void evaluate(const ElasticContact& element, Fourier& fourier, const Eigen::VectorXd& q,
              NormalContactEvaluation& out, bool jacobian);

/// The element of a contact of law elastic (src/contact/elastic.cpp: its keys), validated by
/// System::validate: k_t = stiffness, n_0 = preload - normal_stiffness gap, d = 2 with a
/// second_direction.
ElasticContact elastic_element(const Contact& contact);

/// Rigid unilateral contacts with Coulomb friction (law unilateral, src/contact/unilateral.cpp)
/// as a complementarity problem on their relative displacements, q = q0 - G lambda: q0 those
/// without contact forces, G = W^T K^-1 W the Delassus matrix of the structure that holds the
/// contacts statically (time integration: the massless nodes' K_cc; the static state: all of
/// K), lambda stacked per contact, its d tangential entries from `first`, then the normal one.
/// One increment from `reference` (the tangential displacements it starts from):
///   lambda_N = max(0, lambda_N + e (v - g_0)),
///   lambda_T = proj_{|.| <= mu lambda_N} (lambda_T + e (u - u_reference)),
/// e = 1 / diag(G): Signorini on the displacement, Coulomb on the increment (stick holds the
/// reference; a slip moves along the force). Solved by the semi-smooth Newton method with the
/// exact generalised Jacobian and halving steps, from out.lambda (a warm start; zero when its
/// size differs), to 1e-12 of the forces' size, at most 100 steps; where that stalls, again with
/// the steps' test on the residual's 2-norm instead of its largest entry, and both from zero
/// (out.iterations counts them all).
struct RigidContact {
    int first = 0;  ///< its first entry in lambda
    int d = 1;      ///< tangential directions
    double mu = 0, gap = 0;
};
struct RigidContactSolution {
    Eigen::VectorXd lambda, q;
    std::vector<int> state;  ///< per contact: 0 open, 1 stuck, 2 slipping
    double residual = 0;     ///< |lambda - proj(...)|_inf at the end
    int iterations = 0;
};
/// False (with out at its last iterate) when Newton's method does not converge.
bool solve_rigid_contacts(const std::vector<RigidContact>& contacts, const Eigen::MatrixXd& G, const Eigen::VectorXd& q0,
                          const Eigen::VectorXd& reference, RigidContactSolution& out);
/// A contact of law unilateral as the problem's entry starting at `first`.
RigidContact rigid_contact(const Contact& contact, int first);

/// The directions of a contact with a normal direction (laws elastic and unilateral), named
/// for messages: the tangential one (Contact::direction, or its dof / other_dof), the
/// second_direction (3D), the normal_direction; empty without a normal_direction.
std::vector<std::pair<std::string, Eigen::VectorXd>> contact_direction_vectors(const Contact& contact);
/// Throws InvalidInput, naming the key after `where` and the law, unless the contact has a
/// normal_direction, its directions are orthogonal (to 1e-12) and its two tangential ones (3D)
/// of equal length (the friction cone is circular in the tangential plane).
void validate_normal_directions(const Contact& contact, const std::string& where, const char* law);
/// The parameters both laws with a normal direction share, in the order they end their lists:
/// friction_coefficient and gap first, then second_direction (3D) and normal_direction last.
struct NormalContactParameters {
    LawParameter friction_coefficient, gap, second_direction, normal_direction;
};
NormalContactParameters normal_contact_parameters();

}  // namespace hbf
