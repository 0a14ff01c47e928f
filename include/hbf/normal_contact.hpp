// hbfriction — friction contacts whose normal load follows the motion and which separate
// (issue 31). First step: the 2D elastic element (one normal and one tangential direction) on
// the samples of one period, with the exact Jacobian of its AFT force.
//
// Definition. Relative displacements u (tangential) and v (normal, positive closing), normal
// stiffness k_n > 0, tangential stiffness k_t > 0, friction coefficient mu >= 0, and n_0, the
// normal force at v = 0 (a preload N_0 >= 0, or -k_n g_0 for an initial gap g_0 >= 0):
//   N = max(0, n_0 + k_n v)                  normal force; separated where it is 0;
//   T = k_t (u - s),  |T| <= mu N            tangential force; the slider s moves only where
//                                            |T| = mu N, in the direction of T;
//   separated: T = 0, s = u                  (the tangential spring unloads).
// With v = 0 and n_0 = N_0 it is the Jenkins element with F_c = mu N_0 (contact.hpp's jenkins).
//
// On the samples (u_j, v_j), j = 0..N_t-1, of one period the slider is marched period after
// period, as Jenkins' is: the trial force k_t (u_j - s) either stays within mu N_j (stuck: s
// kept) or the slider moves to s = u_j - mu N_j sign(trial) / k_t (slipping); a separated
// sample sets s = u_j. After a slip or a separation the start is forgotten, so the second
// period is the periodic cycle. A cycle with neither (permanent stick) has a one-parameter
// family of slider positions, the interval of s with |k_t (u_j - s)| <= mu N_j at every
// sample: its midpoint is taken (for a constant N it is Jenkins' centred slider
// (max u + min u) / 2, the symmetric solution). Each force sample is then linear in at most
// three samples of (u, v) on its stick/slip/separation pattern (its own and its slider's
// anchors), so the Jacobian P (dF/dX) E is exact on the pattern.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "hbf/fourier.hpp"

namespace hbf {

/// The state of a contact at one time sample.
enum class ContactState : unsigned char { separated, stuck, slipping };

/// The 2D elastic friction element (see the top of this file).
struct ElasticContact2D {
    double normal_stiffness = 0;      ///< k_n > 0
    double tangential_stiffness = 0;  ///< k_t > 0
    double friction_coefficient = 0;  ///< mu >= 0
    double normal_offset = 0;         ///< n_0: the normal force at v = 0 (N_0, or -k_n g_0)
};

/// The periodic cycle on the samples.
struct NormalContactCycle {
    Eigen::VectorXd tangential;  ///< T_j
    Eigen::VectorXd normal;      ///< N_j
    std::vector<ContactState> state;
    /// The slider's dependence: s at sample j (after the sample) equals
    /// sum_m (u_weight[m] u_{anchor[m]} + v_weight[m] v_{anchor[m]}) + const over up to two
    /// anchors; a stuck sample's T_j = k_t (u_j - s_{j-1}).
    struct Slider {
        int anchor[2] = {-1, -1};
        double u_weight[2] = {0.0, 0.0};
        double v_weight[2] = {0.0, 0.0};
    };
    std::vector<Slider> slider_before;  ///< s_{j-1}'s dependence, for each sample j
    bool permanent_stick = false;
};

/// The periodic cycle of `element` on the samples u, v (equal sizes). Throws InvalidInput for
/// parameters out of range or samples of different sizes.
NormalContactCycle march(const ElasticContact2D& element, const Eigen::VectorXd& u, const Eigen::VectorXd& v);

/// The AFT forces and their exact Jacobian with respect to the coefficients of u and v (the
/// normal force does not depend on u).
struct NormalContactEvaluation {
    Eigen::VectorXd tangential, normal;  ///< coefficients (2H+1)
    Eigen::MatrixXd tangential_u, tangential_v, normal_v;
};
void evaluate(const ElasticContact2D& element, Fourier& fourier, const Eigen::VectorXd& u, const Eigen::VectorXd& v,
              NormalContactEvaluation& out, bool jacobian);

}  // namespace hbf
