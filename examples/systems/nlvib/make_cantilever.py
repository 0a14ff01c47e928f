#!/usr/bin/env python3
"""Writes NLvib's cantilever with a cubic spring at its tip (the ECL benchmark beam) for hbf.

The structure is the one of NLvib's ninth example (Krack and Gross, Harmonic Balance for
Nonlinear Vibration Problems, Springer 2019; after F. Thouverez, Presentation of the ECL
benchmark, MSSP 17 (2003) 195-202), from its published parameters: an Euler-Bernoulli beam,
0.7 m long, square section 14 mm x 14 mm, E = 2.05e11 Pa, rho = 7800 kg/m^3, 20 equidistant
nodes (19 Hermite-cubic elements, consistent mass), clamped at x = 0; two DOFs per free node
(transverse displacement [m], rotation [rad]), N = 38; a cubic spring f = 6e9 q^3 [N, m]
between the tip's transverse displacement and the ground.

NLvib computes the first nonlinear mode of the undamped beam (modal amplitude a, the first
harmonic's M-norm, from 1e-5 to 1e-3). The forced response is ours (NLvib's example has
none): Rayleigh damping C = a M + b K with ZETA of critical at the first two linear modes (the
stiffness part damps the beam's high modes, which the time integration and the monodromy
would otherwise resolve at their own frequencies), and a force of TIP_FORCE at the tip.

Writes cantilever_cubic_mass.mtx, cantilever_cubic_stiffness.mtx, cantilever_cubic_damping.mtx
(Matrix Market, symmetric) and cantilever_cubic.toml beside this script (or in --out DIR).
Only the Python standard library is used.

Usage: make_cantilever.py [--out DIR]
"""
import argparse
import math
import os

LENGTH = 0.7              # [m]
SIDE = 0.014              # height = thickness [m]
E = 2.05e11               # Young's modulus [Pa]
RHO = 7800.0              # density [kg/m^3]
NODES = 20                # equidistant, node 1 clamped
K3 = 6.0e9                # the tip's cubic spring [N/m^3]
ZETA = 0.01               # damping ratio of the first two linear modes (Rayleigh)
TIP_FORCE = 0.2           # forced response: amplitude of the tip force [N]
NAME = "cantilever_cubic"


def element_matrices(l):
    """Hermite-cubic beam element: stiffness and consistent mass (DOFs w1, theta1, w2, theta2)."""
    ei = E * SIDE ** 4 / 12.0
    rho_a = RHO * SIDE * SIDE
    ks = ei / l ** 3
    ms = rho_a * l / 420.0
    ke = [[12, 6 * l, -12, 6 * l], [6 * l, 4 * l * l, -6 * l, 2 * l * l],
          [-12, -6 * l, 12, -6 * l], [6 * l, 2 * l * l, -6 * l, 4 * l * l]]
    me = [[156, 22 * l, 54, -13 * l], [22 * l, 4 * l * l, 13 * l, -3 * l * l],
          [54, 13 * l, 156, -22 * l], [-13 * l, -3 * l * l, -22 * l, 4 * l * l]]
    return [[ks * v for v in row] for row in ke], [[ms * v for v in row] for row in me]


def assemble():
    """Dense K and M (lists of rows) without the clamped node's two DOFs."""
    elements = NODES - 1
    n = 2 * elements
    ke, me = element_matrices(LENGTH / elements)
    k = [[0.0] * n for _ in range(n)]
    m = [[0.0] * n for _ in range(n)]
    for e in range(elements):
        dofs = [2 * (e - 1), 2 * (e - 1) + 1, 2 * e, 2 * e + 1]  # node e (clamped for e = 0), node e + 1
        for a in range(4):
            for b in range(4):
                i, j = dofs[a], dofs[b]
                if i >= 0 and j >= 0:
                    k[i][j] += ke[a][b]
                    m[i][j] += me[a][b]
    return k, m


def lowest_frequencies(k, m, count):
    """The `count` lowest w with det(K - w^2 M) = 0, by inverse iteration on K^-1 M with the
    modes found M-orthogonalised away (dense, small)."""
    n = len(k)
    found, modes = [], []
    for _ in range(count):
        x = [1.0 + i for i in range(n)]
        lam = 0.0
        for _ in range(500):
            for phi in modes:  # remove the lower modes: x -= phi (phi^T M x)
                p = sum(phi[i] * sum(m[i][j] * x[j] for j in range(n)) for i in range(n))
                x = [u - p * v for u, v in zip(x, phi)]
            y = gauss(k, [sum(m[i][j] * x[j] for j in range(n)) for i in range(n)])
            norm = math.sqrt(sum(v * v for v in y))
            lam_new = norm / math.sqrt(sum(v * v for v in x))
            x = [v / norm for v in y]
            if abs(lam_new - lam) <= 1e-15 * lam_new:
                break
            lam = lam_new
        mass = sum(x[i] * sum(m[i][j] * x[j] for j in range(n)) for i in range(n))
        modes.append([v / math.sqrt(mass) for v in x])
        found.append(1.0 / math.sqrt(lam_new))
    return found


def gauss(a, b):
    """Solves a x = b (a copied) by Gaussian elimination with partial pivoting."""
    n = len(a)
    a = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(a[r][c]))
        a[c], a[p] = a[p], a[c]
        for r in range(c + 1, n):
            f = a[r][c] / a[c][c]
            if f != 0.0:
                a[r] = [u - f * v for u, v in zip(a[r], a[c])]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (a[r][n] - sum(a[r][j] * x[j] for j in range(r + 1, n))) / a[r][r]
    return x


def write_mtx(path, a):
    n = len(a)
    entries = [(i, j, a[i][j]) for j in range(n) for i in range(j, n) if a[i][j] != 0.0]
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write("%% written by make_cantilever.py (lower triangle, 1-based)\n")
        f.write("%d %d %d\n" % (n, n, len(entries)))
        for i, j, v in entries:
            f.write("%d %d %.17g\n" % (i + 1, j + 1, v))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)), help="output directory")
    args = parser.parse_args()
    k, m = assemble()
    n = len(k)
    w1, w2 = lowest_frequencies(k, m, 2)
    # zeta(w) = a / (2 w) + b w / 2 equal to ZETA at w1 and w2
    b = 2.0 * ZETA / (w1 + w2)
    a = b * w1 * w2
    c = [[a * mv + b * kv for mv, kv in zip(mr, kr)] for mr, kr in zip(m, k)]
    os.makedirs(args.out, exist_ok=True)
    for suffix, matrix in (("mass", m), ("stiffness", k), ("damping", c)):
        write_mtx(os.path.join(args.out, "%s_%s.mtx" % (NAME, suffix)), matrix)
    tip = n - 2  # the tip's transverse DOF (0-based)
    excitation = [0.0] * n
    excitation[tip] = TIP_FORCE
    with open(os.path.join(args.out, NAME + ".toml"), "w") as f:
        f.write("# NLvib's cantilever with a cubic spring at its tip (the ECL benchmark beam), written by\n"
                "# make_cantilever.py (see there): 0.7 m, 14 mm x 14 mm, E = 2.05e11 Pa, rho = 7800 kg/m^3,\n"
                "# 19 elements, N = %d DOFs (DOF 2 i - 1 the transverse displacement of free node i, DOF 2 i\n"
                "# its rotation), the cubic spring f = %g q^3 at the tip (DOF %d). SI units, w in rad/s\n"
                "# (linear modes %.4f and %.4f rad/s).\n"
                "# NLvib's example is the undamped beam's first nonlinear mode (modal amplitude 1e-5 to 1e-3);\n"
                "# the damping and the force are ours: Rayleigh damping C = %.6g M + %.6g K (1 %% at the\n"
                "# first two modes) and %g N at the tip. The forced response bends to the right with two folds:\n"
                "#     hbf frf --config cantilever_cubic.toml --stability monodromy\n"
                "#     hbf modes --config cantilever_cubic.toml --amin 1e-5 --amax 1e-3\n"
                % (n, K3, tip + 1, w1, w2, a, b, TIP_FORCE))
        f.write("[structure]\n")
        for suffix in ("mass", "stiffness", "damping"):
            f.write('%s = "%s_%s.mtx"\n' % (suffix, NAME, suffix))
        f.write("excitation = [%s]\n" % ", ".join("%g" % v for v in excitation))
        f.write("\n[[contact]]   # the cubic spring at the tip\n")
        f.write("dof = %d\nlaw = \"polynomial\"\ncubic = %g\n" % (tip + 1, K3))
        f.write("\n[frequency]\nwmin = %.1f\nwmax = %.1f\n" % (0.8 * w1, 2.0 * w1))
        f.write("\n[output]   # the tip's transverse displacement\nreport = [%d]\n" % (tip + 1))


if __name__ == "__main__":
    main()
