#!/usr/bin/env python3
"""handout_table.py - the medians of bench_handout's JSON lines (handout.sh)
as the Markdown table of docs/notes/handout.md: one row per scheme, rank
0's mode, reports, osc and chunk/prefetch; units/s and rank-0 CPU us/unit
at each np."""
import json
import statistics
import sys


def main():
    runs = {}
    for path in sys.argv[1:]:
        with open(path) as f:
            for line in f:
                line = line.strip()
                if not line.startswith("{"):
                    continue
                d = json.loads(line)
                key = (d["scheme"], d["osc"], d["root"], d["reports"], d["chunk"], d["prefetch"])
                runs.setdefault(key, {}).setdefault(d["np"], []).append(d)
    nps = sorted({np_ for by_np in runs.values() for np_ in by_np})
    head = " | ".join(f"np {n}: units/s | {'rank-0 CPU us/unit' if i == 0 else 'us/unit'}" for i, n in enumerate(nps))
    print(f"| scheme | chunk C / prefetch P | {head} |")
    print("| --- | --- |" + " ---: | ---: |" * len(nps))
    oscs = {"-": 0, "rdma": 1, "pt2pt": 2, "ucx": 3}
    for key in sorted(runs, key=lambda k: (k[0] != "p2p", oscs.get(k[1], 9), k[2] != "poll", -k[3], k[4], k[5])):
        scheme, osc, root, reports, chunk, prefetch = key
        if scheme == "p2p":
            name = "(a) request/reply" + (" (the farm)" if (chunk, prefetch) == (1, 2) else "")
            cp = f"C={chunk} P={prefetch}"
        else:
            mode = "polls" if root == "poll" else "blocked in MPI"
            name = f"(b) counter, osc/{osc}, rank 0 {mode}, {'reports' if reports else 'no reports'}"
            cp = f"C={chunk}"
        cells = []
        for n in nps:
            rs = runs[key].get(n)
            if not rs:
                cells.append("- | -")
                continue
            ups = statistics.median(r["units_per_s"] for r in rs)
            cpu = statistics.median(r["root_cpu_us_per_unit"] for r in rs)
            cells.append(f"{ups:,.0f} | {cpu:.2f}")
        print(f"| {name} | {cp} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
