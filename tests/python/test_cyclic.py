"""A sector of a cyclically symmetric wheel from Python (hbfriction.load of a [cyclic] file,
nodal_diameters, frf, modes): the same numbers as hbf nodal-diameters and hbf frf on the same file, the
nodal-diameter-0 family against the sector with its cut faces merged by hand, and the refusals."""
import csv
import io
import os

import numpy as np
import pytest

import hbfriction
from conftest import SOURCE, run_hbf

WHEEL = os.path.join(SOURCE, "examples", "systems", "bladed_disk", "wheel24.toml")


def test_the_sector_and_its_families_are_the_command_lines():
    sector = hbfriction.load(WHEEL)
    assert sector.cyclic == {"sectors": 24, "engine_order": 3, "neighbours": [(4, 0), (5, 1)]}
    families = hbfriction.nodal_diameters(sector)
    _, out, _ = run_hbf("nodal-diameters", "--config", WHEEL)
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == len(families) == 13 * 4
    for k, row in enumerate(rows):
        assert int(row["nodal_diameter"]) == families.nodal_diameter[k]
        assert float(row["released"]) == pytest.approx(families.released[k], rel=1e-14)
        assert float(row["stuck"]) == pytest.approx(families.stuck[k], rel=1e-14)
        assert row["excited_by"] == families.excited_by[k]
    # Nodal diameter 0 (every sector in phase): the sector with the next sector's disk merged
    # into its own (DOF 5 into DOF 1), the contact between the platform and the next sector's,
    # which then moves with it, carrying no force: released and stuck alike.
    m = sector.mass.toarray()[:5, :5]
    k = sector.stiffness.toarray()[:5, :5]
    t = np.zeros((5, 4))
    t[:4, :4] = np.eye(4)
    t[4, 0] = 1.0
    mm, km = t.T @ m @ t, t.T @ k @ t
    expected = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(mm, km)).real))
    got = families.released[families.nodal_diameter == 0]
    assert np.allclose(got, expected, rtol=1e-10)
    assert np.allclose(families.stuck[families.nodal_diameter == 0], expected, rtol=1e-10)


def test_the_sectors_frf_is_hbf_frfs():
    sector = hbfriction.load(WHEEL)
    branch = hbfriction.frf(sector)
    assert branch.status == "completed"
    _, out, _ = run_hbf("frf", "--config", WHEEL, "--quiet")
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == len(branch.w)
    assert np.allclose([float(r["y4_max"]) for r in rows], branch.y4_max, rtol=1e-12)
    # the peak between nodal diameter 3's released and stuck resonances
    families = hbfriction.nodal_diameters(sector)
    first = (families.nodal_diameter == 3) & (families.mode == 1)
    assert families.released[first][0] < branch.peak["w"] < families.stuck[first][0]


def test_what_a_sector_does_not_take_is_refused():
    sector = hbfriction.load(WHEEL)
    with pytest.raises(ValueError, match="not available for a sector model"):
        hbfriction.timeint(sector, 4.5)
    with pytest.raises(ValueError, match="not a sector"):
        hbfriction.nodal_diameters(hbfriction.absorber())
    with pytest.raises(ValueError, match="harmonics = 0 is out of range"):
        hbfriction.nodal_diameters(sector, harmonics=0)


def test_a_nonlinear_mode_of_the_engine_orders_family():
    """The mode of nodal diameter 3 that engine order 3 excites: a travelling wave whose linear
    limit solves the sector's folded eigenproblem (built here by hand in NumPy)."""
    sector = hbfriction.load(WHEEL)
    backbone = hbfriction.modes(sector)
    assert backbone.status == "completed"
    linear = backbone.linear
    families = hbfriction.nodal_diameters(sector)
    first = (families.nodal_diameter == 3) & (families.mode == 1)
    assert linear["omega"] == pytest.approx(families.stuck[first][0], rel=1e-12)
    phi = linear["shape"]
    assert phi.dtype == complex
    # The next sector's disk (DOF 5) and platform (DOF 6) are DOFs 1 and 2 delayed by 2 pi 3 / 24.
    turn = np.exp(-2j * np.pi * 3 / 24)
    assert phi[4] == pytest.approx(turn * phi[0], abs=1e-12)
    assert phi[5] == pytest.approx(turn * phi[1], abs=1e-12)
    # T^H (K' - w^2 M) phi = 0 with K' = K + k_t d d^T (the stuck damper, platform to the next
    # platform), T the identity on the own DOFs and the turn from DOFs 5, 6 to 1, 2.
    m = sector.mass.toarray()
    k = sector.stiffness.toarray()
    d = np.zeros(6)
    d[1], d[5] = 1.0, -1.0
    k = k + 15.0 * np.outer(d, d)
    t = np.zeros((6, 4), dtype=complex)
    t[:4, :4] = np.eye(4)
    t[4, 0] = t[5, 1] = turn
    r = t.conj().T @ (k - linear["omega"] ** 2 * m) @ phi
    assert np.abs(r).max() <= 1e-10 * np.abs(k @ phi).max()
    assert np.vdot(phi, m @ phi).real == pytest.approx(1.0, rel=1e-12)
    # friction softens it towards the released frequency
    assert families.released[first][0] < backbone.w[-1] < backbone.w[0]
