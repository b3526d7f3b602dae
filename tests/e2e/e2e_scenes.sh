#!/bin/bash
# e2e_scenes.sh BIN PNGINFO MPIRUN SOURCE_DIR
# --list-scenes; every named scene renders; --dump-scene writes the scene
# and renders nothing; dump -> load -> dump is byte-identical and the
# loaded dump renders the same pixels with the same scene hash, also under
# mpirun; the committed example renders; bad scene files are bad input.
BIN=$1 PNGINFO=$2 MPIRUN=${3:-} SRC=$4
source "$(dirname "$0")/../support/lib.sh"
ARGS=(--width 48 --height 27 -s 4 -j 2 -q)

"$BIN" --list-scenes >"$WORK/list.txt" 2>"$WORK/list.err"
check_eq "--list-scenes exit status" $? 0
check_eq "--list-scenes names by book, one line each" \
    "$(awk '/^[A-Z]/ {print "[" $NF "]"} /^  [a-z]/ {print $1}' "$WORK/list.txt" | tr '\n' ' ')" \
    "[1):] final diffuse materials defocus [2):] bouncing-spheres checkered-spheres earth perlin-spheres quads simple-light cornell-box cornell-smoke book2-final [3):] book3-final "
[ ! -s "$WORK/list.err" ] && [ "$(awk '/^  [a-z]/ && NF < 3' "$WORK/list.txt" | wc -l)" -eq 0 ] &&
    pass "--list-scenes: each scene has a description" || fail "--list-scenes output: $(cat "$WORK/list.txt")"

summary() { sed -n "s/^$2: *//p" "$1"; }
hashes=""
for s in final diffuse materials defocus; do
    if "$BIN" "${ARGS[@]}" --scene $s -o "$WORK/$s.png" >"$WORK/$s.out" 2>"$WORK/$s.err"; then
        pass "--scene $s renders: $(summary "$WORK/$s.out" scene)"
    else
        fail "--scene $s: $(head -c 300 "$WORK/$s.err")"
    fi
    hashes+="$(summary "$WORK/$s.out" "image hash") "
    # dump -> load -> dump is byte-identical; --dump-scene renders nothing.
    "$BIN" "${ARGS[@]}" --scene $s --dump-scene "$WORK/$s.json" -o "$WORK/none.png" >"$WORK/d.out" 2>&1
    check_eq "--scene $s --dump-scene exit status" $? 0
    [ ! -e "$WORK/none.png" ] && [ ! -s "$WORK/d.out" ] && pass "--dump-scene wrote no image, printed nothing" ||
        fail "--dump-scene rendered or printed: $(head -c 200 "$WORK/d.out")"
    "$BIN" --scene-file "$WORK/$s.json" --dump-scene "$WORK/$s.2.json"
    cmp -s "$WORK/$s.json" "$WORK/$s.2.json" && pass "$s: dump -> load -> dump byte-identical" ||
        fail "$s: the second dump differs"
    # The loaded dump is the same scene and the same image.
    "$BIN" "${ARGS[@]}" --scene-file "$WORK/$s.json" -o "$WORK/$s.file.png" >"$WORK/$s.file.out" 2>&1
    check_eq "$s from its dump: scene hash" "$(summary "$WORK/$s.file.out" scene | sed 's/.*hash //')" \
        "$(summary "$WORK/$s.out" scene | sed 's/.*hash //')"
    check_eq "$s from its dump: decoded pixels" "$("$PNGINFO" "$WORK/$s.file.png")" "$("$PNGINFO" "$WORK/$s.png")"
done
check_eq "four scenes, four different images" "$(echo $hashes | tr ' ' '\n' | sort -u | wc -l)" 4

# The seeded final scene of another seed and grid round-trips too.
"$BIN" --seed 7 --grid 3 --dump-scene "$WORK/f7.json" && "$BIN" --scene-file "$WORK/f7.json" --dump-scene "$WORK/f7b.json"
cmp -s "$WORK/f7.json" "$WORK/f7b.json" && pass "final --seed 7 --grid 3: dump round trip" || fail "f7 dumps differ"
# ... and renders as the seeded scene does, given the same --seed (it also
# keys the sampling).
"$BIN" "${ARGS[@]}" --seed 7 --grid 3 -o "$WORK/f7.png" >/dev/null 2>&1
"$BIN" "${ARGS[@]}" --seed 7 --scene-file "$WORK/f7.json" -o "$WORK/f7file.png" >/dev/null 2>&1
check_eq "final --seed 7 --grid 3 from its dump: decoded pixels" "$("$PNGINFO" "$WORK/f7file.png")" "$("$PNGINFO" "$WORK/f7.png")"
if [ -n "$MPIRUN" ]; then
    mpirun_np 2 "$BIN" "${ARGS[@]}" -j 1 --scene-file "$WORK/defocus.json" -o "$WORK/mpi.png" >"$WORK/mpi.out" 2>&1
    check_eq "mpirun -np 2 --scene-file: same pixels" "$("$PNGINFO" "$WORK/mpi.png")" "$("$PNGINFO" "$WORK/defocus.png")"
    mpirun_np 2 "$BIN" --list-scenes >"$WORK/mlist.txt" 2>&1
    check_eq "mpirun -np 2 --list-scenes prints once" "$(wc -l <"$WORK/mlist.txt")" "$(wc -l <"$WORK/list.txt")"
else
    skip "scene files under mpirun: no mpirun"
fi

# The committed example (README) renders.
"$BIN" "${ARGS[@]}" --scene-file "$SRC/scenes/example.json" -o "$WORK/example.png" >"$WORK/ex.out" 2>&1
check_eq "scenes/example.json renders" $? 0

# Bad scene files: exit 2, one message naming file, field and problem,
# nothing rendered (no image file), on one rank and under mpirun.
O="$WORK/out"
bad() { # name json
    printf '%s' "$2" >"$WORK/$1"
}
CAM='"camera": {"lookfrom": [0, 0, 0], "lookat": [0, 0, -1]}'
bad radius.json "{$CAM, \"materials\": [{\"type\": \"lambertian\", \"albedo\": [0.5, 0.5, 0.5]}], \"spheres\": [
  {\"center\": [0, 0, -1], \"radius\": 0.5, \"material\": 0},
  {\"center\": [0, 0, -1], \"radius\": 0.5, \"material\": 0},
  {\"center\": [0, 0, -1], \"radius\": 0.5, \"material\": 0},
  {\"center\": [0, 0, -1], \"radius\": \"big\", \"material\": 0}]}"
bad syntax.json "{$CAM, \"spheres\": [}"
bad field.json "{$CAM, \"spheres\": [], \"lights\": []}"
expect_usage_error "scene file: wrong type" "$WORK/radius.json: spheres\[3\].radius: expected a number$" \
    "$BIN" "${ARGS[@]}" --scene-file "$WORK/radius.json" -o "$O/x.png"
expect_usage_error "scene file: bad JSON" "$WORK/syntax.json: line 1, column [0-9]*: invalid JSON$" \
    "$BIN" "${ARGS[@]}" --scene-file "$WORK/syntax.json" -o "$O/x.png"
expect_usage_error "scene file: unknown field" "$WORK/field.json: lights: unknown field" \
    "$BIN" "${ARGS[@]}" --scene-file "$WORK/field.json" -o "$O/x.png"
expect_usage_error "scene file: missing" "$WORK/nope.json: cannot read: No such file or directory$" \
    "$BIN" "${ARGS[@]}" --scene-file "$WORK/nope.json" -o "$O/x.png"
expect_usage_error "scene file: dump of a bad file" "$WORK/radius.json: spheres\[3\].radius" \
    "$BIN" --scene-file "$WORK/radius.json" --dump-scene "$O/x.json"
expect_usage_error "unknown scene" "--scene: no scene named 'cornell' (see --list-scenes)$" \
    "$BIN" "${ARGS[@]}" --scene cornell -o "$O/x.png"
expect_usage_error "--scene with --scene-file" "--scene and --scene-file: give one or the other$" \
    "$BIN" "${ARGS[@]}" --scene final --scene-file "$WORK/defocus.json" -o "$O/x.png"
expect_usage_error "--dump-scene into a missing directory" "--dump-scene: cannot write" \
    "$BIN" --dump-scene "$O/nodir/x.json"
if [ -n "$MPIRUN" ]; then
    # mpirun adds its own banner; rt-mpi's message must appear once.
    mpirun_np 2 "$BIN" "${ARGS[@]}" -j 1 --scene-file "$WORK/radius.json" -o "$O/x.png" >"$WORK/m.out" 2>"$WORK/m.err"
    status=$?
    n=$(grep -c "^rt-mpi: error: $WORK/radius.json: spheres\[3\].radius: expected a number$" "$WORK/m.err")
    [ $status -eq 2 ] && [ "$n" -eq 1 ] && [ "$(grep -c '^rt-mpi:' "$WORK/m.err")" -eq 1 ] && [ ! -e "$O/x.png" ] &&
        pass "scene file error under mpirun -np 2: status 2, one message, no image" ||
        fail "scene file error under mpirun -np 2: status $status, $n messages: $(head -c 300 "$WORK/m.err")"
else
    skip "scene file error under mpirun: no mpirun"
fi
finish
