// hbfriction — internal to event_exact: polynomials in time. Within a Taylor step every signal
// of the flow is a polynomial in s = (t - t0) / h; their evaluation, the step's Taylor
// coefficients, the matrix exponential, the roots of the guards and Gauss-Legendre quadrature.
// The functions the flow calls every step are defined here, inline: out of line (in another
// translation unit than the engine) the exact polish of the default FRF took 8 % longer.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
inline Eigen::Index step_polynomial(const Eigen::MatrixXd& a, const Eigen::VectorXd& z, double h, Eigen::MatrixXd& buffer) {
    constexpr int max_terms = 80;
    if (buffer.rows() != z.size() || buffer.cols() != max_terms) buffer.resize(z.size(), max_terms);
    buffer.col(0) = z;
    const double scale = std::max(1.0, z.cwiseAbs().maxCoeff());
    Eigen::Index used = 1;
    double previous = std::numeric_limits<double>::infinity();
    for (int k = 1; k < max_terms; ++k) {
        buffer.col(k).noalias() = a * buffer.col(k - 1);
        buffer.col(k) *= h / static_cast<double>(k);
        used = k + 1;
        const double size = buffer.col(k).cwiseAbs().maxCoeff();
        if (k >= 4 && size <= 1e-18 * scale && previous <= 1e-16 * scale) break;
        previous = size;
    }
    return used;
}

/// The root of the polynomial c in [lo, hi] where it changes sign (p(lo), p(hi) of opposite
/// signs or zero), by Newton safeguarded with bisection, to rounding.
inline double refine_root(const Eigen::RowVectorXd& c, double lo, double hi) {
    double p_lo = horner(c, lo);
    if (p_lo == 0.0) return lo;
    double x = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
        const double px = horner(c, x);
        if (px == 0.0) return x;
        if ((px > 0.0) == (p_lo > 0.0)) {
            lo = x;
            p_lo = px;
        } else {
            hi = x;
        }
        if (hi - lo <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(hi))) break;
        const double dp = horner_derivative(c, x);
        double next = dp != 0.0 ? x - px / dp : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool tiny = std::abs(next - x) <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x));
        x = next;
        if (tiny) break;
    }
    return std::min(std::max(x, lo), hi);
}

/// First root of the polynomial c on (0, s_end]: the first of 16 samples where it is below
/// -eta, or the first local minimum below -eta between two samples (a dip both samples miss:
/// a short phase near grazing), refined in the bracket before it. Returns -1 if none.
inline double first_root(const Eigen::RowVectorXd& c, double s_end, double eta) {
    constexpr int samples = 16;
    Eigen::RowVectorXd d(std::max<Eigen::Index>(1, c.size() - 1));
    d.setZero();
    for (Eigen::Index k = 1; k < c.size(); ++k) d(k - 1) = static_cast<double>(k) * c(k);
    double lo = 0.0, p_lo = c(0), d_lo = d(0);
    for (int j = 1; j <= samples; ++j) {
        const double s = s_end * j / samples;
        const double p = horner(c, s), dp = horner(d, s);
        if (p < -eta) {
            if (p_lo > 0.0) return refine_root(c, lo, s);
            if (j > 1) return lo;
            // Zero at the start (a slip or a stick that begins at the edge of its limit) and
            // negative at the first sample: a phase shorter than one sample, if the guard is
            // positive in between. Its end is the root after the first positive fine sample.
            constexpr int fine = 64;
            for (int k = 1; k < fine; ++k) {
                const double x = s * k / fine;
                if (horner(c, x) > 0.0) return refine_root(c, x, s);
            }
            return lo;
        }
        if (d_lo < 0.0 && dp > 0.0 && p_lo > 0.0) {  // a minimum between the samples
            const double bottom = refine_root(d, lo, s);
            if (horner(c, bottom) < -eta) return refine_root(c, lo, bottom);
        }
        lo = s;
        p_lo = p;
        d_lo = dp;
    }
    return -1.0;
}

/// Gauss-Legendre nodes and weights on [0, 1] (10 points: exact for degree 19).
const std::array<std::pair<double, double>, 10>& gauss_legendre();

}  // namespace hbf::detail::exact
