#!/usr/bin/python3
"""Is a refined beam's deviation the model's data or the solver? (issue 30, mesh convergence)

The generator examples/systems/beam/make_beam.py writes the damping matrix entry by entry,
C_ij = a M_ij + b K_ij rounded to double. On a fine mesh the stiffness-proportional part cancels
strongly on the low modes (b K phi is ~1e-13 of its terms at 5000 elements), so the rounding of
each entry, 1e-16 relative, is not small against the damping force it should produce.

This script solves the linear (no contact: the free beam) response Z x = f,
Z = K - w^2 M + i w C, for the meshes given, independently of hbf: SciPy's sparse LU in double
as the preconditioner of an iterative refinement whose residual is formed in long double (80-bit)
from the files' exact double entries. It does so twice:
  * with C as written in the damping file (the model the files describe);
  * with C applied as a (M x) + b (K x) in long double (the model the generator meant),
and prints the mid-span and tip complex amplitudes under the 10 N mid-span force, with the
mid-span deviation from the first (coarsest) mesh's.
If the second agrees across meshes while the first does not, the difference is in the data.

Usage (Debian's python3 with python3-numpy and python3-scipy, which scripts/install-deps.sh
installs):
  /usr/bin/python3 benchmarks/beam_damping_rounding.py [--elements 100 1000 5000] [--w 40]
Writes the generated meshes into a temporary directory (the 5000-element files take 3 MB).
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import scipy.io
import scipy.sparse.linalg as sla

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BEAM = os.path.join(ROOT, "examples", "systems", "beam")
LD = np.longdouble


def rayleigh_coefficients():
    sys.dont_write_bytecode = True  # no __pycache__ beside the shipped example
    sys.path.insert(0, BEAM)
    import make_beam as mb  # the generator's constants and its rule for a and b
    c0 = math.sqrt(mb.E * mb.INERTIA / (mb.RHO * mb.AREA * mb.LENGTH ** 4))
    w1, w2 = 1.8751 ** 2 * c0, 4.6941 ** 2 * c0
    b = 2.0 * mb.ZETA / (w1 + w2)
    return b * w1 * w2, b


def load(directory, n):
    read = lambda kind: scipy.io.mmread(os.path.join(directory, "beam%d_%s.mtx" % (n, kind))).tocoo()
    text = open(os.path.join(directory, "beam%d.toml" % n)).read()
    force = np.array([float(v) for v in re.search(r"excitation = \[([^\]]*)\]", text).group(1).split(",")])
    return read("mass"), read("stiffness"), read("damping"), force


def product(matrix, xr, xi):
    """matrix (real, COO) times x = xr + i xi, summed in long double."""
    yr = np.zeros(matrix.shape[0], LD)
    yi = np.zeros(matrix.shape[0], LD)
    entries = matrix.data.astype(LD)
    np.add.at(yr, matrix.row, entries * xr[matrix.col])
    np.add.at(yi, matrix.row, entries * xi[matrix.col])
    return yr, yi


def solve(m, k, c, force, w, rayleigh, sweeps=12):
    """Z x = f by LU in double refined with long-double residuals; C = rayleigh (a, b) or the matrix c."""
    lu = sla.splu((k.tocsc() - w * w * m.tocsc() + 1j * w * c.tocsc()).tocsc())
    n = force.size
    xr, xi = np.zeros(n, LD), np.zeros(n, LD)
    W = LD(w)
    for _ in range(sweeps):
        kr, ki = product(k, xr, xi)
        mr, mi = product(m, xr, xi)
        if rayleigh is None:
            cr, ci = product(c, xr, xi)
        else:
            cr, ci = LD(rayleigh[0]) * mr + LD(rayleigh[1]) * kr, LD(rayleigh[0]) * mi + LD(rayleigh[1]) * ki
        rr = force.astype(LD) - (kr - W * W * mr - W * ci)
        ri = -(ki - W * W * mi + W * cr)
        step = lu.solve(rr.astype(float) + 1j * ri.astype(float))
        xr += step.real.astype(LD)
        xi += step.imag.astype(LD)
    return lambda i: complex(float(xr[i]), float(xi[i]))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--elements", type=int, nargs="+", default=[100, 1000, 5000])
    parser.add_argument("--w", type=float, default=40.0, help="excitation frequency [rad/s] (default 40)")
    args = parser.parse_args()
    if any(e < 2 or e % 2 for e in args.elements):
        parser.error("--elements: even numbers of at least 2 (mid-span must be a node)")
    if not args.w > 0:
        parser.error("--w must be positive")
    a, b = rayleigh_coefficients()
    print("free beam, w = %g rad/s, Rayleigh a = %.6g 1/s, b = %.6g s" % (args.w, a, b))
    print("complex amplitudes [m] of the transverse displacements under the beam's 10 N mid-span force;")
    print("dev = |x_mid - x_mid(first mesh)| / |x_mid(first mesh)|, dev_im the same for Im x_mid")
    print("%8s  %-20s %-36s %-36s %-8s %s" % ("elements", "damping", "x_mid", "x_tip", "dev", "dev_im"))
    first = {}
    with tempfile.TemporaryDirectory() as work:
        for elements in args.elements:
            subprocess.run([sys.executable, os.path.join(BEAM, "make_beam.py"), "--elements", str(elements),
                            "--out", work], check=True, stdout=subprocess.DEVNULL)
            n = 2 * elements
            m, k, c, force = load(work, n)
            mid, tip = n // 2 - 2, n - 2  # 0-based transverse DOFs of the mid-span node and the tip
            for label, rayleigh in (("C as written", None), ("aM+bK, long double", (a, b))):
                x = solve(m, k, c, force, args.w, rayleigh)
                first.setdefault(label, x(mid))
                ref = first[label]
                print("%8d  %-20s %-36s %-36s %.2e %.2e" % (
                    elements, label, "%.9e%+.9ej" % (x(mid).real, x(mid).imag),
                    "%.9e%+.9ej" % (x(tip).real, x(tip).imag), abs(x(mid) - ref) / abs(ref),
                    abs(x(mid).imag - ref.imag) / abs(ref.imag)))


if __name__ == "__main__":
    main()
