#!/usr/bin/env bash
# Runs every libFuzzer target of FUZZ_DIR (built by `make fuzz`) for SECONDS each, JOBS at a time.
# Seeds: the hand-made and once-crashing inputs of fuzz/regressions/, small files generated here,
# and real files from ../shared/data when present (copied into the build tree, never the project).
# Exits 1 when any target found a crash, leak, sanitizer report or hang; the inputs are in
# FUZZ_DIR/findings/<target>/ and belong, once fixed, in fuzz/regressions/<target>/.
set -euo pipefail
fuzz_dir=${1:?usage: fuzz.sh FUZZ_DIR SECONDS [JOBS]}
seconds=${2:?usage: fuzz.sh FUZZ_DIR SECONDS [JOBS]}
jobs=${3:-1}
root=$(cd "$(dirname "$0")/.." && pwd)
shared="$root/../shared/data"
targets=(mesh_reader cloud_reader npy_reader capture_description grasp_description contacts_json
  grasps_file)
# Seeds larger than this slow every mutation down; small real files carry the same structure.
max_seed_bytes=262144

# prefix_copy TARGET PREFIX_BYTE FILE: a mesh/cloud seed is one format-selector byte + the file.
prefix_copy() {
  local dir="$fuzz_dir/corpus/$1" name
  name=$(basename "$3")
  [[ $(stat -c %s "$3") -le $max_seed_bytes ]] || return 0
  { printf "\\x$2"; cat "$3"; } > "$dir/seed-$name"
}

for t in "${targets[@]}"; do
  mkdir -p "$fuzz_dir/corpus/$t" "$fuzz_dir/findings/$t"
  cp "$root/fuzz/regressions/$t/"* "$fuzz_dir/corpus/$t/" 2>/dev/null || true
done
if [[ -d "$shared" ]]; then
  n=0
  while IFS= read -r f; do
    case "${f##*.}" in
      ply) prefix_copy mesh_reader 00 "$f" ;; obj) prefix_copy mesh_reader 01 "$f" ;;
      off) prefix_copy mesh_reader 02 "$f" ;; stl) prefix_copy mesh_reader 03 "$f" ;;
    esac
    n=$((n + 1)); [[ $n -lt 40 ]] || break
  done < <(find "$shared/objects" -type f \( -name '*.ply' -o -name '*.obj' -o -name '*.stl' \) \
             -size -256k 2>/dev/null | sort)
  while IFS= read -r f; do prefix_copy cloud_reader 00 "$f"; done < \
    <(find "$shared/scans" -name '*.pcd' -size -256k 2>/dev/null | sort | head -20)
  while IFS= read -r f; do
    [[ $(stat -c %s "$f") -le $max_seed_bytes ]] && cp "$f" "$fuzz_dir/corpus/npy_reader/seed-$(basename "$f")"
  done < <(find "$shared/captures" -name '*.npy' 2>/dev/null | sort | head -5)
else
  echo "fuzz: $shared is absent; seeding with fuzz/regressions only" >&2
fi
for d in "$root"/grasping/hands/*/; do
  cp "$d"/*.grasp.json "$fuzz_dir/corpus/grasp_description/" 2>/dev/null || true
done

status=0
run_target() {
  local t=$1
  "$fuzz_dir/fuzz/fuzz_$t" "$fuzz_dir/corpus/$t" -max_total_time="$seconds" -timeout=20 \
    -rss_limit_mb=4096 -max_len=$max_seed_bytes -print_final_stats=1 \
    -artifact_prefix="$fuzz_dir/findings/$t/" > "$fuzz_dir/findings/$t.log" 2>&1
}
running=0
for t in "${targets[@]}"; do
  echo "fuzz: $t for ${seconds} s"
  run_target "$t" &
  running=$((running + 1))
  if [[ $running -ge $jobs ]]; then wait -n || true; running=$((running - 1)); fi
done
wait || true
for t in "${targets[@]}"; do
  execs=$(grep -m1 'stat::number_of_executed_units' "$fuzz_dir/findings/$t.log" | awk '{print $2}')
  found=$(find "$fuzz_dir/findings/$t" -type f | wc -l)
  echo "fuzz: $t: ${execs:-?} inputs, $found finding(s)"
  if [[ $found -gt 0 ]]; then
    status=1
    find "$fuzz_dir/findings/$t" -type f | sed 's/^/  /'
    grep -m3 -E 'ERROR|SUMMARY|terminate|uncaught' "$fuzz_dir/findings/$t.log" | sed 's/^/  /' || true
  fi
done
exit $status
