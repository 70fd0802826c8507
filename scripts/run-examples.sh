#!/usr/bin/env bash
# run-examples.sh -- runs every example in examples/ at its small size, as CI does, and stops at
# the first failure (each example checks what it shows and exits non-zero with the reason).
#
# Usage: scripts/run-examples.sh [extra cargo flags, e.g. --release]
#
# Each example writes its files to target/examples-out/NAME/. Run from anywhere inside the
# repository. `cargo test` already compiles the examples; this only runs them.
set -euo pipefail
cd "$(dirname "$0")/.."

examples=()
for path in examples/*.rs; do
    examples+=("$(basename "$path" .rs)")
done
if [ ${#examples[@]} -eq 0 ]; then
    echo "run-examples: no examples in examples/" >&2
    exit 1
fi

start=$SECONDS
for name in "${examples[@]}"; do
    echo "== example $name (--small)"
    if ! cargo run --quiet "$@" --example "$name" -- --small --out "target/examples-out/$name"; then
        echo "run-examples: example $name failed" >&2
        exit 1
    fi
done
echo "run-examples: ${#examples[@]} examples passed in $((SECONDS - start)) s"
