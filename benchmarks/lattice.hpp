// hbfriction benchmarks and tests: an elastic block with a meshed contact face of many nodes,
// built in code (no files), for the many-node condensed solver (issue 32).
//
// A lattice of nx x ny x (layers + 1) nodes (3D; 2D: nx x (layers + 1), ny ignored) at unit
// spacing, the bottom layer clamped, every pair of neighbouring nodes (offsets in {-1, 0, 1} per
// axis) joined by an axial spring of stiffness 1 / |e| (a truss with face and body diagonals:
// stable), unit lumped masses, Rayleigh damping C = beta K with 1 % at the first mode's
// frequency (approximately: beta = 0.02 / w1 with w1 the lowest eigenfrequency). The top layer
// of nx ny nodes (2D: nx) is one contact interface against a rigid wall above it, law elastic
// (closing along +z, 2D +y; tangents x, y; 2D x), stiffnesses k_t, k_n and a preload pressure
// per node; the force F cos(w t) pushes every top node along x (and y in 3D, half as hard), so
// that the face slides and, with the block's rocking, unloads on one side.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/interface.hpp"
#include "hbf/model.hpp"

namespace hbf::bench {

struct LatticeOptions {
    int nx = 10, ny = 10;  ///< contact nodes: nx ny (3D) or nx (2D)
    int dimension = 3;     ///< 2 or 3
    int layers = 2;        ///< free node layers (the clamped one not counted)
    double tangential_stiffness = 2.0, normal_stiffness = 5.0;  ///< per node
    double friction_coefficient = 0.3;
    double preload = 0.02;  ///< normal preload per node (a pressure times the node's area)
    double force = 0.01;    ///< per top node, along x (3D: and half of it along y)
};

inline System lattice(const LatticeOptions& o) {
    const int d = o.dimension, nx = o.nx, ny = d == 3 ? o.ny : 1, nz = o.layers;
    // node (i, j, l), l = 1..nz free; DOFs d p + axis, p = ((l - 1) ny + j) nx + i
    auto node = [&](int i, int j, int l) { return ((l - 1) * ny + j) * nx + i; };
    const int nodes = nx * ny * nz, dofs = d * nodes;
    std::vector<Eigen::Triplet<double>> k, m;
    for (int p = 0; p < dofs; ++p) m.emplace_back(p, p, 1.0);
    for (int l = 0; l <= nz; ++l)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (int dl = -1; dl <= 1; ++dl)
                    for (int dj = (d == 3 ? -1 : 0); dj <= (d == 3 ? 1 : 0); ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            // each link once: towards the lexicographically larger neighbour
                            const int key = (dl * 3 + dj) * 3 + di;
                            if (key <= 0) continue;
                            const int i2 = i + di, j2 = j + dj, l2 = l + dl;
                            if (i2 < 0 || i2 >= nx || j2 < 0 || j2 >= ny || l2 < 0 || l2 > nz) continue;
                            if (l == 0 && l2 == 0) continue;  // both clamped
                            Eigen::Vector3d e(di, d == 3 ? dj : dl, d == 3 ? dl : 0);
                            const double length = e.norm();
                            e /= length;
                            const double s = 1.0 / length;
                            const int a = l > 0 ? node(i, j, l) : -1, b = l2 > 0 ? node(i2, j2, l2) : -1;
                            for (int p = 0; p < d; ++p)
                                for (int q = 0; q < d; ++q) {
                                    const double v = s * e(p) * e(q);
                                    if (a >= 0) k.emplace_back(d * a + p, d * a + q, v);
                                    if (b >= 0) k.emplace_back(d * b + p, d * b + q, v);
                                    if (a >= 0 && b >= 0) {
                                        k.emplace_back(d * a + p, d * b + q, -v);
                                        k.emplace_back(d * b + p, d * a + q, -v);
                                    }
                                }
                        }
    System s;
    s.mass.resize(dofs, dofs);
    s.stiffness.resize(dofs, dofs);
    s.mass.setFromTriplets(m.begin(), m.end());
    s.stiffness.setFromTriplets(k.begin(), k.end());
    // The first mode of a clamped lattice this shallow is stiff; its frequency from a few
    // inverse iterations is enough for the damping's scale.
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(s.stiffness);
    Eigen::VectorXd v = Eigen::VectorXd::Ones(dofs);
    double lambda = 1.0;
    for (int it = 0; it < 50; ++it) {
        Eigen::VectorXd w = ldlt.solve(v);
        lambda = v.dot(v) / v.dot(w);
        v = w / w.norm();
    }
    const double w1 = std::sqrt(lambda);
    s.damping = (0.02 / w1) * s.stiffness;
    s.excitation = Eigen::VectorXd::Zero(dofs);
    ContactInterface face;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const int p = node(i, j, nz);
            std::vector<int> triple;
            for (int a = 0; a < d; ++a) triple.push_back(d * p + a);
            face.nodes.push_back(triple);
            s.excitation(d * p) = o.force;
            if (d == 3) s.excitation(d * p + 1) = 0.5 * o.force;
        }
    Eigen::RowVectorXd normal = Eigen::RowVectorXd::Zero(d);
    normal(d - 1) = 1.0;
    face.normals = normal;
    if (d == 3) face.tangents = Eigen::RowVector3d(1.0, 0.0, 0.0);
    face.prototype.law = parse_friction_law("elastic");
    face.prototype.stiffness = o.tangential_stiffness;
    face.prototype.values["normal_stiffness"] = o.normal_stiffness;
    face.prototype.values["preload"] = o.preload;
    face.prototype.values["friction_coefficient"] = o.friction_coefficient;
    s.contacts = interface_contacts(face, dofs, dofs, [](int dof) { return dof; });
    return s;
}

}  // namespace hbf::bench
