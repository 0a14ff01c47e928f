// hbfriction — internal to event_exact: polynomials in time. Within a Taylor step every signal
// of the flow is a polynomial in s = (t - t0) / h; their evaluation, the step's Taylor
// coefficients, the matrix exponential, the roots of the guards and Gauss-Legendre quadrature.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <utility>

namespace hbf::detail::exact {

constexpr double pi = 3.14159265358979323846;

/// The polynomial c(0) + c(1) s + c(2) s^2 + ... at s (Horner), its derivative, and the vector
/// polynomial whose coefficients are the columns of u.
inline double horner(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 0; --k) p = p * s + c(k);
    return p;
}
inline double horner_derivative(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 1; --k) p = p * s + static_cast<double>(k) * c(k);
    return p;
}
inline Eigen::VectorXd evaluate(const Eigen::Ref<const Eigen::MatrixXd>& u, double s) {
    Eigen::VectorXd z = u.col(u.cols() - 1);
    for (Eigen::Index k = u.cols() - 2; k >= 0; --k) z = z * s + u.col(k);
    return z;
}

/// exp(a d) by scaling and squaring of its Taylor series (to rounding).
Eigen::MatrixXd taylor_exp(const Eigen::MatrixXd& a, double d);

/// Taylor coefficients of the flow over one step: u_k = (a h)^k z / k!, until they vanish.
/// `buffer` keeps its capacity between steps; returns the number of columns used.
Eigen::Index step_polynomial(const Eigen::MatrixXd& a, const Eigen::VectorXd& z, double h, Eigen::MatrixXd& buffer);

/// The root of the polynomial c in [lo, hi] where it changes sign (p(lo), p(hi) of opposite
/// signs or zero), by Newton safeguarded with bisection, to rounding.
double refine_root(const Eigen::RowVectorXd& c, double lo, double hi);

/// First root of the polynomial c on (0, s_end]: the first of 16 samples where it is below
/// -eta, or the first local minimum below -eta between two samples (a dip both samples miss:
/// a short phase near grazing), refined in the bracket before it. Returns -1 if none.
double first_root(const Eigen::RowVectorXd& c, double s_end, double eta);

/// Gauss-Legendre nodes and weights on [0, 1] (10 points: exact for degree 19).
const std::array<std::pair<double, double>, 10>& gauss_legendre();

}  // namespace hbf::detail::exact
