"""The automatic H has one home (frf.hpp: automatic_harmonics): hbf frf, Python's frf() and the
hb_vs_timeint benchmark report the same H for each law of the registry (contact_law.hpp), with and
without the exact polish, and with an excitation harmonic h (H times h)."""
import json
import os
import subprocess

import pytest

import hbfriction
from conftest import run_hbf

LAWS = [law["name"] for law in hbfriction._core.contact_laws() if law["preset"]]
BENCHMARK = os.environ.get("HBF_HB_VS_TIMEINT", "")


def cli_harmonics(tmp_path, *flags):
    summary = tmp_path / "summary.json"
    # (--error-points 0: the H chosen is the subject, not its accuracy)
    run_hbf("frf", *flags, "--wmin", "0.5", "--wmax", "0.6", "--error-points", "0", "--out", str(tmp_path / "frf.csv"),
            "--summary", str(summary))
    return json.loads(summary.read_text())["parameters"]["harmonics"]


@pytest.mark.parametrize("law", LAWS)
def test_cli_python_and_benchmark_choose_the_same_h(law, tmp_path):
    system = hbfriction.absorber(law)
    without = cli_harmonics(tmp_path, "--law", law, "--exact", "off")
    assert hbfriction.frf(system, exact=False, wmin=0.5, wmax=0.6).metadata["parameters"]["harmonics"] == without
    # the law's own H (at least 10) without the polish
    assert without == max(10, [l for l in hbfriction._core.contact_laws() if l["name"] == law][0]["default_harmonics"])
    # with the default polish choice (on for the laws it covers: HB then only supplies the branch)
    default = cli_harmonics(tmp_path, "--law", law)
    assert hbfriction.frf(system, wmin=0.5, wmax=0.6).metadata["parameters"]["harmonics"] == default
    exact = [l for l in hbfriction._core.contact_laws() if l["name"] == law][0]["exact_stick"]
    assert default == (10 if exact else without)
    # h = 2: twice the harmonics (no polish at h > 1)
    doubled = cli_harmonics(tmp_path, "--law", law, "--excitation-harmonic", "2")
    assert doubled == 2 * without
    assert hbfriction.frf(hbfriction.absorber(law, excitation_harmonic=2), wmin=0.5, wmax=0.6) \
        .metadata["parameters"]["harmonics"] == doubled
    # the benchmark harmonic balance against time integration (its HB side, without the polish)
    if not BENCHMARK:
        pytest.skip("HBF_HB_VS_TIMEINT is not set (benchmarks not built: HBF_BUILD_BENCHMARKS=OFF)")
    run = subprocess.run([BENCHMARK, "--law", law, "--fe", "0.5", "--points", "2", "--wmin", "0.5", "--wmax", "0.6",
                          "--repeats", "1", "--check-every", "0"], capture_output=True, text=True, check=True)
    cases = json.loads(run.stdout.strip().splitlines()[-1])["cases"]
    assert [c["harmonics"] for c in cases] == [without]


STIFF_JENKINS = """[structure]
mass = [1.0]
stiffness = [1.0e10]
damping = [1.0]
excitation = [1.0e5]

[[contact]]
dof = 1
law = "jenkins"
friction_limit = 5000.0
stiffness = 1.0e9

[frequency]
wmin = 90000.0
wmax = 110000.0
"""


def test_the_file_s_lowest_frequency_decides_the_automatic_polish_in_both_front_ends(tmp_path):
    # A stiff, lightly damped oscillator (natural frequency 1e5, damping ratio 5e-6): at the
    # default w = 0.5 its mode is far above w and flowed in closed form, but it rings through the
    # whole period (decay time 2 s against T = 12.6 s): 2.6e6 samples, 1.6e5 Taylor steps' worth,
    # above the exact solver's bound; at the file's wmin = 90000 the mode is slow: 24 steps. The
    # library's frf_settings decides on the file's wmin for hbf and Python alike (Python decided
    # on 0.5 before: no polish, and a different automatic H).
    path = tmp_path / "stiff.toml"
    path.write_text(STIFF_JENKINS)
    system = hbfriction.load(str(path))
    assert hbfriction._core.exact_cost_refusal(system, 0.5)
    assert not hbfriction._core.exact_cost_refusal(system, 90000.0)
    summary = tmp_path / "summary.json"
    run_hbf("frf", "--config", str(path), "--out", str(tmp_path / "frf.csv"), "--summary", str(summary))
    cli = json.loads(summary.read_text())
    branch = hbfriction.frf(system)
    assert cli["exact"]["enabled"] is True
    assert branch.settings.exact is True
    assert branch.metadata["parameters"]["harmonics"] == cli["parameters"]["harmonics"] == 10
    # and below the bound's frequency both leave it off
    run_hbf("frf", "--config", str(path), "--wmin", "0.5", "--wmax", "0.6", "--out", str(tmp_path / "low.csv"),
            "--summary", str(summary))
    low = hbfriction.frf(system, wmin=0.5, wmax=0.6)
    assert json.loads(summary.read_text())["exact"]["enabled"] is False
    assert low.settings.exact is False
