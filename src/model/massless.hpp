// hbfriction — internal (not installed), model level: the exact static condensation of massless
// DOFs, so that time integration and the event-exact solver (which need M > 0) run on reduced
// models with a massless boundary (time_integration.hpp, event_exact.hpp). Time integration's
// use of it (the reduced options, the expanded response) is in time_integration/massless.hpp.
//
// With the DOFs split into massive R and massless S (zero rows of M; C must vanish on S),
// the S rows of the equations of motion are static:
//     K_SS y_S + K_SR y_R + W_S f = F_S cos(omega t)
// so y_S = K_SS^-1 (F_S cos - K_SR y_R - W_S f), and the R rows become
//     M_RR y_R'' + C_RR y_R' + (K_RR - K_RS K_SS^-1 K_SR) y_R + W^_R f = (F_R - K_RS K_SS^-1 F_S) cos,
// with W^_R = W_R - K_RS K_SS^-1 W_S. A contact on massive DOFs only keeps its law. A contact
// that moves massless DOFs sees q = w^_R^T y_R - g f with the compliance
// g = w_S^T K_SS^-1 w_S > 0 and the load's share p = w_S^T K_SS^-1 F_S: exact Coulomb in series
// with that compliance is a Jenkins element of stiffness 1 / g along w^_R whose slider is the
// original q and whose spring's far end moves by p cos(h omega t) (Contact::base_motion:
// f = (w^_R^T y_R + p cos - q) / g); a Jenkins contact (k_t) becomes one of stiffness
// 1 / (1 / k_t + g) with the same slider and base motion. Refused, with the reason: other laws
// on massless DOFs, two such contacts coupled through K_SS^-1, damping on massless DOFs, a
// singular K_SS, or an M singular other than by zero rows.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "hbf/model.hpp"

namespace hbf::detail {

class MasslessCondensation {
public:
    /// Throws InvalidInput naming why the system cannot be condensed.
    explicit MasslessCondensation(const System& system);

    const System& reduced() const { return reduced_; }
    /// The system condensed (kept by reference: it must outlive the condensation).
    const System& original() const { return system_; }
    /// A state of the original system (time_integration.hpp's layout) as one of the reduced.
    Eigen::VectorXd reduce_state(const Eigen::VectorXd& state) const;

    /// The massless DOFs as linear functions of the reduced state: y_S = load cos(h w t) +
    /// from_massive y_R + from_sliders s, with the converted contacts' forces
    /// f_c = k_c (w^_c^T y_R + p_c cos - s_c) substituted (s: the reduced contacts' internal
    /// states, p: their base motion).
    struct MasslessMap {
        Eigen::VectorXd load;          ///< K_SS^-1 F_S (S)
        Eigen::MatrixXd from_massive;  ///< S x R
        Eigen::MatrixXd from_sliders;  ///< S x contacts
    };
    MasslessMap massless_map() const;
    /// Original DOF i: its index among the massive (R) or the massless (S) DOFs.
    int position(int dof) const { return position_[static_cast<std::size_t>(dof)]; }
    bool massless(int dof) const { return system_.mass.coeff(dof, dof) == 0.0; }
    /// True when contact c moves massless DOFs (it became a Jenkins element).
    bool converted(int contact) const { return converted_[static_cast<std::size_t>(contact)]; }
    /// The original indices of the massive (R) and of the massless (S) DOFs.
    const std::vector<int>& massive_dofs() const { return massive_; }
    const std::vector<int>& massless_dofs() const { return massless_; }
    /// y_S from y_R, the reduced contacts' forces f and the excitation's cosine cos(h w t).
    Eigen::VectorXd massless_displacement(const Eigen::VectorXd& y_r, const Eigen::VectorXd& f, double cosine) const;
    /// The first harmonic of y_S from those of y_R and of f (the load's part, on harmonic h,
    /// only when h = 1).
    Eigen::VectorXcd massless_harmonic(const Eigen::VectorXcd& y_r1, const Eigen::VectorXcd& f1) const;

private:
    const System& system_;
    System reduced_;
    std::vector<int> massive_, massless_;      // original DOF indices
    std::vector<int> position_;                // original DOF -> index in R or S
    Eigen::MatrixXd x_;                        // K_SS^-1 K_SR (S x R)
    Eigen::MatrixXd g_w_;                      // K_SS^-1 W_S (S x contacts)
    Eigen::VectorXd g_f_;                      // K_SS^-1 F_S
    std::vector<bool> converted_;              // per contact: became a Jenkins element
};

}  // namespace hbf::detail
