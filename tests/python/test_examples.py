"""examples/python: the scripts run and print what hbf computes for the same cases."""
import json
import os
import re
import subprocess
import sys

import pytest

from conftest import SOURCE, run_hbf

EXAMPLES = os.path.join(SOURCE, "examples", "python")


def run_example(name, *args, cwd):
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args], capture_output=True, text=True,
                       cwd=cwd, timeout=600)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_three_laws_prints_the_cli_peaks(tmp_path):
    out = run_example("three_laws.py", str(tmp_path / "laws.png"), cwd=tmp_path)
    assert (tmp_path / "laws.png").stat().st_size > 10000
    for law in ("coulomb", "dahl", "lugre"):
        line = next(l for l in out.splitlines() if l.startswith(law))
        assert "completed" in line
        value = float(re.search(r"y1_max = (\S+)", line).group(1))
        summary = tmp_path / (law + ".json")
        run_hbf("frf", "--quiet", "--law", law, "--out", os.devnull, "--summary", str(summary))
        peaks = [p["y_max"] for p in json.loads(summary.read_text())["peaks"] if p["output"] == "y1"]
        assert value == pytest.approx(max(peaks), rel=1e-8)  # printed with 9 digits


def test_three_laws_refuses_a_bad_plot_path_before_the_work(tmp_path):
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, "three_laws.py"), str(tmp_path / "no" / "x.png")],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode != 0 and "ValueError" in r.stderr and "coulomb" not in r.stdout


def test_fe_sparse_runs_on_a_small_mesh(tmp_path):
    out = run_example("fe_sparse.py", "100", str(tmp_path / "bar.png"), cwd=tmp_path)
    assert re.search(r"^100 DOFs: \d+ points in .* status completed", out, re.M)
    assert "stick-slip" in out and (tmp_path / "bar.png").exists()
