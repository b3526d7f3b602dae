#!/usr/bin/python3
"""test_simulate_scaling.py [RT_MPI_SERIAL] - tools/simulate_scaling.py on
cases whose answer is known by hand: equal unit costs that divide evenly over
the ranks (efficiency 1), a static split with one slow block (efficiency
0.5), the request/reply round trip with prefetch 1 and 2, the poll back-off,
the cost profile's scaling to other image sizes, determinism; and, given the
serial binary, that its schedule port builds exactly the units rt-mpi hands
out. Prints PASS/FAIL per check and "N passed, N failed"."""
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
             nap_base=0.0, nap_cap=0.0, nap_slack=0.0, probe_miss=0)
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
for y0, y1, s0, s1 in us:
    for y in range(y0, y1):
        cover[y] = cover.get(y, 0) + (s1 - s0)
check("make_units covers every row x sample once (97 rows, 64 ranks)", cover == {y: 10 for y in range(97)})
check("make_units: band 5 never exceeds 5 rows", max(u[1] - u[0] for u in sim.make_units(97, 10, 7, band=5)) == 5)

# 8. the command line, on a synthetic trace
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

    # 9. the real schedule: units of rt-mpi-serial's trace == make_units
    if len(sys.argv) > 1:
        check("rt-mpi-serial given is executable: " + sys.argv[1], os.access(sys.argv[1], os.X_OK))
        for w, h, s, band, passes in ((64, 40, 4, 0, 1), (32, 5, 8, 0, 1), (16, 3, 20, 0, 1), (24, 37, 2, 5, 1),
                                      (8, 300, 1, 0, 1), (16, 40, 12, 0, 3), (16, 4, 12, 0, 2)):
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
            got = sorted((e["unit"], (e["y0"], e["y1"], e["s0"], e["s1"])) for e in sim.load_trace(t))
            want = list(enumerate(sim.make_units(h, s, 1, band=band, passes=passes)))
            check("schedule port == rt-mpi units (%dx%d, %d spp, band %d, %d pass%s: %d units)"
                  % (w, h, s, band, passes, "es" if passes > 1 else "", len(want)),
                  got == want, "\n  rt-mpi %s\n  port   %s" % (got[:8], want[:8]))
    else:
        print("note: no rt-mpi-serial given: schedule cross-check not run")

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
