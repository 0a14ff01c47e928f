// hbfriction — the modal receptance (receptance.hpp: use_modes, solve with modes): the structure
// by its lowest modes plus the static residual flexibility, the contacts' springs and dampers
// added by the Woodbury identity, and the N-long response without forming Z_k^-1.
#include "hbf/receptance.hpp"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/MatOp/SymShiftInvert.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "hbf/error.hpp"

namespace hbf {

namespace {
using Complex = std::complex<double>;

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
    // One column of X at a time: the sums of that column stay in cache.
    std::vector<long double> sum(static_cast<std::size_t>(rows));
    Eigen::MatrixXd out(rows, columns);
    for (Eigen::Index c = 0; c < columns; ++c) {
        std::fill(sum.begin(), sum.end(), 0.0L);
        for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
            const long double v = x(j, c);
            for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
                sum[static_cast<std::size_t>(it.row())] += static_cast<long double>(it.value()) * v;
        }
        for (Eigen::Index i = 0; i < rows; ++i) out(i, c) = static_cast<double>(sum[static_cast<std::size_t>(i)]);
    }
    return out;
}

}  // namespace

void Receptance::set_mass_damping(double xi) {
    require_finite(xi, "xi", "artificial damping");
    mass_damping_ = xi;
    c_values_ = c_values_given_ - xi * m_values_;
    if (modal_.damping_given.size() > 0)
        modal_.damping = modal_.damping_given - Eigen::VectorXd::Constant(modal_.damping_given.size(), xi);
}

Eigen::VectorXcd Receptance::apply_mass_damping(const Harmonic& h, const Eigen::VectorXcd& z) const {
    const int nc = contacts();
    if (!h.ok || z.size() != nc) return {};
    const double kw = h.k * h.omega;
    if (h.k == 0) return Eigen::VectorXcd::Zero(nc);  // xi enters as i k w xi M
    const Modal& md = modal_;
    if (md.lambda.size() == 0) {
        // dZ_k/dxi = -i k w M: dG_k/dxi = i k w W^T Z_k^-1 M Z_k^-1 W, and W^T Z_k^-1 =
        // (Z_k^-1 W)^T when Z_k is symmetric.
        if (!symmetric_ || h.solution.rows() != dofs() || h.solution.cols() < nc) return {};
        const auto solution = h.solution.leftCols(nc);
        const Eigen::VectorXcd u = solution * z;
        Eigen::VectorXcd mu(dofs());
        mu.real() = mass_ * u.real();
        mu.imag() = mass_ * u.imag();
        return Complex(0.0, kw) * (solution.transpose() * mu);
    }
    const auto m = md.lambda.size();
    Eigen::VectorXcd dd(m);  // d(d_j)/dxi = i k w d_j^2 (d_j as modal_terms: 0 for a hidden mode)
    const double p_size = md.p.size() > 0 ? md.p.cwiseAbs().maxCoeff() : 0.0;
    for (Eigen::Index j = 0; j < m; ++j) {
        const Complex d = 1.0 / Complex(md.lambda(j) - kw * kw, kw * md.damping(j));
        if (std::isfinite(std::abs(d)))
            dd(j) = Complex(0.0, kw) * d * d;
        else if (md.p.row(j).cwiseAbs().maxCoeff() <= 1e-8 * p_size)
            dd(j) = 0.0;
        else
            return {};  // solve_modal took a limit there
    }
    Eigen::VectorXcd shift(nc);
    for (int c = 0; c < nc; ++c) shift(c) = Complex(md.kappa(c), kw * md.delta(c));
    // A^-1 = I - S G_k (S G_k = S G_B A^-1 = (A - I) A^-1).
    const Eigen::VectorXcd u = z - shift.cwiseProduct(h.apply(z));
    Eigen::VectorXcd pu(m);
    pu.real() = md.p * u.real();
    pu.imag() = md.p * u.imag();
    pu = dd.cwiseProduct(pu);
    Eigen::VectorXcd v(nc);
    v.real() = md.p.transpose() * pu.real();
    v.imag() = md.p.transpose() * pu.imag();
    return v - h.apply(shift.cwiseProduct(v));
}

void Receptance::use_modes(int modes, const Eigen::VectorXd& contact_stiffness, const Eigen::VectorXd& contact_damping) {
    const int n = dofs(), nc = contacts();
    if (modes < 1) throw InvalidInput("modes = " + std::to_string(modes) + " is out of range: allowed >= 1");
    if (!cyclic_.empty())
        throw InvalidInput("modes = " + std::to_string(modes) + ": the modal receptance does not take a sector model "
                           "(cyclic symmetry): allowed modes = 0");
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
    Eigen::MatrixXcd g_b_omega = Eigen::MatrixXcd::Zero(nc, nc);  // as g_b in modal_terms: two real products
    if (k > 0) {
        g_b_omega.real() = md.p.transpose() * (dd.real().asDiagonal() * md.p) + r_factor_omega.real() * md.w_r_w;
        g_b_omega.imag() = md.p.transpose() * (dd.imag().asDiagonal() * md.p) + r_factor_omega.imag() * md.w_r_w;
    }
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
        // G = G_B A^-1: G' = (G_B' - G A') A^-1 with A' = S' G_B + S G_B' (two n_c^3 products).
        h.contact = g_b * a_inverse;
        h.contact_omega =
            k == 0 ? Eigen::MatrixXcd(Eigen::MatrixXcd::Zero(nc, nc))  // omega does not enter at k = 0
                   : Eigen::MatrixXcd((g_b_omega - h.contact * (shift_omega.asDiagonal() * g_b +
                                                                shift.asDiagonal() * g_b_omega)) *
                                      a_inverse);
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
