#!/bin/bash
# profile.sh [rt-mpi options...]
# Instruction counts of the render, from valgrind's callgrind: repeatable for
# the same binary and inputs, whatever else the machine is doing. Builds the
# program in $PROFILE_BUILD_DIR (default build-profile/): release flags,
# baseline x86-64 (no -march: valgrind 3.19 cannot decode AVX-512), -g, and
# no LTO, so the intersector stays a function of its own: where the render
# runs its AVX path loop (our BVH on a CPU with AVX), rt_bvh_closest_packet_avx
# for the rays it traces in packets and rt_bvh_closest_avx for the others,
# else rt_accel_closest, once per ray segment. Renders the final
# scene at 150x100, 8 spp, 1 thread unless the options say otherwise (later
# options win), e.g.
#   tools/profile.sh --accel brute --width 60 --height 40 -s 2
# and prints instructions per ray segment: in the intersector (per query)
# and in everything else of the render (camera, shading, sampling, RNG).
# The full profile stays in $PROFILE_BUILD_DIR/callgrind.out for
# callgrind_annotate. PROFILE_CFLAGS adds compiler flags, e.g.
# PROFILE_CFLAGS=-march=x86-64-v3 (AVX2; a build dir of its own).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${PROFILE_BUILD_DIR:-$ROOT/build-profile}
mkdir -p "$BUILD"
RT_EXTRA_PACKAGES="valgrind python3" RT_BUILD_TARGET=rt-mpi "$ROOT/scripts/setup.sh" "$BUILD" -DRT_LTO=OFF \
    -DRT_MPI=OFF -DBUILD_TESTING=OFF "-DCMAKE_C_FLAGS=-g ${PROFILE_CFLAGS:-}" >/dev/null 2>"$BUILD/setup.log" ||
    { cat "$BUILD/setup.log" >&2; exit 2; }
OUT=$BUILD/callgrind.out
OPTS=(--width 150 --height 100 -s 8 -j 1 "$@")
rm -f "$BUILD/profile.png" "$BUILD/profile.json"
valgrind --tool=callgrind --callgrind-out-file="$OUT" "$BUILD/rt-mpi" "${OPTS[@]}" --no-checkpoint --quiet \
    -o "$BUILD/profile.png" --stats "$BUILD/profile.json" >"$BUILD/valgrind.log" 2>&1 ||
    { tail -5 "$BUILD/valgrind.log" >&2; echo "profile.sh: the render failed under callgrind" >&2; exit 1; }
callgrind_annotate --inclusive=yes --tree=caller "$OUT" >"$BUILD/callgrind.txt" 2>/dev/null
python3 - "$BUILD/callgrind.txt" "$BUILD/profile.json" "${OPTS[*]}" <<'PY'
import json, re, sys
text, stats, opts = open(sys.argv[1]).read(), json.load(open(sys.argv[2])), sys.argv[3]
num = lambda s: int(s.replace(",", ""))
# callgrind_annotate --tree=caller: a function's line is "COUNT (PCT)  *  FILE:NAME",
# preceded by one "COUNT (PCT)  <  FILE:CALLER (CALLSx)" line per caller.
LINE = r"^\s*[\d,]+ \([^)]*\)\s+"
def own_line(fn):
    return LINE + r"\*\s+\S*:%s(?: \[.*)?$" % re.escape(fn)
def inclusive(fn):
    m = re.search(own_line(fn), text, re.M)
    if not m:
        sys.exit("profile.sh: %s not found in the profile" % fn)
    return num(m.group(0).split()[0])
def calls(fn):
    m = re.search(r"((?:%s<.*\n)+)%s" % (LINE, own_line(fn)), text, re.M)
    return sum(num(c) for c in re.findall(r"\(([\d,]+)x\)", m.group(1))) if m else 0
segs = stats["ray_segments"]
# The AVX path loop calls the packet traversal for the segments it traces
# in packets (render.h, rt_render_in_packet) and the AVX traversal for the
# others; every other path loop calls rt_accel_closest, once per segment.
present = lambda fn: re.search(own_line(fn), text, re.M) is not None
# the render: rank 0 renders its units as one stream (team.c); the
# commits of finished units (farm.c's local_done) are not part of it
render = inclusive("rt_render_stream") - (inclusive("local_done") if present("local_done") else 0)
# Camera rays whose tile has a candidate list (primary.h: our BVH only) go
# to rt_primary_closest instead, one call each.
lists = "rt_primary_closest"
n_list = calls(lists) if present(lists) else 0
list_query = inclusive(lists) if n_list else 0
if present("rt_bvh_closest_avx"):
    single, packet = "rt_bvh_closest_avx", "rt_bvh_closest_packet_avx"
    # every other segment is one ray of a packet (2 to 8 rays) or one single query
    in_packets, n_packets = segs - n_list - calls(single), calls(packet)
    if not 2 * n_packets <= in_packets <= 8 * n_packets:
        sys.exit("profile.sh: %d calls of %s, %d of %s and %d of %s for %d ray segments: per-query counts would be "
                 "wrong" % (calls(single), single, n_packets, packet, n_list, lists, segs))
    query, packet_query, name = inclusive(single) + inclusive(packet), inclusive(packet), single + " + " + packet
else:
    fn = "rt_accel_closest"
    if calls(fn) + n_list != segs:
        sys.exit("profile.sh: %d calls of %s and %d of %s, %d ray segments: per-query counts would be wrong"
                 % (calls(fn), fn, n_list, lists, segs))
    query, packet_query, name, in_packets = inclusive(fn), None, fn, 0
query += list_query
if n_list:
    name += " + " + lists
print("profile.sh: callgrind, rt-mpi %s (intersector: %s)" % (opts, name))
print("  ray segments                          %12d" % segs)
print("  instructions in the render            %12d" % render)
print("  per segment                           %12.1f" % (render / segs))
print("  in the intersector, per query         %12.1f" % (query / segs))
if n_list:
    print("    per camera ray through its tile's list (%4.1f%% of them) %8.1f" % (100.0 * n_list / segs, list_query / n_list))
if packet_query is not None:
    print("    per ray in packets (%4.1f%% of them) %12.1f" % (100.0 * in_packets / segs, packet_query / in_packets))
if segs - in_packets - n_list:
    print("    per ray one at a time               %12.1f" % ((query - (packet_query or 0) - list_query) / (segs - in_packets - n_list)))
print("  everything else, per segment          %12.1f" % ((render - query) / segs))
PY
