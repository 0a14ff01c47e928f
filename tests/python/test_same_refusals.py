"""Issue 29: Python and hbf refuse the same inputs with the same message. Every bad-input case
of the CLI suite's 'hbf frf rejects bad input' (tests/test_cli.cpp) that has a Python form runs
through both. Where the value is a range of the library (FrfSettings::validate, the preset's
parameters: check_given_preset_parameters, AbsorberParameters::validate), the message is the
library's, word for word: hbf only puts the flag in front ('--tolerance: tolerance = 1 ...').
Where the CLI has a syntax of its own the refusal is the same but the words name that syntax:
--harmonics (0 = automatic, odd, odd:H; Python's harmonics is an integer), --exact (on/off;
Python's exact is a bool: both name the other spelling to use), --at (a comma-separated text;
Python's at is a list: the value is printed as each front end reads it). The CLI-only spellings
(--exact yes, --at 0.7,x, --harmonics 1e3) have no Python form: a wrong type is a TypeError."""
import pytest

import hbfriction
from conftest import exact_solver_covers, run_hbf

A = hbfriction.absorber
F = hbfriction.frf


def cli_refusal(args):
    code, _, err = run_hbf("frf", "--out", "/dev/null", *args.split(), check=False)
    assert code == 2, (args, err)
    line = err.strip().splitlines()[0]
    prefix = "hbf frf: error: "
    assert line.startswith(prefix), line
    return line[len(prefix):]


def python_refusal(call):
    with pytest.raises(ValueError) as e:
        call()
    return str(e.value)


# (CLI arguments, the Python call): the library's message in both.
SAME_WORDS = [
    ("--law coulomb --dlft-eps 0", lambda: A("coulomb", dlft_eps=0)),
    ("--law lugre --dlft-eps 1", lambda: A("lugre", dlft_eps=1)),
    ("--law coulomb --xi 0.1", lambda: A("coulomb", xi=0.1)),
    ("--law lugre --eps 0.1", lambda: A("lugre", eps=0.1)),
    ("--law dahl --viscous 0.1", lambda: A("dahl", viscous=0.1)),
    ("--law coulomb-reg --eps 0", lambda: A("coulomb-reg", eps=0)),
    ("--max-step 0", lambda: F(A(), max_step=0.0)),
    ("--time-samples 5", lambda: F(A(), time_samples=5)),
    ("--max-amplitude 0", lambda: F(A(), max_amplitude=0.0)),
    ("--tolerance 1", lambda: F(A(), tolerance=1.0)),
    ("--wmin 2", lambda: F(A(), wmin=2.0)),
    ("--mu -1", lambda: A(mu=-1)),
    ("--law lugre --wb 0", lambda: A("lugre", wb=0)),
    ("--modes -1", lambda: F(A(), modes=-1)),
]


@pytest.mark.parametrize("args, call", SAME_WORDS, ids=[a for a, _ in SAME_WORDS])
def test_the_same_refusal_in_the_same_words(args, call):
    cli = cli_refusal(args)
    python = python_refusal(call)
    flag = args.split()[-2]
    # hbf names the flag in front of the library's message, unless the message starts with it
    assert cli in (python, flag + ": " + python), (cli, python)


# Refused by both; the words name each front end's own spelling.
SAME_REFUSAL = [
    ("--law dahl --exact on", lambda: F(A("dahl"), exact=True), exact_solver_covers()),
    ("--harmonics -1", lambda: F(A(), harmonics=-1), "harmonics = -1 is out of range: allowed "),
    ("--harmonics 101", lambda: F(A(), harmonics=101), "harmonics = 101 is out of range: allowed "),
    ("--at 0.7,-1", lambda: F(A(), at=[0.7, -1.0]), "is out of range: allowed frequencies > 0"),
]


@pytest.mark.parametrize("args, call, words", SAME_REFUSAL, ids=[a for a, _, _ in SAME_REFUSAL])
def test_the_same_refusal_in_each_front_ends_spelling(args, call, words):
    assert words in cli_refusal(args)
    assert words in python_refusal(call)
