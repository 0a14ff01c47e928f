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

And a reduced model of the same beam, beam<N>_reduced.toml, with the features of the reduced
finite-element models users bring (a massless contact coordinate, physical units, the
response of interest a combination of the coordinates):
  * Guyan (static) reduction onto the transverse displacements of 5 master nodes, at 1/5,
    2/5, ..., 5/5 of the length (the tip): y = T u, T = [I; -K_ss^-1 K_sm], M_r = T^T M T,
    K_r = T^T K T, C_r = a M_r + b K_r (the same Rayleigh coefficients), F_r = T^T F;
  * a massless contact shoe, coordinate 6: joined to the tip by a spring K_SHOE, it slides on
    the ground with exact Coulomb friction (limit 3 N), so M and C are zero in its row;
  * outputs: the mid-span displacement, the row T[mid-span] (an [[output]] vector), and the
    tip.
And beam<N>_jointed.toml, friction and polynomial stiffness in one model: the same Guyan model
(no shoe) whose tip is held by a friction joint (law dahl: a bristle of 3 kN/m sliding at 10 N)
and stiffened by a cubic spring f = K3_TIP q^3 (the geometric stiffening of a large tip
deflection); every element smooth, so the stability analysis covers it.
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
K_SHOE = 1.0e5     # spring between the tip and the massless contact shoe (reduced model) [N/m]
JOINT_LIMIT = 10.0      # the jointed model's friction joint at the tip: slip force [N]
JOINT_STIFFNESS = 3.0e3  # and bristle stiffness [N/m] (law dahl)
K3_TIP = 5.0e8           # its cubic spring at the tip: f = K3_TIP q^3 [N/m^3]
MASTERS = 5        # master nodes of the reduced model


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


def dense(lower, n):
    """The symmetric dense matrix (list of rows) of a lower triangle {(i, j): value}."""
    a = [[0.0] * n for _ in range(n)]
    for (i, j), v in lower.items():
        a[i][j] = v
        a[j][i] = v
    return a


def solve(a, b):
    """Solves a x = b (a: n x n rows, b: n x m rows) by Gaussian elimination with partial
    pivoting, skipping the zeros of the band; a and b are overwritten."""
    n, m = len(a), len(b[0])
    for col in range(n):
        pivot = max(range(col, n), key=lambda r: abs(a[r][col]))
        a[col], a[pivot] = a[pivot], a[col]
        b[col], b[pivot] = b[pivot], b[col]
        for r in range(col + 1, n):
            factor = a[r][col] / a[col][col]
            if factor == 0.0:
                continue
            row, top = a[r], a[col]
            for c in range(col, n):
                if top[c] != 0.0:
                    row[c] -= factor * top[c]
            for c in range(m):
                b[r][c] -= factor * b[col][c]
    x = [[0.0] * m for _ in range(n)]
    for r in range(n - 1, -1, -1):
        for c in range(m):
            total = b[r][c] - sum(a[r][k] * x[k][c] for k in range(r + 1, n) if a[r][k] != 0.0)
            x[r][c] = total / a[r][r]
    return x


def congruence(a, t):
    """t^T a t for a dense symmetric a (n x n) and t (n x m)."""
    n, m = len(t), len(t[0])
    at = [[sum(a[i][k] * t[k][c] for k in range(n) if a[i][k] != 0.0) for c in range(m)] for i in range(n)]
    p = [[sum(t[k][r] * at[k][c] for k in range(n)) for c in range(m)] for r in range(m)]
    return [[0.5 * (p[r][c] + p[c][r]) for c in range(m)] for r in range(m)]  # symmetric to the bit


def matrix_text(rows):
    return "[" + ",\n        ".join("[" + ", ".join("%.17g" % v for v in row) + "]" for row in rows) + "]"


def guyan(elements, k, m, a, b):
    """The beam reduced (Guyan) onto the transverse displacements of the master nodes: K_r, M_r,
    C_r = a M_r + b K_r, and the row of T at mid-span (mid-span is not a master)."""
    n = 2 * elements
    masters = [2 * (elements * j // MASTERS - 1) for j in range(1, MASTERS + 1)]
    slaves = [i for i in range(n) if i not in masters]
    kd, md = dense(k, n), dense(m, n)
    k_ss = [[kd[i][j] for j in slaves] for i in slaves]
    k_sm = [[kd[i][j] for j in masters] for i in slaves]
    x = solve(k_ss, k_sm)
    t = [[0.0] * MASTERS for _ in range(n)]
    for c, i in enumerate(masters):
        t[i][c] = 1.0
    for r, i in enumerate(slaves):
        for c in range(MASTERS):
            t[i][c] = -x[r][c]
    k_r, m_r = congruence(kd, t), congruence(md, t)
    c_r = [[a * m_r[i][j] + b * k_r[i][j] for j in range(MASTERS)] for i in range(MASTERS)]
    return k_r, m_r, c_r, t[2 * (elements // 2 - 1)]


def write_structure(f, mass, stiffness, damping, mid_row):
    """A reduced model's [structure] table: its matrices and T^T F (the force at mid-span)."""
    f.write("[structure]\n")
    f.write("mass = %s\n" % matrix_text(mass))
    f.write("stiffness = %s\n" % matrix_text(stiffness))
    f.write("damping = %s\n" % matrix_text(damping))
    f.write("excitation = [%s]   # T^T F: 10 N at mid-span\n" % ", ".join("%.17g" % (FORCE * v) for v in mid_row))


def write_reduced(out, name, elements, k, m, a, b):
    """The Guyan-reduced beam with a massless contact shoe (see the module comment)."""
    n = 2 * elements
    k_r, m_r, c_r, mid_row = guyan(elements, k, m, a, b)
    nr = MASTERS + 1
    stiffness = [[0.0] * nr for _ in range(nr)]
    mass = [[0.0] * nr for _ in range(nr)]
    damping = [[0.0] * nr for _ in range(nr)]
    for i in range(MASTERS):
        for j in range(MASTERS):
            stiffness[i][j] = k_r[i][j]
            mass[i][j] = m_r[i][j]
            damping[i][j] = c_r[i][j]
    tip = MASTERS - 1
    stiffness[tip][tip] += K_SHOE
    stiffness[tip][MASTERS] = stiffness[MASTERS][tip] = -K_SHOE
    stiffness[MASTERS][MASTERS] = K_SHOE
    row = mid_row + [0.0]
    with open(os.path.join(out, name + "_reduced.toml"), "w") as f:
        f.write("# The %d-DOF beam of %s.toml reduced (Guyan) onto the transverse displacements of %d master nodes\n"
                "# (coordinates 1-%d, the last one the tip), plus a massless contact shoe (coordinate %d) joined to\n"
                "# the tip by a spring of %g N/m and sliding on the ground with exact Coulomb friction.\n"
                "# Written by make_beam.py (see there). SI units: m, N, kg, w in rad/s.\n"
                % (n, name, MASTERS, MASTERS, nr, K_SHOE))
        write_structure(f, mass, stiffness, damping, row)
        f.write("\n[[contact]]   # the massless shoe against the ground\n")
        f.write("dof = %d\nlaw = \"coulomb\"\nfriction_limit = %g\n" % (nr, FRICTION))
        f.write("\n[frequency]\nwmin = 30.0\nwmax = 80.0\n")
        f.write("\n[solver]\nharmonics = 20\n")
        f.write("\n[[output]]   # mid-span displacement: its row of T (mid-span is not a master)\n")
        f.write("name = \"midspan\"\nrow = [%s]\n" % ", ".join("%.17g" % v for v in row))
        f.write("\n[[output]]   # the tip\nname = \"tip\"\ndof = %d\n" % MASTERS)


def write_jointed(out, name, elements, k, m, a, b):
    """The Guyan-reduced beam (no shoe) whose tip is held by a friction joint (Dahl: a bristle of
    stiffness JOINT_STIFFNESS sliding at JOINT_LIMIT) and stiffened by a cubic spring K3_TIP:
    friction and polynomial stiffness in one model, every element smooth."""
    n = 2 * elements
    k_r, m_r, c_r, mid_row = guyan(elements, k, m, a, b)
    with open(os.path.join(out, name + "_jointed.toml"), "w") as f:
        f.write("# The %d-DOF beam of %s.toml reduced (Guyan) onto the transverse displacements of %d master nodes\n"
                "# (coordinates 1-%d, the last one the tip), its tip held by a friction joint (law dahl: a bristle of\n"
                "# stiffness %g N/m sliding at %g N) and stiffened by a cubic spring f = %g q^3 (N, q in m): the\n"
                "# geometric stiffening of a large tip deflection. Friction and polynomial stiffness in one model.\n"
                "# Written by make_beam.py (see there). SI units: m, N, kg, w in rad/s.\n"
                % (n, name, MASTERS, MASTERS, JOINT_STIFFNESS, JOINT_LIMIT, K3_TIP))
        write_structure(f, m_r, k_r, c_r, mid_row)
        f.write("\n[[contact]]   # the friction joint at the tip\n")
        f.write("dof = %d\nlaw = \"dahl\"\nfriction_limit = %g\nstiffness = %g\n" % (MASTERS, JOINT_LIMIT, JOINT_STIFFNESS))
        f.write("\n[[contact]]   # the cubic spring at the tip\n")
        f.write("dof = %d\nlaw = \"polynomial\"\ncubic = %g\n" % (MASTERS, K3_TIP))
        f.write("\n[frequency]\nwmin = 30.0\nwmax = 160.0\n")
        f.write("\n[[output]]   # mid-span displacement: its row of T (mid-span is not a master)\n")
        f.write("name = \"midspan\"\nrow = [%s]\n" % ", ".join("%.17g" % v for v in mid_row))
        f.write("\n[[output]]   # the tip\nname = \"tip\"\ndof = %d\n" % MASTERS)


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
    if args.elements % MASTERS == 0:
        write_reduced(args.out, name, args.elements, k, m, a, b)
        write_jointed(args.out, name, args.elements, k, m, a, b)


if __name__ == "__main__":
    main()
