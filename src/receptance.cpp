// hbfriction — the linear structure per harmonic condensed onto the contacts (receptance.hpp).
#include "hbf/receptance.hpp"

#include <cmath>
#include <vector>

#include "hbf/error.hpp"

namespace hbf {

namespace {
using Complex = std::complex<double>;
using SparseComplex = Eigen::SparseMatrix<Complex>;

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
    k_values_ = values_on_pattern(stiffness_);
    m_values_ = values_on_pattern(mass_);
    c_values_ = values_on_pattern(damping_);
    z_ = pattern.cast<Complex>();
    z_.makeCompressed();
    dz_ = z_;
    if (dofs() > dense_limit) {
        lu_ = std::make_unique<Eigen::SparseLU<SparseComplex>>();
        lu_->analyzePattern(z_);
    }
}

Eigen::MatrixXcd Receptance::precise_residual(int k, double omega, const Eigen::MatrixXcd& rhs,
                                              const Eigen::MatrixXcd& x) const {
    using Long = std::complex<long double>;
    const long double kw = static_cast<long double>(k) * static_cast<long double>(omega);
    const Eigen::Index columns = rhs.cols();
    std::vector<Long> r(static_cast<std::size_t>(rhs.size()));
    for (Eigen::Index c = 0; c < columns; ++c)
        for (Eigen::Index i = 0; i < rhs.rows(); ++i)
            r[static_cast<std::size_t>(c * rhs.rows() + i)] = Long(rhs(i, c).real(), rhs(i, c).imag());
    for (int j = 0; j < z_.outerSize(); ++j)
        for (int p = z_.outerIndexPtr()[j]; p < z_.outerIndexPtr()[j + 1]; ++p) {
            const int i = z_.innerIndexPtr()[p];
            const auto q = static_cast<Eigen::Index>(p);
            const Long z(static_cast<long double>(k_values_(q)) - kw * kw * static_cast<long double>(m_values_(q)),
                         kw * static_cast<long double>(c_values_(q)));
            for (Eigen::Index c = 0; c < columns; ++c)
                r[static_cast<std::size_t>(c * rhs.rows() + i)] -= z * Long(x(j, c).real(), x(j, c).imag());
        }
    Eigen::MatrixXcd out(rhs.rows(), columns);
    for (Eigen::Index c = 0; c < columns; ++c)
        for (Eigen::Index i = 0; i < rhs.rows(); ++i) {
            const Long v = r[static_cast<std::size_t>(c * rhs.rows() + i)];
            out(i, c) = Complex(static_cast<double>(v.real()), static_cast<double>(v.imag()));
        }
    return out;
}

Receptance::Harmonic Receptance::solve(int k, double omega, bool load) {
    if (k < 0) throw InvalidInput("harmonic k = " + std::to_string(k) + " is out of range: allowed k >= 0");
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    Harmonic h;
    h.k = k;
    h.omega = omega;
    const double kw = k * omega;
    // Z_k and dZ_k/domega = -2 k^2 omega M + i k C, on the union pattern.
    {
        Eigen::Map<Eigen::VectorXcd> z(z_.valuePtr(), z_.nonZeros()), dz(dz_.valuePtr(), dz_.nonZeros());
        z.real() = k_values_ - kw * kw * m_values_;
        z.imag() = kw * c_values_;
        dz.real() = -2.0 * k * k * omega * m_values_;
        dz.imag() = static_cast<double>(k) * c_values_;
    }
    const SparseComplex& z = z_;
    const SparseComplex& dz = dz_;
    auto singular = [&] {
        return "singular dynamic stiffness Z_k = K - (k w)^2 M + i k w C at harmonic k = " + std::to_string(k) +
               " at w = " + format_number(omega) +
               " (an undamped resonance hit exactly, or a rigid-body mode that no contact holds)";
    };
    // Columns: W, then F; one solve for all of them. Small models use a dense LU (no sparse
    // bookkeeping), large ones a sparse LU.
    const int nc = contacts();
    Eigen::MatrixXcd rhs(dofs(), nc + (load ? 1 : 0));
    rhs.leftCols(nc) = directions_.cast<Complex>();
    if (load) rhs.col(nc) = excitation_.cast<Complex>();
    // Two steps of iterative refinement with the residual b - Z x in long double, Z's entries
    // K - (k w)^2 M + i k w C formed in long double too: a finite-element K is badly
    // conditioned (~N^4 for a beam) and its entries reach 1e10, so Z rounded to double alone
    // moves a lightly damped resonance by ~1e-7 relative; refined, the solution is accurate to
    // working precision (mixed-precision refinement), and so is the condensed residual.
    Eigen::MatrixXcd x, dx;
    auto refine = [&](const auto& solve) {
        for (int step = 0; step < 2 && x.allFinite(); ++step) x += solve(precise_residual(k, omega, rhs, x));
    };
    if (dofs() <= dense_limit) {
        const Eigen::MatrixXcd zd(z);
        const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(zd);
        x = lu.solve(rhs);
        refine([&](const Eigen::MatrixXcd& r) { return Eigen::MatrixXcd(lu.solve(r)); });
        if (x.allFinite()) dx = -lu.solve(Eigen::MatrixXcd(dz * x));
    } else {
        Eigen::SparseLU<SparseComplex>& lu = *lu_;
        lu.factorize(z);
        if (lu.info() != Eigen::Success) {
            h.message = singular();
            return h;
        }
        x = lu.solve(rhs);
        refine([&](const Eigen::MatrixXcd& r) { return Eigen::MatrixXcd(lu.solve(r)); });
        if (x.allFinite()) dx = -Eigen::MatrixXcd(lu.solve(Eigen::MatrixXcd(dz * x)));
    }
    // A factorisation that succeeded on a numerically singular Z_k shows in the backward error
    // |Z x - b| / (|Z| |x| + |b|) (unit-free: FE stiffnesses reach 1e10, displacements 1e-6).
    const double z_size = Eigen::Map<const Eigen::VectorXcd>(z.valuePtr(), z.nonZeros()).cwiseAbs().maxCoeff();
    const double scale = z_size * x.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff();
    if (!x.allFinite() || !dx.allFinite() || !((z * x - rhs).cwiseAbs().maxCoeff() <= 1e-8 * scale)) {
        h.message = "numerically " + singular();
        return h;
    }
    // Sensitivities (above): d(Z^-1 b)/domega = -Z^-1 (dZ) Z^-1 b.
    const Eigen::MatrixXcd wt = directions_.transpose().cast<Complex>();
    h.contact = wt * x.leftCols(nc);
    h.contact_omega = wt * dx.leftCols(nc);
    h.output = outputs_.cast<Complex>() * x.leftCols(nc);
    if (load) {
        h.contact_load = wt * x.col(nc);
        h.contact_load_omega = wt * dx.col(nc);
        h.output_load = outputs_.cast<Complex>() * x.col(nc);
    }
    h.solution = std::move(x);
    h.ok = true;
    return h;
}

}  // namespace hbf
