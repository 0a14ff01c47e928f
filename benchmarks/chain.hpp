// hbfriction benchmarks: the finite-element-like chain of hb_scaling and exact_scaling. N masses
// on a fixed-free bar of unit total mass and stiffness (masses 1/N, springs N: its first mode
// stays at w1 = pi/2 whatever N), stiffness-proportional damping of 1 % at w1, the force
// cos(w t) at the free end, and `contacts` exact Coulomb contacts to the ground near the free
// end (friction limits 0.5, 0.4, 0.3, 0.2). In units where mass is `mass_unit` times and
// stiffness `stiffness_unit` times these numbers (lengths unchanged), time scales by
// sqrt(mass_unit / stiffness_unit): w1, the damping, the force and the friction limits with it.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hbf/model.hpp"

namespace hbf::bench {

inline System chain(int n, int contacts, double mass_unit = 1.0, double stiffness_unit = 1.0) {
    std::vector<Eigen::Triplet<double>> k, m;
    const double spring = n * stiffness_unit, mass = mass_unit / n;
    for (int i = 0; i < n; ++i) {
        m.emplace_back(i, i, mass);
        // Spring i joins DOF i - 1 (the wall for i = 0) and DOF i.
        k.emplace_back(i, i, spring);
        if (i > 0) {
            k.emplace_back(i - 1, i - 1, spring);
            k.emplace_back(i - 1, i, -spring);
            k.emplace_back(i, i - 1, -spring);
        }
    }
    System s;
    s.mass.resize(n, n);
    s.stiffness.resize(n, n);
    s.mass.setFromTriplets(m.begin(), m.end());
    s.stiffness.setFromTriplets(k.begin(), k.end());
    const double w1 = M_PI / 2.0 / std::sqrt(mass_unit / stiffness_unit);
    s.damping = (2.0 * 0.01 / w1) * s.stiffness;  // zeta = beta w / 2 = 1 % at w1
    s.excitation = Eigen::VectorXd::Zero(n);
    s.excitation(n - 1) = stiffness_unit;  // a force: stiffness x length
    for (int c = 0; c < contacts; ++c) {
        Contact contact;
        contact.dof = n - 1 - c * std::max(1, n / 10);
        contact.law = FrictionLaw::coulomb;
        contact.friction_limit = (0.5 - 0.1 * c) * stiffness_unit;
        s.contacts.push_back(contact);
    }
    return s;
}

}  // namespace hbf::bench
