#!/usr/bin/env python3
"""The friction absorber under three friction laws
===============================================

The paper's friction absorber under its three friction laws: exact Coulomb (event-exact
polish), Dahl and LuGre, at the same friction coefficient, plotted with matplotlib.

Usage: three_laws.py [PLOT.png] [MU]   (defaults: three_laws.png in the current directory, 0.2)
Prints each law's largest peak of y1 (``y1_max``, the largest ``|y1(t)|`` over one period;
nondimensional x1 / x_s).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import hbfriction  # noqa: E402


def main():
    plot = sys.argv[1] if len(sys.argv) > 1 else "three_laws.png"
    mu = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
    hbfriction.check_output(plot)  # before the work: never a computation lost to a bad path
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for law in ("coulomb", "dahl", "lugre"):
        branch = hbfriction.frf(hbfriction.absorber(law, mu=mu))
        peak = branch.peak
        print("%-8s %3d points, %-9s largest peak y1_max = %.9g at w = %.9g (%.3f s)"
              % (law, len(branch), branch.status, peak["value"], peak["w"], branch.seconds))
        ax.plot(branch.w, branch.y1_max, label="%s (%s)" % (law, "exact" if branch.exact[0] == "yes" else
                                                            "H = %d" % branch.settings.harmonic_balance.harmonics))
    ax.set_yscale("log")
    ax.set_xlabel("w = Omega / omega1")
    ax.set_ylabel("y1_max = max over one period of |y1(t)|")
    ax.set_title("Friction absorber (r = 0.1, wa = 1, fe = 0.5, mu = %g)" % mu)
    ax.legend()
    fig.tight_layout()
    fig.savefig(plot)
    print("wrote", plot)


if __name__ == "__main__":
    main()
