#!/usr/bin/env bash
# Reproduces the paper's Table I and robustness histograms on ../shared/data/objects (the results
# are discussed in docs/results.md). Resumable: rerun the same command to continue.
#   scripts/reproduce-paper.sh [DATA_DIR] [OUT_DIR]      (JOBS=2 for two parallel objects)
set -euo pipefail
data=$(realpath "${1:-../shared/data/objects}")
out=${2:-paper_reproduction}
jobs=${JOBS:-1}
skelgrasp=${SKELGRASP:-build/apps/skelgrasp}
mkdir -p "$out"
list="$out/objects.txt"
{
  ls "$data"/ycb/*.ply "$data"/ycb_poisson_simox/*.stl
  ls "$data"/kit/*.obj | awk 'NR % 6 == 1'   # every 6th KIT model
} > "$list"
echo "$(wc -l < "$list") objects listed in $list"
common=(--objects "$list" --hands armar3,sdh,shadow --planners skeleton,surface --jobs "$jobs"
        --timeout 20 --robustness-grasps 10 --robustness-samples 100 --surface-candidates 0)
# Correct friction cones, mu = 0.35; robustness as the paper states it (hand moved, 10 mm / 5 deg).
# The paper's judge (the object held still); the default, settled, lets it move (docs/evaluation.md).
"$skelgrasp" evaluate "${common[@]}" --mu 0.35 --robustness-variant paper --out "$out/mu035"
# The reference code's quality quirks and its robustness sampling (object moved, 5 mm / 2.5 deg).
"$skelgrasp" evaluate "${common[@]}" --reference-compat --robustness-variant reference --out "$out/reference_compat"
