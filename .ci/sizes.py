#!/usr/bin/python3
"""Size limits of src/ and analysis/ (docs/layout.md): in src/, at most 5 functions over 60
lines; in analysis/ (Python), none; no file over 600 lines. C++ functions are found as
clang-format lays them out: a line at indentation 0 or 4 that opens a signature with "(" and
ends, possibly lines later, in "{"; the body runs to the matching "}". A Python function runs
from its "def" to the next line indented as deep or less. Prints the long ones; exits 1 when
a limit is exceeded. Usage: .ci/sizes.py [REPO]"""
import re
import subprocess
import sys

MAX_LONG_FUNCTIONS, LONG, MAX_FILE_LINES = 5, 60, 600
NOT_A_FUNCTION = re.compile(r'^\s*(namespace|struct|class|using|template|typedef|enum|public|'
                            r'private|protected|return|if|for|while|switch|else|do|case|'
                            r'default|static_assert|extern)\b')


def functions(path):
    """(length, first line, name) of every function body in a file."""
    lines = open(path, encoding='utf-8').read().split('\n')
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        starts = (re.match(r'^(\s{0,4})[A-Za-z]', line) and '(' in line
                  and not NOT_A_FUNCTION.match(line))
        if not starts:
            i += 1
            continue
        j, signature = i, ''
        while j < len(lines):
            signature += lines[j]
            if lines[j].rstrip().endswith(('{', ';', '}')):
                break
            j += 1
        head = signature.split('(')[0]
        if j >= len(lines) or not lines[j].rstrip().endswith('{') or ')' not in signature \
                or '=' in head:
            i += 1
            continue
        depth, k = 0, j
        for k in range(j, len(lines)):
            depth += lines[k].count('{') - lines[k].count('}')
            if depth == 0:
                break
        names = re.findall(r'([A-Za-z_][A-Za-z0-9_:]*)\s*\(', signature)
        out.append((k - i + 1, i + 1, names[0] if names else '?'))
        indent = len(line) - len(line.lstrip())
        i = k + 1 if indent == 0 else j + 1
    return out


def python_functions(path):
    """(length, first line, name) of every def in a Python file (blank lines at a body's end
    not counted)."""
    lines = open(path, encoding='utf-8').read().split('\n')
    out = []
    for i, line in enumerate(lines):
        m = re.match(r'^(\s*)def (\w+)', line)
        if not m:
            continue
        indent, last = len(m.group(1)), i
        for k in range(i + 1, len(lines)):
            if lines[k].strip() and len(lines[k]) - len(lines[k].lstrip()) <= indent:
                break
            if lines[k].strip():
                last = k
        out.append((last - i + 1, i + 1, m.group(2)))
    return out


def main():
    repo = sys.argv[1] if len(sys.argv) > 1 else '.'
    listed = lambda *patterns: subprocess.check_output(  # noqa: E731
        ['git', '-C', repo, 'ls-files', *patterns], text=True).split()
    long_functions, long_python, long_files = [], [], []
    for f in listed('src/*.cpp', 'src/*.h') + listed('analysis/*.py'):
        path = repo + '/' + f
        n = sum(1 for _ in open(path, encoding='utf-8'))
        if n > MAX_FILE_LINES:
            long_files.append((n, f))
        if f.endswith('.py'):
            long_python += [(n, f, line, name) for n, line, name in python_functions(path)
                            if n > LONG]
        else:
            long_functions += [(n, f, line, name) for n, line, name in functions(path)
                               if n > LONG]
    long_functions.sort(reverse=True)
    for n, f, line, name in long_functions + long_python:
        print(f'sizes: {name} ({f}:{line}) is {n} lines')
    for n, f in long_files:
        print(f'sizes: {f} is {n} lines, over {MAX_FILE_LINES}')
    ok = len(long_functions) <= MAX_LONG_FUNCTIONS and not long_files and not long_python
    print(f'sizes: {len(long_functions)} C++ functions over {LONG} lines (at most '
          f'{MAX_LONG_FUNCTIONS}), {len(long_python)} Python functions over {LONG} lines '
          f'(none allowed), {len(long_files)} files over {MAX_FILE_LINES} lines: '
          + ('ok' if ok else 'FAILED'))
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
