#!/bin/bash
# e2e_book2.sh BIN PNGINFO MPIRUN
# Book 2's scenes: each renders; the same pixels for any -j, -np, --band,
# --split, --passes, both samplers, and across an interrupt and --resume;
# adaptive sampling and the denoiser's buffers work; the earth's texture
# comes from --texture-dir, and a missing or bad one is bad input.
BIN=$1 PNGINFO=$2 MPIRUN=${3:-}
source "$(dirname "$0")/../support/lib.sh"
px() { "$PNGINFO" "$1"; }

# An earth texture of our own (a JPEG gradient), as earthmap.jpg.
/usr/bin/python3 -c "
from PIL import Image
im = Image.new('RGB', (64, 32))
im.putdata([(4 * x, 8 * y, 128) for y in range(32) for x in range(64)])
im.save('$WORK/earthmap.jpg', quality=90)" || fail "could not write a test JPEG"
T=(--texture-dir "$WORK")

for s in bouncing-spheres checkered-spheres earth perlin-spheres quads simple-light cornell-box cornell-smoke \
    book2-final; do
    if "$BIN" --scene $s "${T[@]}" --width 40 -s 4 -j 2 -q -o "$WORK/$s.png" >"$WORK/$s.out" 2>"$WORK/$s.err"; then
        pass "--scene $s renders: $(sed -n 's/^image: *//p' "$WORK/$s.out")"
    else
        fail "--scene $s: $(head -c 300 "$WORK/$s.err")"
    fi
done
# The book's settings are the scene's defaults; a width alone keeps its aspect.
check_eq "cornell-box's own size, samples and depth" "$(sed -n 's/^image: *//p' "$WORK/cornell-box.out")" \
    "40x40, 4 spp, max depth 50, seed 42"
# Every scene dumped: dump -> load -> dump is byte-identical, and the dump
# renders the same scene (hash) and the same image as the named scene; the
# earth's image is referred to by a path relative to the dump.
mkdir -p "$WORK/dumps"
hash_of() { sed -n "s/^$2: *//p" "$1" | sed 's/.*hash //'; }
for s in bouncing-spheres checkered-spheres earth perlin-spheres quads simple-light cornell-box cornell-smoke \
    book2-final; do
    D="$WORK/dumps/$s.json" A=(--width 24 --height 16 -s 2 --max-depth 6 -j 2 -q)
    "$BIN" --scene $s "${T[@]}" --dump-scene "$D" 2>"$WORK/d.err" || { fail "$s --dump-scene: $(cat "$WORK/d.err")"; continue; }
    (cd "$WORK/dumps" && "$BIN" --scene-file "$s.json" --dump-scene "$s.2.json") 2>"$WORK/d.err"
    cmp -s "$D" "$WORK/dumps/$s.2.json" && pass "$s: dump -> load -> dump byte-identical" ||
        fail "$s: the second dump differs $(cat "$WORK/d.err")"
    "$BIN" --scene $s "${T[@]}" "${A[@]}" -o "$WORK/n.png" >"$WORK/n.out" 2>&1
    "$BIN" --scene-file "$D" "${A[@]}" -o "$WORK/f.png" >"$WORK/f.out" 2>&1
    check_eq "$s from its dump: scene hash" "$(hash_of "$WORK/f.out" scene)" "$(hash_of "$WORK/n.out" scene)"
    check_eq "$s from its dump: image hash" "$(hash_of "$WORK/f.out" "image hash")" "$(hash_of "$WORK/n.out" "image hash")"
done
grep -q '"path": "../earthmap.jpg"' "$WORK/dumps/earth.json" && pass "the earth's dump refers to ../earthmap.jpg" ||
    fail "earth.json: $(grep path "$WORK/dumps/earth.json")"

# One image, many ways to cut the work: every result has the same pixels.
same_as() { # label ref.png cmd...
    local label=$1 ref=$2
    shift 2
    "$@" -q -o "$WORK/t.png" >/dev/null 2>"$WORK/t.err" || { fail "$label: $(head -c 300 "$WORK/t.err")"; return; }
    check_eq "$label: same pixels" "$(px "$WORK/t.png")" "$(px "$ref")"
}
# Lit scenes sample their lights (a quad; a quad and a sphere in
# simple-light; through media in cornell-smoke and book2-final), or not.
for s in book2-final cornell-smoke bouncing-spheres simple-light "cornell-smoke --no-light-sampling" \
    cornell-box "cornell-box --no-light-sampling" quads; do
    A=(--scene $s "${T[@]}" --width 48 --height 36 -s 8 --max-depth 12)
    for sm in sobol random; do
        "$BIN" "${A[@]}" --sampler $sm -j 1 -q -o "$WORK/ref-$s-$sm.png" >/dev/null 2>&1
        same_as "$s $sm -j 2 --band 1" "$WORK/ref-$s-$sm.png" "$BIN" "${A[@]}" --sampler $sm -j 2 --band 1
    done
    R="$WORK/ref-$s-sobol.png"
    same_as "$s --passes 3" "$R" "$BIN" "${A[@]}" -j 2 --passes 3
    if [ -n "$MPIRUN" ]; then
        same_as "$s mpirun -np 3" "$R" mpirun_np 3 "$BIN" "${A[@]}" -j 1
        same_as "$s mpirun -np 4 --split samples" "$R" mpirun_np 4 "$BIN" "${A[@]}" -j 1 --split samples --band 36
        same_as "$s mpirun -np 5 --split columns" "$R" mpirun_np 5 "$BIN" "${A[@]}" -j 1 --split columns --band 36
    else
        skip "book 2 under mpirun: no mpirun"
    fi
done
# The world's walk and brute force give the same image, also where the
# glass spheres' rooms answer without the walk (world_rooms.c): book2-final's
# smoke in a glass sphere, book3-final's glass sphere.
# So do the paths eight at a time in AVX-512 lanes (path_lanes.c), which
# quads-only scenes run on CPUs that have them, with light sampling or not.
for item in book2-final book3-final cornell-box quads cornell-box-lit; do
    s=${item%-lit} ls=--no-light-sampling
    [ "$item" = "$s" ] || ls="" # -lit: with light sampling, the scene's default
    A=(--scene "$s" "${T[@]}" --width 32 --height 24 -s 4 --max-depth 40 $ls)
    "$BIN" "${A[@]}" -j 2 -o "$WORK/walk-$item.png" >"$WORK/walk-$item.out" 2>&1
    same_as "$item --accel brute" "$WORK/walk-$item.png" "$BIN" "${A[@]}" -j 2 --accel brute
done
if grep -q avx512dq /proc/cpuinfo; then
    for s in cornell-box quads cornell-box-lit; do
        grep -q "avx-512 paths 8 a register" "$WORK/walk-$s.out" && pass "$s: paths in AVX-512 lanes" ||
            fail "$s: not in the lanes: $(grep intersector "$WORK/walk-$s.out")"
    done
    grep -q "avx-512 paths" "$WORK/walk-book2-final.out" && fail "book2-final in the lanes" ||
        pass "book2-final: not in the lanes (its spheres and media)"
else
    skip "the AVX-512 lanes: this CPU has no AVX-512 DQ"
fi
# Adaptive sampling and the buffers run the book-2 loop too.
A=(--scene cornell-smoke --width 48 --height 36 -s 64 --max-depth 12 --noise-threshold 0.05 --aov albedo,normal)
"$BIN" "${A[@]}" -j 1 -q -o "$WORK/ad1.png" >/dev/null 2>&1
same_as "adaptive + aov -j 2" "$WORK/ad1.png" "$BIN" "${A[@]}" -j 2 --band 3
[ -s "$WORK/ad1.albedo.pfm" ] && [ -s "$WORK/ad1.normal.pfm" ] && pass "aov buffers written" || fail "no aov buffers"

# Interrupted and resumed: the same image.
A=(--scene cornell-box --width 96 --height 64 -s 600 --max-depth 20 -q)
"$BIN" "${A[@]}" -j 2 -o "$WORK/full.png" >/dev/null 2>&1
"$BIN" "${A[@]}" -j 2 -o "$WORK/res.png" --checkpoint-interval 0 >/dev/null 2>"$WORK/res.err" &
pid=$!
for ((i = 0; i < 600; i++)); do [ -s "$WORK/res.png.ckpt" ] && break; sleep 0.1; done
kill -TERM $pid
wait $pid
check_eq "cornell-box interrupted: exit status" $? 75
expect_refusal 3 "resumed with --no-light-sampling" "different job (light sampling (0 on, 1 off) 0, this job has 1)" \
    "$BIN" "${A[@]}" --no-light-sampling -j 2 -o "$WORK/res.png" --resume
"$BIN" "${A[@]}" -j 2 -o "$WORK/res.png" --resume >"$WORK/res.out" 2>&1
check_eq "cornell-box resumed: exit status" $? 0
check_eq "cornell-box resumed: same pixels" "$(px "$WORK/res.png")" "$(px "$WORK/full.png")"

# The earth's texture: missing, not an image, truncated.
expect_usage_error "earth without earthmap.jpg" "earthmap.jpg: no such file: scene 'earth' needs the book's earth texture" \
    "$BIN" --scene earth --texture-dir "$WORK/out" --width 32 -s 1 -o "$WORK/out/e.png"
mkdir -p "$WORK/bad" && echo "not an image" >"$WORK/bad/earthmap.jpg"
expect_usage_error "earth: not an image" "bad/earthmap.jpg: not a PNG or JPEG file" \
    "$BIN" --scene book2-final --texture-dir "$WORK/bad" --width 32 -s 1 -o "$WORK/out/e.png"
head -c 300 "$WORK/earthmap.jpg" >"$WORK/bad/earthmap.jpg"
expect_usage_error "earth: truncated JPEG" "bad/earthmap.jpg: image file is truncated" \
    "$BIN" --scene earth --texture-dir "$WORK/bad" --width 32 -s 1 -o "$WORK/out/e.png"

# Scene files with hostile images: one line naming the scene file, the field
# and the image, exit status 2, no image written.
/usr/bin/python3 -c "
from PIL import Image
import zlib
Image.new('CMYK', (8, 8), (0, 50, 100, 0)).save('$WORK/bad/cmyk.jpg')
Image.new('RGB', (8, 8)).save('$WORK/bad/ok.png')
b = bytearray(open('$WORK/bad/ok.png', 'rb').read())
b[b.index(b'IDAT') + 6] ^= 0xFF
open('$WORK/bad/crc.png', 'wb').write(bytes(b))" ||
    fail "could not write the hostile images"
for c in "cmyk.jpg:CMYK JPEG is not supported" "crc.png:PNG chunk with a bad CRC" "missing.png:no such file"; do
    f=${c%%:*}
    printf '{"version": 2, "camera": {"lookfrom": [0, 0, 9], "lookat": [0, 0, 0]}, "textures": [{"type": "image", "path": "%s"}]}' \
        "$f" >"$WORK/bad/$f.json"
    expect_usage_error "scene file with $f" "bad/$f.json: textures\[0\].path: .*bad/$f: ${c#*:}" \
        "$BIN" --scene-file "$WORK/bad/$f.json" --width 8 -s 1 -o "$WORK/out/img.png"
done
[ ! -e "$WORK/out/img.png" ] && pass "no image written for a bad texture" || fail "an image was written"
finish
