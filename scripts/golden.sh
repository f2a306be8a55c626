#!/usr/bin/env bash
# Behaviour guard for refactors: runs a fixed set of cases (the paper sweep, the FE paper-rotor
# sweep, meshed stators 2-D and 3-D, a ring, a stator with mass in a collocated run, an FE rotor
# with two stations and with torsion, a convergence study, a stress probe) with VTK/HDF5 series
# into DIR/<case>/. Compare two such directories with scripts/golden_compare.py.
#
#   bash scripts/golden.sh DIR [RUBSIM_BINARY]      (ONLY="paper ring" runs just those cases)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: golden.sh DIR [binary]}
bin=${2:-target/release/rubsim}
mkdir -p "$out"
series='--set output.hdf5={every=7} --set output.vtk={every=97}'
run() {
  local name=$1; shift
  if [ -n "${ONLY:-}" ] && [[ " $ONLY " != *" $name "* ]]; then return; fi
  echo "golden: $name" >&2; "$bin" "$@" --out "$out/$name" > "$out/$name.log"; }
run paper sweep scenes/paper/partial_rub.toml
run fe_paper sweep scenes/fe/paper_rotor_rub.toml --set run.error_estimate=false
# Meshed stators: series over the last revolutions only (each frame holds the whole mesh).
late='--set output.hdf5={every=53,from_revolution=28} --set output.vtk={every=997,from_revolution=28}'
run annulus run scenes/stators/annulus.toml --set run.revolutions=30 \
  --set run.transient_revolutions=15 $late
run diaphragm run scenes/stators/diaphragm.toml --speed 1.2 --set run.revolutions=8 \
  --set run.transient_revolutions=4 --set 'output.hdf5={every=53,from_revolution=6}' \
  --set 'output.vtk={every=997,from_revolution=6}'
run seal3d run tests/data/scenes/seal3d.toml $series
run ring run tests/data/scenes/ring.toml $series
run massive_collocated run tests/data/scenes/single.toml --set stator.0.density=7800 \
  --set 'run.integrator="collocated"' $series
run massive_fi run tests/data/scenes/single.toml --set stator.0.density=7800 \
  --set 'run.integrator="forward_increment"' $series
run two_stations run scenes/fe/two_disk_two_stations.toml --speed 2.1 --set run.revolutions=60 \
  --set run.transient_revolutions=40 $series
run torsion run scenes/fe/paper_rotor_rub_torsion.toml --speed 3.1 --set run.revolutions=60 \
  --set run.transient_revolutions=40 $series
run convergence convergence scenes/paper/partial_rub.toml --speed 3.1 --levels 3 --reference 7
run stress stress scenes/stators/diaphragm.toml --speed 1.2 --set run.revolutions=8 \
  --set run.transient_revolutions=4
echo "golden: done in $out" >&2
