#!/usr/bin/env python3
"""Writes one sector of a bladed disk, a plane-stress finite-element model, for hbf frf --config.

A steel wheel of N = 24 sectors (thickness 10 mm, SI units) in its plane: a disk ring from
r = 0.10 m (clamped to the shaft) to r = 0.16 m and a straight blade 21 mm wide from the rim to
r = 0.30 m, with a platform: a lip on each side of the blade just above the rim, reaching
towards the neighbouring blades. Bilinear 4-node quadrilaterals (2 x 2 Gauss points,
consistent mass). Each node's two DOFs are its radial and circumferential displacements
(u_r, u_t: the node's own polar frame), so that the sector's right cut face (theta = 15 deg)
moves as the next sector's left face (theta = 0) DOF for DOF: [cyclic] left and right.

An under-platform damper joins the tip of this blade's right lip to the tip of the next
blade's left lip ([[contact]] neighbour_dof): a Jenkins element (stiffness k_t in series with
a slider of slip force mu N) on their relative circumferential displacement. A force
F cos(omega t) at the blade tip, circumferential, travels round the wheel with engine order 3.

The system file reduces the sector inside hbf ([reduction], Craig-Bampton: the damper's DOFs,
the loaded DOF and the cut faces kept, 12 fixed-interface modes), with stiffness-proportional
damping of the reduced model.

Writes, beside this script (or in --out DIR): sector_mass.mtx, sector_stiffness.mtx (Matrix
Market, symmetric, coordinate) and sector.toml. Only the Python standard library is used.

Usage: make_sector.py [--modes 12] [--slip-force 20] [--out DIR]
"""
import argparse
import math
import os

E = 210e9            # Young's modulus [Pa]
NU = 0.3             # Poisson's ratio
RHO = 7850.0         # density [kg/m^3]
THICKNESS = 0.01     # [m]
SECTORS = 24
ENGINE_ORDER = 3
R_IN, R_RIM, R_TIP = 0.10, 0.16, 0.30   # shaft, rim, blade tip [m]
NR, NT = 2, 4        # disk elements: radial, circumferential (over the sector)
NB = 8               # blade elements along its length
LIP = 0.010          # platform lip length (circumferential) [m]
LIP_LEVEL = 1        # the lips sit between blade levels 1 and 2
K_DAMPER = 2.0e8     # the damper's contact stiffness k_t [N/m]
SLIP_FORCE = 200.0   # its slip force mu N [N], above the optimum (hbf optimize: 143)
FORCE = 5.0          # tip force amplitude [N]
BETA = 2e-6          # stiffness-proportional damping of the reduced model, C_r = BETA K_r [s]
MODES = 12           # fixed-interface modes kept


def quad_matrices(xy):
    """Stiffness and consistent mass (8 x 8, DOFs x1 y1 x2 y2 ...) of a plane-stress bilinear quad
    with corners xy (counter-clockwise), by 2 x 2 Gauss quadrature."""
    c = E / (1.0 - NU * NU)
    d = [[c, c * NU, 0.0], [c * NU, c, 0.0], [0.0, 0.0, c * (1.0 - NU) / 2.0]]
    k = [[0.0] * 8 for _ in range(8)]
    m = [[0.0] * 8 for _ in range(8)]
    g = 1.0 / math.sqrt(3.0)
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    for xi in (-g, g):
        for eta in (-g, g):
            n = [(1 + a * xi) * (1 + b * eta) / 4.0 for a, b in corners]
            dn_dxi = [a * (1 + b * eta) / 4.0 for a, b in corners]
            dn_deta = [b * (1 + a * xi) / 4.0 for a, b in corners]
            j11 = sum(dn_dxi[i] * xy[i][0] for i in range(4))
            j12 = sum(dn_dxi[i] * xy[i][1] for i in range(4))
            j21 = sum(dn_deta[i] * xy[i][0] for i in range(4))
            j22 = sum(dn_deta[i] * xy[i][1] for i in range(4))
            det = j11 * j22 - j12 * j21
            if det <= 0.0:
                raise ValueError("a distorted or clockwise element")
            dn_dx = [(j22 * dn_dxi[i] - j12 * dn_deta[i]) / det for i in range(4)]
            dn_dy = [(-j21 * dn_dxi[i] + j11 * dn_deta[i]) / det for i in range(4)]
            b = [[0.0] * 8 for _ in range(3)]
            for i in range(4):
                b[0][2 * i] = dn_dx[i]
                b[1][2 * i + 1] = dn_dy[i]
                b[2][2 * i] = dn_dy[i]
                b[2][2 * i + 1] = dn_dx[i]
            w = det * THICKNESS
            db = [[sum(d[r][s] * b[s][col] for s in range(3)) for col in range(8)] for r in range(3)]
            for p in range(8):
                for q in range(8):
                    k[p][q] += w * sum(b[r][p] * db[r][q] for r in range(3))
            for i in range(4):
                for j in range(4):
                    v = w * RHO * n[i] * n[j]
                    m[2 * i][2 * j] += v
                    m[2 * i + 1][2 * j + 1] += v
    return k, m


def polar(r, theta):
    return (r * math.cos(theta), r * math.sin(theta))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--modes", type=int, default=MODES)
    parser.add_argument("--slip-force", type=float, default=SLIP_FORCE)
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    args = parser.parse_args()
    alpha = 2.0 * math.pi / SECTORS
    nodes = []      # (x, y)
    index = {}      # name -> node number

    def node(name, xy):
        index[name] = len(nodes)
        nodes.append(xy)
        return index[name]

    # The disk: rings i = 1..NR (i = 0, the shaft, is clamped: no node), j = 0..NT across.
    for i in range(1, NR + 1):
        for j in range(NT + 1):
            node(("disk", i, j), polar(R_IN + (R_RIM - R_IN) * i / NR, alpha * j / NT))
    # The blade: three lines of nodes (the rim nodes j = 1, 2, 3 moved radially outward along
    # the sector's middle), levels 1..NB above the rim (level 0 is the disk's rim).
    middle = alpha / 2.0
    radial = (math.cos(middle), math.sin(middle))
    for level in range(1, NB + 1):
        for s in range(3):
            x0, y0 = nodes[index[("disk", NR, s + 1)]]
            h = (R_TIP - R_RIM) * level / NB
            node(("blade", level, s), (x0 + h * radial[0], y0 + h * radial[1]))
    # The lips: from the blade's sides at levels LIP_LEVEL and LIP_LEVEL + 1, LIP outward
    # along the circumference's tangent (left: towards theta = 0, right: towards alpha).
    tangent = (-math.sin(middle), math.cos(middle))
    for side, sign, s in (("left", -1.0, 0), ("right", 1.0, 2)):
        for level in (LIP_LEVEL, LIP_LEVEL + 1):
            x0, y0 = nodes[index[("blade", level, s)]]
            node(("lip", side, level), (x0 + sign * LIP * tangent[0], y0 + sign * LIP * tangent[1]))

    def at(level, s):
        return index[("disk", NR, s + 1)] if level == 0 else index[("blade", level, s)]

    elements = []
    for i in range(NR):
        for j in range(NT):
            a = index[("disk", i, j)] if i > 0 else None
            b = index[("disk", i, j + 1)] if i > 0 else None
            c = index[("disk", i + 1, j + 1)]
            d = index[("disk", i + 1, j)]
            # counter-clockwise: outward along theta_j, back along theta_{j+1}
            elements.append([a, d, c, b] if i > 0 else [("shaft", j), d, c, ("shaft", j + 1)])
    for level in range(NB):
        for s in range(2):
            elements.append([at(level, s), at(level + 1, s), at(level + 1, s + 1), at(level, s + 1)])
    lo, hi = LIP_LEVEL, LIP_LEVEL + 1
    elements.append([index[("lip", "left", lo)], index[("lip", "left", hi)], at(hi, 0), at(lo, 0)])
    elements.append([at(lo, 2), at(hi, 2), index[("lip", "right", hi)], index[("lip", "right", lo)]])

    n = 2 * len(nodes)
    k_global = {}
    m_global = {}
    for element in elements:
        xy, dofs, thetas = [], [], []
        for corner in element:
            if isinstance(corner, tuple):  # a clamped shaft node: no DOF
                p = polar(R_IN, alpha * corner[1] / NT)
                xy.append(p)
                dofs += [None, None]
                thetas.append(math.atan2(p[1], p[0]))
            else:
                xy.append(nodes[corner])
                dofs += [2 * corner, 2 * corner + 1]
                thetas.append(math.atan2(nodes[corner][1], nodes[corner][0]))
        k, m = quad_matrices(xy)
        # Each node's (u_x, u_y) = R(theta) (u_r, u_t): A_polar = R^T A R per node pair.
        rot = [[0.0] * 8 for _ in range(8)]
        for i, th in enumerate(thetas):
            c, s = math.cos(th), math.sin(th)
            rot[2 * i][2 * i], rot[2 * i][2 * i + 1] = c, -s
            rot[2 * i + 1][2 * i], rot[2 * i + 1][2 * i + 1] = s, c
        for a_matrix, target in ((k, k_global), (m, m_global)):
            ar = [[sum(a_matrix[p][q] * rot[q][col] for q in range(8)) for col in range(8)] for p in range(8)]
            polar_matrix = [[sum(rot[q][p] * ar[q][col] for q in range(8)) for col in range(8)] for p in range(8)]
            for p in range(8):
                for q in range(8):
                    if dofs[p] is None or dofs[q] is None or dofs[p] < dofs[q]:
                        continue
                    target[(dofs[p], dofs[q])] = target.get((dofs[p], dofs[q]), 0.0) + polar_matrix[p][q]

    def write_mtx(path, entries):
        with open(path, "w") as f:
            f.write("%%MatrixMarket matrix coordinate real symmetric\n")
            f.write("%% one sector of a plane-stress bladed disk (make_sector.py); DOFs 2 p + 1, 2 p + 2 = u_r, u_t of node p\n")
            kept = sorted((key, v) for key, v in entries.items() if v != 0.0)
            f.write("%d %d %d\n" % (n, n, len(kept)))
            for (i, j), v in kept:
                f.write("%d %d %.17g\n" % (i + 1, j + 1, v))

    os.makedirs(args.out, exist_ok=True)
    write_mtx(os.path.join(args.out, "sector_mass.mtx"), m_global)
    write_mtx(os.path.join(args.out, "sector_stiffness.mtx"), k_global)

    def ut(name):  # 1-based circumferential DOF of a node
        return 2 * index[name] + 2

    left = [2 * index[("disk", i, 0)] + 1 + c for i in range(1, NR + 1) for c in (0, 1)]
    right = [2 * index[("disk", i, NT)] + 1 + c for i in range(1, NR + 1) for c in (0, 1)]
    tip = 2 * index[("blade", NB, 1)] + 2
    excitation = ["0"] * n
    excitation[tip - 1] = repr(FORCE)
    with open(os.path.join(args.out, "sector.toml"), "w") as f:
        f.write("""# One sector of a plane-stress bladed disk of %d sectors (written by make_sector.py: see there):
# a disk ring clamped at r = %g m, a blade to r = %g m with a platform lip on each side, %d nodes,
# %d DOFs (u_r, u_t of each node in its own polar frame). SI units: m, N, kg, w in rad/s.
# An under-platform damper (Jenkins) joins this blade's right lip tip to the next blade's left
# lip tip; a tip force of %g N, circumferential, travels with engine order %d. Reduced inside hbf
# (Craig-Bampton: the damper's DOFs, the loaded DOF and the cut faces kept).
[structure]
mass = "sector_mass.mtx"
stiffness = "sector_stiffness.mtx"
excitation = [%s]

[cyclic]
sectors = %d
engine_order = %d
left = %s     # the disk's nodes on theta = 0 (u_r, u_t)
right = %s    # the same nodes of the next sector (theta = %g deg)

[[contact]]                   # the under-platform damper
law = "jenkins"
dof = %d                      # u_t of the right lip's tip
neighbour_dof = %d            # u_t of the next sector's left lip tip
stiffness = %g            # k_t [N/m]
friction_limit = %g           # mu N [N]

[reduction]
method = "craig-bampton"
modes = %d
rayleigh = [0.0, %g]

[frequency]   # rad/s: around the blade's first bending mode in nodal diameter %d
wmin = 5800.0
wmax = 6900.0

[solver]
harmonics = 5

[output]
report = [%d, %d]      # u_t of the blade tip (the force) and of the right lip's tip
""" % (SECTORS, R_IN, R_TIP, len(nodes), n, FORCE, ENGINE_ORDER, ", ".join(excitation), SECTORS, ENGINE_ORDER,
            left, right, math.degrees(alpha), ut(("lip", "right", LIP_LEVEL)), ut(("lip", "left", LIP_LEVEL)),
            K_DAMPER, args.slip_force, args.modes, BETA, ENGINE_ORDER, tip, ut(("lip", "right", LIP_LEVEL))))


if __name__ == "__main__":
    main()
