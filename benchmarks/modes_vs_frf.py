#!/usr/bin/python3
"""Nonlinear modes against the full FRF (issue 33's must-show): does the backbone of the first
mode pass through the FRF peaks of hbf frf, and how far is the single-nonlinear-mode synthesis?

For the paper's absorber (exact Coulomb, tuned: wa = 1) and a detuned one (wa = 0.4, the
released absorber's mode far below the main mass's), at fe = 0.1 ... 1:

  * the FRF (hbfriction.frf: hbf frf's defaults, exact polish and refined peaks) over
    [0.5, 1.5]: its highest y1_amp1 (the main mass's first harmonic) and where;
  * the backbone (hbfriction.modes, a = 1e-3 .. 1e3, synthesis=True): its frequency where its
    own y1_amp1 equals the FRF peak's (linear interpolation between points; the first
    crossing), and the synthesised response's peak (frequency, y1_amp1) for the same force.

Prints one row per case, the differences relative to the FRF peak. An FRF that reaches the
amplitude cap (the friction cannot limit the resonance: fe above the limit the paper derives)
has no peak, and the synthesis is then cut at the backbone's end (its status says so).

Usage: PYTHONPATH=build/python /usr/bin/python3 benchmarks/modes_vs_frf.py [--fe 0.1 0.2 ...]
       [--wa 1 0.4]
About 1 minute on this machine.
"""
import argparse
import warnings

import numpy as np

import hbfriction


def crossings(a, w, level):
    """Frequencies where the curve a(w) (in backbone order) crosses `level`."""
    out = []
    for k in range(len(a) - 1):
        if (a[k] - level) * (a[k + 1] - level) <= 0 and a[k + 1] != a[k]:
            out.append(w[k] + (level - a[k]) * (w[k + 1] - w[k]) / (a[k + 1] - a[k]))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fe", type=float, nargs="+", default=[0.1, 0.2, 0.3, 0.5, 0.7, 1.0])
    parser.add_argument("--wa", type=float, nargs="+", default=[1.0, 0.4])
    args = parser.parse_args()
    warnings.simplefilter("ignore", hbfriction.IncompleteResultWarning)
    print("%-5s %-5s | %-26s | %-20s | %-38s" % ("wa", "fe", "FRF peak: w, y1_amp1", "backbone w there",
                                                   "synthesised peak: w, y1_amp1 (status)"))
    for wa in args.wa:
        for fe in args.fe:
            system = hbfriction.absorber("coulomb", fe=fe, wa=wa)
            frf = hbfriction.frf(system, omega_start=0.5, omega_end=1.5)
            amp, w = np.asarray(frf.y1_amp1), np.asarray(frf.w)
            i = int(np.argmax(amp))
            mode = hbfriction.modes(system, 1e-3, 1e3, synthesis=True)
            syn = mode.synthesis
            k = int(np.argmax(syn.y1_amp1)) if len(syn) else None
            synthesised = ("%.5f, %.4g (%+.2f%%, %+.2f%%) %s" % (syn.w[k], syn.y1_amp1[k], 100 * (syn.w[k] / w[i] - 1),
                                                                 100 * (syn.y1_amp1[k] / amp[i] - 1), mode.status)
                           if k is not None else "none (%s)" % mode.status)
            if frf.status != "completed":
                print("%-5g %-5g | %-26s | %-20s | %s" % (wa, fe, "none (%s: amplitude cap)" % frf.status, "-",
                                                         synthesised))
                continue
            there = crossings(np.asarray(mode.y1_amp1), np.asarray(mode.w), amp[i])
            backbone = "%.5f (%+.2f%%)" % (there[0], 100 * (there[0] / w[i] - 1)) if there else "never reaches it"
            print("%-5g %-5g | %.5f, %-18.5g | %-20s | %s" % (wa, fe, w[i], amp[i], backbone, synthesised))


if __name__ == "__main__":
    main()
