// Shared helpers for the tests: independent reference computations and process running.
#pragma once

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <algorithm>
#include <complex>
#include <string>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::test {

/// Steady-state complex amplitudes of the absorber when its contact is replaced by a linear
/// spring k and damper c between the masses, solved with Eigen on the System matrices
/// (independent of the closed forms).
inline Eigen::VectorXcd absorber_with_linear_contact(const AbsorberParameters& p, double omega,
                                                    double k, double c) {
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    const Eigen::VectorXd w = s.contact_direction(s.contacts[0]);
    return linear_response(Eigen::MatrixXd(s.mass), Eigen::MatrixXd(s.damping) + c * w * w.transpose(),
                           Eigen::MatrixXd(s.stiffness) + k * w * w.transpose(), s.excitation, omega);
}

inline double relative_difference(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}
inline double relative_difference(std::complex<double> a, std::complex<double> b) {
    return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

/// An undamped structure (M, K, force amplitude F) with one exact Coulomb contact of limit
/// `limit` from DOF `dof` (0-based) to the ground.
inline System grounded_coulomb(const Eigen::MatrixXd& m, const Eigen::MatrixXd& k, const Eigen::VectorXd& f, int dof,
                               double limit) {
    System s;
    s.mass = sparse(m);
    s.damping = SparseMatrix(m.rows(), m.cols());
    s.stiffness = sparse(k);
    s.excitation = f;
    Contact c;
    c.dof = dof;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = limit;
    s.contacts.push_back(c);
    return s;
}

/// Den Hartog's forced oscillator u'' + u + rho sign(u') = cos(eta t): unit mass, stiffness and
/// force, exact Coulomb friction rho to the ground, no viscous damping.
inline System den_hartog_oscillator(double rho) {
    const Eigen::MatrixXd one = Eigen::MatrixXd::Identity(1, 1);
    return grounded_coulomb(one, one, Eigen::VectorXd::Ones(1), 0, rho);
}

/// Central differences (step h) of the HB residual at (x, omega): dR/dX in `fd`, dR/domega in
/// `fd_omega`, to check the exact Jacobians against.
inline void central_differences(hbf::HarmonicBalance& hb, const Eigen::VectorXd& x, double omega, Eigen::MatrixXd& fd,
                                Eigen::VectorXd& fd_omega, double h = 1e-6) {
    Eigen::VectorXd rp, rm;
    fd.resize(x.size(), x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
        Eigen::VectorXd xp = x, xm = x;
        xp(k) += h;
        xm(k) -= h;
        hb.evaluate(xp, omega, rp);
        hb.evaluate(xm, omega, rm);
        fd.col(k) = (rp - rm) / (2 * h);
    }
    hb.evaluate(x, omega + h, rp);
    hb.evaluate(x, omega - h, rm);
    fd_omega = (rp - rm) / (2 * h);
}

/// Tight CVODE settings for references: rtol 1e-12, atol 1e-14, steady-tol 1e-11.
inline TimeIntegrationOptions tight_time_integration() {
    TimeIntegrationOptions o;
    o.relative_tolerance = 1e-12;
    o.absolute_tolerance = 1e-14;
    o.steady_tolerance = 1e-11;
    return o;
}

/// Harmonic balance's start from an integrated orbit (condensed, no state signals): its
/// relative displacements along `directions` (N x signals), on the H harmonics of `hb`.
inline Eigen::VectorXd from_orbit(HarmonicBalance& hb, const PeriodicResponse& orbit, const Eigen::MatrixXd& directions) {
    Fourier fourier(hb.harmonics(), static_cast<int>(orbit.time.size()));
    Eigen::VectorXd x(hb.unknowns()), coefficients(fourier.size());
    for (Eigen::Index a = 0; a < directions.cols(); ++a) {
        fourier.to_coefficients(orbit.displacement * directions.col(a), coefficients);
        x.segment(a * hb.coefficients(), hb.coefficients()) = coefficients;
    }
    return x;
}

}  // namespace hbf::test

namespace hbf::test {

/// 1-DOF oscillator y'' + c y' + y + f = F cos(omega t) with one Dahl contact to ground
/// (friction limit F_c, bristle stiffness sigma0): stiffness 1 + sigma0 in stick, 1 in slip.
inline System dahl_oscillator(double sigma0, double friction_limit, double force, double damping) {
    System s;
    s.mass = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.damping = sparse(Eigen::MatrixXd::Constant(1, 1, damping));
    s.stiffness = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.excitation = Eigen::VectorXd::Constant(1, force);
    Contact contact;
    contact.dof = 0;
    contact.law = FrictionLaw::dahl;
    contact.friction_limit = friction_limit;
    contact.stiffness = sigma0;
    s.contacts.push_back(contact);
    return s;
}

/// A mass on a spring k1 (damper c) and, behind a spring k_t, a massless DOF held by exact
/// Coulomb friction F_c to the ground: exactly a Jenkins element (k_t, F_c) on the mass.
inline System massless_contact(double kt, double limit) {
    Eigen::Matrix2d k;
    k << 1.0 + kt, -kt, -kt, kt;
    System s;
    s.mass = sparse(Eigen::Vector2d(1.0, 0.0).asDiagonal());
    s.stiffness = sparse(k);
    s.damping = sparse(Eigen::Vector2d(0.05, 0.0).asDiagonal());
    s.excitation = Eigen::Vector2d(1.0, 0.0);
    Contact c;
    c.dof = 1;
    c.law = FrictionLaw::coulomb;
    c.friction_limit = limit;
    s.contacts = {c};
    return s;
}

inline System jenkins_equivalent(double kt, double limit) {
    System s;
    s.mass = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.stiffness = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.damping = sparse(Eigen::MatrixXd::Constant(1, 1, 0.05));
    s.excitation = Eigen::VectorXd::Ones(1);
    Contact c;
    c.dof = 0;
    c.law = FrictionLaw::jenkins;
    c.stiffness = kt;
    c.friction_limit = limit;
    s.contacts = {c};
    return s;
}

/// 4 DOFs, DOF 4 massless, damped; a Dahl contact between DOFs 1 and 2 and an exact Coulomb
/// contact along the direction (0, 0.3, -0.5, 1) (force_direction).
inline System four_dofs() {
    Eigen::MatrixXd k(4, 4);
    k << 3, -1, 0, 0, -1, 2.5, -1, 0, 0, -1, 2, -0.5, 0, 0, -0.5, 1.5;
    System s;
    s.mass = sparse(Eigen::Vector4d(1.0, 0.5, 0.8, 0.0).asDiagonal());
    s.stiffness = sparse(k);
    s.damping = 0.02 * s.stiffness;
    s.excitation = Eigen::Vector4d(1.0, 0.0, 0.2, 0.0);
    Contact dahl;
    dahl.dof = 0;
    dahl.other_dof = 1;
    dahl.law = FrictionLaw::dahl;
    dahl.friction_limit = 0.3;
    dahl.stiffness = 2.0;
    Contact coulomb;
    coulomb.direction = Eigen::Vector4d(0.0, 0.3, -0.5, 1.0);
    coulomb.law = FrictionLaw::coulomb;
    coulomb.friction_limit = 0.2;
    s.contacts = {dahl, coulomb};
    return s;
}

/// Largest entry of |A - B| relative to the largest entry of |B|.
inline double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

/// The branch of `hb` over [wmin, wmax] (required to complete) solved at each omega of
/// `omegas`, in order.
inline std::vector<SolutionPoint> sampled_points(HarmonicBalance& hb, const std::vector<double>& omegas, double wmin,
                                                 double wmax, double tolerance = 1e-12) {
    ContinuationOptions o;
    o.omega_start = wmin;
    o.omega_end = wmax;
    o.corrector.tolerance = tolerance;
    const BranchResult b = continue_branch(hb, o);
    INFO(b.summary());
    REQUIRE(b.status == ContinuationStatus::completed);
    std::vector<SolutionPoint> samples = sample_branch(hb, b, omegas, o.corrector);
    REQUIRE(samples.size() == omegas.size());
    return samples;
}

/// Every DOF's coefficients at each omega of `omegas`, from a branch over [wmin, wmax].
inline std::vector<Eigen::MatrixXd> sampled_dofs(const System& system, const HarmonicBalanceOptions& options,
                                                 const std::vector<double>& omegas, double wmin, double wmax,
                                                 double tolerance = 1e-12) {
    HarmonicBalance hb(system, options);
    REQUIRE((options.formulation == Formulation::automatic || hb.formulation() == options.formulation));
    std::vector<Eigen::MatrixXd> y;
    for (const SolutionPoint& p : sampled_points(hb, omegas, wmin, wmax, tolerance)) y.push_back(hb.dofs(p.x, p.omega));
    return y;
}

/// A law elastic contact on DOF 1 (k_t, k_n, mu, preload N_0) whose normal direction is `normal`.
inline Contact elastic_contact(double kt, double kn, double mu, double preload, const std::vector<double>& normal) {
    Contact c;
    c.law = FrictionLaw::elastic;
    c.dof = 0;
    c.stiffness = kt;
    c.values["normal_stiffness"] = kn;
    c.values["friction_coefficient"] = mu;
    c.values["preload"] = preload;
    c.lists["normal_direction"] = normal;
    return c;
}

/// A chain of n unit masses and springs (fixed at DOF 1's end, free at DOF n's, damping
/// 0.05 M + 0.02 K), forced at DOF n (1.0); DOF 1 on a law elastic contact whose normal
/// coordinate is DOF 2 (k_t 2, k_n 5, mu 0.3, preload 1): with n = 33 stick, slip and lift-off
/// at w = 0.3 to 1.5.
inline System elastic_chain(int n) {
    System s;
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
        k(i, i) = i + 1 < n ? 2.0 : 1.0;
        if (i + 1 < n) k(i, i + 1) = k(i + 1, i) = -1.0;
    }
    s.mass = sparse(Eigen::MatrixXd::Identity(n, n));
    s.stiffness = sparse(k);
    s.damping = sparse(0.05 * Eigen::MatrixXd::Identity(n, n) + 0.02 * k);
    s.excitation = Eigen::VectorXd::Zero(n);
    s.excitation(n - 1) = 1.0;
    std::vector<double> normal(static_cast<std::size_t>(n), 0.0);
    normal[1] = 1.0;
    s.contacts = {elastic_contact(2.0, 5.0, 0.3, 1.0, normal)};
    return s;
}

}  // namespace hbf::test
