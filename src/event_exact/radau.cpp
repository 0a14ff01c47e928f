// hbfriction — the Radau IIA collocation tables (radau.hpp), computed in long double.
#include "event_exact/radau.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace hbf::detail::exact {

namespace {

using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;

/// P_s(x) - P_{s-1}(x) by the three-term recurrence.
long double radau_polynomial(int s, long double x) {
    long double p0 = 1.0L, p1 = x;
    if (s == 1) return p1 - p0;
    for (int k = 2; k <= s; ++k) {
        const long double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    return p1 - p0;
}

RadauTable make_table(int s) {
    // The roots in (-1, 1]: sign changes on a fine grid, then bisection; x = 1 is one of them.
    std::vector<long double> roots;
    const int grid = 4000 * s;
    long double x0 = -1.0L, f0 = radau_polynomial(s, x0);
    for (int k = 1; k <= grid; ++k) {
        const long double x1 = -1.0L + 2.0L * k / grid;
        const long double f1 = k == grid ? 0.0L : radau_polynomial(s, x1);
        if (k == grid) {
            roots.push_back(1.0L);
            break;
        }
        if ((f0 < 0) != (f1 < 0)) {
            long double lo = x0, hi = x1, flo = f0;
            for (int it = 0; it < 200; ++it) {
                const long double mid = 0.5L * (lo + hi), fm = radau_polynomial(s, mid);
                if ((fm < 0) == (flo < 0)) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            roots.push_back(0.5L * (lo + hi));
        }
        x0 = x1;
        f0 = f1;
    }
    if (static_cast<int>(roots.size()) != s) throw std::logic_error("radau_table: root count");
    std::vector<long double> c(static_cast<std::size_t>(s));
    for (int i = 0; i < s; ++i) c[static_cast<std::size_t>(i)] = 0.5L * (1.0L + roots[static_cast<std::size_t>(i)]);
    // Lagrange basis on the nodes in monomials: L = V^-1, V_ik = c_i^k.
    LongMatrix v(s, s);
    for (int i = 0; i < s; ++i)
        for (int k = 0; k < s; ++k) v(i, k) = std::pow(c[static_cast<std::size_t>(i)], static_cast<long double>(k));
    const LongMatrix l = v.fullPivLu().inverse();  // l(k, j): coefficient k of l_j
    RadauTable t;
    t.stages = s;
    t.c.resize(s);
    t.a.resize(s, s);
    LongMatrix a(s, s);
    for (int i = 0; i < s; ++i) {
        const long double ci = c[static_cast<std::size_t>(i)];
        t.c(i) = static_cast<double>(ci);
        for (int j = 0; j < s; ++j) {
            long double sum = 0.0L;
            for (int k = 0; k < s; ++k) sum += l(k, j) * std::pow(ci, static_cast<long double>(k + 1)) / (k + 1);
            a(i, j) = sum;
        }
    }
    t.a = a.cast<double>();
    LongMatrix w(s + 1, s + 1);
    for (int i = 0; i <= s; ++i) {
        const long double sigma = i == 0 ? 0.0L : c[static_cast<std::size_t>(i - 1)];
        for (int k = 0; k <= s; ++k) w(i, k) = k == 0 ? 1.0L : std::pow(sigma, static_cast<long double>(k));
    }
    t.to_monomial = w.fullPivLu().inverse().cast<double>();
    // The eigen-decomposition of A^-1 (in long double, then rounded): the stages' systems apart.
    const LongMatrix a_inverse = a.fullPivLu().inverse();
    const Eigen::EigenSolver<LongMatrix> eigen(a_inverse, true);
    if (eigen.info() != Eigen::Success) throw std::logic_error("radau_table: eigenvalues of A^-1");
    using LongComplex = Eigen::Matrix<std::complex<long double>, Eigen::Dynamic, Eigen::Dynamic>;
    const LongComplex vectors = eigen.eigenvectors();
    const LongComplex right = (LongComplex(vectors.inverse()) * a_inverse.cast<std::complex<long double>>()).transpose();
    t.lambda = eigen.eigenvalues().cast<std::complex<double>>();
    t.vectors = vectors.cast<std::complex<double>>();
    t.right = right.cast<std::complex<double>>();
    t.partner = Eigen::VectorXi::Constant(s, -1);
    for (int k = 0; k + 1 < s; ++k)
        if (t.lambda(k).imag() > 0.0 && std::abs(t.lambda(k + 1) - std::conj(t.lambda(k))) <= 1e-12 * std::abs(t.lambda(k))) {
            t.partner(k + 1) = k;
            ++k;
        }
    return t;
}

}  // namespace

const RadauTable& radau_table(int stages) {
    if (stages < 2 || stages > 12) throw std::invalid_argument("radau_table: stages 2..12");
    static std::mutex guard;
    static std::map<int, RadauTable> tables;
    const std::lock_guard<std::mutex> lock(guard);
    auto it = tables.find(stages);
    if (it == tables.end()) it = tables.emplace(stages, make_table(stages)).first;
    return it->second;
}

}  // namespace hbf::detail::exact
