#!/bin/bash
# e2e_adaptive.sh BIN SERIAL_BIN MPIRUN
# Adaptive sampling (--noise-threshold, --spp-map) and the denoiser's
# buffers (--aov) through the whole program: the image, the buffers and the
# samples-per-pixel map are byte-identical for any -np, -j, --band and
# --passes, in the build without MPI and across a resume (also of a
# progressive run); the summary and --stats count
# the samples as the map shows them; bad combinations are refused.
BIN=$1 SERIAL=$2 MPIRUN=${3:-}
source "$(dirname "$0")/../support/lib.sh"
A=(--width 96 --height 64 -s 64 --noise-threshold 0.05 --aov albedo,normal -q)
FILES=(png albedo.pfm normal.pfm spp.pfm)

render() { # name command... : NAME.png, NAME.albedo.pfm, NAME.normal.pfm, NAME.spp.pfm
    local name=$1
    shift
    "$@" "${A[@]}" -o "$WORK/$name.png" --spp-map "$WORK/$name.spp.pfm" --stats "$WORK/$name.json" \
        >"$WORK/$name.out" 2>"$WORK/$name.err"
}
render ref "$BIN" -j 1
check_eq "reference run exit status" $? 0
for f in "${FILES[@]}"; do
    [ -s "$WORK/ref.$f" ] && pass "reference wrote ref.$f" || fail "no ref.$f"
done
same_as_ref() { # label name
    local f bad=""
    for f in "${FILES[@]}"; do cmp -s "$WORK/ref.$f" "$WORK/$2.$f" || bad="$bad $f"; done
    [ -z "$bad" ] && pass "$1: image, buffers and map identical" || fail "$1: differs in$bad"
}
variant() { # label name command...
    local label=$1 name=$2
    shift 2
    if render "$name" "$@"; then same_as_ref "$label" "$name"; else fail "$label: exit status $? ($(head -c 300 "$WORK/$name.err"))"; fi
}
variant "-j 2" j2 "$BIN" -j 2
variant "-j 2 --band 1" b1 "$BIN" -j 2 --band 1
variant "-j 1 --band 7" b7 "$BIN" -j 1 --band 7
variant "build without MPI" serial "$SERIAL" -j 2
# Progressive passes: the same files, and a preview.
variant "--passes 4" p4 "$BIN" -j 2 --passes 4 --preview "$WORK/p4.preview.png"
[ -s "$WORK/p4.preview.png" ] && pass "--passes 4 wrote a preview" || fail "--passes 4: no preview"
if [ -n "$MPIRUN" ]; then
    variant "mpirun -np 2" np2 mpirun_np 2 "$BIN" -j 1
    variant "mpirun -np 3 --band 1" np3 mpirun_np 3 "$BIN" -j 1 --band 1
    variant "mpirun -np 4 --band 5 -j 2" np4 mpirun_np 4 "$BIN" -j 2 --band 5
    variant "mpirun -np 3 --passes 3 --band 2" np3p mpirun_np 3 "$BIN" -j 1 --passes 3 --band 2
    # 5 ranks want more units (16 each) than the 64 rows: tiles, or sample
    # ranges whose pixels take their counts from their pilots.
    variant "mpirun -np 5, tiles" np5c mpirun_np 5 "$BIN" -j 1 --split columns
    variant "mpirun -np 5, sample ranges" np5s mpirun_np 5 "$BIN" -j 1 --split samples
    # Fewer rows than the ranks want units: rows split into sample ranges,
    # each unit computes its pixels' counts from their pilots.
    S=(--width 96 --height 4 -s 64 --noise-threshold 0.05 -q)
    "$BIN" "${S[@]}" -j 1 -o "$WORK/few.png" >/dev/null
    mpirun_np 3 "$BIN" "${S[@]}" -j 1 --band 1 -o "$WORK/few3.png" >/dev/null
    cmp -s "$WORK/few.png" "$WORK/few3.png" && pass "4 rows on 3 ranks: identical" || fail "4 rows on 3 ranks differ"
else
    skip "mpirun variants: no mpirun"
fi

# The samples: the map (count / 64 per pixel, linear), the summary line and
# --stats tell the same, and the threshold did stop pixels early.
python3 - "$WORK" <<'PY' && pass "map, summary and --stats agree on the samples" || fail "samples accounting"
import json, re, struct, sys
w = sys.argv[1]
f = open(w + "/ref.spp.pfm", "rb")
assert f.readline().strip() == b"PF"
width, height = map(int, f.readline().split())
scale = float(f.readline())
v = struct.unpack(("<" if scale < 0 else ">") + "%df" % (width * height * 3), f.read())
counts = [round(v[3 * i] * 64) for i in range(width * height)]
assert all(c in (16, 32, 64) for c in counts), sorted(set(counts))
mean = sum(counts) / len(counts)
st = json.load(open(w + "/ref.json"))["adaptive"]
by = st["pixels_by_samples"]
print("map mean %.4f, stats %s" % (mean, st))
assert st["noise_threshold"] == 0.05
assert abs(st["mean_samples_per_pixel"] - mean) < 1e-9
assert {int(k): n for k, n in by.items()} == {c: counts.count(c) for c in (16, 32, 64)}
assert counts.count(16) > 0 and counts.count(64) > 0 and mean < 60
line = open(w + "/ref.out").read()
m = re.search(r"^adaptive: +([0-9.]+) samples per pixel", line, re.M)
assert m and abs(float(m.group(1)) - mean) < 0.05, m
PY

# The buffers change no pixel of the image; the threshold does.
"$BIN" "${A[@]:0:8}" -q -j 2 -o "$WORK/noaov.png" >/dev/null
cmp -s "$WORK/noaov.png" "$WORK/ref.png" && pass "without --aov: the same image" || fail "--aov changed the image"
"$BIN" --width 96 --height 64 -s 64 -q -j 2 -o "$WORK/full.png" >/dev/null
cmp -s "$WORK/full.png" "$WORK/ref.png" && fail "the threshold changed nothing" || pass "the threshold changes the image"
# An .exr output takes its buffers as .exr files.
if "$BIN" --version | grep -qw exr; then
    "$BIN" --width 32 --height 16 -s 4 -q --aov normal -o "$WORK/e.exr" >/dev/null
    [ -s "$WORK/e.normal.exr" ] && [ ! -e "$WORK/e.albedo.exr" ] && pass "--aov normal beside e.exr: e.normal.exr" ||
        fail "--aov with .exr: $(ls "$WORK" | grep '^e\.')"
fi

# Resume: stopped after its first checkpoint, the run ends with the same bytes.
R=(--width 160 --height 96 -s 1024 --noise-threshold 0.01 --aov albedo -q)
"$BIN" "${R[@]}" -j 2 -o "$WORK/rref.png" --stats "$WORK/rref.json" >/dev/null
"$BIN" "${R[@]}" -j 2 -o "$WORK/r.png" --checkpoint-interval 0 >/dev/null 2>&1 &
pid=$!
for ((i = 0; i < 600; i++)); do [ -s "$WORK/r.png.ckpt" ] && break; sleep 0.1; done
kill -TERM $pid
wait $pid
check_eq "stopped run's exit status" $? 75
"$BIN" "${R[@]}" -j 1 -o "$WORK/r.png" --noise-threshold 0.02 --resume >/dev/null 2>"$WORK/r.err"
check_eq "a resume with another threshold is refused (exit status)" $? 3
grep -q "noise threshold" "$WORK/r.err" && pass "the refusal names the threshold" || fail "refusal: $(cat "$WORK/r.err")"
"$BIN" "${R[@]}" -j 1 -o "$WORK/r.png" --resume --stats "$WORK/r.json" >"$WORK/r.out" 2>&1
check_eq "resume exit status" $? 0
rendered_only_missing "adaptive resume" "$WORK/r.out" "$WORK/r.json" "$WORK/rref.json"
cmp -s "$WORK/r.png" "$WORK/rref.png" && cmp -s "$WORK/r.albedo.pfm" "$WORK/rref.albedo.pfm" &&
    pass "resumed image and albedo identical" || fail "resumed files differ"
# A progressive run stopped after a checkpoint, resumed without passes.
"$BIN" "${R[@]}" -j 2 --passes 5 -o "$WORK/rp.png" --checkpoint-interval 0 >/dev/null 2>&1 &
pid=$!
for ((i = 0; i < 600; i++)); do [ -s "$WORK/rp.png.ckpt" ] && break; sleep 0.1; done
kill -TERM $pid
wait $pid
check_eq "stopped progressive run's exit status" $? 75
"$BIN" "${R[@]}" -j 2 -o "$WORK/rp.png" --resume --stats "$WORK/rp.json" >"$WORK/rp.out" 2>&1
rendered_only_missing "adaptive progressive resume" "$WORK/rp.out" "$WORK/rp.json" "$WORK/rref.json"
cmp -s "$WORK/rp.png" "$WORK/rref.png" && cmp -s "$WORK/rp.albedo.pfm" "$WORK/rref.albedo.pfm" &&
    pass "progressive run resumed: identical" || fail "progressive run resumed: files differ"

# Bad combinations: one line, exit status 2, no file.
OUT="$WORK/out/o.png"
expect_usage_error "threshold 0" "--noise-threshold: '0' is not a number above 0" "$BIN" --noise-threshold 0 -o "$OUT"
expect_usage_error "threshold junk" "--noise-threshold: '0.1x'" "$BIN" --noise-threshold 0.1x -o "$OUT"
expect_usage_error "map without threshold" "--spp-map: the samples per pixel vary only" \
    "$BIN" --spp-map "$WORK/out/m.png" -o "$OUT"
expect_usage_error "unknown buffer" "--aov: 'depth' is not albedo or normal" "$BIN" --aov albedo,depth -o "$OUT"
finish
