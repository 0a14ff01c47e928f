"""Systems from NumPy and SciPy: matrices round-trip, and an FE model built in Python gives the
FRF of hbf frf --config on the same matrices written as Matrix Market files."""
import os

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import hbfriction
from conftest import SOURCE, assert_table_equals_csv, run_hbf


def chain(n, law="dahl"):
    """A fixed-free chain of n masses 0.5 (unit springs, Rayleigh damping 0.008 M + 0.002 K: about
    7 % of critical on the first mode), forced at the tip, with one contact from DOF n/2 to the
    ground (F_c = 0.01, sigma0 = 0.05: stick-slip around the first resonance)."""
    k = sp.diags([2.0 * np.ones(n), -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1], format="lil")
    k[n - 1, n - 1] = 1.0
    k = k.tocsr()
    m = sp.identity(n, format="csr") * 0.5
    c = 0.008 * m + 0.002 * k
    f = np.zeros(n)
    f[-1] = 0.02
    contact = hbfriction.Contact(dof=n // 2, law=law, friction_limit=0.01, stiffness=0.05)
    return m, k, c, f, contact


def test_numpy_matrices_round_trip():
    mass = np.diag([1.0, 0.1])
    stiffness = np.array([[1.1, -0.1], [-0.1, 0.1]])
    damping = np.array([[0.01, 0.0], [0.0, 0.002]])
    s = hbfriction.System(mass, stiffness, [0.5, 0.0], damping=damping,
                          contacts=[hbfriction.Contact(dof=0, other_dof=1, friction_limit=0.2)])
    np.testing.assert_array_equal(s.mass.toarray(), mass)
    np.testing.assert_array_equal(s.stiffness.toarray(), stiffness)
    np.testing.assert_array_equal(s.damping.toarray(), damping)
    assert s.excitation == [0.5, 0.0] and s.dofs == 2 and s.law == "coulomb"
    # A 1-D array is the diagonal (as in a TOML file); lists, Fortran order and ints convert.
    s.mass = [1.0, 0.1]
    np.testing.assert_array_equal(s.mass.toarray(), mass)
    s.stiffness = np.asfortranarray(stiffness)
    np.testing.assert_array_equal(s.stiffness.toarray(), stiffness)
    s.damping = [[0, 0], [0, 0]]
    assert s.damping.nnz == 0


def test_scipy_sparse_round_trips_in_every_format():
    m, k, c, f, contact = chain(30)
    for fmt in ("csr", "csc", "coo", "lil", "dok", "bsr"):
        s = hbfriction.System(m.asformat(fmt), k.asformat(fmt), f, damping=c.asformat(fmt), contacts=[contact])
        assert sp.issparse(s.stiffness)
        assert (s.stiffness != k).nnz == 0 and (s.mass != m).nnz == 0 and (s.damping != c).nnz == 0
        np.testing.assert_array_equal(s.excitation, f)


def test_the_absorber_preset_is_the_papers_matrices():
    s = hbfriction.absorber("dahl", r=0.2, wa=1.5, wb=0.5)
    np.testing.assert_allclose(s.mass.toarray(), np.diag([1.0, 0.2]), rtol=1e-15)
    ka = 0.2 * 1.5 ** 2
    np.testing.assert_allclose(s.stiffness.toarray(), [[1.0 + ka, -ka], [-ka, ka]], rtol=1e-15)
    (c,) = s.contacts
    assert (c.dof, c.other_dof, c.law) == (0, 1, "dahl")
    assert c.friction_limit == 0.2 and c.stiffness == pytest.approx(0.2 * 0.5 ** 2, rel=1e-15)


def test_an_fe_model_from_scipy_equals_hbf_frf_on_its_matrix_market_files(tmp_path):
    n = 40
    m, k, c, f, contact = chain(n)
    for name, matrix in (("mass", m), ("stiffness", k), ("damping", c)):
        scipy.io.mmwrite(str(tmp_path / name), matrix)
    toml = tmp_path / "chain.toml"
    toml.write_text("""[structure]
mass = "mass.mtx"
stiffness = "stiffness.mtx"
damping = "damping.mtx"
excitation = [%s]
[[contact]]
dof = %d
law = "dahl"
friction_limit = 0.01
stiffness = 0.05
[frequency]
wmin = 0.02
wmax = 0.12
[[output]]
name = "tip"
dof = %d
[[output]]
name = "stretch"
row = [%s]
""" % (", ".join(repr(x) for x in f), n // 2 + 1, n,
       ", ".join("1.0" if i == n - 1 else "-1.0" if i == 0 else "0.0" for i in range(n))))
    csv_path = tmp_path / "frf.csv"
    run_hbf("frf", "--quiet", "--config", str(toml), "--out", str(csv_path))
    stretch = np.zeros(n)
    stretch[-1], stretch[0] = 1.0, -1.0
    s = hbfriction.System(m, k, f, damping=c, contacts=[contact])
    b = hbfriction.frf(s, outputs=[("tip", np.eye(n)[-1]), ("stretch", stretch)], wmin=0.02, wmax=0.12)
    assert_table_equals_csv(b, csv_path.read_text())
    # The same through load(): the file's outputs and frequency range apply.
    assert_table_equals_csv(hbfriction.frf(hbfriction.load(toml)), csv_path.read_text())
    assert b.metadata["status"] == "completed" and b.metadata["parameters"]["dofs"] == n
    assert {"stick", "stick-slip"} <= set(b.regime)


def test_load_reads_the_files_settings():
    s = hbfriction.load(os.path.join(SOURCE, "examples", "systems", "chain3.toml"))
    assert s.dofs == 3 and s.law == "jenkins,dahl"
    assert [o.name for o in s.outputs] == ["y1", "y3"]
    assert s.file_settings == {"omega_start": 0.2, "omega_end": 3.0}
    assert [c.law for c in s.contacts] == ["jenkins", "dahl"]


def test_contacts_are_values_assigned_back():
    s = hbfriction.absorber("jenkins")
    contacts = s.contacts
    contacts[0].friction_limit = 0.3
    assert s.contacts[0].friction_limit == 0.2  # a copy, as documented
    s.contacts = contacts
    assert s.contacts[0].friction_limit == 0.3
    b = hbfriction.frf(s, wmin=1.0, wmax=1.05)
    assert b.status == "completed"


def test_every_contact_is_reported():
    # chain3_exact.toml: Jenkins between m1 and m2, exact Coulomb from m3. The FRF's table has a
    # stick fraction and a regime per contact, and its transitions name their contact; solve_at
    # gives the same per-contact regimes as the FRF's sample row at that frequency (same H).
    s = hbfriction.load(os.path.join(SOURCE, "examples", "systems", "chain3_exact.toml"))
    b = hbfriction.frf(s, exact=False, harmonics=20, at=[1.0])
    assert "regime" not in b and "regime_c1" in b and "regime_c2" in b
    contacts = {t["contact"] for t in b.transitions}
    assert contacts == {1, 2}
    row = [k for k in range(len(b)) if b.point[k] == "sample"][0]
    one = hbfriction.solve_at(s, 1.0, harmonics=20)
    assert len(one.regimes) == 2 and len(one.stick_fractions) == 2
    assert one.regimes == [b.regime_c1[row], b.regime_c2[row]]
    assert one.stick_fractions == pytest.approx([b.stick_fraction_c1[row], b.stick_fraction_c2[row]], abs=1e-12)
    assert one.regime == one.regimes[0] and one.stick_fraction == one.stick_fractions[0]


def test_a_contact_with_a_normal_direction_from_python(tmp_path):
    # examples/systems/liftoff3.toml built from NumPy (law elastic: no friction_limit, the normal
    # direction a vector over the DOFs): the same table as hbf frf --config on the file, with
    # the contact's opening and normal force columns; a wrong normal direction is refused.
    k = np.array([[1.5, 0.5, -0.5], [0.5, 1.5, 0.0], [-0.5, 0.0, 0.5]])
    contact = hbfriction.Contact(dof=0, law="elastic", stiffness=3.0, normal_stiffness=5.0,
                                 friction_coefficient=0.3, preload=1.0, normal_direction=[0.0, 1.0, 0.0])
    assert contact.normal_direction == [0.0, 1.0, 0.0] and contact.second_direction == []
    s = hbfriction.System([1.0, 0.5, 0.3], k, [0.05, 0.15, 0.0], damping=0.03 * k, contacts=[contact])
    b = hbfriction.frf(s, outputs=[0, 1], wmin=0.3, wmax=3.0)
    assert b.status == "completed"
    assert max(b.separated_fraction) > 0.5 and min(b.normal_force_mean) > 0.0
    csv_path = tmp_path / "frf.csv"
    run_hbf("frf", "--config", os.path.join(SOURCE, "examples", "systems", "liftoff3.toml"), "--out", str(csv_path))
    assert_table_equals_csv(b, csv_path.read_text())
    contact.normal_direction = [1.0, 1.0, 0.0]  # not orthogonal to the tangential direction
    with pytest.raises(ValueError, match="normal_direction"):
        hbfriction.frf(hbfriction.System([1.0, 0.5, 0.3], k, [0.05, 0.15, 0.0], contacts=[contact]))


def test_a_rigid_unilateral_contact_from_python(tmp_path):
    # examples/systems/liftoff3_rigid.toml built from NumPy (law unilateral on two massless
    # nodes, the preload a static load): the same table as hbf frf --config on the file; a
    # contact on a coordinate with mass is refused naming it.
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3_rigid.toml")
    k = np.array([[4.5, 0.5, -0.5, -3.0, 0.0], [0.5, 6.5, 0.0, 0.0, -5.0], [-0.5, 0.0, 0.5, 0.0, 0.0],
                  [-3.0, 0.0, 0.0, 3.0, 0.0], [0.0, -5.0, 0.0, 0.0, 5.0]])
    c = np.zeros((5, 5))
    c[:3, :3] = [[0.045, 0.015, -0.015], [0.015, 0.045, 0.0], [-0.015, 0.0, 0.015]]
    contact = hbfriction.Contact(dof=3, law="unilateral", friction_coefficient=0.3,
                                 normal_direction=[0.0, 0.0, 0.0, 0.0, 1.0])
    s = hbfriction.System([1.0, 0.5, 0.3, 0.0, 0.0], k, [0.05, 0.15, 0.0, 0.0, 0.0], damping=c,
                          contacts=[contact])
    s.static_load = [0.0, -1.0, 0.0, 0.0, 1.0]
    b = hbfriction.frf(s, outputs=[0, 1], wmin=0.3, wmax=3.0)
    assert b.status == "completed"
    assert max(b.separated_fraction) > 0.5 and min(b.normal_force_mean) > 0.0
    csv_path = tmp_path / "frf.csv"
    run_hbf("frf", "--config", path, "--out", str(csv_path))
    assert_table_equals_csv(b, csv_path.read_text())
    contact.dof = 0  # y1 has mass
    contact.normal_direction = [0.0, 0.0, 0.0, 0.0, 1.0]
    with pytest.raises(ValueError, match="carries mass"):
        heavy = hbfriction.System([1.0, 0.5, 0.3, 0.0, 0.0], k, [0.05, 0.15, 0.0, 0.0, 0.0], contacts=[contact])
        heavy.static_load = [0.0, -1.0, 0.0, 0.0, 1.0]
        hbfriction.frf(heavy)


def test_a_static_load_from_python(tmp_path):
    # liftoff3.toml with a static load (System.static_load, [structure] static_load in a file):
    # the same table from NumPy as hbf frf --config on the file; a load of the wrong size is
    # refused naming it, and the property round-trips (None clears it).
    path = os.path.join(SOURCE, "examples", "systems", "liftoff3.toml")
    s = hbfriction.load(path)
    assert s.static_load == []
    s.static_load = [0.1, 0.3, 0.0]
    assert s.static_load == [0.1, 0.3, 0.0]
    b = hbfriction.frf(s, outputs=[0, 1], wmin=0.3, wmax=3.0)
    assert b.status == "completed"
    text = open(path).read().replace("excitation = [0.05, 0.15, 0.0]\n",
                                     "excitation = [0.05, 0.15, 0.0]\nstatic_load = [0.1, 0.3, 0.0]\n")
    loaded = tmp_path / "loaded.toml"
    loaded.write_text(text)
    csv_path = tmp_path / "frf.csv"
    run_hbf("frf", "--config", str(loaded), "--out", str(csv_path))
    assert_table_equals_csv(b, csv_path.read_text())
    with pytest.raises(ValueError, match="static load vector has 2 entries"):
        s.static_load = [0.1, 0.3]
        s.validate()
    s.static_load = None
    assert s.static_load == []


def test_a_reduced_finite_element_model_from_a_file(tmp_path):
    # hbfriction.load reads [reduction] as hbf does: the shipped 200-DOF beam (its Matrix Market
    # matrices, 10 N at mid-span) with the tip in contact, reduced by Craig-Bampton onto the
    # contact and loaded DOFs with 10 modes (12 coordinates); the outputs are FE DOFs 99 and
    # 199 by name; the FRF is the same table as hbf frf --config on the file.
    beam = os.path.join(SOURCE, "examples", "systems", "beam")
    excitation = ", ".join("10.0" if i == 99 else "0" for i in range(1, 201))
    path = tmp_path / "reduced.toml"
    path.write_text(
        '[structure]\nmass = "%s/beam200_mass.mtx"\nstiffness = "%s/beam200_stiffness.mtx"\n'
        'damping = "%s/beam200_damping.mtx"\nexcitation = [%s]\n'
        '[[contact]]\ndof = 199\nlaw = "coulomb"\nfriction_limit = 3\n'
        '[frequency]\nwmin = 35.0\nwmax = 45.0\n[solver]\nharmonics = 5\n'
        '[output]\nreport = [99, 199]\n[reduction]\nmodes = 10\n' % (beam, beam, beam, excitation))
    s = hbfriction.load(path)
    assert s.dofs == 12
    # (error_points=0: H = 5 is far from converged on this beam, about 50 % at its peak, which
    # the estimate says; the subject here is the reading of the file)
    b = hbfriction.frf(s, exact=False, error_points=0)
    assert b.status == "completed"
    csv_path = tmp_path / "frf.csv"
    run_hbf("frf", "--config", str(path), "--exact", "off", "--error-points", "0", "--out", str(csv_path))
    assert "y99_max" in csv_path.read_text().splitlines()[0]
    assert_table_equals_csv(b, csv_path.read_text())


def test_the_structured_jacobian_from_python():
    # jacobian="structured" (the condensed Jacobian in its structure, GMRES): the lift-off
    # example's peak equals the dense corrector's, the summary says which form ran, and a TOML
    # file's [solver] jacobian is read; a form that does not exist is refused.
    s = hbfriction.load(os.path.join(SOURCE, "examples", "systems", "liftoff3.toml"))
    structured = hbfriction.frf(s, jacobian="structured")
    dense = hbfriction.frf(s, jacobian="dense")
    assert structured.status == dense.status == "completed"
    assert structured.metadata["parameters"]["structured_jacobian"] == 1
    assert dense.metadata["parameters"]["structured_jacobian"] == 0
    assert structured.metadata["solver"]["krylov_iterations"] > 0
    a, b = structured.peaks[0], dense.peaks[0]
    assert a["w"] == pytest.approx(b["w"], rel=1e-7)
    assert a["y_max"] == pytest.approx(b["y_max"], rel=1e-7)
    with pytest.raises(ValueError, match="jacobian"):
        hbfriction.frf(s, jacobian="sparse")
