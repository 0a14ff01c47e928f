// The elastic friction contact with a normal direction (law `elastic`, issue 31) inside
// harmonic balance: its constant-normal-load limit against Jenkins, the exact Jacobians of both
// formulations, lift-off, the energy balance, and bad input.
#include <catch2/catch.hpp>

#include <cmath>

#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/stability.hpp"
#include "hbf/static_state.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

const FrictionLaw elastic = parse_friction_law("elastic");

/// The paper's absorber (default parameters) with a third DOF y3: a mass m3 on a spring k3 to
/// the ground, the normal coordinate of the absorber's contact (the contact pushes it by N).
/// The tangential and normal motions are uncoupled but through the contact.
System absorber_with_normal(double mu, double normal_stiffness, double preload, double gap = 0.0) {
    const System two = friction_absorber(AbsorberParameters{}, FrictionLaw::jenkins);
    const Eigen::MatrixXd m2(two.mass), k2(two.stiffness);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3, 3), k = Eigen::MatrixXd::Zero(3, 3);
    m.topLeftCorner(2, 2) = m2;
    k.topLeftCorner(2, 2) = k2;
    m(2, 2) = 0.5;
    k(2, 2) = 2.0;
    System s;
    s.mass = sparse(m);
    s.damping = SparseMatrix(3, 3);
    s.stiffness = sparse(k);
    s.excitation = Eigen::Vector3d(two.excitation(0), 0.0, 0.0);
    Contact c;
    c.law = elastic;
    c.dof = 0;
    c.other_dof = 1;
    c.stiffness = two.contacts[0].stiffness;
    c.values["normal_stiffness"] = normal_stiffness;
    c.values["friction_coefficient"] = mu;
    if (preload > 0.0) c.values["preload"] = preload;
    if (gap > 0.0) c.values["gap"] = gap;
    c.lists["normal_direction"] = {0.0, 0.0, 1.0};
    s.contacts.push_back(c);
    return s;
}

}  // namespace

TEST_CASE("elastic contact: with a static normal coordinate the 2D element is the Jenkins absorber, "
          "F_c = mu N, to 1e-8 (both formulations)",
          "[elastic_contact]") {
    // Statically k3 v + (N_0 + k_n v) = 0 (the contact's force N acts along +e3 in
    // M y'' + K y + w N = F), so v = -N_0 / (k3 + k_n) and N = N_0 k3 / (k3 + k_n): 2/10 N_0.
    // The tangential motion does not move y3 (N does not depend on u), so N stays constant
    // and the element is Jenkins with F_c = mu N. With mu = 0.5, N_0 = 2: F_c = 0.2, the
    // preset's Jenkins absorber.
    const double mu = 0.5, kn = 8.0, n0 = 2.0, k3 = 2.0;
    const System contact = absorber_with_normal(mu, kn, n0);
    const System jenkins = friction_absorber(AbsorberParameters{}, FrictionLaw::jenkins);
    REQUIRE(std::abs(mu * n0 * k3 / (k3 + kn) - jenkins.contacts[0].friction_limit) < 1e-15);
    const double v0 = -n0 / (k3 + kn);
    for (Formulation formulation : {Formulation::condensed, Formulation::full}) {
        HarmonicBalance a(jenkins, HarmonicBalanceOptions{10, 0, formulation});
        HarmonicBalance b(contact, HarmonicBalanceOptions{10, 0, formulation});
        const int n = a.coefficients();
        REQUIRE(b.unknowns() == a.unknowns() + n);
        CorrectorOptions options;
        Corrector ca(a, options), cb(b, options);
        // stick (0.6), stick-slip and slip near the resonances
        for (double omega : {0.6, 0.93, 1.0, 1.08, 1.4}) {
            INFO(to_string(formulation) << " w = " << omega);
            Eigen::VectorXd xa = a.linear_guess(omega), xb = b.linear_guess(omega);
            // the first guess carries the static normal deflection on harmonic 0
            const Eigen::VectorXd vb = b.relative(xb, 0).tail(n);
            CHECK(std::abs(vb(0) - v0) <= 1e-14);
            int iterations = 0;
            double ra = 0, rb = 0;
            REQUIRE(ca.solve_at(xa, omega, a.unknown_scale(xa), iterations, ra));
            REQUIRE(cb.solve_at(xb, omega, b.unknown_scale(xb), iterations, rb));
            const Eigen::VectorXd qa = a.relative(xa, 0), qb = b.relative(xb, 0);
            const double size = qa.cwiseAbs().maxCoeff();
            CHECK((qb.head(n) - qa).cwiseAbs().maxCoeff() <= 1e-8 * size);
            Eigen::VectorXd normal = qb.tail(n);
            normal(0) -= v0;
            CHECK(normal.cwiseAbs().maxCoeff() <= 1e-12);
            const Eigen::MatrixXd ya = a.dofs(xa, omega), yb = b.dofs(xb, omega);
            CHECK((ya.col(0) - yb.col(0)).cwiseAbs().maxCoeff() <= 1e-8 * ya.col(0).cwiseAbs().maxCoeff());
        }
    }
}

TEST_CASE("elastic contact: the exact Jacobians of both formulations against central differences, "
          "2D and 3D, through stick, slip and separation",
          "[elastic_contact]") {
    // A 4-DOF structure: y1, y2 tangential, y3 normal, y4 a second mass on y1.
    Eigen::MatrixXd m = Eigen::Vector4d(1.0, 0.7, 0.5, 0.3).asDiagonal();
    Eigen::MatrixXd k(4, 4);
    k << 3.0, 0.0, 0.0, -1.0,  //
        0.0, 2.0, 0.0, 0.0,    //
        0.0, 0.0, 2.5, 0.0,    //
        -1.0, 0.0, 0.0, 1.0;
    Eigen::MatrixXd c = 0.02 * k;
    for (int directions : {1, 2}) {
        System s;
        s.mass = sparse(m);
        s.damping = sparse(c);
        s.stiffness = sparse(k);
        s.excitation = Eigen::Vector4d(1.0, 0.4, 0.6, 0.0);
        Contact contact;
        contact.law = elastic;
        contact.dof = 0;
        contact.stiffness = 2.0;
        contact.values["normal_stiffness"] = 4.0;
        contact.values["friction_coefficient"] = 0.4;
        contact.values["preload"] = 0.3;
        if (directions == 2) contact.lists["second_direction"] = {0.0, 1.0, 0.0, 0.0};
        contact.lists["normal_direction"] = {0.0, 0.0, 1.0, 0.0};
        s.contacts.push_back(contact);
        for (Formulation formulation : {Formulation::condensed, Formulation::full}) {
            HarmonicBalance hb(s, HarmonicBalanceOptions{4, 64, formulation});
            const int n = hb.coefficients();
            // a state that separates (normal amplitude 0.3 against a preload over k_n of 0.075)
            // and slips: harmonic 1 of each signal or DOF, a mean and a little harmonic 2
            Eigen::VectorXd x = Eigen::VectorXd::Zero(hb.unknowns());
            for (int signal = 0; signal < hb.unknowns() / n; ++signal) {
                x(signal * n + 1) = 0.3 * std::cos(1.0 + signal);
                x(signal * n + 2) = 0.25 * std::sin(2.0 + signal);
                x(signal * n + 3) = 0.02 * (signal + 1);
                x(signal * n) = -0.01 * signal;
            }
            Eigen::VectorXd r, r_omega, fd_omega;
            Eigen::MatrixXd j, fd;
            hb.evaluate(x, 1.3, r, &j, &r_omega);
            hbf::test::central_differences(hb, x, 1.3, fd, fd_omega, 1e-7);
            INFO(directions << " tangential direction(s), " << to_string(formulation));
            const double scale = j.cwiseAbs().maxCoeff();
            CHECK((j - fd).cwiseAbs().maxCoeff() <= 1e-6 * scale);
            CHECK((r_omega - fd_omega).cwiseAbs().maxCoeff() <= 1e-6 * std::max(1.0, r_omega.cwiseAbs().maxCoeff()));
            // the sample states include separation and slip
            const Eigen::VectorXd phi = hb.stick_indicator(x, 1.3, 0);
            CHECK(phi.maxCoeff() == 1.0);                              // separated
            CHECK((phi.array() == 0.0).count() > 0);                   // slipping
        }
    }
}

TEST_CASE("elastic contact: bad parameters and directions are refused, naming the contact and the key",
          "[elastic_contact]") {
    const System good = absorber_with_normal(0.5, 8.0, 2.0);
    REQUIRE_NOTHROW(good.validate());
    auto refused = [&](const std::string& what, auto change) {
        System s = good;
        change(s.contacts[0]);
        INFO(what);
        try {
            s.validate();
            FAIL("accepted");
        } catch (const InvalidInput& e) {
            const std::string message = e.what();
            INFO(message);
            CHECK(message.find("contact 1: ") == 0);
            CHECK(message.find(what) != std::string::npos);
        }
    };
    refused("friction_coefficient", [](Contact& c) { c.values["friction_coefficient"] = -0.1; });
    refused("normal_stiffness", [](Contact& c) { c.values["normal_stiffness"] = 0.0; });
    refused("normal_stiffness", [](Contact& c) { c.values.erase("normal_stiffness"); });
    refused("preload", [](Contact& c) { c.values["preload"] = -1.0; });
    refused("preload", [](Contact& c) { c.values["gap"] = 0.1; });  // both given
    refused("normal_direction", [](Contact& c) { c.lists["normal_direction"] = {0.0, 0.0, 0.0}; });
    refused("normal_direction", [](Contact& c) { c.lists["normal_direction"] = {0.0, 1.0}; });
    refused("normal_direction", [](Contact& c) { c.lists["normal_direction"] = {1.0, 0.0, 1.0}; });  // not orthogonal
    refused("normal_direction", [](Contact& c) { c.lists.erase("normal_direction"); });
    refused("second_direction", [](Contact& c) { c.lists["second_direction"] = {0.0, 0.0, 0.5}; });
    refused("friction_limit", [](Contact& c) { c.friction_limit = 0.2; });
    refused("dof", [](Contact& c) { c.dof = 7; });
    // the exact solver of 1D friction refuses the law up front; its stability comes from its own
    // orbit solver (test_elastic_exact.cpp)
    CHECK_THROWS_AS(exact_periodic_orbit(good, 1.0, Eigen::VectorXd::Zero(state_size(good))), InvalidInput);
    CHECK(stability_refusal(good).empty());
}

namespace {

/// A structure that imposes the contact's motion: two unit masses on springs kappa (1e9) to
/// the ground, forced by (kappa - w^2) (a, b) cos(w t): their motion is u = a cos, v = b cos up
/// to the contact forces over kappa (1e-9 of them).
System driven(double a, double b, double omega, const Contact& contact, int dofs = 2) {
    const double kappa = 1e9;
    System s;
    s.mass = sparse(Eigen::MatrixXd::Identity(dofs, dofs));
    s.damping = SparseMatrix(dofs, dofs);
    s.stiffness = sparse(kappa * Eigen::MatrixXd::Identity(dofs, dofs));
    s.excitation = Eigen::VectorXd::Zero(dofs);
    s.excitation(0) = (kappa - omega * omega) * a;
    s.excitation(dofs - 1) = (kappa - omega * omega) * b;
    s.contacts.push_back(contact);
    return s;
}

Contact elastic_element(double kt, double kn, double mu, double n0, int dofs = 2) {
    Contact c;
    c.law = elastic;
    c.dof = 0;
    c.stiffness = kt;
    c.values["normal_stiffness"] = kn;
    c.values["friction_coefficient"] = mu;
    c.values["preload"] = n0;
    c.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(dofs), 0.0);
    c.lists["normal_direction"].back() = 1.0;
    return c;
}

/// Solves harmonic balance at omega from `start` (empty: the linear guess); the point and
/// its metrics.
PointMetrics solve(HarmonicBalance& hb, double omega, SolutionPoint& p, const Eigen::VectorXd& start = {}) {
    Corrector corrector(hb, CorrectorOptions{});
    p.x = start.size() > 0 ? start : hb.linear_guess(omega);
    p.omega = omega;
    INFO("solve at w = " << omega);
    REQUIRE(corrector.solve_at(p.x, omega, hb.unknown_scale(p.x), p.iterations, p.residual));
    return Analyser(hb, {0})(p);
}

/// The largest difference between the first harmonics of every DOF of a harmonic-balance point
/// and of an integrated orbit, relative to the orbit's largest.
double first_harmonic_gap(HarmonicBalance& hb, const SolutionPoint& p, const PeriodicResponse& orbit) {
    const Eigen::MatrixXd y = hb.dofs(p.x, p.omega);
    double worst = 0;
    for (Eigen::Index i = 0; i < y.cols(); ++i)
        worst = std::max(worst, std::abs(std::complex<double>(y(1, i), -y(2, i)) - orbit.harmonic1(i)));
    return worst / orbit.harmonic1.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("elastic contact: tangential and normal motion in phase (Yang and Menq): the loop and the energy per "
          "cycle of the closed form, converging at second order in the time samples",
          "[elastic_contact]") {
    // u = a cos(theta), v = b cos(theta), N = N_0 + k_n b cos(theta) > 0 (k_n b < N_0), and
    // k_t a > mu k_n b (the cone shrinks more slowly than the spring unloads). From the reversal
    // at theta = 0 (T = mu N(0)) the element sticks, T = mu (N_0 + k_n b) + k_t a (cos - 1),
    // until T = -mu N at cos(theta_1) = c_1 = (k_t a - 2 mu N_0 - mu k_n b) / (k_t a + mu k_n b),
    // then slips with T = -mu N (its slider moves with s' = -sin (a + mu k_n b / k_t) < 0) to the
    // reversal at pi; sticks, T = -mu (N_0 - k_n b) + k_t a (1 + cos), until T = mu N at
    // c_2 = (2 mu N_0 - mu k_n b - k_t a) / (k_t a - mu k_n b), and slips with T = mu N to 2 pi.
    // Slip occurs iff k_t a > mu N_0 (c_1 > -1, c_2 < 1), as for a constant load. The energy
    // per cycle, W = closed integral of T du = a closed integral of T dc (c = cos theta), is
    // the sum of the four segments' integrals below.
    const double kt = 2.0, kn = 3.0, mu = 0.4, n0 = 1.0, a = 1.0, b = 0.25, omega = 1.0;
    const double c1 = (kt * a - 2 * mu * n0 - mu * kn * b) / (kt * a + mu * kn * b);
    const double c2 = (2 * mu * n0 - mu * kn * b - kt * a) / (kt * a - mu * kn * b);
    const double energy = a * ((mu * (n0 + kn * b) - kt * a) * (c1 - 1) + kt * a * (c1 * c1 - 1) / 2) -
                          a * mu * (n0 * (-1 - c1) + kn * b * (1 - c1 * c1) / 2) +
                          a * ((kt * a - mu * (n0 - kn * b)) * (c2 + 1) + kt * a * (c2 * c2 - 1) / 2) +
                          a * mu * (n0 * (1 - c2) + kn * b * (1 - c2 * c2) / 2);
    auto loop = [&](double theta) {  // T(theta) of the closed form
        const double c = std::cos(theta), wrapped = std::fmod(theta, 2 * M_PI);
        if (wrapped <= std::acos(c1)) return mu * (n0 + kn * b) + kt * a * (c - 1);
        if (wrapped <= M_PI) return -mu * (n0 + kn * b * c);
        if (wrapped <= 2 * M_PI - std::acos(c2)) return -mu * (n0 - kn * b) + kt * a * (1 + c);
        return mu * (n0 + kn * b * c);
    };
    const System s = driven(a, b, omega, elastic_element(kt, kn, mu, n0));
    double previous = 0;
    for (int samples : {1024, 4096, 16384}) {
        HarmonicBalance hb(s, HarmonicBalanceOptions{20, samples});
        SolutionPoint p;
        const PointMetrics m = solve(hb, omega, p);
        const double error = std::abs(m.energy / energy - 1.0);
        INFO("N_t = " << samples << ": W = " << m.energy << " against " << energy << ", error " << error);
        // the trapezoidal rule of the AFT on a force with kinks: second order, with a
        // coefficient that depends on where the kinks fall between samples (measured 2.4e-6,
        // 1.3e-7, 1.3e-8 here)
        CHECK(error * samples * samples <= 4.0);
        if (samples >= 4096) CHECK(error <= 1e-6);
        if (previous > 0) CHECK(error < previous / 8);
        previous = error;
        CHECK(m.contacts[0].separated_fraction == 0.0);
        CHECK(std::abs(m.contacts[0].normal_mean - n0) <= 1e-8);
        CHECK(std::abs(m.contacts[0].normal_amplitude - kn * b) <= 1e-8);
        CHECK(m.energy_error <= 1e-9);
        // the loop: the marched samples are the closed form's (the motion's error, 1e-9)
        const Eigen::VectorXd t = hb.force_samples(p.x, omega, 0).head(samples);
        double worst = 0;
        for (int j = 0; j < samples; ++j) worst = std::max(worst, std::abs(t(j) - loop(2 * M_PI * j / samples)));
        CHECK(worst <= 1e-8);
    }
}

TEST_CASE("elastic contact: separation starts where the normal amplitude reaches the static normal force over "
          "k_n (closed form), to 1e-8 in w",
          "[elastic_contact]") {
    // y1 tangential, y2 normal, unit masses on unit springs, uncoupled but through the contact;
    // F = (f1, f2) cos(w t). Closed, y2 is linear: k2 v_0 + N_0 + k_n v_0 = 0 gives the static
    // force N_s = N_0 k2 / (k2 + k_n), and (k2 + k_n - w^2) V = f2 its amplitude: N = N_s +
    // k_n V cos, so separation starts where k_n |V| = N_s, below the normal resonance at
    // w^2 = k2 + k_n - f2 k_n (k2 + k_n) / (N_0 k2).
    const double kt = 1.0, kn = 3.0, mu = 0.3, n0 = 1.0, k2 = 1.0, f2 = 0.1;
    const double onset = std::sqrt(k2 + kn - f2 * kn * (k2 + kn) / (n0 * k2));
    System s = driven(0.0, 0.0, 1.0, elastic_element(kt, kn, mu, n0));
    s.stiffness = sparse(Eigen::Matrix2d::Identity());
    s.damping = sparse(Eigen::Vector2d(0.05, 0.0).asDiagonal());  // on y1 only: y2 stays as above
    s.excitation = Eigen::Vector2d(0.2, f2);
    HarmonicBalance hb(s, HarmonicBalanceOptions{10, 0});
    // from 0.8 of the onset in small steps (each solve from the last), then by bisection, each
    // solve from the last closed point below the onset
    Eigen::VectorXd closed;
    auto margin = [&](double omega, const Eigen::VectorXd& start) {  // min N / N_s
        SolutionPoint p;
        const PointMetrics m = solve(hb, omega, p, start);
        if (m.contacts[0].separated_fraction == 0.0) closed = p.x;
        return std::make_pair((m.contacts[0].normal_mean - m.contacts[0].normal_amplitude) / (n0 * k2 / (k2 + kn)),
                              m.contacts[0].separated_fraction);
    };
    double low = 0.8 * onset, high = low;
    REQUIRE(margin(low, {}).first > 0.0);
    for (Eigen::VectorXd last = closed; margin(high, last).first > 1e-12; last = closed) {
        low = high;
        high += 0.013 * onset;  // not onto the onset itself (0.8 + 20 x 0.01)
        REQUIRE(high < 1.2 * onset);
    }
    {   // past the onset the contact opens: separated for part of the period
        SolutionPoint p;
        const PointMetrics m = solve(hb, high, p, closed);
        CHECK(m.contacts[0].separated_fraction > 0.0);
    }
    for (int i = 0; i < 60 && high - low > 1e-13; ++i) {
        const double middle = 0.5 * (low + high);
        const Eigen::VectorXd start = closed;
        (margin(middle, start).first > 1e-12 ? low : high) = middle;
    }
    INFO("onset by harmonic balance " << low << ", closed form " << onset);
    CHECK(std::abs(low - onset) <= 1e-8 * onset);
}

TEST_CASE("elastic contact 3D: rotating the tangential directions leaves the response unchanged (1e-10), and "
          "circular motion slides steadily as the closed form says, at first order in the samples",
          "[elastic_contact]") {
    // An anisotropic structure (y1, y2 tangential with different stiffnesses, y3 normal) forced
    // along y1 and y2: an elliptic tangential orbit whose slip direction turns.
    Eigen::MatrixXd m = Eigen::Vector3d(1.0, 1.2, 0.8).asDiagonal();
    Eigen::MatrixXd k = Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal();
    System s;
    s.mass = sparse(m);
    s.damping = sparse(0.02 * k);
    s.stiffness = sparse(k);
    s.excitation = Eigen::Vector3d(0.6, 0.5, 0.1);
    Contact c = elastic_element(1.5, 4.0, 0.3, 1.0, 3);
    c.lists["second_direction"] = {0.0, 1.0, 0.0};
    Contact rotated = c;
    const double angle = 0.7;
    rotated.direction = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0);
    rotated.lists["second_direction"] = {-std::sin(angle), std::cos(angle), 0.0};
    System r = s;
    s.contacts = {c};
    r.contacts = {rotated};
    for (double omega : {0.9, 1.1, 1.3}) {
        HarmonicBalance a(s, HarmonicBalanceOptions{8, 0}), b(r, HarmonicBalanceOptions{8, 0});
        SolutionPoint pa, pb;
        const PointMetrics ma = solve(a, omega, pa), mb = solve(b, omega, pb);
        const Eigen::MatrixXd ya = a.dofs(pa.x, omega), yb = b.dofs(pb.x, omega);
        INFO("w = " << omega << ": stick " << ma.contacts[0].stick_fraction << ", separated "
                    << ma.contacts[0].separated_fraction);
        CHECK((ya - yb).cwiseAbs().maxCoeff() <= 1e-10 * ya.cwiseAbs().maxCoeff());
        CHECK(std::abs(ma.energy - mb.energy) <= 1e-10 * std::abs(ma.energy));
        CHECK(std::abs(ma.contacts[0].stick_fraction - mb.contacts[0].stick_fraction) <= 1e-12);
        CHECK(ma.energy > 0.0);
    }
    // Circular motion u = a (cos, sin), constant N: the slider circles at radius
    // sqrt(a^2 - (mu N / k_t)^2) with T (|T| = mu N) along its velocity, so the energy per
    // cycle is 2 pi mu N sqrt(a^2 - (mu N / k_t)^2). Imposed by drivers: y1 on a stiff spring
    // kappa as above; y2 = a sin(w t) (complex amplitude -i a) by a driver at its own resonance
    // (stiffness w^2) with a large damper c, Z = i w c, forced by w c a cos(w t); the normal y3
    // held by kappa (N = N_0 to 1e-9). The return map is first order where the slip direction
    // turns (normal_contact.hpp).
    const double kt = 2.0, mu = 0.4, n0 = 1.0, radius = 0.5, kappa = 1e9, omega = 1.0;
    const double exact = 2 * M_PI * mu * n0 * std::sqrt(radius * radius - std::pow(mu * n0 / kt, 2));
    Contact circle = elastic_element(kt, 5.0, mu, n0, 3);
    circle.lists["second_direction"] = {0.0, 1.0, 0.0};
    System turning;
    turning.mass = sparse(Eigen::Matrix3d::Identity());
    turning.damping = sparse(Eigen::Vector3d(0.0, kappa, 0.0).asDiagonal());
    turning.stiffness = sparse(Eigen::Vector3d(kappa, omega * omega, kappa).asDiagonal());
    turning.excitation = Eigen::Vector3d((kappa - omega * omega) * radius, omega * kappa * radius, 0.0);
    turning.contacts = {circle};
    double previous = 0;
    for (int samples : {256, 1024, 4096}) {
        HarmonicBalance hb(turning, HarmonicBalanceOptions{10, samples});
        SolutionPoint p;
        const PointMetrics m = solve(hb, omega, p);
        const double error = std::abs(m.energy / exact - 1.0);
        INFO("N_t = " << samples << ": W = " << m.energy << " against " << exact);
        CHECK(m.contacts[0].stick_fraction == 0.0);
        CHECK(m.contacts[0].separated_fraction == 0.0);
        CHECK(std::abs(m.contacts[0].normal_amplitude) <= 1e-8);
        CHECK(error <= 3.0 / samples);  // first order (measured 1.1e-2 at 128, 7e-4 at 2048 on the element alone)
        if (previous > 0) CHECK(error < previous / 3.0);
        previous = error;
    }
}

TEST_CASE("elastic contact from a system file: examples/systems/liftoff3.toml passes through stick, stick-slip "
          "and lift-off, and bad keys and directions are refused with exit 2",
          "[elastic_contact][cli]") {
    const ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml";
    const ::test::fs::path out = dir.path / "frf.csv", summary = dir.path / "frf.json";
    const ::test::Result r = ::test::run_hbf(
        "frf --config '" + example + "' --out '" + out.string() + "' --summary '" + summary.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    // the JSON's contact summary: open for more than half the period somewhere above w = 2
    const nlohmann::json contacts = nlohmann::json::parse(::test::slurp(summary)).at("contacts");
    REQUIRE(contacts.size() == 1);
    CHECK(contacts[0].at("stick_fraction_max").get<double>() == 1.0);
    CHECK(contacts[0].at("separated_fraction_max").get<double>() > 0.5);
    CHECK(contacts[0].at("open_from_w").get<double>() > 2.0);
    CHECK(contacts[0].at("normal_force_amp_max").get<double>() > 0.0);
    const auto rows = ::test::parse_csv(::test::slurp(out));
    REQUIRE(rows.size() > 100);
    bool stick = false, slip = false, open = false;
    double worst = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        stick = stick || ::test::column(rows, rows[k], "stick_fraction") == 1.0;
        const double stuck = ::test::column(rows, rows[k], "stick_fraction");
        slip = slip || (stuck > 0.0 && stuck < 1.0);  // stick-slip
        open = open || ::test::column(rows, rows[k], "separated_fraction") > 0.0;
        worst = std::max(worst, ::test::column(rows, rows[k], "energy_error"));
        CHECK(::test::column(rows, rows[k], "normal_force_mean") > 0.0);  // N >= 0, and not always open
        CHECK(::test::column(rows, rows[k], "normal_force_amp") >= 0.0);
    }
    CHECK(stick);
    CHECK(slip);
    CHECK(open);
    CHECK(worst <= 1e-8);  // input work = viscous + friction dissipation on every point

    const std::string head = "[structure]\nmass = [1.0, 1.0]\nstiffness = [[2.0, 0.0], [0.0, 2.0]]\n"
                             "excitation = [1.0, 0.0]\n[[contact]]\ndof = 1\nlaw = \"elastic\"\nstiffness = 1.0\n";
    const std::string good = "normal_stiffness = 2.0\nfriction_coefficient = 0.3\npreload = 1.0\n";
    ::test::check_bad_config(head + good, {"normal_direction", "missing"}, dir);
    ::test::check_bad_config(head + good + "normal_direction = [0.0, 1.0]\nfriction_limit = 0.3\n",
                           {"contact[1].friction_limit", "does not apply to law 'elastic'"}, dir);
    ::test::check_bad_config(head + "normal_stiffness = 0.0\nfriction_coefficient = 0.3\nnormal_direction = [0.0, 1.0]\n",
                           {"contact[1]", "normal_stiffness", "> 0"}, dir);
    ::test::check_bad_config(head + "normal_stiffness = 2.0\nfriction_coefficient = -0.3\nnormal_direction = [0.0, 1.0]\n",
                           {"contact[1]", "friction_coefficient", ">= 0"}, dir);
    ::test::check_bad_config(head + good + "normal_direction = [0.6, 0.8]\n",
                           {"contact[1]", "normal_direction", "not orthogonal"}, dir);
    ::test::check_bad_config(head + good + "normal_direction = [1.0, 1.0]\n",
                           {"contact[1].normal_direction", "has length 1.414", "allowed a unit vector"}, dir);
    ::test::check_bad_config(head + good + "normal_direction = [0.0, 0.0]\n",
                           {"contact[1]", "normal_direction", "not all zero"}, dir);
    ::test::check_bad_config(head + good + "normal_direction = [0.0, 1.0, 0.0]\n",
                           {"contact[1].normal_direction", "3 entries", "allowed 2"}, dir);
    ::test::check_bad_input("frf --law elastic", {"law = elastic has no preset"}, dir);
}

TEST_CASE("elastic contact, time integration: with a static normal coordinate it is the Jenkins absorber's "
          "integration, and it refuses what it cannot integrate",
          "[elastic_contact][time_integration]") {
    // As in the first test: N stays N_0 k3 / (k3 + k_n), F_c = mu N = 0.2, so the elastic
    // integrator (its own events) and the Jenkins one (the general integrator) must agree.
    const System contact = absorber_with_normal(0.5, 8.0, 2.0);
    const System jenkins = friction_absorber(AbsorberParameters{}, FrictionLaw::jenkins);
    TimeIntegrationOptions options = hbf::test::tight_time_integration();
    for (double omega : {0.7, 0.95, 1.2}) {
        const PeriodicResponse a = integrate_steady_state(jenkins, omega, options);
        // the same start: Jenkins' steady state, the normal DOF at its static deflection
        Eigen::VectorXd start = Eigen::VectorXd::Zero(state_size(contact));
        start.head(2) = a.state.head(2);
        start(2) = -2.0 / 10.0;
        start.segment(3, 2) = a.state.segment(2, 2);
        start(6) = a.state(4);  // slider
        start(7) = 1.0;          // stuck (settled at t = 0)
        const PeriodicResponse b = integrate_steady_state(contact, omega, options, &start);
        INFO("w = " << omega << ": " << a.message << " / " << b.message);
        REQUIRE(a.converged);
        REQUIRE(b.converged);
        CHECK(std::abs(b.y_max[0] - a.y_max[0]) <= 1e-8 * a.y_max[0]);
        CHECK(std::abs(b.y_max[1] - a.y_max[1]) <= 1e-8 * a.y_max[1]);
        CHECK(std::abs(b.stick_fraction - a.stick_fraction) <= 1e-8);
        CHECK(std::abs(b.energy - a.energy) <= 1e-7 * std::max(a.energy, 1e-3));
        CHECK(b.contacts[0].separated_fraction == 0.0);
    }
    System mixed = contact;
    Contact other;
    other.law = FrictionLaw::jenkins;
    other.dof = 0;
    other.friction_limit = 0.1;
    other.stiffness = 1.0;
    mixed.contacts.push_back(other);
    CHECK_THROWS_WITH(integrate_steady_state(mixed, 1.0, options),
                      Catch::Contains("contact 2") && Catch::Contains("law elastic alone"));
}

TEST_CASE("elastic contact: harmonic balance against time integration on examples/systems/liftoff3.toml in "
          "stick, stick-slip and lift-off, converging in H",
          "[elastic_contact][time_integration]") {
    const System s = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    const Eigen::MatrixXd directions = s.contact_directions(s.contacts[0]);
    // the largest difference of the first harmonics of every DOF, relative, at H = 5, 10, 20, 40
    // (measured: stick 8.6e-11 at every H; stick-slip 3.9e-4, 4.5e-5, 6.5e-6, 1.6e-6; lift-off
    // 5.2e-4, 1.5e-4, 3.7e-5, 1.1e-5, with the slider placed where the contact closed between
    // two samples; at the last open sample instead it was 1.2e-3, 1.1e-3, 5.0e-5, 3.9e-5)
    struct Case {
        double omega;
        std::string regime;
        double bound_h40;
    };
    for (const Case& c : {Case{0.8, "stick", 1e-9}, Case{1.2, "stick-slip", 5e-6}, Case{2.8, "lift-off", 3e-5}}) {
        TimeIntegrationOptions options = hbf::test::tight_time_integration();
        const Eigen::VectorXd start = linear_stuck_state(s, c.omega);
        const PeriodicResponse ti = integrate_steady_state(s, c.omega, options, &start);
        INFO(c.regime << " at w = " << c.omega << ": " << ti.message);
        REQUIRE(ti.converged);
        CHECK(ti.energy_error <= 1e-8);
        if (c.regime == "stick") CHECK(ti.regime == "stick");
        if (c.regime == "stick-slip") CHECK((ti.regime == "stick-slip" && ti.contacts[0].separated_fraction == 0.0));
        if (c.regime == "lift-off") CHECK(ti.contacts[0].separated_fraction > 0.5);
        std::vector<double> errors;
        for (int harmonics : {5, 10, 20, 40}) {
            HarmonicBalance hb(s, HarmonicBalanceOptions{harmonics, 0});
            SolutionPoint p;
            const PointMetrics m = solve(hb, c.omega, p, hbf::test::from_orbit(hb, ti, directions));
            errors.push_back(first_harmonic_gap(hb, p, ti));
            CHECK(std::abs(m.contacts[0].separated_fraction - ti.contacts[0].separated_fraction) <= 0.02);
            CHECK(m.energy_error <= 1e-8);
        }
        INFO("H = 5, 10, 20, 40: " << errors[0] << ", " << errors[1] << ", " << errors[2] << ", " << errors[3]);
        CHECK(errors[3] <= c.bound_h40);
        if (c.regime != "stick") CHECK(errors[3] < errors[0] / 10);
    }
}

TEST_CASE("elastic contact 3D: harmonic balance converges to time integration at first order in the samples "
          "(the slip direction turns)",
          "[elastic_contact][time_integration]") {
    // The anisotropic structure of the isotropy test, sliding on an elliptic orbit at w = 1.1
    // (measured: 4.2e-3, 2.1e-3, 1.05e-3, 5.3e-4 at H = 5, 10, 20, 40, N_t = 4 (2H + 1)
    // rounded up: the return map's first order where the slip direction turns).
    System s;
    s.mass = sparse(Eigen::Vector3d(1.0, 1.2, 0.8).asDiagonal());
    s.damping = sparse(0.02 * Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal());
    s.stiffness = sparse(Eigen::Vector3d(1.0, 1.7, 2.0).asDiagonal());
    s.excitation = Eigen::Vector3d(0.6, 0.5, 0.1);
    Contact c = elastic_element(1.5, 4.0, 0.3, 1.0, 3);
    c.lists["second_direction"] = {0.0, 1.0, 0.0};
    s.contacts = {c};
    const double omega = 1.1;
    const Eigen::VectorXd start = linear_stuck_state(s, omega);
    const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration(), &start);
    INFO(ti.message);
    REQUIRE(ti.converged);
    CHECK(ti.regime == "slip");
    CHECK(ti.energy_error <= 1e-8);
    const Eigen::MatrixXd directions = s.contact_directions(s.contacts[0]);
    std::vector<double> errors;
    for (int harmonics : {5, 10, 20, 40}) {
        HarmonicBalance hb(s, HarmonicBalanceOptions{harmonics, 0});
        SolutionPoint p;
        solve(hb, omega, p, hbf::test::from_orbit(hb, ti, directions));
        errors.push_back(first_harmonic_gap(hb, p, ti));
    }
    INFO("H = 5, 10, 20, 40: " << errors[0] << ", " << errors[1] << ", " << errors[2] << ", " << errors[3]);
    for (std::size_t k = 1; k < errors.size(); ++k) CHECK(errors[k] == Approx(errors[k - 1] / 2).epsilon(0.15));
    CHECK(errors.back() <= 1e-3);
}

TEST_CASE("examples/systems/absorber_normal.toml: the paper's absorber whose contact has a still normal "
          "coordinate gives the Jenkins absorber's peaks to 1e-8",
          "[elastic_contact][cli]") {
    const ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/absorber_normal.toml";
    auto peaks = [&](const std::string& args) {
        const ::test::fs::path out = dir.path / "frf.csv", summary = dir.path / "summary.json";
        const ::test::Result r = ::test::run_hbf(args + " --error-points 0 --out '" + out.string() + "' --summary '" + summary.string() + "'", dir);
        INFO(args << ": " << r.err);
        REQUIRE(r.exit_code == 0);
        return nlohmann::json::parse(::test::slurp(summary)).at("peaks");
    };
    const nlohmann::json normal = peaks("frf --config '" + example + "'");
    const nlohmann::json jenkins = peaks("frf --law jenkins --exact off");
    REQUIRE(normal.size() == 4);
    REQUIRE(jenkins.size() == normal.size());
    for (std::size_t k = 0; k < normal.size(); ++k) {
        INFO("peak " << k << ": " << normal[k].dump() << " / " << jenkins[k].dump());
        CHECK(normal[k].at("refined").get<bool>());
        CHECK(std::abs(normal[k].at("w").get<double>() - jenkins[k].at("w").get<double>()) <= 1e-8);
        CHECK(std::abs(normal[k].at("y_max").get<double>() / jenkins[k].at("y_max").get<double>() - 1.0) <= 1e-8);
    }
}

// ---- static loads (System::static_load, static_state.hpp) ----

TEST_CASE("static state: liftoff3.toml's contact stuck, slipping and open under static loads, against the "
          "closed forms",
          "[elastic_contact][static_load]") {
    // K y + (T, N, 0) = F_s with N = N_0 + k_n y2 (N_0 = 1, k_n = 5) and the tangential force
    // T = k_t y1 (k_t = 3) while |T| <= mu N (mu = 0.3), T = mu N sign(y1) beyond, T = N = 0 open:
    // each a linear system, solved here and checked for its own conditions.
    System s = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    Eigen::Matrix3d k(Eigen::MatrixXd(s.stiffness));
    const double kt = 3.0, kn = 5.0, mu = 0.3, n0 = 1.0;
    struct Case {
        Eigen::Vector3d load;
        std::string state;
    };
    for (const Case& c : {Case{Eigen::Vector3d(0, 0, 0), "stuck"}, Case{Eigen::Vector3d(0.3, 0.2, 0), "slipping"},
                          Case{Eigen::Vector3d(-0.3, 0.2, 0), "slipping"}, Case{Eigen::Vector3d(0, -1.5, 0.1), "open"}}) {
        s.static_load = c.load;
        Eigen::Matrix3d a = k;
        Eigen::Vector3d rhs = c.load;
        if (c.state != "open") {
            a(1, 1) += kn;
            rhs(1) -= n0;
        }
        if (c.state == "stuck") a(0, 0) += kt;
        const double sign = c.load(0) >= 0 ? 1.0 : -1.0;  // the slip direction (checked below)
        if (c.state == "slipping") {
            a(0, 1) += sign * mu * kn;
            rhs(0) -= sign * mu * n0;
        }
        const Eigen::Vector3d y = a.fullPivLu().solve(rhs);
        const double normal = n0 + kn * y(1);
        INFO(c.state << " under " << c.load.transpose() << ": y = " << y.transpose() << ", N = " << normal);
        // the closed form's own conditions
        if (c.state == "open") CHECK(normal < 0.0);
        if (c.state == "stuck") CHECK(std::abs(kt * y(0)) < mu * normal);
        if (c.state == "slipping") CHECK((kt * y(0) * sign > mu * normal && normal > 0.0));
        const StaticState r = static_state(s);
        INFO(r.message);
        REQUIRE(r.ok);
        CHECK(r.contacts[0].state == c.state);
        CHECK((r.displacement - y).cwiseAbs().maxCoeff() <= 1e-12);
        CHECK(std::abs(r.contacts[0].force(1) - (c.state == "open" ? 0.0 : normal)) <= 1e-12);
    }
    // Bad input: a static load of the wrong size, or not finite, names the key.
    s.static_load = Eigen::Vector2d(1.0, 0.0);
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("static load vector has 2 entries"));
    s.static_load = Eigen::Vector3d(1.0, NAN, 0.0);
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("static load vector has non-finite entries"));
}

TEST_CASE("static state of the laws along one direction: Jenkins and Iwan clamp, Dahl's monotonic curve, exact "
          "Coulomb refused",
          "[static_load]") {
    // One DOF y on a spring k = 2 to the ground, the contact to the ground, a static load P.
    auto one = [](const Contact& c, double load) {
        System s;
        s.mass = sparse(Eigen::MatrixXd::Identity(1, 1));
        s.stiffness = sparse(2.0 * Eigen::MatrixXd::Identity(1, 1));
        s.damping = SparseMatrix(1, 1);
        s.excitation = Eigen::VectorXd::Constant(1, 0.1);
        s.static_load = Eigen::VectorXd::Constant(1, load);
        s.contacts.push_back(c);
        return s;
    };
    Contact jenkins;
    jenkins.law = FrictionLaw::jenkins;
    jenkins.stiffness = 3.0;
    jenkins.friction_limit = 0.5;
    // stuck: y = P / (k + k_t) with k_t y <= F_c; slipping: y = (P - F_c) / k
    StaticState r = static_state(one(jenkins, 0.5));
    REQUIRE(r.ok);
    CHECK(r.contacts[0].state == "stuck");
    CHECK(std::abs(r.displacement(0) - 0.5 / 5.0) <= 1e-14);
    r = static_state(one(jenkins, -2.0));
    REQUIRE(r.ok);
    CHECK(r.contacts[0].state == "slipping");
    CHECK(std::abs(r.displacement(0) - (-2.0 + 0.5) / 2.0) <= 1e-14);
    CHECK(std::abs(r.contacts[0].force(0) + 0.5) <= 1e-14);
    // Dahl: k y + F_c (1 - exp(-sigma0 y / F_c)) = P, presliding
    Contact dahl = jenkins;
    dahl.law = FrictionLaw::dahl;
    r = static_state(one(dahl, 1.0));
    REQUIRE(r.ok);
    const double y = r.displacement(0);
    CHECK(r.contacts[0].state == "presliding");
    CHECK(std::abs(2.0 * y + 0.5 * (1.0 - std::exp(-3.0 * y / 0.5)) - 1.0) <= 1e-12);
    // Iwan: the sum of its sliders' clamps; at a load far beyond its macro-slip force F_S it slips
    // with f = F_S: y = (P - F_S) / k
    Contact iwan = jenkins;
    iwan.law = parse_friction_law("iwan");
    r = static_state(one(iwan, 5.0));
    REQUIRE(r.ok);
    CHECK(r.contacts[0].state == "slipping");
    CHECK(std::abs(r.displacement(0) - (5.0 - 0.5) / 2.0) <= 1e-12);
    // exact Coulomb: no single-valued static force
    Contact coulomb = jenkins;
    coulomb.law = FrictionLaw::coulomb;
    r = static_state(one(coulomb, 0.2));
    CHECK(!r.ok);
    CHECK_THAT(r.message, Catch::Contains("law coulomb has no single-valued static force"));
}

TEST_CASE("static load in harmonic balance: a load whose free deflection is normal to the contact is a larger "
          "preload, the response shifted by that deflection (full, condensed and modal, preload and gap)",
          "[elastic_contact][static_load]") {
    // liftoff3.toml with the static load F_s = K d, d = (0, delta, 0): the structure without its
    // contact would deflect by d, along the contact's normal only. With y = y_B + d the equations
    // K y + e2 max(0, n_0 + k_n y2) + e1 T(y1) = F_s + F cos become those of y_B without the load
    // and with n_0 + k_n delta in place of n_0 (the tangential motion y1 unchanged): the same
    // periodic responses shifted by d, at every point (stick, stick-slip, lift-off), whatever the
    // permanent-stick convention (it sees the same tangential motion).
    const System file = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    const double delta = 0.1, kn = 5.0;
    const Eigen::Vector3d d(0.0, delta, 0.0);
    struct Case {
        double preload, gap;
    };
    for (const Case& c : {Case{1.0, 0.0}, Case{0.0, 0.05}}) {
        System loaded = file, shifted = file;
        loaded.contacts[0].values.erase("preload");
        if (c.preload > 0.0) loaded.contacts[0].values["preload"] = c.preload;
        if (c.gap > 0.0) loaded.contacts[0].values["gap"] = c.gap;
        loaded.static_load = Eigen::MatrixXd(file.stiffness) * d;
        shifted.contacts[0].values["preload"] = c.preload - kn * c.gap + kn * delta;  // n_0 + k_n delta > 0
        // the unknowns of a formulation from the DOFs' coefficients y ((2H+1) x N)
        const Eigen::MatrixXd w = loaded.contact_directions(loaded.contacts[0]);
        auto unknowns = [&](Formulation f, const Eigen::MatrixXd& y) {
            if (f == Formulation::full) return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(y.data(), y.size()));
            Eigen::VectorXd x(2 * y.rows());
            x << y * w.col(0), y * w.col(1);
            return x;
        };
        for (double omega : {0.6, 1.2, 2.2}) {
            // B (full) from its linear guess; the others from B's solution, A's shifted by d (from
            // their own linear guesses, the open contact's, the corrector misses some lift-off points)
            Eigen::MatrixXd yb0;
            // full, condensed by the sparse LU, condensed by the modal receptance (all 3 modes)
            for (const int variant : {0, 1, 2}) {
                const Formulation f = variant == 0 ? Formulation::full : Formulation::condensed;
                HarmonicBalanceOptions options{10, 0};
                options.formulation = f;
                options.modes = variant == 2 ? 3 : 0;
                HarmonicBalance a(loaded, options), b(shifted, options);
                SolutionPoint pa, pb;
                const PointMetrics mb = yb0.size() == 0 ? solve(b, omega, pb) : solve(b, omega, pb, unknowns(f, yb0));
                const Eigen::MatrixXd yb = b.dofs(pb.x, omega);
                if (yb0.size() == 0) yb0 = yb;
                Eigen::MatrixXd start = yb;
                start.row(0) += d.transpose();
                const PointMetrics ma = solve(a, omega, pa, unknowns(f, start));
                Eigen::MatrixXd ya = a.dofs(pa.x, omega);
                ya.row(0) -= d.transpose();
                const double gap = (ya - yb).cwiseAbs().maxCoeff() / yb.cwiseAbs().maxCoeff();
                INFO((c.gap > 0 ? "gap" : "preload") << ", " << (variant == 0 ? "full" : variant == 1 ? "condensed" : "modal")
                                                      << " at w = " << omega << ": relative difference " << gap
                                                      << ", regime " << ma.contacts[0].regime << ", open "
                                                      << ma.contacts[0].separated_fraction);
                CHECK(gap <= 1e-8);  // the corrector's tolerance
                CHECK(std::abs(ma.contacts[0].normal_mean - mb.contacts[0].normal_mean) <= 1e-8);
                CHECK(ma.energy_error <= 1e-8);
            }
        }
    }
}

TEST_CASE("static load: harmonic balance against time integration started from the static state, and the "
          "solvers that refuse a static load",
          "[elastic_contact][static_load][time_integration]") {
    // liftoff3.toml (coupled: the static load also loads the contact tangentially) with a static
    // load pressing the contact and pushing it sideways (the static state: stuck, N = 0.447,
    // |T| = 0.117). In stick-slip the periodic state is unique, and harmonic balance converges in H
    // to time integration (which starts from the static state). (In permanent stick they differ
    // by the mean tangential force: static_state.hpp.)
    System s = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    s.static_load = Eigen::Vector3d(0.1, 0.3, 0.0);
    const Eigen::MatrixXd directions = s.contact_directions(s.contacts[0]);
    for (double omega : {1.18, 2.2}) {
        const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration());
        INFO("w = " << omega << ": " << ti.message);
        REQUIRE(ti.converged);
        CHECK(ti.regime != "stick");
        std::vector<double> errors;
        for (int harmonics : {5, 40}) {
            HarmonicBalance hb(s, HarmonicBalanceOptions{harmonics, 0});
            SolutionPoint p;
            solve(hb, omega, p, hbf::test::from_orbit(hb, ti, directions));
            errors.push_back(first_harmonic_gap(hb, p, ti));
            // the mean: harmonic 0 of every DOF against the orbit's mean
            const Eigen::MatrixXd y = hb.dofs(p.x, omega);
            const Eigen::VectorXd mean = ti.displacement.colwise().mean();
            if (harmonics == 40) CHECK((y.row(0).transpose() - mean).cwiseAbs().maxCoeff() <= 1e-4);
        }
        INFO("H = 5, 40: " << errors[0] << ", " << errors[1]);
        CHECK(errors[1] <= 5e-5);
        CHECK(errors[1] < errors[0] / 5);
    }
    // odd harmonics drop harmonic 0; the general integrator and the exact solver carry no load
    HarmonicBalanceOptions odd{5, 0};
    odd.odd_harmonics = true;
    CHECK_THROWS_WITH(HarmonicBalance(s, odd), Catch::Contains("static load"));
    System jenkins = friction_absorber(AbsorberParameters{}, FrictionLaw::jenkins);
    jenkins.static_load = Eigen::Vector2d(0.1, 0.0);
    CHECK_THROWS_WITH(integrate_steady_state(jenkins, 1.0, TimeIntegrationOptions{}),
                      Catch::Contains("static load"));
    CHECK_THAT(exact_solver_refusal(jenkins), Catch::Contains("static load"));
}

TEST_CASE("static load from a system file: hbf frf reports the static state (stderr and JSON), bad loads exit 2",
          "[elastic_contact][static_load][cli]") {
    const ::test::TempDir dir;
    const std::string example =
        ::test::slurp(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml");
    const std::string anchor = "excitation = [0.05, 0.15, 0.0]\n";
    REQUIRE(example.find(anchor) != std::string::npos);
    auto with = [&](const std::string& line) {
        std::string text = example;
        return text.replace(text.find(anchor), anchor.size(), anchor + line);
    };
    const ::test::fs::path file = dir.path / "loaded.toml", out = dir.path / "frf.csv", summary = dir.path / "frf.json";
    ::test::write_file(file, with("static_load = [0.1, 0.3, 0.0]\n"));
    const ::test::Result r = ::test::run_hbf("frf --config '" + file.string() + "' --out '" + out.string() +
                                                 "' --summary '" + summary.string() + "'",
                                             dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.err, Catch::Contains("static state: contact 1: stuck"));
    // stuck: (K + diag(k_t, k_n, 0)) y = F_s - (0, N_0, 0), N = N_0 + k_n y2, T = k_t y1
    Eigen::Matrix3d k;
    k << 1.5 + 3.0, 0.5, -0.5, 0.5, 1.5 + 5.0, 0.0, -0.5, 0.0, 0.5;
    const Eigen::Vector3d y = k.fullPivLu().solve(Eigen::Vector3d(0.1, 0.3 - 1.0, 0.0));
    const nlohmann::json rest = nlohmann::json::parse(::test::slurp(summary)).at("static_state");
    CHECK(rest.at("solved").get<bool>());
    REQUIRE(rest.at("contacts").size() == 1);
    CHECK(rest.at("contacts")[0].at("state").get<std::string>() == "stuck");
    CHECK(std::abs(rest.at("contacts")[0].at("normal_force").get<double>() - (1.0 + 5.0 * y(1))) <= 1e-12);
    CHECK(std::abs(rest.at("contacts")[0].at("tangential_force").get<double>() - 3.0 * std::abs(y(0))) <= 1e-12);
    // the mean normal force of the FRF's first point (permanent stick at w = 0.3) near the static one
    const auto rows = ::test::parse_csv(::test::slurp(out));
    REQUIRE(rows.size() > 10);
    CHECK(std::abs(::test::column(rows, rows[1], "normal_force_mean") - (1.0 + 5.0 * y(1))) <= 0.05);

    ::test::check_bad_config(with("static_load = [0.1, 0.3]\n"), {"structure.static_load", "2", "3"}, dir);
    ::test::check_bad_config(with("static_load = [0.1, nan, 0.0]\n"), {"structure.static_load"}, dir);
    ::test::write_file(file, with("static_load = [0.1, 0.3, 0.0]\n"));
    ::test::check_bad_input("frf --config '" + file.string() + "' --harmonics odd", {"static load", "harmonic 0"}, dir);
    // the general integrator (a jenkins contact) carries no static load
    const ::test::fs::path jenkins = dir.path / "jenkins.toml";
    ::test::write_file(jenkins, "[structure]\nmass = [1.0]\nstiffness = [[1.0]]\nexcitation = [0.5]\n"
                                "static_load = [0.1]\n[[contact]]\ndof = 1\nlaw = \"jenkins\"\n"
                                "friction_limit = 0.3\nstiffness = 1.0\n");
    ::test::check_bad_input("timeint --config '" + jenkins.string() + "' --w 1", {"static load", "general time integrator"},
                            dir);
}

TEST_CASE("continuation through a corner sharper than a right angle: liftoff3.toml with excitation [0.05, 0.2, 0] "
          "passes w = 1.8857, where permanent stick turns into stick-slip",
          "[elastic_contact][continuation]") {
    // It stalled there (min_step, exit 1): every arclength hyperplane missed the branch beyond
    // the corner. Now the corner is crossed by a solve at a fixed frequency just beyond it, and
    // the branch completes; the point after the corner is a solution (time integration there,
    // stick-slip, within harmonic balance's H = 10 error).
    const ::test::TempDir dir;
    std::string text = ::test::slurp(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml");
    const std::string anchor = "excitation = [0.05, 0.15, 0.0]";
    REQUIRE(text.find(anchor) != std::string::npos);
    text.replace(text.find(anchor), anchor.size(), "excitation = [0.05, 0.2, 0.0]");
    const ::test::fs::path file = dir.path / "corner.toml", out = dir.path / "frf.csv", summary = dir.path / "frf.json";
    ::test::write_file(file, text);
    const ::test::Result r = ::test::run_hbf(
        "frf --config '" + file.string() + "' --out '" + out.string() + "' --summary '" + summary.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const nlohmann::json j = nlohmann::json::parse(::test::slurp(summary));
    CHECK(j.at("status").get<std::string>() == "completed");
    CHECK(j.at("solver").at("crossed_corners").get<int>() >= 1);
    CHECK(j.at("coverage").get<double>() == 1.0);
    // the first stick-slip point beyond w = 1.8857 against time integration
    const auto rows = ::test::parse_csv(::test::slurp(out));
    double omega = 0, y1 = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double w = ::test::column(rows, rows[k], "w");
        if (w > 1.8858 && ::test::column(rows, rows[k], "stick_fraction") < 1.0) {
            omega = w;
            y1 = ::test::column(rows, rows[k], "y1_max");
            break;
        }
    }
    REQUIRE(omega > 0.0);
    REQUIRE(omega < 1.9);
    System s = io::read_system_config(file.string()).system;
    const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration());
    INFO("w = " << omega << ": HB y1_max " << y1 << ", TI " << ti.summary());
    REQUIRE(ti.converged);
    CHECK(ti.regime == "stick-slip");
    CHECK(std::abs(y1 - ti.y_max[0]) <= 1e-3 * ti.y_max[0]);
}

TEST_CASE("hbf loop on a contact of law elastic writes its normal displacement and force and where it is open",
          "[elastic_contact][cli]") {
    // At w = 2.8 the example's contact is open 60 % of the period: every sample must have
    // fn = max(0, N_0 + k_n qn) (N_0 = 1, k_n = 5), open = 1 exactly where fn = 0, and the
    // tangential force within the cone, |f| <= mu fn (mu = 0.3).
    const ::test::TempDir dir;
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml";
    const ::test::fs::path out = dir.path / "loop.csv";
    const ::test::Result r = ::test::run_hbf("loop --config '" + example + "' --w 2.8 --out '" + out.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto rows = ::test::parse_csv(::test::slurp(out));
    REQUIRE(rows.size() > 100);
    int open = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double qn = ::test::column(rows, rows[k], "qn"), fn = ::test::column(rows, rows[k], "fn");
        CHECK(std::abs(fn - std::max(0.0, 1.0 + 5.0 * qn)) <= 1e-12);
        CHECK(::test::column(rows, rows[k], "open") == (fn > 0.0 ? 0.0 : 1.0));
        CHECK(std::abs(::test::column(rows, rows[k], "f")) <= 0.3 * fn + 1e-12);
        open += fn > 0.0 ? 0 : 1;
    }
    CHECK(open > static_cast<int>(rows.size()) / 3);
}

TEST_CASE("elastic contact, time integration: mu = 0 is frictionless and a contact closing faster tangentially than "
          "its cone grows slips at once (against harmonic balance, in lift-off)",
          "[elastic_contact][time_integration]") {
    // With mu = 0 the stick margin mu N - |T| is never positive: the integrator held the
    // contact stuck from every closing (a bonded tangential spring; 1.1e-2 off harmonic balance
    // here). Measured after the fix: 2e-7 at H = 40, N_t = 8192.
    System s = io::read_system_config(std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml").system;
    s.contacts[0].values["friction_coefficient"] = 0.0;
    const double omega = 2.8;
    const Eigen::VectorXd rest = linear_stuck_state(s, omega);
    const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration(), &rest);
    INFO(ti.message);
    REQUIRE(ti.converged);
    CHECK(ti.regime == "slip");
    CHECK(ti.contacts[0].separated_fraction > 0.3);
    HarmonicBalance hb(s, HarmonicBalanceOptions{40, 8192});
    SolutionPoint p;
    const PointMetrics m = solve(hb, omega, p, hbf::test::from_orbit(hb, ti, s.contact_directions(s.contacts[0])));
    CHECK(m.energy == Approx(0.0).margin(1e-12));  // no friction: the normal spring's work vanishes
    CHECK(first_harmonic_gap(hb, p, ti) <= 1e-6);
}
