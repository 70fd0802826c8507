#!/usr/bin/env bash
# The Python package's check, from a clean machine: a venv under target/python-venv (reused
# when present), pinned build and test tools, the wheel built by maturin in release mode and
# installed, then pytest over python/tests. Run from anywhere; exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."

venv=target/python-venv
python=${PYTHON:-python3}
# Pinned: the build tool, the test runner, and what the Dask helpers' tests import.
pins=(maturin==1.16.0 numpy==2.4.6 pytest==9.2.0 pyarrow==26.0.1 pandas==3.1.1
      "dask[distributed]==2026.8.0" mypy==2.4.1)

if [[ ! -x $venv/bin/python ]]; then
    echo "python-ci: creating $venv"
    "$python" -m venv "$venv"
fi
# A pip "check" of the pins is cheap when they are installed; a fresh venv downloads them.
if ! "$venv/bin/python" - "${pins[@]}" <<'PY'
import sys
from importlib.metadata import version, PackageNotFoundError
for pin in sys.argv[1:]:
    name, want = pin.split("==")
    name = name.split("[")[0]
    try:
        if version(name) != want:
            sys.exit(1)
    except PackageNotFoundError:
        sys.exit(1)
PY
then
    echo "python-ci: installing ${pins[*]}"
    "$venv/bin/pip" install --quiet --disable-pip-version-check "${pins[@]}"
fi

echo "python-ci: building the wheel"
rm -f target/wheels/spheresweep-*.whl
"$venv/bin/maturin" build --release --quiet -m python/Cargo.toml -o target/wheels \
    -i "$venv/bin/python"
wheel=$(ls target/wheels/spheresweep-*.whl)
"$venv/bin/pip" install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheel"

echo "python-ci: stubtest and mypy"
# The stubs against the installed module, and the Dask helpers' types.
(cd target && "../$venv/bin/python" -m mypy.stubtest spheresweep \
    && "../$venv/bin/python" -m mypy --config-file ../python/pyproject.toml ../python/spheresweep/distributed.py)

echo "python-ci: pytest"
# From outside the source tree, so that the installed wheel is what is imported.
(cd target && "../$venv/bin/python" -m pytest -q -p no:cacheprovider ../python/tests)

# A user's install: a fresh venv, the wheel with its [distributed] extra (the pinned versions
# as constraints, resolved by pip from the wheel's metadata), then the Dask example of
# docs/distributed.md run as printed. SPHERESWEEP_SKIP_FRESH_INSTALL=1 skips it.
if [[ -z ${SPHERESWEEP_SKIP_FRESH_INSTALL:-} ]]; then
    echo "python-ci: a fresh venv from the wheel with [distributed]"
    fresh=target/python-fresh-venv
    rm -rf "$fresh"
    "$python" -m venv "$fresh"
    # pip takes no extras in a constraint: `dask[distributed]==V` is written `dask==V`.
    printf '%s\n' "${pins[@]}" | grep -v -e '^maturin' -e '^pytest' -e '^mypy' \
        | sed 's/\[[^]]*\]//' > target/python-constraints.txt
    "$fresh/bin/pip" install --quiet --disable-pip-version-check --no-cache-dir \
        -c target/python-constraints.txt "$wheel[distributed]"
    (cd target && "../$fresh/bin/python" ../python/tests/docs_distributed_example.py ../docs/distributed.md)
    rm -rf "$fresh"
fi
