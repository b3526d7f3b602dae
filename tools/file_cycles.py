#!/usr/bin/env python3
"""file_cycles.py [SRC_DIR] - lists pairs of .c files of src/ that depend on
each other: a.c depends on b.c when it includes b.h or calls an rt_*
function defined in b.c (a definition: a line at column 0 with the name and
no ';'). Prints "two-file cycles: none" or the pairs; exit 1 when there are
any. A heuristic over the text, no compiler needed."""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', 'src')
files = {}
for d, _, names in os.walk(root):
    for f in names:
        if f.endswith(('.c', '.h')):
            files[f] = os.path.join(d, f)
text = {f: open(p, encoding='utf-8').read() for f, p in files.items() if f.endswith('.c')}
defined = {}
for f, s in text.items():
    for m in re.finditer(r'^[a-z][\w *]*[ *](rt_\w+)\([^;]*$', s, re.M):
        defined.setdefault(m.group(1), f)
deps = {}
for f, s in text.items():
    d = {h + '.c' for h in re.findall(r'#include "([\w.]+)\.h"', s) if h + '.c' in text}
    d |= {defined[c] for c in re.findall(r'\b(rt_\w+)\(', s) if c in defined}
    d.discard(f)
    deps[f] = d
pairs = sorted({tuple(sorted((a, b))) for a in deps for b in deps[a] if a in deps.get(b, ())})
print('two-file cycles:', ', '.join(' <-> '.join(p) for p in pairs) if pairs else 'none')
sys.exit(1 if pairs else 0)
