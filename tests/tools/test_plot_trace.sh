#!/bin/bash
# test_plot_trace.sh PYTHON RT_MPI [MPIRUN] - tools/plot_trace.py on the
# trace and stats of a real small run (2 ranks under mpirun when given, else
# one): it writes a PNG of a sensible size whose summary counts the units and
# ranks of the trace, with both colourings, with and without --stats; and it
# refuses a trace without units. Skips (77) when matplotlib is missing.
PY=$1 BIN=$2 MPIRUN=${3:-}
source "$(dirname "$0")/../support/lib.sh"
PLOT=$(cd "$(dirname "$0")/../.." && pwd)/tools/plot_trace.py
if ! "$PY" -c 'import matplotlib' 2>/dev/null; then
    skip "$PY has no matplotlib (Debian: apt-get install python3-matplotlib)"
    [ "$FAILED" -eq 0 ] && exit 77 # ctest shows it skipped (with RT_REQUIRE_ALL=1 it failed)
    finish
fi

ARGS=(--width 160 --height 24 -s 24 -j 1 -q --no-checkpoint -o "$WORK/img.png" --trace "$WORK/t.json" --stats "$WORK/s.json")
if [ -n "$MPIRUN" ]; then
    NP=2
    mpirun_np 2 "$BIN" "${ARGS[@]}" >"$WORK/run.out" 2>&1 || { cat "$WORK/run.out"; fail "the traced run"; finish; }
else
    NP=1
    "$BIN" "${ARGS[@]}" >"$WORK/run.out" 2>&1 || { cat "$WORK/run.out"; fail "the traced run"; finish; }
fi
UNITS=$("$PY" -c 'import json,sys; print(sum(e["ph"] == "X" for e in json.load(open(sys.argv[1]))["traceEvents"]))' "$WORK/t.json")

png_size() { # file -> "WIDTHxHEIGHT" from the IHDR chunk, or "not a png"
    "$PY" - "$1" <<'EOF'
import struct, sys
b = open(sys.argv[1], "rb").read(32)
print("%dx%d" % struct.unpack(">II", b[16:24]) if b[:8] == b"\x89PNG\r\n\x1a\n" and b[12:16] == b"IHDR" else "not a png")
EOF
}

out=$("$PY" "$PLOT" "$WORK/t.json" --stats "$WORK/s.json" -o "$WORK/plot.png" 2>&1)
check_eq "plot_trace exit status" "$?" 0
echo "$out"
check_eq "summary counts the trace" "$(echo "$out" | grep -o '^plot_trace: [0-9]* ranks, [0-9]* units')" \
    "plot_trace: $NP ranks, $UNITS units"
size=$(png_size "$WORK/plot.png")
w=${size%x*} h=${size#*x}
if [ "$size" != "not a png" ] && [ "$w" -ge 800 ] && [ "$h" -ge 300 ] && [ "$h" -le 3000 ]; then
    pass "PNG of a readable size ($size)"
else
    fail "PNG size: $size"
fi
bytes=$(stat -c %s "$WORK/plot.png" 2>/dev/null || echo 0)
if [ "$bytes" -gt 20000 ]; then pass "PNG has content ($bytes bytes)"; else fail "PNG too small: $bytes bytes"; fi

"$PY" "$PLOT" "$WORK/t.json" --color samples -o "$WORK/plot2.png" >"$WORK/o2" 2>&1
check_eq "without --stats, colour by samples: exit status" "$?" 0
check_eq "colour by samples is used" "$(grep -c 'colour by samples' "$WORK/o2")" 1

echo '{"traceEvents":[{"name":"process_name","ph":"M","pid":0,"tid":0,"args":{"name":"rank 0"}}]}' >"$WORK/empty.json"
"$PY" "$PLOT" "$WORK/empty.json" -o "$WORK/plot3.png" >"$WORK/o3" 2>&1
st=$?
if [ $st -ne 0 ] && [ ! -e "$WORK/plot3.png" ]; then pass "a trace without units is refused ($st)"; else
    fail "a trace without units: status $st"; fi
finish
