// hbfriction — polynomials in time of the event-exact solver (polynomial.hpp).
#include "polynomial.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hbf::detail::exact {

/// exp(a d) by scaling and squaring of its Taylor series (to rounding).
Eigen::MatrixXd taylor_exp(const Eigen::MatrixXd& a, double d) {
    const double norm = (a * d).cwiseAbs().colwise().sum().maxCoeff();
    int squarings = 0;
    double scale = d;
    while (norm * (scale / d) > 0.5 && squarings < 60) {
        scale *= 0.5;
        ++squarings;
    }
    const Eigen::MatrixXd as = a * scale;
    Eigen::MatrixXd term = Eigen::MatrixXd::Identity(a.rows(), a.cols());
    Eigen::MatrixXd sum = term;
    for (int k = 1; k < 40; ++k) {
        term = as * term / static_cast<double>(k);
        sum += term;
        if (term.cwiseAbs().maxCoeff() <= 1e-18 * sum.cwiseAbs().maxCoeff()) break;
    }
    for (int k = 0; k < squarings; ++k) sum = sum * sum;
    return sum;
}

/// Taylor coefficients of the flow over one step: u_k = (a h)^k z / k!, until they vanish.
/// `buffer` keeps its capacity between steps; returns the number of columns used.
Eigen::Index step_polynomial(const Eigen::MatrixXd& a, const Eigen::VectorXd& z, double h, Eigen::MatrixXd& buffer) {
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
double refine_root(const Eigen::RowVectorXd& c, double lo, double hi) {
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
double first_root(const Eigen::RowVectorXd& c, double s_end, double eta) {
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
const std::array<std::pair<double, double>, 10>& gauss_legendre() {
    static const std::array<std::pair<double, double>, 10> rule = [] {
        std::array<std::pair<double, double>, 10> r{};
        const int n = 10;
        for (int i = 0; i < n; ++i) {
            double x = std::cos(pi * (i + 0.75) / (n + 0.5));
            double dp = 0.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = x;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (x * p1 - p0) / (x * x - 1.0);
                const double dx = p1 / dp;
                x -= dx;
                if (std::abs(dx) < 1e-16) break;
            }
            r[static_cast<std::size_t>(i)] = {0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp)};
        }
        return r;
    }();
    return rule;
}

}  // namespace hbf::detail::exact
