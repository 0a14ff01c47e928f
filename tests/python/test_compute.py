"""solve_at, timeint, analytic, optimize and map: each equals its hbf command for the same case."""
import json
import os
import re

import numpy as np
import pytest

import hbfriction
from conftest import SOURCE, assert_table_equals_csv, format_number, read_csv, run_hbf


def test_solve_at_equals_hbf_loop():
    _, text, _ = run_hbf("loop", "--law", "lugre", "--w", "1.1")
    fields, _ = read_csv(text)
    s = hbfriction.solve_at(hbfriction.absorber("lugre"), 1.1)
    columns = {"t": s.t, "y1": s.y[:, 0], "y2": s.y[:, 1], "q": s.q, "v": s.v, "f": s.f, "f_series": s.f_series}
    for name, values in columns.items():
        assert [format_number(x) for x in values] == fields[name], name
    assert [str(int(x)) for x in s.stick] == fields["stick"]
    # One period of the solution: the metrics are those of its signals, and the energy balances.
    assert s.omega == 1.1 and s.harmonics == 10
    assert s.y_max[0] == pytest.approx(np.abs(s.y[:, 0]).max(), rel=1e-3)
    assert s.energy_error < 1e-6
    assert s.coefficients.shape == (21, 2)


def test_solve_at_past_a_stuck_resonance_is_an_error():
    # Exact Coulomb stuck at mu = 50: the undamped resonance near w = 0.85 caps branch 1, and
    # branch 2 starts at w itself: the solution there is found.
    s = hbfriction.solve_at(hbfriction.absorber(mu=50.0), 1.2, max_amplitude=100.0)
    assert s.regime == "stick"
    with pytest.raises(hbfriction.SolveError, match="no solution at w = 1.2"):
        hbfriction.solve_at(hbfriction.absorber("lugre"), 1.2, max_points=3)


def test_timeint_equals_hbf_timeint():
    _, text, _ = run_hbf("timeint", "--quiet", "--law", "dahl", "--wmin", "0.8", "--wmax", "1.2", "--points", "3")
    t = hbfriction.timeint(hbfriction.absorber("dahl"), [0.8, 1.0, 1.2])
    assert_table_equals_csv(t, text)
    assert t.status == "completed" and len(t.responses) == 3
    r = t.responses[0]
    assert r["y"].shape == (256, 2) and r["friction_force"].shape == (256, 1)
    # The sampled period's largest |y1| is below the exact turning point, and close to it.
    assert np.abs(r["y"][:, 0]).max() <= t.y1_max[0] * (1 + 1e-9)
    assert np.abs(r["y"][:, 0]).max() >= t.y1_max[0] * (1 - 1e-3)


def test_analytic_equals_hbf_analytic():
    _, text, _ = run_hbf("analytic", "--law", "lugre", "--wmin", "0.5", "--wmax", "1.5", "--points", "5")
    t = hbfriction.analytic(hbfriction.absorber("lugre"), [0.5, 0.75, 1.0, 1.25, 1.5])
    assert_table_equals_csv(t, text)


def test_optimize_equals_hbf_optimize(tmp_path):
    summary = tmp_path / "opt.json"
    _, text, _ = run_hbf("optimize", "--quiet", "--law", "lugre", "--range", "0.05:1", "--summary", str(summary))
    cli = json.loads(summary.read_text())
    r = hbfriction.optimize(lambda mu: hbfriction.absorber("lugre", mu=mu), 0.05, 1.0)
    assert r.status == cli["status"] == "converged"
    assert r.parameter == cli["optimum"]["value"]
    assert r.peak["value"] == cli["optimum"]["peak"] and r.peak["w"] == cli["optimum"]["peak_w"]
    fields, _ = read_csv(text)
    assert [format_number(p) for p in r.trace["parameter"]] == fields["mu"]
    assert list(r.trace["phase"]) == fields["phase"]


def test_optimize_with_values_out_of_range_fails_those_frfs_only():
    # mu <= 0.1 is refused by the callable: those FRFs fail, the search goes on above.
    def system(mu):
        if mu <= 0.1:
            raise ValueError("mu = %g is out of range for this study: allowed > 0.1" % mu)
        return hbfriction.absorber("lugre", mu=mu)

    r = hbfriction.optimize(system, 0.05, 1.0)
    assert r.status == "converged" and r.parameter == pytest.approx(0.2942178, rel=1e-4)
    assert r.failed >= 1 and r.failed_in_bracket == 0
    with pytest.raises(RuntimeError, match="must return an hbfriction.System"):
        hbfriction.optimize(lambda mu: hbfriction.absorber("lugre", mu=mu) if mu < 0.3 else 42, 0.05, 1.0)


def test_map_equals_hbf_map():
    _, text, _ = run_hbf("map", "--quiet", "--law", "lugre", "--param", "mu", "--values", "0.2,0.4", "--threads", "2")
    lines = text.splitlines()
    m = hbfriction.map(lambda mu: hbfriction.absorber("lugre", mu=mu), [0.2, 0.4], threads=2)
    expected = [lines[0]]
    for value, b in zip(m.values, m.branches):
        status = b.metadata["status"]
        expected += ["%s,%s,%s" % (format_number(value), status, row) for row in b.csv().splitlines()[1:]]
    assert lines == expected
    assert list(m.status) == ["completed", "completed"]
    # Each FRF of the map is the FRF computed alone.
    alone = hbfriction.frf(hbfriction.absorber("lugre", mu=0.4))
    np.testing.assert_array_equal(alone.y1_max, m.branches[1].y1_max)
    assert m.peak[1] == alone.peak["value"]


def test_timeint_exact_equals_hbf_timeint_method_exact():
    _, text, _ = run_hbf("timeint", "--quiet", "--law", "jenkins", "--wmin", "0.8", "--wmax", "1.2", "--points", "3",
                         "--method", "exact")
    t = hbfriction.timeint(hbfriction.absorber("jenkins"), [0.8, 1.0, 1.2], method="exact")
    assert_table_equals_csv(t, text)
    assert t.status == "completed"
    with pytest.raises(ValueError, match="method = 'exact': contact 1 has law dahl"):
        hbfriction.timeint(hbfriction.absorber("dahl"), 1.0, method="exact")


def assert_table_near_csv(t, text):
    """The table is the CLI's CSV: the words exactly, the numbers to 1e-12 (an exact orbit's last
    Newton step leaves a rounding that the module's and the executable's builds need not share)."""
    fields, header = read_csv(text)
    assert t.columns == header
    for name in header:
        for value, cli in zip(t[name], fields[name]):
            if t[name].dtype.kind == "U":
                assert value == cli, name
            else:
                assert value == pytest.approx(float(cli), rel=1e-12, abs=1e-15), name


def test_timeint_exact_with_rigid_contacts_equals_hbf_timeint():
    # law unilateral (liftoff3_rigid.toml): the exact sweep from Python, each orbit from the secant
    # through the previous two as in hbf timeint --method exact: the same table; at w = 2.3 the
    # orbit is unstable (a note, the status stays completed).
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    _, text, err = run_hbf("timeint", "--config", path, "--wmin", "2.1", "--wmax", "2.7", "--points", "4",
                           "--method", "exact")
    t = hbfriction.timeint(hbfriction.load(path), [2.1, 2.3, 2.5, 2.7], method="exact")
    assert_table_near_csv(t, text)
    assert t.status == "completed"
    assert "exact orbits are unstable" in err
    # the notes are the CLI's (their numbers to 1e-9, as the tables'): the unstable orbit's among them
    assert any("1 of 4 exact orbits are unstable" in note for note in t.notes)
    number = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
    cli_notes = [line.split("note: ", 1)[1] for line in err.splitlines() if ": note: " in line]
    assert len(cli_notes) == len(t.notes)
    for note, cli in zip(t.notes, cli_notes):
        assert number.sub("#", note) == number.sub("#", cli), note
        for ours, theirs in zip(number.findall(note), number.findall(cli)):
            assert float(ours) == pytest.approx(float(theirs), rel=1e-9), note


def test_timeint_exact_symmetric_equals_hbf_timeint_symmetric_on():
    # tests/data/mirror_pair.toml (two masses on 3D rigid contacts, mirror images of each other):
    # Python's symmetric=True is hbf timeint --symmetric on (the same table to 1e-12), its orbits
    # their own mirror images (y1 <-> y3, y2 <-> -y4: equal maxima); refused where it would do
    # nothing, naming why.
    path = os.path.join(SOURCE, "tests", "data", "mirror_pair.toml")
    _, text, _ = run_hbf("timeint", "--config", path, "--wmin", "0.6", "--wmax", "0.9", "--points", "4",
                         "--method", "exact", "--symmetric", "on")
    t = hbfriction.timeint(hbfriction.load(path), [0.6, 0.7, 0.8, 0.9], method="exact", symmetric=True)
    assert_table_near_csv(t, text)
    assert t.status == "completed"
    for a, b in (("y1_max", "y3_max"), ("y2_max", "y4_max")):
        assert np.allclose(t[a], t[b], rtol=1e-10, atol=0.0)
    with pytest.raises(ValueError, match="symmetric = True applies to method = 'exact'"):
        hbfriction.timeint(hbfriction.load(path), 0.7, symmetric=True)
    liftoff = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    with pytest.raises(ValueError, match="symmetric = True: mirror-symmetric orbits apply to law unilateral's 3D"):
        hbfriction.timeint(hbfriction.load(liftoff), 2.1, method="exact", symmetric=True)


def test_frf_start_harmonics_equals_hbf_frf_and_the_cold_start():
    # liftoff3_rigid.toml at w = 1.1, H = 10: the start from the H = 3 solution is the cold start's
    # point (unique there), and Python's start_harmonics is hbf frf --start-harmonics; a value at
    # or above H raises, naming the option.
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    system = hbfriction.load(path)
    options = dict(wmin=1.1, wmax=1.1, harmonics=10, exact=False, error_points=0)
    cold = hbfriction.frf(system, **options)
    low = hbfriction.frf(system, start_harmonics=3, **options)
    _, text, _ = run_hbf("frf", "--config", path, "--wmin", "1.1", "--wmax", "1.1", "--harmonics", "10", "--exact",
                         "off", "--error-points", "0", "--start-harmonics", "3")
    fields, header = read_csv(text)
    compared = 0
    for name in header:
        if low[name].dtype.kind == "U":
            assert list(low[name]) == fields[name], name
            continue
        if fields[name][0] == "":  # not computed at this point: NaN in all three
            assert np.isnan(low[name][0]) and np.isnan(cold[name][0]), name
            continue
        assert low[name][0] == pytest.approx(float(fields[name][0]), rel=1e-12, abs=1e-15), name
        if name in ("iterations", "residual", "energy_error"):  # Newton's own path from each start
            continue
        assert low[name][0] == pytest.approx(cold[name][0], rel=1e-8, abs=1e-12), name
        compared += 1
    assert compared >= 10
    with pytest.raises(ValueError, match="start_harmonics = 10 is out of range"):
        hbfriction.frf(system, start_harmonics=10, **options)


def test_timeint_that_does_not_converge_is_failed_with_the_reason():
    # Two periods cannot settle the undamped stuck absorber's free vibration: hbf timeint exits 1.
    code, text, err = run_hbf("timeint", "--quiet", "--law", "dahl", "--w", "1.0", "--max-periods", "2",
                              "--min-periods", "2", check=False)
    assert code == 1
    with pytest.warns(hbfriction.IncompleteResultWarning, match="did not converge"):
        t = hbfriction.timeint(hbfriction.absorber("dahl"), 1.0, max_periods=2, min_periods=2)
    assert t.status == "failed" and list(t.converged) == ["false"]
    assert_table_equals_csv(t, text)
    assert [e for e in t.errors if "did not converge" in e] and all(e in err for e in t.errors)


def test_exact_branch_equals_hbf_timeint_sweep_branch():
    # liftoff3_rigid.toml over [2.2, 2.8]: the branch of exact orbits through its two folds, as
    # hbf timeint --method exact --sweep branch has it (the same table, folds and status).
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    _, text, err = run_hbf("timeint", "--config", path, "--wmin", "2.2", "--wmax", "2.8", "--points", "31",
                           "--method", "exact", "--sweep", "branch")
    b = hbfriction.exact_branch(hbfriction.load(path), 2.2, 2.8, points=31)
    assert_table_equals_csv(b, text)
    assert b.status == "completed" and b.branch_status == "completed"
    assert len(b.folds) == 2 and b.folds[0]["w"] > b.folds[1]["w"]
    for fold in b.folds:
        assert ("a fold at w = %s" % format_number(fold["w"])) in err
    # the orbit at each fold's turn: unstable on one side, stable on the other (a saddle-node)
    for fold in b.folds:
        before, after = b.responses[fold["point"] - 2], b.responses[fold["point"] + 2]
        assert (before["max_multiplier"] - 1) * (after["max_multiplier"] - 1) < 0
    # the unstable stretches between the folds are noted, as by the CLI
    unstable = sum(r["max_multiplier"] > 1 + 1e-6 for r in b.responses)
    assert unstable > 0
    assert any(("%d of %d exact orbits are unstable" % (unstable, len(b.responses))) in note for note in b.notes)
    with pytest.raises(ValueError, match="points = 1 is out of range"):
        hbfriction.exact_branch(hbfriction.load(path), 2.2, 2.8, points=1)


def test_a_time_limit_stops_timeint_and_keeps_its_frequencies():
    # 400 frequencies of the Dahl absorber take about 4 s; stopped after 0.5 s, the frequencies
    # done are the result (status incomplete, stopped, a warning naming the limit), each equal to
    # a whole run's over the same frequencies; the one under way is not written.
    system = hbfriction.absorber("dahl")
    w = np.linspace(0.5, 1.6, 400)
    with pytest.warns(hbfriction.IncompleteResultWarning, match="time limit of 0.5 s"):
        t = hbfriction.timeint(system, w, time_limit=0.5)
    assert t.stopped
    assert t.status == "incomplete"
    n = len(t.w)
    assert 1 <= n < len(w)
    assert any("%d of 400 frequencies computed" % n in m for m in t.warnings)
    whole = hbfriction.timeint(system, w[:n])
    assert not whole.stopped
    assert np.array_equal(t.w, whole.w)
    assert np.allclose(t.y1_max, whole.y1_max, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="time_limit = -1 is out of range"):
        hbfriction.timeint(system, 1.0, time_limit=-1)
