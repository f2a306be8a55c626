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
cargo test --release --features fault-injection -- --ignored
# The Python package (from_ross against ROSS's rotor objects); quick when scripts/test.sh has
# built it.
.venv/bin/pip install -q ./python
export RUBSIM_BIN="${RUBSIM_BIN:-$PWD/target/release/rubsim}"
status=0
RUBSIM_REQUIRE_ROSS=1 .venv/bin/python -m pytest tests/post -q -m slow || status=$?
if [ "$status" -eq 5 ]; then
  echo "scripts/test-slow.sh: pytest collected no slow tests in tests/post" >&2
  exit 1
fi
[ "$status" -eq 0 ] || exit "$status"
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
