#!/usr/bin/env bash
# The project's test command (README): the fast tier a newcomer runs, build included, in about
# 10 minutes on a fresh 2-core machine. Installs what the tests need (ROSS excepted), runs the
# Rust tests (`cargo test --release --workspace --features fault-injection`: every test not marked
# `#[ignore = "slow tier …"]`, with the test hooks that kill a run at chosen points), then
# the Python read-back tests of the VTK/HDF5 outputs with pyvista, VTK, meshio and h5py
# (tests/post, `-m "not slow"`, against the release binary that `cargo test` builds), and the
# Python package's tests (python/tests) against its wheel, built here from the checkout and
# installed into .venv (`pip wheel ./python`: maturin from PyPI, the crates from crates.io).
# The slow tier is scripts/test-slow.sh; CI (.ci/run) runs both. Tiers and their cost:
# docs/PERFORMANCE.md, "Test tiers and build time".
set -euo pipefail
cd "$(dirname "$0")/.."
# The Debian packages first (the build links libhdf5); the Python venv (about 75 s of downloads
# on a fresh machine) is made while cargo builds, and waited for before pytest.
RUBSIM_SKIP_PY=1 bash scripts/setup.sh
pylog=$(mktemp)
RUBSIM_SKIP_APT=1 RUBSIM_SKIP_ROSS="${RUBSIM_SKIP_ROSS:-1}" bash scripts/setup.sh >"$pylog" 2>&1 &
py=$!
trap 'kill "$py" 2>/dev/null || true' EXIT
# --workspace: the features of the dependencies unified with the Python package's (python/), so
# that its wheel below reuses this build's compiled library instead of compiling it again.
cargo test --release --workspace --features fault-injection
if ! wait "$py"; then
  echo "scripts/test.sh: the Python setup failed:" >&2
  cat "$pylog" >&2
  exit 1
fi
rm -f "$pylog"
# The wheel (abi3: one file for every CPython ≥ 3.9) into target/wheels/, then installed; the
# slow tier installs the same file into its ROSS 3 venv (Python 3.12). Built with the test hooks
# (`fault-injection`, inert unless their variables are set) so that it links the library
# `cargo test` compiled: about 45 s here against 2 min for a library of its own; users'
# `pip install ./python` builds it without them.
rm -f target/wheels/rubsim-*.whl
MATURIN_PEP517_ARGS="--features fault-injection" \
  .venv/bin/pip wheel -q --no-deps -w target/wheels ./python
.venv/bin/pip install -q --force-reinstall --no-deps target/wheels/rubsim-*.whl
export RUBSIM_BIN="${RUBSIM_BIN:-$PWD/target/release/rubsim}"
status=0
.venv/bin/python -m pytest tests/post python/tests -q -m "not slow" || status=$?
if [ "$status" -eq 5 ]; then
  echo "scripts/test.sh: pytest collected no tests in tests/post and python/tests" >&2
  exit 1
fi
exit "$status"
