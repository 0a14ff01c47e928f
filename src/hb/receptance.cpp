// hbfriction — the linear structure per harmonic condensed onto the contacts (receptance.hpp).
#include "hbf/receptance.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/MatOp/SymShiftInvert.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "hbf/error.hpp"

namespace hbf {

namespace {
using Complex = std::complex<double>;
using SparseComplex = Eigen::SparseMatrix<Complex>;

/// a b + r c for real a (N x m) and c (N x n), complex b (m x n) and r, as real products: the
/// N-long work of the modal receptance without complex multiplications (which cost several
/// times more: most of the time of a 2000-DOF modal FRF went there).
Eigen::MatrixXcd real_product(const Eigen::MatrixXd& a, const Eigen::MatrixXcd& b, Complex r, const Eigen::MatrixXd& c) {
    Eigen::MatrixXcd out(a.rows(), b.cols());
    out.real() = a * b.real() + r.real() * c;
    out.imag() = a * b.imag() + r.imag() * c;
    return out;
}

/// A X for a sparse A, the sums in long double: a finite-element matrix times a smooth vector
/// (a mode) cancels to a small fraction of its terms (the modal damping phi^T C phi of a
/// stiffness-proportional C).
Eigen::MatrixXd precise_product(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixXd& x) {
    const Eigen::Index rows = a.rows(), columns = x.cols();
    std::vector<long double> sum(static_cast<std::size_t>(rows * columns), 0.0L);
    for (Eigen::Index j = 0; j < a.outerSize(); ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
            for (Eigen::Index c = 0; c < columns; ++c)
                sum[static_cast<std::size_t>(c * rows + it.row())] +=
                    static_cast<long double>(it.value()) * static_cast<long double>(x(j, c));
    Eigen::MatrixXd out(rows, columns);
    for (Eigen::Index c = 0; c < columns; ++c)
        for (Eigen::Index i = 0; i < rows; ++i) out(i, c) = static_cast<double>(sum[static_cast<std::size_t>(c * rows + i)]);
    return out;
}

/// A double-double number hi + lo (|lo| <= ulp(hi) / 2) and the error-free operations the
/// refinement's residual needs (Dekker, Knuth; the products by FMA).
struct DoubleDouble {
    double hi = 0.0, lo = 0.0;
};
DoubleDouble two_sum(double a, double b) {
    const double s = a + b, v = s - a;
    return {s, (a - (s - v)) + (b - v)};
}
DoubleDouble two_product(double a, double b) {
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}
/// a b for a double-double a, to a relative error of ~1e-32.
DoubleDouble product(const DoubleDouble& a, double b) {
    DoubleDouble p = two_product(a.hi, b);
    p.lo += a.lo * b;
    return two_sum(p.hi, p.lo);
}
DoubleDouble product(const DoubleDouble& a, const DoubleDouble& b) {
    DoubleDouble p = two_product(a.hi, b.hi);
    p.lo += a.hi * b.lo + a.lo * b.hi;
    return two_sum(p.hi, p.lo);
}
/// s += t.
void accumulate(DoubleDouble& s, const DoubleDouble& t) {
    DoubleDouble u = two_sum(s.hi, t.hi);
    u.lo += s.lo + t.lo;
    s = two_sum(u.hi, u.lo);
}

void require_shape(bool ok, const std::string& what, long rows, long cols, long expected_rows, long expected_cols) {
    if (!ok)
        throw InvalidInput(what + " is " + std::to_string(rows) + " x " + std::to_string(cols) +
                           ": allowed " + std::to_string(expected_rows) + " x " + std::to_string(expected_cols));
}
}  // namespace

Receptance::Receptance(Eigen::SparseMatrix<double> mass, Eigen::SparseMatrix<double> damping,
                       Eigen::SparseMatrix<double> stiffness, Eigen::MatrixXd directions, Eigen::VectorXd excitation,
                       Eigen::MatrixXd outputs)
    : mass_(std::move(mass)),
      damping_(std::move(damping)),
      stiffness_(std::move(stiffness)),
      directions_(std::move(directions)),
      outputs_(std::move(outputs)),
      excitation_(std::move(excitation)) {
    const long n = stiffness_.rows();
    require_shape(n > 0 && stiffness_.cols() == n, "stiffness K", n, stiffness_.cols(), std::max(1L, n), std::max(1L, n));
    require_shape(mass_.rows() == n && mass_.cols() == n, "mass M", mass_.rows(), mass_.cols(), n, n);
    require_shape(damping_.rows() == n && damping_.cols() == n, "damping C", damping_.rows(), damping_.cols(), n, n);
    require_shape(directions_.rows() == n, "contact directions W", directions_.rows(), directions_.cols(), n,
                  directions_.cols());
    require_shape(excitation_.size() == n, "excitation F", excitation_.size(), 1, n, 1);
    require_shape(outputs_.cols() == n, "outputs T", outputs_.rows(), outputs_.cols(), outputs_.rows(), n);
    auto finite = [](Eigen::SparseMatrix<double>& m) {  // the stored values only: never densified
        m.makeCompressed();
        return Eigen::Map<const Eigen::VectorXd>(m.valuePtr(), m.nonZeros()).allFinite();
    };
    if (!finite(mass_) || !finite(damping_) || !finite(stiffness_) || !directions_.allFinite() ||
        !excitation_.allFinite() || !outputs_.allFinite())
        throw InvalidInput("the structure's matrices and vectors must be finite (a NaN or infinity was given)");
    // The union pattern of K, M, C (every stored entry), and each matrix's values on it.
    std::vector<Eigen::Triplet<double>> entries;
    for (const Eigen::SparseMatrix<double>* m : {&stiffness_, &mass_, &damping_})
        for (int j = 0; j < m->outerSize(); ++j)
            for (Eigen::SparseMatrix<double>::InnerIterator it(*m, j); it; ++it)
                entries.emplace_back(static_cast<int>(it.row()), j, 1.0);
    Eigen::SparseMatrix<double> pattern(n, n);
    pattern.setFromTriplets(entries.begin(), entries.end());
    pattern.makeCompressed();
    auto values_on_pattern = [&](const Eigen::SparseMatrix<double>& m) {  // m is compressed (above)
        Eigen::VectorXd v = Eigen::VectorXd::Zero(pattern.nonZeros());
        for (int j = 0; j < n; ++j) {
            int p = pattern.outerIndexPtr()[j];
            for (int q = m.outerIndexPtr()[j]; q < m.outerIndexPtr()[j + 1]; ++q) {
                while (pattern.innerIndexPtr()[p] < m.innerIndexPtr()[q]) ++p;  // the row is in the pattern
                v(p) += m.valuePtr()[q];
            }
        }
        return v;
    };
    auto symmetric = [](const Eigen::SparseMatrix<double>& m) {
        const Eigen::SparseMatrix<double> difference = m - Eigen::SparseMatrix<double>(m.transpose());
        return Eigen::Map<const Eigen::VectorXd>(difference.valuePtr(), difference.nonZeros()).isZero(0.0);
    };
    symmetric_ = symmetric(stiffness_) && symmetric(mass_) && symmetric(damping_);
    k_values_ = values_on_pattern(stiffness_);
    m_values_ = values_on_pattern(mass_);
    c_values_ = values_on_pattern(damping_);
    c_values_given_ = c_values_;
    z_ = pattern.cast<Complex>();
    z_.makeCompressed();
    if (dofs() > dense_limit) {
        lu_ = std::make_unique<Eigen::SparseLU<SparseComplex>>();
        lu_->analyzePattern(z_);
    }
}

Eigen::MatrixXcd Receptance::precise_residual(int k, double omega, const Eigen::MatrixXcd& rhs,
                                              const Eigen::MatrixXcd& x) const {
    const DoubleDouble kw = two_product(static_cast<double>(k), omega);
    const DoubleDouble kw2 = product(kw, kw);
    return precise_combination(1.0, {-kw2.hi, -kw2.lo}, {kw.hi, kw.lo}, rhs, x);
}

Eigen::MatrixXcd Receptance::precise_derivative_product(int k, double omega, const Eigen::MatrixXcd& x) const {
    // dZ_k/domega x = (-2 k^2 omega M + i k C) x: C holds a multiple of K in Rayleigh damping,
    // and C x cancels as K x does (in double it erred by 1e-4 on the 10,000-DOF beam).
    const DoubleDouble m_coefficient = product(two_product(-2.0 * k, static_cast<double>(k)), omega);
    return -precise_combination(0.0, {m_coefficient.hi, m_coefficient.lo}, {static_cast<double>(k), 0.0},
                                Eigen::MatrixXcd::Zero(x.rows(), x.cols()), x);
}

Eigen::MatrixXcd Receptance::precise_combination(double k_coefficient, std::pair<double, double> m_pair,
                                                 std::pair<double, double> c_pair, const Eigen::MatrixXcd& rhs,
                                                 const Eigen::MatrixXcd& x) const {
    const DoubleDouble m_coefficient = {m_pair.first, m_pair.second}, c_coefficient = {c_pair.first, c_pair.second};
    // b - Z_k x to about twice the working precision: Z_k x cancels to |b| out of terms of size
    // |Z| |x|, 4e10 times larger on the 1000-element beam, where long double's 64-bit mantissa
    // left the refinement stalled at 1e-8 (G noisy at 2e-8 between frequencies 1e-9 apart).
    // Each entry's coefficient K_ij - (k w)^2 M_ij + i k w C_ij is formed in double-double from
    // the three matrices kept apart (k w and (k w)^2 exact too), so the refinement converges to
    // the solution of Z_k as given. Its products with x are error-free (FMA) and summed with a
    // compensated sum (Ogita, Rump & Oishi's Dot2: a running sum and one running error term):
    // the result is as if computed in double-double and rounded, error <= eps |r| + (n eps)^2
    // sum |Z_ij x_j|, with fewer operations than a double-double accumulator (12 % less time
    // for the 10,000-DOF beam's receptance).
    const Eigen::Index rows = rhs.rows(), columns = rhs.cols();
    Eigen::MatrixXd sum_re = rhs.real(), sum_im = rhs.imag();
    Eigen::MatrixXd err_re = Eigen::MatrixXd::Zero(rows, columns), err_im = err_re;
    const Eigen::MatrixXd x_re = x.real(), x_im = x.imag();
    // s += -(a.hi + a.lo) v into (s, e): the product error-free, the sum's error into e.
    auto subtract = [](double& s, double& e, const DoubleDouble& a, double v) {
        const double p = a.hi * v;
        const double product_error = std::fma(a.hi, v, -p) + a.lo * v;
        const double t = s - p, z = t - s;
        e += ((s - (t - z)) + (-p - z)) - product_error;
        s = t;
    };
    for (int j = 0; j < z_.outerSize(); ++j)
        for (int q = z_.outerIndexPtr()[j]; q < z_.outerIndexPtr()[j + 1]; ++q) {
            const Eigen::Index i = z_.innerIndexPtr()[q];
            // Z_ij = zr + i zi in double-double.
            DoubleDouble zr = {k_coefficient * k_values_(q), 0.0};
            if (m_values_(q) != 0.0) accumulate(zr, product(m_coefficient, m_values_(q)));
            const DoubleDouble zi = c_values_(q) != 0.0 ? product(c_coefficient, c_values_(q)) : DoubleDouble{};
            const DoubleDouble minus_zi = {-zi.hi, -zi.lo};
            for (Eigen::Index c = 0; c < columns; ++c) {
                const double xr = x_re(j, c), xi = x_im(j, c);
                // re: b - (zr xr - zi xi); im: b - (zr xi + zi xr)
                subtract(sum_re(i, c), err_re(i, c), zr, xr);
                subtract(sum_im(i, c), err_im(i, c), zr, xi);
                if (zi.hi != 0.0) {
                    subtract(sum_re(i, c), err_re(i, c), minus_zi, xi);
                    subtract(sum_im(i, c), err_im(i, c), zi, xr);
                }
            }
        }
    Eigen::MatrixXcd out(rows, columns);
    out.real() = sum_re + err_re;
    out.imag() = sum_im + err_im;
    return out;
}

bool Receptance::direct_solve(int k, double omega, const Eigen::MatrixXcd& rhs, Eigen::MatrixXcd& x,
                              Eigen::MatrixXcd& w_dx) {
    const double kw = k * omega;
    // Z_k on the union pattern (dZ_k/domega = -2 k^2 omega M + i k C is applied by
    // precise_derivative_product).
    {
        Eigen::Map<Eigen::VectorXcd> z(z_.valuePtr(), z_.nonZeros());
        z.real() = k_values_ - kw * kw * m_values_;
        z.imag() = kw * c_values_;
    }
    const SparseComplex& z = z_;
    // Small models use a dense LU (no sparse bookkeeping), large ones a sparse LU.
    // Iterative refinement with the residual b - Z x in double-double (precise_residual), Z's
    // terms K, (k w)^2 M, k w C kept apart: a finite-element K is badly conditioned (~N^4 for a
    // beam) and its entries reach 1e10, so Z rounded to double alone moves a lightly damped
    // resonance by ~1e-7 relative; refined, the solution is accurate to working precision
    // (mixed-precision refinement), and so is the condensed residual.
    auto refine = [&](const auto& solve, const Eigen::MatrixXcd& b, Eigen::MatrixXcd& y) {
        // Until the correction is below 1e-15 of y, or stops shrinking (by half a step), at most
        // 40 steps. Each step shrinks the error by about cond(Z) eps: 2 to 4 steps on the
        // 200- and 2000-DOF beams; on the 10,000-DOF beam 0.17 at the first harmonic near w = 30,
        // 20 steps (measured). Capped at 5 steps, G kept an error of 1e-7 there, which varied
        // between frequencies: the corrector needed 11 iterations a point, half its
        // corrections failed, and the default FRF did not finish in 90 minutes.
        y = solve(b);
        double previous = std::numeric_limits<double>::infinity();
        for (int step = 0; step < 40 && y.allFinite(); ++step) {
            const Eigen::MatrixXcd dy = solve(precise_residual(k, omega, b, y));
            // Largest moduli by their squares (std::abs of a complex calls hypot: 5 % of the time).
            const double size = std::sqrt(dy.cwiseAbs2().maxCoeff());
            if (size > previous) break;  // diverging (cond(Z) eps > 1): keep the better y
            y += dy;
            if (size > 0.5 * previous || size <= 1e-15 * std::sqrt(y.cwiseAbs2().maxCoeff())) break;
            previous = size;
        }
    };
    // The sensitivities W^T dx/domega = -W^T Z^-1 dZ x, dZ x formed in double-double (C x cancels
    // like K x when C holds a multiple of K). For a symmetric Z, W^T Z^-1 is the refined
    // solution's W columns transposed: -(Z^-1 W)^T dZ x, no further solve; otherwise the solve of
    // dZ x is refined as x is. Unrefined, it erred by cond(Z) eps: 0.17 on the 10,000-DOF beam at
    // k = 1, w = 30, and that dG/domega cost the continuation 5 to 20 corrector iterations a
    // point where 2 do, and a crawl at stick-slip kinks (250 points over 0.15 rad/s).
    auto solve_all = [&](const auto& solve) {
        refine(solve, rhs, x);
        if (!x.allFinite()) return;
        const Eigen::MatrixXcd dz_x = precise_derivative_product(k, omega, x);
        if (symmetric_) {
            w_dx = -x.leftCols(contacts()).transpose() * dz_x;
        } else {
            Eigen::MatrixXcd dx;
            refine(solve, Eigen::MatrixXcd(-dz_x), dx);
            w_dx = directions_.transpose().cast<Complex>() * dx;
        }
    };
    if (dofs() <= dense_limit) {
        const Eigen::PartialPivLU<Eigen::MatrixXcd> lu{Eigen::MatrixXcd(z)};
        solve_all([&](const Eigen::MatrixXcd& r) { return Eigen::MatrixXcd(lu.solve(r)); });
    } else {
        Eigen::SparseLU<SparseComplex>& lu = *lu_;
        lu.factorize(z);
        if (lu.info() != Eigen::Success) return false;
        solve_all([&](const Eigen::MatrixXcd& r) { return Eigen::MatrixXcd(lu.solve(r)); });
    }
    // A factorisation that succeeded on a numerically singular Z_k shows in the backward error
    // |Z x - b| / (|Z| |x| + |b|) (unit-free: FE stiffnesses reach 1e10, displacements 1e-6).
    if (!x.allFinite() || !w_dx.allFinite()) return false;
    const double z_size = Eigen::Map<const Eigen::VectorXcd>(z.valuePtr(), z.nonZeros()).cwiseAbs().maxCoeff();
    const double scale = z_size * x.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff();
    return (z * x - rhs).cwiseAbs().maxCoeff() <= 1e-8 * scale;
}

Eigen::VectorXcd Receptance::Harmonic::apply(const Eigen::VectorXcd& z) const {
    if (contact.size() > 0 || !factored) return contact * z;
    return factored->g_b * factored->lu.solve(z);
}

Eigen::VectorXcd Receptance::Harmonic::apply_omega(const Eigen::VectorXcd& z) const {
    if (contact.size() > 0 || !factored) return contact_omega * z;
    // G = G_B A^-1, A = I + S G_B: G' = G_B' A^-1 - G_B A^-1 (S' G_B + S G_B') A^-1.
    const Factored& f = *factored;
    const Eigen::VectorXcd y = f.lu.solve(z);
    const Eigen::VectorXcd inner = f.shift_omega.cwiseProduct(f.g_b * y) + f.shift.cwiseProduct(f.g_b_omega * y);
    return f.g_b_omega * y - f.g_b * f.lu.solve(inner);
}

void Receptance::Harmonic::materialize() {
    if (contact.size() > 0 || !factored) return;
    const Factored& f = *factored;
    const Eigen::MatrixXcd a_inverse = f.lu.inverse();
    contact = f.g_b * a_inverse;
    contact_omega = f.g_b_omega * a_inverse -
                    contact * (f.shift_omega.asDiagonal() * f.g_b + f.shift.asDiagonal() * f.g_b_omega) * a_inverse;
}

Receptance::Harmonic Receptance::solve(int k, double omega, bool load, bool solution, bool explicit_contact) {
    if (k < 0) throw InvalidInput("harmonic k = " + std::to_string(k) + " is out of range: allowed k >= 0");
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    if (modes() > 0) return solve_modal(k, omega, load, solution, explicit_contact);
    Harmonic h;
    h.k = k;
    h.omega = omega;
    auto singular = [&] {
        return "singular dynamic stiffness Z_k = K - (k w)^2 M + i k w C at harmonic k = " + std::to_string(k) +
               " at w = " + format_number(omega) +
               " (an undamped resonance hit exactly, or a rigid-body mode that no contact holds)";
    };
    // Columns: W, then F; one solve for all of them.
    const int nc = contacts();
    Eigen::MatrixXcd rhs(dofs(), nc + (load ? 1 : 0));
    rhs.leftCols(nc) = directions_.cast<Complex>();
    if (load) rhs.col(nc) = excitation_.cast<Complex>();
    Eigen::MatrixXcd x, w_dx;
    Eigen::VectorXcd pole;  // the F column's pole term where the contacts do not see it (below)
    if (!direct_solve(k, omega, rhs, x, w_dx)) {
        // An undamped resonance of a part of the structure that no contact sees, hit exactly
        // (two uncoupled oscillators, one with a contact: the contacts' shift regularises only
        // what they see). G_k and W^T Z_k^-1 F are smooth through it: Z_k^-1 = v v^T / mu(w) +
        // a regular part with W^T v = 0. Solved at w (1 -+ delta), the pole's term is odd in the
        // offset and cancels in the mean (error ~delta^2 of the regular part); a column the pole
        // does not touch changes by ~delta there, one it touches by ~1/delta. A pole in the W
        // columns, or one the contacts see, is a singular Z_k for the contacts: a status. A
        // pole in the F column the contacts do not see: the response of the DOFs it moves is
        // unbounded there (those entries of solution and output_load infinite), the contacts'
        // motion is not.
        const double delta = 1e-6;
        Eigen::MatrixXcd below, d_below, above, d_above;
        if (k == 0 || !direct_solve(k, omega * (1.0 - delta), rhs, below, d_below) ||
            !direct_solve(k, omega * (1.0 + delta), rhs, above, d_above)) {
            h.message = "numerically " + singular();
            return h;
        }
        x = 0.5 * (below + above);
        w_dx = 0.5 * (d_below + d_above);
        for (Eigen::Index c = 0; c < rhs.cols(); ++c) {
            const Eigen::VectorXcd jump = above.col(c) - below.col(c);
            const double size = jump.cwiseAbs().maxCoeff();
            if (!(size > 1e-3 * x.col(c).cwiseAbs().maxCoeff())) continue;  // no pole in this column
            const double seen = (directions_.transpose().cast<Complex>() * jump).cwiseAbs().maxCoeff();
            if (c < nc || !(seen <= 1e-8 * size * directions_.cwiseAbs().maxCoeff())) {
                h.message = "numerically " + singular();
                return h;
            }
            pole = jump;
        }
    }
    // Sensitivities (above): d(Z^-1 b)/domega = -Z^-1 (dZ) Z^-1 b.
    const Eigen::MatrixXcd wt = directions_.transpose().cast<Complex>();
    h.contact = wt * x.leftCols(nc);
    h.contact_omega = w_dx.leftCols(nc);
    h.output = outputs_.cast<Complex>() * x.leftCols(nc);
    if (load) {
        h.contact_load = wt * x.col(nc);
        h.contact_load_omega = w_dx.col(nc);
        h.output_load = outputs_.cast<Complex>() * x.col(nc);
        if (pole.size() > 0) {
            const Complex infinity(std::numeric_limits<double>::infinity(), 0.0);
            const double size = pole.cwiseAbs().maxCoeff();
            const Eigen::VectorXcd output_pole = outputs_.cast<Complex>() * pole;
            for (Eigen::Index i = 0; i < pole.size(); ++i)
                if (std::abs(pole(i)) > 1e-8 * size) x(i, nc) = infinity;
            for (Eigen::Index i = 0; i < output_pole.size(); ++i)
                if (std::abs(output_pole(i)) > 1e-8 * size * outputs_.row(i).cwiseAbs().maxCoeff())
                    h.output_load(i) = infinity;
        }
    }
    h.solution = std::move(x);
    h.ok = true;
    return h;
}

}  // namespace hbf

// ---- modal basis (receptance.hpp) ------------------------------------------------------------

namespace hbf {

void Receptance::set_mass_damping(double xi) {
    require_finite(xi, "xi", "artificial damping");
    mass_damping_ = xi;
    c_values_ = c_values_given_ - xi * m_values_;
    if (modal_.damping_given.size() > 0)
        modal_.damping = modal_.damping_given - Eigen::VectorXd::Constant(modal_.damping_given.size(), xi);
}

void Receptance::use_modes(int modes, const Eigen::VectorXd& contact_stiffness, const Eigen::VectorXd& contact_damping) {
    const int n = dofs(), nc = contacts();
    if (modes < 1) throw InvalidInput("modes = " + std::to_string(modes) + " is out of range: allowed >= 1");
    if (contact_stiffness.size() != nc || contact_damping.size() != nc)
        throw InvalidInput("modal receptance: one contact spring and damper per contact direction are needed");
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mass_ldlt(mass_);
    const double m_scale = mass_.rows() > 0 ? mass_.diagonal().cwiseAbs().maxCoeff() : 0.0;
    if (mass_ldlt.info() != Eigen::Success || !(mass_ldlt.vectorD().minCoeff() > 1e-13 * m_scale))
        throw InvalidInput("modes: the modal basis needs a positive definite mass matrix (massless DOFs: use modes = 0, "
                           "the direct solve)");
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> k_ldlt(stiffness_);
    const double k_scale = stiffness_.diagonal().cwiseAbs().maxCoeff();
    if (k_ldlt.info() != Eigen::Success || !(k_ldlt.vectorD().minCoeff() > 1e-13 * k_scale))
        throw InvalidInput("modes: the modal basis needs a positive definite stiffness matrix K (a rigid-body mode, "
                           "or a negative stiffness: use modes = 0, the direct solve)");
    const int m = std::min(modes, n);
    Eigen::VectorXd lambda;
    Eigen::MatrixXd phi;
    if (n <= 200 || m + 2 >= n) {
        // Dense, in the inverse form L^-1 M L^-T v = v / lambda (K = L L^T): the low modes are
        // the largest eigenvalues there, accurate to rounding (the direct form K phi = lambda M
        // phi errs by eps lambda_max absolutely: 4e-7 of lambda_1 on the beam).
        const Eigen::LLT<Eigen::MatrixXd> llt{Eigen::MatrixXd(stiffness_)};
        if (llt.info() != Eigen::Success) throw InvalidInput("modes: the dense Cholesky factorisation of K failed");
        const Eigen::MatrixXd l_inv_m = llt.matrixL().solve(Eigen::MatrixXd(mass_));
        const Eigen::MatrixXd a = llt.matrixL().solve(Eigen::MatrixXd(l_inv_m.transpose()));
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(0.5 * (a + a.transpose()));
        if (dense.info() != Eigen::Success) throw InvalidInput("modes: the dense eigensolver failed");
        lambda.resize(m);
        phi.resize(n, m);
        for (int j = 0; j < m; ++j) {  // ascending lambda = descending 1 / lambda
            const Eigen::Index col = n - 1 - j;
            lambda(j) = 1.0 / dense.eigenvalues()(col);
            phi.col(j) = llt.matrixU().solve(dense.eigenvectors().col(col));
        }
    } else {
        using Op = Spectra::SymShiftInvert<double, Eigen::Sparse, Eigen::Sparse>;
        using BOp = Spectra::SparseSymMatProd<double>;
        Op op(stiffness_, mass_);
        BOp bop(mass_);
        const int ncv = std::min(n, std::max(2 * m + 1, m + 20));
        Spectra::SymGEigsShiftSolver<Op, BOp, Spectra::GEigsMode::ShiftInvert> eigs(op, bop, m, ncv, 0.0);
        eigs.init();
        const Eigen::Index converged = eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12);
        if (eigs.info() != Spectra::CompInfo::Successful || converged < m)
            throw InvalidInput("modes: the sparse eigensolver (Spectra) found " + std::to_string(converged) + " of " +
                               std::to_string(m) + " modes");
        const Eigen::VectorXd values = eigs.eigenvalues();
        const Eigen::MatrixXd vectors = eigs.eigenvectors();
        std::vector<int> order(static_cast<std::size_t>(m));
        for (int j = 0; j < m; ++j) order[static_cast<std::size_t>(j)] = j;
        std::sort(order.begin(), order.end(), [&](int a, int b) { return values(a) < values(b); });
        lambda.resize(m);
        phi.resize(n, m);
        for (int j = 0; j < m; ++j) {
            lambda(j) = values(order[static_cast<std::size_t>(j)]);
            phi.col(j) = vectors.col(order[static_cast<std::size_t>(j)]);
        }
    }
    if (!(n <= 200 || m + 2 >= n)) {
        // Spectra's pairs carry the rounding of K's factorisation: on the 1000-element beam
        // (K_ii up to 8e12 N/m) the modal receptance erred by 1e-5 at the first harmonic and
        // 5e-3 at the 20th, whatever the number of modes. Two sweeps of subspace iteration with
        // Rayleigh-Ritz remove it without cancellation: Y = K^-1 M Phi (refined, the residual in
        // double-double), and since K Y = M Phi the projection Y^T K Y is formed as Y^T (M Phi),
        // a product of well-scaled terms; the small pencil (Y^T M Phi, Y^T M Y) gives the
        // pairs.
        for (int sweep = 0; sweep < 2; ++sweep) {
            const Eigen::MatrixXd mx = mass_ * phi;
            const Eigen::MatrixXcd mx_complex = mx.cast<Complex>();
            Eigen::MatrixXd y = k_ldlt.solve(mx);
            for (int step = 0; step < 2; ++step)
                y += k_ldlt.solve(Eigen::MatrixXd(precise_residual(0, 1.0, mx_complex, y.cast<Complex>()).real()));
            Eigen::MatrixXd kr = y.transpose() * mx, mr = y.transpose() * (mass_ * y);
            kr = 0.5 * (kr + kr.transpose()).eval();
            mr = 0.5 * (mr + mr.transpose()).eval();
            const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> small(kr, mr);
            if (small.info() != Eigen::Success || !(small.eigenvalues().minCoeff() > 0.0)) break;
            lambda = small.eigenvalues();  // ascending
            phi = y * small.eigenvectors();
        }
    }
    for (int j = 0; j < m; ++j) {  // M-normalised
        const double norm = std::sqrt(phi.col(j).dot(mass_ * phi.col(j)));
        phi.col(j) /= norm;
    }
    // C must be diagonal in the modal basis.
    const Eigen::MatrixXd c_modal = phi.transpose() * precise_product(damping_, phi);
    Eigen::VectorXd c = c_modal.diagonal();
    const double c_scale = c_modal.cwiseAbs().maxCoeff();
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j)
            if (i != j && std::abs(c_modal(i, j)) > 1e-8 * c_scale)
                throw InvalidInput("modes: the damping matrix C is not diagonal in the modal basis (modes " +
                                   std::to_string(i + 1) + " and " + std::to_string(j + 1) +
                                   " are coupled): allowed Rayleigh (a M + b K) or modal damping; use modes = 0, "
                                   "the direct solve");
    // The truncated modes enter through the static residual flexibility R. With Rayleigh
    // damping (c_j = a + b lambda_j, fitted on the computed modes) their receptance is
    // 1 / (lambda_j (1 + i k w b) + i k w a - (k w)^2) ~ R / (1 + i k w b): the stiffness-
    // proportional part damps them too (measured on the beam: 2e-7 of G at k = 1, 2e-5 at
    // k = 20 when left out). Other modal damping: R undamped.
    double rayleigh_b = 0.0;
    if (m >= 2 && c.cwiseAbs().maxCoeff() > 0.0) {
        Eigen::MatrixXd a(m, 2);
        a.col(0).setOnes();
        a.col(1) = lambda;
        const Eigen::Vector2d fit = a.colPivHouseholderQr().solve(c);
        if ((a * fit - c).cwiseAbs().maxCoeff() <= 1e-6 * c.cwiseAbs().maxCoeff()) rayleigh_b = fit(1);
    }
    Modal& md = modal_;
    md.residual_damping = rayleigh_b;
    md.lambda = lambda;
    md.damping_given = c;
    md.damping = c - Eigen::VectorXd::Constant(m, mass_damping_);
    md.phi = phi;
    md.p = phi.transpose() * directions_;
    md.p_load = phi.transpose() * excitation_;
    md.t_phi = outputs_ * phi;
    const Eigen::VectorXd inverse_lambda = lambda.cwiseInverse();
    // K^-1 [W, F] with two steps of iterative refinement, the residual b - K x in double-double
    // (precise_residual at k = 0: a finite-element K is badly conditioned).
    Eigen::MatrixXd rhs(n, nc + 1);
    rhs.leftCols(nc) = directions_;
    rhs.col(nc) = excitation_;
    Eigen::MatrixXd static_solution = k_ldlt.solve(rhs);
    const Eigen::MatrixXcd complex_rhs = rhs.cast<Complex>();
    for (int step = 0; step < 2; ++step)
        static_solution += k_ldlt.solve(
            Eigen::MatrixXd(precise_residual(0, 1.0, complex_rhs, static_solution.cast<Complex>()).real()));
    md.residual_w = static_solution.leftCols(nc) - phi * (inverse_lambda.asDiagonal() * md.p);
    md.residual_load = static_solution.col(nc) - phi * inverse_lambda.cwiseProduct(md.p_load);
    md.kappa = contact_stiffness;
    md.delta = contact_damping;
    md.phi_max = phi.cwiseAbs().colwise().maxCoeff().transpose();
    md.residual_w_max = md.residual_w.cwiseAbs().colwise().maxCoeff().transpose();
    md.residual_load_max = md.residual_load.cwiseAbs().maxCoeff();
    md.w_r_w = directions_.transpose() * md.residual_w;
    md.w_r_f = directions_.transpose() * md.residual_load;
    md.t_r_w = outputs_ * md.residual_w;
    md.t_r_f = outputs_ * md.residual_load;
}

Receptance::ModalTerms Receptance::modal_terms(int k, double omega) const {
    const Modal& md = modal_;
    const int nc = contacts();
    const auto m = md.lambda.size();
    const double kw = k * omega;
    ModalTerms t;
    t.d.resize(m);
    const double p_size = md.p.size() > 0 ? md.p.cwiseAbs().maxCoeff() : 0.0;
    for (Eigen::Index j = 0; j < m; ++j) {
        t.d(j) = 1.0 / Complex(md.lambda(j) - kw * kw, kw * md.damping(j));
        if (!std::isfinite(std::abs(t.d(j))) && md.p.row(j).cwiseAbs().maxCoeff() <= 1e-8 * p_size) {
            t.d(j) = 0.0;
            t.hidden.push_back(j);
        }
    }
    // The residual flexibility's factor 1 / (1 + i k w b) (see use_modes).
    t.r_factor = 1.0 / Complex(1.0, kw * md.residual_damping);
    // P^T diag(d) P + r W^T R W as two real products (P real: half the work of a complex one;
    // the n_c x m x n_c product dominates an interface of hundreds of nodes).
    t.g_b.resize(nc, nc);
    t.g_b.real() = md.p.transpose() * (t.d.real().asDiagonal() * md.p) + t.r_factor.real() * md.w_r_w;
    t.g_b.imag() = md.p.transpose() * (t.d.imag().asDiagonal() * md.p) + t.r_factor.imag() * md.w_r_w;
    t.u_b = md.p.transpose().cast<Complex>() * t.d.cwiseProduct(md.p_load.cast<Complex>()) +
            t.r_factor * md.w_r_f.cast<Complex>();
    t.shift.resize(nc);
    for (int c = 0; c < nc; ++c) t.shift(c) = Complex(md.kappa(c), kw * md.delta(c));
    return t;
}

Receptance::ModalResponse Receptance::modal_response_terms(int k, double omega, const Eigen::VectorXcd& lambda,
                                                          bool load) const {
    const Modal& md = modal_;
    const int nc = contacts();
    if (md.lambda.size() == 0) throw InvalidInput("the modal response needs the modal receptance (use_modes)");
    if (lambda.size() != nc) throw InvalidInput("the modal response needs one force per contact direction");
    ModalResponse r;
    const ModalTerms t = modal_terms(k, omega);
    if (!t.d.allFinite()) {  // a mode a contact sees, hit exactly (solve_modal takes the limit)
        r.regular = false;
        return r;
    }
    // A mode hit exactly that no contact sees, under the load: unbounded (solve_modal).
    for (Eigen::Index j : t.hidden)
        if (load && std::abs(md.p_load(j)) > 1e-8 * md.p_load.cwiseAbs().maxCoeff()) r.unbounded = true;
    const Eigen::MatrixXcd identity = Eigen::MatrixXcd::Identity(nc, nc);
    // Y = B^-1 (W g + F [load]) with g = -A^-1 lambda - S u: solve_modal's N-long solution
    // (B^-1 W A^-1 and B^-1 F - B^-1 W S u) applied to (-lambda, 1), without forming it.
    r.g = -Eigen::PartialPivLU<Eigen::MatrixXcd>(identity + t.shift.asDiagonal() * t.g_b).solve(lambda);
    if (load)
        r.g -= t.shift.cwiseProduct(Eigen::PartialPivLU<Eigen::MatrixXcd>(identity + t.g_b * t.shift.asDiagonal()).solve(t.u_b));
    r.eta = md.p.cast<Complex>() * r.g;
    if (load) r.eta += md.p_load.cast<Complex>();
    r.eta = t.d.cwiseProduct(r.eta);
    r.r_factor = t.r_factor;
    return r;
}

double Receptance::response_bound(int k, double omega, const Eigen::VectorXcd& lambda, bool load) const {
    const Modal& md = modal_;
    const ModalResponse r = modal_response_terms(k, omega, lambda, load);
    if (!r.regular) {  // the limit, as solve_modal takes it
        const double delta = 1e-6;
        return std::max(response_bound(k, omega * (1.0 - delta), lambda, load),
                        response_bound(k, omega * (1.0 + delta), lambda, load));
    }
    if (r.unbounded) return std::numeric_limits<double>::infinity();
    const double bound = md.phi_max.dot(r.eta.cwiseAbs()) + std::abs(r.r_factor) * (md.residual_w_max.dot(r.g.cwiseAbs()) +
                                                                                      (load ? md.residual_load_max : 0.0));
    return std::isfinite(bound) ? bound : std::numeric_limits<double>::infinity();
}

Eigen::VectorXcd Receptance::modal_response(int k, double omega, const Eigen::VectorXcd& lambda, bool load) const {
    const Modal& md = modal_;
    const ModalResponse r = modal_response_terms(k, omega, lambda, load);
    if (!r.regular || r.unbounded) {  // rare: solve_modal's N-long solution handles both
        const Harmonic h = solve_modal(k, omega, load, true);
        if (!h.ok) return Eigen::VectorXcd::Constant(dofs(), Complex(std::numeric_limits<double>::quiet_NaN(), 0.0));
        Eigen::VectorXcd y = -h.solution.leftCols(contacts()) * lambda;
        if (load) y += h.solution.col(contacts());
        return y;
    }
    // Phi eta + r (R W g + R F [load]), as real products (real_product's reason).
    Eigen::VectorXcd y(dofs());
    Eigen::VectorXd residual_re = md.residual_w * r.g.real(), residual_im = md.residual_w * r.g.imag();
    if (load) residual_re += md.residual_load;
    y.real() = md.phi * r.eta.real() + r.r_factor.real() * residual_re - r.r_factor.imag() * residual_im;
    y.imag() = md.phi * r.eta.imag() + r.r_factor.real() * residual_im + r.r_factor.imag() * residual_re;
    return y;
}

Receptance::Harmonic Receptance::solve_modal(int k, double omega, bool load, bool with_solution,
                                             bool explicit_contact) const {
    const Modal& md = modal_;
    const int nc = contacts();
    const auto m = md.lambda.size();
    Harmonic h;
    h.k = k;
    h.omega = omega;
    const ModalTerms t = modal_terms(k, omega);
    const Eigen::VectorXcd& d = t.d;
    const Eigen::VectorXcd& shift = t.shift;
    const Eigen::MatrixXcd& g_b = t.g_b;
    const Complex r_factor = t.r_factor;
    // Derivatives in omega: of d_j, of the residual's factor, of the shift.
    Eigen::VectorXcd dd(m);
    for (Eigen::Index j = 0; j < m; ++j) dd(j) = -d(j) * d(j) * Complex(-2.0 * k * k * omega, k * md.damping(j));
    // A hidden mode under the load: the DOFs and outputs it moves are unbounded (infinite).
    const auto loaded = [&](Eigen::Index j) {
        return std::abs(md.p_load(j)) > 1e-8 * md.p_load.cwiseAbs().maxCoeff();
    };
    const Complex infinity(std::numeric_limits<double>::infinity(), 0.0);
    auto unbounded = [&](const Eigen::MatrixXd& shape, Eigen::VectorXcd& values) {
        for (Eigen::Index j : t.hidden) {
            if (!loaded(j) || shape.rows() == 0) continue;
            const double size = shape.col(j).cwiseAbs().maxCoeff();
            for (Eigen::Index i = 0; i < shape.rows(); ++i)
                if (std::abs(shape(i, j)) > 1e-8 * size) values(i) = infinity;
        }
    };
    const Complex r_factor_omega = -Complex(0.0, k * md.residual_damping) * r_factor * r_factor;
    auto singular = [&] {
        h.message = "singular dynamic stiffness at harmonic k = " + std::to_string(k) + " at w = " + format_number(omega) +
                    " (an undamped mode hit exactly by the modal receptance)";
        return h;
    };
    if (!d.allFinite()) {
        // An undamped mode a contact sees, hit exactly: the contacts' shift regularises it (Z_k +
        // W shift W^T is regular there, as in the direct solve), so everything solved here is
        // smooth through it; only the Woodbury form divides by the pole. The mean of w (1 -+
        // 1e-6) (an error ~1e-12 of the regular part; the offsets are never exact poles).
        const double delta = 1e-6;
        const Harmonic below = solve_modal(k, omega * (1.0 - delta), load, with_solution, true);
        const Harmonic above = solve_modal(k, omega * (1.0 + delta), load, with_solution, true);
        if (!below.ok || !above.ok) return singular();
        h = below;
        h.omega = omega;
        h.contact = 0.5 * (below.contact + above.contact);
        h.contact_omega = 0.5 * (below.contact_omega + above.contact_omega);
        h.contact_load = 0.5 * (below.contact_load + above.contact_load);
        h.contact_load_omega = 0.5 * (below.contact_load_omega + above.contact_load_omega);
        h.output = 0.5 * (below.output + above.output);
        h.output_load = 0.5 * (below.output_load + above.output_load);
        h.solution = 0.5 * (below.solution + above.solution);
        return h;
    }
    const Eigen::MatrixXcd pc = md.p.cast<Complex>();
    const Eigen::MatrixXcd dp = d.asDiagonal() * pc;
    Eigen::MatrixXcd g_b_omega(nc, nc);  // as g_b in modal_terms: two real products
    g_b_omega.real() = md.p.transpose() * (dd.real().asDiagonal() * md.p) + r_factor_omega.real() * md.w_r_w;
    g_b_omega.imag() = md.p.transpose() * (dd.imag().asDiagonal() * md.p) + r_factor_omega.imag() * md.w_r_w;
    Eigen::VectorXcd shift_omega(nc);
    for (int c = 0; c < nc; ++c) shift_omega(c) = Complex(0.0, k * md.delta(c));
    const Eigen::MatrixXcd identity = Eigen::MatrixXcd::Identity(nc, nc);
    auto factors = std::make_shared<Harmonic::Factored>();
    factors->lu.compute(identity + shift.asDiagonal() * g_b);
    const Eigen::PartialPivLU<Eigen::MatrixXcd>& a_lu = factors->lu;
    // A^-1 itself only where something needs it formed (G_k explicit, outputs, the N-long solution).
    const bool formed = explicit_contact || outputs() > 0 || with_solution;
    const Eigen::MatrixXcd a_inverse = formed ? Eigen::MatrixXcd(a_lu.inverse()) : Eigen::MatrixXcd();
    if (!a_inverse.allFinite() || !a_lu.matrixLU().allFinite()) return singular();
    if (explicit_contact) {
        h.contact = g_b * a_inverse;
        h.contact_omega = g_b_omega * a_inverse -
                          g_b * a_inverse * (shift_omega.asDiagonal() * g_b + shift.asDiagonal() * g_b_omega) * a_inverse;
    }
    const Eigen::MatrixXcd t_b_w = real_product(md.t_phi, dp, r_factor, md.t_r_w);
    h.output = outputs() > 0 ? Eigen::MatrixXcd(t_b_w * a_inverse) : Eigen::MatrixXcd(0, nc);
    Eigen::VectorXcd u;
    if (load) {
        const Eigen::VectorXcd dpl = d.cwiseProduct(md.p_load.cast<Complex>());
        const Eigen::VectorXcd u_b_omega =
            pc.transpose() * dd.cwiseProduct(md.p_load.cast<Complex>()) + r_factor_omega * md.w_r_f.cast<Complex>();
        // (I + G_B S)^-1 v = v - G_B A^-1 (S v) (push-through): no second LU.
        auto b_solve = [&](const Eigen::VectorXcd& v) -> Eigen::VectorXcd {
            return v - g_b * a_lu.solve(Eigen::VectorXcd(shift.cwiseProduct(v)));
        };
        u = b_solve(t.u_b);
        h.contact_load = u;
        h.contact_load_omega =
            b_solve(Eigen::VectorXcd(u_b_omega - g_b_omega * shift.cwiseProduct(u) - g_b * shift_omega.cwiseProduct(u)));
        const Eigen::VectorXcd t_b_f = real_product(md.t_phi, dpl, r_factor, md.t_r_f);
        h.output_load = t_b_f - t_b_w * (shift.asDiagonal() * u);
        if (!u.allFinite() || !h.contact_load_omega.allFinite()) return singular();
        unbounded(md.t_phi, h.output_load);
    }
    if (with_solution) {
        const Eigen::MatrixXcd b_w = real_product(md.phi, dp, r_factor, md.residual_w);
        h.solution.resize(dofs(), nc + (load ? 1 : 0));
        h.solution.leftCols(nc) = b_w * a_inverse;
        if (load) {
            const Eigen::VectorXcd b_f =
                real_product(md.phi, d.cwiseProduct(md.p_load.cast<Complex>()), r_factor, md.residual_load);
            h.solution.col(nc) = b_f - b_w * (shift.asDiagonal() * u);
            Eigen::VectorXcd column = h.solution.col(nc);
            unbounded(md.phi, column);
            h.solution.col(nc) = column;
        }
    }
    if (!explicit_contact) {
        factors->g_b = g_b;
        factors->g_b_omega = g_b_omega;
        factors->shift = shift;
        factors->shift_omega = shift_omega;
        h.ok = g_b.allFinite() && g_b_omega.allFinite();
        h.factored = std::move(factors);
    } else {
        h.ok = h.contact.allFinite() && h.contact_omega.allFinite();
    }
    if (!h.ok) return singular();
    return h;
}

}  // namespace hbf
