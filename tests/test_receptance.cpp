// The receptance unit (receptance.hpp) against dense references: Z_k^-1 by a dense LU of the
// same matrices, finite differences in omega, the full linear response, and its errors.
#include <catch2/catch.hpp>
#include <cmath>

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
