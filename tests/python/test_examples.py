"""examples/python: the scripts run and print what hbf computes for the same cases."""
import json
import os
import re
import subprocess
import sys

import pytest

import hbfriction

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


def _readme_block(first_line, fence):
    """The lines of README.md from the one starting first_line (inside a ``` fence block) to its end."""
    lines = open(os.path.join(SOURCE, "README.md")).read().splitlines()
    out, inside = [], False
    for i, line in enumerate(lines):
        if not inside and line.startswith(first_line) and i > 0 and any(l.startswith(fence) for l in lines[max(0, i - 2):i]):
            inside = True
        if inside and line.startswith("```"):
            break
        if inside:
            out.append(line)
    return "\n".join(out) + "\n"


def test_readme_python_quickstart_runs_and_matches_the_cli(tmp_path):
    toml = _readme_block("# my_system.toml", "```toml")
    code = _readme_block("import hbfriction", "```python")
    assert "[structure]" in toml and "hbfriction.frf" in code
    (tmp_path / "my_system.toml").write_text(toml)
    r = subprocess.run([sys.executable, "-c", code + "\nprint(repr(branch.peak['value']))\n"], capture_output=True,
                       text=True, cwd=tmp_path, timeout=600)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0].startswith("completed")
    python_peak = float(r.stdout.splitlines()[-1])
    # the same system from the command line at the same H: the same refined peak
    summary = tmp_path / "frf.json"
    run_hbf("frf", "--config", str(tmp_path / "my_system.toml"), "--harmonics", "10", "--quiet", "--out", os.devnull,
            "--summary", str(summary))
    cli_peak = max(p["y_max"] for p in json.load(open(summary))["peaks"] if p.get("output") == "y1")
    assert abs(python_peak - cli_peak) <= 1e-9 * cli_peak


def test_the_package_version_is_hbf_s():
    _, out, _ = run_hbf("--version")
    assert out.strip() == "hbf " + hbfriction.__version__
