#!/usr/bin/env bash
# Regenerates the meshed-stator figures and tables of docs/VALIDATION.md §8 and
# docs/PERFORMANCE.md (issue 4: stator geometry pipeline). Needs gmsh (scripts/setup.sh).
# Usage: bash scripts/make_mesh_figures.sh [--no-bench]   (about 40 minutes on 2 cores;
# the benchmark alone about 15)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/rubsim
out=out/figures/stators
dst=docs/figures/stators
rm -rf "$out" "$dst"
mkdir -p "$out" "$dst"

# Regimes, orbits and contact forces of the meshed-stator scenes.
for s in rod2d diaphragm segmented_casing segmented_casing_beams labyrinth_seal; do
  $bin sweep "scenes/stators/$s.toml" --out "$out/$s" | tee "$out/$s.txt"
  cp "$out/$s/bifurcation.png" "$dst/${s}_bifurcation.png"
  cp "$out/$s/orbits_1.png" "$dst/${s}_orbits.png"
done
$bin sweep scenes/paper/partial_rub.toml --out "$out/bar" > "$out/bar.txt"

# Stress and strain in the stator (the paper's Fig. 10): the rod as bar and as 2-D body, and
# the other stators at three speeds.
$bin stress scenes/paper/partial_rub.toml --set stator.0.elements=4 --out "$out/stress_bar" | tee "$out/stress_bar.txt"
$bin stress scenes/stators/rod2d.toml --out "$out/stress_rod2d" | tee "$out/stress_rod2d.txt"
for s in diaphragm segmented_casing segmented_casing_beams labyrinth_seal; do
  $bin stress "scenes/stators/$s.toml" --speed 1.0 --speed 1.4 --speed 2.0 --out "$out/stress_$s" | tee "$out/stress_$s.txt"
done
cp "$out/stress_bar/stress.png" "$dst/stress_bar.png"
cp "$out/stress_rod2d/stress.png" "$dst/stress_rod2d.png"
cp "$out/stress_rod2d/stress_field_rod_3.1.png" "$dst/stress_field_rod2d_3.1.png"
cp "$out/stress_diaphragm/stress_field_diaphragm_1.4.png" "$dst/stress_field_diaphragm_1.4.png"
cp "$out/stress_segmented_casing/stress_field_casing_1.4.png" "$dst/stress_field_casing_1.4.png"
cp "$out/stress_labyrinth_seal/stress_field_seal_1.4.png" "$dst/stress_field_seal_1.4.png"

# The node-to-nodes contact as the boundary mesh is refined (the paper's caveat).
$bin refine scenes/stators/annulus.toml --key stator.0.parameters.n --values 32,64,128,256,512 \
  --set run.samples_per_rev=512 --set run.revolutions=80 --set run.transient_revolutions=40 \
  --out "$out/refine_annulus" | tee "$out/refine_annulus.txt"
$bin refine scenes/stators/rod2d.toml --key stator.0.parameters.nx --values 1,2,4,8,16,32 \
  --set run.samples_per_rev=256 --out "$out/refine_rod" | tee "$out/refine_rod.txt"
cp "$out/refine_annulus/refine_force.png" "$dst/refine_annulus_force.png"
cp "$out/refine_annulus/refine_orbit.png" "$dst/refine_annulus_orbit.png"

# Time per step against stator DOFs, massless and with mass (docs/PERFORMANCE.md).
if [ "${1:-}" != "--no-bench" ]; then
  hs=0.004,0.002,0.0014,0.001,0.0007,0.0005,0.00042
  $bin refine scenes/stators/bench_annulus.toml --key stator.0.parameters.h --values "$hs" \
    --out "$out/bench_massless" | tee "$out/bench_massless.txt"
  # 12 instead of 4 revolutions: the difference is the per-step cost without the one-time
  # compliance columns.
  $bin refine scenes/stators/bench_annulus.toml --key stator.0.parameters.h --values "$hs" \
    --set run.revolutions=12 --out "$out/bench_massless_long" | tee "$out/bench_massless_long.txt"
  $bin refine scenes/stators/bench_annulus.toml --key stator.0.parameters.h --values "$hs" \
    --set stator.0.density=1200 --set run.speed_ratio=6 --set run.revolutions=2 \
    --set run.transient_revolutions=1 --out "$out/bench_mass" | tee "$out/bench_mass.txt"
  cp "$out/bench_massless_long/refine_cost.png" "$dst/bench_massless_cost.png"
  cp "$out/bench_mass/refine_cost.png" "$dst/bench_mass_cost.png"
fi
echo "figures in $dst"
