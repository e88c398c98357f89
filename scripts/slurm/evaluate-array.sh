#!/usr/bin/env bash
# Submits a skelgrasp evaluation to Slurm: one `evaluate --shard i/n` per array task and one
# merge job that starts when every shard finished (afterok), so the merged directory holds the
# same results as a single `evaluate` run (docs/evaluation.md, "On a Slurm cluster").
#
#   scripts/slurm/evaluate-array.sh --shards 8 --out /scratch/eval [--cpus 4] [--time 04:00:00]
#       [--partition P] [--sbatch-arg ARG]... [--skelgrasp PATH] [--dry-run] -- EVALUATE_OPTIONS...
#
# EVALUATE_OPTIONS are passed to every shard as they are (e.g. --objects /data/ycb --hands sdh);
# --shard, --out and --jobs are set here. A shard that fails or is pre-empted can be resubmitted
# (`evaluate` resumes its directory); the merge job then needs `skelgrasp merge` by hand
# (the command is printed in the merge job's log and below).
# --dry-run prints the sbatch calls instead of submitting them.
set -euo pipefail

usage() {
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
fail() {
  echo "evaluate-array: error: $*" >&2
  exit 2
}

shards=""
out=""
cpus=1
time_limit="04:00:00"
partition=""
dry_run=0
skelgrasp=""
extra_sbatch=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --shards) shards=${2:-}; shift 2 || usage ;;
    --out) out=${2:-}; shift 2 || usage ;;
    --cpus) cpus=${2:-}; shift 2 || usage ;;
    --time) time_limit=${2:-}; shift 2 || usage ;;
    --partition) partition=${2:-}; shift 2 || usage ;;
    --sbatch-arg) extra_sbatch+=("${2:-}"); shift 2 || usage ;;
    --skelgrasp) skelgrasp=${2:-}; shift 2 || usage ;;
    --dry-run) dry_run=1; shift ;;
    -h | --help) usage ;;
    --) shift; break ;;
    *) fail "unknown option '$1' (evaluate options go after --)" ;;
  esac
done
evaluate_options=("$@")

[[ "$shards" =~ ^[1-9][0-9]*$ ]] || fail "--shards must be a positive integer, got '$shards'"
# Slurm's default MaxArraySize is 1001; larger batches need more objects per shard, not more shards.
((shards <= 1000)) || fail "--shards $shards is above 1000 (Slurm's default MaxArraySize)"
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || fail "--cpus must be a positive integer, got '$cpus'"
[[ -n "$out" ]] || fail "--out DIR is required (a folder every node can write, e.g. on /scratch)"
[[ ${#evaluate_options[@]} -gt 0 ]] || fail "no evaluate options after -- (at least --objects)"
for option in "${evaluate_options[@]}"; do
  case "$option" in
    --shard | --shard=* | --out | --out=* | --jobs | --jobs=*)
      fail "$option is set by this script; leave it out of the evaluate options" ;;
  esac
done
if [[ -z "$skelgrasp" ]]; then
  skelgrasp=$(command -v skelgrasp || true)
  [[ -n "$skelgrasp" ]] || skelgrasp="$(cd "$(dirname "$0")/../.." && pwd)/build/apps/skelgrasp"
fi
[[ $dry_run -eq 1 || -x "$skelgrasp" ]] || fail "$skelgrasp: not an executable (use --skelgrasp PATH)"
if [[ $dry_run -eq 0 ]]; then
  command -v sbatch > /dev/null || fail "sbatch not found: run this on a Slurm login node"
  mkdir -p "$out/logs"
fi
out=$(realpath -m "$out")

common=(--time="$time_limit" "${extra_sbatch[@]}")
[[ -n "$partition" ]] && common+=(--partition="$partition")

# One shard per array task; SLURM_ARRAY_TASK_ID is expanded on the compute node, not here.
printf -v shard_cmd '%q ' "$skelgrasp" evaluate "${evaluate_options[@]}" --jobs "$cpus"
shard_cmd+="--shard \${SLURM_ARRAY_TASK_ID}/$shards --out $(printf %q "$out")/shard-\${SLURM_ARRAY_TASK_ID}"
merge_dirs=""
for ((i = 0; i < shards; ++i)); do merge_dirs+=" $(printf %q "$out/shard-$i")"; done
printf -v merge_cmd '%q ' "$skelgrasp" merge
merge_cmd+="${merge_dirs# } --out $(printf %q "$out/merged")"

array_call=(sbatch --parsable --job-name=skelgrasp-evaluate --array="0-$((shards - 1))"
  --cpus-per-task="$cpus" --output="$out/logs/shard-%a.log" "${common[@]}" --wrap="$shard_cmd")
if [[ $dry_run -eq 1 ]]; then
  printf '%q ' "${array_call[@]}"
  echo
  array_job="<ARRAY_JOB_ID>"
else
  array_job=$("${array_call[@]}")
  array_job=${array_job%%;*}  # --parsable prints "id" or "id;cluster"
fi
merge_call=(sbatch --parsable --job-name=skelgrasp-merge --dependency="afterok:$array_job"
  --cpus-per-task=1 --output="$out/logs/merge.log" "${common[@]}"
  --wrap="echo 'merge: $merge_cmd'; $merge_cmd")
if [[ $dry_run -eq 1 ]]; then
  printf '%q ' "${merge_call[@]}"
  echo
  exit 0
fi
merge_job=$("${merge_call[@]}")
echo "evaluate-array: submitted $shards shard(s) as job $array_job, merge as job ${merge_job%%;*}"
echo "evaluate-array: results in $out/merged; if a shard fails, resubmit it and run: $merge_cmd"
