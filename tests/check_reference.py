#!/usr/bin/env python3
"""Checks that the built documentation lists everything `hbf reference` reports.

Every command's flags and output columns, every contact law's parameters and every
system-file key must appear in the first column of its generated table on the built HTML
pages (docs/_ext/hbf_reference.py gives each table an id: hbf-flags-<command>,
hbf-columns-<command>, hbf-law-<law>, hbf-config-<table>). Prints what is missing and exits 1.

--self-test adds a dummy flag, column, law parameter and config key to the reference and
requires the check to report exactly those four: the check can fail.

Usage: check_reference.py --html DIR (--hbf HBF | --json FILE) [--self-test]
"""
import argparse
import copy
import json
import os
import subprocess
import sys
from html.parser import HTMLParser


class Tables(HTMLParser):
    """The first-column texts of every table with an id starting with 'hbf-'."""

    def __init__(self):
        super().__init__()
        self.tables = {}
        self.current = None  # the id of the open hbf table
        self.depth = 0       # nesting of tables inside it
        self.column = -1     # the cell's column in its row
        self.cell = None     # the text of an open first-column cell

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "table":
            if self.current is None and attrs.get("id", "").startswith("hbf-"):
                self.current = attrs["id"]
                self.tables[self.current] = []
                self.depth = 0
            elif self.current is not None:
                self.depth += 1
        elif self.current is not None and self.depth == 0:
            if tag == "tr":
                self.column = -1
            elif tag == "td":
                self.column += 1
                if self.column == 0:
                    self.cell = ""

    def handle_endtag(self, tag):
        if self.current is None:
            return
        if tag == "table":
            if self.depth == 0:
                self.current = None
            else:
                self.depth -= 1
        elif tag == "td" and self.cell is not None:
            self.tables[self.current].append(self.cell.strip())
            self.cell = None

    def handle_data(self, data):
        if self.cell is not None:
            self.cell += data


def read_tables(html_dir):
    tables = {}
    for page in ("reference/cli.html", "reference/contact-laws.html", "reference/system-file.html"):
        path = os.path.join(html_dir, page)
        if not os.path.isfile(path):
            raise SystemExit("check_reference.py: no page %s" % path)
        parser = Tables()
        with open(path, encoding="utf-8") as f:
            parser.feed(f.read())
        for ident, entries in parser.tables.items():
            if ident in tables:
                raise SystemExit("check_reference.py: table %s appears twice" % ident)
            tables[ident] = entries
    return tables


def config_table_id(table):
    return "hbf-config-" + ("top" if table == "" else table.replace("[]", "-tables"))


def missing(reference, tables):
    """What the reference reports and the tables do not list, as readable lines."""
    lacks = []

    def need(ident, name, what):
        if name not in tables.get(ident, ()):
            lacks.append("%s: %s (table %s)" % (what, name, ident))

    for c in reference["commands"]:
        for f in c["flags"]:
            if f["name"] not in ("-h,--help", "--help"):
                need("hbf-flags-" + c["name"], f["name"], "flag of hbf " + c["name"])
        for col in c.get("output", {}).get("columns", []):
            need("hbf-columns-" + c["name"], col["name"], "column of hbf " + c["name"])
    for law in reference["laws"]:
        if law["friction_limit"]:
            need("hbf-law-" + law["name"], "friction_limit", "parameter of law " + law["name"])
        for p in law["parameters"]:
            need("hbf-law-" + law["name"], p["key"], "parameter of law " + law["name"])
    for k in reference["config"]:
        need(config_table_id(k["table"]), k["key"], "system-file key of [%s]" % (k["table"] or "top level"))
    return lacks


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--html", required=True)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--hbf")
    source.add_argument("--json")
    parser.add_argument("--self-test", action="store_true")
    args = parser.parse_args()
    if args.hbf:
        reference = json.loads(subprocess.run([args.hbf, "reference"], check=True, capture_output=True, text=True).stdout)
    else:
        with open(args.json) as f:
            reference = json.load(f)
    tables = read_tables(args.html)
    if not args.self_test:
        lacks = missing(reference, tables)
        counted = (sum(len(c["flags"]) for c in reference["commands"]), sum(len(law["parameters"]) for law in reference["laws"]),
                   len(reference["config"]))
        if lacks:
            print("the documentation's reference misses:\n  " + "\n  ".join(lacks))
            return 1
        print("reference complete: %d flags, %d law parameters, %d system-file keys" % counted)
        return 0
    # Self-test: one dummy entry of each kind must be reported, and nothing else.
    edited = copy.deepcopy(reference)
    frf = next(c for c in edited["commands"] if c["name"] == "frf")
    frf["flags"].append({"name": "--dummy-flag", "value": "", "default": "", "required": False, "summary": "x", "details": ""})
    frf["output"]["columns"].append({"name": "dummy_column", "meaning": "x"})
    edited["laws"][0]["parameters"].append({"key": "dummy_parameter", "meaning": "x", "kind": "number", "allowed": "",
                                            "zero_means": "", "default": 0, "per_area": False})
    edited["config"].append({"table": "solver", "key": "dummy_key", "meaning": "x"})
    lacks = missing(edited, tables)
    expected = ["--dummy-flag", "dummy_column", "dummy_parameter", "dummy_key"]
    found = [e for e in expected if any(": %s (" % e in line for line in lacks)]
    if found != expected or len(lacks) != len(expected):
        print("self-test failed: expected exactly %s missing, the check reported:\n  %s" % (expected, "\n  ".join(lacks)))
        return 1
    print("self-test: the four dummy entries were reported missing:\n  " + "\n  ".join(lacks))
    return 0


if __name__ == "__main__":
    sys.exit(main())
