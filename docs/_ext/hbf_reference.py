"""The reference pages' generated parts: directives that render what `hbf reference` reports.

`hbf reference` (src/cli/reference_command.cpp) prints every command's flags and output
columns, the contact laws' parameters and the system-file keys as JSON; these directives turn
it into tables, so a new flag, column, law parameter or key appears in the documentation
without being written twice:

    ```{hbf-command} frf
    ```                      the command's description, flags, output and columns
    ```{hbf-law} coulomb
    ```                      the law's definition and parameter table
    ```{hbf-config} structure
    ```                      the keys of one system-file table

After reading every page, the build warns (an error under -W) for any command, law or table
that no directive rendered: the reference cannot silently miss one.
"""
import json
import os
import subprocess

from docutils import nodes
from docutils.parsers.rst import Directive
from sphinx.util import logging

logger = logging.getLogger(__name__)
_reference = None


def reference():
    """The JSON of `$HBF_EXECUTABLE reference`, read once per build."""
    global _reference
    if _reference is None:
        path = os.environ.get("HBF_REFERENCE_JSON")
        if path:  # a given reference (the completeness test's edited copy)
            with open(path) as f:
                _reference = json.load(f)
        else:
            exe = os.environ.get("HBF_EXECUTABLE")
            if not exe:
                raise RuntimeError("HBF_EXECUTABLE is not set: the hbf program to document")
            out = subprocess.run([exe, "reference"], check=True, capture_output=True, text=True).stdout
            _reference = json.loads(out)
    return _reference


def _table(ident, headers, rows, widths):
    """A docutils table of plain-text cells (no markup is parsed: descriptions keep their |, * and
    _), its first column literal; `ident` is its HTML id, by which tests/check_reference.py finds it."""
    table = nodes.table(classes=["hbf-reference", "colwidths-given"], ids=[ident])
    group = nodes.tgroup(cols=len(headers))
    table += group
    for w in widths:
        group += nodes.colspec(colwidth=w)
    head = nodes.thead()
    group += head
    row = nodes.row()
    for h in headers:
        row += nodes.entry("", nodes.paragraph(text=h))
    head += row
    body = nodes.tbody()
    group += body
    for cells in rows:
        row = nodes.row()
        for k, cell in enumerate(cells):
            para = nodes.paragraph()
            if k == 0:
                para += nodes.literal(text=cell)
            else:
                para += nodes.Text(cell)
            row += nodes.entry("", para)
        body += row
    return table


def _paragraphs(text):
    return [nodes.paragraph(text=" ".join(p.split())) for p in text.split("\n\n") if p.strip()]


def _record(env, kind, name):
    if not hasattr(env, "hbf_rendered"):
        env.hbf_rendered = set()
    env.hbf_rendered.add((kind, name))


class CommandDirective(Directive):
    required_arguments = 1

    def run(self):
        name = self.arguments[0]
        commands = {c["name"]: c for c in reference()["commands"]}
        if name not in commands:
            raise self.error("hbf-command: no command '%s' (known: %s)" % (name, ", ".join(sorted(commands))))
        c = commands[name]
        _record(self.state.document.settings.env, "command", name)
        out = [nodes.paragraph(text=c["description"])]
        flags = []
        for f in c["flags"]:
            value = f["value"] or "(flag)"
            default = f["default"] if f["default"] != "" else ("required" if f["required"] else "")
            meaning = f["details"] or f["summary"]  # the details restate the summary in full
            flags.append([f["name"], value, default, " ".join(meaning.split())])
        out.append(nodes.rubric(text="Flags"))
        out.append(_table("hbf-flags-" + name, ["flag", "value", "default", "meaning"], flags, [18, 14, 10, 58]))
        if "output" in c:
            o = c["output"]
            out.append(nodes.rubric(text="Output"))
            out.extend(_paragraphs(o["intro"]))
            out.append(_table("hbf-columns-" + name, ["column", "meaning"], [[k["name"], k["meaning"]] for k in o["columns"]], [25, 75]))
            out.extend(_paragraphs(o["outro"]))
        return out


class LawDirective(Directive):
    required_arguments = 1

    def run(self):
        name = self.arguments[0]
        laws = {law["name"]: law for law in reference()["laws"]}
        if name not in laws:
            raise self.error("hbf-law: no law '%s' (known: %s)" % (name, ", ".join(sorted(laws))))
        law = laws[name]
        _record(self.state.document.settings.env, "law", name)
        para = nodes.paragraph()
        para += nodes.Text("Definition: ")
        para += nodes.literal(text=law["definition"])
        para += nodes.Text(". Default harmonics without the exact polish: %d." % law["default_harmonics"])
        out = [para]
        rows = []
        if law["friction_limit"]:
            rows.append(["friction_limit", "slip force F_c (required)", "finite and > 0", "", ""])
        for p in law["parameters"]:
            allowed = p["allowed"] or {"pairs": "rows of two numbers", "direction": "N numbers, not all zero",
                                       "rows": "a table of numbers (TOML rows or Matrix Market)",
                                       "direction_rows": "rows of N numbers"}.get(p["kind"], "")
            if p["zero_means"]:
                allowed += "; 0 means " + p["zero_means"]
            default = "" if p["default"] is None else "%.6g" % p["default"]
            rows.append([p["key"], p["meaning"], allowed, default, "per area" if p["per_area"] else ""])
        out.append(_table("hbf-law-" + name, ["key", "meaning", "allowed", "default", "interface"], rows, [20, 38, 24, 8, 10]))
        return out


class ConfigDirective(Directive):
    required_arguments = 1

    def run(self):
        table = self.arguments[0]
        name = "" if table == "top" else table
        keys = [k for k in reference()["config"] if k["table"] == name]
        if not keys:
            tables = sorted({k["table"] or "top" for k in reference()["config"]})
            raise self.error("hbf-config: no table '%s' (known: %s)" % (table, ", ".join(tables)))
        _record(self.state.document.settings.env, "config", name)
        return [_table("hbf-config-" + (table.replace("[]", "-tables")), ["key", "meaning"], [[k["key"], k["meaning"]] for k in keys], [22, 78])]


class SystemsDirective(Directive):
    """Every system file under examples/systems (of $HBF_SOURCE_DIR), with its leading comment:
    a new example is listed without anyone writing it here."""

    def run(self):
        root = os.environ.get("HBF_SOURCE_DIR")
        if not root:
            raise self.error("hbf-systems: HBF_SOURCE_DIR is not set (the repository's root)")
        base = os.path.join(root, "examples", "systems")
        rows = []
        for folder, _, files in sorted(os.walk(base)):
            for name in sorted(files):
                if not name.endswith(".toml"):
                    continue
                path = os.path.join(folder, name)
                comment = []
                with open(path, encoding="utf-8") as f:
                    for line in f:
                        if not line.startswith("#"):
                            break
                        comment.append(line[1:].strip())
                if not comment:
                    raise self.error("hbf-systems: %s has no leading comment saying what it is" % path)
                rows.append([os.path.relpath(path, root), " ".join(comment)])
        return [_table("hbf-systems", ["file", "what it is"], rows, [30, 70])]


def _merge(app, env, docnames, other):
    if hasattr(other, "hbf_rendered"):
        if not hasattr(env, "hbf_rendered"):
            env.hbf_rendered = set()
        env.hbf_rendered |= other.hbf_rendered


def _purge(app, env, docname):
    pass  # the set only grows within one build; a fresh build (the test command's) starts empty


def _check_complete(app, env):
    """Every command, law and system-file table rendered somewhere."""
    ref = reference()
    rendered = getattr(env, "hbf_rendered", set())
    wanted = [("command", c["name"]) for c in ref["commands"]]
    wanted += [("law", law["name"]) for law in ref["laws"]]
    wanted += [("config", t) for t in sorted({k["table"] for k in ref["config"]})]
    for kind, name in wanted:
        if (kind, name) not in rendered:
            logger.warning("the reference misses %s '%s': no hbf-%s directive renders it" % (kind, name or "top", kind))


def setup(app):
    app.add_directive("hbf-command", CommandDirective)
    app.add_directive("hbf-law", LawDirective)
    app.add_directive("hbf-config", ConfigDirective)
    app.add_directive("hbf-systems", SystemsDirective)
    app.connect("env-merge-info", _merge)
    app.connect("env-purge-doc", _purge)
    app.connect("env-updated", _check_complete)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
