// hbfriction — polynomials in time of the event-exact solver (polynomial.hpp).
#include "event_exact/polynomial.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hbf::detail::exact {

Eigen::VectorXd balance(Eigen::MatrixXd& a) {
    const Eigen::Index n = a.rows();
    Eigen::VectorXd d = Eigen::VectorXd::Ones(n);
    for (int sweep = 0; sweep < 100; ++sweep) {
        bool done = true;
        for (Eigen::Index i = 0; i < n; ++i) {
            double c = a.col(i).cwiseAbs().sum() - std::abs(a(i, i));
            double r = a.row(i).cwiseAbs().sum() - std::abs(a(i, i));
            if (c == 0.0 || r == 0.0) continue;
            const double total = c + r;
            double f = 1.0;
            while (c < r / 2.0) {
                f *= 2.0;
                c *= 4.0;
            }
            while (c >= r * 2.0) {
                f /= 2.0;
                c /= 4.0;
            }
            if ((c + r) / f < 0.95 * total) {
                done = false;
                d(i) *= f;
                a.row(i) /= f;
                a.col(i) *= f;
            }
        }
        if (done) break;
    }
    return d;
}

Eigen::VectorXcd balanced_eigenvalues(Eigen::MatrixXd a) {
    balance(a);
    return Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
}

/// The fast modes of a (n x n, its last 3 states cos, sin, 1 of the forcing; nz = n - 3), the
/// slow flow's coordinates (ModeData) and the largest slow |eigenvalue|. The dynamic block az
/// is balanced first (d^-1 az d); its eigenvectors give right [d v; 0] and left
/// [w^T d^-1, w^T d^-1 B (lambda - Omega)^-1] (B: the forcing columns, Omega: their
/// rotation), normalised by G = W^T V. Returns false (no split) when no eigenvalue is fast,
/// an eigen-solve fails or its vectors do not pass the residual checks.
/// exp(a d) by scaling and squaring of its Taylor series (to rounding), on a balanced a: the
/// number of squarings follows the norm of a, which balancing brings down to the size of its
/// eigenvalues whatever the units (a mechanical a in raw units has entries K / M next to 1).
Eigen::MatrixXd taylor_exp(const Eigen::MatrixXd& given, double d) {
    Eigen::MatrixXd a = given;
    const Eigen::VectorXd balancing = balance(a);
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
    return balancing.asDiagonal() * sum * balancing.cwiseInverse().asDiagonal();
}

/// Taylor coefficients of the flow over one step: u_k = (a h)^k z / k!, until they vanish.
/// `buffer` keeps its capacity between steps; returns the number of columns used.

/// The root of the polynomial c in [lo, hi] where it changes sign (p(lo), p(hi) of opposite
/// signs or zero), by Newton safeguarded with bisection, to rounding.

/// First root of the polynomial c on (0, s_end]: the first of 16 samples where it is below
/// -eta, or the first local minimum below -eta between two samples (a dip both samples miss:
/// a short phase near grazing), refined in the bracket before it. Returns -1 if none.

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
