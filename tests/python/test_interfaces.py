"""Meshed interfaces and reduction from NumPy/SciPy (issue 32, item 5): System.add_interface,
hbfriction.reduce, and the per-node results read back (Branch.interface_states, per_contact).

The model: examples/systems/block/make_block.py at 3 x 2 x 2 bricks (81 FE DOFs, a 9-node end
face pressed against a wall), written into a temporary directory; its system file is the
reference for the arrays given from Python (the same model through the TOML path), the full FE
model the reference for a reduction that keeps every mode, and hbf frf's CSV the reference for
the per-node results.
"""
import csv
import io
import os
import subprocess
import sys
import tomllib

import numpy as np
import pytest
import scipy.io

import hbfriction as h

SOURCE = os.environ.get("HBF_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HBF = os.environ.get("HBF_EXECUTABLE", "hbf")


@pytest.fixture(scope="module")
def block(tmp_path_factory):
    out = tmp_path_factory.mktemp("block")
    subprocess.run([sys.executable, os.path.join(SOURCE, "examples", "systems", "block", "make_block.py"),
                    "--nx", "3", "--ny", "2", "--nz", "2", "--out", str(out)], check=True)
    return out


def fe_system(block):
    """The block's FE model and its interface from the generated arrays (0-based DOFs)."""
    config = tomllib.load(open(block / "block.toml", "rb"))
    s = h.System(scipy.io.mmread(block / "block_mass.mtx").tocsr(), scipy.io.mmread(block / "block_stiffness.mtx").tocsr(),
                 np.array(config["structure"]["excitation"], dtype=float))
    face = config["interface"][0]
    nodes = np.asarray(scipy.io.mmread(block / "block_nodes.mtx")).astype(int) - 1
    areas = np.asarray(scipy.io.mmread(block / "block_areas.mtx")).ravel()
    added = s.add_interface(nodes, face["normal"], tangent=face["tangent"], area=areas,
                            preload_pressure=face["preload_pressure"], name=face["name"], law=face["law"],
                            friction_coefficient=face["friction_coefficient"], stiffness=face["stiffness"],
                            normal_stiffness=face["normal_stiffness"])
    assert added == {"name": face["name"], "first": 0, "count": 9, "dimension": 3}
    reported = [d - 1 for d in config["output"]["report"]]
    return s, config, reported


def test_an_interface_and_reduction_from_numpy_equal_the_system_files(block):
    s, config, reported = fe_system(block)
    assert s.dofs == 81 and len(s.contacts) == 9 and s.interfaces[0]["count"] == 9
    # the preload pressure's static load: p A along x on the face's nodes, p times the face's area in all
    assert sum(s.static_load) == pytest.approx(config["interface"][0]["preload_pressure"] * 0.02 * 0.02, rel=1e-12)
    r = h.reduce(s, config["reduction"]["modes"], damping_ratios=config["reduction"]["damping_ratios"])
    assert r.recovery.shape == (81, r.dofs) and r.dofs == 28 + 20  # 27 face DOFs, the loaded DOF, 20 modes
    assert r.retained[:27] == sorted(np.asarray(scipy.io.mmread(block / "block_nodes.mtx")).astype(int).ravel() - 1)
    # T's rows of the retained DOFs are [I 0]
    assert np.array_equal(r.recovery[r.retained, :28], np.eye(28))
    r.outputs = r.fe_outputs(reported)
    from_file = h.load(block / "block.toml")
    # stuck, and partly open past the resonance (H = 3; frequencies with one solution): equal to 1e-9
    for w, start in ((20000.0, 19950.0), (35700.0, None)):  # 35700: reached from below, over the resonance
        a = h.solve_at(r, w, omega_from=start, harmonics=3, locate_folds=False)
        b = h.solve_at(from_file, w, omega_from=start, harmonics=3, locate_folds=False)
        assert np.allclose(a.output_max, b.output_max, rtol=1e-9, atol=0), w
        assert b.regime != "stick" or w == 20000.0


def test_a_reduction_keeping_every_mode_is_the_fe_model(block):
    # Craig-Bampton with every fixed-interface mode is the FE model in other coordinates: the
    # contacts' solutions equal those of the unreduced model (81 DOFs, condensed on the contacts).
    s, config, reported = fe_system(block)
    s.outputs = [h.Output.dof(d) for d in reported]
    r = h.reduce(s, 81 - 28)
    r.outputs = r.fe_outputs(reported)
    # stuck (the reduction is linear: the contacts act on retained DOFs), with the preload's
    # static state on harmonic 0, away from and near the resonance
    for w in (20000.0, 34800.0):
        a = h.solve_at(r, w, omega_from=w - 50.0, harmonics=3)
        b = h.solve_at(s, w, omega_from=w - 50.0, harmonics=3)
        assert np.allclose(a.output_max, b.output_max, rtol=1e-8, atol=0), w


def test_the_per_node_results_read_back_are_hbf_frfs_columns(block):
    from_file = h.load(block / "block.toml")
    assert from_file.interfaces == [{"name": "end face", "first": 0, "count": 9, "dimension": 3}]
    # (error_points 0: the columns' agreement is the subject; H = 3 is far from converged)
    b = h.frf(from_file, harmonics=3, omega_start=34500.0, omega_end=35000.0, error_points=0)
    assert b.status == "completed"
    done = subprocess.run([HBF, "frf", "--config", str(block / "block.toml"), "--harmonics", "3", "--wmin", "34500",
                           "--wmax", "35000", "--error-points", "0", "--quiet"], stdout=subprocess.PIPE, check=True,
                          text=True)
    rows = list(csv.DictReader(io.StringIO(done.stdout)))
    assert len(rows) == len(b)
    states = b.interface_states("end face")
    assert states["stick_fraction"].shape == (len(b), 9)
    for i in range(9):
        column = np.array([float(x["separated_fraction_c%d" % (i + 1)]) for x in rows])
        assert np.array_equal(states["separated_fraction"][:, i], column)
        column = np.array([float(x["stick_fraction_c%d" % (i + 1)]) for x in rows])
        assert np.array_equal(states["stick_fraction"][:, i], column)
    for share in ("stuck_share", "slip_share", "open_share"):
        column = np.array([float(x[share + "_i1"]) for x in rows])
        assert np.allclose(states[share], column, rtol=1e-14, atol=1e-15)
        assert np.allclose(getattr(b, share + "_i1"), column, rtol=1e-14, atol=1e-15)
    total = states["stuck_share"] + states["slip_share"] + states["open_share"]
    assert np.allclose(total, 1.0, atol=1e-12)
    # the band starts stuck; up the resonance the face's edges lift off and nodes slip
    assert states["stuck_share"][0] == 1.0
    assert states["open_share"].max() > 0.1 and states["slip_share"].max() > 0.01
    assert b.per_contact("normal_force_mean").shape == (len(b), 9)
    with pytest.raises(KeyError, match="end face"):
        b.interface_states("flange")


def test_bad_interfaces_and_reductions_name_the_key(block):
    s, _, _ = fe_system(block)
    nodes = np.asarray(scipy.io.mmread(block / "block_nodes.mtx")).astype(int) - 1
    law = dict(law="elastic", friction_coefficient=0.3, stiffness=2e13, normal_stiffness=5e13)

    def fresh():
        return h.System(s.mass, s.stiffness, s.excitation)

    cases = [
        (lambda: fresh().add_interface(np.vstack([nodes[:-1], [[78, 79, 81]]]), [1, 0, 0], **law), "allowed 1..81"),
        (lambda: fresh().add_interface(np.vstack([nodes[:-1], nodes[:1]]), [1, 0, 0], **law), "used twice"),
        (lambda: fresh().add_interface(nodes + 0.5, [1, 0, 0], **law), "not a DOF index"),
        (lambda: fresh().add_interface(nodes, [1, 0.1, 0], **law), "normal: row 1 has length"),
        (lambda: fresh().add_interface(nodes, [1, 0, 0], tangent=[1, 0, 0], **law), "not orthogonal"),
        (lambda: fresh().add_interface(nodes, [1, 0, 0], area=-1.0, **law), "area"),
        (lambda: fresh().add_interface(nodes, [1, 0, 0], preload_pressure=-1.0, **law), "preload_pressure"),
        (lambda: fresh().add_interface(nodes, [1, 0, 0], law="jenkins", friction_limit=1.0, stiffness=1.0),
         "no normal direction"),
        (lambda: [t.add_interface(nodes[2:5], [1, 0, 0], **law)
                  for t in [fresh()] if t.add_interface(nodes[:3], [1, 0, 0], **law)],
         "node 0's DOF %d is also a node DOF of interface 'interface 1'" % nodes[2][0]),
        (lambda: h.reduce(s, 1000), r"reduction.modes = 1000 is out of range: allowed 0..53"),
        (lambda: h.reduce(s, 10, method="guyan"), "reduction.method"),
        (lambda: h.reduce(s, 10, damping_ratios=[1.5]), "reduction.damping_ratios"),
        (lambda: h.reduce(s, 10, damping_ratios=[0.01], rayleigh=(0, 1e-6)), "alternatives"),
        (lambda: h.reduce(s, 10).add_interface(nodes, [1, 0, 0], **law), "already reduced"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    # an unconstrained structure: the constraint modes do not exist
    free = h.System(np.eye(4), np.diag([1.0, 1.0, 0.0, 0.0]), [1.0, 0.0, 0.0, 0.0])
    free.add_interface([[0, 1]], [0.0, 1.0], **law)
    with pytest.raises(ValueError, match="reduction.interface: the structure with its retained DOFs held is singular"):
        h.reduce(free, 1)
    # the system is unchanged by a refused interface
    t = fresh()
    with pytest.raises(ValueError):
        t.add_interface(nodes, [1, 0.1, 0], **law)
    assert len(t.contacts) == 0 and t.interfaces == [] and len(t.static_load) == 0
