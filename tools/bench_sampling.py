#!/usr/bin/env python3
"""bench_sampling.py [--build DIR] [--width W] [--height H] [--ref-spp N] [-j J]
                     [--scenes a,b,c] [--configs a,b] [--rounds R] [--quick]

Time to the same error (issues 28 and 34): per scene, renders with each
sampler configuration (random = sampling version 2's sampler, sobol, sobol
+ Russian roulette = the default; with --configs also adaptive sampling at
three noise thresholds, where the sample count is the most a pixel may
take) at several sample counts, and prints samples, ray segments, wall
time, and the errors against a reference in two spaces:
- display: the image as the viewer sees it, each channel clamped to [0, 1]
  and taken to gamma 2 (sqrt), 0-255, as the PNG writer does: RMSE in
  8-bit levels. The dark, noisy parts of an image weigh here as they look.
- linear: radiance as rendered (PFM), RMSE and 8x8-block RMSE, where the
  sky's and the highlights' errors dominate.
Then, for each space, the time each configuration needs to reach the error
of the random sampler at 500 spp (the error interpolated on log-log between
the renders that bracket it), as a fraction of the random sampler's, twice:
- wall: the renders' real wall times, each the fastest of R interleaved
  rounds (every configuration and sample count renders once per round, in
  turn, so a load that comes and goes on a shared machine falls on all);
- estimate: ray segments (counted exactly) x cost per segment, the cost the
  fastest of R interleaved 64-spp renders per configuration;
- paired wall (display space): each configuration at the sample count that
  reaches the target, rendered R times back to back with the random
  sampler at 500 spp, alternating which goes first: the median ratio of
  the two wall times (and the range), the most direct measure on a
  machine whose load changes from minute to minute.

The reference is rendered once with the random sampler (cached under
BUILD/bench_sampling/) as two halves with seeds of their own: the scene is
read from a file (--dump-scene), so the seed changes only the sampling, and
the renders under test (seed 42) share no random numbers with it. The
halves also measure the reference's own noise, in each space: E|A - B|^2 / 4
is the mean square error of their mean (in display space to first order,
the display map being smooth at the noise's scale except at clamped
pixels), and it is taken off every MSE, so the RMSEs are those against the
true image. Not a test: timings depend on the machine and its load.
"""
import argparse
import json
import math
import os
import re
import struct
import subprocess
import sys
from array import array

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = [  # name, options, sample counts
    ("random", ["--sampler", "random"], [125, 250, 500, 1000]),
    ("sobol", ["--sampler", "sobol", "--no-roulette"], [32, 64, 128, 256, 500]),
    ("sobol+rr", ["--sampler", "sobol", "--roulette"], [32, 64, 128, 256, 500]),
    # opt-in (--configs): adaptive sampling
    ("adapt0.05", ["--sampler", "sobol", "--roulette", "--noise-threshold", "0.05"], [128, 256, 512, 1024]),
    ("adapt0.02", ["--sampler", "sobol", "--roulette", "--noise-threshold", "0.02"], [128, 256, 512, 1024]),
    ("adapt0.01", ["--sampler", "sobol", "--roulette", "--noise-threshold", "0.01"], [128, 256, 512, 1024, 2048]),
]
TARGET = ("random", 500)


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    m = re.match(rb"PF\s+(\d+)\s+(\d+)\s+(\S+)\s", data)
    if not m:
        sys.exit(f"bench_sampling: {path} is not a colour PFM")
    w, h, scale = int(m.group(1)), int(m.group(2)), float(m.group(3))
    px = array("f")
    px.frombytes(data[m.end():m.end() + w * h * 12])
    if (scale < 0) != (sys.byteorder == "little"):
        px.byteswap()
    return w, h, px


def run(binary, args):
    out = subprocess.run([binary] + args, check=True, capture_output=True, text=True).stdout
    wall = float(re.search(r"wall time: +([0-9.]+) s render", out).group(1))
    segs = int(re.search(r"ray segments: +(\d+)", out).group(1))
    return wall, segs


def block_means(w, h, px, b=8):
    bw, bh = w // b, h // b
    out = [0.0] * (bw * bh * 3)
    for y in range(bh * b):
        row = (y // b) * bw
        base = y * w * 3
        for x in range(bw * b):
            i, o = base + x * 3, (row + x // b) * 3
            out[o] += px[i]
            out[o + 1] += px[i + 1]
            out[o + 2] += px[i + 2]
    return [v / (b * b) for v in out]


def display(px):
    """Each channel as the viewer sees it: clamped, gamma 2, 0-255."""
    return array("d", (255.0 * math.sqrt(v if v < 1.0 else 1.0) if v > 0.0 else 0.0 for v in px))


def mse(a, b):
    return sum((x - y) * (x - y) for x, y in zip(a, b)) / len(a)


def channel_means(px):
    n = len(px) // 3
    return [sum(px[c::3]) / n for c in range(3)]


def time_to(points, target):
    """Time at which MSE reaches target, interpolated on log-log between the
    two renders that bracket it (or extrapolated from the last two, marked)."""
    pts = sorted(points)  # (time, mse)
    for (t0, m0), (t1, m1) in zip(pts, pts[1:]):
        if m0 >= target >= m1 and m0 > 0 and m1 > 0 and m0 != m1:
            f = math.log(m0 / target) / math.log(m0 / m1)
            return math.exp(math.log(t0) + f * math.log(t1 / t0)), ""
    (t0, m0), (t1, m1) = (pts[0], pts[1]) if target > pts[0][1] else (pts[-2], pts[-1])
    if m0 <= 0 or m1 <= 0 or m0 == m1:
        return float("nan"), "?"
    f = math.log(m0 / target) / math.log(m0 / m1)
    t = math.exp(min(math.log(t0) + f * math.log(t1 / t0), 700.0))
    if f < 0 or t > 4 * pts[-1][0]:  # the error all but stopped falling: not within reach
        return float("inf"), ">"
    return t, "~"


def paired_walls(binary, sfile, size, configs, name, spp, rounds):
    """Wall time of configuration name at spp (the count that reaches the
    target) over the random sampler's at 500 spp, rendered back to back,
    R times, alternating which goes first: the sorted ratios."""
    opts = {c[0]: c[1] for c in configs}
    t_name, t_spp = TARGET
    jobs = [(opts[t_name], t_spp), (opts[name], spp)]
    ratios = []
    for r in range(rounds):
        wall = {}
        for k in ((0, 1) if r % 2 == 0 else (1, 0)):
            o, n = jobs[k]
            wall[k] = run(binary, ["--scene-file", sfile, "--seed", "42", "-s", str(n), "-o",
                                   os.path.join(os.path.dirname(sfile), "paired.pfm")] + o + size)[0]
        ratios.append(wall[1] / wall[0])
    return sorted(ratios)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--width", type=int, default=300)
    ap.add_argument("--height", type=int, default=200)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("-j", "--threads", type=int, default=2)
    ap.add_argument("--scenes", default="final,materials,defocus")
    ap.add_argument("--configs", default="random,sobol,sobol+rr",
                    help="of " + ",".join(c[0] for c in CONFIGS) + " (random is always in)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="150x100, 1024-spp reference, one round")
    o = ap.parse_args()
    if o.quick:
        o.width, o.height, o.ref_spp, o.rounds = 150, 100, 1024, 1
    wanted = set(o.configs.split(",")) | {"random"}
    configs = [c for c in CONFIGS if c[0] in wanted]
    binary = os.path.join(o.build, "rt-mpi")
    cache = os.path.join(o.build, "bench_sampling")
    os.makedirs(cache, exist_ok=True)
    size = ["--width", str(o.width), "--height", str(o.height), "-j", str(o.threads), "-q", "--no-checkpoint"]
    version = subprocess.run([binary, "--version"], check=True, capture_output=True, text=True).stdout.strip()
    print(f"# {version}; {o.width}x{o.height}, -j {o.threads}, reference {o.ref_spp} spp (random sampler), "
          f"wall times and cost per ray segment: fastest of {o.rounds} interleaved rounds")
    summary = []
    for scene in o.scenes.split(","):
        sfile = os.path.join(cache, f"{scene}.json")
        subprocess.run([binary, "--scene", scene, "--seed", "42", "--dump-scene", sfile], check=True)
        halves = []
        for k, seed in enumerate((1001, 1002)):
            path = os.path.join(cache, f"ref_{scene}_{o.width}x{o.height}_{o.ref_spp}_{k}.pfm")
            if not os.path.exists(path):
                print(f"# rendering reference half {k + 1} of {scene} ({o.ref_spp // 2} spp) ...", file=sys.stderr)
                run(binary, ["--scene-file", sfile, "--sampler", "random", "--seed", str(seed), "-s",
                             str(o.ref_spp // 2), "-o", path + ".tmp.pfm"] + size)
                os.replace(path + ".tmp.pfm", path)
            halves.append(read_pfm(path)[2])
        w, h = o.width, o.height
        ref = array("f", [(a + b) * 0.5 for a, b in zip(*halves)])
        ref_d = display(ref)
        ref_mse = mse(halves[0], halves[1]) / 4
        ref_d_mse = mse(display(halves[0]), display(halves[1])) / 4
        ref_blocks = block_means(w, h, ref)
        ref_block_mse = mse(block_means(w, h, halves[0]), block_means(w, h, halves[1])) / 4
        ref_means = channel_means(ref)
        print(f"\n## {scene}: reference's own RMSE (taken off below) {math.sqrt(ref_d_mse):.3f} display, "
              f"{math.sqrt(ref_mse):.5f} linear; channel means {ref_means[0]:.4f} {ref_means[1]:.4f} {ref_means[2]:.4f}")
        # the renders, every one once per round, in turn; the fastest wall time of each
        walls, results = {}, {}
        for rnd in range(o.rounds):
            for name, opts, spps in configs:
                for spp in spps:
                    out = os.path.join(cache, f"out_{scene}_{name}_{spp}.pfm")
                    wall, segs = run(binary, ["--scene-file", sfile, "--seed", "42", "-s", str(spp), "-o", out,
                                              "--stats", out + ".json"] + opts + size)
                    walls[name, spp] = min(walls.get((name, spp), float("inf")), wall)
                    if rnd == 0:
                        with open(out + ".json") as f:
                            mean_spp = json.load(f).get("adaptive", {}).get("mean_samples_per_pixel", spp)
                        img = read_pfm(out)[2]
                        e = max(mse(img, ref) - ref_mse, 1e-30)
                        ed = max(mse(display(img), ref_d) - ref_d_mse, 1e-30)
                        eb = max(mse(block_means(w, h, img), ref_blocks) - ref_block_mse, 1e-30)
                        means = channel_means(img)
                        d = " ".join(f"{m - r:+.5f}" for m, r in zip(means, ref_means))
                        results[name, spp] = (mean_spp, segs, e, ed, eb, d)
        print(f"{'config':<10} {'spp':>5} {'mean spp':>8} {'segments':>11} {'seg/sample':>10} {'wall s':>7} "
              f"{'display':>8} {'RMSE':>8} {'8x8 RMSE':>9} {'mean - ref (r g b)':>26}")
        points = {}
        for name, _, spps in configs:
            for spp in spps:
                mean_spp, segs, e, ed, eb, d = results[name, spp]
                print(f"{name:<10} {spp:>5} {mean_spp:>8.1f} {segs:>11} {segs / (w * h * mean_spp):>10.3f} "
                      f"{walls[name, spp]:>7.3f} {math.sqrt(ed):>8.4f} {math.sqrt(e):>8.5f} {math.sqrt(eb):>9.5f} "
                      f"{d:>26}")
                points.setdefault(name, []).append((spp, segs, walls[name, spp], {"display": ed, "linear": e}))
        # cost per ray segment: the fastest of R interleaved renders of each
        cost = {name: float("inf") for name, _, _ in configs}
        for _ in range(o.rounds):
            for name, opts, _ in configs:
                wall, segs = run(binary, ["--scene-file", sfile, "--seed", "7", "-s", "64", "-o",
                                          os.path.join(cache, "cost.pfm")] + opts + size)
                cost[name] = min(cost[name], wall / segs)
        print("cost per ray segment (ns): " +
              ", ".join(f"{n} {cost[n] * 1e9:.2f} ({cost[n] / cost['random']:.3f}x)" for n in cost))
        t_name, t_spp = TARGET
        base = next(p for p in points[t_name] if p[0] == t_spp)
        for space in ("display", "linear"):
            target = base[3][space]
            print(f"to the {space} RMSE of {t_name} at {t_spp} spp ({math.sqrt(target):.5g}):")
            for name, _, _ in configs:
                pts = points[name]
                n, mark = time_to([(p[0], p[3][space]) for p in pts], target)
                t, tmark = time_to([(p[2], p[3][space]) for p in pts], target)
                s, smark = time_to([(p[1], p[3][space]) for p in pts], target)
                est = s * cost[name] / (base[1] * cost[t_name])
                paired = ""
                if space == "display" and name != t_name and not mark and n == n:
                    ratios = paired_walls(binary, sfile, size, configs, name, math.ceil(n), o.rounds)
                    paired = f"  paired wall {ratios[len(ratios) // 2]:.2f}x ({ratios[0]:.2f}-{ratios[-1]:.2f})"
                print(f"  {name:<10} {mark}{n:6.0f} spp  wall {tmark}{t / base[2]:.2f}x  "
                      f"estimate {smark}{est:.2f}x  segments {smark}{s / base[1]:.2f}x{paired}")
                summary.append((scene, space, name, t / base[2], est, s / base[1], tmark + smark, paired))
    print("\n## summary: time and ray segments to the error of random at 500 spp, relative to random")
    print(f"{'scene':<10} {'space':<8} {'config':<10} {'wall':>6} {'estimate':>9} {'segments':>9}")
    for scene, space, name, rt, re, rs, mark, paired in summary:
        print(f"{scene:<10} {space:<8} {name:<10} {rt:>5.2f}x {re:>8.2f}x {rs:>8.2f}x {mark}{paired}")


if __name__ == "__main__":
    main()
