#!/usr/bin/python3
"""Harmonic balance's error on the mitred bar end (examples/systems/mitre), per frequency and H,
against the exact periodic orbit solved from harmonic balance's own state.

For each w and H, `hbf frf` is run twice as a single point (--wmin w --wmax w):
  * --exact off: harmonic balance's y365 maximum and first harmonic;
  * --exact on: the exact orbit solved from that solution's state (the polish), its metrics.
The orbits of this interface form families (a node stuck all period can be held anywhere inside
its cone), and each history lands on its own member; so harmonic balance is measured against the
member its own state leads to, not against an orbit from another history.

H >= 7 start from H = 5 (--start-harmonics 5; a cold start at H >= 7 stalls at some w), H >= 10
ask for the structured Jacobian (H = 5 and 7 take the automatic one: structured too on this
model, whose unknowns exceed 1500 from H = 5 on; the dense form gives the same solutions, up to
hundreds of times slower). Each run is bounded (--time-limit). Prints one row per (w, H), the
errors relative to the exact orbit, and a JSON line at the end.

Usage: /usr/bin/python3 benchmarks/mitre_hb_error.py --hbf build/hbf
       [--w 16000 17500 ...] [--harmonics 3 5 7 10 20] [--force-scale 1] [--time-limit 900]
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "examples", "systems", "mitre", "mitre.toml")


def run_point(hbf, w, h, exact, force_scale, time_limit, folder):
    """One `hbf frf` at w: (exit code, the CSV's first row or None, seconds)."""
    out = os.path.join(folder, "w%g_h%d_%s.csv" % (w, h, "exact" if exact else "hb"))
    cmd = [hbf, "frf", "--config", CONFIG, "--wmin", repr(w), "--wmax", repr(w), "--harmonics", str(h),
           "--exact", "on" if exact else "off", "--force-scale", repr(force_scale), "--time-limit",
           repr(time_limit), "--out", out]
    if h >= 7:
        cmd += ["--start-harmonics", "5"]
    if h >= 10:
        cmd += ["--jacobian", "structured"]
    start = time.monotonic()
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    row = None
    if os.path.exists(out):
        with open(out) as f:
            rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
        # the point at w itself (an FRF of one frequency may carry located transitions too)
        at = [r for r in rows if abs(float(r["w"]) - w) <= 1e-9 * w]
        row = at[0] if at else None
    return done.returncode, row, seconds, done.stderr.strip().splitlines()[-1:] if done.stderr else []


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--hbf", default=os.path.join(HERE, "..", "build", "hbf"))
    parser.add_argument("--w", type=float, nargs="+",
                        default=[16000.0, 17500.0, 18500.0, 19500.0, 20200.0, 20700.0, 21200.0])
    parser.add_argument("--harmonics", type=int, nargs="+", default=[3, 5, 7, 10, 20])
    parser.add_argument("--force-scale", type=float, default=1.0)
    parser.add_argument("--time-limit", type=float, default=900.0)
    parser.add_argument("--output", default="y365", help="the reported output compared")
    args = parser.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as folder:
        print("| w | H | HB %s max against its exact orbit | HB %s first harmonic against it | the exact orbit's max, "
              "first harmonic | exact row | seconds (HB, HB + polish) |" % (args.output, args.output))
        print("|---|---|---|---|---|---|---|")
        for w in args.w:
            for h in args.harmonics:
                code_hb, hb, t_hb, err_hb = run_point(args.hbf, w, h, False, args.force_scale, args.time_limit, folder)
                code_ex, ex, t_ex, err_ex = run_point(args.hbf, w, h, True, args.force_scale, args.time_limit, folder)
                entry = {"w": w, "H": h, "exit_hb": code_hb, "exit_exact": code_ex, "seconds": [t_hb, t_ex]}
                if hb is None or ex is None or ex.get("exact") != "yes":
                    why = (err_hb or err_ex or ["no row"])[-1]
                    print("| %g | %d | no comparison (exit %d / %d, exact = %s): %s | | | | %.0f, %.0f |"
                          % (w, h, code_hb, code_ex, ex.get("exact") if ex else "-", why, t_hb, t_ex))
                    entry["failed"] = why
                else:
                    m_hb, a_hb = float(hb[args.output + "_max"]), float(hb[args.output + "_amp1"])
                    m_ex, a_ex = float(ex[args.output + "_max"]), float(ex[args.output + "_amp1"])
                    entry.update({"hb_max": m_hb, "hb_amp1": a_hb, "exact_max": m_ex, "exact_amp1": a_ex,
                                  "max_error": (m_hb - m_ex) / m_ex, "amp1_error": (a_hb - a_ex) / a_ex})
                    print("| %g | %d | %+.1e | %+.1e | %.6e, %.6e | %s | %.0f, %.0f |"
                          % (w, h, entry["max_error"], entry["amp1_error"], m_ex, a_ex, ex["exact"], t_hb, t_ex))
                results.append(entry)
                print(end="", flush=True)
    print(json.dumps(results))


if __name__ == "__main__":
    main()
