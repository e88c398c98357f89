#!/usr/bin/env python3
"""Per-dataset breakdown of a `skelgrasp evaluate` output directory (docs/results.md).

Usage: scripts/results_by_source.py EVAL_DIR
Prints one Markdown table: per hand, planner and object source (YCB google_16k .ply, the paper's
Poisson meshes .stl, KIT .obj): objects, force-closure rate (mean +- std over objects that
generated a grasp), median time per valid grasp and robustness r (mean +- std over scored grasps),
with the same definitions as summary.md.
"""
import json
import statistics
import sys


def source(path):
    if path.endswith(".stl"):
        return "Poisson (paper)"
    if path.endswith(".obj"):
        return "KIT"
    return "YCB google_16k"


def mean_std(values, scale=1.0):
    if not values:
        return "–"
    sd = statistics.pstdev(values) if len(values) > 1 else 0.0
    return f"{statistics.mean(values) * scale:.1f} ± {sd * scale:.1f}"


def main(directory):
    runs = [json.loads(line) for line in open(f"{directory}/runs.jsonl")]
    results = [json.loads(line) for line in open(f"{directory}/results.jsonl")]
    print("| hand | planner | objects | force-closure rate % | median ms per valid grasp | robustness r % |")
    print("|---|---|---|---|---|---|")
    for hand in ("armar3", "sdh", "shadow"):
        for planner in ("skeleton", "surface"):
            for src in ("YCB google_16k", "Poisson (paper)", "KIT"):
                rs = [r for r in runs if r["hand"] == hand and r["planner"] == planner
                      and source(r["object"]) == src]
                if not rs:
                    continue
                fc = [r["force_closure_rate"] for r in rs if r["generated"] > 0]
                ms = [r["ms_per_valid_grasp"] for r in rs if r["ms_per_valid_grasp"] is not None]
                rob = [x["robustness"] for x in results if x["hand"] == hand
                       and x["planner"] == planner and source(x["object"]) == src
                       and x["robustness"] is not None]
                median = f"{statistics.median(ms):.1f}" if ms else "–"
                print(f"| {hand} | {planner} | {src}: {len(rs)} | {mean_std(fc, 100)} | {median} | "
                      f"{mean_std(rob, 100)} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
