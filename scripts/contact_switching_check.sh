#!/usr/bin/env bash
# Checks time::CONTACT_SWITCHING_FACTOR (φ = 0.5, the contact term of the stability limit
# counted 1/φ² times): every scene of scenes/ with a rotor and a stator is run at its planned
# step at ω/ω_n = 1.7, 3.1 and 4.9, the paper's case also with stiffness_ratio 1e4 … 1e6, and
# one markdown row per run is printed (docs/VALIDATION.md §10): the planned Δt against the
# stability limit, the steps in contact, and whether the run went to its end (a divergence or
# a non-finite value stops it with exit 1).
#   bash scripts/contact_switching_check.sh [rubsim binary]   (release build by default)
# SCENES=<pattern> runs only the scenes whose path matches it (and the stiff paper runs when it
# is `paper`). A run of the 3-D labyrinth seal takes ~10 min on a loaded machine.
set -uo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/release/rubsim}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
scenes=$(find scenes -name '*.toml' | sort | grep -v -e transients/ -e friswell_5_9_1 | grep -e "${SCENES:-.}")
run() {
  local scene="$1" speed="$2"; shift 2
  local dir="$out/run" t0 t1 rc
  rm -rf "$dir"
  t0=$(date +%s.%N)
  "$bin" run "$scene" --speed "$speed" --out "$dir" "$@" > "$out/log" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  python3 - "$scene" "$speed" "$rc" "$(echo "$t1 - $t0" | bc)" "$dir/summary.json" "$out/log" "$*" <<'PY'
import json, sys
scene, speed, rc, wall, summary, log, sets = sys.argv[1:]
name = scene.removeprefix("scenes/") + (f" `{sets.replace('--set ', '')}`" if sets else "")
if rc != "0":
    err = [l for l in open(log) if "error" in l.lower()]
    print(f"| {name} | {speed} | | | | | **failed**: {err[-1].strip()[:160] if err else rc} |")
    sys.exit()
r = json.load(open(summary))["result"]
p, s = r["plan"], r["stats"]
est = (r.get("error") or {}).get("extents_rel")
est = "no error estimate" if est is None else f"est. rel. error {est:.1e}"
print(f"| {name} | {speed} | {p['dt']:.3e} | {p['limit']:.3e} | {p['dt'] / p['limit']:.2f} | "
      f"{s['whole']['contact_instants']} / {s['steps']} | to the end, {est}, {float(wall):.0f} s |")
PY
}
echo "| scene | ω/ω_n | Δt (s) | limit (s) | Δt/limit | steps in contact / steps | outcome |"
echo "|---|---|---|---|---|---|---|"
for scene in $scenes; do
  if ! grep -q '^\[\[stator\]\]' "$scene"; then continue; fi
  for speed in 1.7 3.1 4.9; do
    run "$scene" "$speed"
  done
done
[ -n "${SCENES:-}" ] && [ "${SCENES}" != paper ] && exit 0
for eps in 1e4 1e5 1e6; do
  for speed in 1.7 3.1 4.9; do
    run scenes/paper/partial_rub.toml "$speed" --set "stator.0.stiffness_ratio=$eps"
  done
done
