#!/usr/bin/env bash
# Installs what rubsim needs on a fresh Debian machine (idempotent, quick when done):
#   - Debian: gmsh (stator meshing), libhdf5-dev + pkg-config (HDF5 output), build tools
#   - Python venv .venv with pyvista, vtk, meshio, h5py, pytest, jsonschema (post-processing scripts and
#     tests), imageio + imageio-ffmpeg (GIF/MP4 movies of post/animate.py), matplotlib (the
#     Python package's example, python/examples/runup.py) and ROSS
#     (ross-rotordynamics, the version pip resolves; with plotly<6, which ROSS 2.3.0 needs to
#     import) for tests/post/test_ross.py — about 65 s more on a fresh venv (docs/VALIDATION.md §7.3)
# Needs root (or sudo) for apt-get. Skip parts with RUBSIM_SKIP_APT=1 / RUBSIM_SKIP_PY=1, and
# ROSS alone with RUBSIM_SKIP_ROSS=1 (the fast test tier, scripts/test.sh, does not compare with
# ROSS; the slow tier, scripts/test-slow.sh, installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
need=()
for p in gmsh libhdf5-dev pkg-config; do
  dpkg -s "$p" >/dev/null 2>&1 || need+=("$p")
done
if [ "${RUBSIM_SKIP_APT:-0}" != 1 ] && [ ${#need[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
  echo "setup: installing ${need[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
if [ "${RUBSIM_SKIP_PY:-0}" != 1 ]; then
  if [ ! -x .venv/bin/python ] || ! .venv/bin/python -c "import pyvista, vtk, meshio, h5py, pytest, imageio, imageio_ffmpeg, scipy, jsonschema, matplotlib" 2>/dev/null; then
    echo "setup: creating .venv with pyvista, vtk, meshio, h5py, pytest, imageio, imageio-ffmpeg, scipy, jsonschema, matplotlib" >&2
    python3 -m venv .venv
    .venv/bin/pip install -q --upgrade pip
    .venv/bin/pip install -q pyvista vtk meshio h5py pytest imageio imageio-ffmpeg scipy jsonschema matplotlib
  fi
  if [ "${RUBSIM_SKIP_ROSS:-0}" != 1 ] && ! .venv/bin/python -c "import ross" >/dev/null 2>&1; then
    echo "setup: installing ROSS (ross-rotordynamics, plotly<6) into .venv for tests/post/test_ross.py" >&2
    .venv/bin/pip install -q ross-rotordynamics 'plotly<6'
  fi
fi
