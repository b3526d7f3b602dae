#!/usr/bin/python3
"""plot_trace.py - draws an rt-mpi --trace timeline as a picture.

  plot_trace.py TRACE.json [--stats STATS.json] -o OUT.png
                [--color auto|rows|samples] [--title TEXT]

Top: a Gantt chart, one lane per rank, one bar per work unit from its start
to its end, coloured by its first row (where in the image it is) or, when
the job split rows into sample ranges, by its sample range. Bottom: per rank,
how the render wall time was spent: busy (rendering), waiting for rank 0,
in MPI calls (comm) and the rest (idle = wall - busy - wait - comm), from --stats; without it, busy is
summed from the trace and the rest of the wall time counts as idle.

Needs matplotlib (Debian: python3-matplotlib). Prints one summary line.
"""
import argparse
import json
import sys


def load(path):
    with open(path) as f:
        doc = json.load(f)
    evs = doc["traceEvents"] if isinstance(doc, dict) else doc
    units, names = [], {}
    for e in evs:
        if e.get("ph") == "M" and e.get("name") == "process_name":
            names[int(e["pid"])] = e.get("args", {}).get("name", "rank %d" % e["pid"])
        elif e.get("ph") == "X":
            a = e.get("args", {})
            units.append({"rank": int(e["pid"]), "t0": float(e["ts"]) * 1e-6,
                          "t1": (float(e["ts"]) + float(e["dur"])) * 1e-6,
                          "y0": int(a.get("y0", 0)), "y1": int(a.get("y1", 1)),
                          "s0": int(a.get("s0", 0)), "s1": int(a.get("s1", 1))})
    return units, names


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace", help="rt-mpi --trace file")
    ap.add_argument("--stats", help="rt-mpi --stats file of the same run (busy/wait/comm/idle per rank)")
    ap.add_argument("-o", "--output", required=True, help="PNG (or any format matplotlib writes) to write")
    ap.add_argument("--color", choices=("auto", "rows", "samples"), default="auto",
                    help="colour units by first row or by sample range (auto: samples when split) [auto]")
    ap.add_argument("--title", help="title (default: from the stats or the file name)")
    ap.add_argument("--dpi", type=int, default=110)
    args = ap.parse_args(argv)

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib import cm, colors
        from matplotlib.patches import Patch
    except ImportError:
        sys.stderr.write("plot_trace: needs matplotlib (Debian: apt-get install python3-matplotlib; "
                         "then run it with /usr/bin/python3)\n")
        return 2

    units, names = load(args.trace)
    if not units:
        sys.stderr.write("plot_trace: %s has no work units (ph X events)\n" % args.trace)
        return 1
    stats = None
    if args.stats:
        with open(args.stats) as f:
            stats = json.load(f)
    nranks = max([u["rank"] for u in units] + list(names) + [len(stats["per_rank"]) - 1 if stats else 0]) + 1
    height = stats["height"] if stats else max(u["y1"] for u in units)
    samples = stats["samples"] if stats else max(u["s1"] for u in units)
    wall = stats["render_seconds"] if stats else max(u["t1"] for u in units)
    split = len({(u["s0"], u["s1"]) for u in units}) > 1
    mode = args.color if args.color != "auto" else ("samples" if split else "rows")

    ranges = sorted({(u["s0"], u["s1"]) for u in units})
    if mode == "samples" and len(ranges) <= 20:
        # a few sample ranges: one distinct colour each, labelled
        base = matplotlib.colormaps["tab10" if len(ranges) <= 10 else "tab20"] if hasattr(matplotlib, "colormaps") \
            else cm.get_cmap("tab10" if len(ranges) <= 10 else "tab20")
        cmap = colors.ListedColormap([base(i) for i in range(len(ranges))])
        norm = colors.BoundaryNorm(list(range(len(ranges) + 1)), len(ranges))
        index = {r: i for i, r in enumerate(ranges)}
        key = lambda u: index[(u["s0"], u["s1"])] + 0.5
        clabel = "sample range of the unit"
    elif mode == "samples":
        norm = colors.Normalize(0, samples)
        cmap = matplotlib.colormaps["viridis"] if hasattr(matplotlib, "colormaps") else cm.get_cmap("viridis")
        key = lambda u: (u["s0"] + u["s1"]) / 2.0
        clabel = "sample range (middle sample of the unit)"
    else:
        norm = colors.Normalize(0, height)
        cmap = matplotlib.colormaps["turbo"] if hasattr(matplotlib, "colormaps") else cm.get_cmap("turbo")
        key = lambda u: (u["y0"] + u["y1"]) / 2.0
        clabel = "image row (middle row of the unit; 0 = top)"

    # ---- per-rank numbers ----
    busy_tr = [0.0] * nranks
    count = [0] * nranks
    for u in units:
        busy_tr[u["rank"]] += u["t1"] - u["t0"]
        count[u["rank"]] += 1
    if stats:
        pr = {int(x["rank"]): x for x in stats["per_rank"]}
        # the stats' idle is wall - busy - comm, waiting included: split it
        util = [(pr[r]["busy_seconds"], pr[r]["wait_seconds"], pr[r]["comm_seconds"],
                 max(pr[r]["idle_seconds"] - pr[r]["wait_seconds"], 0.0))
                if r in pr else (0, 0, 0, wall) for r in range(nranks)]
    else:
        util = [(busy_tr[r], 0.0, 0.0, max(wall - busy_tr[r], 0.0)) for r in range(nranks)]

    lane_h = 0.42 if nranks <= 16 else max(0.12, 6.0 / nranks)
    gantt_h = max(1.6, min(9.0, 0.9 + lane_h * nranks))
    util_h = max(1.6, min(5.0, 0.9 + 0.28 * nranks))
    fig = plt.figure(figsize=(12, gantt_h + util_h + 1.0))
    gs = fig.add_gridspec(2, 2, height_ratios=[gantt_h, util_h], width_ratios=[60, 1], hspace=0.45, wspace=0.02)
    ax = fig.add_subplot(gs[0, 0])
    cax = fig.add_subplot(gs[0, 1])
    ax2 = fig.add_subplot(gs[1, 0], sharex=None)

    edge = "white" if len(units) <= 400 else "none"
    for r in range(nranks):
        mine = [u for u in units if u["rank"] == r]
        if not mine:
            continue
        ax.broken_barh([(u["t0"], u["t1"] - u["t0"]) for u in mine], (r - 0.4, 0.8),
                       facecolors=[cmap(norm(key(u))) for u in mine], edgecolor=edge, linewidth=0.4)
    ax.set_ylim(nranks - 0.5, -0.5)
    step = max(1, nranks // 32)
    ticks = list(range(0, nranks, step))
    ax.set_yticks(ticks)
    ax.set_yticklabels(["rank %d (%d)" % (r, count[r]) for r in ticks], fontsize=8 if nranks > 8 else 9)
    ax.set_xlim(0, max(wall, max(u["t1"] for u in units)) * 1.01)
    ax.set_xlabel("seconds since the render started")
    ax.set_ylabel("rank (units)")
    ax.grid(axis="x", alpha=0.3)
    title = args.title
    if not title:
        if stats:
            title = "%ux%u, %u spp: %d rank%s x %d thread%s, %d units, %.2f s render" % (
                stats["width"], stats["height"], stats["samples"], stats["ranks"], "s" if stats["ranks"] > 1 else "",
                stats["threads_per_rank"], "s" if stats["threads_per_rank"] > 1 else "", len(units),
                stats["render_seconds"])
        else:
            title = "%s: %d ranks, %d units" % (args.trace, nranks, len(units))
    ax.set_title(title, fontsize=11)
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    sm.set_array([])
    cb = fig.colorbar(sm, cax=cax)
    cb.set_label(clabel, fontsize=8)
    if mode == "samples" and len(ranges) <= 20:
        cb.set_ticks([i + 0.5 for i in range(len(ranges))])
        cb.set_ticklabels(["%d-%d" % r for r in ranges])
        cb.ax.tick_params(labelsize=8)
        cb.ax.invert_yaxis()
    if mode == "rows":
        cb.ax.invert_yaxis()

    # ---- utilisation ----
    parts = [("busy", "#2b8a3e"), ("wait", "#f08c00"), ("comm", "#1c7ed6"), ("idle", "#adb5bd")]
    left = [0.0] * nranks
    for k, (name, col) in enumerate(parts):
        vals = [util[r][k] for r in range(nranks)]
        ax2.barh(range(nranks), vals, left=left, color=col, height=0.7, label=name)
        left = [left[r] + vals[r] for r in range(nranks)]
    for r in range(nranks):
        tot = sum(util[r]) or 1.0
        if nranks <= 32:
            ax2.text(left[r], r, " %.0f%% busy" % (100.0 * util[r][0] / tot), va="center", fontsize=8)
    ax2.set_ylim(nranks - 0.5, -0.5)
    ax2.set_yticks(ticks)
    ax2.set_yticklabels(["rank %d" % r for r in ticks], fontsize=8 if nranks > 8 else 9)
    ax2.set_xlim(0, max(max(left), wall) * 1.12)
    ax2.set_xlabel("seconds of the render wall time" + ("" if stats else " (no --stats: busy from the trace)"))
    ax2.set_title("per-rank utilisation (idle = wall - busy - wait - comm)", fontsize=10, loc="left")
    ax2.legend(handles=[Patch(color=c, label=n) for n, c in parts], ncol=4, fontsize=8, loc="lower right",
               bbox_to_anchor=(1.0, 1.0), frameon=False, borderaxespad=0.2)
    ax2.grid(axis="x", alpha=0.3)
    fig.savefig(args.output, dpi=args.dpi, bbox_inches="tight")
    busy_share = sum(u[0] for u in util) / (wall * nranks) if wall > 0 else 0.0
    print("plot_trace: %d ranks, %d units, colour by %s, %.1f%% busy overall -> %s"
          % (nranks, len(units), mode, 100 * busy_share, args.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
