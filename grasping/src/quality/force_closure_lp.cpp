// The force-closure linear program and the squeeze LP of settling; GLPK is used only in this file.
#include <glpk.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "skelgrasp/grasping/quality/quality.h"

namespace skelgrasp::grasping {

namespace {

constexpr int kWrenchRows = 6;

struct ProblemDeleter {
  void operator()(glp_prob* problem) const { glp_delete_prob(problem); }
};

// GLPK's terminal switch lives in its environment, which Debian's GLPK 5.0 keeps per thread
// (glp_config("TLS") = "_Thread_local"): switching it off here does not race with other threads,
// and the previous state is restored for callers that use GLPK themselves.
class QuietGlpk {
 public:
  QuietGlpk() : previous_(glp_term_out(GLP_OFF)) {}
  ~QuietGlpk() { glp_term_out(previous_); }
  QuietGlpk(const QuietGlpk&) = delete;
  QuietGlpk& operator=(const QuietGlpk&) = delete;

 private:
  int previous_;
};

// GLPK creates that per-thread environment on first use and frees it only in glp_free_env(): a
// thread that ends without calling it leaks it (about 700 bytes; LeakSanitizer reports each such
// thread, e.g. short-lived std::threads). One guard per thread that solved an LP frees it when the
// thread ends (glp_free_env does nothing when a caller already freed it).
struct GlpkEnvironmentRelease {
  ~GlpkEnvironmentRelease() { glp_free_env(); }
};

// A constraint matrix as GLPK loads it: 1-based triplet arrays (index 0 unused), zeros left out.
class Triplets {
 public:
  void reserve(std::size_t nonzeros) {
    rows_.reserve(nonzeros + 1);
    cols_.reserve(nonzeros + 1);
    values_.reserve(nonzeros + 1);
  }
  void add(int row, int col, double value) {
    if (value == 0) return;
    rows_.push_back(row);
    cols_.push_back(col);
    values_.push_back(value);
  }
  void loadInto(glp_prob* lp) const {
    glp_load_matrix(lp, static_cast<int>(values_.size()) - 1, rows_.data(), cols_.data(),
                    values_.data());
  }

 private:
  std::vector<int> rows_{0}, cols_{0};
  std::vector<double> values_{0.0};
};

}  // namespace

ClosureLpResult solveClosureLp(const std::vector<Wrench>& wrenches) {
  if (wrenches.empty()) throw InvalidArgument("force-closure LP: no wrenches");
  for (const auto& w : wrenches) {
    if (!w.allFinite()) throw InvalidArgument("force-closure LP: non-finite wrench");
  }
  thread_local const GlpkEnvironmentRelease release_at_thread_exit;
  const QuietGlpk quiet;
  const int n = static_cast<int>(wrenches.size());
  // Substituting alpha_i = l + beta_i (beta_i >= 0) keeps the LP to 7 rows instead of n + 7:
  //   maximise l  s.t.  sum_i beta_i w_i + l (sum_i w_i) = 0,  sum_i beta_i + n l = 1.
  // Same optimum l* as the textbook form (alpha_i - l >= 0 rows); the simplex then works on a
  // 7 x 7 basis whatever the number of wrenches.
  std::unique_ptr<glp_prob, ProblemDeleter> problem(glp_create_prob());
  glp_prob* lp = problem.get();
  glp_set_obj_dir(lp, GLP_MAX);
  glp_add_rows(lp, kWrenchRows + 1);
  for (int row = 1; row <= kWrenchRows; ++row) glp_set_row_bnds(lp, row, GLP_FX, 0.0, 0.0);
  glp_set_row_bnds(lp, kWrenchRows + 1, GLP_FX, 1.0, 1.0);
  glp_add_cols(lp, n + 1);
  const int margin_col = n + 1;
  Wrench sum = Wrench::Zero();
  Triplets matrix;
  matrix.reserve(static_cast<std::size_t>(n + 1) * (kWrenchRows + 1));
  for (int i = 0; i < n; ++i) {
    const int col = i + 1;
    glp_set_col_bnds(lp, col, GLP_LO, 0.0, 0.0);
    for (int k = 0; k < kWrenchRows; ++k) matrix.add(k + 1, col, wrenches[i][k]);
    matrix.add(kWrenchRows + 1, col, 1.0);
    sum += wrenches[i];
  }
  glp_set_col_bnds(lp, margin_col, GLP_FR, 0.0, 0.0);
  glp_set_obj_coef(lp, margin_col, 1.0);
  for (int k = 0; k < kWrenchRows; ++k) matrix.add(k + 1, margin_col, sum[k]);
  matrix.add(kWrenchRows + 1, margin_col, static_cast<double>(n));
  matrix.loadInto(lp);

  glp_smcp options;
  glp_init_smcp(&options);
  options.msg_lev = GLP_MSG_OFF;
  // Measured on the bench grasps (grasping_bench BM_ForceClosureLpVsHull): dual simplex (primal
  // as fallback) 0.15 ms for 80 wrenches against 0.22 ms primal; the presolver and GLPK's
  // scaling only add time on this 7-row problem.
  options.meth = GLP_DUALP;
  options.presolve = GLP_OFF;
  ClosureLpResult result;
  const int code = glp_simplex(lp, &options);
  result.iterations = glp_get_it_cnt(lp);
  if (code != 0) {
    result.error = "glp_simplex failed with code " + std::to_string(code);
    return result;
  }
  const int status = glp_get_status(lp);
  if (status == GLP_OPT) {
    result.feasible = true;
    result.margin = glp_get_obj_val(lp);
  } else if (status != GLP_NOFEAS) {
    result.error = "glp_simplex ended with status " + std::to_string(status);
  }
  return result;
}

SqueezeLpResult solveSqueezeLp(const std::vector<Wrench>& wrenches, const std::vector<int>& group,
                               const std::vector<double>& normal,
                               const std::vector<Wrench>& pressing) {
  if (wrenches.empty()) throw InvalidArgument("squeeze LP: no wrenches");
  if (group.size() != wrenches.size() || normal.size() != wrenches.size())
    throw InvalidArgument("squeeze LP: one group and one normal force per wrench");
  for (std::size_t i = 0; i < wrenches.size(); ++i) {
    if (!wrenches[i].allFinite() || !std::isfinite(normal[i]))
      throw InvalidArgument("squeeze LP: non-finite wrench or normal force");
  }
  for (const auto& p : pressing) {
    if (!p.allFinite()) throw InvalidArgument("squeeze LP: non-finite pressing wrench");
  }
  thread_local const GlpkEnvironmentRelease release_at_thread_exit;
  const QuietGlpk quiet;
  // One row per pushing group, after the 6 wrench rows, in the order the groups first appear.
  std::map<int, int> group_row;
  for (int g : group) {
    if (g >= 0 && !group_row.count(g))
      group_row.emplace(g, kWrenchRows + 1 + static_cast<int>(group_row.size()));
  }
  const int n = static_cast<int>(wrenches.size());
  std::unique_ptr<glp_prob, ProblemDeleter> problem(glp_create_prob());
  glp_prob* lp = problem.get();
  glp_set_obj_dir(lp, GLP_MIN);
  const int pressing_row = kWrenchRows + static_cast<int>(group_row.size()) + 1;
  glp_add_rows(lp, pressing_row - 1 + static_cast<int>(pressing.size()));
  for (int row = 1; row <= kWrenchRows; ++row) glp_set_row_bnds(lp, row, GLP_FX, 0.0, 0.0);
  for (const auto& [g, row] : group_row) glp_set_row_bnds(lp, row, GLP_LO, 1.0, 0.0);
  // residual . p_j = (plus - minus) . p_j >= 0.
  for (std::size_t j = 0; j < pressing.size(); ++j)
    glp_set_row_bnds(lp, pressing_row + static_cast<int>(j), GLP_LO, 0.0, 0.0);
  // Columns: the n edge weights, then the residual's positive and negative parts (6 each).
  glp_add_cols(lp, n + 2 * kWrenchRows);
  Triplets matrix;
  for (int i = 0; i < n; ++i) {
    const int col = i + 1;
    glp_set_col_bnds(lp, col, GLP_LO, 0.0, 0.0);
    for (int k = 0; k < kWrenchRows; ++k) matrix.add(k + 1, col, wrenches[i][k]);
    if (group[i] >= 0) matrix.add(group_row.at(group[i]), col, normal[i]);
  }
  for (int k = 0; k < kWrenchRows; ++k) {
    const int plus = n + 1 + k, minus = n + 1 + kWrenchRows + k;
    glp_set_col_bnds(lp, plus, GLP_LO, 0.0, 0.0);
    glp_set_col_bnds(lp, minus, GLP_LO, 0.0, 0.0);
    glp_set_obj_coef(lp, plus, 1.0);
    glp_set_obj_coef(lp, minus, 1.0);
    matrix.add(k + 1, plus, -1.0);
    matrix.add(k + 1, minus, 1.0);
    for (std::size_t j = 0; j < pressing.size(); ++j) {
      matrix.add(pressing_row + static_cast<int>(j), plus, pressing[j][k]);
      matrix.add(pressing_row + static_cast<int>(j), minus, -pressing[j][k]);
    }
  }
  matrix.loadInto(lp);
  glp_smcp options;
  glp_init_smcp(&options);
  options.msg_lev = GLP_MSG_OFF;
  options.presolve = GLP_OFF;
  SqueezeLpResult result;
  const int code = glp_simplex(lp, &options);
  if (code != 0 || glp_get_status(lp) != GLP_OPT) {
    result.error = "glp_simplex failed (code " + std::to_string(code) + ", status " +
                   std::to_string(glp_get_status(lp)) + ")";
    return result;
  }
  for (int k = 0; k < kWrenchRows; ++k) {
    result.residual[k] =
        glp_get_col_prim(lp, n + 1 + k) - glp_get_col_prim(lp, n + 1 + kWrenchRows + k);
  }
  result.balanced = glp_get_obj_val(lp) <= kSqueezeBalanceTolerance;
  return result;
}

LoadLpResult solveLoadLp(const std::vector<Wrench>& columns, const Wrench& load,
                         const Eigen::MatrixXd& limits, const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& upper, double max_scale) {
  const int n = static_cast<int>(columns.size());
  if (limits.cols() != n || limits.rows() != lower.size() || limits.rows() != upper.size())
    throw InvalidArgument("load LP: one limit column per wrench and two bounds per limit row");
  if (!load.allFinite() || !limits.allFinite() || !lower.allFinite() || !upper.allFinite() ||
      !(lower.array() <= upper.array()).all() || !(max_scale > 0) || !std::isfinite(max_scale))
    throw InvalidArgument(
        "load LP: non-finite load, limits or bounds, or a lower bound above its upper");
  for (const auto& w : columns) {
    if (!w.allFinite()) throw InvalidArgument("load LP: non-finite wrench");
  }
  thread_local const GlpkEnvironmentRelease release_at_thread_exit;
  const QuietGlpk quiet;
  const int m = static_cast<int>(limits.rows());
  std::unique_ptr<glp_prob, ProblemDeleter> problem(glp_create_prob());
  glp_prob* lp = problem.get();
  glp_set_obj_dir(lp, GLP_MAX);
  glp_add_rows(lp, kWrenchRows + std::max(m, 0));
  for (int row = 1; row <= kWrenchRows; ++row) glp_set_row_bnds(lp, row, GLP_FX, 0.0, 0.0);
  for (int r = 0; r < m; ++r) {
    glp_set_row_bnds(lp, kWrenchRows + 1 + r, lower[r] < upper[r] ? GLP_DB : GLP_FX, lower[r],
                     upper[r]);
  }
  glp_add_cols(lp, n + 1);
  Triplets matrix;
  for (int c = 0; c < n; ++c) {
    const int col = c + 1;
    glp_set_col_bnds(lp, col, GLP_LO, 0.0, 0.0);
    for (int k = 0; k < kWrenchRows; ++k) matrix.add(k + 1, col, columns[c][k]);
    for (int r = 0; r < m; ++r) matrix.add(kWrenchRows + 1 + r, col, limits(r, c));
  }
  const int scale_col = n + 1;
  glp_set_col_bnds(lp, scale_col, GLP_DB, 0.0, max_scale);
  glp_set_obj_coef(lp, scale_col, 1.0);
  for (int k = 0; k < kWrenchRows; ++k) matrix.add(k + 1, scale_col, load[k]);
  matrix.loadInto(lp);
  glp_smcp options;
  glp_init_smcp(&options);
  options.msg_lev = GLP_MSG_OFF;
  options.presolve = GLP_OFF;
  LoadLpResult result;
  const int code = glp_simplex(lp, &options);
  if (code == 0 && glp_get_status(lp) == GLP_NOFEAS) {
    result.feasible = false;
    return result;
  }
  if (code != 0 || glp_get_status(lp) != GLP_OPT) {
    result.error = "glp_simplex failed (code " + std::to_string(code) + ", status " +
                   std::to_string(glp_get_status(lp)) + ")";
    return result;
  }
  result.scale = glp_get_obj_val(lp);
  return result;
}

}  // namespace skelgrasp::grasping
