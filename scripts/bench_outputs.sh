#!/usr/bin/env bash
# Overhead of the VTK/HDF5 time series (docs/PERFORMANCE.md): one speed of the meshed truss arc
# (tests/data/scenes/fe_arc.toml: 300 nodes, 448 bars, 150 contact nodes; 30 revolutions,
# 57 600 steps) without series, then with a frame every 10th step in each format.
# Prints the best of N runs (default 5) of the integration loop's wall time (the time loop
# including the frame sink; the report line of `rubsim run`), the frames and the bytes written.
set -euo pipefail
cd "$(dirname "$0")/.."
n="${1:-5}"
bin=target/release/rubsim
scene=tests/data/scenes/fe_arc.toml
cargo build --release -q
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { # label, extra args…
  local label=$1; shift
  local best=""
  for _ in $(seq "$n"); do
    rm -rf "$tmp/out"
    s=$("$bin" run "$scene" --out "$tmp/out" "$@" | sed -n 's/.* in \([0-9.]*\) s |.*/\1/p')
    best=$(python3 -c "print(min(float(x) for x in '$best $s'.split()))")
  done
  local bytes
  bytes=$(du -sb "$tmp/out" | cut -f1)
  printf '%-34s loop %.3f s   output %s bytes\n' "$label" "$best" "$bytes"
}
run "no time series"
run "hdf5 every 10" --set 'output.hdf5={ every = 10 }'
run "vtk every 10" --set 'output.vtk={ every = 10 }'
run "vtk + hdf5 every 10" --set 'output.vtk={ every = 10 }' --set 'output.hdf5={ every = 10 }'
run "hdf5 every 10, no velocity" --set 'output.hdf5={ every = 10, fields = ["displacement", "contact_force", "stress"] }'
