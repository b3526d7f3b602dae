# bench_lib.sh - helpers shared by the benchmark scripts (sourced by bench.sh
# and ab_render.sh).

# segment_rate FILE: the ray segments per second (M/s) rt-mpi printed to FILE.
segment_rate() { sed -n 's/^ray segments: *[0-9]* (\([0-9.]*\) M\/s)/\1/p' "$1"; }
# median: of the numbers on standard input, one per line (the mean of the
# middle two for an even count).
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
# ratio A B: A / B with three decimals.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.3f", a / b}'; }
