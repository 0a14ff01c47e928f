// hbfriction — internal to stability: the variational equation ds' = A(t) ds of one HB solution,
// Hill's matrix and its sorted multipliers (see stability.hpp).
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "hbf/continuation.hpp"
#include "hbf/fourier.hpp"
#include "hbf/contact_force.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/harmonic_balance.hpp"

namespace hbf::detail {

/// Value and tau-derivative (d/dtheta) of a coefficient vector at phase theta.
void at_phase(const Eigen::VectorXd& c, double theta, double& value, double& rate);

/// The eigenvalues of a (empty when the eigensolver fails).
Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& a);

/// The variational equation ds' = A(t) ds of one HB solution (see stability.hpp).
class Variational {
public:
    Variational(HarmonicBalance& hb, const Eigen::MatrixXd& minv, const Eigen::MatrixXd& w, const SolutionPoint& p);
    int size() const { return d_; }
    double omega() const { return omega_; }
    /// A(t) at phase theta = omega t.
    void matrix(double theta, Eigen::MatrixXd& a) const;
    /// Hill's matrix on the samples of `fourier` (all harmonics 0..H).
    Eigen::MatrixXd hill(Fourier& fourier) const;

private:
    const System& system_;
    double omega_;
    int n_, d_ = 0;
    std::vector<Eigen::VectorXd> q_, z_;
    std::vector<std::unique_ptr<BoundLaw>> laws_;  // each contact's law bound to it
    std::vector<int> state_index_;
    // Contact c's directions are the columns first_[c] .. + count_[c] - 1 of w_ (one, or m for
    // an element over several coordinates: BoundLaw::directions).
    std::vector<int> first_, count_;
    Eigen::MatrixXd base_, w_, mw_;
    mutable Eigen::VectorXd q_at_, v_at_, f_at_;
    mutable Eigen::MatrixXd fq_at_, fv_at_;
    /// Adds contact c's part of A at phase theta.
    void add_contact(int c, double theta, Eigen::MatrixXd& a) const;
    /// Contact c's relative displacements and velocities (count_[c] each) at phase theta.
    void motion(int c, double theta, Eigen::VectorXd& q, Eigen::VectorXd& v) const;
};

/// Hill's classical sorted selection: mu = exp(lambda T) of the d exponents with the smallest
/// |Im lambda|; empty when the matrix would exceed max_size rows or the eigensolver failed.
Eigen::VectorXcd sorted_hill(const Variational& v, Fourier& fourier, int max_size);

}  // namespace hbf::detail
