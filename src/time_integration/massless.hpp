// Exact static condensation of massless DOFs, so that time integration (which needs M > 0)
// runs on reduced models with a massless boundary (time_integration.hpp).
//
// With the DOFs split into massive R and massless S (zero rows of M; C must vanish on S),
// the S rows of the equations of motion are static:
//     K_SS y_S + K_SR y_R + W_S f = F_S cos(omega t)
// so y_S = K_SS^-1 (F_S cos - K_SR y_R - W_S f), and the R rows become
//     M_RR y_R'' + C_RR y_R' + (K_RR - K_RS K_SS^-1 K_SR) y_R + W^_R f = (F_R - K_RS K_SS^-1 F_S) cos,
// with W^_R = W_R - K_RS K_SS^-1 W_S. A contact on massive DOFs only keeps its law. A contact
// that moves massless DOFs sees q = w^_R^T y_R - g f with the compliance
// g = w_S^T K_SS^-1 w_S > 0: exact Coulomb in series with that compliance is a Jenkins element
// of stiffness 1 / g along w^_R whose slider is the original q; a Jenkins contact (k_t) becomes
// one of stiffness 1 / (1 / k_t + g) with the same slider. Refused, with the reason: other laws
// on massless DOFs, two such contacts coupled through K_SS^-1, F_S != 0 together with them,
// damping on massless DOFs, a singular K_SS, or an M singular other than by zero rows.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::detail {

class MasslessCondensation {
public:
    /// Throws InvalidInput naming why the system cannot be condensed.
    explicit MasslessCondensation(const System& system);

    const System& reduced() const { return reduced_; }
    /// Options for the reduced system: the outputs that involve massive DOFs only, mapped.
    TimeIntegrationOptions reduced_options(const TimeIntegrationOptions& options) const;
    /// A state of the original system (time_integration.hpp's layout) as one of the reduced.
    Eigen::VectorXd reduce_state(const Eigen::VectorXd& state) const;
    /// The reduced system's response as the original's: every DOF, the state and the
    /// outputs of `options`. Massless DOFs come from the samples of the final period (their
    /// y_max is the largest sample, their velocity a central difference of the samples; their
    /// first harmonic uses the exact ones of the massive DOFs and the sampled friction force).
    void expand(PeriodicResponse& response, const TimeIntegrationOptions& options) const;

    /// The massless DOFs as linear functions of the reduced state: y_S = load cos(h w t) +
    /// from_massive y_R + from_sliders s, with the converted contacts' forces
    /// f_c = k_c (w^_c^T y_R - s_c) substituted (s: the reduced contacts' internal states).
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

private:
    Eigen::VectorXd massless_displacement(const Eigen::VectorXd& y_r, const Eigen::VectorXd& f, double cosine) const;

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
