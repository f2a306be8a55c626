#!/usr/bin/env bash
# Fuzz rubsim's readers with cargo-fuzz (libFuzzer): the scene loader with `--set` overrides
# (`scene`), the MSH reader (`msh`), the output manifest reader (`manifest`) and the ROSS rotor
# file import of `import-ross`, TOML and JSON (`ross`); the targets are
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
#
# FUZZ_BUILD=quick (CI, .ci/run) builds cheaply for a short run: no sanitizer, opt-level 1,
# line tables only, 16 codegen units, in its own target directory fuzz/target/quick (so it never
# invalidates the full build's artifacts). The coverage instrumentation, debug assertions and
# overflow checks stay; the inputs run slower than in the full build.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
export RUSTC_BOOTSTRAP=1
if ! command -v cargo-fuzz > /dev/null; then
  cargo install cargo-fuzz --locked
fi
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene msh manifest ross)
fi
sanitizer="${FUZZ_SANITIZER:-address}"
build=()
case "${FUZZ_BUILD:-full}" in
  full) ;;
  quick)
    sanitizer="${FUZZ_SANITIZER:-none}"
    export CARGO_PROFILE_RELEASE_OPT_LEVEL=1 CARGO_PROFILE_RELEASE_DEBUG=line-tables-only
    build=(--codegen-units 16 --target-dir target/quick)
    ;;
  *) echo "scripts/fuzz.sh: FUZZ_BUILD is full or quick, not ${FUZZ_BUILD}" >&2; exit 2 ;;
esac
limit=(-max_total_time="${FUZZ_TIME:-30}")
if [ -n "${FUZZ_RUNS:-}" ]; then
  limit=(-runs="$FUZZ_RUNS")
fi
for t in "${targets[@]}"; do
  case "$t" in
    scene) max_len=8192 ;;
    msh) max_len=16384 ;;
    manifest) max_len=4096 ;;
    ross) max_len=16384 ;;
    *) echo "scripts/fuzz.sh: unknown target $t (scene, msh, manifest, ross)" >&2; exit 2 ;;
  esac
  mkdir -p "corpus/$t"
  echo "== fuzz $t (${limit[*]}, sanitizer $sanitizer, ${FUZZ_BUILD:-full} build)"
  # -timeout: an input running 10 s is a hang; -rss_limit_mb: 2 GB of memory is a failure.
  cargo fuzz run --sanitizer "$sanitizer" "${build[@]}" "$t" "corpus/$t" "seeds/$t" -- \
    "${limit[@]}" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
done
