// hbfriction — the linear structure per harmonic condensed onto the contacts (receptance.hpp):
// the direct solve (a sparse or dense LU of Z_k) with its refinement in extended precision.
#include "hbf/receptance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "hbf/error.hpp"

namespace hbf {

namespace {
using Complex = std::complex<double>;
using SparseComplex = Eigen::SparseMatrix<Complex>;

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
    // Dense LU for small models and for dense matrices of moderate size (a reduced model's
    // are full: the sparse LU of a full matrix is several times slower than the dense one).
    const double size = dofs();
    dense_ = dofs() <= dense_limit ||
             (static_cast<double>(z_.nonZeros()) > 0.25 * size * size && dofs() <= dense_fill_limit);
    if (!dense_) {
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
    // the solution of Z_k as given. Its products with x are error-free and summed with a
    // compensated sum (Ogita, Rump & Oishi's Dot2: a running sum and one running error term):
    // the result is as if computed in double-double and rounded, error <= eps |r| + (n eps)^2
    // sum |Z_ij x_j|. The products are Dekker's (Veltkamp splits, no FMA call), and the
    // columns are the innermost, contiguous loop (x and the sums transposed) in blocks that
    // stay in cache: a reduced model's dense K times a thousand columns is then a streamed,
    // vectorised loop.
    const Eigen::Index rows = rhs.rows(), columns = rhs.cols();
    struct Entry {
        Eigen::Index i, j;
        DoubleDouble a;     // the coefficient
        double head, tail;  // a.hi = head + tail, each of at most 26 significant bits
    };
    auto entry = [](Eigen::Index i, Eigen::Index j, const DoubleDouble& a) {
        const double t = 134217729.0 * a.hi, head = t - (t - a.hi);  // 2^27 + 1
        return Entry{i, j, a, head, a.hi - head};
    };
    std::vector<Entry> real_part, imaginary_part;  // of Z_ij
    for (int j = 0; j < z_.outerSize(); ++j)
        for (int q = z_.outerIndexPtr()[j]; q < z_.outerIndexPtr()[j + 1]; ++q) {
            const Eigen::Index i = z_.innerIndexPtr()[q];
            DoubleDouble zr = {k_coefficient * k_values_(q), 0.0};
            if (m_values_(q) != 0.0) accumulate(zr, product(m_coefficient, m_values_(q)));
            if (zr.hi != 0.0) real_part.push_back(entry(i, j, zr));
            if (c_values_(q) != 0.0) {
                const DoubleDouble zi = product(c_coefficient, c_values_(q));
                if (zi.hi != 0.0) imaginary_part.push_back(entry(i, j, zi));
            }
        }
    // Transposed (columns x rows): a column block of one row is contiguous.
    const Eigen::MatrixXd x_re = x.real().transpose(), x_im = x.imag().transpose();
    const bool real_x = (x_im.array() == 0.0).all();
    Eigen::MatrixXd sum_re = rhs.real().transpose(), sum_im = rhs.imag().transpose();
    Eigen::MatrixXd err_re = Eigen::MatrixXd::Zero(columns, rows), err_im = err_re;
    // sum(block, e.i) -= sign e.a x(block, e.j) for every entry, block by block of columns.
    auto subtract = [&](const std::vector<Entry>& entries, double sign, const Eigen::MatrixXd& v, Eigen::MatrixXd& sum,
                        Eigen::MatrixXd& err, Eigen::Index first, Eigen::Index count) {
        for (const Entry& e : entries) {
            const double hi = sign * e.a.hi, lo = sign * e.a.lo, head = sign * e.head, tail = sign * e.tail;
            const double* vj = v.data() + e.j * columns + first;
            double* s = sum.data() + e.i * columns + first;
            double* r = err.data() + e.i * columns + first;
            for (Eigen::Index c = 0; c < count; ++c) {
                const double value = vj[c];
                const double t = 134217729.0 * value, value_head = t - (t - value), value_tail = value - value_head;
                const double p = hi * value;
                const double product_error =
                    (((head * value_head - p) + head * value_tail + tail * value_head) + tail * value_tail) + lo * value;
                const double u = s[c] - p, z = u - s[c];
                r[c] += ((s[c] - (u - z)) + (-p - z)) - product_error;
                s[c] = u;
            }
        }
    };
    constexpr Eigen::Index block = 64;
    for (Eigen::Index first = 0; first < columns; first += block) {
        const Eigen::Index count = std::min(block, columns - first);
        // re: b - (zr xr - zi xi); im: b - (zr xi + zi xr)
        subtract(real_part, 1.0, x_re, sum_re, err_re, first, count);
        subtract(imaginary_part, 1.0, x_re, sum_im, err_im, first, count);
        if (real_x) continue;
        subtract(real_part, 1.0, x_im, sum_im, err_im, first, count);
        subtract(imaginary_part, -1.0, x_im, sum_re, err_re, first, count);
    }
    Eigen::MatrixXcd out(rows, columns);
    out.real() = (sum_re + err_re).transpose();
    out.imag() = (sum_im + err_im).transpose();
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
    if (!cyclic_.empty()) {
        // A sector: the own DOFs' equations T^H Z T u = T^H b, x = T u; refined by the same
        // residual b - Z x, whose folded part T^H (b - Z x) is what the next solve sees.
        const SparseComplex t = cyclic_basis(k), th = t.adjoint();
        const SparseComplex own = th * z * t;
        if (dense_) {
            const Eigen::PartialPivLU<Eigen::MatrixXcd> lu{Eigen::MatrixXcd(own)};
            solve_all([&](const Eigen::MatrixXcd& r) { return Eigen::MatrixXcd(t * Eigen::MatrixXcd(lu.solve(th * r))); });
        } else {
            Eigen::SparseLU<SparseComplex> lu;
            lu.analyzePattern(own);
            lu.factorize(own);
            if (lu.info() != Eigen::Success) return false;
            solve_all([&](const Eigen::MatrixXcd& r) {
                return Eigen::MatrixXcd(t * Eigen::MatrixXcd(lu.solve(Eigen::MatrixXcd(th * r))));
            });
        }
        if (!x.allFinite() || !w_dx.allFinite()) return false;
        const double z_size = Eigen::Map<const Eigen::VectorXcd>(z.valuePtr(), z.nonZeros()).cwiseAbs().maxCoeff();
        const double scale = z_size * x.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff();
        return (th * (z * x - rhs)).cwiseAbs().maxCoeff() <= 1e-8 * scale;
    }
    if (dense_) {
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

void Receptance::set_cyclic(std::vector<std::pair<int, int>> neighbours, double phase) {
    if (modes() > 0) throw InvalidInput("the modal receptance does not take a sector model (cyclic symmetry): allowed modes = 0");
    for (const auto& [d, m] : neighbours)
        if (d < 0 || d >= dofs() || m < 0 || m >= dofs() || d == m)
            throw InvalidInput("cyclic symmetry: the pair (" + std::to_string(d + 1) + ", " + std::to_string(m + 1) +
                               ") names a DOF outside the structure: allowed 1.." + std::to_string(dofs()));
    cyclic_ = std::move(neighbours);
    cyclic_phase_ = phase;
    symmetric_ = cyclic_.empty() && symmetric_;  // T_k^H Z_k T_k is Hermitian-structured, not symmetric
}

Receptance::SparseComplex Receptance::cyclic_basis(int k) const {
    std::vector<int> column(static_cast<std::size_t>(dofs()), 0);
    for (const auto& pair : cyclic_) column[static_cast<std::size_t>(pair.first)] = -1;
    int own = 0;
    for (int& c : column) c = c < 0 ? -1 : own++;
    std::vector<Eigen::Triplet<Complex>> entries;
    for (int i = 0; i < dofs(); ++i)
        if (column[static_cast<std::size_t>(i)] >= 0) entries.emplace_back(i, column[static_cast<std::size_t>(i)], 1.0);
    const Complex turn = std::polar(1.0, -k * cyclic_phase_);
    for (const auto& [d, m] : cyclic_) entries.emplace_back(d, column[static_cast<std::size_t>(m)], turn);
    SparseComplex t(dofs(), own);
    t.setFromTriplets(entries.begin(), entries.end());
    return t;
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
