// Uses the installed library: the Coulomb full-stick amplitude of the paper's absorber at
// omega = 0.5 must be fe / (1 - (1 + r) omega^2) = 0.5 / 0.725 (derived by hand), by the closed
// form and by time integration (which links SUNDIALS through the installed package).
#include <hbf/hbf.hpp>  // the umbrella: every public header, installed and self-contained
#include <cmath>
#include <cstdio>
#include <string>

int main() {
    const hbf::AbsorberParameters p;  // r = 0.1, fe = 0.5
    const double y = std::abs(hbf::analytic::coulomb_stick(p, 0.5).y1);
    const double expected = 0.5 / 0.725;
    const hbf::System system = hbf::friction_absorber(p, hbf::FrictionLaw::coulomb);
    const Eigen::VectorXd start = hbf::linear_stuck_state(system, 0.5);
    const hbf::PeriodicResponse r = hbf::integrate_steady_state(system, 0.5, hbf::TimeIntegrationOptions{}, &start);
    std::printf("consumer: |Y1| = %.15g, time integration %.15g, expected %.15g\n", y, r.y_max[0], expected);
    // the installed headers and library are one version
    const bool same_version = std::string(hbf::version()) == HBF_VERSION_STRING;
    std::printf("consumer: hbfriction %s (headers %s)\n", hbf::version(), HBF_VERSION_STRING);
    return std::abs(y - expected) < 1e-14 && r.converged && std::abs(r.y_max[0] - expected) < 1e-8 && same_version ? 0
                                                                                                                    : 1;
}
