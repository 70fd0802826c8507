#!/usr/bin/env bash
# edmd_peer.sh -- performance peer: F. Smallenburg's hard-sphere EDMD ("Single" variant,
# neighbour lists + one event per particle; https://github.com/FSmallenburg/EDMD,
# Eur. Phys. J. E 45, 22 (2022)).
#
# Usage:
#   scripts/edmd_peer.sh EDMD_DIR N PHI [MAXTIME|auto] [BUILD_DIR]
#
#   EDMD_DIR   path of an existing EDMD checkout (must contain Single/mdSingle.c);
#              this script never downloads anything.
#   N          number of particles; the peer's FCC start needs N = 4*k^3 (4000, 32000, 108000, ...)
#   PHI        packing fraction
#   MAXTIME    simulated time (units of tau = sqrt(m sigma^2 / kT)); "auto" (default) picks it so
#              that about $EDMD_COLLISIONS collisions (default 1e7) happen, using the Enskog /
#              Carnahan-Starling collision rate N/2 * 4 rho sigma^2 g(sigma) sqrt(pi kT/m).
#   BUILD_DIR  where the edited copy is compiled and run (default: a fresh mktemp dir, removed at exit)
#
# The peer's parameters are plain globals near the top of Single/mdSingle.c; they are edited with
# sed in a copy (FCC start, N, phi, maxtime, thermostat off, no snapshots).  Build:
#   ${CC:-gcc} ${EDMD_CFLAGS:--Ofast -march=native} mdSingle.c -o md -lm
# Run pinned to core ${EDMD_CPU:-0} with taskset (if available).
#
# The peer prints "Simtime: t, Collisions: c, ..." at every write event; the first one is at t=0,
# right after initialisation.  Each such line is time-stamped on arrival (stdout line-buffered with
# stdbuf), and the rate is (c_last - c_first) / (wall_last - wall_first): real collisions only
# (not neighbour-list updates or stale events), excluding setup and the final snapshot write.
#
# Output (stdout): one line "N phi collisions_per_second".  Details go to stderr.
set -euo pipefail

die() { echo "edmd_peer.sh: $*" >&2; exit 1; }

[[ $# -ge 3 ]] || die "usage: $0 EDMD_DIR N PHI [MAXTIME|auto] [BUILD_DIR]"
EDMD_DIR=$1; N=$2; PHI=$3; MAXTIME=${4:-auto}; BUILD_DIR=${5:-}
SRC=$EDMD_DIR/Single
[[ -f $SRC/mdSingle.c && -f $SRC/mdSingle.h && -f $SRC/mt19937ar.c ]] \
    || die "no Single/mdSingle.c, mdSingle.h, mt19937ar.c under $EDMD_DIR"
[[ $N =~ ^[0-9]+$ ]] || die "N must be an integer"
[[ $PHI =~ ^[0-9]*\.?[0-9]+$ ]] || die "PHI must be a number"
awk -v n="$N" 'BEGIN { k = int(exp(log(n/4)/3) + 0.5); exit !(4*k*k*k == n) }' \
    || die "N must be 4*k^3 for the peer's FCC start (e.g. 4000, 32000, 108000)"

if [[ $MAXTIME == auto ]]; then
    MAXTIME=$(awk -v n="$N" -v phi="$PHI" -v target="${EDMD_COLLISIONS:-1e7}" 'BEGIN {
        pi = 3.141592653589793; rho = 6*phi/pi
        g = (1 - phi/2) / (1 - phi)^3                    # Carnahan-Starling contact value
        rate = n/2 * 4*rho*g*sqrt(pi)                    # collisions per tau (sigma = m = kT = 1)
        printf "%.6g", target/rate }')
fi
[[ $MAXTIME =~ ^[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?$ ]] || die "MAXTIME must be a number or auto"
# about 100 progress lines per run (the write event is O(N), negligible)
WRITEINT=$(awk -v t="$MAXTIME" 'BEGIN { printf "%.6g", t/100 }')

if [[ -z $BUILD_DIR ]]; then
    BUILD_DIR=$(mktemp -d "${TMPDIR:-/tmp}/edmd_peer.XXXXXX")
    trap 'rm -rf "$BUILD_DIR"' EXIT
fi
mkdir -p "$BUILD_DIR"
cp "$SRC/mdSingle.c" "$SRC/mdSingle.h" "$SRC/mt19937ar.c" "$BUILD_DIR/"
cd "$BUILD_DIR"

# Edit the parameter globals in the copy; each edit must hit exactly one line.
edit() {  # edit REGEX REPLACEMENT
    [[ $(grep -cE "$1" mdSingle.c) == 1 ]] || die "pattern not found once in mdSingle.c: $1"
    sed -i -E "s/$1/$2/" mdSingle.c
}
edit '^double maxtime = [^;]*;'              "double maxtime = $MAXTIME;"
edit '^int makesnapshots = [^;]*;'           'int makesnapshots = 0;'
edit '^double writeinterval = [^;]*;'        "double writeinterval = $WRITEINT;"
edit '^double snapshotinterval = [^;]*;'     "double snapshotinterval = $MAXTIME;"
edit '^int initialconfig = [^;]*;'           'int initialconfig = 1;'
edit '^double packfrac = [^;]*;'             "double packfrac = $PHI;"
edit '^int N = [^;]*;'                       "int N = $N;"
edit '^const int usethermostat = [^;]*;'     'const int usethermostat = 0;'

# shellcheck disable=SC2086
${CC:-gcc} ${EDMD_CFLAGS:--Ofast -march=native} mdSingle.c -o md -lm \
    || die "build failed in $BUILD_DIR"

PIN=()
if command -v taskset >/dev/null 2>&1; then PIN=(taskset -c "${EDMD_CPU:-0}"); fi
BUF=()
if command -v stdbuf >/dev/null 2>&1; then BUF=(stdbuf -oL); fi

echo "edmd_peer: N=$N phi=$PHI maxtime=$MAXTIME build=$BUILD_DIR cmd=${PIN[*]} ${BUF[*]} ./md" >&2
t_start=$EPOCHREALTIME
t_first=; c_first=; t_last=; c_last=; tail_lines=()
while IFS= read -r line; do
    now=$EPOCHREALTIME
    if [[ $line =~ ^Simtime:\ ([0-9.]+),\ Collisions:\ ([0-9]+) ]]; then
        if [[ -z $t_first ]]; then t_first=$now; c_first=${BASH_REMATCH[2]}; fi
        t_last=$now; c_last=${BASH_REMATCH[2]}; sim_last=${BASH_REMATCH[1]}
    else
        tail_lines+=("$line")
    fi
done < <("${PIN[@]}" "${BUF[@]}" ./md; echo "EXIT_STATUS $?")
t_end=$EPOCHREALTIME

[[ ${tail_lines[-1]} == "EXIT_STATUS 0" ]] || { printf '%s\n' "${tail_lines[@]}" >&2; die "peer failed"; }
[[ -n $t_first && $c_last -gt $c_first ]] || die "no progress lines from peer"
[[ $c_last -lt 4000000000 ]] || echo "edmd_peer: warning: peer's unsigned collision counter may have wrapped" >&2

awk -v n="$N" -v phi="$PHI" -v c0="$c_first" -v c1="$c_last" -v t0="$t_first" -v t1="$t_last" \
    -v ts="$t_start" -v te="$t_end" -v sim="$sim_last" 'BEGIN {
    printf "edmd_peer: %d collisions in %.3f s between first and last progress line (sim time %s); whole process %.3f s -> %.0f coll/s incl. setup\n", c1-c0, t1-t0, sim, te-ts, c1/(te-ts) > "/dev/stderr"
    printf "%d %s %.0f\n", n, phi, (c1-c0)/(t1-t0) }'
