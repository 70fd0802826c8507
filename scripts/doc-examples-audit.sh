#!/usr/bin/env bash
# doc-examples-audit.sh -- count the public items whose rustdoc has no code example.
#
# Usage:
#   scripts/doc-examples-audit.sh [--list] [PACKAGE ...]
#
#   PACKAGE   a workspace package to audit (default: spheresweep); e.g.
#             scripts/doc-examples-audit.sh spheresweep spheresweep-study spheresweep-bench
#   --list    also print where each item without an example is (file:line:column)
#
# The lint `rustdoc::missing_doc_code_examples` is unstable, so this needs a nightly toolchain
# (`rustup toolchain install nightly`); it is an audit for people, not part of CI, which stays
# on stable. Without nightly the script says so and exits 0. It builds in its own target
# directory ($DOC_AUDIT_TARGET_DIR, default /tmp/spheresweep-doc-audit) so that the stable
# build is left alone, and touches each package's src/lib.rs so that rustdoc runs again rather
# than replaying a cached result. Exit status: 0 after a completed audit (whatever the
# count), 1 if rustdoc failed.
set -euo pipefail

cd "$(dirname "$0")/.."

list=false
packages=()
for arg in "$@"; do
    case "$arg" in
        --list) list=true ;;
        -h | --help)
            sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
            exit 0
            ;;
        -*)
            echo "doc-examples-audit: unknown option $arg" >&2
            exit 2
            ;;
        *) packages+=("$arg") ;;
    esac
done
[ ${#packages[@]} -eq 0 ] && packages=(spheresweep)

if ! cargo +nightly --version >/dev/null 2>&1; then
    echo "doc-examples-audit: no nightly toolchain (rustup toolchain install nightly); nothing audited"
    exit 0
fi

target="${DOC_AUDIT_TARGET_DIR:-/tmp/spheresweep-doc-audit}"
total=0
for package in "${packages[@]}"; do
    # The package's directory, from cargo metadata (the root package lives at the top).
    manifest=$(cargo +nightly metadata --no-deps --format-version 1 |
        python3 -c 'import json, sys
name = sys.argv[1]
hits = [p["manifest_path"] for p in json.load(sys.stdin)["packages"] if p["name"] == name]
print(hits[0] if hits else "")' "$package")
    if [ -z "$manifest" ]; then
        echo "doc-examples-audit: no package $package in this workspace" >&2
        exit 2
    fi
    lib="$(dirname "$manifest")/src/lib.rs"
    [ -f "$lib" ] && touch "$lib"
    log=$(mktemp)
    if ! CARGO_TARGET_DIR="$target" cargo +nightly rustdoc -p "$package" --all-features -- \
        -Z unstable-options \
        -Zcrate-attr="feature(rustdoc_missing_doc_code_examples)" \
        -W rustdoc::missing-doc-code-examples >"$log" 2>&1; then
        cat "$log" >&2
        rm -f "$log"
        echo "doc-examples-audit: rustdoc failed on $package" >&2
        exit 1
    fi
    # Each warning is "missing code example in this documentation" followed by its location.
    locations=$(grep -A2 "missing code example" "$log" | grep -- '-->' | sed 's/^ *--> *//' || true)
    rm -f "$log"
    count=$(printf '%s' "$locations" | grep -c . || true)
    echo "$package: $count public items without a code example"
    if $list && [ "$count" -gt 0 ]; then
        printf '%s\n' "$locations" | sed 's/^/  /'
    fi
    total=$((total + count))
done
if [ ${#packages[@]} -gt 1 ]; then
    echo "total: $total"
fi
