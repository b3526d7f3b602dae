#!/bin/bash
# test_install.sh BUILD_DIR BUILT_BIN
# `cmake --install` into a fresh prefix gives a working rt-mpi on PATH, the
# man page (made from --help: every option of the help is in it, and groff
# reads it without a warning), the example scenes and the Slurm script
# under share/rt-mpi, and the docs; the installed Slurm script runs the
# rt-mpi on PATH with the program's own defaults (it passes no image size
# or samples unless told to).
BUILD=$1 BUILT=$2
source "$(dirname "$0")/../support/lib.sh"
P=$WORK/prefix

if ! cmake --install "$BUILD" --prefix "$P" >"$WORK/install.log" 2>&1; then
    fail "cmake --install: $(tail -5 "$WORK/install.log")"
    finish
fi
pass "cmake --install --prefix $P ($(grep -c Installing "$WORK/install.log") files)"
for f in bin/rt-mpi share/rt-mpi/slurm/rt-mpi.sbatch; do
    [ -x "$P/$f" ] && pass "$f (executable)" || fail "$f missing or not executable"
done
for f in share/man/man1/rt-mpi.1 share/rt-mpi/scenes/example.json share/doc/rt-mpi/SCENES_AND_FORMATS.md \
    share/doc/rt-mpi/CONTAINERS.md; do
    [ -s "$P/$f" ] && pass "$f" || fail "$f missing"
done

cmp -s "$P/share/doc/rt-mpi/README.md" "$(dirname "$0")/../../README.md" && pass "share/doc/rt-mpi/README.md" ||
    fail "share/doc/rt-mpi/README.md is not the README"

# The installed program from PATH, on an installed scene.
export PATH="$P/bin:$PATH"
check_eq "rt-mpi on PATH" "$(command -v rt-mpi)" "$P/bin/rt-mpi"
check_eq "--version of the installed program" "$(rt-mpi --version | head -1)" "$("$BUILT" --version | head -1)"
A=(--width 48 --height 32 -s 2 -q --no-checkpoint)
rt-mpi "${A[@]}" "$P/share/rt-mpi/scenes/example.json" -o "$WORK/i.png" >"$WORK/i.out" 2>&1
"$BUILT" "${A[@]}" "$P/share/rt-mpi/scenes/example.json" -o "$WORK/b.png" >"$WORK/b.out" 2>&1
check_eq "installed rt-mpi renders the installed example scene (image hash)" \
    "$(sed -n 's/^image hash: *//p' "$WORK/i.out")" "$(sed -n 's/^image hash: *//p' "$WORK/b.out")"

# The man page: the version, every option of --help, no roff warnings.
MAN=$P/share/man/man1/rt-mpi.1
grep -q "^\.TH RT-MPI 1 .*\"rt-mpi $(rt-mpi --version | sed -n 's/^rt-mpi \([^ ]*\).*/\1/p')\"" "$MAN" &&
    pass "man page names the version" || fail "man page .TH: $(grep '^\.TH' "$MAN")"
missing=""
n=0
for o in $(rt-mpi --help | sed '/^Examples:/,$d' | grep -o -- '--[a-z][a-z-]*' | sort -u); do
    n=$((n + 1))
    grep -qF -- "\\fB$(sed 's/-/\\-/g' <<<"$o")\\fR" "$MAN" || missing+=" $o"
done
check_eq "every option of --help ($n) is an item of the man page; missing:" "${missing:-none}" none
missing=""
for s in OPTIONS EXAMPLES ENVIRONMENT '"EXIT STATUS"'; do
    grep -q "^\.SH $s\$" "$MAN" || missing+=" $s"
done
check_eq "man page sections" "${missing:-none}" none
if command -v groff >/dev/null; then
    warn=$(groff -man -Tutf8 -ww -z "$MAN" 2>&1)
    check_eq "groff -ww: no warnings" "${warn:-none}" none
    groff -man -Tutf8 "$MAN" 2>/dev/null | grep -q "OMP_NUM_THREADS" && pass "man page renders (ENVIRONMENT)" ||
        fail "man page does not render"
else
    skip "man page rendering (no groff: apt-get install groff-base)"
fi

# The installed Slurm script, outside Slurm, with an mpirun that only
# prints what it was given: the rt-mpi on PATH, no size or samples of its
# own (the program's defaults), and those given through RT_WIDTH & co.
mkdir -p "$WORK/fake"
printf '#!/bin/sh\necho "mpirun $*"\n' >"$WORK/fake/mpirun"
chmod +x "$WORK/fake/mpirun"
(cd "$WORK" && PATH="$WORK/fake:$PATH" RT_OUTPUT="$WORK/s.png" "$P/share/rt-mpi/slurm/rt-mpi.sbatch" \
    >"$WORK/sb.out" 2>"$WORK/sb.err")
check_eq "sbatch script outside Slurm: exit status" $? 0
cmd=$(grep '^mpirun ' "$WORK/sb.out")
case $cmd in *" $P/bin/rt-mpi -o $WORK/s.png "*) pass "sbatch runs the rt-mpi on PATH: $cmd" ;;
    *) fail "sbatch command: '$cmd' $(cat "$WORK/sb.err")" ;; esac
case " $cmd " in *" --width "* | *" --height "* | *" -s "*) fail "sbatch overrides the program's defaults: $cmd" ;;
    *) pass "sbatch keeps the program's default size and samples" ;; esac
(cd "$WORK" && PATH="$WORK/fake:$PATH" RT_OUTPUT="$WORK/s.png" RT_WIDTH=64 RT_HEIGHT=48 RT_SAMPLES=4 \
    "$P/share/rt-mpi/slurm/rt-mpi.sbatch" >"$WORK/sb.out" 2>"$WORK/sb.err")
case "$(grep '^mpirun ' "$WORK/sb.out") " in *" --width 64 --height 48 -s 4 "*) pass "RT_WIDTH, RT_HEIGHT, RT_SAMPLES passed on" ;;
    *) fail "RT_WIDTH & co: $(cat "$WORK/sb.out")" ;; esac
finish
