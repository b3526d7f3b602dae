#!/usr/bin/env python3
"""file_cycles.py [SRC_DIR] - lists the cycles among the files of src/:
headers that include each other, and .c files that depend on each other
over any number of steps. a.c depends on b.c when it calls an rt_*
function defined in b.c, from its own code or from the code of a header it
includes (directly or not): a static inline function in a header runs in
every file that includes it, so its calls count there. Including b.h for
its types alone is no dependency (a header may declare the functions of
several .c files, as render.h does render.c's and adapt.c's). Prints
"cycles: none" or the files of each cycle (a set: the files that reach
each other); exit 1 when there are any. A heuristic over the text
(comments, preprocessor lines and prototypes do not count as calls), no
compiler needed."""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', 'src')
text = {}
for d, _, names in os.walk(root):
    for f in names:
        if f.endswith(('.c', '.h')):
            with open(os.path.join(d, f), encoding='utf-8') as fp:
                text[f] = re.sub(r'/\*.*?\*/|//[^\n]*', '', fp.read(), flags=re.S)
includes = {f: [h for h in re.findall(r'#include "([\w.]+)"', s) if h in text] for f, s in text.items()}


def bodies(s):
    """The text inside function bodies: a brace at file level that follows
    a ')' opens one; struct, enum and initialiser braces do not."""
    s = re.sub(r'^[ \t]*#.*(\\\n.*)*', '', s, flags=re.M)
    out, depth, keep = [], 0, False
    for i, ch in enumerate(s):
        if ch == '{':
            if depth == 0:
                keep = re.search(r'\)\s*$', s[max(0, i - 300):i]) is not None
            depth += 1
        elif ch == '}':
            depth -= 1
        elif depth and keep:
            out.append(ch)
    return ''.join(out)


def reach(f):
    """Every header f includes, directly or through other headers."""
    seen, todo = set(), list(includes[f])
    while todo:
        h = todo.pop()
        if h not in seen:
            seen.add(h)
            todo.extend(includes[h])
    return seen


def cycles(graph):
    """Strongly connected components of more than one node (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(n):
        index[n] = low[n] = len(index)
        stack.append(n)
        on.add(n)
        for m in sorted(graph.get(n, ())):
            if m not in index:
                visit(m)
                low[n] = min(low[n], low[m])
            elif m in on:
                low[n] = min(low[n], index[m])
        if low[n] == index[n]:
            comp = []
            while True:
                m = stack.pop()
                on.discard(m)
                comp.append(m)
                if m == n:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for n in sorted(graph):
        if n not in index:
            visit(n)
    return out


sources = [f for f in text if f.endswith('.c')]
defined = {}
for f in sources:
    for m in re.finditer(r'^[a-z][\w *]*[ *](rt_\w+)\([^;]*$', text[f], re.M):
        defined.setdefault(m.group(1), f)
code = {f: bodies(s) for f, s in text.items()}
deps = {}
for f in sources:
    headers = reach(f)
    d = set()
    for s in [code[f]] + [code[h] for h in headers]:
        d |= {defined[c] for c in re.findall(r'\b(rt_\w+)\(', s) if c in defined}
    d.discard(f)
    deps[f] = d

found = cycles({f: set(includes[f]) for f in text if f.endswith('.h')}) + cycles(deps)
print('cycles:', '; '.join('{' + ', '.join(c) + '}' for c in found) if found else 'none')
sys.exit(1 if found else 0)
