// hbfriction — which systems the exact polish takes, and where its orbits start
// (exact_polish.hpp).
#include <cmath>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/rigid_exact.hpp"

namespace hbf {

namespace {
/// d/dt of the Fourier series c (c0, a1, b1, a2, b2, ...: c0 + sum a_k cos k w t + b_k sin k w t) at t = 0.
double rate_at_zero(const Eigen::VectorXd& c, double omega) {
    double rate = 0.0;
    for (int k = 1; 2 * k < c.size(); ++k) rate += omega * k * c(2 * k);
    return rate;
}
}  // namespace

std::string exact_polish_refusal(const System& system, double omega_min, int modes) {
    if (system.cyclic.active())
        return "the exact polish is not available for a sector model (cyclic symmetry): the FRF is harmonic balance's";
    if (rigid_contacts_only(system)) return rigid_solver_refusal(system);
    if (elastic_contacts_only(system)) return elastic_solver_refusal(system);
    const int m = exact_solver_modes(system, modes);
    if (m == 0) return omega_min > 0.0 ? exact_cost_refusal(system, omega_min) : exact_solver_refusal(system);
    try {
        const ModalExactModel model(system, m);
        const std::string why =
            omega_min > 0.0 ? exact_cost_refusal(model.system(), omega_min) : exact_solver_refusal(model.system());
        return why.empty() ? why : "on its modal form (" + std::to_string(model.modes()) + " modes): " + why;
    } catch (const InvalidInput& e) {
        return e.what();
    }
}

Eigen::VectorXd exact_start_state(HarmonicBalance& hb, const SolutionPoint& point) {
    const System& s = hb.system();
    if (elastic_contacts_only(s)) {  // [y, y', sliders, modes] from the HB orbit's samples
        const Eigen::MatrixXd y = hb.dofs(point.x, point.omega);
        Eigen::MatrixXd samples(hb.time_samples(), s.dofs());
        Eigen::VectorXd column(hb.time_samples()), velocity(s.dofs());
        for (int i = 0; i < s.dofs(); ++i) {
            hb.fourier().to_time(y.col(i), column);
            samples.col(i) = column;
            velocity(i) = rate_at_zero(y.col(i), point.omega);
        }
        return elastic_start_state(s, samples, velocity);
    }
    const bool rigid = rigid_contacts_only(s);  // the state: y and y' alone
    const int n = s.dofs(), nc = rigid ? 0 : time_domain_elements(s);  // the state is per time-domain element
    Eigen::VectorXd state = Eigen::VectorXd::Zero(2 * n + 2 * nc);
    auto at_zero = [&](const Eigen::VectorXd& c, double& value, double& rate) {
        value = c(0);
        for (int k = 1; 2 * k < c.size(); ++k) value += c(2 * k - 1);
        rate = rate_at_zero(c, point.omega);
    };
    const Eigen::MatrixXd y = hb.dofs(point.x, point.omega);
    for (int i = 0; i < n; ++i) at_zero(y.col(i), state(i), state(n + i));
    if (rigid) return state;
    // an elastic slider holding the force f at q sits at s = q - f / k_t; it slips when |f| is at
    // its limit and moves with the velocity
    auto slider = [&](int e, const Contact& k, double q, double v, double f) {
        state(2 * n + e) = q - f / k.stiffness;
        state(2 * n + nc + e) = std::abs(f) >= k.friction_limit * (1.0 - 1e-9) && f * v > 0.0 ? (f > 0 ? 1 : -1) : 0;
    };
    int e = 0;
    for (int c = 0; c < static_cast<int>(s.contacts.size()); ++c) {
        const Contact& k = s.contacts[static_cast<std::size_t>(c)];
        double q = 0, v = 0;
        const Eigen::VectorXd relative = hb.relative(point.x, c);
        at_zero(relative, q, v);
        const std::vector<Contact> elements = contact_law(k.law).time_elements(k);
        if (elements.size() > 1) {  // each element's force from its own law on the contact's q(t)
            for (const Contact& element : elements) {
                const double f = contact_law(element.law)
                                     .periodic_model(element)
                                     ->force_samples(hb.fourier(), point.omega, relative, Eigen::VectorXd())(0);
                if (elastic_slider(element)) slider(e, element, q, v, f);
                ++e;
            }
        } else if (elastic_slider(k)) {
            slider(e++, k, q, v, hb.force_samples(point.x, point.omega, c)(0));
        } else {
            const double phi = hb.stick_indicator(point.x, point.omega, c)(0);
            state(2 * n + nc + e++) = phi < 0.0 ? 0 : (v > 0 ? 1 : -1);
        }
    }
    return state;
}

}  // namespace hbf
