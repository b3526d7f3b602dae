#!/usr/bin/python3
"""simulate_scaling.py - predicts how rt-mpi scales, by replaying measured
work-unit costs on N ranks x T threads in a deterministic discrete-event
simulation of the farm (src/farm/) and its schedule (src/core/schedule.c).

  simulate_scaling.py --trace TRACE.json [--stats STATS.json]
                      [--width W --height H --samples S] [--threads T]
                      [--ranks 1,2,4,...] [--network ib|eth|shm]
                      [--service-json SERVE.json] [--json OUT.json]

Cost model. Every unit of the trace gives a cost density: its duration times
the threads of the traced run, per pixel-sample (thread-seconds). Averaged
per row, this is a cost profile over the image height; a simulated job of
another size maps its rows onto that profile (by relative height, integrating
the piecewise-constant profile) and scales by its width and sample count. A
unit of rows [y0,y1) x columns [x0,x1) x samples [s0,s1) (a column tile
costs its share of the row) on a rank with T threads takes
cost/T seconds (perfect OpenMP scaling inside a rank: the pixels of a unit
are spread over the threads in chunks of 8), times --slowdown (ranks that
share cores, as in an oversubscribed test run).

The farm as built (--farm v2, the default; src/farm/ since df446ae):
  - a worker's HELLO asks for --prefetch units; each unit done is a 32-byte
    REPORT, also its request for the next; rank 0 answers with UNITS;
  - a worker keeps the sums (held.c): a unit extends a held piece of the
    same rows and columns, covering the whole width, whose samples end where
    it starts (a column tile is never extended); one whose rows and columns
    overlap a piece without extending it seals the store (sent at once, a
    message of its own);
  - it sends what it holds, one SUMS message per store (56 + 8 ids + rows x
    columns x 24 bytes a piece; 40 + ... before column tiles, --piece-header),
    when rank 0 says IDLE (nothing left for it)
    or FLUSH (a progressive pass done), every --flush-interval, at
    --flush-mb; an idle worker beats every lease/4;
  - rank 0 handles one message at a time: --service-msg + bytes x
    (--service-byte + 1/bandwidth); a worker packs a flush at --pack-byte;
  - the makespan ends when rank 0 holds every sum; the final combination
    is the time from the last report to the last sums.
  Policy "tiles" (the farm as built: too few rows are cut into column
  tiles, so every pixel's sums reach rank 0 once; the ledger hands out by
  affinity); "affinity" (the same ledger with rows cut into sample ranges,
  the farm before tiles, rt-mpi --split samples): a rank continues the band
  whose sample ranges it was last given; "split" is the farm before
  affinity. --reports-first (not built): rank 0 reads reports before sums.
  The defaults are the farm as built (d743106): 16 units per rank
  (--units-per-rank), a 0.1 s flush interval (--flush-interval), policy
  tiles for --compare; the farm before it had 8, 1 s and sample ranges.

The farm before df446ae (--farm v1; docs/notes/scaling-v1.md), every
number an option:
  - each message takes --latency seconds from sender to receiver;
  - rank 0 handles one message at a time (one MPI thread that polls and naps):
    a result of B bytes (rows*width*3*8 + 32) occupies it for
    service_msg + B*service_byte + B/bandwidth seconds, a request (hello)
    for service_msg per unit it hands out; the reply (the next unit, or
    done) leaves when that ends;
  - an idle rank 0 or waiting worker polls with the farm's back-off: naps of
    50 us doubling to 1 ms (--nap-base, --nap-cap) plus the timer's
    overshoot (--nap-slack), and notices a message at the first poll after
    it arrived; a rendering worker takes its queued units without delay;
  - workers keep --prefetch units in flight: a hello asks for that many,
    each result is the request for one more;
  - rank 0 also renders with its own thread from the same queue, without
    messages (unless --serve-only).

Policies:
  static  each rank renders one contiguous block of rows (H*r/N ..), then
          sends it to rank 0, which receives the blocks after its own;
  bands   the farm with the schedule of src/schedule.c but no sample split
          (guided row bands, 16 rows at most, towards ranks x
          --units-per-rank units: 16 as built, 8 for v1);
  split   the farm exactly as src/schedule.c did before column tiles: when
          rows are fewer than ranks x units per rank, bands are split into
          sample ranges
          (v2: handed out in schedule order, the farm before affinity);
  affinity  v2: as split, handed out by affinity (ledger.c);
  tiles   v2, the farm as built: as affinity, but rows are cut into column
          tiles of at least --min-cols columns (sample ranges only when the
          image is too narrow).

Parallel efficiency = total cost / (N * T * makespan), the makespan ending
when rank 0 holds every result. Everything is deterministic: the same input
gives the same numbers.
"""
import argparse
import heapq
import json
import math
import sys
from collections import deque

HDR_BYTES = 4 * 8  # result header: unit, segments, start, end (int64)

# rank 0's cost per message and per byte received in the farm as built (v2),
# fitted by validate_scaling.sh on the project's 2-core box (serve CPU
# seconds of --empty-units --serve-only runs; the run of docs/SCALING.md,
# column tiles, 511d5d2); a worker's cost per byte to pack a flush
V2_MSG = 1.96e-6
V2_BYTE = 0.31e-9
V2_PACK = 0.23e-9

NETWORKS = {
    # latency (s), bandwidth (bytes/s)
    "ib": (2e-6, 12.5e9),   # InfiniBand-class: ~2 us MPI latency, 100 Gb/s
    "eth": (50e-6, 1.25e9),  # 10 Gb Ethernet with TCP: ~50 us, 10 Gb/s
    "shm": (1e-6, math.inf),  # one node, shared memory: copies are in service_byte
}


# ---- input ---------------------------------------------------------------

def load_trace(path):
    """Unit events of an rt-mpi --trace file: list of dicts."""
    with open(path) as f:
        doc = json.load(f)
    evs = doc["traceEvents"] if isinstance(doc, dict) else doc
    out = []
    for e in evs:
        if e.get("ph") != "X":
            continue
        a = e.get("args", {})
        # x0, x1: the unit's columns (traces since column tiles; before
        # them every unit was the whole width: x1 None)
        out.append({"rank": int(e["pid"]), "ts": float(e["ts"]) * 1e-6, "dur": float(e["dur"]) * 1e-6,
                    "unit": int(a.get("unit", len(out))), "y0": int(a["y0"]), "y1": int(a["y1"]),
                    "s0": int(a["s0"]), "s1": int(a["s1"]), "x0": int(a.get("x0", 0)),
                    "x1": int(a["x1"]) if "x1" in a else None})
    if not out:
        raise SystemExit("simulate_scaling: %s has no unit events (ph X)" % path)
    return out


def cost_profile(events, width, threads, height=None):
    """Cost per pixel-sample (thread-seconds) of every traced row."""
    H = height or max(e["y1"] for e in events)
    num = [0.0] * H
    den = [0.0] * H
    for e in events:
        rs = (e["y1"] - e["y0"]) * (e["s1"] - e["s0"])
        cols = width if e.get("x1") is None else e["x1"] - e.get("x0", 0)
        if rs <= 0 or cols <= 0:
            continue
        d = e["dur"] * threads / (rs * cols)
        w = e["s1"] - e["s0"]
        for y in range(e["y0"], min(e["y1"], H)):
            num[y] += d * w
            den[y] += w
    known = [num[y] / den[y] for y in range(H) if den[y] > 0]
    mean = sum(known) / len(known)
    return [num[y] / den[y] if den[y] > 0 else mean for y in range(H)]


class Job:
    """A job of W x H pixels x S samples with row costs from a profile."""

    def __init__(self, profile, width, height, samples):
        self.W, self.H, self.S = width, height, samples
        Hm = len(profile)
        cum = [0.0]
        for p in profile:
            cum.append(cum[-1] + p)

        def F(x):  # integral of the piecewise-constant profile over [0, x)
            if x >= Hm:
                return cum[Hm]
            i = int(x)
            return cum[i] + (x - i) * profile[i]

        # R[y]: cost of rows [0, y) for one sample of every pixel
        self.R = [0.0] * (height + 1)
        for y in range(height):
            # mean cost per pixel-sample over the profile rows this row covers
            row = width * (height / Hm) * (F((y + 1) * Hm / height) - F(y * Hm / height))
            self.R[y + 1] = self.R[y] + row
        self.total = self.R[height] * samples

    def cols(self, u):
        """Columns of a unit (y0, y1, s0, s1[, x0, x1]): the whole width
        unless it is a column tile."""
        if len(u) > 4 and u[5] is not None:
            return u[5] - u[4]
        return self.W

    def cost(self, u):
        """Thread-seconds of a unit; the profile is per row, so a tile costs
        its share of the row's columns."""
        c = (self.R[u[1]] - self.R[u[0]]) * (u[3] - u[2])
        w = self.cols(u)
        return c if w == self.W else c * w / self.W

    def payload(self, u):
        return (u[1] - u[0]) * self.cols(u) * 3 * 8 + HDR_BYTES


# ---- the schedule of src/schedule.c ----------------------------------------

def make_units(height, samples, ranks, band=0, max_band=16, per_rank=16, min_samples=1, split=True, passes=1,
               width=None, min_cols=16, split_mode="columns"):
    """The units rt_sched_init builds (nothing committed yet), in hand-out
    order, as tuples (y0, y1, s0, s1, x0, x1): rows [y0, y1) x samples
    [s0, s1) x columns [x0, x1). per_rank: the units wanted per rank and
    pass (src/app/setup.c gives the schedule 16 since column tiles; 8
    before, and for --farm v1). Pass by pass, in each pass guided row bands
    in row order. When rows are fewer than ranks * per_rank (k = ceil(want
    / rows) pieces a row wanted), each band is cut into k column tiles
    (split_mode "columns", the default since column tiles) if the width
    allows tiles of min_cols columns (k <= width // min_cols), else (or
    with split_mode "samples", the farm before tiles) into `splits` sample
    ranges; a pass never has both. split=False: neither (the "bands"
    policy). width None: not known, never tiles, x0 = 0 and x1 = None (the
    whole width)."""
    if split_mode not in ("columns", "samples"):
        raise ValueError("split_mode %r (columns, samples)" % (split_mode,))
    passes = max(1, min(passes, samples))
    todo = height
    mb = band if band else (max_band if max_band else 16)
    want = ranks * (per_rank if per_rank else 8)
    splits = tiles = 1
    pass_len = samples // passes
    if split and 0 < todo < want:
        k = (want + todo - 1) // todo
        cmax = max(1, (width or 0) // (min_cols if min_cols else 16))
        if split_mode == "columns" and width and k <= cmax:
            tiles = k
        else:
            kmax = max(pass_len // (min_samples if min_samples else 1), 1)
            splits = min(k, kmax)
    bands = []
    y, remaining = 0, todo
    while y < height:
        rows = mb
        if not band:
            g = remaining // (2 * want // (splits * tiles) + 1)
            rows = 1 if g < 1 else min(g, mb)
        y1 = min(y + rows, height)
        bands.append((y, y1))
        remaining -= y1 - y
        y = y1
    cols = [(width * t // tiles, width * (t + 1) // tiles) if width else (0, None) for t in range(tiles)]
    units = []
    for k in range(passes):
        p0 = samples * k // passes
        p1 = samples * (k + 1) // passes
        for y0, y1 in bands:
            for x0, x1 in cols:
                for j in range(splits):
                    s0 = p0 + (p1 - p0) * j // splits
                    s1 = p0 + (p1 - p0) * (j + 1) // splits
                    if s1 > s0:
                        units.append((y0, y1, s0, s1, x0, x1))
    return units


# ---- the model -------------------------------------------------------------

class Model:
    def __init__(self, threads=1, latency=2e-6, bandwidth=12.5e9, service_msg=20e-6, service_byte=0.0,
                 prefetch=2, nap_base=50e-6, nap_cap=1e-3, nap_slack=80e-6, slowdown=1.0, serve_only=False,
                 band=0, probe_miss=1, passes=1, worker_overhead=0.0, farm="v2", per_rank=16,
                 flush_interval=0.1, flush_bytes=64 << 20, lease=5.0, pack_byte=0.0, reports_first=False,
                 min_cols=16, piece_hdr=None):
        self.T = threads
        self.L = latency
        self.B = bandwidth
        self.a = service_msg
        self.b = service_byte
        self.prefetch = max(1, prefetch)
        self.nap_base, self.nap_cap, self.nap_slack = nap_base, nap_cap, nap_slack
        self.slowdown = slowdown
        self.serve_only = serve_only
        self.band = band
        self.probe_miss = probe_miss
        self.passes = passes
        self.worker_overhead = worker_overhead
        self.farm = farm  # "v1": results unit by unit (before df446ae); "v2": sums held, sent per flush
        self.per_rank = per_rank
        # rt-mpi --flush-interval 0: only when rank 0 asks (IDLE, FLUSH)
        self.flush_interval = flush_interval if flush_interval > 0 else math.inf
        self.flush_bytes = flush_bytes
        self.lease = lease
        self.pack_byte = pack_byte
        self.reports_first = reports_first  # not built: rank 0 takes reports before sums
        self.min_cols = min_cols  # narrowest column tile (schedule.h min_cols)
        # bytes of a piece's header in a SUMS message before its unit ids:
        # 7 int64 since column tiles (y0, y1, x0, x1, s0, s1, n), 5 before
        self.piece_hdr = PIECE_HDR if piece_hdr is None else piece_hdr

    def result_service(self, nbytes):
        return self.a + nbytes * self.b + (nbytes / self.B if self.B != math.inf else 0.0)

    def nap(self, i):
        """Length of the i-th nap of an idle loop (0-based), overshoot included."""
        return min(self.nap_base * (1 << min(i, 5)), self.nap_cap) + self.nap_slack

    def next_poll(self, since, t):
        """When a loop idle since `since` notices a message that arrived at t.
        It polls at `since`, then after naps of base, 2*base, ... capped at
        cap (each plus the timer overshoot); the message is seen at the
        first poll at or after t, or --probe-miss polls later (Open MPI's
        ob1 MPI_Iprobe returns false on the call whose progress pulls the
        message in, so it is seen one poll late)."""
        if t <= since:
            return since
        if self.nap_base <= 0 and self.nap_slack <= 0:
            return t
        p, i = since, 0
        while p < t:
            if i >= 6:  # the naps are all nap(6) from here on
                step = self.nap(6)
                k = max(math.ceil((t - p) / step - 1e-12), 1)
                p += k * step
                i += k
                break
            p += self.nap(i)
            i += 1
        for _ in range(self.probe_miss):
            p += self.nap(i)
            i += 1
        return p


def simulate_static(job, N, m):
    """Contiguous row blocks, no balancing; rank 0 then receives the blocks."""
    H = job.H
    busy = [0.0] * N
    rows = [0] * N
    arrivals = []
    for r in range(N):
        y0, y1 = H * r // N, H * (r + 1) // N
        rows[r] = y1 - y0
        if y1 <= y0:
            continue
        d = job.cost((y0, y1, 0, job.S)) / m.T * m.slowdown
        busy[r] = d
        if r > 0:
            arrivals.append((d + m.L, r, job.payload((y0, y1, 0, job.S))))
    t = busy[0]
    arrivals.sort()
    service = 0.0
    for arr, r, nbytes in arrivals:
        s = m.result_service(nbytes)
        t = max(t, arr) + s
        service += s
    makespan = max(t, max(busy))
    return {"makespan": makespan, "units": sum(1 for x in rows if x), "messages": len(arrivals),
            "per_rank_units": [1 if x else 0 for x in rows], "per_rank_busy": busy,
            "per_rank_rows": [float(x) for x in rows], "server_busy": service}


def simulate_farm(job, N, m, split=True):
    """The rt-mpi farm: discrete-event simulation of rank 0's server, its
    render thread and N-1 workers."""
    # the farm before df446ae: 8 units per rank, sample ranges
    units = make_units(job.H, job.S, N, band=m.band, split=split, passes=m.passes, width=job.W, per_rank=8,
                       split_mode="samples")
    cost = [job.cost(u) / m.T * m.slowdown for u in units]
    nbytes = [job.payload(u) for u in units]
    n = len(units)
    nxt = 0
    per_units = [0] * N
    per_busy = [0.0] * N
    per_rows = [0.0] * N
    done_units = 0
    makespan = 0.0
    messages = 0
    server_busy = 0.0

    events = []
    seq = 0

    def push(t, kind, who, data=None):
        nonlocal seq
        heapq.heappush(events, (t, seq, kind, who, data))
        seq += 1

    def record(rank, i, t_end):
        nonlocal done_units, makespan
        u = units[i]
        per_units[rank] += 1
        per_busy[rank] += cost[i]
        per_rows[rank] += (u[1] - u[0]) * (u[3] - u[2]) / job.S * job.cols(u) / job.W
        done_units += 1
        makespan = max(makespan, t_end)

    # rank 0's render thread: takes units straight from the queue
    local = N == 1 or not m.serve_only
    if local:
        if nxt < n:
            push(cost[nxt], "local_end", 0, nxt)
            nxt += 1

    # workers: queue of units, rendering flag, idle since, outstanding at rank 0
    wq = [deque() for _ in range(N)]
    w_busy = [False] * N
    w_idle = [0.0] * N
    w_wake = [False] * N
    outstanding = [0] * N

    # server state
    inbox = deque()
    s_idle_since = 0.0
    s_scheduled = False

    for r in range(1, N):
        push(m.L, "arrive", 0, ("hello", r, m.prefetch))

    def send_unit(t, r):
        nonlocal nxt
        if nxt < n:
            push(t + m.L, "unit", r, nxt)
            nxt += 1
            return True
        return False

    def worker_start(t, r):
        i = wq[r].popleft()
        w_busy[r] = True
        push(t + cost[i], "w_end", r, i)

    while events:
        t, _, kind, who, data = heapq.heappop(events)
        if kind == "local_end":
            record(0, data, t)
            if nxt < n:
                push(t + cost[nxt], "local_end", 0, nxt)
                nxt += 1
        elif kind == "arrive":  # a message reaches rank 0
            inbox.append(data)
            if not s_scheduled:
                s_scheduled = True
                push(m.next_poll(s_idle_since, t), "serve", 0)
        elif kind == "serve":  # rank 0's server polls
            if not inbox:
                s_scheduled = False
                s_idle_since = t
                continue
            msg = inbox.popleft()
            messages += 1
            if msg[0] == "hello":
                _, r, want = msg
                sent = max(0, min(want, n - nxt))
                d = m.a * max(sent, 1)
                server_busy += d
                t1 = t + d
                nxt_before = nxt
                for k in range(sent):
                    push(t1 + m.L, "unit", r, nxt_before + k)
                nxt += sent
                outstanding[r] += sent
            else:
                _, r, i = msg
                d = m.result_service(nbytes[i])
                server_busy += d
                t1 = t + d
                record(r, i, t1)
                if not send_unit(t1, r):
                    outstanding[r] -= 1
            push(t1, "serve", 0)
        elif kind == "unit":  # a unit reaches worker `who`
            r = who
            wq[r].append(data)
            if not w_busy[r] and not w_wake[r]:
                w_wake[r] = True
                push(m.next_poll(w_idle[r], t), "w_poll", r)
        elif kind == "w_poll":
            r = who
            w_wake[r] = False
            if not w_busy[r] and wq[r]:
                worker_start(t, r)
        elif kind == "w_end":
            r, i = who, data
            push(t + m.L, "arrive", 0, ("result", r, i))
            if m.worker_overhead > 0:  # message handling between units
                push(t + m.worker_overhead, "w_free", r)
                continue
            w_busy[r] = False
            if wq[r]:
                worker_start(t, r)
            else:
                w_idle[r] = t
        elif kind == "w_free":
            r = who
            w_busy[r] = False
            if wq[r]:
                worker_start(t, r)
            else:
                w_idle[r] = t
    assert done_units == n, (done_units, n)
    return {"makespan": makespan, "units": n, "messages": messages, "per_rank_units": per_units,
            "per_rank_busy": per_busy, "per_rank_rows": per_rows, "server_busy": server_busy}


# ---- the farm as rewritten (v2): sums held by the workers ------------------

PIECE_HDR = 7 * 8  # a piece in a SUMS message: y0, y1, x0, x1, s0, s1, n (int64), then n unit ids
PIECE_HDR_SAMPLES = 5 * 8  # before column tiles: y0, y1, s0, s1, n
REPORT_BYTES = 4 * 8  # a REPORT: id, segments, start, end (int64) per unit
UNIT_WORDS = 7  # a unit in a UNITS message: 7 uint32 since column tiles (5 before); rank 0's sends are not charged


def piece_bytes(cols, y0, y1, n_ids, hdr=PIECE_HDR):
    """A piece of rows [y0, y1) x `cols` columns with n_ids unit ids."""
    return hdr + 8 * n_ids + (y1 - y0) * cols * 3 * 8


class Held:
    """A worker's held sums (held.c), bookkeeping only: a store of pieces
    [y0, y1, x0, x1, s0, s1, n_ids]. A unit extends a piece of the same rows
    and columns that covers the whole width and whose samples end where the
    unit's start (a column tile never is extended); a unit whose rows and
    columns both overlap a piece it does not extend does not fit: the store
    is sealed (sent as a message of its own) and a new one begun."""

    def __init__(self, width):
        self.W = width
        self.store = []    # pieces of the current store
        self.sealed = []   # full stores waiting to be sent
        self.bytes = 0     # sums in the current store (held.c's count)

    def extended(self, u):
        for p in self.store:
            if (p[0] == u[0] and p[1] == u[1] and p[2] == 0 and p[3] == self.W and p[2] == u[4]
                    and p[3] == u[5] and p[5] == u[2]):
                return p
        return None

    def fits(self, u):
        if self.extended(u) is not None:
            return True
        return not any(p[0] < u[1] and u[0] < p[1] and p[2] < u[5] and u[4] < p[3] for p in self.store)

    def add(self, u):
        """Adds unit u = (y0, y1, s0, s1, x0, x1); returns "extended", "new"
        or "sealed" (the store was sealed first)."""
        p = self.extended(u)
        if p is not None:
            p[5] = u[3]
            p[6] += 1
            return "extended"
        how = "new"
        if not self.fits(u):
            self.sealed.append(self.store)
            self.store, self.bytes, how = [], 0, "sealed"
        self.store.append([u[0], u[1], u[4], u[5], u[2], u[3], 1])
        self.bytes += (u[1] - u[0]) * (u[5] - u[4]) * 24
        return how

    def held_bytes(self):
        return self.bytes + sum((p[1] - p[0]) * (p[3] - p[2]) * 24 for st in self.sealed for p in st)

    def take(self):
        """The stores to send (sealed ones first), each a list of pieces."""
        stores = self.sealed + ([self.store] if self.store else [])
        self.sealed, self.store, self.bytes = [], [], 0
        return stores


class Picker:
    """Which queued unit a rank gets next. "fifo": schedule order (the farm
    before affinity, policies bands and split). "affinity" (as built): a rank
    first continues the band whose sample ranges it was last given, then
    starts a band nobody has started, then takes the next range of any band
    (the tail), so a row's sample ranges mostly stay on one rank."""

    def __init__(self, units, mode):
        self.units, self.mode = units, mode
        self.n = len(units)
        self.nxt = 0
        if mode == "affinity":
            # groups (ledger.c): runs of units with the same rows and
            # columns whose samples follow on; with column tiles every tile
            # is a group of its own
            self.groups = []
            for i, u in enumerate(units):
                prev = units[self.groups[-1][-1]] if self.groups else None
                if prev is not None and prev[:2] == u[:2] and prev[4:6] == u[4:6] and prev[3] == u[2]:
                    self.groups[-1].append(i)
                else:
                    self.groups.append([i])
            self.gnext = [0] * len(self.groups)
            self.fresh = 0  # first group that may be untouched
            self.any = 0    # first group that may have ranges left
            self.cur = {}
            self.left = self.n

    def remaining(self):
        return self.n - self.nxt if self.mode == "fifo" else self.left

    def take(self, r):
        if self.mode == "fifo":
            if self.nxt >= self.n:
                return None
            self.nxt += 1
            return self.nxt - 1
        if not self.left:
            return None
        g = self.cur.get(r)
        if g is None or self.gnext[g] >= len(self.groups[g]):
            g = None
            while self.fresh < len(self.groups) and self.gnext[self.fresh] > 0:
                self.fresh += 1
            if self.fresh < len(self.groups):
                g = self.fresh
            else:
                while self.gnext[self.any] >= len(self.groups[self.any]):
                    self.any += 1
                g = self.any
        i = self.groups[g][self.gnext[g]]
        self.gnext[g] += 1
        self.cur[r] = g
        self.left -= 1
        return i


def simulate_farm2(job, N, m, split=True, affinity=False, split_mode="columns"):
    """The farm of df446ae/c08005a: discrete-event simulation of rank 0's
    server, its render thread and N-1 workers that report each unit in 32
    bytes and keep its sums (held.c), sending them combined per flush.
    split_mode: rows cut into column tiles ("columns", as built since
    column tiles) or sample ranges ("samples", before) when too few."""
    units = make_units(job.H, job.S, N, band=m.band, split=split, passes=m.passes, per_rank=m.per_rank,
                       width=job.W, min_cols=m.min_cols, split_mode=split_mode)
    n = len(units)
    cost = [job.cost(u) / m.T * m.slowdown for u in units]
    pick = Picker(units, "affinity" if affinity else "fifo")
    W = job.W
    a, b = m.a, m.b
    bw = 0.0 if m.B == math.inf else 1.0 / m.B
    beat = m.lease / 4

    per_units = [0] * N
    per_busy = [0.0] * N
    per_rows = [0.0] * N
    held_peak = [0] * N
    st = {"in": 0, "complete": None, "last_done": 0.0, "messages": 0, "bytes": 0, "server_busy": 0.0,
          "sums_msgs": 0, "sums_bytes": 0, "report_msgs": 0, "beats": 0, "flushes": 0}

    events = []
    seq = [0]

    def push(t, kind, who, data=None):
        heapq.heappush(events, (t, seq[0], kind, who, data))
        seq[0] += 1

    def account(rank, i):
        u = units[i]
        per_units[rank] += 1
        per_busy[rank] += cost[i]
        per_rows[rank] += (u[1] - u[0]) * (u[3] - u[2]) / job.S * (u[5] - u[4]) / W

    # rank 0's render thread: takes from the same queue, its sums go in at once
    if N == 1 or not m.serve_only:
        i = pick.take(0)
        if i is not None:
            push(cost[i], "local_end", 0, i)

    # workers
    wq = [deque() for _ in range(N)]
    w_busy = [False] * N
    w_idle = [0.0] * N
    w_wake = [False] * N
    held = [Held(W) for _ in range(N)]  # sums held (held.c)
    w_want = [False] * N                # rank 0 asked (IDLE, FLUSH)
    w_last_flush = [0.0] * N
    w_last_sent = [0.0] * N
    w_finished = [False] * N
    w_unreported = [0] * N

    # rank 0's book
    credit = [0] * N
    assigned = [0] * N
    held_units = [0] * N
    idle_sent = [False] * N
    pass_of = [0] * n
    if m.passes > 1:
        ends = [job.S * (k + 1) // max(1, min(m.passes, job.S)) for k in range(max(1, min(m.passes, job.S)))]
        for i, u in enumerate(units):
            k = 0
            while u[3] > ends[k]:
                k += 1
            pass_of[i] = k
    npasses = max(pass_of) + 1 if n else 1
    pass_left = [0] * npasses
    for k in pass_of:
        pass_left[k] += 1
    pass_asked = [0]
    inbox = deque()
    sums_box = deque() if m.reports_first else inbox
    s_idle_since = [0.0]
    s_scheduled = [False]

    for r in range(1, N):
        push(m.L, "arrive", 0, ("hello", r, 4))
        push(beat, "w_beat", r)
        if m.flush_interval != math.inf:
            # worker.c: flushes staggered over the interval by rank, so
            # that they do not all arrive at once
            w_last_flush[r] = -m.flush_interval * (r - 1) / max(1, N - 1)
            push(w_last_flush[r] + m.flush_interval, "w_tick", r)

    def sums_in(t, k):
        st["in"] += k
        if st["in"] == n and st["complete"] is None:
            st["complete"] = t

    def serve_peer(t, r):
        sent = []
        while credit[r] > 0:
            i = pick.take(r)
            if i is None:
                break
            sent.append(i)
            credit[r] -= 1
        if sent:
            idle_sent[r] = False
            assigned[r] += len(sent)
            push(t + m.L, "units", r, sent)
        elif assigned[r] == 0 and not idle_sent[r]:
            idle_sent[r] = True
            push(t + m.L, "ask", r)

    def flush(t, r):
        """Sends the sealed stores, then the current one: a message each."""
        w_want[r] = False
        w_last_flush[r] = t
        stores = held[r].take()
        if stores:
            st["flushes"] += 1
        for s in stores:
            nbytes = sum(piece_bytes(p[3] - p[2], p[0], p[1], p[6], m.piece_hdr) for p in s)
            nids = sum(p[6] for p in s)
            t += nbytes * m.pack_byte
            push(t + m.L, "arrive", 0, ("sums", r, nbytes, nids))
        w_last_sent[r] = t

    def worker_start(t, r):
        i = wq[r].popleft()
        w_busy[r] = True
        push(t + cost[i], "w_end", r, i)

    def worker_idle(t, r):
        w_busy[r] = False
        if wq[r]:
            worker_start(t, r)
        else:
            w_idle[r] = t

    def wake(t, r):
        """A message reached worker r: seen at once while it renders, at its
        next poll while it naps."""
        if w_busy[r]:
            return t
        if not w_wake[r]:
            w_wake[r] = True
            push(m.next_poll(w_idle[r], t), "w_poll", r)
        return None

    while events:
        t, _, kind, who, data = heapq.heappop(events)
        if kind == "local_end":
            account(0, data)
            sums_in(t, 1)
            k = pass_of[data]
            pass_left[k] -= 1
            i = pick.take(0)
            if i is not None:
                push(t + cost[i], "local_end", 0, i)
        elif kind == "arrive":
            (sums_box if data[0] == "sums" else inbox).append(data)
            if not s_scheduled[0]:
                s_scheduled[0] = True
                push(m.next_poll(s_idle_since[0], t), "serve", 0)
        elif kind == "serve":
            if not inbox and not sums_box:
                s_scheduled[0] = False
                s_idle_since[0] = t
                continue
            msg = inbox.popleft() if inbox else sums_box.popleft()
            typ, r = msg[0], msg[1]
            st["messages"] += 1
            if typ == "hello":
                d = a + msg[2] * b
                st["bytes"] += msg[2]
                t1 = t + d
                credit[r] = m.prefetch
                serve_peer(t1, r)
            elif typ == "report":
                i = msg[2]
                d = a + REPORT_BYTES * (b + bw)
                st["bytes"] += REPORT_BYTES
                st["report_msgs"] += 1
                t1 = t + d
                account(r, i)
                assigned[r] -= 1
                held_units[r] += 1
                pass_left[pass_of[i]] -= 1
                st["last_done"] = t1
                credit[r] += 1
                serve_peer(t1, r)
            elif typ == "sums":
                nbytes, nids = msg[2], msg[3]
                d = a + nbytes * (b + bw)
                st["bytes"] += nbytes
                st["sums_msgs"] += 1
                st["sums_bytes"] += nbytes
                t1 = t + d
                held_units[r] -= nids
                sums_in(t1, nids)
            else:  # beat
                d = a
                st["beats"] += 1
                t1 = t + d
            st["server_busy"] += d
            # a progressive pass is done: ask every holder for its sums
            while pass_asked[0] + 1 < npasses and pass_left[pass_asked[0]] == 0:
                pass_asked[0] += 1
                for q in range(1, N):
                    if held_units[q] > 0:
                        push(t1 + m.L, "ask", q)
            push(t1, "serve", 0)
        elif kind == "units":
            r = who
            wq[r].extend(data)
            if not w_busy[r] and not w_wake[r]:
                w_wake[r] = True
                push(m.next_poll(w_idle[r], t), "w_poll", r)
        elif kind == "ask":  # IDLE or FLUSH reached worker r
            r = who
            w_want[r] = True
            t0 = wake(t, r)
            if t0 is not None:
                flush(t0, r)
        elif kind == "w_poll":
            r = who
            w_wake[r] = False
            if w_want[r]:
                flush(t, r)
            if not w_busy[r] and wq[r]:
                worker_start(t, r)
        elif kind == "w_end":
            r, i = who, data
            h = held[r]
            h.add(units[i])  # a unit that does not fit seals the store: sent at once
            held_peak[r] = max(held_peak[r], h.held_bytes())
            push(t + m.L, "arrive", 0, ("report", r, i))
            w_last_sent[r] = t
            if (w_want[r] or h.sealed or t - w_last_flush[r] >= m.flush_interval
                    or h.held_bytes() >= m.flush_bytes):
                flush(t, r)
            if m.worker_overhead > 0:
                push(t + m.worker_overhead, "w_free", r)
            else:
                worker_idle(t, r)
        elif kind == "w_free":
            worker_idle(t, who)
        elif kind == "w_tick":  # the flush interval, checked at a poll
            r = who
            if st["complete"] is None:
                if t - w_last_flush[r] >= m.flush_interval - 1e-12 and (held[r].store or held[r].sealed):
                    t0 = t if w_busy[r] else m.next_poll(w_idle[r], t)
                    flush(t0, r)
                push(max(t, w_last_flush[r]) + m.flush_interval, "w_tick", r)
        elif kind == "w_beat":  # a quarter lease without a word: a beat
            r = who
            if st["complete"] is None:
                if t - w_last_sent[r] >= beat - 1e-12:
                    push(t + m.L, "arrive", 0, ("beat", r))
                    w_last_sent[r] = t
                push(w_last_sent[r] + beat, "w_beat", r)
        # the end: rank 0 holds every sum
        if st["complete"] is not None and not inbox and not sums_box:
            break
    assert st["in"] == n, (st["in"], n)
    makespan = st["complete"]
    # after the end: FINISH, then a BYE (4 doubles) from every worker
    msgs = st["messages"] + (N - 1)
    nbytes = st["bytes"] + 32 * (N - 1)
    return {"makespan": makespan, "units": n, "messages": msgs, "bytes": nbytes,
            "sums_messages": st["sums_msgs"], "sums_bytes": st["sums_bytes"], "reports": st["report_msgs"],
            "beats": st["beats"], "flushes": st["flushes"],
            "serve_cpu": a * msgs + b * nbytes,
            "final_combine": (makespan - st["last_done"]) if N > 1 and st["last_done"] > 0 else 0.0,
            "held_peak_mb": [x / 2 ** 20 for x in held_peak],
            "per_rank_units": per_units, "per_rank_busy": per_busy, "per_rank_rows": per_rows,
            "server_busy": st["server_busy"]}


POLICIES = ("static", "bands", "split", "affinity", "tiles")
V2_ONLY = ("affinity", "tiles")
AS_BUILT = "tiles"  # the farm as built: affinity ledger, rows cut into column tiles


def simulate(job, N, m, policy, setup=0.0, startup=0.0, write=0.0):
    """One policy on N ranks. Efficiency = total cost / (N * T * (setup +
    makespan)): the render phase from the scene broadcast (setup: broadcast
    and BVH build) to rank 0 holding every sum; efficiency_job also counts
    start-up (MPI) and the image write."""
    if policy == "static":
        res = simulate_static(job, N, m)
    elif m.farm == "v1":
        if policy in V2_ONLY:
            raise ValueError("policy %s is a v2 policy" % policy)
        res = simulate_farm(job, N, m, split=policy == "split")
    elif policy in ("bands", "split", "affinity", "tiles"):
        res = simulate_farm2(job, N, m, split=policy != "bands", affinity=policy in ("affinity", "tiles"),
                             split_mode="columns" if policy == "tiles" else "samples")
    else:
        raise ValueError(policy)
    ideal = job.total / m.T * m.slowdown
    res["efficiency"] = ideal / (N * (setup + res["makespan"])) if res["makespan"] > 0 else 1.0
    res["efficiency_job"] = ideal / (N * (startup + setup + res["makespan"] + write)) if res["makespan"] > 0 else 1.0
    res.setdefault("final_combine", 0.0)
    res.setdefault("sums_bytes", 0)
    res["server_util"] = res["server_busy"] / res["makespan"] if res["makespan"] > 0 else 0.0
    res["units_per_s"] = res["units"] / res["makespan"] if res["makespan"] > 0 else 0.0
    # rank 0's service demand against the ideal makespan: >= 1 means rank 0
    # alone takes longer than the job would on N * T perfectly used threads
    res["server_load"] = res["server_busy"] * N / ideal if ideal > 0 else 0.0
    return res


# ---- command line ----------------------------------------------------------

def parse_ranks(s):
    out = []
    for part in s.split(","):
        part = part.strip()
        if "-" in part:  # 1-4096: powers of two
            lo, hi = (int(x) for x in part.split("-"))
            v = lo
            while v <= hi:
                out.append(v)
                v *= 2
        elif part:
            out.append(int(part))
    if not out or min(out) < 1:
        raise argparse.ArgumentTypeError("ranks must be positive")
    return out


def compare(job, m, args):
    """Prediction (policy tiles, the farm as built; split with --farm v1)
    for the rank count of
    the measured runs (repeats of one configuration), next to what they
    measured: per rank units, busy share and rows (mean over the runs, with
    the range), rank 0's message count and the load imbalance."""
    runs = []
    for path in args.compare:
        with open(path) as f:
            runs.append(json.load(f))
    N = int(runs[0]["ranks"])
    if any(int(x["ranks"]) != N for x in runs):
        raise SystemExit("simulate_scaling: --compare runs differ in rank count")
    v2 = m.farm == "v2"
    res = simulate(job, N, m, (args.compare_policy or AS_BUILT) if v2 else "split")
    pu, pb, prow = res["per_rank_units"], res["per_rank_busy"], res["per_rank_rows"]
    spb = sum(pb) or 1.0

    def per_run(x):
        pr = sorted(x["per_rank"], key=lambda r: r["rank"])
        u = [float(r["units"]) for r in pr]
        b = [float(r["busy_seconds"]) for r in pr]
        sb = sum(b) or 1.0
        if v2:
            msgs = float(x.get("rank0_messages_in", 0))
        else:
            msgs = (N - 1) + sum(u[1:]) if N > 1 else 0
        return {"units": u, "share": [100 * v / sb for v in b], "rows": [float(r["rows"]) for r in pr],
                "messages": msgs, "imbalance": max(b) / (sb / N),
                "bytes": float(x.get("rank0_bytes_in", 0)), "fc": float(x.get("final_combine_seconds", 0)),
                "cpu": float(x.get("rank0_serve_cpu_seconds", 0)),
                "wall": float(x.get("render_seconds", 0))}

    meas = [per_run(x) for x in runs]
    mean = lambda xs: sum(xs) / len(xs)

    def cell(key, r, fmt):
        vals = [x[key][r] for x in meas]
        if len(vals) == 1:
            return fmt % vals[0]
        return (fmt % mean(vals)) + (" [" + fmt + "-" + fmt + "]") % (min(vals), max(vals))

    trace_ok = None
    if args.compare_trace:
        trace_ok = True
        for path, x in zip(args.compare_trace, meas):
            tu = [0.0] * N
            for e in load_trace(path):
                tu[e["rank"]] += 1
            trace_ok &= tu == x["units"]
    n = len(meas)
    print("== %s: %d run%s measured (mean [min-max]) vs predicted ==" % (args.label or args.compare[0], n,
                                                                        "s" if n > 1 else ""))
    print("%5s %19s %6s %19s %6s %19s %7s" % ("rank", "units measured", "pred", "busy% measured", "pred",
                                             "rows measured", "pred"))
    for r in range(N):
        print("%5d %19s %6d %19s %6.1f %19s %7.1f" % (r, cell("units", r, "%.0f"), pu[r], cell("share", r, "%.1f"),
                                                      100 * pb[r] / spb, cell("rows", r, "%.0f"), prow[r]))
    tot = [sum(x["units"]) for x in meas]
    print("%5s %19s %6d" % ("sum", "%.0f" % mean(tot) if min(tot) == max(tot) else "%.0f-%.0f" % (min(tot), max(tot)),
                            sum(pu)))
    msg = [x["messages"] for x in meas]
    imb = [x["imbalance"] for x in meas]
    if v2:
        print("messages rank 0 received (hellos, reports, sums, beats, byes): measured %.0f [%.0f-%.0f], "
              "predicted %d" % (mean(msg), min(msg), max(msg), res["messages"]))
        for key, name, pred, scale, fmt in (("bytes", "MB rank 0 received", res["bytes"], 1e-6, "%.3f"),
                                            ("fc", "final combination, ms", res["final_combine"], 1e3, "%.2f"),
                                            ("cpu", "rank 0 serve CPU, ms", res["serve_cpu"], 1e3, "%.2f")):
            v = [x[key] * scale for x in meas]
            print(("%s: measured " + fmt + " [" + fmt + "-" + fmt + "], predicted " + fmt)
                  % (name, mean(v), min(v), max(v), pred * scale))
    else:
        print("messages rank 0 received (hellos + results): measured %.0f [%.0f-%.0f], predicted %d"
              % (mean(msg), min(msg), max(msg), res["messages"]))
    print("load imbalance (max busy / mean busy): measured %.3f [%.3f-%.3f], predicted %.3f"
          % (mean(imb), min(imb), max(imb), max(pb) / (spb / N)))
    if trace_ok is not None:
        print("trace check: units per rank in the traces %s the stats" % ("match" if trace_ok else "DIFFER from"))
    print("render wall (not validated here: ranks share 2 cores): measured %.2f s, predicted %.2f s"
          % (mean([x["wall"] for x in meas]), res["makespan"]))
    print()
    row = {"label": args.label, "ranks": N, "runs": n, "units_total_measured": tot,
           "units_total_predicted": sum(pu),
           "rank0_units_measured": mean([x["units"][0] for x in meas]), "rank0_units_predicted": pu[0],
           "worker_units_measured": mean([mean(x["units"][1:]) for x in meas]) if N > 1 else 0.0,
           "worker_units_predicted": mean(pu[1:]) if N > 1 else 0.0,
           "rank0_share_measured": mean([x["share"][0] for x in meas]), "rank0_share_predicted": 100 * pb[0] / spb,
           "messages_measured": mean(msg), "messages_predicted": res["messages"],
           "imbalance_measured": mean(imb), "imbalance_predicted": max(pb) / (spb / N),
           "trace_matches_stats": trace_ok}
    if v2:
        for key, pred in (("bytes", res["bytes"]), ("fc", res["final_combine"]), ("cpu", res["serve_cpu"])):
            row[key + "_measured"] = [x[key] for x in meas]
            row[key + "_predicted"] = pred
    if args.summary:
        with open(args.summary, "a") as f:
            f.write(json.dumps(row) + "\n")
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--trace", nargs="+", help="rt-mpi --trace file of a real run (unit costs); several runs of "
                    "one job: each row's cost is its cheapest (a unit that other work on the machine preempted "
                    "looks dearer than it is)")
    ap.add_argument("--empty-units", action="store_true",
                    help="units cost nothing (as rt-mpi --empty-units): the farm's own rate; needs --width, "
                         "--height, --samples instead of a trace")
    ap.add_argument("--stats", help="rt-mpi --stats file of the same run (width, threads)")
    ap.add_argument("--trace-width", type=int, help="width of the traced run (else from --stats)")
    ap.add_argument("--trace-threads", type=int, help="threads per rank of the traced run (else from --stats)")
    ap.add_argument("--width", type=int, help="simulated job width (default: the traced one)")
    ap.add_argument("--height", type=int, help="simulated job height (default: the traced one)")
    ap.add_argument("--samples", type=int, help="simulated samples per pixel (default: the traced one)")
    ap.add_argument("--threads", type=int, default=16, help="threads per rank [16]")
    ap.add_argument("--ranks", type=parse_ranks, default=parse_ranks("1-4096"),
                    help="list, or LO-HI for the powers of two between [1-4096]")
    ap.add_argument("--policies", help="static,bands,split,affinity,tiles [v2: all five; v1: static,bands,split]")
    ap.add_argument("--farm", choices=("v1", "v2"), default="v2",
                    help="v2: the farm as built (df446ae: 32-byte reports, sums held and sent per flush); "
                         "v1: every unit's sums to rank 0 (bec6e4d and before), to reproduce old predictions [v2]")
    ap.add_argument("--flush-interval", type=float, default=0.1,
                    help="v2: a worker's flush interval, s (rt-mpi --flush-interval; 1 before column tiles) [0.1]")
    ap.add_argument("--flush-mb", type=float, default=64, help="v2: a worker flushes when it holds this, MB [64]")
    ap.add_argument("--lease", type=float, default=5.0, help="v2: lease, s; an idle worker beats every lease/4 [5]")
    ap.add_argument("--pack-byte", type=float, default=V2_PACK,
                    help="v2: a worker's seconds per byte to pack a flush [%g, measured]" % V2_PACK)
    ap.add_argument("--reports-first", action="store_true",
                    help="v2, not built: rank 0 takes hellos, reports and beats before sums (probing their tags "
                         "first), so a burst of flushes does not hold up the next units")
    ap.add_argument("--min-cols", type=int, default=16,
                    help="v2: narrowest column tile (schedule.h min_cols); rows are cut into tiles only when "
                         "ceil(ranks x units per rank / rows) <= width / this [16]")
    ap.add_argument("--piece-header", type=int, default=PIECE_HDR,
                    help="v2: bytes of a piece's header in a SUMS message before its unit ids: %d since column "
                         "tiles (7 int64), %d before (to reproduce older predictions) [%d]"
                         % (PIECE_HDR, PIECE_HDR_SAMPLES, PIECE_HDR))
    ap.add_argument("--units-per-rank", type=int, default=16,
                    help="v2: the schedule's target units per rank and pass (src/app/setup.c: 16 since column "
                         "tiles, 8 before; v1 always 8) [16]")
    ap.add_argument("--network", choices=sorted(NETWORKS), default="ib",
                    help="latency/bandwidth preset: ib (2 us, 12.5 GB/s), eth (50 us, 1.25 GB/s), "
                         "shm (1 us, copies in service) [ib]")
    ap.add_argument("--latency", type=float, help="one-way message latency, s (overrides --network)")
    ap.add_argument("--bandwidth", type=float, help="rank 0 ingress bandwidth, bytes/s (overrides --network)")
    ap.add_argument("--service-json", help="rank 0 service time fitted by validate_scaling.sh "
                                           "(service_msg_s, service_byte_s)")
    ap.add_argument("--service-msg", type=float,
                    help="rank 0 seconds per message (v1 default 20e-6; v2 default %g, measured)" % V2_MSG)
    ap.add_argument("--service-byte", type=float,
                    help="rank 0 seconds per byte received (v1 default 0; v2 default %g, measured)" % V2_BYTE)
    ap.add_argument("--prefetch", type=int, default=2, help="units in flight per worker [2]")
    ap.add_argument("--band", type=int, default=0, help="fixed rows per unit as --band (0: guided) [0]")
    ap.add_argument("--passes", type=int, default=1, help="progressive passes as rt-mpi --passes [1]")
    ap.add_argument("--serve-only", action="store_true", help="rank 0 does not render")
    ap.add_argument("--nap-base", type=float, default=50e-6, help="first poll back-off nap, s [50e-6]")
    ap.add_argument("--nap-cap", type=float, default=1e-3, help="longest nap, s [1e-3]")
    ap.add_argument("--nap-slack", type=float, default=80e-6, help="timer overshoot per nap, s [80e-6]")
    ap.add_argument("--probe-miss", type=int, default=0,
                    help="polls that miss a message which arrived during a nap: 0 for the farm as built "
                         "(it probes twice before napping), 1 for the farm before that fix [0]")
    ap.add_argument("--worker-overhead", type=float, default=0.0,
                    help="seconds a worker spends between two units outside rendering (message handling; "
                         "under Open MPI's yield-when-idle on shared cores it is milliseconds) [0]")
    ap.add_argument("--setup", type=float, default=0.0,
                    help="seconds of scene broadcast and BVH build, counted in the render phase [0]")
    ap.add_argument("--startup", type=float, default=0.0, help="seconds of MPI start-up before it (E+) [0]")
    ap.add_argument("--write", type=float, default=0.0, help="seconds of image writing after it (E+) [0]")
    ap.add_argument("--slowdown", type=float, default=1.0, help="unit durations times this (shared cores)")
    ap.add_argument("--per-rank", action="store_true", help="print units and busy share per rank")
    ap.add_argument("--compare", metavar="STATS.json", nargs="+",
                    help="print the prediction (policy tiles, the farm as built; see --compare-policy) next to "
                         "these measured runs (repeats of one configuration)")
    ap.add_argument("--compare-policy", choices=("bands", "split", "affinity", "tiles"),
                    help="v2: the policy --compare predicts with [tiles]")
    ap.add_argument("--compare-trace", metavar="TRACE.json", nargs="+",
                    help="the measured runs' traces (checked against their stats)")
    ap.add_argument("--summary", metavar="FILE", help="append the --compare summary as a JSON line")
    ap.add_argument("--label", default="", help="title of the --compare table")
    ap.add_argument("--json", help="write every result to this file")
    ap.add_argument("-q", "--quiet", action="store_true", help="no table on stdout")
    args = ap.parse_args(argv)

    if args.empty_units:
        if not (args.width and args.height and args.samples):
            ap.error("--empty-units needs --width, --height and --samples")
        args.trace, args.trace_width, args.trace_threads = None, args.width, 1
    elif not args.trace:
        ap.error("need --trace (or --empty-units)")
    stats = {}
    if args.stats:
        with open(args.stats) as f:
            stats = json.load(f)
    tw = args.trace_width or stats.get("width")
    tt = args.trace_threads or stats.get("threads_per_rank")
    if not tw or not tt:
        ap.error("need --stats, or --trace-width and --trace-threads")
    if args.empty_units:
        events = []
        th, ts = args.height, args.samples
        profile = [0.0] * th
    else:
        events = load_trace(args.trace[0])
        th = stats.get("height") or max(e["y1"] for e in events)
        ts = stats.get("samples") or max(e["s1"] for e in events)
        profile = cost_profile(events, tw, tt, th)
        for path in args.trace[1:]:
            profile = [min(x, y) for x, y in zip(profile, cost_profile(load_trace(path), tw, tt, th))]
    W = args.width or tw
    H = args.height or th
    S = args.samples or ts
    job = Job(profile, W, H, S)

    lat, bw = NETWORKS[args.network]
    if args.latency is not None:
        lat = args.latency
    if args.bandwidth is not None:
        bw = args.bandwidth if args.bandwidth > 0 else math.inf
    smsg, sbyte = (20e-6, 0.0) if args.farm == "v1" else (V2_MSG, V2_BYTE)
    if args.service_json:
        with open(args.service_json) as f:
            sj = json.load(f)
        if args.farm == "v1":
            if "service_msg_s" not in sj:
                ap.error("%s holds v2 costs (per message and byte): give --farm v1 its costs per result "
                         "(--service-msg, --service-byte)" % args.service_json)
            smsg, sbyte = sj["service_msg_s"], sj["service_byte_s"]
        else:
            smsg, sbyte = sj["msg_s"], sj["byte_s"]
    if args.service_msg is not None:
        smsg = args.service_msg
    if args.service_byte is not None:
        sbyte = args.service_byte
    m = Model(threads=args.threads, latency=lat, bandwidth=bw, service_msg=smsg, service_byte=sbyte,
              prefetch=args.prefetch, nap_base=args.nap_base, nap_cap=args.nap_cap, nap_slack=args.nap_slack,
              slowdown=args.slowdown, serve_only=args.serve_only, band=args.band,
              probe_miss=args.probe_miss, passes=args.passes, worker_overhead=args.worker_overhead,
              farm=args.farm, per_rank=args.units_per_rank, flush_interval=args.flush_interval,
              flush_bytes=args.flush_mb * 2 ** 20, lease=args.lease, pack_byte=args.pack_byte,
              reports_first=args.reports_first, min_cols=args.min_cols, piece_hdr=args.piece_header)
    if args.compare:
        return compare(job, m, args)
    if not args.policies:
        args.policies = "static,bands,split" if args.farm == "v1" else ",".join(POLICIES)
    policies = [p.strip() for p in args.policies.split(",") if p.strip()]
    for p in policies:
        if p not in POLICIES or (p in V2_ONLY and args.farm == "v1"):
            ap.error("unknown policy %r (static, bands, split%s)" % (p, "" if args.farm == "v1" else ", affinity, tiles"))

    out = {"job": {"width": W, "height": H, "samples": S, "cost_thread_seconds": job.total},
           "trace": {"files": args.trace, "width": tw, "height": th, "samples": ts, "threads": tt,
                     "units": len(events)},
           "model": {"threads": m.T, "latency_s": m.L, "bandwidth_Bps": None if m.B == math.inf else m.B,
                     "service_msg_s": m.a, "service_byte_s": m.b, "prefetch": m.prefetch,
                     "nap_base_s": m.nap_base, "nap_cap_s": m.nap_cap, "nap_slack_s": m.nap_slack,
                     "slowdown": m.slowdown, "serve_only": m.serve_only, "band": m.band,
                     "probe_miss": m.probe_miss, "passes": m.passes, "worker_overhead_s": m.worker_overhead,
                     "farm": m.farm, "units_per_rank": m.per_rank, "flush_interval_s": None if m.flush_interval == math.inf else m.flush_interval,
                     "flush_bytes": m.flush_bytes, "lease_s": m.lease, "pack_byte_s": m.pack_byte,
                     "reports_first": m.reports_first, "min_cols": m.min_cols, "piece_header": m.piece_hdr,
                     "setup_s": args.setup, "startup_s": args.startup, "write_s": args.write},
           "results": []}
    if not args.quiet:
        bw_s = "inf" if m.B == math.inf else "%.3g GB/s" % (m.B / 1e9)
        if args.empty_units:
            print("job %dx%d, %d spp, empty units (no rendering: the farm's own rate)" % (W, H, S))
        else:
            print("job %dx%d, %d spp: %.1f thread-seconds (profile from %s: %dx%d, %d spp, %d thread%s, %d units)"
                  % (W, H, S, job.total, " ".join(args.trace), tw, th, ts, tt, "s" if tt > 1 else "", len(events)))
        print("model: %d threads/rank, latency %.3g us, bandwidth %s, rank 0 service %.3g us/msg + %.3g ns/byte, "
              "prefetch %d, naps %.0f us..%.0f us +%.0f us, probe miss %d%s%s"
              % (m.T, m.L * 1e6, bw_s, m.a * 1e6, m.b * 1e9, m.prefetch, m.nap_base * 1e6, m.nap_cap * 1e6,
                 m.nap_slack * 1e6, m.probe_miss, ", serve-only" if m.serve_only else "",
                 ", slowdown %.3g" % m.slowdown if m.slowdown != 1 else ""))
        hdr = "%7s" % "ranks" + "".join("%9s" % (("u/s " if args.empty_units else "E ") + p) for p in policies)
        hdr += "".join("%9s" % ("T " + p) for p in policies)
        hdr += "".join("%9s" % ("units " + p[:2]) for p in policies if p != "static")
        hdr += "".join("%9s" % ("r0 " + p[:2]) for p in policies if p != "static")
        if m.farm == "v2":
            hdr += "".join("%9s" % ("fc " + p[:2]) for p in policies if p != "static")
            hdr += "".join("%9s" % ("MB " + p[:2]) for p in policies if p != "static")
        print("E: parallel efficiency of the render phase%s; T: makespan (s); units: work units; "
              "r0: rank 0's server busy share" % (" (with %.3g s of set-up)" % args.setup if args.setup else ""))
        if m.farm == "v2":
            print("fc: final combination (s, last unit reported to last sums in); MB: sums rank 0 receives")
        if args.startup or args.write:
            print("E+: the whole job, with %.3g s start-up and %.3g s image writing" % (args.startup, args.write))
            hdr += "".join("%9s" % ("E+ " + p[:2]) for p in policies)
        print(hdr)
    for N in args.ranks:
        row = {"ranks": N}
        for p in policies:
            row[p] = simulate(job, N, m, p, setup=args.setup, startup=args.startup, write=args.write)
        out["results"].append(row)
        if not args.quiet:
            if args.empty_units:
                line = "%7d" % N + "".join("%9.0f" % row[p]["units_per_s"] for p in policies)
            else:
                line = "%7d" % N + "".join("%9.3f" % row[p]["efficiency"] for p in policies)
            line += "".join("%9.3g" % row[p]["makespan"] for p in policies)
            line += "".join("%9d" % row[p]["units"] for p in policies if p != "static")
            line += "".join("%8.1f%%" % (100 * row[p]["server_util"]) for p in policies if p != "static")
            if m.farm == "v2":
                line += "".join("%9.3g" % row[p]["final_combine"] for p in policies if p != "static")
                line += "".join("%9.0f" % (row[p]["sums_bytes"] / 1e6) for p in policies if p != "static")
            if args.startup or args.write:
                line += "".join("%9.3f" % row[p]["efficiency_job"] for p in policies)
            print(line)
            if args.per_rank:
                for p in policies:
                    tot = sum(row[p]["per_rank_busy"]) or 1.0
                    print("        %-6s units %s" % (p, " ".join("%d" % x for x in row[p]["per_rank_units"])))
                    print("        %-6s busy%% %s" % (p, " ".join("%.1f" % (100 * x / tot)
                                                              for x in row[p]["per_rank_busy"])))
    if not args.quiet and not args.empty_units:
        for p in policies:
            if p == "static":
                continue
            over = [row["ranks"] for row in out["results"] if row[p]["server_load"] >= 1.0]
            half = [row["ranks"] for row in out["results"] if row[p]["server_load"] >= 0.5]
            print("rank 0 (%s): service demand >= 50%% of the ideal makespan from %s ranks, >= 100%% "
                  "(rank 0 is the bottleneck) from %s ranks" % (p, half[0] if half else "no tested number of",
                                                                over[0] if over else "no tested number of"))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    return out


if __name__ == "__main__":
    main()
