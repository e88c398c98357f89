#!/usr/bin/env bash
# Regenerates the tables of docs/results.md. Each table there sits between two markers,
# <!-- results:NAME --> and <!-- /results:NAME -->, under the command that produces it; this
# script runs that command and writes the new table between the markers.
#
#   scripts/results.sh [SECTION...]
#
# Sections (the fast ones take minutes on 2 cores, the slow ones hours):
#   fast:  judge segment reconstruct skeleton demo run           (the default)
#   slow:  ranking (58 YCB meshes, 3 hands, mu 0.35 and 0.5; about an hour on one core)
#          scan2grasp (ten YCB meshes seen in two single views, 4 hands, two judges; about an hour)
#          paper (scripts/reproduce-paper.sh; about 1.5 hours with JOBS=2 in the environment)
#          physics (bench physics: 58 YCB meshes, 3 hands, nominal; sim_r on 12; about 1.5 hours)
#   all:   every section
#
# Environment: SKELGRASP (default build/apps/skelgrasp), DATA (../shared/data),
# OUT (results_output: the commands' own outputs, kept for a look), RESULTS_MD (docs/results.md),
# NICE (default "nice -n 10"; set it empty to run at normal priority). Timings are wall clock on
# whatever else the machine runs; run on a quiet machine for figures worth comparing.
set -euo pipefail
cd "$(dirname "$0")/.."

skelgrasp=${SKELGRASP:-build/apps/skelgrasp}
data=${DATA:-../shared/data}
out=${OUT:-results_output}
results_md=${RESULTS_MD:-docs/results.md}
read -r -a nice_cmd <<< "${NICE-nice -n 10}"

[[ -x "$skelgrasp" ]] || { echo "results.sh: $skelgrasp: not built (make, or SKELGRASP=...)" >&2; exit 2; }
[[ -d "$data/objects" ]] || { echo "results.sh: $data: no shared data (DATA=...)" >&2; exit 2; }
command -v python3 > /dev/null || { echo "results.sh: python3 is needed to format the tables" >&2; exit 2; }
mkdir -p "$out"

# The commands' logs (stderr) go to $out/commands.log; a failing command stops the script.
sg() { "${nice_cmd[@]}" "$skelgrasp" "$@" 2>> "$out/commands.log"; }
say() { echo "results.sh: $*" >&2; }
trap 'say "failed; the last lines of $out/commands.log:"; tail -n 5 "$out/commands.log" >&2 || true' ERR

# splice NAME FILE: replace the table between NAME's markers in $results_md by FILE's content.
splice() {
  python3 - "$1" "$2" "$results_md" <<'PY'
import os, sys
name, table, md = sys.argv[1:4]
text = open(md, encoding="utf-8").read()
begin, end = f"<!-- results:{name} -->", f"<!-- /results:{name} -->"
if begin not in text or end not in text:
    sys.exit(f"results.sh: {md} has no markers for '{name}'")
i = text.index(begin) + len(begin)
j = text.index(end)
body = open(table, encoding="utf-8").read().strip("\n")
tmp = f"{md}.tmp.{os.getpid()}"
with open(tmp, "w", encoding="utf-8") as f:
    f.write(text[:i] + "\n" + body + "\n" + text[j:])
os.replace(tmp, md)
PY
  say "$1: table written to $results_md"
}

# The judge: stepwise closing + hull against fast closing + LP, fixed YCB grasps, one core.
section_judge() {
  sg bench judge --json "$out/judge.json" > "$out/judge.txt"
  python3 - "$out/judge.json" > "$out/judge.md" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))["hands"]
print("| hand | close + FC ms | robustness of one grasp, ms (100 samples) | stepwise + hull: close + FC ms | robustness ms | robustness, fast / stepwise |")
print("|---|---|---|---|---|---|")
for hand in ("armar3", "sdh", "shadow", "parallel_gripper"):
    if hand not in d:
        continue
    n, o = d[hand]["new"], d[hand]["old"]
    print(f"| {hand} | {n['close_ms'] + n['fc_ms']:.2f} | {1e3 * n['robustness_s']:.0f} | "
          f"{o['close_ms'] + o['fc_ms']:.1f} | {1e3 * o['robustness_s']:.0f} | "
          f"{o['robustness_s'] / n['robustness_s']:.0f}x |")
PY
  splice judge "$out/judge.md"
}

# Segmentation of the eight labelled mOSD scans, both methods.
section_segment() {
  local scans=("$data"/scans/pcd/osd_test*.pcd)
  sg bench segment "${scans[@]}" --method lccp --json "$out/segment_lccp.json" > "$out/segment_lccp.txt"
  sg bench segment "${scans[@]}" --method euclidean --json "$out/segment_euclidean.json" > "$out/segment_euclidean.txt"
  python3 - "$out/segment_euclidean.json" "$out/segment_lccp.json" > "$out/segment.md" <<'PY'
import json, os, sys
eu, lc = (json.load(open(p)) for p in sys.argv[1:3])
print("| scene | objects | found: Euclidean / LCCP | precision | recall |")
print("|---|---|---|---|---|")
by_input = {os.path.basename(s["input"]): s for s in lc["scenes"]}
for s in eu["scenes"]:
    l = by_input[os.path.basename(s["input"])]
    print(f"| {os.path.basename(s['input'])} | {s['objects_labelled']} | {s['objects_found']} / {l['objects_found']} | "
          f"{s['mean_precision']:.3f} / {l['mean_precision']:.3f} | {s['mean_recall']:.3f} / {l['mean_recall']:.3f} |")
a, b = eu["summary"], lc["summary"]
print(f"| **all {a['scenes']} scans, {a['objects']} objects** | | count within ±1: {a['count_within_one']} / {b['count_within_one']} | "
      f"**{a['mean_precision']:.3f} / {b['mean_precision']:.3f}** | **{a['mean_recall']:.3f} / {b['mean_recall']:.3f}** |")
print()
print(f"Segmentation time for the eight scans (after filters and plane): Euclidean {a['segment_s']:.2f} s, LCCP {b['segment_s']:.2f} s.")
PY
  splice segment "$out/segment.md"
}

# Scan to closed mesh, per stage, best of 3, one thread.
section_reconstruct() {
  cat > "$out/00_flashlight.json" <<EOF
{"depth": "$(realpath "$data")/captures/gqcnn_primesense/00_flashlight/depth_0.npy",
 "mask": "$(realpath "$data")/captures/gqcnn_primesense/00_flashlight/segmask_0.png",
 "intrinsics": "$(realpath "$data")/captures/gqcnn_primesense/calib/primesense.intr",
 "camera_to_world": "$(realpath "$data")/captures/gqcnn_primesense/calib/primesense.tf"}
EOF
  local p="$data/scans/pcd"
  sg bench reconstruct "$p/pcl_table_scene_mug_stereo_textured.pcd" "$p/pcl_milk_cartoon_all_small_clorox.pcd" \
    "$p/osd_test2.pcd" "$p/osd_test46.pcd" "$p/osd_test50.pcd" "$p/osd_test58.pcd" "$out/00_flashlight.json" \
    --repeat 3 --json "$out/reconstruct.json" > "$out/reconstruct.txt"
  python3 - "$out/reconstruct.json" > "$out/reconstruct.md" <<'PY'
import json, os, sys
rows = json.load(open(sys.argv[1]))["rows"]
keys = ["load_s", "filters_s", "scene_s", "normals_s", "poisson_s", "trim_s", "regularise_s", "observed_s", "total_s"]
print("| input | points | load | filters | scene | normals | Poisson | trim | regularise | flags | total |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    cells = " | ".join(f"{r[k]:.2f}" for k in keys)
    print(f"| {os.path.basename(r['input'])} | {r['points']} | {cells} |")
PY
  splice reconstruct "$out/reconstruct.md"
}

# Regularisation + skeleton per mesh over the 75 YCB meshes (google_16k and the paper's Poisson ones).
section_skeleton() {
  sg bench skeleton "$data/objects/ycb" "$data/objects/ycb_poisson_simox" --json "$out/skeleton.json" > "$out/skeleton.txt"
  python3 - "$out/skeleton.json" > "$out/skeleton.md" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
rows = d["objects"]
ok = [r for r in rows if r.get("status") == "ok"]
print("| meshes | skeletons | regularise s, median | skeleton s, median | total s, median |")
print("|---|---|---|---|---|")
print(f"| {len(rows)} | {len(ok)} | {d['median_regularise_s']:.2f} | {d['median_skeleton_s']:.2f} | {d['median_total_s']:.2f} |")
PY
  splice skeleton "$out/skeleton.md"
}

# The demo scene: grasps and best r per object, and the scene's run time.
section_demo() {
  rm -rf "$out/demo"
  sg demo --out "$out/demo" > "$out/demo.txt"
  python3 - "$out/demo" > "$out/demo.md" <<'PY'
import json, re, sys
d = sys.argv[1]
run = json.load(open(f"{d}/grasps.json"))
made = dict((int(k), name) for name, k in re.findall(
    r'<tr><td>(\w+)</td><td><a href="report.html#object-(\d+)"', open(f"{d}/index.html").read()))
print("| object | grasps | best r | r of the first-ranked grasp |")
print("|---|---|---|---|")
for o in run["objects"]:
    grasps = [g for g in run["grasps"] if g["object"] == o["id"]]
    rs = [g["robustness"]["r"] for g in grasps if g.get("robustness")]
    best = f"{max(rs):.2f}" if rs else "–"
    first = f"{grasps[0]['robustness']['r']:.2f}" if grasps and grasps[0].get("robustness") else "–"
    print(f"| {made.get(o['id'], o['id'])} | {o['grasps']} | {best} | {first} |")
print()
print(f"The run over the five objects took {run['timing']['total_s']:.1f} s (`total_s` in grasps.json's `timing`).")
PY
  splice demo "$out/demo.md"
}

# The main job per stage: each demo object as a one-target run, and two real scans.
section_run() {
  sg bench run demo "$data/scans/pcd/gpd_table_mug.pcd" "$data/scans/pcd/pcl_table_scene_mug_stereo_textured.pcd" \
    --repeat 3 --json "$out/run.json" > "$out/run.txt"
  python3 - "$out/run.json" > "$out/run.md" <<'PY'
import json, os, sys
rows = json.load(open(sys.argv[1]))["rows"]
stages = ["filter", "segment", "normals", "reconstruct", "skeleton", "occupancy", "plan", "rank"]
print("| input | " + " | ".join(stages) + " | total | grasps |")
print("|---|" + "---|" * (len(stages) + 2))
for r in rows:
    cells = " | ".join(f"{r['stages_s'][s]:.2f}" for s in stages)
    print(f"| {os.path.basename(r['input'])} | {cells} | {r['total_s']:.2f} | {r['grasps']} |")
PY
  splice run "$out/run.md"
}

# Every object of the eight labelled mOSD scans in one run each (run --object all), SDH and
# ARMAR-III, on one thread and on both cores.
section_scenes() {
  local scans=("$data"/scans/pcd/osd_test*.pcd)
  for hand in sdh armar3; do
    sg bench run "${scans[@]}" --object all --hand "$hand" --repeat 1 \
      --json "$out/scenes_$hand.json" > "$out/scenes_$hand.txt"
  done
  python3 - "$out/scenes_sdh.json" "$out/scenes_armar3.json" > "$out/scenes.md" <<'PY'
import json, os, sys
sdh, armar = (json.load(open(p))["rows"] for p in sys.argv[1:3])
print("| scene | objects | with a grasp: SDH / ARMAR-III | one thread, s: SDH / ARMAR-III | two threads / one |")
print("|---|---|---|---|---|")
totals = [0, 0, 0]
for a, b in zip(sdh, armar):
    totals[0] += a["objects"]; totals[1] += a["objects_with_grasps"]; totals[2] += b["objects_with_grasps"]
    print(f"| {os.path.basename(a['input'])} | {a['objects']} | {a['objects_with_grasps']} / {b['objects_with_grasps']} | "
          f"{a['one_thread_s']:.1f} / {b['one_thread_s']:.1f} | {a['ratio']:.2f} / {b['ratio']:.2f} |")
print(f"| **all 8 scans** | {totals[0]} | **{totals[1]} ({100 * totals[1] / totals[0]:.0f} %) / "
      f"{totals[2]} ({100 * totals[2] / totals[0]:.0f} %)** | | |")
PY
  splice scenes "$out/scenes.md"
}

# evaluate --robust-ranking, as plan ranks; writes one table row per hand from summary.md.
# ranking_rows DIR MU LABEL: the rows of one batch ("58 YCB": the object count, then LABEL).
ranking_rows() {
  python3 - "$1/summary.md" "$2" "$3" <<'PY'
import re, sys
summary, mu, objects = sys.argv[1:4]
names = {"armar3": "ARMAR-III", "sdh": "Schunk SDH", "shadow": "Shadow"}
text = open(summary).read()
ranked = {m[0]: m for m in re.findall(
    r"^\| (\w+) \| skeleton \| (\d+) \| [\d.]+% \((\d+)\) \| ([\d.]+)% \| ([\d.]+)% \| ([\d.]+) \|$", text, re.M)}
refined = {m[0]: m for m in re.findall(
    r"^\| (\w+) \| skeleton \| (\d+) \| ([\d.]+)% \(([\d.]+)%\) \| [\d.]+% \([\d.]+%\) \| ([\d.]+) \| [\d.]+ \|$", text, re.M)}
for hand in ("armar3", "sdh", "shadow"):
    if hand not in ranked:
        continue
    _, runs, with_grasp, median, mean, plan_s = ranked[hand]
    r = refined.get(hand)
    without = f"{r[2]} % ({r[3]} %) | {r[4]}" if r else "– | –"
    label = f"{runs} {objects}".strip()
    print(f"| {names[hand]} | {label} | {mu} | {with_grasp} of {runs} | **{median} %** ({mean} %) | {plan_s} | {without} |")
PY
}

ranking_header() {
  echo "| hand | objects | μ | objects with a grasp | top-10 r, median (mean) | plan s, median | without the refinement for robustness: top-10 r | plan s |"
  echo "|---|---|---|---|---|---|---|---|"
}

# ranking_batch OUT_DIR OBJECTS MU: the goal's command.
ranking_batch() {
  sg evaluate --objects "$2" --hands armar3,sdh,shadow --planners skeleton --robust-ranking \
    --no-load-check --robustness-grasps 10 --robustness-samples 50 --mu "$3" --timeout 20 --jobs 1 \
    --out "$1" > /dev/null
}

section_ranking() {
  ranking_batch "$out/ranking_mu035" "$data/objects/ycb" 0.35
  ranking_batch "$out/ranking_mu05" "$data/objects/ycb" 0.5
  { ranking_header
    ranking_rows "$out/ranking_mu035" 0.35 YCB
    ranking_rows "$out/ranking_mu05" 0.5 YCB; } > "$out/ranking.md"
  splice ranking "$out/ranking.md"
}

# The physics judge on what plan returns: bench physics over the 58 YCB meshes (nominal), and with
# sim_r (10 perturbed executions per grasp) over the first 12 of them for ARMAR-III and the SDH.
physics_table() {
  python3 - "$@" <<'PY'
import json, statistics, sys
names = {"armar3": "ARMAR-III", "sdh": "Schunk SDH", "shadow": "Shadow", "parallel_gripper": "parallel gripper"}
print("| hand | objects with a grasp | r of the executed grasps, median (mean) over objects | nominal holds (physics) "
      "| mean sim_r | mean r − sim_r | Spearman r ~ holds | Spearman r ~ sim_r | ms CPU per execution |")
print("|---|---|---|---|---|---|---|---|---|")
for path in sys.argv[1:]:
    doc = json.load(open(path))
    for s in doc["summary"]:
        rows = [g for g in doc["grasps"] if g["hand"] == s["hand"]]
        per_object = {}
        for g in rows:
            per_object.setdefault(g["object"], []).append(g["r"] or 0.0)
        tops = [statistics.mean(v) for v in per_object.values()]
        tops += [0.0] * (s["objects"] - len(tops))
        fmt = lambda v, f="{:.2f}": "–" if v is None else f.format(v)
        print(f"| {names.get(s['hand'], s['hand'])} | {s['objects_with_grasps']} of {s['objects']} "
              f"| {statistics.median(tops):.2f} ({statistics.mean(tops):.2f}) "
              f"| **{100 * s['nominal_hold_rate']:.0f} %** of {s['grasps']} | {fmt(s['mean_sim_r'])} "
              f"| {fmt(s['mean_r_minus_sim_r'], '{:+.2f}')} | {fmt(s['spearman_r_nominal'])} "
              f"| {fmt(s['spearman_r_sim_r'])} | {s['ms_cpu_per_execution']:.0f} |")
PY
}

section_physics() {
  sg bench physics "$data/objects/ycb" --hands armar3,sdh,shadow --json "$out/physics.json" \
    > "$out/physics.txt"
  sg bench physics "$data/objects/ycb" --hands armar3,sdh --limit 12 --grasps 5 --samples 10 \
    --json "$out/physics_sim_r.json" > "$out/physics_sim_r.txt"
  physics_table "$out/physics.json" "$out/physics_sim_r.json" > "$out/physics.md"
  splice physics "$out/physics.md"
}

# From one view to the real object: ten YCB meshes, two single views each, run per view and hand,
# the top 10 judged on the true mesh; with the load check (run's default) and without it.
scan2grasp_meshes=(003_cracker_box 005_tomato_soup_can 006_mustard_bottle 011_banana 021_bleach_cleanser
  024_bowl 025_mug 035_power_drill 043_phillips_screwdriver 048_hammer)
section_scan2grasp() {
  local meshes=()
  for m in "${scan2grasp_meshes[@]}"; do meshes+=("$data/objects/ycb/$m.ply"); done
  sg bench scan2grasp "${meshes[@]}" --views 2 --no-physics --timeout 0 \
    --json "$out/scan2grasp.json" > "$out/scan2grasp.txt"
  sg bench scan2grasp "${meshes[@]}" --views 2 --no-physics --timeout 0 --no-load-check \
    --json "$out/scan2grasp_no_load_check.json" > "$out/scan2grasp_no_load_check.txt"
  python3 - "$out/scan2grasp.json" "$out/scan2grasp_no_load_check.json" > "$out/scan2grasp.md" <<'PY'
import json, sys
print("| hand | judge | objects with grasps | views with grasps | claimed r | **r on the true object** | top-10 starting inside | claimed − true | run s |")
print("|---|---|---|---|---|---|---|---|---|")
for path in sys.argv[1:3]:
    d = json.load(open(path))
    judge = "settled, load check" if d["load_check"] else "settled, no load check"
    for h in d["summary"]:
        diff = h["claimed_minus_true_r"]
        print(f"| {h['hand']} | {judge} | {h['objects_with_grasps']} / {h['objects']} | "
              f"{h['views_with_grasps']} / {h['views']} | {h['median_claimed_r']:.2f} | "
              f"**{h['median_true_r']:.2f}** | {h['starts_inside']} / {h['top_grasps']} | "
              f"{'-' if diff is None else f'{diff:+.2f}'} | {h['median_run_s']:.1f} |")
PY
  splice scan2grasp "$out/scan2grasp.md"
}

# The paper's Table I: scripts/reproduce-paper.sh, then its two summaries' tables.
section_paper() {
  SKELGRASP="$skelgrasp" "${nice_cmd[@]}" scripts/reproduce-paper.sh "$data/objects" "$out/paper" \
    2>> "$out/commands.log"
  for mode in reference_compat mu035; do
    { echo "| hand | planner | objects | grasps | time per valid grasp | force-closure rate | robustness r | precision / power |"
      echo "|---|---|---|---|---|---|---|---|"
      grep -E '^\| (armar3|sdh|shadow) \|' "$out/paper/$mode/summary.md" | head -6; } > "$out/paper_$mode.md"
    splice "paper_$mode" "$out/paper_$mode.md"
  done
}

fast=(judge segment reconstruct skeleton demo run scenes)
slow=(ranking scan2grasp paper physics)
sections=("$@")
[[ ${#sections[@]} -eq 0 ]] && sections=("${fast[@]}")
[[ "${sections[*]}" == "all" ]] && sections=("${fast[@]}" "${slow[@]}")
for s in "${sections[@]}"; do
  declare -F "section_$s" > /dev/null || { echo "results.sh: unknown section '$s'" >&2; exit 2; }
done
for s in "${sections[@]}"; do
  say "$s ..."
  start=$(date +%s)
  "section_$s"
  say "$s took $(($(date +%s) - start)) s"
done
