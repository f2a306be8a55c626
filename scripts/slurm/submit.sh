#!/bin/bash
# Submits a rubsim sweep, map or continuation in segments (`continue … --segments M`) to Slurm: an array of N shards (at most T running at once),
# then the merge as a job that waits for the whole array. Prints the two job IDs.
#
#   scripts/slurm/submit.sh map scenes/paper/regime_map.toml out/map 32 8 [rubsim args…]
#   scripts/slurm/submit.sh continue scenes/paper/partial_rub.toml out/branch 8 4 --period 1 --segments 8
#
# RUBSIM (default: rubsim on PATH) is the binary the jobs run; extra arguments go to every
# shard (e.g. --set key=value). SBATCH_* variables and sbatch options in the environment
# (partition, account, time) apply as usual.
set -euo pipefail
if [ $# -lt 5 ]; then
    echo "usage: $0 sweep|map|continue SCENE OUT SHARDS THROTTLE [rubsim args…]" >&2
    exit 2
fi
cmd=$1 scene=$2 out=$3 n=$4 throttle=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
# The jobs' logs go to the submitting folder (rubsim-shard-<array>_<task>.out,
# rubsim-merge-<job>.out, as the .sbatch files name them), not into OUT: rubsim writes only into
# folders that hold nothing but its own output, and a log there would make OUT a user's folder.
array=$(sbatch --parsable --chdir="$PWD" \
    --array="1-$n%$throttle" "$here/shard.sbatch" "$cmd" "$scene" "$out" "$n" "$@")
array=${array%%;*}
merge=$(sbatch --parsable --chdir="$PWD" \
    --dependency="afterany:$array" "$here/merge.sbatch" "$out")
echo "array $array merge ${merge%%;*}"
