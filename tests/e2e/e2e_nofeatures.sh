#!/bin/bash
# e2e_nofeatures.sh SOURCE_DIR BUILD_DIR FULL_BIN
# A site without OpenEXR, cJSON and libjpeg-turbo: configures a second, small build in
# BUILD_DIR (OpenEXR hidden from find_package, cJSON and JPEG turned off; no LTO,
# no tests, only the rt-mpi target), and checks that it builds, links
# neither library, says what it lacks in --version, refuses .exr output and
# every option that needs JSON with one line naming the feature and how to
# get it (exit 2, no file), and renders a PNG with the full build's hash.
SRC=$1 NOFEAT=$2 FULL=$3
source "$(dirname "$0")/../support/lib.sh"

if ! cmake -S "$SRC" -B "$NOFEAT" -DCMAKE_BUILD_TYPE=Release -DRT_LTO=OFF -DBUILD_TESTING=OFF \
        -DCMAKE_DISABLE_FIND_PACKAGE_OpenEXR=ON -DRT_WITH_CJSON=OFF -DRT_WITH_JPEG=OFF >"$WORK/configure.log" 2>&1; then
    fail "configure without OpenEXR and cJSON: $(tail -5 "$WORK/configure.log")"
    finish
fi
pass "configures without OpenEXR and cJSON"
grep -q "OpenEXR output OFF .*cJSON OFF .*JPEG textures OFF " "$WORK/configure.log" &&
    pass "configure says: $(grep 'OpenEXR output' "$WORK/configure.log" | sed 's/^-- //')" ||
    fail "configure does not report the features: $(grep 'rt-mpi' "$WORK/configure.log")"
if ! nice cmake --build "$NOFEAT" -j 2 --target rt-mpi >"$WORK/build.log" 2>&1; then
    fail "build without OpenEXR and cJSON: $(grep -m5 -i error "$WORK/build.log")"
    finish
fi
BIN=$NOFEAT/rt-mpi
pass "builds without OpenEXR and cJSON"
libs=$(ldd "$BIN" | grep -ci 'libcjson\|libopenexr\|libjpeg')
check_eq "links none of cJSON, OpenEXR, libjpeg (libraries found by ldd)" "$libs" 0
check_eq "--version features" "$("$BIN" --version | sed -n 's/^features: //p')" "mpi openmp png"
check_eq "the full build's features" "$("$FULL" --version | sed -n 's/^features: //p')" "mpi openmp png exr json jpeg"

A=(--width 24 --height 16 -s 2 -q --no-checkpoint)
O="$WORK/out"
expect_usage_error ".exr output" "--output '$O/x.exr': this rt-mpi was built without OpenEXR (feature 'exr'): install OpenEXR 3 (Debian: apt-get install libopenexr-dev) and rebuild" \
    "$BIN" "${A[@]}" -o "$O/x.exr"
expect_usage_error ".exr preview" "--preview '$O/p.exr': this rt-mpi was built without OpenEXR" \
    "$BIN" "${A[@]}" --passes 2 --preview "$O/p.exr" -o "$O/x.png"
JSONMSG="this rt-mpi was built without JSON support (feature 'json'): install cJSON (Debian: apt-get install libcjson-dev) and rebuild"
expect_usage_error "--scene-file" "--scene-file: $JSONMSG" "$BIN" "${A[@]}" --scene-file "$SRC/scenes/example.json" -o "$O/x.png"
expect_usage_error "positional scene file" "scene file: $JSONMSG" "$BIN" "${A[@]}" "$SRC/scenes/example.json" -o "$O/x.png"
expect_usage_error "--dump-scene" "--dump-scene: $JSONMSG" "$BIN" --dump-scene "$O/s.json"
expect_usage_error "--stats" "--stats: $JSONMSG" "$BIN" "${A[@]}" -o "$O/x.png" --stats "$O/s.json"
expect_usage_error "--trace" "--trace: $JSONMSG" "$BIN" "${A[@]}" -o "$O/x.png" --trace "$O/t.json"

# What it has still works, and makes the same image.
hash_of() { sed -n 's/^image hash: *//p' "$1"; }
"$BIN" "${A[@]}" -o "$WORK/n.png" >"$WORK/n.out" 2>&1
"$FULL" "${A[@]}" -o "$WORK/f.png" >"$WORK/f.out" 2>&1
check_eq "PNG render: same hash as the full build" "$(hash_of "$WORK/n.out")" "$(hash_of "$WORK/f.out")"
cmp -s "$WORK/n.png" "$WORK/f.png" && pass "same PNG bytes as the full build" || fail "the PNG differs from the full build's"
"$BIN" "${A[@]}" -o "$WORK/n.pfm" >/dev/null 2>&1 && [ -s "$WORK/n.pfm" ] && pass ".pfm (linear float) still written" ||
    fail ".pfm not written"
finish
