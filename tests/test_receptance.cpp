

// The receptance unit (receptance.hpp) against dense references: Z_k^-1 by a dense LU of the
// same matrices, finite differences in omega, the full linear response, and its errors.
#include <catch2/catch.hpp>
#include <algorithm>
#include <map>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hbf/error.hpp"
#include "hbf/model.hpp"
#include "hbf/receptance.hpp"

using namespace hbf;

namespace {

/// A damped chain of n unit springs to the ground at the first DOF, masses 1 + i / n, Rayleigh
/// damping 0.01 K + 0.02 M; masses listed in `massless` set to zero (static DOFs).
struct Chain {
    Eigen::SparseMatrix<double> m, c, k;
    Eigen::MatrixXd w, t;
    Eigen::VectorXd f;
};
Chain chain(int n, std::vector<int> massless = {}) {
    std::vector<Eigen::Triplet<double>> km, mm;
    for (int i = 0; i < n; ++i) {
        km.emplace_back(i, i, i + 1 < n ? 2.0 : 1.0);
        if (i + 1 < n) {
            km.emplace_back(i, i + 1, -1.0);
            km.emplace_back(i + 1, i, -1.0);
        }
        if (std::find(massless.begin(), massless.end(), i) == massless.end()) mm.emplace_back(i, i, 1.0 + double(i) / n);
    }
    Chain s;
    s.k.resize(n, n);
    s.m.resize(n, n);
    s.k.setFromTriplets(km.begin(), km.end());
    s.m.setFromTriplets(mm.begin(), mm.end());
    s.c = 0.01 * s.k + 0.02 * s.m;
    s.w = Eigen::MatrixXd::Zero(n, 2);
    s.w(n - 1, 0) = 1.0;                      // the tip against the ground
    s.w(n / 2, 1) = 1.0;                      // a pair in the middle
    s.w(n / 2 + 1, 1) = -1.0;
    s.f = Eigen::VectorXd::Zero(n);
    s.f(0) = 1.0;
    s.t = Eigen::MatrixXd::Zero(2, n);
    s.t(0, n - 1) = 1.0;                      // the tip
    s.t.row(1).setConstant(1.0 / n);          // the mean displacement: an output vector, not a DOF
    return s;
}

Eigen::MatrixXcd dense_z(const Chain& s, int k, double omega) {
    const double kw = k * omega;
    return (Eigen::MatrixXd(s.k) - kw * kw * Eigen::MatrixXd(s.m)).cast<std::complex<double>>() +
           std::complex<double>(0.0, kw) * Eigen::MatrixXd(s.c).cast<std::complex<double>>();
}

}  // namespace

TEST_CASE("Receptance G_k = W^T Z_k^-1 W, the loads and the outputs equal a dense solve", "[receptance]") {
    for (const std::vector<int>& massless : {std::vector<int>{}, std::vector<int>{3, 7, 29}}) {
        const Chain s = chain(30, massless);
        Receptance r(s.m, s.c, s.k, s.w, s.f, s.t);
        for (int k : {0, 1, 3}) {
            const double omega = 0.37;
            const Receptance::Harmonic h = r.solve(k, omega);
            REQUIRE(h.ok);
            const Eigen::MatrixXcd zinv = dense_z(s, k, omega).inverse();
            const Eigen::MatrixXcd wc = s.w.cast<std::complex<double>>(), tc = s.t.cast<std::complex<double>>();
            const Eigen::VectorXcd fc = s.f.cast<std::complex<double>>();
            INFO("k = " << k << ", massless DOFs " << massless.size());
            CHECK((h.contact - wc.transpose() * zinv * wc).norm() < 1e-10 * h.contact.norm());
            CHECK((h.contact_load - wc.transpose() * zinv * fc).norm() < 1e-10 * h.contact_load.norm());
            CHECK((h.output - tc * zinv * wc).norm() < 1e-10 * h.output.norm());
            CHECK((h.output_load - tc * zinv * fc).norm() < 1e-10 * h.output_load.norm());
        }
    }
}

TEST_CASE("Receptance: the first harmonic's output load is the linear response of model.hpp", "[receptance]") {
    const Chain s = chain(12);
    Receptance r(s.m, s.c, s.k, s.w, s.f, Eigen::MatrixXd::Identity(12, 12));
    const Receptance::Harmonic h = r.solve(1, 0.8);
    REQUIRE(h.ok);
    const Eigen::VectorXcd y = linear_response(Eigen::MatrixXd(s.m), Eigen::MatrixXd(s.c), Eigen::MatrixXd(s.k), s.f, 0.8);
    CHECK((h.output_load - y).norm() < 1e-12 * y.norm());
}

TEST_CASE("Receptance derivatives in omega equal central differences", "[receptance]") {
    const Chain s = chain(20, {5});
    Receptance r(s.m, s.c, s.k, s.w, s.f, s.t);
    for (int k : {1, 2}) {
        const double omega = 0.61, d = 1e-6;
        const Receptance::Harmonic h = r.solve(k, omega), plus = r.solve(k, omega + d), minus = r.solve(k, omega - d);
        REQUIRE((h.ok && plus.ok && minus.ok));
        const Eigen::MatrixXcd fd = (plus.contact - minus.contact) / (2 * d);
        const Eigen::VectorXcd fd_load = (plus.contact_load - minus.contact_load) / (2 * d);
        CHECK((h.contact_omega - fd).norm() < 1e-6 * std::max(1.0, fd.norm()));
        CHECK((h.contact_load_omega - fd_load).norm() < 1e-6 * std::max(1.0, fd_load.norm()));
    }
}

TEST_CASE("Receptance: a singular Z_k is a status with a message, bad shapes are InvalidInput", "[receptance]") {
    // 1 DOF, undamped, unit mass and stiffness: resonance at k w = 1.
    Eigen::SparseMatrix<double> one(1, 1), zero(1, 1);
    one.insert(0, 0) = 1.0;
    Receptance r(one, zero, one, Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1));
    const Receptance::Harmonic resonant = r.solve(2, 0.5);
    CHECK_FALSE(resonant.ok);
    CHECK_THAT(resonant.message, Catch::Contains("harmonic k = 2"));
    CHECK(r.solve(1, 0.5).ok);
    // A free mass (K = 0): harmonic 0 has no static stiffness, the others are fine.
    Receptance free(one, zero, zero, Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Ones(1), Eigen::MatrixXd::Ones(1, 1));
    CHECK_FALSE(free.solve(0, 1.0).ok);
    CHECK(free.solve(1, 1.0).ok);
    CHECK_THROWS_AS(r.solve(-1, 1.0), InvalidInput);
    CHECK_THROWS_AS(r.solve(1, 0.0), InvalidInput);
    Eigen::SparseMatrix<double> two(2, 2);
    CHECK_THROWS_AS(Receptance(one, zero, two, Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Ones(1),
                               Eigen::MatrixXd::Ones(1, 1)),
                    InvalidInput);
    CHECK_THROWS_AS(Receptance(one, zero, one, Eigen::MatrixXd::Ones(2, 1), Eigen::VectorXd::Ones(1),
                               Eigen::MatrixXd::Ones(1, 1)),
                    InvalidInput);
}

namespace {
/// The direct receptance of the chain with contact springs kappa and dampers delta added along
/// the directions (the reference of the modal one with the same shift).
Receptance shifted_direct(const Chain& s, const Eigen::VectorXd& kappa, const Eigen::VectorXd& delta) {
    Eigen::SparseMatrix<double> k = s.k, c = s.c;
    for (Eigen::Index j = 0; j < s.w.cols(); ++j) {
        k += (kappa(j) * s.w.col(j) * s.w.col(j).transpose()).sparseView();
        c += (delta(j) * s.w.col(j) * s.w.col(j).transpose()).sparseView();
    }
    return Receptance(s.m, c, k, s.w, s.f, s.t);
}
}  // namespace

TEST_CASE("Modal receptance with every mode equals the direct solve, contact springs and dampers included",
          "[receptance][modal]") {
    // With all N modes the static residual vanishes and the modal sum is exact; the contact
    // springs and dampers enter by the n_c x n_c Woodbury identity.
    const Chain s = chain(30);
    const Eigen::Vector2d kappa(0.7, 0.2), delta(0.05, 0.3);
    Receptance direct = shifted_direct(s, kappa, delta);
    Receptance modal(s.m, s.c, s.k, s.w, s.f, s.t);
    modal.use_modes(30, kappa, delta);
    REQUIRE(modal.modes() == 30);
    for (int k : {0, 1, 3}) {
        const double omega = 0.37;
        const Receptance::Harmonic a = direct.solve(k, omega), b = modal.solve(k, omega);
        REQUIRE(a.ok);
        REQUIRE(b.ok);
        INFO("k = " << k);
        CHECK((b.contact - a.contact).norm() < 1e-10 * a.contact.norm());
        CHECK((b.contact_load - a.contact_load).norm() < 1e-10 * a.contact_load.norm());
        CHECK((b.output - a.output).norm() < 1e-10 * a.output.norm());
        CHECK((b.output_load - a.output_load).norm() < 1e-10 * a.output_load.norm());
        CHECK((b.solution - a.solution).norm() < 1e-10 * a.solution.norm());
        // The N-long response to given contact forces without forming Z^-1 W (HB's dofs()),
        // against the direct solution applied to them, with and without the load.
        const Eigen::Vector2cd lambda(std::complex<double>(0.3, -1.1), std::complex<double>(-0.8, 0.25));
        for (const bool load : {false, true}) {
            Eigen::VectorXcd expected = -a.solution.leftCols(2) * lambda;
            if (load) expected += a.solution.col(2);
            const Eigen::VectorXcd y = modal.modal_response(k, omega, lambda, load);
            INFO("load = " << load);
            CHECK((y - expected).norm() < 1e-10 * expected.norm());
        }
        if (k > 0) {
            CHECK((b.contact_omega - a.contact_omega).norm() < 1e-9 * a.contact_omega.norm());
            CHECK((b.contact_load_omega - a.contact_load_omega).norm() < 1e-9 * a.contact_load_omega.norm());
        }
    }
}

TEST_CASE("Modal receptance truncated (Spectra): converges to the direct solve, exact derivatives", "[receptance][modal]") {
    // 400 DOFs (the sparse eigensolver's range; w_1 = 0.003). Truncated to m modes
    // plus the static residual flexibility, whose damping follows the Rayleigh fit: the error
    // is the truncated modes' dynamic part, ~(k w / w_{m+1})^2 of their share. At k w <= 0.004
    // it must fall as m grows, at the rate (w_21 / w_81)^2 from 20 to 80 modes.
    const Chain s = chain(400);
    const Eigen::Vector2d kappa(0.3, 0.1), delta(0.02, 0.01);
    Receptance direct = shifted_direct(s, kappa, delta);
    Receptance spectrum(s.m, s.c, s.k, s.w, s.f, s.t);
    spectrum.use_modes(81, kappa, delta);
    const Eigen::VectorXd w_n = spectrum.natural_frequencies();
    double previous = 1.0;
    std::map<int, double> errors;
    for (int m : {5, 20, 80}) {
        Receptance modal(s.m, s.c, s.k, s.w, s.f, s.t);
        modal.use_modes(m, kappa, delta);
        REQUIRE(modal.modes() == m);
        double error = 0.0;
        for (int k : {1, 2, 4}) {
            const double omega = 0.001;
            const Receptance::Harmonic a = direct.solve(k, omega), b = modal.solve(k, omega);
            REQUIRE(b.ok);
            error = std::max(error, (b.contact - a.contact).norm() / a.contact.norm());
            error = std::max(error, (b.contact_load - a.contact_load).norm() / a.contact_load.norm());
            // derivatives: central differences of the modal receptance itself
            const double d = 1e-8;
            const Receptance::Harmonic plus = modal.solve(k, omega + d), minus = modal.solve(k, omega - d);
            CHECK((b.contact_omega - (plus.contact - minus.contact) / (2 * d)).norm() < 1e-5 * b.contact_omega.norm());
            CHECK((b.contact_load_omega - (plus.contact_load - minus.contact_load) / (2 * d)).norm() <
                  1e-5 * b.contact_load_omega.norm());
        }
        INFO("m = " << m << ": largest relative error " << error);
        CHECK(error < previous);
        previous = error;
        errors[m] = error;
    }
    // the rate: (w_21 / w_81)^2 from 20 to 80 modes (measured 0.072 against 0.065)
    const double rate = std::pow(w_n(20) / w_n(80), 2);
    CHECK(errors[80] / errors[20] == Approx(rate).epsilon(0.5));
    CHECK(errors[80] < 1e-3);
}

TEST_CASE("Modal receptance: what it cannot represent is refused with the reason", "[receptance][modal]") {
    const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
    auto message = [&](const Chain& s, int modes) {
        try {
            Receptance r(s.m, s.c, s.k, s.w, s.f, s.t);
            r.use_modes(modes, zero, zero);
        } catch (const InvalidInput& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(message(chain(20), 0), Catch::Contains("allowed >= 1"));
    CHECK_THAT(message(chain(20, {4}), 5), Catch::Contains("positive definite mass"));
    Chain coupled = chain(20);
    coupled.c.coeffRef(3, 3) += 0.5;  // a local damper: not diagonal in the modes
    CHECK_THAT(message(coupled, 5), Catch::Contains("not diagonal in the modal basis"));
    Chain free = chain(20);
    free.k.coeffRef(0, 0) -= 1.0;  // the spring to the ground removed: a rigid-body mode
    CHECK_THAT(message(free, 5), Catch::Contains("positive definite stiffness"));
}

namespace {
/// x = Z^-1 B for Z = K - w^2 M + i w C as stored in double, solved in binary128 (113-bit
/// mantissa: cond(Z) 1e16 leaves 1e-18) as the real system [[A, -Bi], [Bi, A]] by Gaussian
/// elimination with partial pivoting: an independent reference for an ill-conditioned Z.
Eigen::MatrixXcd quad_solve(const Eigen::MatrixXd& k, const Eigen::MatrixXd& m, const Eigen::MatrixXd& c, double w,
                            const Eigen::MatrixXd& b) {
    using Q = __float128;
    const Eigen::Index n = k.rows(), r = b.cols();
    std::vector<std::vector<Q>> a(static_cast<std::size_t>(2 * n), std::vector<Q>(static_cast<std::size_t>(2 * n + 2 * r), 0));
    const Q qw = w;
    for (Eigen::Index i = 0; i < n; ++i) {
        for (Eigen::Index j = 0; j < n; ++j) {
            const Q re = Q(k(i, j)) - qw * qw * Q(m(i, j)), im = qw * Q(c(i, j));
            const auto I = static_cast<std::size_t>(i), J = static_cast<std::size_t>(j), N = static_cast<std::size_t>(n);
            a[I][J] = re;
            a[I][J + N] = -im;
            a[I + N][J] = im;
            a[I + N][J + N] = re;
        }
        for (Eigen::Index col = 0; col < r; ++col)
            a[static_cast<std::size_t>(i)][static_cast<std::size_t>(2 * n + col)] = b(i, col);  // imaginary rhs 0
    }
    const auto size = static_cast<std::size_t>(2 * n), width = static_cast<std::size_t>(2 * n + r);
    for (std::size_t p = 0; p < size; ++p) {
        std::size_t best = p;
        for (std::size_t i = p + 1; i < size; ++i)
            if ((a[i][p] < 0 ? -a[i][p] : a[i][p]) > (a[best][p] < 0 ? -a[best][p] : a[best][p])) best = i;
        std::swap(a[p], a[best]);
        for (std::size_t i = p + 1; i < size; ++i) {
            const Q factor = a[i][p] / a[p][p];
            for (std::size_t j = p; j < width; ++j) a[i][j] -= factor * a[p][j];
        }
    }
    Eigen::MatrixXcd x(n, r);
    std::vector<Q> sol(size);
    for (std::size_t col = 0; col < static_cast<std::size_t>(r); ++col) {
        for (std::size_t i = size; i-- > 0;) {
            Q s = a[i][size + col];
            for (std::size_t j = i + 1; j < size; ++j) s -= a[i][j] * sol[j];
            sol[i] = s / a[i][i];
        }
        for (Eigen::Index i = 0; i < n; ++i)
            x(i, static_cast<Eigen::Index>(col)) = {static_cast<double>(sol[static_cast<std::size_t>(i)]),
                                                    static_cast<double>(sol[static_cast<std::size_t>(i + n)])};
    }
    return x;
}

/// An n x n matrix of uniform numbers in [-0.5, 0.5) from a fixed 64-bit LCG seed.
Eigen::MatrixXd random_matrix(int n, std::uint64_t seed) {
    Eigen::MatrixXd random(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
            random(i, j) = static_cast<double>(seed >> 11) / 9007199254740992.0 - 0.5;
        }
    return random;
}

/// K = Q diag(lambda) Q^T, lambda from 1 to 1e16 (log-spaced), Q the orthogonal factor of
/// `random`: symmetric, cond 1e16.
Eigen::MatrixXd ill_conditioned_stiffness(const Eigen::MatrixXd& random) {
    const Eigen::Index n = random.rows();
    const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(random).householderQ();
    Eigen::VectorXd lambda(n);
    for (Eigen::Index i = 0; i < n; ++i) lambda(i) = std::pow(10.0, 16.0 * static_cast<double>(i) / static_cast<double>(n - 1));
    const Eigen::MatrixXd k = q * lambda.asDiagonal() * q.transpose();
    return 0.5 * (k + k.transpose());
}
}  // namespace

TEST_CASE("Receptance: the refined solve is exact to working precision at cond(Z) ~ 1e16 (more than 5 refinement steps)",
          "[receptance]") {
    // K = Q diag(lambda) Q^T with lambda from 1 to 1e16 and Q a fixed random rotation: a dense
    // 40-DOF model (sparse-LU path) whose Z_1 at w^2 = 0.5 has cond ~ 1e16. The double LU is
    // off by 2e-2 and each refinement step shrinks the error by only cond eps: capped at 5
    // steps, as it was, G kept an error of 5e-8 here (measured; the 10,000-DOF beam: 1e-7, and
    // its FRF crawled). Reference: the same stored matrices solved in binary128.
    const int n = 40;
    const Eigen::MatrixXd random = random_matrix(n, 12345);
    const Eigen::MatrixXd k = ill_conditioned_stiffness(random);
    const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n), c = 1e-3 * Eigen::MatrixXd::Identity(n, n);
    Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 2);
    w(0, 0) = 1.0;
    w(n - 1, 1) = 1.0;
    const double omega = std::sqrt(0.5);
    Receptance receptance(m.sparseView(), c.sparseView(), k.sparseView(0.0, 0.0), w, Eigen::VectorXd::Unit(n, 1),
                          Eigen::MatrixXd(0, n));
    const Receptance::Harmonic h = receptance.solve(1, omega, false);
    REQUIRE(h.ok);
    const Eigen::MatrixXcd reference = w.transpose() * quad_solve(k, m, c, omega, w);
    // The plain double solve is far off (what refinement has to recover):
    const Eigen::MatrixXcd z = (k - omega * omega * m).cast<std::complex<double>>() +
                               std::complex<double>(0.0, omega) * c.cast<std::complex<double>>();
    const Eigen::MatrixXcd unrefined = w.transpose() * z.partialPivLu().solve(w.cast<std::complex<double>>());
    const double scale = reference.cwiseAbs().maxCoeff();
    INFO("unrefined error " << (unrefined - reference).cwiseAbs().maxCoeff() / scale);
    CHECK((unrefined - reference).cwiseAbs().maxCoeff() > 1e-6 * scale);
    CHECK((h.contact - reference).cwiseAbs().maxCoeff() <= 1e-13 * scale);
}

TEST_CASE("Receptance: dG/domega is exact to 1e-9 at cond(Z) ~ 1e16 with damping proportional to K",
          "[receptance]") {
    // The model of the previous case with Rayleigh damping C = 1e-3 M + 1e-9 K. The derivative
    // -W^T Z^-1 dZ Z^-1 W was an unrefined solve of dZ x (off by cond(Z) eps, 0.17 on the
    // 10,000-DOF beam at k = 1, which cost its continuation 5 to 20 corrector iterations a point
    // and crawled at stick-slip kinks); it is now -(Z^-1 W)^T dZ x from the refined solution, with
    // dZ x formed in double-double (C x cancels like K x). Reference: central differences of the
    // binary128 solve at d = 1e-6 (truncation ~d^2: 1e-7 at d = 1e-4, 3e-11 here; rounding ~1e-16 / d).
    const int n = 40;
    const Eigen::MatrixXd random = random_matrix(n, 4242);
    Eigen::MatrixXd k = ill_conditioned_stiffness(random);
    // Symmetric (W^T Z^-1 = (Z^-1 W)^T, no further solve) and with a skew-symmetric part added
    // to K (e.g. a follower force: the refined solve of dZ x).
    const bool skew = GENERATE(false, true);
    if (skew) {
        const Eigen::MatrixXd s = random.triangularView<Eigen::StrictlyUpper>();
        k += 0.05 * (s - s.transpose());
    }
    INFO((skew ? "K with a skew part" : "symmetric K"));
    const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd c = 1e-3 * m + 1e-9 * k;
    Eigen::MatrixXd w = Eigen::MatrixXd::Zero(n, 2);
    w(0, 0) = 1.0;
    w(n - 1, 1) = 1.0;
    const Eigen::VectorXd f = Eigen::VectorXd::Unit(n, 1);
    const double omega = std::sqrt(0.5), d = 1e-6;
    Receptance receptance(m.sparseView(), c.sparseView(0.0, 0.0), k.sparseView(0.0, 0.0), w, f, Eigen::MatrixXd(0, n));
    const Receptance::Harmonic h = receptance.solve(1, omega, true);
    REQUIRE(h.ok);
    Eigen::MatrixXd b(n, 3);
    b << w, f;
    const Eigen::MatrixXcd plus = w.transpose() * quad_solve(k, m, c, omega + d, b);
    const Eigen::MatrixXcd minus = w.transpose() * quad_solve(k, m, c, omega - d, b);
    const Eigen::MatrixXcd reference = (plus - minus) / (2 * d);
    const double scale = reference.leftCols(2).cwiseAbs().maxCoeff();
    INFO("error " << (h.contact_omega - reference.leftCols(2)).cwiseAbs().maxCoeff() / scale);
    CHECK((h.contact_omega - reference.leftCols(2)).cwiseAbs().maxCoeff() <= 1e-9 * scale);
    CHECK((h.contact_load_omega - reference.col(2)).cwiseAbs().maxCoeff() <= 1e-9 * reference.col(2).cwiseAbs().maxCoeff());
}

TEST_CASE("Receptance derivative in the mass damping xi equals central differences: direct, modal (truncated, "
          "contact springs and dampers), explicit and factored",
          "[receptance][modal]") {
    const Chain s = chain(40);
    const Eigen::Vector2d kappa(0.7, 0.2), delta(0.05, 0.3);
    Receptance direct = shifted_direct(s, kappa, delta);
    Receptance modal(s.m, s.c, s.k, s.w, s.f, s.t);
    modal.use_modes(12, kappa, delta);
    const Eigen::Vector2cd z(std::complex<double>(0.3, -1.1), std::complex<double>(-0.8, 0.25));
    for (Receptance* r : {&direct, &modal})
        for (const bool explicit_contact : {true, false})
            for (int k : {0, 1, 3}) {
                const double omega = 0.37, xi = 0.013, d = 1e-6;
                r->set_mass_damping(xi + d);
                const Eigen::VectorXcd plus = r->solve(k, omega, false, true, true).contact * z;
                r->set_mass_damping(xi - d);
                const Eigen::VectorXcd minus = r->solve(k, omega, false, true, true).contact * z;
                r->set_mass_damping(xi);
                const Receptance::Harmonic h = r->solve(k, omega, false, false, explicit_contact);
                REQUIRE(h.ok);
                const Eigen::VectorXcd fd = (plus - minus) / (2 * d), exact = r->apply_mass_damping(h, z);
                INFO("modal " << (r == &modal) << ", explicit " << explicit_contact << ", k = " << k << ": "
                              << fd.transpose() << " against " << exact.transpose());
                REQUIRE(exact.size() == 2);
                CHECK((exact - fd).norm() <= 1e-7 * std::max(fd.norm(), (plus.norm() + minus.norm()) * 1e-3));
                if (k > 0) CHECK(fd.norm() > 1e-3 * plus.norm());  // xi matters: the check is not 0 = 0
                r->set_mass_damping(0.0);
            }
}
