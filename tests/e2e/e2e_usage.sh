#!/bin/bash
# e2e_usage.sh BIN MPIRUN SOURCE_DIR PNGINFO
# What a user and a script see: the scene file as a word of its own,
# --version and --help, a mistyped option, the provenance in --stats and
# --trace (valid JSON whatever bytes the command line holds, under mpirun
# too, with the Slurm job id when there is one), and the EXR's attributes,
# the same facts as the PNG's text chunks.
BIN=$1 MPIRUN=${2:-} SRC=$3 PNGINFO=$4
source "$(dirname "$0")/../support/lib.sh"
A=(--width 48 --height 32 -s 2 -q --no-checkpoint)
hash_of() { sed -n 's/^image hash: *//p' "$1"; }

# rt-mpi SCENE.json is rt-mpi --scene-file SCENE.json.
"$BIN" "${A[@]}" "$SRC/scenes/example.json" -o "$WORK/pos.png" >"$WORK/pos.out" 2>&1
check_eq "positional scene file: exit status" $? 0
"$BIN" "${A[@]}" --scene-file "$SRC/scenes/example.json" -o "$WORK/opt.png" >"$WORK/opt.out" 2>&1
check_eq "positional scene file = --scene-file (image hash)" "$(hash_of "$WORK/pos.out")" "$(hash_of "$WORK/opt.out")"
grep -q "^scene: *file $SRC/scenes/example.json" "$WORK/pos.out" && pass "the summary names the scene file" ||
    fail "summary: $(grep '^scene' "$WORK/pos.out")"

"$BIN" --version >"$WORK/v.out"
check_eq "--version: features" "$(sed -n 's/^features: //p' "$WORK/v.out")" "mpi openmp png exr json jpeg"
MPILIB=$(sed -n 's/^MPI library: //p' "$WORK/v.out")
case $MPILIB in "Open MPI v"*) pass "--version: MPI library ($MPILIB)" ;; *) fail "--version: MPI library '$MPILIB'" ;; esac
"$BIN" --help >"$WORK/h.out" 2>"$WORK/h.err"
check_eq "--help: exit status, nothing on stderr" "$?:$(wc -c <"$WORK/h.err")" "0:0"
expect_usage_error "mistyped option" "unknown option '--wdith' (did you mean --width?)" "$BIN" --wdith 3

# --stats and --trace: a path with a tab, a newline, a quote, a backslash
# and bytes that are no UTF-8 (each becomes U+FFFD, as Python's "replace"
# does for these bytes), read back by Python's strict UTF-8 and JSON.
NAME=$(printf 'a\tb\nc"d\\e\xff\xc3.png')
check_json() { # label stats trace want_mpi want_ranks want_slurm args...
    local label=$1 stats=$2 trace=$3
    shift 3
    if python3 - "$stats" "$trace" "$@" >"$WORK/py.out" 2>&1 <<'EOF'; then
import json, re, socket, sys
stats_path, trace_path, want_mpi, want_ranks, want_slurm = sys.argv[1:6]
argv = [a.encode("utf-8", "surrogateescape").decode("utf-8", "replace") for a in sys.argv[6:]]
s = json.loads(open(stats_path, "rb").read().decode("utf-8"))
t = json.loads(open(trace_path, "rb").read().decode("utf-8"))
bad = []
def want(what, got, exp):
    if got != exp:
        bad.append("%s: %r, want %r" % (what, got, exp))
want("command_line", s["command_line"], argv)
want("trace command_line", t["otherData"]["command_line"], argv)
want("output", s["output"], argv[argv.index("-o") + 1])
want("mpi", s["mpi"], want_mpi == "true")
want("ranks", (s["ranks"], len(s["per_rank"])), (int(want_ranks), int(want_ranks)))
want("features", s["features"], ["mpi", "openmp", "png", "exr", "json", "jpeg"])
want("host", s["host"], socket.gethostname())
want("slurm_job_id", s.get("slurm_job_id"), want_slurm or None)
want("start_time format", bool(re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", s["start_time"])), True)
want("render_seconds >= 0", s["render_seconds"] >= 0, True)
for k in ("version", "mpi_library", "busy_seconds"):
    if k not in s and k not in s["per_rank"][0]:
        bad.append("no %s" % k)
want("trace units", sum(e["ph"] == "X" for e in t["traceEvents"]), s["units"])
print("; ".join(bad) if bad else "version %s, %s, started %s" % (s["version"], s["mpi_library"][:20], s["start_time"]))
sys.exit(1 if bad else 0)
EOF
        pass "$label: $(cat "$WORK/py.out")"
    else
        fail "$label: $(cat "$WORK/py.out")"
    fi
}
mkdir -p "$WORK/j"
(cd "$WORK/j" && env -u SLURM_JOB_ID "$BIN" "${A[@]}" -o "$NAME" --stats s1.json --trace t1.json >/dev/null 2>&1)
check_eq "hostile output name: exit status" $? 0
# (check_json runs in this shell: a check in a subshell would not count)
check_json "one process" "$WORK/j/s1.json" "$WORK/j/t1.json" false 1 "" \
    "$BIN" "${A[@]}" -o "$NAME" --stats s1.json --trace t1.json
check_eq "--version's MPI library in --stats" \
    "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["mpi_library"])' "$WORK/j/s1.json")" "$MPILIB"
if [ -n "$MPIRUN" ]; then
    (cd "$WORK/j" && SLURM_JOB_ID=4242 mpirun_np 2 "$BIN" "${A[@]}" -o "$NAME" --stats s2.json --trace t2.json \
        >/dev/null 2>&1)
    check_eq "mpirun -np 2, hostile output name: exit status" $? 0
    check_json "mpirun -np 2 with SLURM_JOB_ID" "$WORK/j/s2.json" "$WORK/j/t2.json" true 2 4242 \
        "$BIN" "${A[@]}" -o "$NAME" --stats s2.json --trace t2.json
else
    skip "mpirun cases (no MPI build)"
fi

# The EXR carries the PNG's text chunks as string attributes.
"$BIN" "${A[@]}" --seed 7 -o "$WORK/m.png" >/dev/null 2>&1
"$BIN" "${A[@]}" --seed 7 -o "$WORK/m.exr" >/dev/null 2>&1
if command -v exrheader >/dev/null; then
    "$PNGINFO" --text "$WORK/m.png" | sort >"$WORK/png.txt"
    exrheader "$WORK/m.exr" | sed -n 's/^\([^ ]*\) (type string): "\(.*\)"$/\1=\2/p' |
        grep -v '^\(name\|type\)=' | sort >"$WORK/exr.txt"
    if [ "$(wc -l <"$WORK/png.txt")" -ge 5 ] && cmp -s "$WORK/png.txt" "$WORK/exr.txt"; then
        pass "EXR attributes = PNG text chunks ($(tr '\n' ';' <"$WORK/exr.txt" | head -c 200))"
    else
        fail "EXR attributes differ from the PNG's text: $(diff "$WORK/png.txt" "$WORK/exr.txt" | head -20)"
    fi
else
    skip "EXR attributes (no exrheader: apt-get install openexr)"
fi
finish
