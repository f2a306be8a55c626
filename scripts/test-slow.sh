#!/usr/bin/env bash
# The slow test tier, run by CI (.ci/run) after the README's test command (scripts/test.sh, the
# fast tier, which has built the release test binaries): the Rust tests marked
# `#[ignore = "slow tier …"]` (the 10⁵-DOF-class reduced stator, long sweeps and studies), the
# Python tests marked `slow` (ROSS side by side — ROSS installed here and required —, long runs),
# a short fuzz of each reader, and a real one-node Slurm cluster. Tiers and their cost:
# docs/PERFORMANCE.md, "Test tiers and build time".
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# ROSS 3 needs Python ≥ 3.12 (the project's .venv is 3.11 with ROSS 2.3): a venv .venv-ross3 of
# pyenv's 3.12 with ROSS 3.0.0 (the PyPI mirror's latest for it), for from_ross of ROSS 3 rotor
# objects (python/tests/test_from_ross.py) — made (about 2 min of downloads the first time)
# while the Rust tests run, and waited for below.
py312=$(PYENV_VERSION=3.12.1 pyenv which python 2>/dev/null || command -v python3.12 || true)
ross3log=$(mktemp)
ross3=""
if [ -n "$py312" ]; then
  (
    [ -x .venv-ross3/bin/python ] || "$py312" -m venv .venv-ross3
    .venv-ross3/bin/python -c "import ross, pytest" 2>/dev/null \
      || .venv-ross3/bin/pip install -q 'ross-rotordynamics==3.0.0' pytest
  ) >"$ross3log" 2>&1 &
  ross3=$!
fi
cargo test --release --workspace --features fault-injection -- --ignored
# The Python package (from_ross against ROSS's rotor objects): the wheel scripts/test.sh built,
# else built here.
if ! ls target/wheels/rubsim-*.whl >/dev/null 2>&1; then
  MATURIN_PEP517_ARGS="--features fault-injection" \
    .venv/bin/pip wheel -q --no-deps -w target/wheels ./python
fi
.venv/bin/pip install -q --force-reinstall --no-deps target/wheels/rubsim-*.whl
export RUBSIM_BIN="${RUBSIM_BIN:-$PWD/target/release/rubsim}"
status=0
RUBSIM_REQUIRE_ROSS=1 .venv/bin/python -m pytest tests/post python/tests -q -m slow || status=$?
if [ "$status" -eq 5 ]; then
  echo "scripts/test-slow.sh: pytest collected no slow tests in tests/post" >&2
  exit 1
fi
[ "$status" -eq 0 ] || exit "$status"
# The same abi3 wheel in the ROSS 3 venv.
if [ -n "$ross3" ]; then
  if ! wait "$ross3"; then
    echo "scripts/test-slow.sh: the ROSS 3 venv (.venv-ross3) could not be made:" >&2
    cat "$ross3log" >&2
    exit 1
  fi
  .venv-ross3/bin/pip install -q --force-reinstall --no-deps target/wheels/rubsim-*.whl
  RUBSIM_REQUIRE_ROSS=1 .venv-ross3/bin/python -m pytest python/tests/test_from_ross.py -q -m slow
else
  echo "scripts/test-slow.sh: no Python 3.12 (pyenv 3.12.1 or python3.12): from_ross of ROSS 3 objects not tested" >&2
fi
rm -f "$ross3log"
# Issue 13: a short run of each fuzzer (scene, msh, manifest, ross; FUZZ_TIME seconds each) from
# the committed seeds. FUZZ_BUILD=quick builds the instrumented crate cheaply — no AddressSanitizer,
# opt-level 1, 16 codegen units, its own target directory — keeping the coverage
# instrumentation, debug assertions and overflow checks: a panic, an abort, an input running
# 10 s or allocating 2 GB fails. Cold cost: docs/VALIDATION.md §13. The runs of 10^6
# executions use the full build (scripts/fuzz.sh).
FUZZ_BUILD=quick FUZZ_TIME="${FUZZ_TIME:-20}" bash scripts/fuzz.sh
# A real Slurm (issue 12): a one-node cluster runs a small map as an array job and the merge as
# a dependent job; compared with a one-machine run value for value (skips when not root).
bash scripts/slurm/ci_test.sh
