"""Shared helpers of the Python bindings' tests: the hbf executable (HBF_EXECUTABLE), the source
tree (HBF_SOURCE_DIR), and CSV parsing that keeps the CLI's text exactly."""
import csv
import io
import os
import subprocess

import pytest

SOURCE = os.environ.get("HBF_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HBF = os.environ.get("HBF_EXECUTABLE", os.path.join(SOURCE, "build", "hbf"))


def run_hbf(*args, check=True):
    """Runs hbf with args; returns (exit code, stdout, stderr)."""
    r = subprocess.run([HBF, *args], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError("hbf %s: exit %d\n%s" % (" ".join(args), r.returncode, r.stderr))
    return r.returncode, r.stdout, r.stderr


def read_csv(text):
    """{column: list of field texts} of a CSV text, in order."""
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    return {name: [row[j] for row in body] for j, name in enumerate(header)}, header


def format_number(x):
    """The CSV's number format: 15 significant digits, shortest (error.cpp format_number)."""
    import hbfriction
    return hbfriction._core.format_number(float(x))


def assert_table_equals_csv(table, text):
    """Every column of a Table equals the CLI's CSV: numbers to the CSV's 15 digits, counts and
    words exactly, empty fields as NaN (numbers) or "" (words)."""
    import math
    fields, header = read_csv(text)
    assert table.columns == header
    for name in header:
        column = table[name]
        assert len(column) == len(fields[name]), name
        for k, (value, cli) in enumerate(zip(column, fields[name])):
            if column.dtype.kind == "U":
                assert value == cli, (name, k)
            elif cli == "":
                assert math.isnan(value), (name, k, value)
            else:
                assert format_number(value) == cli, (name, k, value, cli)


@pytest.fixture
def source():
    return SOURCE


def exact_solver_covers():
    """'the exact solver covers a, b and c only': the laws whose stick is exact, from the registry
    of contact laws (contact_law.hpp), as the exact solver's refusal names them."""
    import hbfriction
    names = [law["name"] for law in hbfriction._core.contact_laws() if law["exact_stick"]]
    listed = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return "the exact solver covers " + listed + " only"
