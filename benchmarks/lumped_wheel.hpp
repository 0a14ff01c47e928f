// hbfriction benchmarks and tests: a lumped bladed disk, one sector of N identical sectors
// (cyclic.hpp), and the whole wheel assembled from it by hand, sector by sector. Each sector: a
// disk mass (DOF 0), a blade platform (1) and a blade tip (2); springs from the disk to the
// ground, to the platform and (across the cut) to the next sector's disk (DOF 3 of the sector
// model), platform to tip; Rayleigh damping; the force on the tip; a Jenkins contact from the
// platform to the next sector's platform (DOF 4 of the sector model).
#pragma once

#include <cmath>

#include "hbf/contact_law.hpp"
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

/// The same sector with lift-off: the platform also moves normally (DOF 3, mass 0.1, a spring
/// 6 to the ground) and the contact is law elastic between the platform and the next sector's
/// (tangential DOFs 1 and 5, normal DOFs 3 and 6: q = y_1 - y_5, v = y_3 - y_6 positive closing;
/// k_t 2, k_n 3, mu 0.3, preload 0.1); DOF 4 is the next sector's disk. The force acts on the
/// tip and, normally, on the platform (`normal_force`): a fluctuating normal load opens the
/// contact once k_n |v| passes the preload.
inline System lumped_sector_elastic(int sectors, int engine_order, double normal_force) {
    System s = lumped_sector(sectors, engine_order, 1.0);
    const Eigen::MatrixXd k5(s.stiffness), m5(s.mass);
    // 7 DOFs: 0 disk, 1 platform, 2 tip, 3 platform normal, 4 next disk, 5 next platform, 6 next normal
    const int map[5] = {0, 1, 2, 4, 5};
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(7, 7), m = k;
    for (int a = 0; a < 5; ++a)
        for (int b = 0; b < 5; ++b) {
            k(map[a], map[b]) = k5(a, b);
            m(map[a], map[b]) = m5(a, b);
        }
    k(3, 3) += 6.0;
    m(3, 3) = 0.1;
    s.mass = sparse(m);
    s.stiffness = sparse(k);
    s.damping = sparse(0.004 * k);
    s.excitation = Eigen::VectorXd::Zero(7);
    s.excitation(2) = 0.05;
    s.excitation(3) = normal_force;
    Contact c;
    c.dof = 1;
    c.other_dof = 5;
    c.law = FrictionLaw::elastic;
    c.stiffness = 2.0;
    c.values["normal_stiffness"] = 3.0;
    c.values["friction_coefficient"] = 0.3;
    c.values["preload"] = 0.1;
    Eigen::VectorXd normal = Eigen::VectorXd::Zero(7);
    normal(3) = 1.0;
    normal(6) = -1.0;
    c.lists["normal_direction"].assign(normal.data(), normal.data() + 7);
    s.contacts = {c};
    s.cyclic.neighbours = {{4, 0}, {5, 1}, {6, 3}};
    return s;
}

/// The sector's own DOFs: its first ones, every DOF no neighbour pair names as dependent.
inline int own_dofs(const System& s) { return s.dofs() - static_cast<int>(s.cyclic.neighbours.size()); }

/// Wheel DOF of sector j's DOF i: an own DOF in sector j, a dependent DOF its master in sector
/// j + 1 (sector N is sector 0).
inline int wheel_dof(const System& s, int j, int i) {
    const int own = own_dofs(s), n = s.cyclic.sectors;
    if (i < own) return own * j + i;
    for (const auto& [d, m] : s.cyclic.neighbours)
        if (d == i) return own * ((j + 1) % n) + m;
    return -1;
}

/// The wheel assembled by hand: every sector's matrices and contacts placed on the ring (a
/// contact's DOFs and direction vectors mapped to the wheel's DOFs). Its excitation is the
/// travelling force's cosine part F cos(j phi) (the sine part F sin(j phi) is added to the
/// residual by the caller: a System carries a cosine force only).
inline System lumped_wheel(const System& s) {
    const int n = s.cyclic.sectors, own = own_dofs(s), dofs = own * n;
    const double phi = s.cyclic.phase();
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(dofs, dofs), k = m, c = m;
    const Eigen::MatrixXd ms(s.mass), ks(s.stiffness), cs(s.damping);
    System w;
    w.excitation = Eigen::VectorXd::Zero(dofs);
    auto placed = [&](const Eigen::VectorXd& v, int j) {  // a vector over the sector's DOFs on the wheel
        Eigen::VectorXd out = Eigen::VectorXd::Zero(dofs);
        for (int i = 0; i < s.dofs(); ++i) out(wheel_dof(s, j, i)) += v(i);
        return out;
    };
    for (int j = 0; j < n; ++j) {
        for (int a = 0; a < s.dofs(); ++a)
            for (int b = 0; b < s.dofs(); ++b) {
                m(wheel_dof(s, j, a), wheel_dof(s, j, b)) += ms(a, b);
                k(wheel_dof(s, j, a), wheel_dof(s, j, b)) += ks(a, b);
                c(wheel_dof(s, j, a), wheel_dof(s, j, b)) += cs(a, b);
            }
        for (int a = 0; a < own; ++a) w.excitation(wheel_dof(s, j, a)) = s.excitation(a) * std::cos(j * phi);
        for (const Contact& sector_contact : s.contacts) {
            Contact contact = sector_contact;
            if (contact.direction.size() > 0) contact.direction = placed(contact.direction, j);
            contact.dof = wheel_dof(s, j, sector_contact.dof);
            if (sector_contact.other_dof != Contact::ground) contact.other_dof = wheel_dof(s, j, sector_contact.other_dof);
            for (const LawParameter& p : contact_law(contact.law).parameters()) {
                const auto list = contact.lists.find(p.key);
                if (p.kind != LawParameter::Kind::direction || list == contact.lists.end()) continue;
                const Eigen::VectorXd v =
                    placed(Eigen::Map<const Eigen::VectorXd>(list->second.data(), s.dofs()), j);
                list->second.assign(v.data(), v.data() + v.size());
            }
            w.contacts.push_back(contact);
        }
    }
    w.mass = sparse(m);
    w.stiffness = sparse(k);
    w.damping = sparse(c);
    return w;
}

/// A sector's harmonic-balance state on the whole wheel: `y` holds every sector DOF's 2H + 1
/// coefficients (HarmonicBalance::dofs), sector j is sector 0 delayed by j phi / omega (harmonic
/// k turned by k j phi); the wheel's unknowns in lumped_wheel's DOF order.
inline Eigen::VectorXd placed_on_wheel(const System& s, const Eigen::MatrixXd& y) {
    const int n = s.cyclic.sectors, own = own_dofs(s), coefficients = static_cast<int>(y.rows());
    Eigen::VectorXd x(own * n * coefficients);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < own; ++i) {
            Eigen::VectorXd c = y.col(i);
            for (int k = 1; 2 * k < coefficients; ++k) {
                const double a = k * j * s.cyclic.phase(), cs = std::cos(a), sn = std::sin(a);
                c(2 * k - 1) = cs * y(2 * k - 1, i) - sn * y(2 * k, i);
                c(2 * k) = sn * y(2 * k - 1, i) + cs * y(2 * k, i);
            }
            x.segment(wheel_dof(s, j, i) * coefficients, coefficients) = c;
        }
    return x;
}

}  // namespace hbf::bench
