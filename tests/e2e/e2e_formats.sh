#!/bin/bash
# e2e_formats.sh BIN IMGREAD CONVERT [MPIRUN]
# One render written as 8-bit PNG, binary and ASCII PPM, 16-bit PPM and PNG,
# BMP, PFM and EXR: every run prints the same image hash, and
# formats_check.py reads each file back with an independent reader (its own
# parsers, ImageMagick, libpng, OpenEXR) and compares the pixels with the
# PNG's. Then the refusals: unknown extension, options that do not fit.
BIN=$1 IMGREAD=$2 CONVERT=${3:-convert} MPIRUN=${4:-}
source "$(dirname "$0")/../support/lib.sh"
ARGS=(--scene materials --width 67 --height 41 -s 8 -j 2 -q)
D="$WORK/img"
mkdir -p "$D"
echo "67 41" >"$D/size.txt"

hash_of() { sed -n 's/^image hash: *//p' "$1"; }
render() { # file extra-args...
    local f=$1
    shift
    if "$BIN" "${ARGS[@]}" "$@" -o "$D/$f" >"$WORK/$f.out" 2>"$WORK/$f.err"; then
        check_eq "$f: renders the same image (hash of the sums, not of the file: formats_check.py reads the files)" "$(hash_of "$WORK/$f.out")" "$(hash_of "$WORK/ref.png.out")"
    else
        fail "$f: exit status $? ($(head -c 300 "$WORK/$f.err"))"
    fi
}
"$BIN" "${ARGS[@]}" -o "$D/ref.png" >"$WORK/ref.png.out"
check_eq "reference PNG run" $? 0
render p6.ppm
render p3.ppm --ppm-ascii
render p6_16.ppm --bit-depth 16
render a16.png --bit-depth 16
render out.bmp
render out.pfm
render out.exr
ls "$D" | grep -q '\.tmp\.' && fail "a temporary file was left behind" || pass "no temporary files"
# Under MPI every format is the same file byte for byte.
if [ -n "$MPIRUN" ]; then
    for f in p6.ppm out.bmp out.pfm out.exr; do
        mpirun_np 2 "$BIN" "${ARGS[@]}" -j 1 -o "$WORK/mpi-$f" >/dev/null 2>&1
        cmp -s "$WORK/mpi-$f" "$D/$f" && pass "$f: mpirun -np 2 writes the same bytes" || fail "$f: mpirun -np 2 differs"
    done
else
    skip "formats under mpirun: no mpirun"
fi

# ImageMagick (the real one: convert as a package installs it) decodes the
# 8-bit files; libpng and OpenEXR decode the 16-bit PNG and the EXR.
for f in ref:ref.png p6:p6.ppm p3:p3.ppm bmp:out.bmp; do
    "$CONVERT" "$D/${f#*:}" -depth 8 "rgb:$D/im_${f%%:*}.rgb" || fail "ImageMagick could not read ${f#*:}"
done
identify -format '%m %w %h' "$D/out.bmp" >"$WORK/id.txt" 2>&1 && grep -q "^BMP3\? 67 41" "$WORK/id.txt" &&
    pass "identify: $(cat "$WORK/id.txt")" || fail "identify out.bmp: $(cat "$WORK/id.txt")"
"$IMGREAD" png16 "$D/a16.png" "$D/png16.raw" || fail "libpng could not read the 16-bit PNG"
"$IMGREAD" exr "$D/out.exr" "$D/exr.raw" || fail "OpenEXR could not read the EXR"
if python3 "$(dirname "$0")/formats_check.py" "$D" >"$WORK/check.txt" 2>&1; then
    pass "formats_check.py: $(tail -1 "$WORK/check.txt")"
else
    fail "formats_check.py:"
fi
grep -v '^[0-9]* passed' "$WORK/check.txt" | sed 's/^/  /'

# Progressive passes: previews go out in the format their extension names,
# and the final file is the same as from one pass.
"$BIN" "${ARGS[@]}" --passes 2 -o "$D/prog.exr" >"$WORK/prog.out" 2>&1 &&
    cmp -s "$D/prog.exr" "$D/out.exr" && pass "--passes 2 -o .exr: same file as one pass" ||
    fail "--passes 2 -o .exr: $(head -c 300 "$WORK/prog.out")"
"$BIN" "${ARGS[@]}" --passes 3 --preview "$D/prev.pfm" -o "$D/prog.png" >"$WORK/prog.out" 2>&1
check_eq "--passes 3 --preview .pfm: image hash" "$(hash_of "$WORK/prog.out")" "$(hash_of "$WORK/ref.png.out")"
check_eq "the preview is a PFM of the image's size" "$(head -3 "$D/prev.pfm" | tr '\n' ' ')$(stat -c %s "$D/prev.pfm")" \
    "PF 67 41 -1.0 $((14 + 67 * 41 * 12))"

O="$WORK/out"
expect_usage_error "unknown extension" "--output: unsupported file type '.tiff' (supported: .png, .ppm, .bmp, .pfm, .exr)" \
    "$BIN" "${ARGS[@]}" -o "$O/x.tiff"
expect_usage_error "no extension" "--output: unsupported file type 'image'" "$BIN" "${ARGS[@]}" -o "$O/image"
expect_usage_error "16-bit BMP" "--bit-depth 16: .bmp files are written with 8 bits per channel only" \
    "$BIN" "${ARGS[@]}" --bit-depth 16 -o "$O/x.bmp"
expect_usage_error "16-bit EXR" "--bit-depth 16: .exr files are written as 32-bit float" \
    "$BIN" "${ARGS[@]}" --bit-depth 16 -o "$O/x.exr"
expect_usage_error "ASCII PNG" "--ppm-ascii: --output '.*x.png' is not a .ppm file" \
    "$BIN" "${ARGS[@]}" --ppm-ascii -o "$O/x.png"
expect_usage_error "bit depth 12" "--bit-depth: '12' is not 8 or 16" "$BIN" "${ARGS[@]}" --bit-depth 12 -o "$O/x.png"
expect_usage_error "unknown preview extension" "--preview: unsupported file type '.tiff'" \
    "$BIN" "${ARGS[@]}" --passes 2 --preview "$O/p.tiff" -o "$O/x.png"
expect_usage_error "16-bit BMP preview" "--bit-depth 16: .bmp files are written with 8 bits per channel only" \
    "$BIN" "${ARGS[@]}" --passes 2 --bit-depth 16 --preview "$O/p.bmp" -o "$O/x.png"
finish
