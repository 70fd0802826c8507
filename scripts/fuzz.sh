#!/usr/bin/env bash
# Fuzzes each target of fuzz/ for SECONDS_PER_TARGET seconds (default 20) on stable Rust, and
# fails on the first crash, leaving the input in fuzz/artifacts/<target>/.
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET]
#
# The targets are cargo-fuzz targets (`cargo fuzz run --sanitizer none TARGET` works too, with
# cargo-fuzz installed). CI does not install cargo-fuzz: its install alone takes over two
# minutes on two cores. This script builds the targets as `cargo fuzz build --sanitizer none
# --debug-assertions` does (the same RUSTFLAGS: libFuzzer's coverage instrumentation, cfg
# fuzzing, debug assertions, for the target triple only so build scripts stay plain), and runs
# the binaries with libFuzzer's own options. It does not force one codegen unit as cargo-fuzz
# does: the build is what a bounded CI run spends most of its time on.
#
# Corpora grow in fuzz/corpus/<target>/ (ignored by git), started from the committed seeds in
# fuzz/seeds/<target>/. A crash found becomes a file in fuzz/regressions/<target>/, replayed by
# tests/fuzz_regressions.rs, and is fixed.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds="${1:-20}"
targets=(scene_file xyz columns kernels checkpoint)
triple="$(rustc -vV | sed -n 's/^host: //p')"

export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions \
-Ctarget-cpu=x86-64-v3"
# Not --locked: fuzz/Cargo.lock pins what it can, and follows when the library gains a
# dependency.
start=$(date +%s)
cargo build --release --target "$triple" --bins --config 'profile.release.debug="line-tables-only"'
echo "fuzz targets built in $(( $(date +%s) - start )) s"

bin="${CARGO_TARGET_DIR:-target}/$triple/release"
status=0
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t" "artifacts/$t"
    log="artifacts/$t/last-run.log"
    if "$bin/$t" -max_total_time="$seconds" -rss_limit_mb=2048 \
        -timeout=10 -artifact_prefix="artifacts/$t/" -print_final_stats=1 \
        "corpus/$t" "seeds/$t" > "$log" 2>&1; then
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
        echo "fuzz $t: ${runs:-?} executions in ${seconds} s, no crash"
    else
        echo "fuzz $t: FAILED; the input is in fuzz/artifacts/$t/ (log: fuzz/$log):" >&2
        grep -A12 -m1 -E "panicked|ERROR|deadly signal|timeout|out-of-memory" "$log" >&2 || tail -20 "$log" >&2
        status=1
    fi
done
exit $status
