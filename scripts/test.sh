#!/usr/bin/env bash
# The project's test command (README, CI): installs what the tests need, runs the Rust tests,
# then the pytest suite that reads rubsim's VTK/HDF5 outputs back with pyvista, VTK, meshio and
# h5py (tests/post, against the release binary that `cargo test --release` builds).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo test --release
export RUBSIM_BIN="${RUBSIM_BIN:-$PWD/target/release/rubsim}"
status=0
.venv/bin/python -m pytest tests/post -q || status=$?
if [ "$status" -eq 5 ]; then
  echo "scripts/test.sh: pytest collected no tests in tests/post" >&2
  exit 1
fi
exit "$status"
