# help2man.awk - rt-mpi --help (stdin) to the man page rt-mpi.1 (stdout);
# run at build time (cmake/install.cmake) with -v version=X.Y.Z.
# The help's layout (src/app/usage.c, rt_cli_usage) is what this reads:
#   "Usage: ..." and the lines under it       -> SYNOPSIS
#   the first paragraph after them            -> DESCRIPTION
#   "Topic:" at the start of a line           -> a section: Examples,
#                                                Environment and Exit status
#                                                are their own, the rest are
#                                                subsections of OPTIONS
#   "  TERM  text" (indented 2 to 8)          -> an item (.TP)
#   a line indented further                   -> goes on with the item's text

# roff-safe text: backslashes, minus signs, and no control line by accident.
function esc(s) {
    gsub(/\\/, "\\e", s)
    gsub(/-/, "\\-", s)
    return s
}
function line(s) {
    if (s ~ /^[.']/) s = "\\&" s
    print s
}
# An item's term: <ARG> in italics, everything else in bold.
function term(s,    n, w, i, out) {
    n = split(s, w, " ")
    out = ""
    for (i = 1; i <= n; i++) {
        if (w[i] ~ /^</) out = out (i > 1 ? " " : "") "\\fI" esc(w[i]) "\\fR"
        else out = out (i > 1 ? " " : "") "\\fB" esc(w[i]) "\\fR"
    }
    return out
}
function indent(s) {
    match(s, /^ */)
    return RLENGTH
}
BEGIN {
    state = "top"
    print ".\\\" Generated from rt-mpi --help by cmake/help2man.awk; do not edit."
    print ".TH RT-MPI 1 \"\" \"rt-mpi " version "\" \"User Commands\""
    print ".SH NAME"
    print "rt-mpi \\- distributed path tracer (MPI and OpenMP) for the Ray Tracing in One Weekend scenes"
}
state == "top" && /^Usage: / {
    print ".SH SYNOPSIS"
    print ".nf"
    sub(/^Usage: +/, "")
    line(esc($0))
    state = "usage"
    next
}
state == "usage" && /^ +[^ ]/ {
    sub(/^ +/, "")
    line(esc($0))
    next
}
state == "usage" && /^$/ {
    print ".fi"
    print ".SH DESCRIPTION"
    state = "description"
    next
}
state == "description" && /^$/ { state = "sections"; next }
state == "description" { line(esc($0)); next }
/^[A-Z][^:]*:$/ {
    name = substr($0, 1, length($0) - 1)
    if (name == "Examples" || name == "Environment" || name == "Exit status") {
        print ".SH " toupper(name ~ / / ? "\"" name "\"" : name)
    } else {
        if (!options) print ".SH OPTIONS"
        options = 1
        print ".SS \"" name "\""
    }
    next
}
# (indentation measured, not matched with {m,n}: mawk has no intervals)
/^ +[^ ]/ && indent($0) <= 8 {
    s = $0
    sub(/^ +/, "", s)
    t = s
    d = ""
    if (match(s, /  +/)) {
        t = substr(s, 1, RSTART - 1)
        d = substr(s, RSTART + RLENGTH)
    }
    print ".TP"
    line(term(t))
    if (d != "") line(esc(d))
    next
}
/^ +[^ ]/ {
    s = $0
    sub(/^ +/, "", s)
    line(esc(s))
    next
}
/^$/ { next }
{ line(esc($0)) }
END {
    print ".SH FILES"
    print ".TP"
    print "\\fIshare/rt\\-mpi/scenes/\\fR (under the installation prefix, e.g. /usr)"
    print "Example scene files."
    print ".TP"
    print "\\fIshare/rt\\-mpi/slurm/rt\\-mpi.sbatch\\fR"
    print "A Slurm batch script that checkpoints and requeues itself at the time limit."
    print ".SH SEE ALSO"
    print "\\fBmpirun\\fR(1), \\fBsbatch\\fR(1)"
}
