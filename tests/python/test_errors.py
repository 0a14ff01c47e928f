"""Bad input raises ValueError with the library's message (TypeError for a wrong type), as hbf
reports it, and leaves nothing half done."""
import os

import numpy as np
import pytest

import hbfriction
from conftest import SOURCE, exact_solver_covers, run_hbf


def cli_error(*args):
    """hbf's message for a bad flag, without its 'hbf frf: error: --flag: ' prefix."""
    code, _, err = run_hbf(*args, check=False)
    assert code == 2
    line = err.strip().splitlines()[0]
    return line.split(": ", 3)[-1]


def test_out_of_range_parameters_carry_the_cli_message():
    with pytest.raises(ValueError) as e:
        hbfriction.absorber(mu=-1)
    assert str(e.value) == cli_error("frf", "--mu", "-1") == \
        "mu (friction coefficient) = -1 is out of range: allowed finite and > 0"
    with pytest.raises(ValueError) as e:
        hbfriction.absorber("lugre", wb=0)
    assert str(e.value) == cli_error("frf", "--law", "lugre", "--wb", "0")
    with pytest.raises(ValueError) as e:
        hbfriction.frf(hbfriction.absorber(), wmin=2, wmax=1)
    assert str(e.value) == cli_error("frf", "--wmin", "2", "--wmax", "1")
    # The library's ranges (FrfSettings::validate), which the library, Python and hbf apply alike.
    for flag, option, value in (("--tolerance", "tolerance", 0.1), ("--max-step", "max_step", 20.0),
                                ("--time-samples", "time_samples", 10), ("--modes", "modes", -1)):
        with pytest.raises(ValueError) as e:
            hbfriction.frf(hbfriction.absorber(), **{option: value})
        text = "%g" % value
        assert str(e.value) == cli_error("frf", flag, text), option
        assert str(e.value).startswith(option + " = " + text + " is out of range: allowed ")
    with pytest.raises(ValueError) as e:
        hbfriction.frf(hbfriction.absorber("lugre"), exact=True)
    assert exact_solver_covers() in str(e.value)
    assert cli_error("frf", "--law", "lugre", "--exact", "on").startswith(str(e.value).split(": ", 1)[1][:40])


@pytest.mark.parametrize("call, message", [
    (lambda: hbfriction.absorber("stiction"), "law = 'stiction' is not known: allowed coulomb"),
    (lambda: hbfriction.absorber("coulomb", wb=0.5), "wb does not apply to law coulomb"),
    (lambda: hbfriction.absorber(nu=0.5), "unknown parameter 'nu'"),
    (lambda: hbfriction.frf(hbfriction.absorber(), harmonics=500), "harmonics = 500 is out of range: allowed 1..100"),
    (lambda: hbfriction.frf(hbfriction.absorber(), harmonics=0), "harmonics = 0 is out of range"),
    (lambda: hbfriction.frf(hbfriction.absorber(), time_samples=10), "time_samples = 10 is out of range"),
    (lambda: hbfriction.frf(hbfriction.absorber(), toleranse=1e-9), "unknown option 'toleranse'"),
    (lambda: hbfriction.frf(hbfriction.absorber(), tolerance=-1), "tolerance"),
    (lambda: hbfriction.frf(hbfriction.absorber(), at=[-1.0]), "at = -1.0 is out of range"),
    (lambda: hbfriction.frf(hbfriction.absorber(), exact_threads=3), "exact_threads = 3 is out of range: allowed 0"),
    (lambda: hbfriction.frf(hbfriction.absorber(), outputs=[5]), "DOF 5 is out of range: allowed 0..1"),
    (lambda: hbfriction.frf(hbfriction.absorber(), outputs=[("x", [1.0])]), "'x' has 1 coefficients: allowed 2"),
    (lambda: hbfriction.frf(hbfriction.absorber(), stability="sideways"), "method"),
    (lambda: hbfriction.frf(hbfriction.absorber(), formulation="sparse"), "formulation = 'sparse' is not known"),
    (lambda: hbfriction.System([[1.0, 2.0], [3.0, 4.0]], [1.0, 1.0], [1.0, 0.0]), "mass matrix is not symmetric"),
    (lambda: hbfriction.System([[1.0, 0.0]], [1.0], [1.0]), "mass: a square matrix is required, got 1 x 2"),
    (lambda: hbfriction.System([1.0, np.nan], [1.0, 1.0], [1.0, 0.0]), "mass[1] = nan is not finite"),
    (lambda: hbfriction.System([1.0, 1.0], [1.0, 1.0], [1.0, 0.0, 0.0]), "excitation"),
    (lambda: hbfriction.System([1.0], [1.0], [1.0], contacts=[hbfriction.Contact(dof=3, friction_limit=1.0)]),
     "dof"),
    (lambda: hbfriction.System([1.0], [1.0], [1.0], contacts=[hbfriction.Contact(dof=0)]), "friction"),
    (lambda: hbfriction.Contact(law="stiction"), "stiction"),
    (lambda: hbfriction.Contact(friction=0.1), "unknown option 'friction'"),
    (lambda: hbfriction.load("/nonexistent/system.toml"), "path = '/nonexistent/system.toml' cannot be read"),
    (lambda: hbfriction.solve_at(hbfriction.absorber(), 1.0, contact=1), "contact = 1 is out of range: allowed 0..0"),
    (lambda: hbfriction.solve_at(hbfriction.absorber(), -1.0), "w (frequency of the solution) = -1"),
    (lambda: hbfriction.timeint(hbfriction.absorber(), []), "no frequency"),
    (lambda: hbfriction.timeint(hbfriction.absorber(), [0.0]), "w = 0 is out of range"),
    (lambda: hbfriction.timeint(hbfriction.absorber(), 1.0, max_periods=0), "max_periods = 0"),
    (lambda: hbfriction.timeint(hbfriction.absorber(), 1.0, method="euler"), "method = 'euler' is not known"),
    (lambda: hbfriction.analytic(hbfriction.load(os.path.join(SOURCE, "examples", "systems", "chain3.toml")), [1.0]),
     "the paper's absorber"),
    (lambda: hbfriction.optimize(lambda mu: hbfriction.absorber(mu=mu), 1.0, 0.5), "0 < lower < upper"),
    (lambda: hbfriction.map(lambda mu: hbfriction.absorber(mu=mu), []), "values: empty"),
    (lambda: hbfriction.map(lambda mu: hbfriction.absorber(mu=mu), [0.2], threads=-1), "threads = -1"),
])
def test_bad_input_is_a_value_error_naming_it(call, message):
    with pytest.raises(ValueError, match=None) as e:
        call()
    assert message in str(e.value)


def test_a_toml_error_names_the_file_line_and_key(tmp_path):
    path = tmp_path / "bad.toml"
    text = open(os.path.join(SOURCE, "examples", "systems", "chain3.toml")).read().replace("friction_limit = 0.3",
                                                                                         "friction_limt = 0.3")
    path.write_text(text)
    (tmp_path / "chain3_stiffness.mtx").write_text(
        open(os.path.join(SOURCE, "examples", "systems", "chain3_stiffness.mtx")).read())
    with pytest.raises(ValueError, match=r"bad.toml:\d+: .*friction_limt"):
        hbfriction.load(path)


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError, match="not an hbfriction.System"):
        hbfriction.frf("absorber")
    with pytest.raises(TypeError):
        hbfriction.frf(hbfriction.absorber(), harmonics="ten")
    with pytest.raises(TypeError):
        hbfriction.optimize(42, 0.1, 1.0)


@pytest.mark.parametrize("call, kind, message", [
    (lambda: hbfriction.frf(hbfriction.absorber(), harmonics="ten"), TypeError, "harmonics = 'ten': expected an integer"),
    (lambda: hbfriction.frf(hbfriction.absorber(), harmonics=True), TypeError, "harmonics = True: expected an integer"),
    (lambda: hbfriction.frf(hbfriction.absorber(), harmonics=10 ** 20), ValueError,
     "harmonics = 100000000000000000000 is out of range"),
    (lambda: hbfriction.frf(hbfriction.absorber(), tolerance=True), TypeError, "tolerance = True: expected a number"),
    (lambda: hbfriction.frf(hbfriction.absorber(), at="1,2"), TypeError, "at = '1,2': expected a sequence"),
    (lambda: hbfriction.frf(hbfriction.absorber(), at=[0.9, 0.9]), ValueError, "more than once"),
    (lambda: hbfriction.solve_at(hbfriction.absorber(), 1.0, harmonics=2.5), TypeError, "harmonics = 2.5"),
    (lambda: hbfriction.absorber(mu=True), TypeError, "mu = True: expected a number"),
    (lambda: hbfriction.absorber(mu="0.2"), TypeError, "mu = '0.2': expected a number"),
    (lambda: hbfriction.absorber(excitation_harmonic=True), TypeError, "excitation_harmonic = True"),
    (lambda: hbfriction.System([1.0], [1.0], [1.0], contacts=[1, 2]), TypeError, "contacts[0] = 1: expected an hbfriction.Contact"),
    (lambda: hbfriction.System([1.0], [1.0], [1.0], contacts="ab"), TypeError, "contacts: expected a list"),
    (lambda: hbfriction.System([1.0], [1.0], [1.0], excitation_harmonic=2 ** 40), ValueError,
     "excitation_harmonic = 1099511627776 is out of the range of integers"),
    (lambda: hbfriction.timeint(hbfriction.absorber(), 1.0, max_periods="many"), TypeError, "max_periods = 'many'"),
])
def test_argument_errors_name_the_argument_without_a_signature_dump(call, kind, message):
    """Issue 28: a wrong type or an out-of-range integer names the argument (never pybind11's
    'incompatible function arguments' with the signatures), and a bool is not a number."""
    with pytest.raises(kind) as e:
        call()
    assert message in str(e.value)
    assert "incompatible" not in str(e.value) and "Invoked with" not in str(e.value)


def test_exceptions_leave_no_file(tmp_path):
    b = hbfriction.frf(hbfriction.absorber("lugre"), wmin=1.0, wmax=1.05)
    with pytest.raises(ValueError):
        b.write_csv(str(tmp_path / "no" / "such" / "dir.csv"))
    assert os.listdir(tmp_path) == []
