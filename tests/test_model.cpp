#include <catch2/catch.hpp>

#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "hbf/error.hpp"
#include "hbf/absorber.hpp"
#include "hbf/model.hpp"
#include "hbf/hbf.hpp"
#include "support.hpp"

using namespace hbf;

TEST_CASE("linear_response matches the one-DOF closed form", "[model]") {
    const double m = 2.0, c = 0.3, k = 5.0, f = 1.5;
    for (double omega : {0.1, 1.0, 1.58, 3.0}) {
        Eigen::MatrixXd M(1, 1), C(1, 1), K(1, 1);
        M << m;
        C << c;
        K << k;
        Eigen::VectorXd F(1);
        F << f;
        const std::complex<double> expected = f / std::complex<double>(k - m * omega * omega, c * omega);
        CHECK(test::relative_difference(linear_response(M, C, K, F, omega)(0), expected) < 1e-14);
    }
}

TEST_CASE("friction_absorber reproduces the paper's equations of motion (eq. 2)", "[model]") {
    AbsorberParameters p;
    p.mass_ratio = 0.15;
    p.tuning_ratio = 0.9;
    p.excitation = 0.7;
    const System s = friction_absorber(p, FrictionLaw::coulomb);
    REQUIRE_NOTHROW(s.validate());
    REQUIRE(s.contacts.size() == 1);
    // Any state (y, y'', f): row 1 of M y'' + K y + w f must equal eq. 2's first left-hand
    // side, and row 2 divided by r must equal the second.
    const double r = p.mass_ratio, wa2 = p.tuning_ratio * p.tuning_ratio;
    const Eigen::Vector2d y(0.3, -1.1), acc(2.0, 0.7);
    const double f = 0.13;
    const Eigen::VectorXd lhs = s.mass * acc + s.stiffness * y + s.contact_direction(s.contacts[0]) * f;
    CHECK(lhs(0) == Approx(acc(0) + (1 + wa2 * r) * y(0) - wa2 * r * y(1) + f).epsilon(1e-14));
    CHECK(lhs(1) / r == Approx(acc(1) - wa2 * (y(0) - y(1)) - f / r).epsilon(1e-14));
    CHECK(s.excitation(0) == p.excitation);
    CHECK(s.excitation(1) == 0.0);
    CHECK(s.contacts[0].friction_limit == p.friction_coefficient);
}

TEST_CASE("friction_absorber maps wb, xi to the contact stiffness and damping of eq. B.4", "[model]") {
    AbsorberParameters p;
    p.contact_stiffness_ratio = 0.7;
    p.contact_damping_ratio = 0.05;
    const Contact lugre = friction_absorber(p, FrictionLaw::lugre).contacts[0];
    // f = r wb^2 y3 + 2 xi r wb y3'
    CHECK(lugre.stiffness == Approx(p.mass_ratio * 0.49).epsilon(1e-15));
    CHECK(lugre.damping == Approx(2 * 0.05 * p.mass_ratio * 0.7).epsilon(1e-15));
    const Contact dahl = friction_absorber(p, FrictionLaw::dahl).contacts[0];
    CHECK(dahl.damping == 0.0);  // Dahl has no contact damping whatever xi is
}

TEST_CASE("physical <-> nondimensional conversion round trip", "[model]") {
    PhysicalAbsorber a;
    a.m1 = 12.0;
    a.k1 = 3.0e4;
    a.m2 = 1.5;
    a.k2 = 3.4e3;
    a.normal_force = 40.0;
    a.force_amplitude = 25.0;
    a.friction_coefficient = 0.25;
    a.sigma0 = 2.0e3;
    a.sigma1 = 4.0;
    const AbsorberParameters p = to_nondimensional(a);
    CHECK(p.mass_ratio == Approx(1.5 / 12.0));
    CHECK(p.excitation == Approx(25.0 / 40.0));
    const PhysicalAbsorber back = to_physical(p, a.m1, a.k1, a.normal_force);
    CHECK(back.m2 == Approx(a.m2).epsilon(1e-14));
    CHECK(back.k2 == Approx(a.k2).epsilon(1e-14));
    CHECK(back.force_amplitude == Approx(a.force_amplitude).epsilon(1e-14));
    CHECK(back.sigma0 == Approx(a.sigma0).epsilon(1e-14));
    CHECK(back.sigma1 == Approx(a.sigma1).epsilon(1e-14));
    CHECK(back.friction_coefficient == a.friction_coefficient);
    const AbsorberParameters again = to_nondimensional(back);
    CHECK(again.tuning_ratio == Approx(p.tuning_ratio).epsilon(1e-14));
    CHECK(again.contact_stiffness_ratio == Approx(p.contact_stiffness_ratio).epsilon(1e-14));
    CHECK(again.contact_damping_ratio == Approx(p.contact_damping_ratio).epsilon(1e-14));

    const Scales sc = scales_of(a);
    CHECK(sc.frequency == Approx(std::sqrt(a.k1 / a.m1)));
    CHECK(sc.time * sc.frequency == Approx(1.0));
    CHECK(sc.displacement == Approx(a.normal_force / a.k1));
}

TEST_CASE("the scales turn the physical linear response into the nondimensional one", "[model]") {
    // Physical equations (paper eq. 20) with the contact as spring sigma0 and damper sigma1,
    // solved in physical units, divided by x_s at Omega = omega * omega1, must equal the
    // nondimensional solve: this checks r, wa, fe, wb, xi and the scales together.
    PhysicalAbsorber a;
    a.m1 = 3.0;
    a.k1 = 1.2e3;
    a.m2 = 0.4;
    a.k2 = 150.0;
    a.normal_force = 9.0;
    a.force_amplitude = 4.0;
    a.friction_coefficient = 0.3;
    a.sigma0 = 90.0;
    a.sigma1 = 1.7;
    const AbsorberParameters p = to_nondimensional(a);
    const Scales sc = scales_of(a);
    Eigen::MatrixXd M(2, 2), C(2, 2), K(2, 2);
    M << a.m1, 0, 0, a.m2;
    C << a.sigma1, -a.sigma1, -a.sigma1, a.sigma1;
    const double k = a.k2 + a.sigma0;
    K << a.k1 + k, -k, -k, k;
    Eigen::VectorXd F(2);
    F << a.force_amplitude, 0.0;
    const System s = friction_absorber(p, FrictionLaw::lugre);
    const Contact& c = s.contacts[0];
    for (double omega : {0.6, 0.95, 1.3}) {
        const Eigen::VectorXcd physical = linear_response(M, C, K, F, omega * sc.frequency) / sc.displacement;
        const Eigen::VectorXcd nondim = test::absorber_with_linear_contact(p, omega, c.stiffness, c.damping);
        CHECK(test::relative_difference(physical(0), nondim(0)) < 1e-12);
        CHECK(test::relative_difference(physical(1), nondim(1)) < 1e-12);
    }
}

TEST_CASE("invalid parameters are rejected with the parameter's name", "[model]") {
    AbsorberParameters p;
    p.mass_ratio = 0.0;
    CHECK_THROWS_WITH(p.validate(FrictionLaw::coulomb), Catch::Contains("r (mass ratio"));
    p = AbsorberParameters{};
    p.friction_coefficient = -0.1;
    CHECK_THROWS_WITH(p.validate(FrictionLaw::dahl), Catch::Contains("mu (friction coefficient"));
    p = AbsorberParameters{};
    p.contact_stiffness_ratio = 0.0;
    CHECK_NOTHROW(p.validate(FrictionLaw::coulomb));  // wb is not a Coulomb parameter
    CHECK_THROWS_AS(p.validate(FrictionLaw::dahl), InvalidInput);
    p = AbsorberParameters{};
    p.contact_damping_ratio = std::nan("");
    CHECK_THROWS_WITH(p.validate(FrictionLaw::lugre), Catch::Contains("xi"));
    CHECK_THROWS_WITH(parse_friction_law("stribeck"), Catch::Contains("coulomb, dahl, lugre"));

    System s = friction_absorber(AbsorberParameters{}, FrictionLaw::coulomb);
    s.contacts[0].other_dof = 5;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("other_dof"));
    s = friction_absorber(AbsorberParameters{}, FrictionLaw::coulomb);
    s.stiffness.coeffRef(0, 1) = 3.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("not symmetric"));
}

TEST_CASE("Enum names: every value's name parses back to it, and a value or name outside a table names the allowed set") {
    // The round trip through each parser, over every name its own error message allows.
    auto allowed = [](const std::function<void()>& bad_parse) {
        try {
            bad_parse();
        } catch (const InvalidInput& e) {
            const std::string m = e.what();
            const auto at = m.find("allowed ");
            REQUIRE(at != std::string::npos);
            std::vector<std::string> names;
            std::stringstream list(m.substr(at + 8));
            for (std::string name; std::getline(list, name, ',');) names.push_back(name.substr(name.find_first_not_of(' ')));
            return names;
        }
        FAIL("no InvalidInput for an unknown name");
        return std::vector<std::string>{};
    };
    const auto formulations = allowed([] { parse_formulation("none"); });
    CHECK(formulations == std::vector<std::string>{"automatic", "full", "condensed"});
    for (const std::string& n : formulations) CHECK(to_string(parse_formulation(n)) == n);
    const auto forms = allowed([] { parse_jacobian_form("sparse"); });
    CHECK(forms == std::vector<std::string>{"automatic", "dense", "structured"});
    for (const std::string& n : forms) CHECK(to_string(parse_jacobian_form(n)) == n);
    const auto methods = allowed([] { parse_reduction_method("guyan"); });
    CHECK(methods == std::vector<std::string>{"craig-bampton", "massless-boundary", "macneal"});
    for (const std::string& n : methods) CHECK(to_string(parse_reduction_method(n)) == n);
    for (const std::string& n : allowed([] { parse_stability_method("floquet"); }))
        CHECK(to_string(parse_stability_method(n)) == n);
    for (const std::string& n : allowed([] { parse_integration_method("euler"); }))
        CHECK(to_string(parse_integration_method(n)) == n);
    for (const std::string& n : allowed([] { parse_trust_region("line_search"); })) CHECK(to_string(parse_trust_region(n)) == n);
    for (const std::string& n : allowed([] { parse_dense_solver("lu"); })) CHECK(to_string(parse_dense_solver(n)) == n);
    for (const std::string& n : allowed([] { parse_dense_library("mkl"); })) CHECK(to_string(parse_dense_library(n)) == n);
    // Every law has a named id whose name is the registry's.
    for (FrictionLaw law : {FrictionLaw::coulomb, FrictionLaw::dahl, FrictionLaw::lugre, FrictionLaw::coulomb_regularized,
                            FrictionLaw::jenkins, FrictionLaw::iwan, FrictionLaw::elastic, FrictionLaw::unilateral})
        CHECK(parse_friction_law(to_string(law)) == law);
    CHECK(to_string(FrictionLaw::unilateral) == "unilateral");
    // A value no table holds (a cast integer) is an error naming the allowed names, never "?".
    try {
        (void)to_string(static_cast<PointKind>(99));
        FAIL("no InvalidInput for a value outside the table");
    } catch (const InvalidInput& e) {
        CHECK(std::string(e.what()) ==
              "point kind = 99 is not a known value: allowed regular, fold, sample, transition, cap, branch-point, "
              "period-doubling, neimark-sacker");
    }
    CHECK_THROWS_AS(to_string(static_cast<ContinuationStatus>(-1)), InvalidInput);
}
