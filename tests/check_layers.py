#!/usr/bin/env python3
"""Checks that every include of the library points down its layers, and that none is circular.

The layers are the table in src/README.md (between the markers `<!-- layers -->` and
`<!-- /layers -->`): one row a layer, bottom up, with its folder under src/ and the public headers
(include/hbf/) it owns. A file belongs to the layer of its folder (src/<folder>/...), a public
header to the layer that lists it, python/ to the front ends (the last row). A file may include
files of its own layer or of a layer below; an include of a higher layer is an error, and so is a
cycle of includes, a source file at the top of src/, a folder or a public header the table does
not name, and a quoted include that names no file of the repository.

    tests/check_layers.py [--root DIR]      # check DIR (default: this repository); exit 1 on errors
    tests/check_layers.py --self-test       # the check fails on an injected upward include and
                                            # on an injected cycle, and passes on the tree itself
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
ROW = re.compile(r'^\|\s*(\d+)\s*\|([^|]*)\|([^|]*)\|')


def read_table(root):
    """[(layer number, [folders], [public header names])], from src/README.md."""
    path = os.path.join(root, 'src', 'README.md')
    text = open(path, encoding='utf-8').read()
    if '<!-- layers -->' not in text or '<!-- /layers -->' not in text:
        sys.exit(f'{path}: no layer table (markers <!-- layers --> and <!-- /layers -->)')
    body = text.split('<!-- layers -->', 1)[1].split('<!-- /layers -->', 1)[0]
    rows = []
    for line in body.splitlines():
        m = ROW.match(line.strip())
        if not m:
            continue
        folders = [f.strip().strip('`').rstrip('/') for f in m.group(2).split(',') if f.strip()]
        headers = [h.strip().strip('`') for h in m.group(3).split(',') if h.strip() and h.strip() != '-']
        rows.append((int(m.group(1)), folders, headers))
    numbers = [r[0] for r in rows]
    if not rows or numbers != sorted(numbers) or len(set(numbers)) != len(numbers):
        sys.exit(f'{path}: the layer table must number its rows in increasing order')
    return rows


def check(root):
    errors = []
    rows = read_table(root)
    layer_of_folder, layer_of_header, name_of_layer = {}, {}, {}
    for number, folders, headers in rows:
        name_of_layer[number] = '/'.join(folders)
        for f in folders:
            layer_of_folder[f] = number
        for h in headers:
            name = h if h.endswith('.hpp') else h + '.hpp'
            layer_of_header[name] = number
    front = max(name_of_layer)  # python/ and anything the last row names

    files = {}  # path relative to root -> layer
    src = os.path.join(root, 'src')
    for entry in sorted(os.listdir(src)):
        full = os.path.join(src, entry)
        if os.path.isfile(full):
            if entry != 'README.md':
                errors.append(f'src/{entry}: a file at the top of src/ (every source lives in a layer folder)')
            continue
        if entry not in layer_of_folder:
            errors.append(f'src/{entry}/: a folder the layer table of src/README.md does not name')
            continue
        for dirpath, _, names in os.walk(full):
            for n in names:
                if n.endswith(('.cpp', '.hpp', '.h')):
                    files[os.path.relpath(os.path.join(dirpath, n), root)] = layer_of_folder[entry]
    include_dir = os.path.join(root, 'include', 'hbf')
    present = set()
    for n in sorted(os.listdir(include_dir)):
        if not n.endswith('.hpp'):
            continue
        present.add(n)
        if n not in layer_of_header:
            errors.append(f'include/hbf/{n}: a public header the layer table of src/README.md does not name')
            continue
        files[f'include/hbf/{n}'] = layer_of_header[n]
    for n in sorted(set(layer_of_header) - present):
        errors.append(f'src/README.md: the layer table names include/hbf/{n}, which does not exist')
    python = os.path.join(root, 'python')
    if os.path.isdir(python):
        for n in sorted(os.listdir(python)):
            if n.endswith(('.cpp', '.hpp')):
                files[f'python/{n}'] = front

    graph = {}
    for path, layer in files.items():
        text = open(os.path.join(root, path), encoding='utf-8').read()
        targets = []
        for bracket, name in INCLUDE.findall(text):
            if name.startswith('hbf/'):
                target = 'include/' + name
                if target not in files:
                    # a header CMake generates from cmake/<name>.in (hbf/version.hpp): base
                    # layer, includes nothing, so any layer may include it
                    if os.path.exists(os.path.join(root, 'cmake', os.path.basename(name) + '.in')):
                        continue
                    if os.path.basename(name) not in present:
                        errors.append(f'{path}: includes {name}, which is not a header of include/hbf/')
                    continue
            elif bracket == '<':
                continue  # a system or dependency header
            else:
                here = os.path.normpath(os.path.join(os.path.dirname(path), name))
                below_src = os.path.normpath(os.path.join('src', name))
                target = here if here in files else below_src if below_src in files else None
                if target is None:
                    errors.append(f'{path}: includes "{name}", which names no file of src/ or include/')
                    continue
            targets.append(target)
            if files[target] > layer:
                errors.append(f'upward include: {path} ({name_of_layer[layer]}, layer {layer}) includes '
                              f'{name} ({name_of_layer[files[target]]}, layer {files[target]})')
        graph[path] = targets

    # Cycles: a depth-first search that reports each back edge's cycle once.
    state, stack = {}, []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for target in graph.get(node, []):
            if state.get(target) == 1:
                cycle = stack[stack.index(target):] + [target]
                errors.append('circular include: ' + ' -> '.join(cycle))
            elif target not in state:
                visit(target)
        stack.pop()
        state[node] = 2

    sys.setrecursionlimit(10000)
    for node in sorted(graph):
        if node not in state:
            visit(node)
    return errors, len(files)


def run_check(root):
    errors, count = check(root)
    for e in errors:
        print(e)
    if errors:
        print(f'{len(errors)} layer error(s) in {count} files (layers: src/README.md)')
        return 1
    print(f'every include of {count} files points down the layers of src/README.md; no cycle')
    return 0


def self_test(root):
    """The check fails on an injected upward include and on an injected cycle."""
    failures = []
    if run_check(root) != 0:
        failures.append('the tree itself does not pass')
    rows = read_table(root)
    low_folder, high_header = rows[0][1][0], None
    for _, _, headers in reversed(rows):
        if headers:
            high_header = headers[0] if headers[0].endswith('.hpp') else headers[0] + '.hpp'
            break
    with tempfile.TemporaryDirectory() as tmp:
        for part in ('src', 'include', 'python'):
            if os.path.isdir(os.path.join(root, part)):
                shutil.copytree(os.path.join(root, part), os.path.join(tmp, part))
        low = os.path.join(tmp, 'src', low_folder)
        victim = sorted(n for n in os.listdir(low) if n.endswith('.cpp'))[0]
        path = os.path.join(low, victim)
        original = open(path, encoding='utf-8').read()
        open(path, 'w', encoding='utf-8').write(f'#include "hbf/{high_header}"\n' + original)
        errors, _ = check(tmp)
        expected = f'upward include: src/{low_folder}/{victim}'
        if not any(e.startswith(expected) for e in errors):
            failures.append(f'an include of hbf/{high_header} from src/{low_folder}/{victim} was not reported')
        else:
            print(f'self-test: reported as expected: {[e for e in errors if e.startswith(expected)][0]}')
        open(path, 'w', encoding='utf-8').write(original)
        # A cycle inside one layer: two new headers that include each other.
        open(os.path.join(low, 'cycle_a.hpp'), 'w').write(f'#include "{low_folder}/cycle_b.hpp"\n')
        open(os.path.join(low, 'cycle_b.hpp'), 'w').write(f'#include "{low_folder}/cycle_a.hpp"\n')
        errors, _ = check(tmp)
        if not any(e.startswith('circular include:') and 'cycle_a.hpp' in e for e in errors):
            failures.append('a cycle of two headers was not reported')
        else:
            print('self-test: reported as expected: ' + [e for e in errors if e.startswith('circular')][0])
        os.remove(os.path.join(low, 'cycle_a.hpp'))
        os.remove(os.path.join(low, 'cycle_b.hpp'))
        # A source file at the top of src/.
        open(os.path.join(tmp, 'src', 'stray.cpp'), 'w').write('\n')
        errors, _ = check(tmp)
        if not any(e.startswith('src/stray.cpp') for e in errors):
            failures.append('a file at the top of src/ was not reported')
        else:
            print('self-test: reported as expected: src/stray.cpp at the top of src/')
    for f in failures:
        print('SELF-TEST FAILED: ' + f)
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--root', default=os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
    parser.add_argument('--self-test', action='store_true')
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    sys.exit(self_test(root) if args.self_test else run_check(root))


if __name__ == '__main__':
    main()
