"""frf(): the Python result is hbf frf's, column for column, for the same case."""
import json
import math
import os

import numpy as np
import pytest

import hbfriction
from conftest import SOURCE, assert_table_equals_csv, run_hbf


def cli_frf(tmp_path, *args):
    csv_path, json_path = tmp_path / "frf.csv", tmp_path / "frf.json"
    # exit 3: written but doubtful (e.g. harmonic balance's estimated error above its limit);
    # the summary says so, and Python's result must say the same (assert_same_summary)
    code, _, err = run_hbf("frf", "--quiet", "--out", str(csv_path), "--summary", str(json_path), *args, check=False)
    assert code in (0, 3), err
    summary = json.loads(json_path.read_text())
    assert (code == 3) == (summary["outcome"] == "incomplete"), err
    return csv_path.read_text(), summary


def assert_same_summary(python, cli):
    """The JSON summaries agree on everything but wall times."""
    timing = ("seconds", "wall_time_seconds")

    def strip(d):
        if isinstance(d, dict):
            return {k: strip(v) for k, v in d.items() if not k.endswith(timing) and "seconds" not in k}
        if isinstance(d, list):
            return [strip(v) for v in d]
        return d

    assert strip(python) == strip(cli)


def test_default_frf_equals_the_cli(tmp_path):
    text, summary = cli_frf(tmp_path)
    b = hbfriction.frf(hbfriction.absorber())
    assert b.status == "completed"
    assert_table_equals_csv(b, text)
    assert b.csv() == text  # byte for byte
    assert_same_summary(b.metadata, summary)
    # The exact polish ran on every row (coulomb: the CLI's default), and the peak is the JSON's.
    assert set(b.exact) == {"yes"}
    assert b.peak["value"] == pytest.approx(max(p["y_max"] for p in summary["peaks"] if p["output"] == "y1"), rel=1e-15)


@pytest.mark.parametrize("law", ["dahl", "lugre", "jenkins", "coulomb-reg"])
def test_every_law_equals_the_cli(tmp_path, law):
    text, summary = cli_frf(tmp_path, "--law", law, "--mu", "0.3", "--wmin", "0.6", "--wmax", "1.4")
    b = hbfriction.frf(hbfriction.absorber(law, mu=0.3), wmin=0.6, omega_end=1.4)
    assert_table_equals_csv(b, text)
    assert_same_summary(b.metadata, summary)
    assert b.settings.harmonic_balance.harmonics == summary["parameters"]["harmonics"]


def test_samples_stability_and_options_equal_the_cli(tmp_path):
    text, summary = cli_frf(tmp_path, "--law", "lugre", "--at", "0.9,1.1", "--stability", "on", "--harmonics", "12",
                            "--tolerance", "1e-10", "--max-step", "0.5")
    b = hbfriction.frf(hbfriction.absorber("lugre"), at=[0.9, 1.1], stability=True, harmonics=12, tolerance=1e-10,
                       max_step=0.5)
    assert_table_equals_csv(b, text)
    assert_same_summary(b.metadata, summary)
    assert list(b.w[b.point == "sample"]) == [0.9, 1.1]
    assert set(b.stable) <= {"true", "false", "uncertain"}
    assert np.all(np.isfinite(b.stability_margin))


def test_a_toml_system_equals_hbf_frf_config(tmp_path):
    path = os.path.join(SOURCE, "examples", "systems", "chain3.toml")
    text, summary = cli_frf(tmp_path, "--config", path)
    b = hbfriction.frf(hbfriction.load(path))
    assert_table_equals_csv(b, text)
    assert_same_summary(b.metadata, summary)


def test_the_stuck_absorber_is_the_closed_form():
    # mu far above the limit friction coefficient: the contact never slips, and the exact
    # Coulomb FRF is the linear two-mass system of the paper's eq. (5) (hbf analytic).
    system = hbfriction.absorber(mu=50.0)
    b = hbfriction.frf(system, wmin=0.5, wmax=0.9)
    assert set(b.regime) == {"stick"}
    closed = hbfriction.analytic(system, b.w)
    np.testing.assert_allclose(b.y1_max, closed.y1_stick, rtol=1e-9)
    np.testing.assert_allclose(b.y2_max, closed.y2_stick, rtol=1e-9)


def test_branch_object():
    b = hbfriction.frf(hbfriction.absorber("dahl"), outputs=[0], peaks_of_every_output=False)
    assert b.columns[:3] == ["w", "y1_max", "y1_amp1"]
    assert b.y1_max.dtype == np.float64 and b.branch.dtype == np.int64 and b.regime.dtype.kind == "U"
    assert len(b) == len(b.w) == len(b.coefficients())
    assert "y1_max" in b and "max over one period" in b.meaning["y1_max"]
    assert b.metadata["status"] == "completed" and b.metadata["parameters"]["law"] == "dahl"
    # The energy balance of every point: input work = friction energy (no viscous damping).
    assert np.all(b.energy_error < 1e-6)
    with pytest.raises(AttributeError):
        b.no_such_column


def test_an_incomplete_frf_warns_and_says_why():
    # An undamped resonance of the stuck structure caps the branch: never a silent success.
    with pytest.warns(hbfriction.IncompleteResultWarning, match="amplitude"):
        b = hbfriction.frf(hbfriction.absorber(mu=50.0), exact=False, max_amplitude=20.0)
    assert b.status == "incomplete"
    assert b.metadata["status"] == "amplitude_cap"
    assert b.warnings and "spans" in b.warnings[0]
    assert b.peak["state"] == "unbounded" and math.isinf(b.peak["value"])


def test_a_time_limit_stops_the_frf_and_keeps_its_points():
    # 5000 points at max_step 1e-5 and H = 60 take about 10 s; stopped after 1 s, the branch so far
    # is the result (status stopped: incomplete, a warning), its points those of a whole run's start.
    system = hbfriction.absorber("dahl")
    with pytest.warns(hbfriction.IncompleteResultWarning, match="time limit of 1 s"):
        b = hbfriction.frf(system, harmonics=60, max_step=1e-5, time_limit=1)
    assert b.status == "incomplete"
    assert b.metadata["status"] == "stopped"
    assert 10 < len(b.w) < 5000
    assert any("not done after the stop" in n for n in b.notes)
    with pytest.warns(hbfriction.IncompleteResultWarning, match="point_budget"):
        whole = hbfriction.frf(system, harmonics=60, max_step=1e-5, max_points=len(b.w), error_points=0, peaks=False,
                               locate_transitions=False, locate_folds=False)
    assert np.allclose(b.y1_max, whole.y1_max[:len(b.w)], rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="time_limit = -1 is out of range"):
        hbfriction.frf(system, time_limit=-1)


def test_write_csv_follows_the_output_policy(tmp_path):
    b = hbfriction.frf(hbfriction.absorber("lugre"), wmin=1.0, wmax=1.1)
    target = tmp_path / "real.csv"
    target.write_text("old")
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    b.write_csv(str(link))
    assert link.is_symlink() and target.read_text() == b.csv()
    with pytest.raises(ValueError, match="directory"):
        b.write_csv(str(tmp_path))
    with pytest.raises(ValueError):
        b.write_csv(str(tmp_path / "missing" / "x.csv"))
    assert not (tmp_path / "missing").exists()


def test_a_finite_element_model_is_polished_on_its_modal_form(tmp_path):
    # The 200-DOF beam (beyond the exact solver's 64 DOFs): exact=True is accepted and polishes
    # on the modal form, as hbf frf does by default; the same table and summary (modes, the
    # truncation estimate) as the CLI.
    path = os.path.join(SOURCE, "examples", "systems", "beam", "beam200.toml")
    text, summary = cli_frf(tmp_path, "--config", path, "--wmin", "74", "--wmax", "76")
    assert summary["exact"]["modes"] == 20
    assert summary["exact"]["modal_truncation"] < 1e-9
    b = hbfriction.frf(hbfriction.load(path), wmin=74.0, wmax=76.0, exact=True)
    assert set(b.exact) == {"yes"}
    assert_table_equals_csv(b, text)
    assert_same_summary(b.metadata, summary)


def test_harmonic_balance_estimates_its_error_from_python():
    # Exact Coulomb at H = 5 without the polish: the estimate (about 2.4e-2 at the peak, against
    # the exact solver's 2.9e-2) passes the default limit: the FRF is incomplete and says why.
    system = hbfriction.absorber(mu=0.5, fe=1.0)
    b = hbfriction.frf(system, exact=False, harmonics=5)
    assert b.status == "incomplete"
    estimated = [e for e in b.hb_error if e == e]
    assert len(estimated) >= 10
    assert 1e-2 < max(estimated) < 0.1
    assert hbfriction.frf(system, exact=False, harmonics=5, error_limit=0.5).status == "completed"
    assert all(e != e for e in hbfriction.frf(system, exact=False, harmonics=5, error_points=0).hb_error)
    with pytest.raises(ValueError, match="error_points"):
        hbfriction.frf(system, exact=False, error_points=-1)
