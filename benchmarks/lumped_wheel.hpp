// hbfriction benchmarks and tests: a lumped bladed disk, one sector of N identical sectors
// (cyclic.hpp), and the whole wheel assembled from it by hand, sector by sector. Each sector: a
// disk mass (DOF 0), a blade platform (1) and a blade tip (2); springs from the disk to the
// ground, to the platform and (across the cut) to the next sector's disk (DOF 3 of the sector
// model), platform to tip; Rayleigh damping; the force on the tip; a Jenkins contact from the
// platform to the next sector's platform (DOF 4 of the sector model).
#pragma once

#include <cmath>

#include "hbf/model.hpp"

namespace hbf::bench {

constexpr int sector_own = 3;  ///< the sector's own DOFs: disk, platform, tip

/// Sector model: DOFs 0..2 its own, 3 = the next sector's disk, 4 = the next sector's
/// platform. Springs: disk to ground kg, disk to the next disk kd (across the cut), disk to
/// platform kp, platform to tip kt; Rayleigh damping C = beta K; the force on the tip. The
/// contact (Jenkins, tangential stiffness k_c, slip force f_c) joins the platform and the next
/// sector's platform.
inline System lumped_sector(int sectors, int engine_order, double f_c) {
    const double m[sector_own] = {1.0, 0.3, 0.2};
    const double kg = 10.0, kd = 5.0, kp = 8.0, kt = 4.0, beta = 0.004;
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(5, 5), mass = Eigen::MatrixXd::Zero(5, 5);
    auto spring = [&](int a, int b, double value) {
        k(a, a) += value;
        if (b < 0) return;
        k(b, b) += value;
        k(a, b) -= value;
        k(b, a) -= value;
    };
    spring(0, -1, kg);
    spring(0, 3, kd);
    spring(0, 1, kp);
    spring(1, 2, kt);
    for (int i = 0; i < sector_own; ++i) mass(i, i) = m[i];
    System s;
    s.mass = sparse(mass);
    s.stiffness = sparse(k);
    s.damping = sparse(beta * k);
    s.excitation = Eigen::VectorXd::Zero(5);
    s.excitation(2) = 0.05;
    Contact c;
    c.dof = 1;
    c.other_dof = 4;
    c.law = FrictionLaw::jenkins;
    c.stiffness = 2.0;
    c.friction_limit = f_c;
    s.contacts.push_back(c);
    s.cyclic.sectors = sectors;
    s.cyclic.engine_order = engine_order;
    s.cyclic.neighbours = {{3, 0}, {4, 1}};
    return s;
}

/// Wheel DOF of sector j's DOF i (the dependent DOFs are the next sector's).
inline int wheel_dof(int sectors, int j, int i) {
    if (i < sector_own) return sector_own * j + i;
    return sector_own * ((j + 1) % sectors) + (i == 3 ? 0 : 1);
}

/// The wheel assembled by hand: every sector's matrices and contact placed on the ring. Its
/// excitation is the travelling force's cosine part F cos(j phi) (the sine part F sin(j phi)
/// is added to the residual by the caller: a System carries a cosine force only).
inline System lumped_wheel(const System& s) {
    const int n = s.cyclic.sectors, dofs = sector_own * n;
    const double phi = s.cyclic.phase();
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(dofs, dofs), k = m, c = m;
    const Eigen::MatrixXd ms(s.mass), ks(s.stiffness), cs(s.damping);
    System w;
    w.excitation = Eigen::VectorXd::Zero(dofs);
    for (int j = 0; j < n; ++j) {
        for (int a = 0; a < s.dofs(); ++a)
            for (int b = 0; b < s.dofs(); ++b) {
                m(wheel_dof(n, j, a), wheel_dof(n, j, b)) += ms(a, b);
                k(wheel_dof(n, j, a), wheel_dof(n, j, b)) += ks(a, b);
                c(wheel_dof(n, j, a), wheel_dof(n, j, b)) += cs(a, b);
            }
        for (int a = 0; a < sector_own; ++a) w.excitation(wheel_dof(n, j, a)) = s.excitation(a) * std::cos(j * phi);
        Contact contact = s.contacts[0];
        contact.dof = wheel_dof(n, j, s.contacts[0].dof);
        contact.other_dof = wheel_dof(n, j, s.contacts[0].other_dof);
        w.contacts.push_back(contact);
    }
    w.mass = sparse(m);
    w.stiffness = sparse(k);
    w.damping = sparse(c);
    return w;
}

}  // namespace hbf::bench
