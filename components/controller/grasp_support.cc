#include "components/controller/grasp_support.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glpk.h>

#include "components/runtime/check.h"

namespace dmpl {
namespace {

constexpr int kConeEdges = 8;

// The cone's edges of one contact: normal + friction * (a unit tangent). A force is a
// non-negative sum of them; its normal part is the sum of the weights.
std::vector<Eigen::Vector3d> ConeEdges(const SupportContact& c, double friction) {
  const Eigen::Vector3d n = c.normal.normalized();
  const Eigen::Vector3d t1 = n.unitOrthogonal();
  const Eigen::Vector3d t2 = n.cross(t1);
  std::vector<Eigen::Vector3d> edges;
  for (int j = 0; j < kConeEdges; ++j) {
    const double a = 2.0 * M_PI * j / kConeEdges;
    edges.push_back(n + friction * (std::cos(a) * t1 + std::sin(a) * t2));
  }
  return edges;
}

struct ProblemDeleter {
  void operator()(glp_prob* p) const { glp_delete_prob(p); }
};
using Problem = std::unique_ptr<glp_prob, ProblemDeleter>;

// Every contact's cone edges, in the contacts' order.
std::vector<std::vector<Eigen::Vector3d>> AllConeEdges(const std::vector<SupportContact>& contacts,
                                                       double friction) {
  std::vector<std::vector<Eigen::Vector3d>> edges;
  for (const SupportContact& c : contacts) edges.push_back(ConeEdges(c, friction));
  return edges;
}

// Rows 1-3: the contacts' net force; 4-6: their net moment about `centre` over the contacts'
// mean distance from it (in N, like the forces: the simplex's tolerances are absolute); 7 + i:
// the push of contact i (from 0). Columns: contact i's edge j at 1 + i * kConeEdges + j, then
// `extra` more, left without coefficients for the caller.
Problem BuildBalance(const std::vector<SupportContact>& contacts,
                     const std::vector<std::vector<Eigen::Vector3d>>& edges,
                     const Eigen::Vector3d& centre, const SupportLimits& limits, double min_push,
                     int extra) {
  DMPL_DEMAND(limits.friction > 0 && limits.max_push_n > 0);
  Problem lp(glp_create_prob());
  const int m = static_cast<int>(contacts.size());
  glp_add_rows(lp.get(), 6 + m);
  glp_add_cols(lp.get(), m * kConeEdges + extra);
  double reach = 0.0;
  for (const SupportContact& c : contacts) reach += (c.point - centre).norm() / m;
  reach = std::max(reach, 1e-6);
  std::vector<int> rows{0}, cols{0};  // GLPK counts from 1
  std::vector<double> values{0.0};
  auto add = [&](int row, int col, double value) {
    if (std::abs(value) < 1e-12) return;  // rounding's zeros stay zeros
    rows.push_back(row), cols.push_back(col), values.push_back(value);
  };
  for (int i = 0; i < m; ++i) {
    const Eigen::Vector3d arm = (contacts[i].point - centre) / reach;
    for (int j = 0; j < kConeEdges; ++j) {
      const int col = 1 + i * kConeEdges + j;
      const Eigen::Vector3d& edge = edges[i][j];
      glp_set_col_bnds(lp.get(), col, GLP_LO, 0.0, 0.0);
      const Eigen::Vector3d moment = arm.cross(edge);
      for (int r = 0; r < 3; ++r) {
        add(1 + r, col, edge[r]);
        add(4 + r, col, moment[r]);
      }
      add(7 + i, col, 1.0);
    }
    glp_set_row_bnds(lp.get(), 7 + i, GLP_DB, min_push, limits.max_push_n);
  }
  glp_load_matrix(lp.get(), static_cast<int>(rows.size()) - 1, rows.data(), cols.data(),
                  values.data());
  return lp;
}

// Solves; true when an optimum was found.
bool Solve(glp_prob* lp) {
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  // No presolve: it declared feasible grasps infeasible where rounding left 1e-18 coefficients.
  // From the standard basis the simplex reports an infeasible problem as GLP_NOFEAS.
  glp_std_basis(lp);
  return glp_simplex(lp, &parm) == 0 && glp_get_status(lp) == GLP_OPT;
}

}  // namespace

SupportPlan PlanSupport(const std::vector<SupportContact>& contacts, const Eigen::Vector3d& load,
                        const Eigen::Vector3d& centre, const SupportLimits& limits) {
  SupportPlan plan;
  if (contacts.empty() || limits.min_push_n > limits.max_push_n) return plan;
  const auto edges = AllConeEdges(contacts, limits.friction);
  Problem lp = BuildBalance(contacts, edges, centre, limits, limits.min_push_n, 0);
  for (int r = 0; r < 3; ++r) {
    glp_set_row_bnds(lp.get(), 1 + r, GLP_FX, -load[r], -load[r]);
    glp_set_row_bnds(lp.get(), 4 + r, GLP_FX, 0.0, 0.0);
  }
  glp_set_obj_dir(lp.get(), GLP_MIN);
  const int num_cols = static_cast<int>(contacts.size()) * kConeEdges;
  for (int col = 1; col <= num_cols; ++col) glp_set_obj_coef(lp.get(), col, 1.0);
  if (!Solve(lp.get())) return plan;
  plan.feasible = true;
  for (size_t i = 0; i < contacts.size(); ++i) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int j = 0; j < kConeEdges; ++j) {
      const double w = glp_get_col_prim(lp.get(), 1 + static_cast<int>(i) * kConeEdges + j);
      f += w * edges[i][j];
      plan.total_push_n += w;
    }
    plan.forces.push_back(f);
  }
  return plan;
}

double SupportAlong(const std::vector<SupportContact>& contacts, const Eigen::Vector3d& direction,
                    const Eigen::Vector3d& centre, const SupportLimits& limits) {
  if (contacts.empty() || direction.norm() < 1e-9) return 0.0;
  const Eigen::Vector3d d = direction.normalized();
  Problem lp = BuildBalance(contacts, AllConeEdges(contacts, limits.friction), centre, limits,
                            0.0, 1);
  // The last column is the load L >= 0: the contacts' net force is -L d, their moment zero.
  const int load_col = static_cast<int>(contacts.size()) * kConeEdges + 1;
  glp_set_col_bnds(lp.get(), load_col, GLP_LO, 0.0, 0.0);
  for (int r = 0; r < 3; ++r) {
    glp_set_row_bnds(lp.get(), 1 + r, GLP_FX, 0.0, 0.0);
    glp_set_row_bnds(lp.get(), 4 + r, GLP_FX, 0.0, 0.0);
  }
  // Row r of the net force gains + d[r] * L (net + L d = 0): set the load column's entries.
  const int ind[4] = {0, 1, 2, 3};
  const double val[4] = {0.0, d.x(), d.y(), d.z()};
  glp_set_mat_col(lp.get(), load_col, 3, ind, val);
  glp_set_obj_dir(lp.get(), GLP_MAX);
  glp_set_obj_coef(lp.get(), load_col, 1.0);
  if (!Solve(lp.get())) return 0.0;
  return glp_get_col_prim(lp.get(), load_col);
}

}  // namespace dmpl
