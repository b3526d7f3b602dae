# bench_lib.sh - helpers shared by the benchmark scripts (sourced by the
# benchmark and A/B scripts in tools/).

# segment_rate FILE: the ray segments per second (M/s) rt-mpi printed to FILE.
segment_rate() { sed -n 's/^ray segments: *[0-9]* (\([0-9.]*\) M\/s)/\1/p' "$1"; }
# median: of the numbers on standard input, one per line (the mean of the
# middle two for an even count).
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# display_rmse REF IMG: display-space per-pixel RMSE (gamma 2, 0-255) of IMG
# against REF (tools/compare_images.py, Debian's python3 for numpy and PIL).
display_rmse() {
    /usr/bin/python3 "$(dirname "${BASH_SOURCE[0]}")/compare_images.py" --ref "$1" --block 1 x="$2" |
        awk '$1 == "x" {print $NF}'
}
# ratio A B: A / B with three decimals.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f", a / b}'; }

# build_a_b NAME ROOT REV DIR cmake-options...: the program of the working
# tree in DIR/a and of git revision REV in DIR/b, release builds of rt-mpi
# only. REV's tree is unpacked into DIR/src-b again only when REV names
# another commit than last time. Exits 2 (with the log's tail) on failure.
build_a_b() {
    local name=$1 root=$2 rev=$3 dir=$4 commit
    shift 4
    commit=$(git -C "$root" rev-parse --verify -q "$rev^{commit}") ||
        { echo "$name: no git revision '$rev'" >&2; exit 2; }
    mkdir -p "$dir"
    if [ "$(cat "$dir/b.commit" 2>/dev/null)" != "$commit" ]; then
        rm -rf "$dir/src-b" "$dir/b"
        mkdir -p "$dir/src-b"
        git -C "$root" archive "$commit" | tar -x -C "$dir/src-b"
        echo "$commit" >"$dir/b.commit"
    fi
    local src build
    for src in "$root:a" "$dir/src-b:b"; do
        build=$dir/${src##*:}
        RT_BUILD_TARGET=rt-mpi "${src%:*}/scripts/setup.sh" "$build" "$@" >/dev/null 2>"$build.log" ||
            { tail -20 "$build.log" >&2; echo "$name: the build in $build failed" >&2; exit 2; }
    done
}
