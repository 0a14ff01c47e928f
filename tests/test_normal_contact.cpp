// The 2D elastic friction element with a varying normal load (normal_contact.hpp, issue 31):
// the Jenkins element at a constant normal load, the hysteresis loop of in-phase normal and
// tangential motion against its closed form (derived below), the separation onset, the
// permanent-stick slider, the exact Jacobian against central differences, and bad input.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/fourier.hpp"
#include "hbf/contact_force.hpp"
#include "hbf/normal_contact.hpp"

using namespace hbf;

namespace {

constexpr double pi_ = 3.14159265358979323846;

Eigen::VectorXd phases(int samples) {
    return Eigen::VectorXd::LinSpaced(samples, 0.0, 2.0 * pi_ * (samples - 1) / samples);
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
    // tangential stiffness. Against contact_law.hpp's jenkins law (its own march and Jacobian), in
    // gross slip and in permanent stick (the centred slider).
    Fourier fourier(6, 128);
    const ElasticContact element{50.0, 2.0, 0.3, 4.0, 1};
    Contact jenkins;
    jenkins.law = FrictionLaw::jenkins;
    jenkins.friction_limit = 0.3 * 4.0;
    jenkins.stiffness = 2.0;
    const auto model = make_friction_model(jenkins);
    for (const double amplitude : {2.0, 0.2}) {  // slips (k_t U = 4 > 1.2), sticks (0.4 < 1.2)
        const Eigen::VectorXd u = signal(6, 0.1, amplitude, 0.3 * amplitude, 0.1 * amplitude, 0.05 * amplitude);
        Eigen::VectorXd q = Eigen::VectorXd::Zero(26);  // [u; v], v = 0
        q.head(13) = u;
        NormalContactEvaluation e;
        evaluate(element, fourier, q, e, true);
        FrictionEvaluation j;
        model->evaluate(fourier, 1.0, u, Eigen::VectorXd(), j, true);
        INFO("amplitude " << amplitude);
        CHECK((e.force.head(13) - j.force).cwiseAbs().maxCoeff() < 1e-13);
        CHECK((e.jacobian.topLeftCorner(13, 13) - j.force_q).cwiseAbs().maxCoeff() < 1e-12);
        CHECK(std::abs(e.force(13) - 4.0) < 1e-13);
        CHECK(e.force.tail(12).cwiseAbs().maxCoeff() < 1e-13);
        // dN/dv = k_n: the identity times k_n in coefficient space; dN/du = 0.
        CHECK((e.jacobian.bottomRightCorner(13, 13) - 50.0 * Eigen::MatrixXd::Identity(13, 13)).cwiseAbs().maxCoeff() <
              1e-12);
        CHECK(e.jacobian.bottomLeftCorner(13, 13).cwiseAbs().maxCoeff() == 0.0);
        Eigen::MatrixXd ut(128, 1);
        const Eigen::VectorXd vt = Eigen::VectorXd::Zero(128);
        fourier.to_time(u, ut.col(0));
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
        const double ta = std::acos(ca), tc = 2.0 * pi_ - std::acos(cc);
        const ElasticContact element{kn, kt, mu, n0, 1};
        double previous = 0.0;  // the energy error at 256 samples
        for (const int samples : {256, 1024}) {
            const Eigen::VectorXd t = phases(samples);
            const Eigen::MatrixXd u = U * t.array().cos();
            const Eigen::VectorXd v = V * t.array().cos();
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
                } else if (t(j) < pi_) {
                    expected = -mu * (n0 + kn * V * x);
                    state = ContactState::slipping;
                } else if (t(j) == pi_) {
                    expected = -mu * (n0 - kn * V);  // B's end, C's start
                    state = ContactState::slipping;
                } else if (t(j) <= tc) {
                    expected = -mu * (n0 - kn * V) + kt * U * (1.0 + x);
                } else {
                    expected = mu * (n0 + kn * V * x);
                    state = ContactState::slipping;
                }
                worst = std::max(worst, std::abs(cycle.tangential(j, 0) - expected));
                if (cycle.state[static_cast<std::size_t>(j)] != state) ++wrong_state;
                CHECK(std::abs(cycle.normal(j) - (n0 + kn * V * x)) < 1e-14);
            }
            double s1 = 0.0;
            for (int j = 0; j < samples; ++j) s1 += 2.0 / samples * cycle.tangential(j, 0) * std::sin(t(j));
            const double marched = -pi_ * U * s1;
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
    // there, and the first stuck sample j after them carries T = k_t (u_j - s_c), the slider
    // where u was when the contact closed: s_c = u_k + theta (u_j - u_k), k the last separated
    // sample, theta = g_k / (g_k - g_j) the linear interpolation of g = n_0 + k_n v to 0.
    const double kt = 3.0, kn = 2.0, mu = 0.4, n0 = 1.0, onset = n0 / kn;
    const ElasticContact element{kn, kt, mu, n0, 1};
    const int samples = 512;
    const Eigen::VectorXd t = phases(samples);
    const Eigen::MatrixXd u = 0.05 * (t.array() + 0.3).sin();
    for (const double ratio : {0.99, 1.01, 1.5}) {
        const Eigen::VectorXd v = ratio * onset * t.array().cos();
        const NormalContactCycle cycle = march(element, u, v);
        int separated = 0, mismatched = 0;
        for (int j = 0; j < samples; ++j) {
            const bool open = n0 + kn * v(j) <= 0.0;
            const bool reported = cycle.state[static_cast<std::size_t>(j)] == ContactState::separated;
            separated += reported ? 1 : 0;
            mismatched += open != reported ? 1 : 0;
            if (reported) CHECK(cycle.tangential(j, 0) == 0.0);
        }
        INFO("V = " << ratio << " n_0 / k_n: " << separated << " separated samples");
        CHECK(mismatched == 0);
        CHECK((separated > 0) == (ratio > 1.0));
        if (ratio > 1.0) {
            int last = -1;  // the last separated sample, then the first one after it
            for (int j = 0; j < samples; ++j)
                if (cycle.state[static_cast<std::size_t>(j)] == ContactState::separated) last = j;
            const int next = (last + 1) % samples;
            const double gk = n0 + kn * v(last), gj = n0 + kn * v(next), theta = gk / (gk - gj);
            // (just above the onset the load after closing is too small to hold it: it slips)
            if (ratio > 1.2) REQUIRE(cycle.state[static_cast<std::size_t>(next)] == ContactState::stuck);
            if (cycle.state[static_cast<std::size_t>(next)] == ContactState::stuck)
                CHECK(std::abs(cycle.tangential(next, 0) - kt * (1.0 - theta) * (u(next) - u(last))) < 1e-14);
        }
    }
}

TEST_CASE("Normal contact in permanent stick: the slider at the midpoint of its admissible interval",
          "[normal_contact]") {
    // Small tangential motion under a varying normal load: every sample sticks, and the slider
    // is the midpoint of max_j (u_j - mu N_j / k_t) .. min_j (u_j + mu N_j / k_t) (computed here
    // from the samples), so T_j = k_t (u_j - s).
    const double kt = 10.0, kn = 5.0, mu = 0.3, n0 = 2.0;
    const ElasticContact element{kn, kt, mu, n0, 1};
    const int samples = 200;
    const Eigen::VectorXd t = phases(samples);
    const Eigen::MatrixXd u = 0.02 * (t.array() + 0.7).cos() + 0.005 * (3.0 * t.array()).sin() + 0.1;
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
        CHECK(std::abs(cycle.tangential(j, 0) - kt * (u(j) - slider)) < 1e-14);
    }
}

TEST_CASE("Normal contact: the AFT Jacobian equals central differences in slip, stick and separation (2D and 3D)",
          "[normal_contact]") {
    // The forces are piecewise smooth in the samples on each pattern: central differences with
    // a step far below the distance of any sample to a switch equal the Jacobian to rounding
    // (1e-6 relative, as for the other laws). Regimes: gross slip with separation, partial slip
    // under a varying load, permanent stick (the slider's centre from two samples in 2D, from
    // two or three in 3D), and in 3D an elliptical motion whose slip direction turns.
    Fourier fourier(5, 96);
    const int n = 11;
    struct Case {
        const char* name;
        int d;
        std::vector<Eigen::VectorXd> signals;  // u_1, (u_2,) v
    };
    const Case cases[] = {
        {"2D slip and separation", 1, {signal(5, 0.0, 1.0, 0.4, 0.2, 0.1), signal(5, -0.12, 0.45, -0.3, 0.05, 0.02)}},
        {"2D partial slip", 1, {signal(5, 0.2, 0.3, 0.1, 0.05, 0.02), signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)}},
        {"2D permanent stick", 1, {signal(5, 0.2, 0.02, 0.01, 0.004, 0.002), signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)}},
        {"3D elliptical slip", 2,
         {signal(5, 0.1, 1.0, 0.2, 0.1, 0.05), signal(5, -0.2, 0.3, 0.8, -0.1, 0.02), signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)}},
        {"3D slip and separation", 2,
         {signal(5, 0.0, 1.0, 0.4, 0.2, 0.1), signal(5, 0.1, -0.4, 0.6, 0.05, 0.03),
          signal(5, -0.12, 0.45, -0.3, 0.05, 0.02)}},
        {"3D partial slip", 2,
         {signal(5, 0.2, 0.3, 0.1, 0.05, 0.02), signal(5, 0.0, -0.02, 0.05, 0.01, 0.005),
          signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)}},
        {"3D permanent stick", 2,
         {signal(5, 0.2, 0.02, 0.01, 0.004, 0.002), signal(5, -0.1, -0.01, 0.015, 0.003, 0.001),
          signal(5, 0.0, 0.2, 0.1, 0.03, 0.01)}},
    };
    for (const Case& c : cases) {
        const ElasticContact element{2.0, 3.0, 0.4, 1.0, c.d};
        const int m = (c.d + 1) * n;
        Eigen::VectorXd q(m);
        for (int k = 0; k <= c.d; ++k) q.segment(k * n, n) = c.signals[static_cast<std::size_t>(k)];
        NormalContactEvaluation e;
        evaluate(element, fourier, q, e, true);
        Eigen::MatrixXd fd(m, m);
        const double h = 1e-7;
        for (int k = 0; k < m; ++k) {
            NormalContactEvaluation plus, minus;
            Eigen::VectorXd a = q, b = q;
            a(k) += h;
            b(k) -= h;
            evaluate(element, fourier, a, plus, false);
            evaluate(element, fourier, b, minus, false);
            fd.col(k) = (plus.force - minus.force) / (2.0 * h);
        }
        Eigen::MatrixXd u(96, c.d);
        Eigen::VectorXd v(96);
        for (int k = 0; k < c.d; ++k) fourier.to_time(q.segment(k * n, n), u.col(k));
        fourier.to_time(q.segment(c.d * n, n), v);
        const NormalContactCycle cycle = march(element, u, v);
        int counts[3] = {0, 0, 0};
        for (const ContactState s : cycle.state) ++counts[static_cast<int>(s)];
        const std::string name = c.name;
        INFO(name << ": " << counts[0] << " separated, " << counts[1] << " stuck, " << counts[2]
                  << " slipping; largest difference " << (e.jacobian - fd).cwiseAbs().maxCoeff());
        CHECK((e.jacobian - fd).cwiseAbs().maxCoeff() < 1e-6 * std::max(fd.cwiseAbs().maxCoeff(), 1.0));
        if (name.find("separation") != std::string::npos) CHECK((counts[0] > 0 && counts[2] > 0));
        if (name.find("partial") != std::string::npos) CHECK((counts[0] == 0 && counts[1] > 0 && counts[2] > 0));
        if (name.find("permanent") != std::string::npos) CHECK(cycle.permanent_stick);
        if (name.find("elliptical") != std::string::npos) CHECK(counts[2] > 0);
    }
}

TEST_CASE("Normal contact in 3D: motion along one tangential line is the 2D element, in any direction",
          "[normal_contact]") {
    // u = (cos a, sin a) u_1D: the 3D element's forces are (cos a, sin a) times the 2D element's
    // and its states the same (slip, separation, and permanent stick, whose centre of collinear
    // circles is the 2D midpoint).
    const int samples = 240;
    const Eigen::VectorXd t = phases(samples);
    for (const double amplitude : {1.0, 0.02}) {
        const Eigen::VectorXd line = amplitude * ((t.array() + 0.4).cos() + 0.3 * (2.0 * t.array()).sin());
        const Eigen::VectorXd v = 0.35 * t.array().cos() - 0.1;  // separates at amplitude 1? n_0 + k_n v
        for (const double n0 : {1.0, 0.5}) {
            const ElasticContact flat{2.0, 3.0, 0.4, n0, 1}, spatial{2.0, 3.0, 0.4, n0, 2};
            const NormalContactCycle reference = march(flat, line, v);
            for (const double angle : {0.0, 0.7, 2.5}) {
                Eigen::MatrixXd u(samples, 2);
                u.col(0) = std::cos(angle) * line;
                u.col(1) = std::sin(angle) * line;
                const NormalContactCycle cycle = march(spatial, u, v);
                double worst = 0.0;
                int differing = 0;
                for (int j = 0; j < samples; ++j) {
                    worst = std::max({worst, std::abs(cycle.tangential(j, 0) - std::cos(angle) * reference.tangential(j, 0)),
                                      std::abs(cycle.tangential(j, 1) - std::sin(angle) * reference.tangential(j, 0))});
                    if (cycle.state[static_cast<std::size_t>(j)] != reference.state[static_cast<std::size_t>(j)])
                        ++differing;
                }
                INFO("amplitude " << amplitude << ", n_0 " << n0 << ", angle " << angle << ": largest difference "
                                  << worst << ", permanent stick " << reference.permanent_stick);
                CHECK(worst < 1e-12);
                CHECK(differing == 0);
                CHECK(cycle.permanent_stick == reference.permanent_stick);
                CHECK((cycle.normal - reference.normal).cwiseAbs().maxCoeff() == 0.0);
            }
        }
    }
}

TEST_CASE("Normal contact in 3D: rotating the tangential plane rotates the forces (isotropy)", "[normal_contact]") {
    // A generic motion (elliptical, with harmonics) rotated by R(a) in the tangential plane: the
    // forces are R(a) times the unrotated ones, the states unchanged, and the Jacobian
    // blocks rotate likewise: J' = Q J Q^T, Q = R(a) on the tangential signals. Three regimes.
    Fourier fourier(5, 120);
    const int n = 11, m = 33;
    const ElasticContact element{2.0, 3.0, 0.4, 1.0, 2};
    const double scales[] = {1.0, 0.3, 0.02};  // gross slip with separation, partial slip, stick
    for (const double scale : scales) {
        Eigen::VectorXd q(m);
        q.segment(0, n) = scale * signal(5, 0.1, 1.0, 0.2, 0.1, 0.05);
        q.segment(n, n) = scale * signal(5, -0.2, 0.3, 0.8, -0.1, 0.02);
        q.segment(2 * n, n) = signal(5, scale > 0.5 ? -0.12 : 0.0, 0.45, -0.3, 0.05, 0.02);
        NormalContactEvaluation base;
        evaluate(element, fourier, q, base, true);
        for (const double angle : {0.3, 1.9, -2.8}) {
            const double c = std::cos(angle), s = std::sin(angle);
            Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(m, m);
            Q.block(0, 0, n, n) *= c;
            Q.block(0, n, n, n) = -s * Eigen::MatrixXd::Identity(n, n);
            Q.block(n, 0, n, n) = s * Eigen::MatrixXd::Identity(n, n);
            Q.block(n, n, n, n) *= c;
            NormalContactEvaluation turned;
            evaluate(element, fourier, Q * q, turned, true);
            INFO("scale " << scale << ", angle " << angle);
            CHECK((turned.force - Q * base.force).cwiseAbs().maxCoeff() < 1e-10 * base.force.cwiseAbs().maxCoeff());
            CHECK((turned.jacobian - Q * base.jacobian * Q.transpose()).cwiseAbs().maxCoeff() <
                  1e-9 * base.jacobian.cwiseAbs().maxCoeff());
        }
    }
}

TEST_CASE("Normal contact in 3D: circular motion slides steadily, against the closed form", "[normal_contact]") {
    // u = U (cos t, sin t), constant N = N_0, k_t U > mu N_0. Derived: in steady sliding the
    // force has the constant size mu N_0 and is parallel to the slider's velocity; the slider
    // s = u - (mu N_0 / k_t) n turns on a circle of radius rho, its velocity tangent to that
    // circle, so u - s is perpendicular to s: U^2 = rho^2 + (mu N_0 / k_t)^2, and the energy
    // dissipated per cycle is mu N_0 2 pi rho. The march is a return map on the samples: every
    // sample slips with |T_j| = mu N_0 exactly, the cycle turns with the samples (T_{j+1} =
    // R(2 pi / N_t) T_j), and its energy pi U (c_1(T_2) - s_1(T_1)) tends to the closed form as
    // N_t grows.
    const double kt = 4.0, mu = 0.5, n0 = 2.0, U = 0.6, c = mu * n0 / kt;
    const double closed = mu * n0 * 2.0 * pi_ * std::sqrt(U * U - c * c);
    const ElasticContact element{10.0, kt, mu, n0, 2};
    double previous = 0.0;
    for (const int samples : {128, 512, 2048}) {
        const Eigen::VectorXd t = phases(samples);
        Eigen::MatrixXd u(samples, 2);
        u.col(0) = U * t.array().cos();
        u.col(1) = U * t.array().sin();
        const NormalContactCycle cycle = march(element, u, Eigen::VectorXd::Zero(samples));
        const double step = 2.0 * pi_ / samples;
        double size_error = 0.0, turn_error = 0.0, c1 = 0.0, s1 = 0.0;
        int slipping = 0;
        for (int j = 0; j < samples; ++j) {
            const Eigen::Vector2d f = cycle.tangential.row(j).transpose();
            const Eigen::Vector2d g = cycle.tangential.row((j + 1) % samples).transpose();
            const Eigen::Vector2d turned(std::cos(step) * f(0) - std::sin(step) * f(1),
                                         std::sin(step) * f(0) + std::cos(step) * f(1));
            size_error = std::max(size_error, std::abs(f.norm() - mu * n0));
            turn_error = std::max(turn_error, (g - turned).norm());
            slipping += cycle.state[static_cast<std::size_t>(j)] == ContactState::slipping ? 1 : 0;
            c1 += 2.0 / samples * f(1) * std::cos(t(j));
            s1 += 2.0 / samples * f(0) * std::sin(t(j));
        }
        const double energy = pi_ * U * (c1 - s1), error = std::abs(energy - closed);
        INFO(samples << " samples: energy " << energy << " against " << closed << ", |T| error " << size_error
                     << ", turn error " << turn_error);
        CHECK(slipping == samples);
        CHECK(size_error < 1e-13);
        CHECK(turn_error < 1e-10);
        // First order in the sample spacing (the slip direction turns between samples):
        // measured 1.1 %, 0.28 % and 0.070 % at 128, 512 and 2048 samples.
        CHECK(error < 0.02 * closed);
        if (samples > 128) CHECK(error < previous / 3.0);
        previous = error;
    }
}

TEST_CASE("Normal contact in 3D permanent stick: the slider has the largest margin", "[normal_contact]") {
    // Every sample sticks, and the slider minimises max_j (|s - u_j| - r_j), r_j = mu N_j / k_t
    // (convex in s): no move of 1e-6 of the motion's size in 16 directions lowers it.
    const double kt = 10.0, kn = 5.0, mu = 0.3, n0 = 2.0;
    const ElasticContact element{kn, kt, mu, n0, 2};
    const int samples = 300;
    const Eigen::VectorXd t = phases(samples);
    Eigen::MatrixXd u(samples, 2);
    u.col(0) = 0.02 * (t.array() + 0.7).cos() + 0.005 * (3.0 * t.array()).sin() + 0.1;
    u.col(1) = 0.012 * (t.array() - 0.2).sin() - 0.004 * (2.0 * t.array()).cos();
    const Eigen::VectorXd v = 0.2 * (t.array() + 1.0).cos();
    const NormalContactCycle cycle = march(element, u, v);
    REQUIRE(cycle.permanent_stick);
    auto worst = [&](const Eigen::Vector2d& s) {
        double value = -1e300;
        for (int j = 0; j < samples; ++j)
            value = std::max(value, (s - u.row(j).transpose()).norm() - mu * (n0 + kn * v(j)) / kt);
        return value;
    };
    const Eigen::Vector2d s = cycle.slider;
    const double best = worst(s);
    CHECK(best < 0.0);  // admissible
    for (int k = 0; k < 16; ++k) {
        const double a = 2.0 * pi_ * k / 16.0;
        CHECK(worst(s + 2e-8 * Eigen::Vector2d(std::cos(a), std::sin(a))) >= best - 1e-15);
    }
    for (int j = 0; j < samples; ++j) {
        CHECK(cycle.state[static_cast<std::size_t>(j)] == ContactState::stuck);
        CHECK((cycle.tangential.row(j).transpose() - kt * (u.row(j).transpose() - s)).norm() < 1e-14);
    }
}

TEST_CASE("Normal contact: parameters out of range are refused, naming the parameter", "[normal_contact]") {
    const Eigen::MatrixXd u = Eigen::MatrixXd::Zero(8, 1);
    const Eigen::VectorXd v = Eigen::VectorXd::Zero(8);
    const struct {
        ElasticContact element;
        const char* key;
    } bad[] = {{{0.0, 1.0, 0.3, 1.0, 1}, "normal_stiffness"},
               {{1.0, -1.0, 0.3, 1.0, 1}, "tangential_stiffness"},
               {{1.0, 1.0, -0.1, 1.0, 1}, "friction_coefficient"},
               {{1.0, 1.0, 0.3, NAN, 1}, "normal_offset"},
               {{1.0, 1.0, 0.3, 1.0, 3}, "tangential_directions"}};
    for (const auto& b : bad) CHECK_THROWS_WITH(march(b.element, u, v), Catch::Contains(b.key));
    CHECK_THROWS_AS(march({1.0, 1.0, 0.3, 1.0, 1}, u, Eigen::VectorXd::Zero(7)), InvalidInput);
    CHECK_THROWS_AS(march({1.0, 1.0, 0.3, 1.0, 2}, u, v), InvalidInput);  // u has one column
}
