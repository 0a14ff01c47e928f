#!/usr/bin/python3
"""The 3D block example against time integration, and its convergence in H (issue 32, item 4).

examples/systems/block/block.toml (written by make_block.py: a bar of 10 x 4 x 4 bricks, its
25-node end face pressed against a wall, reduced inside hbf by Craig-Bampton) is solved at a few
frequencies that have one periodic solution each (outside the fold interval of the FRF), by

  * hbf timeint --config block.toml --w W (CVODE, the elastic contacts' exact events; started
    from the linear stuck state: the reference), and
  * hbf frf --config block.toml at H = 3, 5, 7, 10, 15 from the band's start (stuck, 14000
    rad/s) up to W: the branch in order, over the resonance's fold interval where W lies above
    it, its row at W (a linear guess near the resonance does not converge),

and prints, per frequency, the regime of the face (nodes stuck, stick-slip, partly open) and the
relative differences of y_max of the three reported outputs (mid-length y, the face centre's
y and x) and of y_amp1 of the first two (the centre's x moves at even harmonics only) and the largest difference of a node's separated fraction and stick fraction.

Usage: /usr/bin/python3 benchmarks/block_reference.py [--hbf build/hbf] [--w 15000 17900 18700]
       [--harmonics 3 5 7 10 15]
The default frequencies: every node stuck (15000 rad/s), every node slipping and 20 of 25 partly
open (17900), the centre stuck and the edges lifting off (18700).
Time (measured on 2 cores): time integration 71 s at 15000 rad/s, about 30 min at 17900 (1321
periods, the events of 25 nodes), 251 s at 18700, 1894 s at 17600; its rows are kept in --cache
(a CSV per frequency) and reused. Harmonic balance: the band up to W, about 5 minutes at H = 3,
10 at H = 7.
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = os.path.join(ROOT, "examples", "systems", "block", "block.toml")
OUTPUTS = ["y338", "y713", "y712"]
NODES = 25


def run(command):
    started = time.monotonic()
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode not in (0, 3):
        sys.exit("%s failed (%d): %s" % (" ".join(command), done.returncode, done.stderr.strip()))
    return list(csv.DictReader(io.StringIO(done.stdout))), time.monotonic() - started


def states(row):
    stick = [float(row["stick_fraction_c%d" % i]) for i in range(1, NODES + 1)]
    sep = [float(row["separated_fraction_c%d" % i]) for i in range(1, NODES + 1)]
    stuck = sum(s == 1.0 for s in stick)
    opened = sum(s > 0.0 for s in sep)
    return stick, sep, "%d stuck, %d stick-slip/slip, %d partly open" % (stuck, NODES - stuck - opened, opened)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--hbf", default=os.path.join(ROOT, "build", "hbf"))
    parser.add_argument("--w", type=float, nargs="+", default=[15000.0, 17900.0, 18700.0])
    parser.add_argument("--harmonics", type=int, nargs="+", default=[3, 5, 7, 10, 15])
    parser.add_argument("--cache", default=os.path.join(tempfile.gettempdir(), "hbf-block-reference"),
                        help="directory of the time-integration rows (ti-W.csv), reused when present")
    args = parser.parse_args()
    os.makedirs(args.cache, exist_ok=True)
    for w in args.w:
        cached = os.path.join(args.cache, "ti-%g.csv" % w)
        if os.path.exists(cached):
            ti, seconds = list(csv.DictReader(open(cached))), float("nan")
        else:
            ti, seconds = run([args.hbf, "timeint", "--config", BLOCK, "--w", repr(w), "--quiet"])
            with open(cached, "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(ti[0].keys()))
                writer.writeheader()
                writer.writerows(ti)
        t = ti[0]
        if t["converged"] != "true":
            print("w = %g: time integration did not converge" % w)
            continue
        t_stick, t_sep, face = states(t)
        print("w = %g rad/s: time integration %.0f s, %d periods; the face: %s" % (w, seconds, int(t["periods"]), face))
        print("   H   y_max diff (%s)   y_amp1 diff (%s)   max |d sep|  max |d stick|  HB s"
              % (", ".join(OUTPUTS), ", ".join(OUTPUTS[:2])))
        for h in args.harmonics:
            rows, seconds = run([args.hbf, "frf", "--config", BLOCK, "--harmonics", str(h), "--wmax", repr(w),
                                 "--quiet"])
            at = [x for x in rows if abs(float(x["w"]) - w) < 1e-9 * w]
            if not at:
                print("  %2d   the branch did not reach w = %g" % (h, w))
                continue
            r = at[-1]
            h_stick, h_sep, _ = states(r)
            dmax = [abs(float(r[o + "_max"]) / float(t[o + "_max"]) - 1.0) for o in OUTPUTS]
            damp = [abs(float(r[o + "_amp1"]) / float(t[o + "_amp1"]) - 1.0) for o in OUTPUTS[:2]]
            dsep = max(abs(a - b) for a, b in zip(h_sep, t_sep))
            dstick = max(abs(a - b) for a, b in zip(h_stick, t_stick))
            print("  %2d   %s   %s   %.2e     %.2e      %.1f" % (
                h, " ".join("%.1e" % d for d in dmax), " ".join("%.1e" % d for d in damp), dsep, dstick, seconds))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
