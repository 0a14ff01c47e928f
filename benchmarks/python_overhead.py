#!/usr/bin/env python3
"""The cost of Python against hbf on the default FRF (the paper's absorber, exact Coulomb).

Run by hand (not by the tests), with the package on the path, e.g. from the project root:
    PYTHONPATH=build/python /usr/bin/python3 benchmarks/python_overhead.py [--repeat 15] [--hbf build/hbf]

Measured in one process, interleaved, median of --repeat runs each (a noisy machine drifts):
  core      hbfriction._core.compute_frf: the C++ FRF with its table and JSON summary, no
            conversion (the baseline);
  frf()     hbfriction.frf(absorber()): the whole Python call (settings, NumPy columns, the
            JSON summary parsed into a dict);
  hbf       the hbf frf process writing its CSV (to /dev/null) and JSON summary, from the
            command's start to its end;
  hbf run   the same run's own wall time (its JSON's wall_time_seconds: parsing the flags,
            the FRF, the verdict; without the process's start and exit);
  python -c the interpreter started, hbfriction imported (NumPy with it) and frf() called.
Printed as ratios: frf() / core is the bindings' own overhead; frf() / hbf run the cost of
getting the FRF in Python rather than from the CLI, each measured from inside its process;
frf() / hbf against the CLI's whole process; python -c / hbf includes the interpreter's start.
Also two FRFs on two Python threads against the same two in turn (the GIL released: about
2 on two cores).
"""
import argparse
import json
import os
import tempfile
import statistics
import subprocess
import sys
import threading
import time

import hbfriction
from hbfriction import _core


def median_seconds(action, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--hbf", default=os.path.join(os.path.dirname(__file__), "..", "build", "hbf"))
    parser.add_argument("--law", default="coulomb")
    args = parser.parse_args()
    system = hbfriction.absorber(args.law)
    settings = _core.default_frf_settings(system)
    summary = os.path.join(tempfile.mkdtemp(prefix="hbf-bench-"), "summary.json")
    cli = [args.hbf, "frf", "--quiet", "--law", args.law, "--out", os.devnull, "--summary", summary]
    script = "import hbfriction; hbfriction.frf(hbfriction.absorber(%r))" % args.law
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(sys.path)
    actions = {
        "core": lambda: _core.compute_frf(system, settings),
        "frf()": lambda: hbfriction.frf(system),
        "hbf": lambda: subprocess.run(cli, check=True),
        "python -c": lambda: subprocess.run([sys.executable, "-c", script], check=True, env=env),
    }
    for action in actions.values():  # warm up: page cache, FFTW plans, imports
        action()
    samples = {name: [] for name in actions}
    samples["hbf run"] = []
    for _ in range(args.repeat):  # interleaved, so that a drift of the machine hits all alike
        for name, action in actions.items():
            samples[name].append(median_seconds(action, 1))
            if name == "hbf":
                with open(summary) as f:
                    samples["hbf run"].append(json.load(f)["wall_time_seconds"])
    os.remove(summary)
    os.rmdir(os.path.dirname(summary))
    t = {name: statistics.median(v) for name, v in samples.items()}
    print("default FRF (%s), median of %d runs each:" % (args.law, args.repeat))
    for name in samples:
        print("  %-10s %8.4f s" % (name, t[name]))
    print("ratios:")
    print("  frf() / core       %.3f   (the bindings' own overhead)" % (t["frf()"] / t["core"]))
    print("  frf() / hbf run    %.3f   (an FRF in Python against the CLI, each timed in its process)" %
          (t["frf()"] / t["hbf run"]))
    print("  frf() / hbf        %.3f   (an FRF in Python against the CLI's whole process)" % (t["frf()"] / t["hbf"]))
    print("  python -c / hbf    %.3f   (with the interpreter's start and NumPy's import)" %
          (t["python -c"] / t["hbf"]))

    lugre = hbfriction.absorber("lugre")
    one = lambda: [hbfriction.frf(lugre) for _ in range(2)]

    def two():
        threads = [threading.Thread(target=hbfriction.frf, args=(lugre,)) for _ in range(2)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()

    sequential = median_seconds(one, args.repeat)
    parallel = median_seconds(two, args.repeat)
    print("two LuGre FRFs: in turn %.4f s, on two threads %.4f s: speed-up %.2f (%d cores)"
          % (sequential, parallel, sequential / parallel, os.cpu_count()))


if __name__ == "__main__":
    main()
