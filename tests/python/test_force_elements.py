"""The force elements without friction from Python and the command line: a Duffing oscillator
(law polynomial) against its first-order closed form, its backbone, the damped start of a
tanh-friction mode, and the laws' parameters in a system file."""
import math

import pytest

import hbfriction
from conftest import run_hbf

DUFFING = """# y'' + 0.05 y' + y + k3 y^3 = 0.02 cos(w t)
[structure]
mass = [1.0]
stiffness = [1.0]
damping = [0.05]
excitation = [0.02]

[[contact]]
dof = 1
law = "polynomial"
cubic = 0.5

[frequency]
wmin = 0.7
wmax = 1.5
"""


def test_duffing_frf_at_h1_on_the_closed_form(tmp_path):
    path = tmp_path / "duffing.toml"
    path.write_text(DUFFING)
    system = hbfriction.load(str(path))
    branch = hbfriction.frf(system, harmonics=1)
    assert branch.status == "completed"
    # (k - w^2 + (3/4) k3 A^2)^2 A^2 + (c w A)^2 = F^2 at every point (A: first-harmonic amplitude)
    worst = 0.0
    for w, a in zip(branch["w"], branch["y1_amp1"]):
        lhs = math.hypot(1.0 - w * w + 0.375 * a * a, 0.05 * w) * a
        worst = max(worst, abs(lhs - 0.02) / 0.02)
    assert worst < 1e-8
    assert set(branch["regime"]) == {"none"}


def test_duffing_backbone_from_python():
    system = hbfriction.System([1.0], [[4.0]], [0.0], damping=[[0.0]],
                               contacts=[hbfriction.Contact(dof=0, law="polynomial", cubic=0.2)])
    table = hbfriction.modes(system, 1e-3, 1.0, harmonics=1)
    assert table.status == "completed"
    for a1, w in zip(table["y1_amp1"], table["w"]):
        assert abs(w - math.sqrt(4.0 + 0.15 * a1 * a1)) < 1e-9 * w
    assert table.linear["start"] == "linear"


def test_tanh_mode_starts_on_the_damped_linear_mode():
    contact = hbfriction.Contact(dof=0, law="coulomb-reg", friction_limit=5.0, regularization=0.05)
    system = hbfriction.System([0.02, 1.0], [[40.0, -40.0], [-40.0, 640.0]], [0.0, 1.0], damping=[[0.0, 0.0], [0.0, 0.0]],
                               contacts=[contact])
    table = hbfriction.modes(system, 3.0, 3.1, harmonics=5)
    assert table.status == "completed"
    assert table.linear["start"] == "run-up"
    assert table.warnings == []
    with pytest.raises(Exception, match="start_frequency"):
        hbfriction.modes(system, 3.0, 3.1, harmonics=5, start_frequency=-1.0)


@pytest.mark.parametrize("table, needle", [
    ('law = "polynomial"\nterms = [[2.5, 1.0]]', "exponent 2.5"),
    ('law = "polynomial"\nterms = [[16, 1.0]]', "1..15"),
    ('law = "polynomial"', "no term"),
    ('law = "polynomial"\ncubic = 1.0\ngap = 0.1', "gap"),
    ('law = "gap"\nstiffness = 1.0\ngap = 0.1\npreload = 1.0', "preload"),
    ('law = "damper"\ncoefficient = 1.0\nexponent = 0.5', "exponent"),
])
def test_bad_force_elements_are_refused_naming_the_key(tmp_path, table, needle):
    path = tmp_path / "bad.toml"
    path.write_text(DUFFING.split("[[contact]]")[0] + "[[contact]]\ndof = 1\n" + table + "\n")
    code, _, err = run_hbf("frf", "--config", str(path), "--dry-run", check=False)
    assert code == 2
    assert needle in err


def test_polynomial_of_several_coordinates_equals_its_springs():
    # The chain ground - 1 - 2 with cubic springs k3 = 0.5 (ground - 1) and 1 (1 - 2), once as two
    # contacts and once as one polynomial of (y1, y2): (y1 - y2)^3 expanded by hand.
    structure = dict(mass=[[1.0, 0.0], [0.0, 2.0]], stiffness=[[2.0, -1.0], [-1.0, 2.0]], excitation=[1.0, 0.0],
                     damping=[[0.03, -0.01], [-0.01, 0.03]])
    springs = hbfriction.System(structure["mass"], structure["stiffness"], structure["excitation"],
                                damping=structure["damping"],
                                contacts=[hbfriction.Contact(dof=0, law="polynomial", cubic=0.5),
                                          hbfriction.Contact(dof=1, other_dof=0, law="polynomial", cubic=1.0)])
    together = hbfriction.Contact(dof=0, law="polynomial", directions=[[0.0, 1.0]],
                                  exponents=[[3, 0], [2, 1], [1, 2], [0, 3]],
                                  coefficients=[[1.5, -1.0], [-3.0, 3.0], [3.0, -3.0], [-1.0, 1.0]])
    assert together.exponents[1] == [2.0, 1.0]
    assert together.directions == [[0.0, 1.0]]
    system = hbfriction.System(structure["mass"], structure["stiffness"], structure["excitation"],
                               damping=structure["damping"], contacts=[together])
    got = hbfriction.frf(system, harmonics=10, wmin=0.42, wmax=0.55)
    want = hbfriction.frf(springs, harmonics=10, wmin=0.42, wmax=0.55)
    assert got.status == "completed" and want.status == "completed"
    # the branch's ends (the same frequencies): the same response, to the corrector's tolerance (1e-9 of the
    # force, amplified near resonance)
    for index in (0, -1):
        assert got["w"][index] == want["w"][index]
        assert abs(got["y1_max"][index] - want["y1_max"][index]) <= 1e-7 * want["y1_max"][index]
        assert abs(got["y2_max"][index] - want["y2_max"][index]) <= 1e-7 * want["y2_max"][index]
    with pytest.raises(Exception, match="coefficients"):
        together.coefficients = [[1.0, 2.0], [3.0]]
