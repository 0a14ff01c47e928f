#!/usr/bin/env python3
"""Writes a finite-element cantilever with a friction contact near its tip, for hbf frf --config.

An Euler-Bernoulli beam (steel, 1 m long, 40 mm x 10 mm section, SI units) clamped at x = 0,
ELEMENTS Hermite-cubic elements, two DOFs per node (transverse displacement w [m], rotation
theta [rad]): N = 2 ELEMENTS DOFs. Consistent mass and stiffness matrices (element matrices
below), Rayleigh damping C = a M + b K with 1 % of critical damping at the first two bending
frequencies of the continuous beam (omega_n = beta_n^2 sqrt(EI / (rho A L^4)), beta_1 L =
1.8751, beta_2 L = 4.6941). A force F cos(omega t) of 10 N acts transversally at mid-span; an
exact Coulomb contact (friction limit 3 N) holds the tip's transverse displacement against
the ground. Omega is in rad/s: the first bending mode is at 52.5 rad/s (8.4 Hz).

Writes, beside this script (or in --out DIR): beam<N>_mass.mtx, beam<N>_stiffness.mtx,
beam<N>_damping.mtx (Matrix Market, symmetric, coordinate: read sparse) and beam<N>.toml.
Only the Python standard library is used.

Usage: make_beam.py [--elements 100] [--out DIR]
"""
import argparse
import math
import os

E = 210e9          # Young's modulus [Pa]
RHO = 7850.0       # density [kg/m^3]
LENGTH = 1.0       # [m]
WIDTH, HEIGHT = 0.04, 0.01  # section [m]
AREA = WIDTH * HEIGHT
INERTIA = WIDTH * HEIGHT ** 3 / 12.0
FORCE = 10.0       # mid-span force amplitude [N]
FRICTION = 3.0     # tip friction limit [N]
ZETA = 0.01        # damping ratio at the first two bending modes


def element_matrices(l):
    k = E * INERTIA / l ** 3
    ke = [[12, 6 * l, -12, 6 * l],
          [6 * l, 4 * l * l, -6 * l, 2 * l * l],
          [-12, -6 * l, 12, -6 * l],
          [6 * l, 2 * l * l, -6 * l, 4 * l * l]]
    m = RHO * AREA * l / 420.0
    me = [[156, 22 * l, 54, -13 * l],
          [22 * l, 4 * l * l, 13 * l, -3 * l * l],
          [54, 13 * l, 156, -22 * l],
          [-13 * l, -3 * l * l, -22 * l, 4 * l * l]]
    return [[k * v for v in row] for row in ke], [[m * v for v in row] for row in me]


def assemble(elements):
    """Lower triangles {(i, j): value} (0-based, i >= j) of K and M without the clamped node."""
    l = LENGTH / elements
    ke, me = element_matrices(l)
    k, m = {}, {}
    for e in range(elements):
        # element e joins nodes e and e + 1; node 0 is clamped (its DOFs removed), node i >= 1
        # has DOFs 2 (i - 1) (w) and 2 (i - 1) + 1 (theta).
        dofs = [2 * (e - 1), 2 * (e - 1) + 1, 2 * e, 2 * e + 1]
        for a in range(4):
            for b in range(4):
                i, j = dofs[a], dofs[b]
                if i < 0 or j < 0 or i < j:
                    continue
                k[(i, j)] = k.get((i, j), 0.0) + ke[a][b]
                m[(i, j)] = m.get((i, j), 0.0) + me[a][b]
    return k, m


def write_mtx(path, n, entries):
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write("% written by make_beam.py (lower triangle, 1-based)\n")
        f.write("%d %d %d\n" % (n, n, len(entries)))
        for (i, j), v in sorted(entries.items(), key=lambda item: (item[0][1], item[0][0])):
            f.write("%d %d %.17g\n" % (i + 1, j + 1, v))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--elements", type=int, default=100, help="number of beam elements (N = 2 x elements DOFs)")
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)), help="output directory")
    args = parser.parse_args()
    if args.elements < 2:
        parser.error("--elements must be at least 2")
    n = 2 * args.elements
    k, m = assemble(args.elements)
    c0 = math.sqrt(E * INERTIA / (RHO * AREA * LENGTH ** 4))
    w1, w2 = 1.8751 ** 2 * c0, 4.6941 ** 2 * c0
    # zeta(w) = a / (2 w) + b w / 2 equal to ZETA at w1 and w2
    b = 2.0 * ZETA / (w1 + w2)
    a = b * w1 * w2
    c = {key: a * m.get(key, 0.0) + b * k.get(key, 0.0) for key in set(k) | set(m)}
    name = "beam%d" % n
    os.makedirs(args.out, exist_ok=True)
    write_mtx(os.path.join(args.out, name + "_stiffness.mtx"), n, k)
    write_mtx(os.path.join(args.out, name + "_mass.mtx"), n, m)
    write_mtx(os.path.join(args.out, name + "_damping.mtx"), n, c)
    mid_node = args.elements // 2
    tip = n - 2  # the tip's transverse DOF (0-based)
    with open(os.path.join(args.out, name + ".toml"), "w") as f:
        f.write("# Euler-Bernoulli cantilever, %d elements, N = %d DOFs (written by make_beam.py: see there).\n"
                % (args.elements, n))
        f.write("# SI units: displacements m, rotations rad, forces N, w in rad/s (first mode %.1f rad/s).\n" % w1)
        f.write("# DOF 2 i - 1 = transverse displacement of node i, DOF 2 i = its rotation (1-based).\n")
        f.write("[structure]\n")
        f.write('mass = "%s_mass.mtx"\n' % name)
        f.write('stiffness = "%s_stiffness.mtx"\n' % name)
        f.write('damping = "%s_damping.mtx"\n' % name)
        excitation = [0.0] * n
        excitation[2 * (mid_node - 1)] = FORCE
        f.write("excitation = [%s]\n" % ", ".join("%g" % v for v in excitation))
        f.write("\n[[contact]]   # the tip's transverse displacement against the ground\n")
        f.write("dof = %d\nlaw = \"coulomb\"\nfriction_limit = %g\n" % (tip + 1, FRICTION))
        f.write("\n[frequency]\nwmin = 30.0\nwmax = 80.0\n")
        f.write("\n[solver]   # exact Coulomb: DLFT error ~1/H (0.4 % in y_max at w = 40 against time integration)\n"
                "harmonics = 20\n")
        f.write("\n[output]   # mid-span and tip transverse displacements\n")
        f.write("report = [%d, %d]\n" % (2 * (mid_node - 1) + 1, tip + 1))


if __name__ == "__main__":
    main()
