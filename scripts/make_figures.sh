#!/usr/bin/env bash
# Regenerates the figures and tables quoted in docs/VALIDATION.md and docs/PERFORMANCE.md.
# Usage: bash scripts/make_figures.sh   (builds the release binary first)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/rubsim
out=out/figures
rm -rf "$out"
$bin sweep scenes/paper/partial_rub.toml --out "$out/paper" | tee "$out.paper.txt"
for f in scenes/paper/sensitivity/*.toml; do
  $bin sweep "$f" --out "$out/$(basename "$f" .toml)" | tee "$out.$(basename "$f" .toml).txt"
done
$bin convergence scenes/paper/partial_rub.toml --out "$out/convergence" | tee "$out.convergence.txt"
# Copy the pictures the docs show.
dst=docs/figures
rm -rf "$dst"; mkdir -p "$dst"
cp "$out"/paper/{cascade,bifurcation,regime_map,contact_force,orbits_1,orbits_2,orbits_3,orbits_4}.png "$dst/"
for f in "$out"/fig1*; do
  n=$(basename "$f")
  for v in "$f"/*/; do
    cp "$v/cascade.png" "$dst/${n}_$(basename "$v")_cascade.png"
  done
done
for v in "$out"/fig14_friction/*/; do cp "$v/orbits_1.png" "$dst/fig15_$(basename "$v")_orbits.png"; done
for s in "$out"/convergence/speed_*/; do
  cp "$s/work_precision.png" "$dst/work_precision_$(basename "$s").png"
  cp "$s/error_vs_dt.png" "$dst/error_vs_dt_$(basename "$s").png"
done
# The thermal spiral (issue 27) and a branch's largest multiplier (issue 29).
"$bin" run scenes/thermal/newkirk_ring.toml --out "$out/thermal" --force >/dev/null
cp "$out/thermal/spiral.png" "$dst/thermal_spiral.png"
cp "$out/thermal/thermal.png" "$dst/thermal_history.png"
"$bin" continue scenes/paper/partial_rub.toml --from 2.0 --to 2.5 --step 0.1 --period 1 \
  --out "$out/continue_pd" --force >/dev/null
cp "$out/continue_pd/branch_multipliers.png" "$dst/continue_multipliers.png"
# Dry whirl and dry whip with stick (issue 28): the rig's sweep from roll into whip.
"$bin" sweep scenes/stick/dry_whirl.toml --out "$out/dry_whirl" --fresh >/dev/null
cp "$out/dry_whirl/dry_whirl.png" "$dst/dry_whirl_sweep.png"
"$bin" run scenes/stick/whirl_runup.toml --out "$out/whirl_runup" --force >/dev/null
cp "$out/whirl_runup/full_waterfall.png" "$dst/dry_whirl_runup.png"
echo "figures in $dst"
# Meshed stators (issue 4): docs/figures/stators.
bash scripts/make_mesh_figures.sh
