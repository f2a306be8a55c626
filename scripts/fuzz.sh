#!/usr/bin/env bash
# Fuzz rubsim's readers with cargo-fuzz (libFuzzer): the scene loader with `--set` overrides
# (`scene`), the MSH reader (`msh`) and the output manifest reader (`manifest`); the targets are
# in fuzz/ (fuzz/src/lib.rs), their committed seeds in fuzz/seeds/<target>/.
#
#   scripts/fuzz.sh                        every target for FUZZ_TIME seconds (default 30)
#   FUZZ_RUNS=1000000 scripts/fuzz.sh msh  one target for 10^6 executions
#
# Each target's working corpus is fuzz/corpus/<target>/ (not committed; the seeds are read from
# fuzz/seeds/<target>/); a crash stops the run with the input in fuzz/artifacts/<target>/ and a
# non-zero exit. Needs cargo-fuzz (`cargo install cargo-fuzz --locked`, installed here when
# missing). Runs on the stable toolchain: cargo-fuzz passes nightly `-Z` flags to rustc, which
# RUSTC_BOOTSTRAP=1 lets the stable compiler accept. FUZZ_SANITIZER=none builds without
# AddressSanitizer (faster; panics and aborts are still caught).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
export RUSTC_BOOTSTRAP=1
if ! command -v cargo-fuzz > /dev/null; then
  cargo install cargo-fuzz --locked
fi
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene msh manifest)
fi
sanitizer="${FUZZ_SANITIZER:-address}"
limit=(-max_total_time="${FUZZ_TIME:-30}")
if [ -n "${FUZZ_RUNS:-}" ]; then
  limit=(-runs="$FUZZ_RUNS")
fi
for t in "${targets[@]}"; do
  case "$t" in
    scene) max_len=8192 ;;
    msh) max_len=16384 ;;
    manifest) max_len=4096 ;;
    *) echo "scripts/fuzz.sh: unknown target $t (scene, msh, manifest)" >&2; exit 2 ;;
  esac
  mkdir -p "corpus/$t"
  echo "== fuzz $t (${limit[*]}, sanitizer $sanitizer)"
  # -timeout: an input running 10 s is a hang; -rss_limit_mb: 2 GB of memory is a failure.
  cargo fuzz run --sanitizer "$sanitizer" "$t" "corpus/$t" "seeds/$t" -- \
    "${limit[@]}" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
done
