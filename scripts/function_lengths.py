#!/usr/bin/env python3
"""Lengths of the C++ function bodies in the given files (clang-formatted Google style: a definition
starts at column 0 or at the class's indentation and ends with its closing brace at the same
indentation). Prints the longest; with --max N, exits 1 when a function in --under DIR is longer.

  scripts/function_lengths.py [--top 15] [--max 60 --under src/core/pipeline ...] FILES...
"""
import argparse
import re
import sys

START = re.compile(r'^(\s*)(?!if\b|for\b|while\b|switch\b|return\b|else\b|namespace\b|class\b|struct\b|enum\b)'
                   r'[\w:<>,~&*\s\[\]]*?[\w:~]+\([^;]*\)[^;]*\{\s*$')


def functions(path):
    lines = open(path, encoding='utf-8', errors='replace').read().split('\n')
    out = []
    i = 0
    while i < len(lines):
        line = lines[i]
        head = line
        # a signature may span several lines: join until the brace
        j = i
        while (not head.rstrip().endswith('{') and j + 1 < len(lines) and j - i < 4 and '(' in head
               and ';' not in head and not head.strip().startswith('//')):
            j += 1
            head += ' ' + lines[j].strip()
        m = START.match(head) if head.rstrip().endswith('{') else None
        if m and not line.strip().startswith(('//', '#', '}')) and '=' not in head.split('(')[0]:
            indent = m.group(1)
            depth = 0
            for k in range(j, len(lines)):
                depth += lines[k].count('{') - lines[k].count('}')
                if depth <= 0:
                    name = re.search(r'([\w:~]+)\(', head).group(1)
                    out.append((k - i + 1, name, path, i + 1))
                    i = k
                    break
        i += 1
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--top', type=int, default=15)
    ap.add_argument('--max', type=int, default=0)
    ap.add_argument('--under', action='append', default=[])
    ap.add_argument('files', nargs='+')
    a = ap.parse_args()
    found = sorted((f for p in a.files for f in functions(p)), reverse=True)
    for n, name, path, line in found[:a.top]:
        print(f'{n:4d}  {name}  {path}:{line}')
    if a.max:
        over = [f for f in found if f[0] > a.max and any(f[2].startswith(u) for u in a.under)]
        for n, name, path, line in over:
            print(f'too long ({n} > {a.max} lines): {name} {path}:{line}', file=sys.stderr)
        return 1 if over else 0
    return 0


if __name__ == '__main__':
    sys.exit(main())
