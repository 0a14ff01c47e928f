// The 2D elastic friction element with a varying normal load (normal_contact.hpp, issue 31):
// the Jenkins element at a constant normal load, the hysteresis loop of in-phase normal and
// tangential motion against its closed form (derived below), the separation onset, the
// permanent-stick slider, the exact Jacobian against central differences, and bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "hbf/contact.hpp"
#include "hbf/error.hpp"
#include "hbf/fourier.hpp"
#include "hbf/friction.hpp"
#include "hbf/normal_contact.hpp"

using namespace hbf;

namespace {

constexpr double pi = 3.14159265358979323846;

Eigen::VectorXd phases(int samples) {
    return Eigen::VectorXd::LinSpaced(samples, 0.0, 2.0 * pi * (samples - 1) / samples);
}

/// Coefficients [c0, c1, s1, ...] of a signal with a few harmonics (a fixed, generic choice).
Eigen::VectorXd signal(int harmonics, double mean, double c1, double s1, double c2, double s3) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * harmonics + 1);
    x(0) = mean;
    x(1) = c1;
    x(2) = s1;
    if (harmonics >= 2) x(3) = c2;
    if (harmonics >= 3) x(6) = s3;
    return x;
}

}  // namespace

TEST_CASE("Normal contact at a constant normal load is the Jenkins element: forces and Jacobian",
          "[normal_contact]") {
    // v = 0 and n_0 = N_0: N = N_0 and the slider limit mu N_0 is Jenkins' F_c, with the same
    // tangential stiffness. Against contact.hpp's jenkins law (its own march and Jacobian), in
    // gross slip and in permanent stick (the centred slider).
    Fourier fourier(6, 128);
    const ElasticContact2D element{50.0, 2.0, 0.3, 4.0};
    Contact jenkins;
    jenkins.law = FrictionLaw::jenkins;
    jenkins.friction_limit = 0.3 * 4.0;
    jenkins.stiffness = 2.0;
    const auto model = make_friction_model(jenkins);
    for (const double amplitude : {2.0, 0.2}) {  // slips (k_t U = 4 > 1.2), sticks (0.4 < 1.2)
        const Eigen::VectorXd u = signal(6, 0.1, amplitude, 0.3 * amplitude, 0.1 * amplitude, 0.05 * amplitude);
        const Eigen::VectorXd v = Eigen::VectorXd::Zero(13);
        NormalContactEvaluation e;
        evaluate(element, fourier, u, v, e, true);
        FrictionEvaluation j;
        model->evaluate(fourier, 1.0, u, Eigen::VectorXd(), j, true);
        INFO("amplitude " << amplitude);
        CHECK((e.tangential - j.force).cwiseAbs().maxCoeff() < 1e-13);
        CHECK((e.tangential_u - j.force_q).cwiseAbs().maxCoeff() < 1e-12);
        CHECK(std::abs(e.normal(0) - 4.0) < 1e-13);
        CHECK(e.normal.tail(12).cwiseAbs().maxCoeff() < 1e-13);
        // dN/dv = k_n: the identity times k_n in coefficient space.
        CHECK((e.normal_v - 50.0 * Eigen::MatrixXd::Identity(13, 13)).cwiseAbs().maxCoeff() < 1e-12);
        Eigen::VectorXd ut(128), vt = Eigen::VectorXd::Zero(128);
        fourier.to_time(u, ut);
        const NormalContactCycle cycle = march(element, ut, vt);
        CHECK(cycle.permanent_stick == (amplitude < 1.0));
    }
}

TEST_CASE("Normal contact: the hysteresis loop of in-phase normal and tangential motion equals its closed form",
          "[normal_contact]") {
    // u = U cos t, v = V cos t with N_0 > k_n V (no separation) and k_t U > mu k_n V (the
    // tangential spring unloads faster than the limit falls). Derived by hand, N_max = N_0 + k_n V:
    //  A  stuck from t = 0 (slipping forward at the largest u):
    //       T = mu N_max - k_t U (1 - cos t) until T = -mu N(t), i.e. cos t = c_a =
    //       (k_t U - 2 mu N_0 - mu k_n V) / (k_t U + mu k_n V);
    //  B  slipping backward to t = pi: T = -mu (N_0 + k_n V cos t) (the limit falls, the trial grows);
    //  C  stuck from t = pi: T = -mu (N_0 - k_n V) + k_t U (1 + cos t) until T = +mu N(t), i.e.
    //       cos t = c_c = (2 mu N_0 - mu k_n V - k_t U) / (k_t U - mu k_n V), t in (pi, 2 pi);
    //  D  slipping forward to t = 2 pi: T = mu (N_0 + k_n V cos t).
    // With u = U x, x = cos t, the dissipated energy W = integral of T du is U times
    //   (mu N_max - k_t U)(c_a - 1) + k_t U (c_a^2 - 1) / 2          (A, x from 1 to c_a)
    //   - mu (N_0 (-1 - c_a) + k_n V (1 - c_a^2) / 2)                 (B, c_a to -1)
    //   + (k_t U - mu N_0 + mu k_n V)(c_c + 1) + k_t U (c_c^2 - 1) / 2 (C, -1 to c_c)
    //   + mu (N_0 (1 - c_c) + k_n V (1 - c_c^2) / 2)                  (D, c_c to 1);
    // at V = 0 it is Jenkins' 4 F (U - F / k_t), F = mu N_0. The march turns at samples 0 and
    // N_t / 2 (N_t even), so its samples equal the loop exactly; its energy -pi U s_1(T) is the
    // trapezoidal rule of a kinked integrand, second order in the sample spacing.
    const double kt = 1.0, kn = 1.0, mu = 0.5, n0 = 1.0, U = 1.0;
    auto energy = [&](double V) {
        const double ca = (kt * U - 2.0 * mu * n0 - mu * kn * V) / (kt * U + mu * kn * V);
        const double cc = (2.0 * mu * n0 - mu * kn * V - kt * U) / (kt * U - mu * kn * V);
        const double a = (mu * (n0 + kn * V) - kt * U) * (ca - 1.0) + kt * U * (ca * ca - 1.0) / 2.0;
        const double b = -mu * (n0 * (-1.0 - ca) + kn * V * (1.0 - ca * ca) / 2.0);
        const double c = (kt * U - mu * n0 + mu * kn * V) * (cc + 1.0) + kt * U * (cc * cc - 1.0) / 2.0;
        const double d = mu * (n0 * (1.0 - cc) + kn * V * (1.0 - cc * cc) / 2.0);
        return U * (a + b + c + d);
    };
    CHECK(std::abs(energy(0.0) - 4.0 * mu * n0 * (U - mu * n0 / kt)) < 1e-14);
    for (const double V : {0.0, 0.3, 0.5, 0.9}) {
        const double ca = (kt * U - 2.0 * mu * n0 - mu * kn * V) / (kt * U + mu * kn * V);
        const double cc = (2.0 * mu * n0 - mu * kn * V - kt * U) / (kt * U - mu * kn * V);
        const double ta = std::acos(ca), tc = 2.0 * pi - std::acos(cc);
        const ElasticContact2D element{kn, kt, mu, n0};
        double previous = 0.0;  // the energy error at 256 samples
        for (const int samples : {256, 1024}) {
            const Eigen::VectorXd t = phases(samples);
            const Eigen::VectorXd u = U * t.array().cos(), v = V * t.array().cos();
            const NormalContactCycle cycle = march(element, u, v);
            double worst = 0.0;
            int wrong_state = 0;
            for (int j = 0; j < samples; ++j) {
                const double x = std::cos(t(j));
                double expected = 0.0;
                ContactState state = ContactState::stuck;
                if (t(j) == 0.0) {
                    expected = mu * (n0 + kn * V);  // D's end
                    state = ContactState::slipping;
                } else if (t(j) <= ta) {
                    expected = mu * (n0 + kn * V) - kt * U * (1.0 - x);
                } else if (t(j) < pi) {
                    expected = -mu * (n0 + kn * V * x);
                    state = ContactState::slipping;
                } else if (t(j) == pi) {
                    expected = -mu * (n0 - kn * V);  // B's end, C's start
                    state = ContactState::slipping;
                } else if (t(j) <= tc) {
                    expected = -mu * (n0 - kn * V) + kt * U * (1.0 + x);
                } else {
                    expected = mu * (n0 + kn * V * x);
                    state = ContactState::slipping;
                }
                worst = std::max(worst, std::abs(cycle.tangential(j) - expected));
                if (cycle.state[static_cast<std::size_t>(j)] != state) ++wrong_state;
                CHECK(std::abs(cycle.normal(j) - (n0 + kn * V * x)) < 1e-14);
            }
            double s1 = 0.0;
            for (int j = 0; j < samples; ++j) s1 += 2.0 / samples * cycle.tangential(j) * std::sin(t(j));
            const double marched = -pi * U * s1;
            INFO("V = " << V << ", " << samples << " samples: largest sample error " << worst << ", W marched "
                        << marched << ", closed form " << energy(V));
            CHECK(worst < 1e-13);
            CHECK(wrong_state == 0);
            // Second order: measured 1.0e-4 then 6.3e-6 (V = 0), 8.9e-6 then 5.0e-7 (V = 0.5).
            const double error = std::abs(marched - energy(V));
            CHECK(error < 2e-4 * energy(V));
            if (samples == 1024) CHECK(error < std::max(previous / 8.0, 1e-12));
            previous = error;
        }
    }
}

TEST_CASE("Normal contact: separation starts when the normal amplitude reaches n_0 / k_n, and unloads the slider",
          "[normal_contact]") {
    // v = V cos t: N = n_0 + k_n V cos t reaches 0 at t = pi first when V = n_0 / k_n. Below it no
    // sample separates; above it exactly the samples with n_0 + k_n V cos t_j <= 0 do, with T = 0
    // there, and the first stuck sample after them carries T = k_t (u_j - u_k), k the last
    // separated one (the spring unloaded, the slider at u_k).
    const double kt = 3.0, kn = 2.0, mu = 0.4, n0 = 1.0, onset = n0 / kn;
    const ElasticContact2D element{kn, kt, mu, n0};
    const int samples = 512;
    const Eigen::VectorXd t = phases(samples);
    const Eigen::VectorXd u = 0.05 * (t.array() + 0.3).sin();
    for (const double ratio : {0.99, 1.01, 1.5}) {
        const Eigen::VectorXd v = ratio * onset * t.array().cos();
        const NormalContactCycle cycle = march(element, u, v);
        int separated = 0, mismatched = 0;
        for (int j = 0; j < samples; ++j) {
            const bool open = n0 + kn * v(j) <= 0.0;
            const bool reported = cycle.state[static_cast<std::size_t>(j)] == ContactState::separated;
            separated += reported ? 1 : 0;
            mismatched += open != reported ? 1 : 0;
            if (reported) CHECK(cycle.tangential(j) == 0.0);
        }
        INFO("V = " << ratio << " n_0 / k_n: " << separated << " separated samples");
        CHECK(mismatched == 0);
        CHECK((separated > 0) == (ratio > 1.0));
        if (ratio > 1.0) {
            int last = -1;  // the last separated sample, then the first one after it
            for (int j = 0; j < samples; ++j)
                if (cycle.state[static_cast<std::size_t>(j)] == ContactState::separated) last = j;
            const int next = (last + 1) % samples;
            if (cycle.state[static_cast<std::size_t>(next)] == ContactState::stuck)
                CHECK(std::abs(cycle.tangential(next) - kt * (u(next) - u(last))) < 1e-14);
        }
    }
}

TEST_CASE("Normal contact in permanent stick: the slider at the midpoint of its admissible interval",
          "[normal_contact]") {
    // Small tangential motion under a varying normal load: every sample sticks, and the slider
    // is the midpoint of max_j (u_j - mu N_j / k_t) .. min_j (u_j + mu N_j / k_t) (computed here
    // from the samples), so T_j = k_t (u_j - s).
    const double kt = 10.0, kn = 5.0, mu = 0.3, n0 = 2.0;
    const ElasticContact2D element{kn, kt, mu, n0};
    const int samples = 200;
    const Eigen::VectorXd t = phases(samples);
    const Eigen::VectorXd u = 0.02 * (t.array() + 0.7).cos() + 0.005 * (3.0 * t.array()).sin() + 0.1;
    const Eigen::VectorXd v = 0.2 * t.array().cos();
    const NormalContactCycle cycle = march(element, u, v);
    REQUIRE(cycle.permanent_stick);
    double lower = -1e300, upper = 1e300;
    for (int j = 0; j < samples; ++j) {
        const double travel = mu * (n0 + kn * v(j)) / kt;
        lower = std::max(lower, u(j) - travel);
        upper = std::min(upper, u(j) + travel);
    }
    REQUIRE(lower < upper);
    const double slider = 0.5 * (lower + upper);
    for (int j = 0; j < samples; ++j) {
        CHECK(cycle.state[static_cast<std::size_t>(j)] == ContactState::stuck);
        CHECK(std::abs(cycle.tangential(j) - kt * (u(j) - slider)) < 1e-14);
    }
}

TEST_CASE("Normal contact: the AFT Jacobian equals central differences in slip, stick and separation",
          "[normal_contact]") {
    // The forces are piecewise linear in the samples on each pattern: central differences with
    // a step far below the distance of any sample to a switch equal the Jacobian to rounding
    // (1e-6 relative, as for the other laws). Three regimes: gross slip with separation, partial
    // slip under a varying load, permanent stick (the slider's anchors at two samples).
    Fourier fourier(5, 96);
    const int n = 11;
    struct Case {
        const char* name;
        Eigen::VectorXd u, v;
    };
    const Case cases[] = {
        {"slip and separation", signal(5, 0.0, 1.0, 0.4, 0.2, 0.1), signal(5, -0.12, 0.45, -0.3, 0.05, 0.02)},
        {"partial slip", signal(5, 0.2, 0.3, 0.1, 0.05, 0.02), signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)},
        {"permanent stick", signal(5, 0.2, 0.02, 0.01, 0.004, 0.002), signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)},
    };
    const ElasticContact2D element{2.0, 3.0, 0.4, 1.0};
    for (const Case& c : cases) {
        NormalContactEvaluation e;
        evaluate(element, fourier, c.u, c.v, e, true);
        Eigen::MatrixXd tu(n, n), tv(n, n), nv(n, n);
        const double h = 1e-7;
        for (int k = 0; k < n; ++k) {
            NormalContactEvaluation plus, minus;
            Eigen::VectorXd a = c.u, b = c.u;
            a(k) += h;
            b(k) -= h;
            evaluate(element, fourier, a, c.v, plus, false);
            evaluate(element, fourier, b, c.v, minus, false);
            tu.col(k) = (plus.tangential - minus.tangential) / (2.0 * h);
            a = c.v;
            b = c.v;
            a(k) += h;
            b(k) -= h;
            evaluate(element, fourier, c.u, a, plus, false);
            evaluate(element, fourier, c.u, b, minus, false);
            tv.col(k) = (plus.tangential - minus.tangential) / (2.0 * h);
            nv.col(k) = (plus.normal - minus.normal) / (2.0 * h);
        }
        Eigen::VectorXd ut(96), vt(96);
        fourier.to_time(c.u, ut);
        fourier.to_time(c.v, vt);
        const NormalContactCycle cycle = march(element, ut, vt);
        int counts[3] = {0, 0, 0};
        for (const ContactState s : cycle.state) ++counts[static_cast<int>(s)];
        INFO(c.name << ": " << counts[0] << " separated, " << counts[1] << " stuck, " << counts[2] << " slipping");
        const double scale = std::max({tu.cwiseAbs().maxCoeff(), tv.cwiseAbs().maxCoeff(), 1.0});
        CHECK((e.tangential_u - tu).cwiseAbs().maxCoeff() < 1e-6 * scale);
        CHECK((e.tangential_v - tv).cwiseAbs().maxCoeff() < 1e-6 * scale);
        CHECK((e.normal_v - nv).cwiseAbs().maxCoeff() < 1e-6 * scale);
        if (std::string(c.name) == "slip and separation") CHECK((counts[0] > 0 && counts[2] > 0));
        if (std::string(c.name) == "partial slip") CHECK((counts[0] == 0 && counts[1] > 0 && counts[2] > 0));
        if (std::string(c.name) == "permanent stick") CHECK(cycle.permanent_stick);
    }
}

TEST_CASE("Normal contact: parameters out of range are refused, naming the parameter", "[normal_contact]") {
    const Eigen::VectorXd u = Eigen::VectorXd::Zero(8), v = Eigen::VectorXd::Zero(8);
    const struct {
        ElasticContact2D element;
        const char* key;
    } bad[] = {{{0.0, 1.0, 0.3, 1.0}, "normal_stiffness"},
               {{1.0, -1.0, 0.3, 1.0}, "tangential_stiffness"},
               {{1.0, 1.0, -0.1, 1.0}, "friction_coefficient"},
               {{1.0, 1.0, 0.3, NAN}, "normal_offset"}};
    for (const auto& b : bad) CHECK_THROWS_WITH(march(b.element, u, v), Catch::Contains(b.key));
    CHECK_THROWS_AS(march({1.0, 1.0, 0.3, 1.0}, u, Eigen::VectorXd::Zero(7)), InvalidInput);
}
