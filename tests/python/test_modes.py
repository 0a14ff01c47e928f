"""Nonlinear modes (hbf modes, hbfriction.modes): the binding and the command against the
describing function of a Jenkins oscillator (derived in tests/test_modes.cpp), and bad input."""
import csv
import io
import math
import os

import numpy as np
import pytest

import hbfriction
from conftest import SOURCE, run_hbf

JENKINS = """# m y'' + c y' + k y + f_Jenkins = 0 (one DOF, a Jenkins element to the ground)
[structure]
mass = [1.0]
stiffness = [1.0]
damping = [0.01]
excitation = [1.0]

[[contact]]
dof = 1
law = "jenkins"
friction_limit = 0.1
stiffness = 0.5
"""


def describing_function(a, m=1.0, c=0.01, k=1.0, kt=0.5, limit=0.1):
    """omega and xi of the EPMC at H = 1 from the closed-form first harmonic of the Jenkins loop."""
    fc, fs = kt * a, 0.0
    if kt * a > limit:
        star = math.acos(1.0 - 2.0 * limit / (kt * a))
        fc = kt * a / math.pi * (star - 0.5 * math.sin(2.0 * star))
        fs = -kt * a / math.pi * math.sin(star) ** 2
    omega = math.sqrt((k + fc / a) / m)
    return omega, (c - fs / (a * omega)) / m


@pytest.fixture
def jenkins(tmp_path):
    path = tmp_path / "jenkins.toml"
    path.write_text(JENKINS)
    return str(path)


def test_python_backbone_is_the_describing_function(jenkins):
    t = hbfriction.modes(hbfriction.load(jenkins), 0.05, 20.0, harmonics=1, time_samples=4096)
    assert t.status == "completed"
    assert t.linear["mode"] == 1
    assert abs(t.linear["omega"] - math.sqrt(1.5)) < 1e-14
    assert len(t) >= 20 and abs(t.a[-1] - 20.0) < 1e-12
    for a, w, xi, zeta in zip(t.a, t.w, t.xi, t.zeta):
        omega, damping = describing_function(a)
        # the AFT's sums differ from the integrals by about 5 / N_t^2 (tests/test_modes.cpp)
        assert abs(w - omega) <= 1e-6 * omega
        assert abs(xi - damping) <= 1e-6 * damping
        assert abs(zeta - xi / (2.0 * w)) <= 1e-15
    assert "zeta_energy" in t.meaning and t.regime_c1[0] == "stick" and t.regime_c1[-1] != "stick"


def test_command_writes_the_same_backbone(jenkins, tmp_path):
    out = tmp_path / "modes.csv"
    summary = tmp_path / "modes.json"
    code, _, err = run_hbf("modes", "--config", jenkins, "--amin", "0.05", "--amax", "20", "--harmonics", "1",
                           "--time-samples", "4096", "--out", str(out), "--summary", str(summary), "--quiet")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    t = hbfriction.modes(hbfriction.load(jenkins), 0.05, 20.0, harmonics=1, time_samples=4096)
    assert len(rows) == len(t)
    assert [float(r["w"]) for r in rows] == pytest.approx(list(t.w), rel=1e-14)
    assert '"status": "completed"' in summary.read_text()


def test_synthesis_is_the_commands(jenkins, tmp_path):
    # F = 1 sustains up to a ~ 100 (released: xi w a ~ c a + 4 F_c / pi = F), inside the range:
    # a complete synthesis (exit 0); with amax 10 its peak lies beyond and the curve is cut (exit 3).
    out = tmp_path / "synthesis.csv"
    code, _, err = run_hbf("modes", "--config", jenkins, "--amin", "0.01", "--amax", "300", "--harmonics", "3",
                           "--synthesis-out", str(out), "--out", os.devnull, "--quiet")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    t = hbfriction.modes(hbfriction.load(jenkins), 0.01, 300.0, harmonics=3, synthesis=True)
    assert t.status == "completed"
    s = t.synthesis
    assert len(rows) == len(s) > 10
    assert [float(r["w"]) for r in rows] == pytest.approx(list(s.w), rel=1e-14)
    # Each point solves the mode's equation |w_mode^2 - w^2 + i w xi| a = |psi^H F| (F = 1 on the one DOF, m = 1).
    xi = np.interp(s.a, t.a, t.xi)
    lhs = np.abs(s.w_mode ** 2 - s.w ** 2 + 1j * s.w * xi) * s.a
    assert np.max(np.abs(lhs - 1.0)) < 1e-3  # xi interpolated between backbone points
    assert list(np.unique(s.flank)) == [-1, 1]
    code, _, err = run_hbf("modes", "--config", jenkins, "--amin", "0.01", "--amax", "10", "--harmonics", "3",
                           "--synthesis-out", str(out), "--out", os.devnull, "--quiet", check=False)
    assert code == 3 and "cut at the backbone's last point a = 10" in err
    with pytest.warns(hbfriction.IncompleteResultWarning, match="cut at the backbone"):
        cut = hbfriction.modes(hbfriction.load(jenkins), 0.01, 10.0, harmonics=3, synthesis=True)
    assert cut.status == "incomplete" and max(cut.synthesis.a) == cut.a[-1]


def test_absorber_backbone_spans_stick_to_slip():
    # Exact Coulomb: stuck, the rigidly joined masses (omega^2 = k1 / (m1 + m2), nondimensional
    # 1 / (1 + r)); sliding, the lower mode of the released absorber.
    t = hbfriction.modes(hbfriction.absorber(), 0.01, 100.0)
    assert t.status == "completed"
    assert abs(t.w[0] - 1.0 / math.sqrt(1.1)) < 1e-12
    released = np.sqrt(np.linalg.eigvals(np.array([[1.0 + 0.1, -0.1], [-1.0, 1.0]])).real.min())
    assert abs(t.w[-1] - released) < 0.01 * released
    assert t.regime_c1[0] == "stick" and t.regime_c1[-1] == "slip"
    assert np.all(t.energy_error <= 1e-6)


@pytest.mark.parametrize("args, message", [
    (("--mode", "3", "--amin", "0.1", "--amax", "1"), "mode = 3 is out of range: allowed 1..1"),
    (("--amin", "1", "--amax", "0.5"), "--amax = 0.5 is out of range: allowed > --amin = 1"),
    (("--amin", "-1", "--amax", "1"), "--amin = -1 is out of range: allowed > 0"),
    (("--amax", "1"), "--amin is missing"),
    (("--mode", "1", "--near", "1", "--amin", "0.1", "--amax", "1"), "--near cannot be combined with --mode"),
])
def test_command_refuses_bad_input(args, message):
    code, out, err = run_hbf("modes", *args, check=False)
    assert code == 2
    assert message in err
    assert out == ""


def test_rigid_body_mode_is_refused(tmp_path):
    path = tmp_path / "free.toml"
    path.write_text("""[structure]
mass = [[1.0, 0.0], [0.0, 1.0]]
stiffness = [[0.0, 0.0], [0.0, 0.0]]
excitation = [1.0, 0.0]

[[contact]]
dof = 1
other_dof = 2
law = "jenkins"
friction_limit = 0.1
stiffness = 1.0
""")
    with pytest.raises(ValueError) as e:
        hbfriction.modes(hbfriction.load(str(path)), 0.1, 1.0)
    assert "rigid-body mode" in str(e.value)
    code, _, err = run_hbf("modes", "--config", str(path), "--amin", "0.1", "--amax", "1", check=False)
    assert code == 2 and "rigid-body mode" in err


def test_condensed_formulation_is_the_full_one():
    # The condensed formulation eliminates the structure exactly per harmonic: the same discrete
    # backbone (tests/test_modes.cpp compares point by point); the ends at the same a_max agree.
    system = hbfriction.absorber()
    full = hbfriction.modes(system, 0.01, 100.0, harmonics=10, formulation="full")
    condensed = hbfriction.modes(system, 0.01, 100.0, harmonics=10, formulation="condensed")
    assert full.formulation == "full" and condensed.formulation == "condensed" and condensed.modes == 0
    assert full.status == condensed.status == "completed"
    assert abs(condensed.w[-1] - full.w[-1]) < 1e-8 and abs(condensed.xi[-1] - full.xi[-1]) < 1e-8
    assert abs(condensed.w[0] - full.w[0]) < 1e-12
    with pytest.raises(ValueError, match="needs the condensed formulation"):
        hbfriction.modes(system, 0.01, 1.0, formulation="full", modes=2)


def test_beam_by_the_modal_receptance():
    # The 200-DOF beam (exact Coulomb at the tip): automatic is condensed there (N (2H + 1) > 1000);
    # its stuck mode by 20 modes and the residual flexibility equals the direct solve's to the
    # truncation, (w / w_21)^2 of the dynamic part: below 1e-7 here.
    beam = hbfriction.load(os.path.join(SOURCE, "examples", "systems", "beam", "beam200.toml"))
    direct = hbfriction.modes(beam, 1e-6, 3e-5, harmonics=5)
    modal = hbfriction.modes(beam, 1e-6, 3e-5, harmonics=5, modes=20)
    assert direct.formulation == modal.formulation == "condensed" and modal.modes == 20
    assert direct.status == modal.status == "completed"
    assert abs(modal.w[0] / direct.w[0] - 1.0) < 1e-7
    assert abs(direct.w[0] - direct.linear["omega"]) < 1e-10 * direct.w[0]
    assert abs(modal.zeta[-1] / direct.zeta[-1] - 1.0) < 1e-6


def test_exact_check_columns(tmp_path):
    # Every point of the exact Coulomb absorber's backbone against the event-exact solver: the
    # stuck points are the linear mode (empty), the slipping ones checked; the gap is harmonic
    # balance's truncation error (about 1 / H for exact Coulomb: tests/test_modes.cpp).
    t = hbfriction.modes(hbfriction.absorber(), 0.1, 20.0, harmonics=20, exact_check=True)
    assert t.status == "completed"
    stuck = np.array([r == "stick" for r in t.regime_c1])
    gap = np.asarray(t.exact_gap, dtype=float)
    assert np.all(np.isnan(gap[stuck])) and np.all(np.isfinite(gap[~stuck][-20:]))
    assert np.nanmax(gap) < 0.05 and np.nanmax(gap[-10:]) < 2e-3
    assert any("exact check:" in n for n in t.notes)
    out = tmp_path / "m.csv"
    code, _, err = run_hbf("modes", "--amin", "0.1", "--amax", "20", "--harmonics", "20", "--exact-check",
                           "--out", str(out), "--quiet")
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert [r["exact_gap"] == "" for r in rows] == list(stuck)


def test_default_range_from_the_slip_onset(tmp_path):
    # One DOF, m = 1: the stuck spring k_t = 0.5 carries F_c = 0.1 at the modal amplitude
    # a* = F_c sqrt(m) / k_t = 0.2; the range is a* / 10 .. 100 a*, linear (xi = c / m) below a*.
    path = tmp_path / "jenkins.toml"
    path.write_text(JENKINS)
    t = hbfriction.modes(hbfriction.load(str(path)), harmonics=1, time_samples=1024)
    assert t.status == "completed"
    assert abs(t.linear["slip_onset"] - 0.2) < 1e-13 and t.linear["slip_contact"] == 0
    assert abs(t.amplitude_min - 0.02) < 1e-14 and abs(t.amplitude_max - 20.0) < 1e-12
    assert abs(t.a[0] - 0.02) < 1e-12 and abs(t.a[-1] - 20.0) < 1e-9
    stuck = t.a < 0.2 * (1 - 1e-9)
    assert stuck.sum() >= 3 and np.all(np.abs(t.xi[stuck] - 0.01) < 1e-12)
    for a, w, xi in zip(t.a, t.w, t.xi):  # slipping beyond a*: the describing function (N_t error ~5e-6)
        w_df, xi_df = describing_function(a)
        assert abs(w - w_df) < 1e-4 * w_df and abs(xi - xi_df) < 1e-4 * xi_df
    assert t.xi.max() > 2 * 0.01
    with pytest.raises(ValueError, match="together"):
        hbfriction.modes(hbfriction.load(str(path)), 0.05)
    with pytest.raises(ValueError, match="amplitude_min = 0.0 is out of range"):
        hbfriction.modes(hbfriction.load(str(path)), 0.0, 1.0)


def test_mode_index_is_zero_based_and_mode_deprecated():
    system = hbfriction.absorber("jenkins")
    second = hbfriction.modes(system, 0.01, 0.1, mode_index=1, harmonics=3)
    assert second.linear["mode_index"] == 1 and second.linear["mode"] == 2
    with pytest.warns(DeprecationWarning, match="mode_index"):
        old = hbfriction.modes(system, 0.01, 0.1, mode=2, harmonics=3)
    assert np.array_equal(second.w, old.w) and np.array_equal(second.a, old.a)
    first = hbfriction.modes(system, 0.01, 0.1, harmonics=3)
    assert first.linear["mode_index"] == 0 and first.w[0] < second.w[0]
    with pytest.raises(ValueError, match="mode_index = -1 is out of range"):
        hbfriction.modes(system, 0.01, 0.1, mode_index=-1)
    with pytest.raises(ValueError, match="give mode_index"):
        hbfriction.modes(system, 0.01, 0.1, mode_index=0, mode=1)


def test_results_print_their_status_and_size():
    system = hbfriction.absorber("jenkins")
    t = hbfriction.modes(system, 0.01, 0.1, harmonics=3)
    assert repr(t) == "<hbfriction.ModeResult: mode_index 0, %d points, a 0.01..0.1, completed>" % len(t)
    ti = hbfriction.timeint(system, [0.9, 1.0])
    assert repr(ti).startswith("<hbfriction.Table: 2 rows, completed, %d columns (w, " % len(ti.columns))
    b = hbfriction.frf(system)
    assert repr(b).startswith("<hbfriction.Branch: %d points, completed" % len(b))


def test_a_time_limit_stops_the_backbone_and_keeps_its_points():
    # The Dahl absorber's backbone at H = 60 over 9 decades in steps of at most 1e-4 takes minutes;
    # stopped after 1 s, the backbone so far is the result (status stopped: incomplete, a
    # warning), its points those of a whole run's start.
    system = hbfriction.absorber("dahl")
    options = dict(harmonics=60, max_step=1e-4, max_points=100000)
    with pytest.warns(hbfriction.IncompleteResultWarning, match="time limit of 1 s"):
        t = hbfriction.modes(system, 1e-6, 1e3, time_limit=1, **options)
    assert t.status == "incomplete"
    assert 3 < len(t) < 100000
    options["max_points"] = len(t)
    with pytest.warns(hbfriction.IncompleteResultWarning, match="point_budget"):
        whole = hbfriction.modes(system, 1e-6, 1e3, **options)
    assert np.allclose(t.w, whole.w, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="time_limit = -1 is out of range"):
        hbfriction.modes(system, 1e-6, 1e3, time_limit=-1)


def test_slip_onset_of_an_opening_contact_equals_the_cli_note():
    # liftoff3_rigid.toml's third stuck mode presses its normal node hard: the contact opens
    # (its normal force reaches 0) before it slips; Python's linear dict says so with the same
    # onset hbf modes prints (the onset itself against a hand computation: tests/test_modes.cpp).
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    t = hbfriction.modes(hbfriction.load(path), mode_index=2, harmonics=3)
    code, _, err = run_hbf("modes", "--config", path, "--mode", "3", "--dry-run")
    assert code == 0, err
    note = [line for line in err.splitlines() if "slip onset" in line][0]
    assert "no stuck motion above it, contact 1 opens there" in note
    printed = float(note.split("a* = ")[1].split(":")[0])
    assert t.linear["slip_opens"] is True and t.linear["slip_contact"] == 0
    assert abs(t.linear["slip_onset"] / printed - 1) < 1e-12
    assert abs(t.amplitude_min / t.linear["slip_onset"] - 0.1) < 1e-14
