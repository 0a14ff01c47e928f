#!/usr/bin/env python3
"""Writes a 3D finite-element bar of brick elements whose free end is pressed against a rigid
wall over a meshed contact patch, for hbf frf --config.

A steel bar (0.2 m long, 20 mm wide, 20 mm high (--height), SI units) of NX x NY x NZ trilinear 8-node
brick elements (2 x 2 x 2 Gauss points, consistent mass), clamped at x = 0. Its end face x = L
is pressed against a rigid wall by a preload pressure: each of its (NY + 1) (NZ + 1) nodes is a
contact node (law elastic: penalty stiffnesses per unit area, Coulomb friction, lift-off),
closing along +x, its frame t1 = y, t2 = z. A transverse force F cos(omega t) along y acts at
the centre node of the mid-length section: the bar bends, its end face slides along y and
turns, so that one side of the face is pressed harder and the other unloaded: the contact goes
from full stick (small forces) through stick-slip to partial lift-off as the response grows
near the first bending resonance.

The system file reduces the model onto the contact nodes inside hbf ([reduction]:
Craig-Bampton, 20 fixed-interface modes, 1 % modal damping of the reduced model's modes), and
harmonic balance solves the reduced model through all its modes ([solver] modes: exact).

Writes, beside this script (or in --out DIR): block_mass.mtx, block_stiffness.mtx (Matrix
Market, symmetric, coordinate), block_nodes.mtx (the contact nodes' DOF triples, 1-based, an
n x 3 array), block_areas.mtx (their areas, n x 1) and block.toml.
DOFs: node (i, j, k) (i = 1..NX along x, j = 0..NY along y, k = 0..NZ along z; the nodes at
i = 0 are clamped) has DOFs 3 p + 1, 3 p + 2, 3 p + 3 (x, y, z; 1-based), p = ((i - 1) (NY + 1)
+ j) (NZ + 1) + k.
Only the Python standard library is used.

Options for other interfaces: --mitre DEG cuts the end face at DEG degrees to the section (the
plane x = L + tan(DEG) (y - W / 2); the end elements are then general trilinear bricks, the
contact frame turns with the face and the nodes' areas are the inclined face's), --law
unilateral makes the nodes rigid contacts (no stiffnesses), --reduction massless-boundary
keeps them massless (the exact solver of law unilateral needs that), --modes, --mu, --wmin,
--wmax set the reduction's fixed-interface modes, the friction coefficient and the band, and
--name the files' base name. examples/systems/mitre is
  make_block.py --nx 10 --ny 8 --nz 2 --mitre 30 --law unilateral --reduction massless-boundary
                --modes 10 --mu 0.36 --wmin 8000 --wmax 26000 --name mitre --out ../mitre
a bar whose mitred end presses 27 nodes against the wall, rigid contacts, reduced to 92
coordinates.

Usage: make_block.py [--nx 10] [--ny 4] [--nz 4] [--mitre 0] [--law elastic] [--reduction craig-bampton]
                     [--modes 20] [--mu 0.3] [--wmin 14000] [--wmax 20000] [--name block] [--out DIR]
"""
import argparse
import math
import os

E = 210e9           # Young's modulus [Pa]
NU = 0.3            # Poisson's ratio
RHO = 7850.0        # density [kg/m^3]
LENGTH, WIDTH, HEIGHT = 0.2, 0.02, 0.02  # along x, y, z [m]
PRESSURE = 2.0e6    # preload pressure on the end face [Pa] (800 N over 4 cm^2)
K_NORMAL = 5.0e13   # normal contact stiffness per unit area [N/m^3]
K_TANGENT = 2.0e13  # tangential contact stiffness per unit area [N/m^3]
MU = 0.3            # friction coefficient
FORCE = 10.0        # transverse force amplitude at mid-length [N]
MODES = 20          # fixed-interface modes kept by the reduction
ZETA = 0.01         # modal damping ratio of the reduced model
W_MIN, W_MAX = 14000.0, 20000.0  # the frequency band [rad/s] around the first bending resonance
HARMONICS = 3       # harmonic balance (README: the convergence in H against time integration)


def gauss_points():
    g = 1.0 / math.sqrt(3.0)
    return [(a, b, c) for a in (-g, g) for b in (-g, g) for c in (-g, g)]


CORNERS = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
           (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]


def add_gauss_point(k, m, n, dn, weight):
    """Adds one Gauss point's share to the element's k and m: shape functions n and their
    x, y, z derivatives dn at the point, weight = the Jacobian determinant there."""
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    g = E / (2 * (1 + NU))
    d = [[lam + 2 * g, lam, lam, 0, 0, 0],
         [lam, lam + 2 * g, lam, 0, 0, 0],
         [lam, lam, lam + 2 * g, 0, 0, 0],
         [0, 0, 0, g, 0, 0],
         [0, 0, 0, 0, g, 0],
         [0, 0, 0, 0, 0, g]]
    bm = [[0.0] * 24 for _ in range(6)]  # strains xx, yy, zz, yz, xz, xy
    for p, (dx, dy, dz) in enumerate(dn):
        bm[0][3 * p] = dx
        bm[1][3 * p + 1] = dy
        bm[2][3 * p + 2] = dz
        bm[3][3 * p + 1], bm[3][3 * p + 2] = dz, dy
        bm[4][3 * p], bm[4][3 * p + 2] = dz, dx
        bm[5][3 * p], bm[5][3 * p + 1] = dy, dx
    db = [[sum(d[r][s] * bm[s][c] for s in range(6)) for c in range(24)] for r in range(6)]
    for a in range(24):
        for b in range(24):
            k[a][b] += weight * sum(bm[r][a] * db[r][b] for r in range(6))
    for p in range(8):
        for q in range(8):
            v = RHO * weight * n[p] * n[q]
            for c in range(3):
                m[3 * p + c][3 * q + c] += v


def element_matrices(corners):
    """24 x 24 stiffness and consistent mass of a trilinear brick with the given 8 corner
    coordinates (in the order of CORNERS; DOFs corner by corner, x y z each), by 2 x 2 x 2 Gauss
    quadrature: the standard isoparametric 8-node element (a rectangular brick, or the
    trapezoidal bricks of a mitred end)."""
    k = [[0.0] * 24 for _ in range(24)]
    m = [[0.0] * 24 for _ in range(24)]
    for (xi, eta, zeta) in gauss_points():
        n = [(1 + a * xi) * (1 + b * eta) * (1 + c * zeta) / 8 for (a, b, c) in CORNERS]
        dref = [(a * (1 + b * eta) * (1 + c * zeta) / 8,
                 b * (1 + a * xi) * (1 + c * zeta) / 8,
                 c * (1 + a * xi) * (1 + b * eta) / 8) for (a, b, c) in CORNERS]
        # J[r][c] = d x_c / d xi_r
        jm = [[sum(dref[p][r] * corners[p][c] for p in range(8)) for c in range(3)] for r in range(3)]
        det = (jm[0][0] * (jm[1][1] * jm[2][2] - jm[1][2] * jm[2][1])
               - jm[0][1] * (jm[1][0] * jm[2][2] - jm[1][2] * jm[2][0])
               + jm[0][2] * (jm[1][0] * jm[2][1] - jm[1][1] * jm[2][0]))
        inv = [[(jm[(c + 1) % 3][(r + 1) % 3] * jm[(c + 2) % 3][(r + 2) % 3]
                 - jm[(c + 1) % 3][(r + 2) % 3] * jm[(c + 2) % 3][(r + 1) % 3]) / det for c in range(3)]
               for r in range(3)]  # inv[r][c] = d xi_c / d x_r
        dn = [tuple(sum(inv[r][c] * dref[p][c] for c in range(3)) for r in range(3)) for p in range(8)]
        add_gauss_point(k, m, n, dn, det)
    return k, m


def box_matrices(hx, hy, hz):
    """element_matrices of a rectangular brick hx x hy x hz, in closed form per Gauss point (the
    square end's files, written before the mitre existed, stay byte for byte what they were)."""
    jac = hx * hy * hz / 8.0
    k = [[0.0] * 24 for _ in range(24)]
    m = [[0.0] * 24 for _ in range(24)]
    for (xi, eta, zeta) in gauss_points():
        n = [(1 + a * xi) * (1 + b * eta) * (1 + c * zeta) / 8 for (a, b, c) in CORNERS]
        dn = [(a * (1 + b * eta) * (1 + c * zeta) / 8 * 2 / hx,
               b * (1 + a * xi) * (1 + c * zeta) / 8 * 2 / hy,
               c * (1 + a * xi) * (1 + b * eta) / 8 * 2 / hz) for (a, b, c) in CORNERS]
        add_gauss_point(k, m, n, dn, jac)
    return k, m


def write_mtx(path, n, entries, comment):
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write("% " + comment + "\n")
        items = sorted((j, i, v) for (i, j), v in entries.items() if v != 0.0)
        f.write("%d %d %d\n" % (n, n, len(items)))
        for j, i, v in items:
            f.write("%d %d %.17g\n" % (i + 1, j + 1, v))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--nx", type=int, default=10)
    parser.add_argument("--ny", type=int, default=4)
    parser.add_argument("--nz", type=int, default=4)
    parser.add_argument("--height", type=float, default=HEIGHT,
                        help="the section's height along z [m] (default 0.02: square, its two bending modes equal)")
    parser.add_argument("--mitre", type=float, default=0.0,
                        help="angle of the end face to the section, degrees (0: square end; in (-60, 60))")
    parser.add_argument("--law", choices=["elastic", "unilateral"], default="elastic")
    parser.add_argument("--reduction", choices=["craig-bampton", "massless-boundary"], default="craig-bampton")
    parser.add_argument("--modes", type=int, default=MODES, help="fixed-interface modes kept (>= 0)")
    parser.add_argument("--mu", type=float, default=MU, help="friction coefficient (>= 0)")
    parser.add_argument("--wmin", type=float, default=W_MIN)
    parser.add_argument("--wmax", type=float, default=W_MAX)
    parser.add_argument("--name", default="block", help="base name of the files written")
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    args = parser.parse_args()
    nx, ny, nz = args.nx, args.ny, args.nz
    if min(nx, ny, nz) < 1 or ny % 2 or nz % 2:
        parser.error("--nx, --ny, --nz must be >= 1, and --ny, --nz even (a centre node for the force)")
    if not -60.0 < args.mitre < 60.0:
        parser.error("--mitre must be in (-60, 60) degrees")
    if args.modes < 0 or args.mu < 0 or not 0 < args.wmin < args.wmax or not args.height > 0:
        parser.error("--modes and --mu must be >= 0, --height > 0, and 0 < --wmin < --wmax")
    hx, hy, hz = LENGTH / nx, WIDTH / ny, args.height / nz
    slope = math.tan(math.radians(args.mitre))

    def position(i, j, k):  # the end face is the plane x = L + slope (y - W / 2)
        y = j * hy
        return (i / nx * (LENGTH + slope * (y - WIDTH / 2)), y, k * hz)

    def node(i, j, k):  # 0-based node number of a free node (i >= 1)
        return ((i - 1) * (ny + 1) + j) * (nz + 1) + k

    n = 3 * nx * (ny + 1) * (nz + 1)
    k_entries, m_entries = {}, {}
    cache = {}
    for ei in range(nx):
        for ej in range(ny):
            for ek in range(nz):
                corners = [position(ei + (a + 1) // 2, ej + (b + 1) // 2, ek + (c + 1) // 2) for (a, b, c) in CORNERS]
                key = tuple(round(v - w, 15) for corner in corners for v, w in zip(corner, corners[0]))
                if key not in cache:
                    cache[key] = element_matrices(corners) if slope else box_matrices(hx, hy, hz)
                ke, me = cache[key]
                dofs = []
                for (a, b, c) in CORNERS:
                    i, j, k = ei + (a + 1) // 2, ej + (b + 1) // 2, ek + (c + 1) // 2
                    p = node(i, j, k) if i >= 1 else None
                    dofs += [None] * 3 if p is None else [3 * p, 3 * p + 1, 3 * p + 2]
                for a in range(24):
                    for b in range(24):
                        r, s = dofs[a], dofs[b]
                        if r is None or s is None or r < s:
                            continue
                        k_entries[(r, s)] = k_entries.get((r, s), 0.0) + ke[a][b]
                        m_entries[(r, s)] = m_entries.get((r, s), 0.0) + me[a][b]
    out, name = args.out, args.name
    os.makedirs(out, exist_ok=True)
    shape = "brick bar %d x %d x %d elements%s" % (nx, ny, nz, ", end mitred %g deg" % args.mitre if args.mitre else "")
    write_mtx(os.path.join(out, name + "_stiffness.mtx"), n, k_entries, shape + ", K [N/m] (make_block.py)")
    write_mtx(os.path.join(out, name + "_mass.mtx"), n, m_entries, shape + ", consistent M [kg] (make_block.py)")
    # The end face's nodes: DOF triples and tributary areas (corners 1/4, edges 1/2 of the
    # face's element area hy hz / cos(mitre)).
    face = hy * hz * math.sqrt(1.0 + slope * slope)
    with open(os.path.join(out, name + "_nodes.mtx"), "w") as f_nodes, \
            open(os.path.join(out, name + "_areas.mtx"), "w") as f_areas:
        count = (ny + 1) * (nz + 1)
        f_nodes.write("%%MatrixMarket matrix array integer general\n")
        f_nodes.write("% the end face's contact nodes: FE DOFs (x, y, z) of each, 1-based (make_block.py)\n")
        f_nodes.write("%d 3\n" % count)
        f_areas.write("%%MatrixMarket matrix array real general\n")
        f_areas.write("% the contact nodes' tributary areas [m^2] (make_block.py)\n")
        f_areas.write("%d 1\n" % count)
        columns = [[], [], []]
        for j in range(ny + 1):
            for k in range(nz + 1):
                p = node(nx, j, k)
                for c in range(3):
                    columns[c].append(3 * p + c + 1)
                wy = 0.5 if j in (0, ny) else 1.0
                wz = 0.5 if k in (0, nz) else 1.0
                f_areas.write("%.17g\n" % (wy * wz * face))
        for c in range(3):  # array format: column by column
            for v in columns[c]:
                f_nodes.write("%d\n" % v)
    centre = node(nx, ny // 2, nz // 2)
    middle = node(max(1, nx // 2), ny // 2, nz // 2)
    excitation = ["0"] * n
    excitation[3 * middle + 1] = repr(FORCE)
    norm = math.sqrt(1.0 + slope * slope)
    normal = "[%r, %r, 0.0]" % (1.0 / norm, 0.0 - slope / norm)
    tangent = "[%r, %r, 0.0]" % (0.0 + slope / norm, 1.0 / norm)
    if args.mitre:
        normal_text, tangent_text = "closing into the wall", "t1 in the face, across the bar; t2 = n x t1 = z"
    else:
        normal_text, tangent_text = "closing along +x (into the wall)", "t1 = y, t2 = n x t1 = z"
    if args.law == "elastic":
        law = """law = "elastic"
friction_coefficient = %g
stiffness = %g          # k_t per unit area [N/m^3]
normal_stiffness = %g   # k_n per unit area [N/m^3]""" % (args.mu, K_TANGENT, K_NORMAL)
        law_text = "law elastic: per-area stiffnesses, Coulomb\n# friction mu = %g, lift-off" % args.mu
    else:
        law = """law = "unilateral"         # rigid contact: no penetration, Coulomb friction
friction_coefficient = %g""" % args.mu
        law_text = "law unilateral: rigid, Coulomb\n# friction mu = %g, lift-off" % args.mu
    if args.reduction == "craig-bampton":
        reduction_text = "Craig-Bampton onto the contact nodes and\n# the loaded DOF"
    else:
        reduction_text = "massless-boundary Craig-Bampton: the contact\n# nodes and the loaded DOF massless"
    if args.reduction == "craig-bampton":
        solver_modes = """# Every mode of the reduced model (3 per contact node, the loaded DOF, the fixed-interface
# modes): the modal receptance without truncation, 4 times faster than the direct solve on
# these dense matrices.
modes = %d""" % (3 * (ny + 1) * (nz + 1) + 1 + args.modes)
    else:
        solver_modes = "# (the retained DOFs are massless: no modal basis; the direct solve per harmonic)"
    end = "its end face" if not args.mitre else "its end face (mitred %g deg to the section)" % args.mitre
    with open(os.path.join(out, name + ".toml"), "w") as f:
        f.write("""# A steel bar of %d x %d x %d brick elements (%d DOFs), clamped at x = 0, %s pressed
# against a rigid wall (written by make_block.py: see there). SI units: m, N, kg, w in rad/s.
# The %d nodes of the end face are contact nodes (%s), preloaded by %g Pa; a transverse force of %g N (y) at the centre
# node of the mid-length section. Reduced inside hbf (%s).
[structure]
mass = "%s_mass.mtx"
stiffness = "%s_stiffness.mtx"
excitation = [%s]

[[interface]]
name = "end face"
nodes = "%s_nodes.mtx"        # each node's FE DOFs (x, y, z)
area = "%s_areas.mtx"         # tributary areas [m^2]
normal = %s         # %s
tangent = %s        # %s
%s
preload_pressure = %g      # [Pa]: each node's N_0 = pressure x area

[reduction]
modes = %d
method = "%s"
damping_ratios = [%g]

[frequency]   # rad/s: stuck at both ends, stick-slip and partial lift-off near the resonance
wmin = %r
wmax = %r

[solver]
harmonics = %d
%s

[output]
report = [%d, %d, %d]      # y at mid-length (the force), the end face centre's y and x
""" % (nx, ny, nz, n, end, (ny + 1) * (nz + 1), law_text, PRESSURE, FORCE, reduction_text, name, name,
            ", ".join(excitation), name, name, normal, normal_text, tangent, tangent_text, law, PRESSURE, args.modes, args.reduction, ZETA,
            args.wmin, args.wmax, HARMONICS, solver_modes, 3 * middle + 2,
            3 * centre + 2, 3 * centre + 1))


if __name__ == "__main__":
    main()
