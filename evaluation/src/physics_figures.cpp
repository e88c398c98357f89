#include "skelgrasp/evaluation/physics_figures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "skelgrasp/common/error.h"

namespace skelgrasp::evaluation {
namespace {

// Ranks 1..n of `values`, ties sharing their mean rank.
std::vector<double> averageRanks(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) ++j;
    const double rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) ranks[order[k]] = rank;
    i = j + 1;
  }
  return ranks;
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n;
  const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0 || syy <= 0) return std::numeric_limits<double>::quiet_NaN();
  return sxy / std::sqrt(sxx * syy);
}

}  // namespace

double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) throw InvalidArgument("spearman: series of different lengths");
  if (x.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  return pearson(averageRanks(x), averageRanks(y));
}

PhysicsFigures physicsFigures(const std::vector<JudgedGrasp>& grasps, std::size_t objects,
                              std::size_t objects_with_grasps) {
  PhysicsFigures figures;
  figures.objects = objects;
  figures.objects_with_grasps = objects_with_grasps;
  figures.grasps = grasps.size();
  std::size_t holds = 0, executions = 0, with_sim = 0;
  double cpu = 0, sim_sum = 0;
  std::vector<double> r_of_pairs, sim_of_pairs, r_of_nominal, nominal;
  for (const auto& g : grasps) {
    holds += g.nominal_holds;
    executions += static_cast<std::size_t>(g.executions);
    cpu += g.cpu_s;
    if (g.sim_r) {
      ++with_sim;
      sim_sum += *g.sim_r;
    }
    if (g.r) {
      r_of_nominal.push_back(*g.r);
      nominal.push_back(g.nominal_holds ? 1.0 : 0.0);
      if (g.sim_r) {
        r_of_pairs.push_back(*g.r);
        sim_of_pairs.push_back(*g.sim_r);
      }
    }
  }
  if (!grasps.empty()) {
    figures.nominal_hold_rate = static_cast<double>(holds) / static_cast<double>(grasps.size());
  }
  if (with_sim > 0) figures.mean_sim_r = sim_sum / static_cast<double>(with_sim);
  if (!r_of_pairs.empty()) {
    const double n = static_cast<double>(r_of_pairs.size());
    figures.mean_r = std::accumulate(r_of_pairs.begin(), r_of_pairs.end(), 0.0) / n;
    figures.mean_r_minus_sim_r =
        *figures.mean_r - std::accumulate(sim_of_pairs.begin(), sim_of_pairs.end(), 0.0) / n;
  }
  figures.spearman_r_sim_r = spearman(r_of_pairs, sim_of_pairs);
  figures.spearman_r_nominal = spearman(r_of_nominal, nominal);
  if (executions > 0) figures.ms_cpu_per_execution = 1000.0 * cpu / static_cast<double>(executions);
  return figures;
}

}  // namespace skelgrasp::evaluation
