// hbfriction benchmarks and tests: a chain of n masses, each pressing a massless contact node
// onto a rigid wall (law unilateral): the node of contact c is tied to mass c along the wall
// (k_t) and to mass c + 1 (cyclically) across it (k_n), with preloads that differ, so that the
// contacts stick, slip and open at different times. DOFs: y_1..y_n the masses, then per contact
// its tangential and its normal node. The parameters repeat with period 3 along the chain
// (masses 1, 0.7, 0.4; k_t 3, 2, 4; k_n 5, 6, 4; preloads 1, 0.6, 0.8; forces 0.3 F, F,
// -0.5 F), springs 1.5 and 1.0 alternate between neighbours, the ends are grounded by 2 and 0.5;
// damping 2 % of each mass and a dashpot 0.01 between the first two; mu = 0.3.
#pragma once

#include <utility>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/model.hpp"

namespace hbf::bench {

/// A spring k between DOFs a and b of K.
inline void add_spring(Eigen::MatrixXd& K, int a, int b, double k) {
    K(a, a) += k;
    K(b, b) += k;
    K(a, b) -= k;
    K(b, a) -= k;
}

/// A system of dense M, C, K, excitation F, static load S and contacts.
inline System assemble_system(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K, const Eigen::MatrixXd& C,
                              const Eigen::VectorXd& F, const Eigen::VectorXd& S, std::vector<Contact> contacts) {
    System s;
    s.contacts = std::move(contacts);
    s.mass = M.sparseView();
    s.stiffness = K.sparseView();
    s.damping = C.sparseView();
    s.excitation = F;
    s.static_load = S;
    return s;
}

inline System contact_chain(int n, double force) {
    const int size = 3 * n;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size), K = M, C = M;
    const double masses[] = {1.0, 0.7, 0.4}, kt[] = {3.0, 2.0, 4.0}, kn[] = {5.0, 6.0, 4.0},
                 preloads[] = {1.0, 0.6, 0.8}, forces[] = {0.3, 1.0, -0.5}, links[] = {1.5, 1.0};
    auto spring = [&K](int a, int b, double k) { add_spring(K, a, b, k); };
    Eigen::VectorXd F = Eigen::VectorXd::Zero(size), S = Eigen::VectorXd::Zero(size);
    for (int i = 0; i < n; ++i) {
        M(i, i) = masses[i % 3];
        C(i, i) = 0.02 * masses[i % 3];
        F(i) = forces[i % 3] * force;
        if (i + 1 < n) spring(i, i + 1, links[i % 2]);
    }
    K(0, 0) += 2.0;
    K(n - 1, n - 1) += 0.5;
    if (n > 1) {
        C(0, 0) += 0.01;
        C(1, 1) += 0.01;
        C(0, 1) = C(1, 0) = -0.01;
    }
    std::vector<Contact> contacts;
    for (int c = 0; c < n; ++c) {
        const int t = n + 2 * c, v = t + 1, across = (c + 1) % n;
        spring(c, t, kt[c % 3]);
        spring(across, v, kn[c % 3]);
        S(v) += preloads[c % 3];       // the node onto the wall
        S(across) -= preloads[c % 3];  // and the structure away from it: N = preload at rest
        Contact k;
        k.law = parse_friction_law("unilateral");
        k.dof = t;
        k.values["friction_coefficient"] = 0.3;
        k.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(size), 0.0);
        k.lists["normal_direction"][static_cast<std::size_t>(v)] = 1.0;
        contacts.push_back(k);
    }
    return assemble_system(M, K, C, F, S, std::move(contacts));
}

}  // namespace hbf::bench

namespace hbf::bench {

/// The chain in 3D: each mass also moves along the wall's second tangential direction (DOFs
/// y_1..y_n after x_1..x_n), tied to a second tangential node of its contact (k_t2 2.5, 3.5,
/// 1.5), with springs 1.2 and 0.8 between neighbours and 1.0, 1.5 to ground at the ends, damping
/// 3 % of each mass, and forces `second` times (-0.4, 0.8, 0.6): the x and y responses differ in
/// phase, so the nodes slip along curved paths. Per contact the nodes t1, t2, n follow the
/// masses' DOFs. With second = 0 the y DOFs stay at rest and the chain is contact_chain's.
inline System contact_chain_3d(int n, double force, double second) {
    const System planar = contact_chain(n, force);
    const int size = 5 * n;
    const Eigen::MatrixXd M2(planar.mass), K2(planar.stiffness), C2(planar.damping);
    // index map: planar DOF -> 3D DOF (x_i -> i; node t of contact c -> 2n + 3c, normal -> 2n + 3c + 2)
    std::vector<int> map(static_cast<std::size_t>(3 * n));
    for (int i = 0; i < n; ++i) map[static_cast<std::size_t>(i)] = i;
    for (int c = 0; c < n; ++c) {
        map[static_cast<std::size_t>(n + 2 * c)] = 2 * n + 3 * c;
        map[static_cast<std::size_t>(n + 2 * c + 1)] = 2 * n + 3 * c + 2;
    }
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(size, size), K = M, C = M;
    Eigen::VectorXd F = Eigen::VectorXd::Zero(size), S = Eigen::VectorXd::Zero(size);
    for (int a = 0; a < 3 * n; ++a) {
        F(map[static_cast<std::size_t>(a)]) = planar.excitation(a);
        S(map[static_cast<std::size_t>(a)]) = planar.static_load(a);
        for (int b = 0; b < 3 * n; ++b) {
            M(map[static_cast<std::size_t>(a)], map[static_cast<std::size_t>(b)]) = M2(a, b);
            K(map[static_cast<std::size_t>(a)], map[static_cast<std::size_t>(b)]) = K2(a, b);
            C(map[static_cast<std::size_t>(a)], map[static_cast<std::size_t>(b)]) = C2(a, b);
        }
    }
    auto spring = [&K](int a, int b, double k) { add_spring(K, a, b, k); };
    const double masses[] = {1.0, 0.7, 0.4}, kt2[] = {2.5, 3.5, 1.5}, forces[] = {-0.4, 0.8, 0.6}, links[] = {1.2, 0.8};
    for (int i = 0; i < n; ++i) {
        const int y = n + i;
        M(y, y) = masses[i % 3];
        C(y, y) = 0.03 * masses[i % 3];
        F(y) = forces[i % 3] * second;
        if (i + 1 < n) spring(y, y + 1, links[i % 2]);
        spring(y, 2 * n + 3 * i + 1, kt2[i % 3]);
    }
    K(n, n) += 1.0;
    K(2 * n - 1, 2 * n - 1) += 1.5;
    std::vector<Contact> contacts;
    for (int c = 0; c < n; ++c) {
        Contact k = planar.contacts[static_cast<std::size_t>(c)];
        k.dof = 2 * n + 3 * c;
        k.lists["second_direction"] = std::vector<double>(static_cast<std::size_t>(size), 0.0);
        k.lists["second_direction"][static_cast<std::size_t>(2 * n + 3 * c + 1)] = 1.0;
        k.lists["normal_direction"] = std::vector<double>(static_cast<std::size_t>(size), 0.0);
        k.lists["normal_direction"][static_cast<std::size_t>(2 * n + 3 * c + 2)] = 1.0;
        contacts.push_back(k);
    }
    return assemble_system(M, K, C, F, S, std::move(contacts));
}

}  // namespace hbf::bench
