// The Iwan joint (src/contact/iwan.cpp): N = 1 is the Jenkins element; Segalman's backbone and
// the Masing loop against their closed forms (derived in iwan.cpp's header); the small-amplitude
// dissipation's power law; harmonic balance against time integration and the exact solver.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "hbf/config.hpp"
#include "hbf/absorber.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/continuation.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/fourier.hpp"
#include "hbf/contact_force.hpp"
#include "hbf/frf.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/model.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/time_integration.hpp"
#include "support.hpp"

using namespace hbf;

namespace {

constexpr double pi = 3.14159265358979323846;

const LawParameter& iwan_parameter(const std::string& key) {
    static const std::vector<LawParameter> p = contact_law(parse_friction_law("iwan")).parameters();
    for (const LawParameter& q : p)
        if (key == q.key) return q;
    throw std::logic_error("no iwan parameter " + key);
}

/// An Iwan contact with Segalman's parameters (F_S, K_T, chi, beta, N).
Contact segalman(double fs, double kt, double chi, double beta, int sliders) {
    Contact c;
    c.law = parse_friction_law("iwan");
    c.friction_limit = fs;
    c.stiffness = kt;
    iwan_parameter("chi").set(c, chi);
    iwan_parameter("beta").set(c, beta);
    iwan_parameter("sliders").set(c, sliders);
    return c;
}

/// Segalman's monotonic-loading force F(u), u >= 0 (iwan.cpp).
struct Segalman {
    double fs, kt, chi, beta;
    double phi_max() const { return fs * (1 + beta) / (kt * (beta + (chi + 1) / (chi + 2))); }
    double r() const {
        const double a = fs / (phi_max() * (beta + (chi + 1) / (chi + 2)));
        return (chi + 1) * a / std::pow(phi_max(), chi + 1);
    }
    double backbone(double u) const {
        if (u >= phi_max()) return fs;
        return kt * u - r() * std::pow(u, chi + 2) / ((chi + 1) * (chi + 2));
    }
    double dissipation(double a) const { return 4 * r() * std::pow(a, chi + 3) / ((chi + 2) * (chi + 3)); }
};

/// The force samples of `contact` over one period of q = a cos t (N_t samples, t_j = 2 pi j / N_t).
Eigen::VectorXd loop(const Contact& contact, double a, int samples) {
    Fourier fourier(1, samples);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(fourier.size());
    q(1) = a;  // the cosine of harmonic 1
    return make_friction_model(contact)->force_samples(fourier, 1.0, q, Eigen::VectorXd());
}

/// The energy dissipated over one period of q = a cos t: the integral of f dq (rectangle rule
/// on the samples, which is the trapezoid rule of a periodic integrand).
double dissipated(const Eigen::VectorXd& f, double a) {
    const int n = static_cast<int>(f.size());
    double d = 0;
    for (int j = 0; j < n; ++j) d += f(j) * (-a * std::sin(2 * pi * j / n));
    return d * 2 * pi / n;
}

System iwan_absorber(Contact contact, double fe = 0.5) {
    AbsorberParameters p;
    p.excitation = fe;
    System s = friction_absorber(p, FrictionLaw::jenkins);
    contact.dof = s.contacts[0].dof;
    contact.other_dof = s.contacts[0].other_dof;
    s.contacts[0] = contact;
    return s;
}

}  // namespace

TEST_CASE("Iwan with one slider is the Jenkins element to 1e-12 (harmonic balance, time integration, exact)",
          "[iwan]") {
    AbsorberParameters p;
    const System jenkins = friction_absorber(p, FrictionLaw::jenkins);
    const double kt = jenkins.contacts[0].stiffness, fs = jenkins.contacts[0].friction_limit;
    Contact table;
    table.law = parse_friction_law("iwan");
    table.friction_limit = fs;
    table.stiffness = kt;
    table.lists["slider_table"] = {kt, fs};
    for (const Contact& one : {segalman(fs, kt, -0.5, 0.0, 1), table}) {
        const System iwan = iwan_absorber(one);
        REQUIRE(time_domain_system(iwan).contacts.size() == 1);
        // the HB residual and its Jacobian at an arbitrary state, stick-slip
        HarmonicBalance a(jenkins, HarmonicBalanceOptions{10, 0}), b(iwan, HarmonicBalanceOptions{10, 0});
        Eigen::VectorXd x = Eigen::VectorXd::Zero(a.unknowns());
        for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = 2.0 * std::sin(1.0 + 3.0 * static_cast<double>(i)) / (1 + i / 4);
        Eigen::VectorXd ra, rb, wa, wb;
        Eigen::MatrixXd ja, jb;
        a.evaluate(x, 1.1, ra, &ja, &wa);
        b.evaluate(x, 1.1, rb, &jb, &wb);
        CHECK((ra - rb).cwiseAbs().maxCoeff() <= 1e-12 * ra.cwiseAbs().maxCoeff());
        CHECK((ja - jb).cwiseAbs().maxCoeff() <= 1e-12 * ja.cwiseAbs().maxCoeff());
        // time integration and the exact orbit
        const PeriodicResponse ta = integrate_steady_state(jenkins, 1.2, test::tight_time_integration());
        const PeriodicResponse tb = integrate_steady_state(iwan, 1.2, test::tight_time_integration());
        REQUIRE(ta.converged);
        REQUIRE(tb.converged);
        INFO("y1_max " << ta.y_max[0] << " - " << tb.y_max[0] << " = " << ta.y_max[0] - tb.y_max[0] << "; k " << time_domain_system(iwan).contacts[0].stiffness - kt << ", F " << time_domain_system(iwan).contacts[0].friction_limit - fs);
        CHECK(std::abs(ta.y_max[0] - tb.y_max[0]) <= 1e-12 * ta.y_max[0]);
        const ExactOrbit ea = exact_periodic_orbit(jenkins, 1.2, ta.state), eb = exact_periodic_orbit(iwan, 1.2, tb.state);
        REQUIRE(ea.converged);
        REQUIRE(eb.converged);
        CHECK(std::abs(ea.y_max[0] - eb.y_max[0]) <= 1e-12 * ea.y_max[0]);
    }
}

TEST_CASE("Iwan (Segalman): the loop tips trace the backbone and the loops follow Masing's rule, to the "
          "discretisation's error, which falls as the sliders grow",
          "[iwan]") {
    const Segalman model{1.0, 1.0, -0.5, 0.5};
    const double phi_max = model.phi_max();
    const int samples = 2000;
    double previous = 0;
    for (int sliders : {50, 200, 800}) {
        const Contact c = segalman(model.fs, model.kt, model.chi, model.beta, sliders);
        double worst = 0;
        for (double a : {0.05 * phi_max, 0.3 * phi_max, 0.8 * phi_max, 1.5 * phi_max}) {
            const Eigen::VectorXd f = loop(c, a, samples);
            const double tip = model.backbone(a);
            worst = std::max(worst, std::abs(f(0) - tip));  // t = 0: q = a, the loop's tip
            for (int j = 0; j <= samples / 2; ++j) {     // the descending branch, q from a to -a
                const double u = a * std::cos(2 * pi * j / samples);
                worst = std::max(worst, std::abs(f(j) - (tip - 2 * model.backbone((a - u) / 2))));
            }
            for (int j = samples / 2; j < samples; ++j) {  // ascending: the mirror image
                const double u = a * std::cos(2 * pi * j / samples);
                worst = std::max(worst, std::abs(f(j) - (-tip + 2 * model.backbone((a + u) / 2))));
            }
        }
        INFO(sliders << " sliders: largest error " << worst << " of F_S = 1");
        // measured 0.57 / N^2 (2.3e-4, 1.4e-5, 8.9e-7): the error falls like 1 / N^2
        CHECK(worst <= 1.0 / (static_cast<double>(sliders) * sliders));
        if (previous > 0) CHECK(worst <= previous / 8);  // 4 times the sliders: 16 times smaller
        previous = worst;
    }
}

TEST_CASE("Iwan (Segalman): the dissipation per cycle at small amplitude follows a^(3 + chi) to 1 %", "[iwan]") {
    for (double chi : {-0.5, -0.2}) {
        const Segalman model{1.0, 1.0, chi, 0.3};
        const Contact c = segalman(model.fs, model.kt, model.chi, model.beta, 1000);
        const double a1 = 0.04 * model.phi_max(), a2 = 0.08 * model.phi_max();
        const double d1 = dissipated(loop(c, a1, 4000), a1), d2 = dissipated(loop(c, a2, 4000), a2);
        const double slope = std::log(d2 / d1) / std::log(a2 / a1);
        INFO("chi = " << chi << ": slope " << slope << ", D(a1) " << d1 << " against " << model.dissipation(a1));
        CHECK(std::abs(slope - (3 + chi)) <= 0.01 * (3 + chi));
        CHECK(std::abs(d1 - model.dissipation(a1)) <= 0.01 * model.dissipation(a1));
    }
}

TEST_CASE("Iwan on the absorber: harmonic balance equals time integration and the exact solver", "[iwan]") {
    AbsorberParameters p;
    const double kt = friction_absorber(p, FrictionLaw::jenkins).contacts[0].stiffness;
    const System s = iwan_absorber(segalman(p.friction_coefficient, kt, -0.5, 0.5, 6));
    REQUIRE(time_domain_system(s).contacts.size() == 7);
    for (double omega : {0.8, 1.0, 1.3}) {
        const PeriodicResponse ti = integrate_steady_state(s, omega, test::tight_time_integration());
        INFO("w = " << omega << ": " << ti.summary());
        REQUIRE(ti.converged);
        const ExactOrbit exact = exact_periodic_orbit(s, omega, ti.state);
        INFO(exact.summary());
        REQUIRE(exact.converged);
        CHECK(std::abs(exact.y_max[0] - ti.y_max[0]) <= 1e-7 * ti.y_max[0]);
        CHECK(std::abs(exact.energy - exact.input_energy) <= 1e-9 * exact.energy);  // C = 0
        HarmonicBalance hb(s, HarmonicBalanceOptions{20, 0});
        const SolutionAt at = solve_at(hb, omega, 0.5);
        REQUIRE(at.found);
        const PointMetrics m = Analyser(hb)(at.point);
        INFO("HB y1_max " << m.y_max[0] << " (" << m.regime << "), TI " << ti.y_max[0] << " (" << ti.regime << ")");
        // measured 1.2e-6 at most (H = 20; jenkins 3.2e-6): the sliders' slip onsets between samples
        CHECK(std::abs(m.y_max[0] - ti.y_max[0]) <= 1e-5 * ti.y_max[0]);
        CHECK(m.regime == ti.regime);
        CHECK(exact.regime == ti.regime);
    }
}

TEST_CASE("Iwan's parameters are checked: ranges, and a slider table with its sums", "[iwan]") {
    const System good = iwan_absorber(segalman(0.2, 0.016, -0.5, 0.5, 10));
    REQUIRE_NOTHROW(good.validate());
    auto refused = [&](Contact c, const std::string& words) {
        const System s = iwan_absorber(c);
        INFO(words);
        CHECK_THROWS_WITH(s.validate(), Catch::Contains(words));
    };
    refused(segalman(0.2, 0.016, -1.0, 0.5, 10), "chi (Segalman exponent chi of the slider density R phi^chi) = -1 is "
                                                 "out of range: allowed in (-1, 0]");
    refused(segalman(0.2, 0.016, 0.1, 0.5, 10), "allowed in (-1, 0]");
    refused(segalman(0.2, 0.016, -0.5, -0.1, 10), "beta");
    refused(segalman(0.2, 0.016, -0.5, 0.5, 0), "allowed an integer in 1..1000");
    refused(segalman(0.2, 0.016, -0.5, 0.5, 1001), "allowed an integer in 1..1000");
    Contact t;
    t.law = parse_friction_law("iwan");
    t.friction_limit = 0.3;
    t.stiffness = 3.0;
    t.lists["slider_table"] = {1.0, 0.1, 2.0, 0.2};
    REQUIRE_NOTHROW(iwan_absorber(t).validate());
    Contact wrong_sum = t;
    wrong_sum.friction_limit = 0.25;
    refused(wrong_sum, "friction_limit = 0.25 with slider_table: allowed the sum of the slip forces F_i, 0.3");
    Contact both = t;
    iwan_parameter("chi").set(both, -0.5);
    refused(both, "chi is given together with slider_table");
    Contact negative = t;
    negative.lists["slider_table"] = {1.0, 0.1, 2.0, -0.2};
    refused(negative, "slider_table[2].F");
}

TEST_CASE("Iwan in a system file: Segalman's keys and a slider table of pairs, row errors named", "[iwan]") {
    const std::string path = "test_iwan_system.toml";
    auto write = [&](const std::string& contact) {
        std::ofstream f(path);
        f << "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [0.5]\n\n[[contact]]\ndof = 1\nlaw = \"iwan\"\n"
          << contact;
    };
    write("friction_limit = 0.3\nstiffness = 3.0\nslider_table = [[1.0, 0.1], [2.0, 0.2]]\n");
    const System table = io::read_system_config(path).system;
    REQUIRE(table.contacts.size() == 1);
    CHECK(table.contacts[0].lists.at("slider_table") == std::vector<double>{1.0, 0.1, 2.0, 0.2});
    const System lowered = time_domain_system(table);
    REQUIRE(lowered.contacts.size() == 2);
    CHECK(lowered.contacts[0].stiffness == 1.0);  // phi = 0.1 before phi = 0.1: stable order
    CHECK(lowered.contacts[1].friction_limit == 0.2);
    write("friction_limit = 0.2\nstiffness = 1.0\nchi = -0.3\nbeta = 0.25\nsliders = 12\n");
    const System s = io::read_system_config(path).system;
    CHECK(iwan_parameter("chi").get(s.contacts[0]) == -0.3);
    CHECK(time_domain_system(s).contacts.size() == 13);  // 12 and the one at phi_max (beta > 0)
    double k = 0, f = 0;
    for (const Contact& e : time_domain_system(s).contacts) {
        k += e.stiffness;
        f += e.friction_limit;
    }
    CHECK(std::abs(k - 1.0) <= 1e-14);  // K_T and F_S for every N
    CHECK(std::abs(f - 0.2) <= 1e-14);
    write("friction_limit = 0.3\nstiffness = 3.0\nslider_table = [[1.0, 0.1, 5.0], [2.0, 0.2]]\n");
    CHECK_THROWS_WITH(io::read_system_config(path), Catch::Contains("contact[1].slider_table[1]") &&
                                                        Catch::Contains("expected a pair of two numbers"));
    write("friction_limit = 0.3\nstiffness = 3.0\nsliders = 2.5\n");
    CHECK_THROWS_WITH(io::read_system_config(path), Catch::Contains("allowed an integer in 1..1000"));
    std::remove(path.c_str());
}
