#!/usr/bin/python3
"""test_simulate_scaling.py [RT_MPI_SERIAL] - tools/simulate_scaling.py on
cases whose answer is known by hand. The farm as built (v2): rank 0's
messages and bytes for a one-worker job, its makespan and final combination
from the per-message, per-byte and packing costs, the flush interval and
flush-mb, a row's sample ranges extending one piece, the split sending rows
again and affinity keeping them together, beats; the defaults of the farm
as built (16 units per rank, a 0.1 s flush interval; 8 units for v1);
column tiles (the farm as built): make_units' rule at its boundaries, held
pieces (a tile is never extended), every pixel's sums into rank 0 once. The old model (v1, kept to
reproduce old predictions): equal unit costs that divide evenly over
the ranks (efficiency 1), a static split with one slow block (efficiency
0.5), the request/reply round trip with prefetch 1 and 2, the poll back-off,
the cost profile's scaling to other image sizes, determinism; and, given the
serial binary, that its schedule port builds exactly the units rt-mpi hands
out (with their columns, x0/x1, when its trace has them). Prints PASS/FAIL
per check and "N passed, N failed"."""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import simulate_scaling as sim  # noqa: E402

passed = failed = 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
        print("PASS: %s" % name)
    else:
        failed += 1
        print("FAIL: %s %s" % (name, detail))


def close(a, b, tol=1e-9):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def ideal(**kw):
    """No latency, no service time, no naps: only the schedule matters."""
    d = dict(threads=1, latency=0.0, bandwidth=math.inf, service_msg=0.0, service_byte=0.0, prefetch=2,
             nap_base=0.0, nap_cap=0.0, nap_slack=0.0, probe_miss=0, farm="v1")
    d.update(kw)
    return sim.Model(**d)


def synthetic_trace(path, width, height, samples, row_cost):
    """One unit per row, all samples; row_cost(y) = seconds per pixel-sample."""
    evs = [{"name": "process_name", "ph": "M", "pid": 0, "tid": 0, "args": {"name": "rank 0"}}]
    t = 0.0
    for y in range(height):
        dur = row_cost(y) * width * samples
        evs.append({"name": "u", "cat": "unit", "ph": "X", "pid": 0, "tid": 0, "ts": t * 1e6, "dur": dur * 1e6,
                    "args": {"unit": y, "y0": y, "y1": y + 1, "s0": 0, "s1": samples}})
        t += dur
    with open(path, "w") as f:
        json.dump({"traceEvents": evs}, f)


# 1. equal costs, units divide evenly: the dynamic policies are perfect
#    (prefetch 1: a worker holds no unit beyond the one it renders)
job = sim.Job([1e-6] * 64, 10, 64, 4)  # 64 rows, 10 px, 4 spp: every row costs 40 us
for pol in ("bands", "split"):
    r = sim.simulate(job, 4, ideal(band=1, prefetch=1), pol)
    check("equal costs, 64 units on 4 ranks, %s: efficiency 1" % pol, close(r["efficiency"], 1.0),
          "(%r)" % r["efficiency"])
    check("equal costs, %s: 16 units per rank" % pol, r["per_rank_units"] == [16] * 4, str(r["per_rank_units"]))
# prefetch 2: the last unit a worker prefetched cannot go to rank 0's idle
# thread, so one worker renders 17 and rank 0 15: efficiency 16/17
r = sim.simulate(job, 4, ideal(band=1, prefetch=2), "bands")
check("prefetch 2 tail: efficiency 16/17", close(r["efficiency"], 16 / 17), "(%r)" % r["efficiency"])
check("prefetch 2 tail: rank 0 renders 15 units, one worker 17", sorted(r["per_rank_units"]) == [15, 16, 16, 17]
      and r["per_rank_units"][0] == 15, str(r["per_rank_units"]))
# sample split: 8 rows for 16 ranks -> 16 sample ranges per row, 128 equal units
job8 = sim.Job([1e-6] * 8, 10, 8, 16)
r = sim.simulate(job8, 16, ideal(prefetch=1), "split")
check("split: 8 rows x 16 sample ranges on 16 ranks: 128 units", r["units"] == 128, str(r["units"]))
check("split: efficiency 1", close(r["efficiency"], 1.0), "(%r)" % r["efficiency"])
r = sim.simulate(job8, 16, ideal(prefetch=1), "bands")
check("bands without split: 8 one-row units on 16 ranks: efficiency 0.5", close(r["efficiency"], 0.5),
      "(%r)" % r["efficiency"])
r = sim.simulate(job, 4, ideal(), "static")
check("static, equal costs, 4 blocks: efficiency 1", close(r["efficiency"], 1.0), "(%r)" % r["efficiency"])

# 2. static split with one slow block: rows 0-15 cost 3x -> 96 / (4 * 48) = 0.5
slow = sim.Job([3e-6] * 16 + [1e-6] * 48, 10, 64, 4)
r = sim.simulate(slow, 4, ideal(), "static")
check("static, one block 3x slower: efficiency 0.5", close(r["efficiency"], 0.5), "(%r)" % r["efficiency"])
r = sim.simulate(slow, 4, ideal(band=1, prefetch=1), "bands")
check("dynamic balances the slow rows: efficiency 1 (96 row costs / 4 ranks, no remainder)",
      close(r["efficiency"], 1.0), "(%r)" % r["efficiency"])
r = sim.simulate(job, 128, ideal(), "static")
check("static, 128 ranks for 64 rows: efficiency 0.5", close(r["efficiency"], 0.5), "(%r)" % r["efficiency"])

# 3. the round trip: serve-only, one worker, prefetch 1, n units of cost c:
#    makespan = a + L + n (c + 2 L + a)   (hello: L + a; then per unit: L, c, L, a)
L, a, c, n = 7e-6, 3e-6, 40e-6, 64
m = ideal(latency=L, service_msg=a, prefetch=1, serve_only=True, band=1)
r = sim.simulate(job, 2, m, "bands")
want = a + L + n * (c + 2 * L + a)
check("prefetch 1 round trip: makespan a + L + n(c + 2L + a)", close(r["makespan"], want, 1e-12),
      "(%r vs %r)" % (r["makespan"], want))
check("prefetch 1: rank 0 received n + 1 messages", r["messages"] == n + 1, str(r["messages"]))
# 4. prefetch 2 hides the round trip when c > 2L + a: makespan = 3L + 3a + n c
m = ideal(latency=L, service_msg=a, prefetch=2, serve_only=True, band=1)
r = sim.simulate(job, 2, m, "bands")
want = 3 * L + 3 * a + n * c
check("prefetch 2 hides latency: makespan 3L + 3a + n c", close(r["makespan"], want, 1e-12),
      "(%r vs %r)" % (r["makespan"], want))
# result bytes: rows * width * 24 + 32 at service_byte and bandwidth
m = ideal(latency=L, service_msg=a, service_byte=1e-9, bandwidth=1e9, prefetch=1, serve_only=True, band=1)
r = sim.simulate(job, 2, m, "bands")
s_res = a + (10 * 24 + 32) * 2e-9
want = a + L + n * (c + 2 * L + s_res)
check("result payload: service a + bytes (b + 1/B)", close(r["makespan"], want, 1e-12),
      "(%r vs %r)" % (r["makespan"], want))

# 5. the poll back-off: naps 50, 100, 200, 400, 800, 1000, 1000 ... us
m = ideal(nap_base=50e-6, nap_cap=1e-3)
check("next poll after 400 us idle: 750 us", close(m.next_poll(0.0, 400e-6), 750e-6), str(m.next_poll(0, 400e-6)))
check("next poll after 3 ms idle: 3550 us", close(m.next_poll(0.0, 3e-3), 3550e-6), str(m.next_poll(0, 3e-3)))
check("next poll of a busy loop: at once", m.next_poll(1.0, 0.5) == 1.0)
m = ideal(nap_base=50e-6, nap_cap=1e-3, probe_miss=1)
check("probe miss: seen one poll later (1550 us)", close(m.next_poll(0.0, 400e-6), 1550e-6),
      str(m.next_poll(0, 400e-6)))

# 6. cost profile: a traced unit's cost scales with width, height, samples
ev = [{"rank": 0, "ts": 0.0, "dur": 0.8, "unit": 0, "y0": 0, "y1": 2, "s0": 0, "s1": 4}]
prof = sim.cost_profile(ev, 10, 2, 2)  # 0.8 s x 2 threads over 2 rows x 4 samples x 10 px
check("cost profile: 0.02 thread-s per pixel-sample", all(close(p, 0.02) for p in prof), str(prof))
check("same job: total 1.6 thread-s", close(sim.Job(prof, 10, 2, 4).total, 1.6))
check("twice the width, height and samples: 8x the cost", close(sim.Job(prof, 20, 4, 8).total, 12.8))
uneven = sim.Job([1.0, 3.0], 1, 4, 1)  # each profile row becomes 2 rows of the same cost
check("profile mapped onto a taller image, row by row", all(close(x, y) for x, y in
                                                            zip(uneven.R, [0, 1.0, 2.0, 5.0, 8.0])), str(uneven.R))

# 7. the schedule port matches src/schedule.c's rules
us = sim.make_units(97, 10, 64)
cover = {}
for y0, y1, s0, s1, _, _ in us:
    for y in range(y0, y1):
        cover[y] = cover.get(y, 0) + (s1 - s0)
check("make_units covers every row x sample once (97 rows, 64 ranks)", cover == {y: 10 for y in range(97)})
check("make_units: band 5 never exceeds 5 rows", max(u[1] - u[0] for u in sim.make_units(97, 10, 7, band=5)) == 5)

# 8. the farm as built (v2): 32-byte reports, sums held and sent per flush.
#    Serve-only, one worker, prefetch 1, 64 one-row units of 10 pixels at
#    4 spp, 40 us each (the job above); L = 0, no naps.
def v2(**kw):
    d = dict(farm="v2", band=1, prefetch=1, serve_only=True, flush_interval=10.0, pack_byte=0.0)
    d.update(kw)
    return ideal(**d)


piece = 56 + 8 + 10 * 24  # header (7 int64 since column tiles), one unit id, a row of sums
r = sim.simulate(job, 2, v2(), "bands")
check("v2: hello + 64 reports + 1 flush + bye = 67 messages", r["messages"] == 67, str(r["messages"]))
want = 4 + 64 * 32 + 64 * piece + 32
check("v2: bytes 4 + 64 x 32 + 64 pieces x %d + 32 = %d" % (piece, want), r["bytes"] == want, str(r["bytes"]))
check("v2: one sums message, sent when rank 0 has nothing left (IDLE)", r["sums_messages"] == 1,
      str(r["sums_messages"]))
a, b, p = 3e-6, 1e-9, 2e-9
r = sim.simulate(job, 2, v2(service_msg=a, service_byte=b), "bands")
want = (a + 4 * b) + 64 * (40e-6 + a + 32 * b) + a + 64 * piece * b
check("v2: makespan (a + 4 b) + n (c + a + 32 b) + a + B b (hello, units, flush; serve-only, prefetch 1)", close(r["makespan"], want, 1e-12),
      "(%r vs %r)" % (r["makespan"], want))
check("v2: final combination a + B b", close(r["final_combine"], a + 64 * piece * b, 1e-12), str(r["final_combine"]))
check("v2: serve CPU a x messages + b x bytes", close(r["serve_cpu"], a * r["messages"] + b * r["bytes"], 1e-12))
r = sim.simulate(job, 2, v2(service_msg=a, service_byte=b, pack_byte=p), "bands")
check("v2: the worker packs its flush first: + B p", close(r["final_combine"], a + 64 * piece * (b + p), 1e-12),
      str(r["final_combine"]))
# the flush interval, 0.99 ms: flushes at its ticks (0.99 ms: 24 units done;
# 1.98 ms: 25 more), then the last 15 when rank 0 says IDLE
r = sim.simulate(job, 2, v2(flush_interval=0.99e-3), "bands")
check("v2: flush interval 0.99 ms: 3 sums messages", r["sums_messages"] == 3, str(r["sums_messages"]))
check("v2: ... and still 64 pieces in all", r["sums_bytes"] == 64 * piece, str(r["sums_bytes"]))
# flush-mb: 16 rows' worth (3840 B) -> a flush after every 16th unit, none left for IDLE
r = sim.simulate(job, 2, v2(flush_bytes=16 * 240), "bands")
check("v2: flush-mb of 16 rows: 4 sums messages", r["sums_messages"] == 4, str(r["sums_messages"]))
# a row's four sample ranges on the one worker extend one piece (4 ids):
# 8 rows < 16 units x 2 ranks -> 4 ranges a row; sums = one image, not four
r = sim.simulate(job8, 2, v2(), "split")
check("v2 split, one worker: 32 units", r["units"] == 32, str(r["units"]))
check("v2 split, one worker: consecutive ranges are one piece: 8 x (56 + 4 x 8 + 240) bytes",
      r["sums_bytes"] == 8 * (56 + 4 * 8 + 240), str(r["sums_bytes"]))
# ranges of a row on different ranks each send the row: 16 rows < 16 x 8
# ranks -> 8 ranges a row
job4 = sim.Job([1e-6] * 16, 10, 16, 64)
rs = sim.simulate(job4, 8, v2(), "split")
ra = sim.simulate(job4, 8, v2(), "affinity")
rb = sim.simulate(job4, 8, v2(), "bands")
img = 16 * 240
check("v2 split on 8 ranks: %d units, sums of at least 3 images" % rs["units"],
      rs["units"] == 128 and rs["sums_bytes"] >= 3 * img, "%d units, %d bytes" % (rs["units"], rs["sums_bytes"]))
check("v2 bands: sums of about one image", img <= rb["sums_bytes"] <= img + 16 * 72, str(rb["sums_bytes"]))
check("v2 affinity: a row's ranges mostly stay together: less than half split's bytes (%d vs %d)"
      % (ra["sums_bytes"], rs["sums_bytes"]), 2 * ra["sums_bytes"] < rs["sums_bytes"])
check("v2 affinity: same units, efficiency within 5%% of split (%.3f vs %.3f)" % (ra["efficiency"], rs["efficiency"]),
      ra["units"] == rs["units"] and ra["efficiency"] > 0.95 * rs["efficiency"])
# equal costs, rank 0 renders too: as balanced as v1
r = sim.simulate(job, 4, ideal(band=1, prefetch=1, farm="v2"), "split")
check("v2: equal costs, 64 units on 4 ranks: efficiency 1, 16 units each",
      close(r["efficiency"], 1.0) and r["per_rank_units"] == [16] * 4, "%r %r" % (r["efficiency"], r["per_rank_units"]))
# an idle worker beats every lease/4: one worker with nothing to do for 1 s
slow1 = sim.Job([1.05 / 10 / 4] + [1e-9] * 3, 10, 4, 4)  # row 0 takes 1.05 s, the rest nothing
r = sim.simulate(slow1, 2, ideal(band=1, prefetch=1, farm="v2", lease=0.4, flush_interval=10.0), "bands")
check("v2: a worker idle for 1.05 s beats 10 times (lease 0.4 s)", r["beats"] == 10, str(r["beats"]))

# 8a. the defaults follow the farm as built (src/app/setup.c, cli.c): 16
#     units per rank, a 0.1 s flush interval; the old model keeps 8
m0 = sim.Model()
check("defaults: 16 units per rank, flush interval 0.1 s, policy tiles as built",
      m0.per_rank == 16 and m0.flush_interval == 0.1 and sim.AS_BUILT == "tiles",
      "%r %r %r" % (m0.per_rank, m0.flush_interval, sim.AS_BUILT))
check("make_units default: 16 units per rank (16 rows x 64 spp on 8 ranks: 8 ranges a row, 128 units)",
      len(sim.make_units(16, 64, 8)) == 128 and len(sim.make_units(16, 64, 8, per_rank=8)) == 64)
r = sim.simulate(job4, 8, ideal(prefetch=1), "split")
check("v1 keeps its 8 units per rank: 64 units", r["units"] == 64, str(r["units"]))
r = sim.simulate(job, 2, v2(flush_interval=0.0, flush_bytes=1 << 30), "bands")
check("v2: flush interval 0 (rt-mpi: only when asked): one sums message", r["sums_messages"] == 1,
      str(r["sums_messages"]))

# 8b. column tiles (the farm as built): when rows are fewer than ranks x
#     units per rank, k = ceil(want / rows) column tiles a row if the width
#     holds k tiles of min_cols (16) columns, else k sample ranges; never both
def shape(units):
    """(tiles, sample ranges) of the first row of a one-pass schedule."""
    first = [u for u in units if u[0] == 0]
    return len({u[4:6] for u in first}), len({u[2:4] for u in first})


# 10 rows, 2 ranks x 16: k = 4; 64 columns hold 4 tiles of 16 (k == cmax), 63 hold 3
ut = sim.make_units(10, 4, 2, width=64)
check("make_units tiles: k == width // min_cols (4 == 64 // 16): 4 tiles of 16 columns, all samples",
      shape(ut) == (4, 1) and len(ut) == 40 and all(u[5] - u[4] == 16 and u[2:4] == (0, 4) for u in ut),
      "%r %d" % (shape(ut), len(ut)))
us = sim.make_units(10, 4, 2, width=63)
check("make_units tiles: k == cmax + 1 (4 > 63 // 16): 4 sample ranges of the whole width",
      shape(us) == (1, 4) and len(us) == 40 and all(u[4:6] == (0, 63) for u in us), "%r %d" % (shape(us), len(us)))
check("make_units: min_cols 32 on 64 columns (cmax 2 < 4): sample ranges",
      shape(sim.make_units(10, 4, 2, width=64, min_cols=32)) == (1, 4))
check("make_units: split_mode samples (the farm before tiles): sample ranges",
      shape(sim.make_units(10, 4, 2, width=64, split_mode="samples")) == (1, 4))
check("make_units: enough rows (32 >= 2 x 16): neither", shape(sim.make_units(32, 4, 2, width=64)) == (1, 1))
check("make_units: per_rank 8 (the farm before tiles): 4 ranks x 8 on 10 rows, 4 tiles",
      shape(sim.make_units(10, 4, 4, width=64, per_rank=8)) == (4, 1))
cover = {}
for y0, y1, s0, s1, x0, x1 in sim.make_units(13, 6, 4, width=100, passes=2):  # k = 5: tiles of 20, 2 passes
    for y in range(y0, y1):
        for x in range(x0, x1):
            cover[y, x] = cover.get((y, x), 0) + (s1 - s0)
check("make_units tiles, 2 passes: every pixel x sample once", cover == {(y, x): 6 for y in range(13)
                                                                            for x in range(100)})
pk = sim.Picker(ut, "affinity")
check("ledger groups: each tile its own group (40), sample ranges one group a band (10)",
      len(pk.groups) == 40 and len(sim.Picker(us, "affinity").groups) == 10,
      "%d %d" % (len(pk.groups), len(sim.Picker(us, "affinity").groups)))
# held pieces (held.c): a whole-width piece is extended by the next samples
# of its rows; a tile piece never is (a second tile of the same rows,
# columns and next samples seals the store); disjoint columns fit
h = sim.Held(64)
check("held: whole width, next samples: extended",
      h.add((0, 1, 0, 2, 0, 64)) == "new" and h.add((0, 1, 2, 4, 0, 64)) == "extended" and h.store[0][4:] == [0, 4, 2])
h = sim.Held(64)
check("held: a tile is not extended by its next samples: the store is sealed",
      h.add((0, 1, 0, 2, 0, 32)) == "new" and h.add((0, 1, 2, 4, 0, 32)) == "sealed" and len(h.sealed) == 1)
h = sim.Held(64)
check("held: tiles of disjoint columns of one row share a store",
      h.add((0, 1, 0, 2, 0, 32)) == "new" and h.add((0, 1, 0, 2, 32, 64)) == "new" and not h.sealed
      and h.bytes == 64 * 24)
# bytes into rank 0: 8 rows x 256 columns at 4 spp on 8 ranks (serve-only):
# k = 16 tiles of 16 columns, 128 units; every pixel's sums arrive once:
# one image + 128 pieces x (56 + 8), whatever the flushes
jt = sim.Job([1e-6] * 8, 256, 8, 4)
img = 8 * 256 * 24
want = img + 128 * (56 + 8)
for fi in (10.0, 1e-4):
    r = sim.simulate(jt, 8, v2(band=0, prefetch=2, flush_interval=fi), "tiles")
    check("v2 tiles on 8 ranks, flush interval %g: 128 units, sums = one image + 128 x 64 bytes = %d" % (fi, want),
          r["units"] == 128 and r["sums_bytes"] == want, "%d units, %d bytes" % (r["units"], r["sums_bytes"]))
ra = sim.simulate(jt, 8, v2(band=0, prefetch=2), "affinity")
check("v2 affinity (sample ranges) on the same job: more than one image (%d)" % ra["sums_bytes"],
      ra["sums_bytes"] > img + 128 * 64)
r = sim.simulate(jt, 8, ideal(prefetch=2, farm="v2", flush_interval=10.0), "tiles")
check("v2 tiles, rank 0 renders too: its tiles send nothing, the others' once",
      r["sums_bytes"] == (128 - r["per_rank_units"][0]) * (16 * 24 + 64) and r["per_rank_units"][0] > 0,
      "%d bytes, rank 0 %d units" % (r["sums_bytes"], r["per_rank_units"][0]))
# 2 passes, one worker: the second pass's tiles do not extend the first's:
# 4 rows x 128 columns, 2 ranks x 16: k = 8 tiles (== cmax), 64 units,
# sums = 2 images + 64 pieces
j2 = sim.Job([1e-6] * 4, 128, 4, 4)
r = sim.simulate(j2, 2, v2(band=0, passes=2), "tiles")
want = 2 * 4 * 128 * 24 + 64 * (56 + 8)
check("v2 tiles, 2 passes, one worker: 64 units, sums = 2 images + 64 x 64 bytes = %d" % want,
      r["units"] == 64 and r["sums_bytes"] == want, "%d units, %d bytes" % (r["units"], r["sums_bytes"]))

# 9. the command line, on a synthetic trace
with tempfile.TemporaryDirectory() as tmp:
    tr = os.path.join(tmp, "t.json")
    synthetic_trace(tr, 20, 32, 4, lambda y: 1e-6)
    out = os.path.join(tmp, "o.json")
    p = subprocess.run([sys.executable, os.path.join(HERE, "..", "..", "tools", "simulate_scaling.py"), "--trace", tr,
                        "--trace-width", "20", "--trace-threads", "1", "--threads", "1", "--ranks", "1-8",
                        "--json", out], capture_output=True, text=True)
    check("CLI runs", p.returncode == 0, p.stderr)
    if p.returncode == 0:
        res = json.load(open(out))["results"]
        check("CLI: ranks 1, 2, 4, 8", [x["ranks"] for x in res] == [1, 2, 4, 8])
        check("CLI: one rank is efficiency 1 for every policy",
              all(close(res[0][pol]["efficiency"], 1.0) for pol in ("static", "bands", "split")))
        check("CLI: efficiency never above 1",
              all(x[pol]["efficiency"] <= 1.0 + 1e-9 for x in res for pol in ("static", "bands", "split")))
    p = subprocess.run([sys.executable, os.path.join(HERE, "..", "..", "tools", "simulate_scaling.py"), "--trace", tr],
                       capture_output=True, text=True)
    check("CLI: refuses a trace without width/threads", p.returncode != 0)
    out1 = os.path.join(tmp, "v1.json")
    p = subprocess.run([sys.executable, os.path.join(HERE, "..", "..", "tools", "simulate_scaling.py"), "--trace", tr,
                        "--trace-width", "20", "--trace-threads", "1", "--threads", "1", "--ranks", "4", "--farm", "v1",
                        "--json", out1], capture_output=True, text=True)
    check("CLI: --farm v1 (the old model) runs", p.returncode == 0, p.stderr)
    if p.returncode == 0:
        d = json.load(open(out1))
        check("CLI: --farm v1 simulates static, bands, split with the v1 model",
              d["model"]["farm"] == "v1" and sorted(d["results"][0]) == ["bands", "ranks", "split", "static"],
              str(sorted(d["results"][0])))
    # 32 rows x 20 columns on 8 ranks x 16: k = 4 > 20 // 16, sample ranges;
    # --min-cols 5: 4 tiles of 5 columns a row, 128 units
    out2 = os.path.join(tmp, "tiles.json")
    p = subprocess.run([sys.executable, os.path.join(HERE, "..", "..", "tools", "simulate_scaling.py"), "--trace", tr,
                        "--trace-width", "20", "--trace-threads", "1", "--threads", "1", "--ranks", "8",
                        "--min-cols", "5", "--json", out2], capture_output=True, text=True)
    check("CLI: --min-cols 5 runs", p.returncode == 0, p.stderr)
    if p.returncode == 0:
        d = json.load(open(out2))
        x = d["results"][0]
        t = x.get("tiles", {})
        check("CLI: v2 simulates all five policies; tiles: 128 tiles of 5 columns, each worker's sent once",
              sorted(x) == ["affinity", "bands", "ranks", "split", "static", "tiles"] and d["model"]["min_cols"] == 5
              and t["units"] == 128 and t["sums_bytes"] == (128 - t["per_rank_units"][0]) * (5 * 24 + 64),
              "%s %r" % (sorted(x), [t.get(k) for k in ("units", "sums_bytes", "per_rank_units")]))
        check("CLI defaults: 16 units per rank, flush interval 0.1 s",
              d["model"]["units_per_rank"] == 16 and d["model"]["flush_interval_s"] == 0.1,
              "%r %r" % (d["model"]["units_per_rank"], d["model"]["flush_interval_s"]))

    # 10. the real schedule: units of rt-mpi-serial's trace == make_units
    if len(sys.argv) > 1:
        check("rt-mpi-serial given is executable: " + sys.argv[1], os.access(sys.argv[1], os.X_OK))
        # one rank: want 8 units; 32x5 (k = 2 == 32 // 16), 48x3 (k = 3 == cmax) and
        # 64x4 with 2 passes are cut into column tiles, 47x3 (k = 3 > 47 // 16),
        # 16x3 and 16x4 into sample ranges
        notes = []
        for w, h, s, band, passes in ((64, 40, 4, 0, 1), (32, 5, 8, 0, 1), (16, 3, 20, 0, 1), (24, 37, 2, 5, 1),
                                      (8, 300, 1, 0, 1), (16, 40, 12, 0, 3), (16, 4, 12, 0, 2), (48, 3, 4, 0, 1),
                                      (47, 3, 4, 0, 1), (64, 4, 12, 0, 2)):
            t = os.path.join(tmp, "r.json")
            cmd = [sys.argv[1], "--width", str(w), "--height", str(h), "-s", str(s), "-j", "1", "-q",
                   "--no-checkpoint", "-o", os.path.join(tmp, "r.png"), "--trace", t]
            if band:
                cmd += ["--band", str(band)]
            if passes > 1:
                cmd += ["--passes", str(passes), "--preview", os.path.join(tmp, "prev.png")]
            p = subprocess.run(cmd, capture_output=True, text=True)
            if p.returncode != 0:
                check("rt-mpi-serial %dx%d runs" % (w, h), False, p.stderr)
                continue
            evs = sim.load_trace(t)
            # units carry their columns (x0, x1) since column tiles; a trace
            # without them is from a binary before tiles: whole rows, cut
            # into sample ranges
            mode = "columns" if all(e["x1"] is not None for e in evs) else "samples"
            if mode == "samples" and not notes:
                notes.append("note: rt-mpi's trace has no x0/x1 (a binary before column tiles): compared with "
                             "the port's sample ranges (split_mode samples)")
            got = sorted((e["unit"], (e["y0"], e["y1"], e["s0"], e["s1"], e["x0"], w if e["x1"] is None else e["x1"]))
                         for e in evs)
            want = list(enumerate(sim.make_units(h, s, 1, band=band, passes=passes, width=w, split_mode=mode)))
            check("schedule port == rt-mpi units (%dx%d, %d spp, band %d, %d pass%s, %d tile%s x %d sample range%s "
                  "a band: %d units)" % ((w, h, s, band, passes, "es" if passes > 1 else "")
                                         + sum(((x, "s" if x > 1 else "") for x in
                                                shape([u for _, u in want if u[3] <= s // max(1, min(passes, s))])),
                                               ())
                                         + (len(want),)),
                  got == want, "\n  rt-mpi %s\n  port   %s" % (got[:8], want[:8]))
        for x in notes:
            print(x)
    else:
        print("note: no rt-mpi-serial given: schedule cross-check not run")

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
