#!/bin/bash
# e2e_camera_keys.sh BIN MPIRUN
# A scene file whose camera moves by keyframes (camera_keys): every frame
# of a range byte-identical to that frame alone (--frame N), on one rank
# and on two; frames between keys differ from the keys'; --turntable on
# such a file is refused with one line, exit 2 and nothing written.
BIN=$1 MPIRUN=${2:-}
source "$(dirname "$0")/../support/lib.sh"

# book 1's materials scene, its camera keyed over 4 frames (a dolly to the right)
"$BIN" --scene materials --dump-scene "$WORK/plain.json" >/dev/null 2>&1 || fail "--dump-scene materials"
sed 's/^{/{"camera_keys": [{"frame": 0, "lookfrom": [3, 1, 4], "lookat": [0, 0, -1]}, {"frame": 4, "lookfrom": [-3, 1, 4], "lookat": [0, 0, -1]}],/' \
    "$WORK/plain.json" >"$WORK/keys.json"
grep -q camera_keys "$WORK/keys.json" || fail "the test's scene file has no keys"
A=("$WORK/keys.json" --width 40 --height 24 -s 4 -q)

expect_refusal 2 "--turntable on a keyed scene" "animates its camera" "$BIN" "${A[@]}" --frames 0-2 --turntable 90:4 \
    -o "$WORK/refused_#.png"

for f in 0 1 2 3; do
    "$BIN" "${A[@]}" -j 1 --frame "$f" -o "$WORK/alone_####.png" >/dev/null 2>"$WORK/err" ||
        fail "--frame $f alone: $(head -c 300 "$WORK/err")"
done
cmp -s "$WORK/alone_0000.png" "$WORK/alone_0001.png" && fail "frames 0 and 1 of the keyed camera are the same" ||
    pass "frames 0 and 1 of the keyed camera differ"
same() { # label launcher-and-args...
    local label=$1 n=0 f
    shift
    rm -f "$WORK"/seq_*.png
    "$@" "${A[@]}" --frames 0-3 -o "$WORK/seq_#.png" >/dev/null 2>"$WORK/err" || {
        fail "$label: $(head -c 300 "$WORK/err")"
        return
    }
    for f in 0 1 2 3; do cmp -s "$WORK/seq_$f.png" "$WORK/alone_000$f.png" && n=$((n + 1)); done
    check_eq "$label: frames identical to --frame N alone" "$n of 4" "4 of 4"
}
same "keyed camera -j 2" "$BIN" -j 2
if [ -n "$MPIRUN" ]; then
    same "keyed camera -np 2 --band 2" mpirun_np 2 "$BIN" -j 1 --band 2
else
    skip "mpirun not found: keyed frames over ranks"
fi
finish
