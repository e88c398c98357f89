#pragma once
#include <limits>
// The grasp sections of the run reports (one target and scene): a table of the ranked grasps with
// their robustness r and its interval, and a histogram of r over the object's scored grasps.
#include <string>
#include <vector>

#include "skelgrasp/pipeline/run_pipeline.h"
#include "skelgrasp/presentation/html_report.h"

namespace skelgrasp::pipeline::internal {

// Rank, type, strategy, epsilon, observed contacts, r [95 % interval] and its failed samples by
// cause ("-" when not scored) and the rank score, one row per grasp.
// The first `max_rows` ranked grasps (all by default), with a line saying how many more
// grasps.json holds.
void addGraspTable(presentation::HtmlReport& report, const std::vector<RankedGrasp>& ranked,
                   std::size_t max_rows = std::numeric_limits<std::size_t>::max());

// An inline SVG bar chart (no file, works offline) of r over the scored grasps, in ten bins of
// 0.1; a sentence instead when no grasp was scored.
void addRobustnessHistogram(presentation::HtmlReport& report,
                            const std::vector<RankedGrasp>& ranked);

// Why the planner's hypotheses were rejected: a table of the rejection reasons and of the first
// colliding link of scene collisions, and the hypothesis, generated and force-closure counts.
void addRejectionTable(presentation::HtmlReport& report, const grasping::PlanSummary& summary);

// The SVG of that chart (for tests): `counts` per bin of width 1 / counts.size().
std::string robustnessHistogramSvg(const std::vector<std::size_t>& counts);

}  // namespace skelgrasp::pipeline::internal
