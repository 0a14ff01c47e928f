#!/usr/bin/env python3
"""A finite-element bar from SciPy sparse matrices
===============================================

A finite-element model from SciPy sparse matrices: an axial bar with a friction contact.

The bar (length 1, EA = 1, mass per length 1) is clamped at x = 0 and split into N linear
elements (consistent mass); Rayleigh damping C = a M + b K. A Dahl contact holds the node at
x = 1/2 against the ground, and the tip carries the force F cos(w t). The FRF over the first
axial mode (w1 = pi / 2 without the contact) is computed by hbfriction's condensed harmonic
balance, whose unknowns are the contact's relative displacement only: the cost does not grow
with N beyond the sparse factorisations.

Usage: fe_sparse.py [N] [PLOT.png]   (defaults: 400 elements, no plot)
"""
import sys

import numpy as np
import scipy.sparse as sp

import hbfriction


def bar(n):
    """Mass and stiffness of a clamped bar of n linear elements (the clamped node removed)."""
    h = 1.0 / n
    ke = np.array([[1.0, -1.0], [-1.0, 1.0]]) / h
    me = np.array([[2.0, 1.0], [1.0, 2.0]]) * h / 6.0
    rows, cols, kv, mv = [], [], [], []
    for e in range(n):
        for a in range(2):
            for b in range(2):
                i, j = e + a - 1, e + b - 1  # DOF i is node i + 1 (node 0 is clamped)
                if i >= 0 and j >= 0:
                    rows.append(i)
                    cols.append(j)
                    kv.append(ke[a, b])
                    mv.append(me[a, b])
    k = sp.csr_matrix((kv, (rows, cols)), shape=(n, n))
    m = sp.csr_matrix((mv, (rows, cols)), shape=(n, n))
    return m, k


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 400
    m, k = bar(n)
    c = 0.05 * m + 0.001 * k
    f = np.zeros(n)
    f[-1] = 0.1
    middle = n // 2 - 1  # node n/2, at x = 1/2
    contact = hbfriction.Contact(dof=middle, law="dahl", friction_limit=0.1, stiffness=5.0)
    system = hbfriction.System(m, k, f, damping=c, contacts=[contact])
    tip = np.zeros(n)
    tip[-1] = 1.0
    branch = hbfriction.frf(system, outputs=[("tip", tip), ("contact", np.eye(1, n, middle).ravel())],
                            wmin=0.8, wmax=2.6)
    peak = branch.peak
    print("%d DOFs: %d points in %.3f s, status %s; largest tip peak %.6g at w = %.6g"
          % (n, len(branch), branch.seconds, branch.status, peak["value"], peak["w"]))
    print("stick-slip regimes along the branch:", sorted(set(branch.regime)))
    if len(sys.argv) > 2:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(branch.w, branch.tip_max, label="tip")
        ax.plot(branch.w, branch.contact_max, label="contact node")
        ax.set_xlabel("w (rad per time unit)")
        ax.set_ylabel("max over one period of |u(t)|")
        ax.set_title("Bar with a Dahl contact, %d elements" % n)
        ax.legend()
        fig.tight_layout()
        hbfriction.check_output(sys.argv[2])
        fig.savefig(sys.argv[2])
        print("wrote", sys.argv[2])


if __name__ == "__main__":
    main()
