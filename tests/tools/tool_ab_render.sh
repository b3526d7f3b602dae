#!/bin/bash
# tool_ab_render.sh ROOT: tools/ab_render.sh, the whole-render A/B timing of
# the working tree against a git revision, builds both and runs: against HEAD
# it prints both rates, their ratio and, when no source differs from HEAD,
# "images: identical"; an unknown revision is refused. (Timings are printed,
# never checked.)
ROOT=$1
source "$(dirname "$0")/../support/lib.sh"
export AB_RENDER_DIR="$WORK/ab"
AB=(bash "$ROOT/tools/ab_render.sh")
"${AB[@]}" HEAD --rounds 1 --width 40 --height 26 -s 2 >"$WORK/same.out" 2>&1
check_eq "against HEAD: exit status" $? 0
cat "$WORK/same.out"
for line in "A (working tree)" "B (HEAD = " "A / B speed"; do
    grep -q "$line" "$WORK/same.out" && pass "prints '$line'" || fail "no '$line' in the output"
done
if git -C "$ROOT" diff --quiet HEAD -- src CMakeLists.txt; then
    grep -q "images: identical" "$WORK/same.out" && pass "HEAD's sources give the same image" ||
        fail "HEAD against itself: $(grep images "$WORK/same.out")"
else
    echo "NOTE: src/ differs from HEAD here: the image comparison is not checked"
fi
"${AB[@]}" no-such-revision --rounds 1 >"$WORK/bad.out" 2>&1
check_eq "unknown revision: exit status" $? 2
grep -q "no git revision 'no-such-revision'" "$WORK/bad.out" && pass "names the bad revision" ||
    fail "bad revision: $(cat "$WORK/bad.out")"
finish
