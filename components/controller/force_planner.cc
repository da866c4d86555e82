#include "components/controller/force_planner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "components/runtime/check.h"

namespace dmpl {

namespace {

// Forces aimed at an arbitrary point: still zero moment (the lines meet there), and the magnitudes
// by least squares around the nominal force with an active set for the minimum: a force below it
// is fixed at the minimum and the others re-solved. Nothing when no such balance exists.
std::optional<ForcePlan> PlanTowards(const std::vector<Eigen::Vector3d>& contacts,
                                     const std::vector<int>& idx, const Eigen::Vector3d& aim,
                                     double nominal_n, double minimum_n,
                                     const Eigen::Vector3d& external) {
  const int n = static_cast<int>(idx.size());
  Eigen::Matrix3Xd u(3, n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d v = aim - contacts[idx[k]];
    if (v.norm() < 1e-9) return std::nullopt;
    u.col(k) = v.normalized();
  }
  std::vector<bool> fixed(n, false);
  Eigen::VectorXd f = Eigen::VectorXd::Constant(n, nominal_n);
  for (int pass = 0; pass <= n; ++pass) {
    Eigen::Vector3d rhs = -external;
    std::vector<int> free;
    for (int k = 0; k < n; ++k) {
      if (fixed[k]) {
        rhs -= minimum_n * u.col(k);
      } else {
        free.push_back(k);
      }
    }
    if (free.empty()) break;
    Eigen::Matrix3Xd uf(3, free.size());
    Eigen::VectorXd f0 = Eigen::VectorXd::Constant(free.size(), nominal_n);
    for (size_t j = 0; j < free.size(); ++j) uf.col(j) = u.col(free[j]);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::Matrix3d> cod(uf * uf.transpose());
    const Eigen::VectorXd ff = f0 - uf.transpose() * cod.solve(uf * f0 - rhs);
    bool violated = false;
    for (size_t j = 0; j < free.size(); ++j) {
      f[free[j]] = ff[j];
      if (ff[j] < minimum_n - 1e-12) {
        fixed[free[j]] = true;
        violated = true;
      }
    }
    for (int k = 0; k < n; ++k) {
      if (fixed[k]) f[k] = minimum_n;
    }
    if (!violated) {
      const Eigen::Vector3d net = u * f + external;
      if (net.norm() > 1e-6 * std::max(1.0, nominal_n)) break;  // unbalanceable: fall back
      ForcePlan plan;
      plan.forces.resize(contacts.size());
      plan.centroid = aim;
      for (int k = 0; k < n; ++k) plan.forces[idx[k]] = {u.col(k), f[k]};
      plan.balanced = true;
      return plan;
    }
  }
  return std::nullopt;
}

}  // namespace

ForcePlan PlanGripForces(const std::vector<Eigen::Vector3d>& contacts,
                         const std::vector<bool>& grip, double nominal_n, double minimum_n,
                         const Eigen::Vector3d& external,
                         const std::optional<Eigen::Vector3d>& aim) {
  DMPL_DEMAND(contacts.size() == grip.size());
  ForcePlan plan;
  plan.forces.resize(contacts.size());
  std::vector<int> idx;
  for (size_t i = 0; i < contacts.size(); ++i) {
    if (grip[i]) idx.push_back(static_cast<int>(i));
  }
  if (idx.empty()) return plan;
  for (int i : idx) plan.centroid += contacts[i];
  plan.centroid /= static_cast<double>(idx.size());
  if (aim && idx.size() >= 2) {
    if (auto towards = PlanTowards(contacts, idx, *aim, nominal_n, minimum_n, external)) {
      return *towards;
    }
  }
  const int n = static_cast<int>(idx.size());
  Eigen::Matrix3Xd u(3, n);
  Eigen::VectorXd d(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d v = plan.centroid - contacts[idx[k]];
    d[k] = v.norm();
    u.col(k) = d[k] > 1e-9 ? Eigen::Vector3d(v / d[k]) : Eigen::Vector3d::Zero();
  }
  if (n < 2 || d.minCoeff() < 1e-6) {
    for (int k = 0; k < n; ++k) plan.forces[idx[k]] = {u.col(k), nominal_n};
    return plan;
  }
  // Least squares: the smallest change to the nominal forces that makes the net force zero
  // (U f = -external), f = f0 - U^T (U U^T)^+ (U f0 + external); U may be rank-deficient
  // (contacts in a plane or on a line), and the part of `external` it cannot reach stays.
  const Eigen::VectorXd f0 = Eigen::VectorXd::Constant(n, nominal_n);
  const Eigen::Matrix3d uut = u * u.transpose();
  const Eigen::CompleteOrthogonalDecomposition<Eigen::Matrix3d> cod(uut);
  Eigen::VectorXd f = f0 - u.transpose() * cod.solve(u * f0 + external);
  // Forces proportional to the distances to the centroid balance exactly (sum of centroid - p_i
  // is zero), and are all positive: add as much of them as the minimum needs.
  double alpha = 0.0;
  for (int k = 0; k < n; ++k) alpha = std::max(alpha, (minimum_n - f[k]) / d[k]);
  f += alpha * d;
  for (int k = 0; k < n; ++k) plan.forces[idx[k]] = {u.col(k), f[k]};
  plan.balanced = true;
  return plan;
}

std::optional<Eigen::Vector3d> NormalsMeetingPoint(const std::vector<Eigen::Vector3d>& contacts,
                                                   const std::vector<Eigen::Vector3d>& normals,
                                                   const std::vector<bool>& grip,
                                                   const Eigen::Vector3d& fallback) {
  DMPL_DEMAND(contacts.size() == grip.size() && normals.size() == grip.size());
  // Minimises sum |(I - n n^T)(p - c)|^2 + eps |p - fallback|^2: the small pull toward the
  // fallback only decides the directions the lines leave free.
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  int lines = 0;
  for (size_t i = 0; i < contacts.size(); ++i) {
    if (!grip[i] || !(normals[i].norm() > 0.5)) continue;
    const Eigen::Vector3d n = normals[i].normalized();
    const Eigen::Matrix3d off = Eigen::Matrix3d::Identity() - n * n.transpose();
    a += off;
    b += off * contacts[i];
    ++lines;
  }
  if (lines < 2) return std::nullopt;
  constexpr double kPull = 1e-3;
  a += kPull * Eigen::Matrix3d::Identity();
  b += kPull * fallback;
  return Eigen::Vector3d(a.ldlt().solve(b));
}

Eigen::Vector3d CentreWithinReach(const Eigen::Vector3d& point, const Eigen::Vector3d& fallback,
                                  const std::vector<Eigen::Vector3d>& contacts,
                                  const std::vector<bool>& grip) {
  DMPL_DEMAND(contacts.size() == grip.size());
  double reach = 0.0;
  for (size_t i = 0; i < contacts.size(); ++i) {
    if (grip[i]) reach = std::max(reach, (contacts[i] - fallback).norm());
  }
  return (point - fallback).norm() > 2.0 * reach ? fallback : point;
}

namespace {

using BoundedMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using BoundedVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

// min w |U f - net|^2 + |f - nominal|^2 over the box [minimum_n, maximum_n]^n, i.e.
// min f'H f / 2 - b'f with H = w U'U + I (positive definite) and b = w U' net + nominal. Each
// force is free, at its minimum or at its maximum; for an assignment the free forces solve their
// rows of H f = b, and the first assignment whose free forces lie in the box and whose bound
// forces are held there by the gradient (the KKT conditions) is the optimum of this convex
// problem. The assignment with every force free comes first: in a balanced grasp it is the answer.
BoundedVector SolveBounded(const Eigen::Matrix3Xd& u, const Eigen::Vector3d& net, double nominal_n,
                           double minimum_n, double maximum_n, double balance_weight) {
  const int n = static_cast<int>(u.cols());
  const BoundedMatrix h = balance_weight * u.transpose() * u + BoundedMatrix::Identity(n, n);
  const BoundedVector b =
      balance_weight * u.transpose() * net + BoundedVector::Constant(n, nominal_n);
  constexpr double kTolerance = 1e-9;
  BoundedVector best =
      BoundedVector::Constant(n, nominal_n).cwiseMax(minimum_n).cwiseMin(maximum_n);
  std::array<int, 6> state{};  // per force: 0 free, 1 at the minimum, 2 at the maximum
  for (;;) {
    BoundedVector f(n);
    int free[6], m = 0;
    for (int k = 0; k < n; ++k) {
      if (state[k] == 0) {
        free[m++] = k;
      } else {
        f[k] = state[k] == 1 ? minimum_n : maximum_n;
      }
    }
    bool optimal = true;
    if (m > 0) {
      BoundedMatrix hf(m, m);
      BoundedVector bf(m);
      for (int i = 0; i < m; ++i) {
        bf[i] = b[free[i]];
        for (int k = 0; k < n; ++k) {
          if (state[k] != 0) bf[i] -= h(free[i], k) * f[k];
        }
        for (int j = 0; j < m; ++j) hf(i, j) = h(free[i], free[j]);
      }
      const BoundedVector x = hf.ldlt().solve(bf);
      for (int i = 0; i < m; ++i) {
        f[free[i]] = x[i];
        optimal = optimal && x[i] >= minimum_n - kTolerance && x[i] <= maximum_n + kTolerance;
      }
    }
    if (optimal) {
      const BoundedVector gradient = h * f - b;  // a force at its minimum must want to go lower,
      for (int k = 0; k < n && optimal; ++k) {
        if (state[k] == 1) optimal = gradient[k] >= -kTolerance;
        if (state[k] == 2) optimal = gradient[k] <= kTolerance;  // ... at its maximum higher
      }
    }
    if (optimal) {
      best = f;
      break;
    }
    int k = 0;
    while (k < n && ++state[k] == 3) state[k++] = 0;
    if (k == n) break;  // not reached for a convex problem; the clamped nominal stays
  }
  return best.cwiseMax(minimum_n).cwiseMin(maximum_n);
}

}  // namespace

ForcePlan PlanBoundedForces(const std::vector<Eigen::Vector3d>& contacts,
                            const std::vector<bool>& grip, const Eigen::Vector3d& aim,
                            double nominal_n, double minimum_n, double maximum_n,
                            const Eigen::Vector3d& net, double balance_weight,
                            const Eigen::Vector3d& unbalanced_along, const FrictionShare& share) {
  // Every force straight at `aim`: no normals, so nothing is clamped.
  const std::vector<Eigen::Vector3d> no_normals(contacts.size(), Eigen::Vector3d::Zero());
  return PlanBoundedForcesAlong(AimWithinCones(contacts, no_normals, grip, aim, M_PI), grip, aim,
                                nominal_n, minimum_n, maximum_n, net, balance_weight,
                                unbalanced_along, share);
}

std::vector<Eigen::Vector3d> AimWithinCones(const std::vector<Eigen::Vector3d>& contacts,
                                            const std::vector<Eigen::Vector3d>& normals,
                                            const std::vector<bool>& grip,
                                            const Eigen::Vector3d& aim, double max_off_normal_rad) {
  DMPL_DEMAND(contacts.size() == grip.size() && normals.size() == grip.size());
  DMPL_DEMAND(max_off_normal_rad >= 0);
  std::vector<Eigen::Vector3d> directions(contacts.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < contacts.size(); ++i) {
    const Eigen::Vector3d toward = aim - contacts[i];
    if (!grip[i] || toward.norm() < 1e-9) continue;
    directions[i] = toward.normalized();
    if (!(normals[i].norm() > 0.5)) continue;
    const Eigen::Vector3d n = normals[i].normalized();
    const double off = std::atan2(directions[i].cross(n).norm(), directions[i].dot(n));
    if (off <= max_off_normal_rad) continue;
    // On the cone's edge, on the side of the aim; along the normal when the aim lies behind
    // the contact's tangent plane (its side there says nothing of where the others push).
    const Eigen::Vector3d side = directions[i] - directions[i].dot(n) * n;
    directions[i] = off >= M_PI / 2 || side.norm() < 1e-6
                        ? n
                        : Eigen::Vector3d(std::cos(max_off_normal_rad) * n +
                                          std::sin(max_off_normal_rad) * side.normalized());
  }
  return directions;
}

ForcePlan PlanBoundedForcesAlong(const std::vector<Eigen::Vector3d>& directions,
                                 const std::vector<bool>& grip, const Eigen::Vector3d& centroid,
                                 double nominal_n, double minimum_n, double maximum_n,
                                 const Eigen::Vector3d& net, double balance_weight,
                                 const Eigen::Vector3d& unbalanced_along,
                                 const FrictionShare& share) {
  DMPL_DEMAND(directions.size() == grip.size());
  DMPL_DEMAND(minimum_n <= nominal_n && nominal_n <= maximum_n && balance_weight > 0);
  DMPL_DEMAND(share.across_n >= 0 && share.along_friction >= 0);
  ForcePlan plan;
  plan.forces.resize(directions.size());
  plan.centroid = centroid;
  std::vector<int> idx;
  for (size_t i = 0; i < directions.size(); ++i) {
    if (!grip[i] || directions[i].isZero()) continue;
    DMPL_DEMAND(std::abs(directions[i].norm() - 1.0) < 1e-9);  // unit, as documented
    idx.push_back(static_cast<int>(i));
  }
  const int n = static_cast<int>(idx.size());
  if (n == 0) return plan;
  DMPL_DEMAND(n <= 6);  // at most 3^n active sets, of at most 6 x 6
  Eigen::Matrix3Xd u(3, n);
  for (int k = 0; k < n; ++k) u.col(k) = directions[idx[k]];
  // The balance is weighed across `unbalanced_along` only (left to friction and the squeeze),
  // unless friction's share along it is bounded too.
  Eigen::Matrix3d across = Eigen::Matrix3d::Identity();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  if (unbalanced_along.norm() > 0) {
    g = unbalanced_along.normalized();
    across -= g * g.transpose();
  }
  const bool along = share.along_friction > 0 && g.norm() > 0;
  const Eigen::Matrix3Xd pu = along ? u : Eigen::Matrix3Xd(across * u);
  const Eigen::Vector3d pnet = along ? net : Eigen::Vector3d(across * net);
  // What friction may carry: the plan balances toward the nearest net friction can make up, so
  // a pair a few degrees off facing each other keeps its squeeze (friction holds the small sum
  // of its pushes) while a push nothing opposes is still eased. Across `unbalanced_along`:
  // share.across_n on each axis. Along it: a near-level push's own part along it (its friction
  // carries that), and a steeper push's coefficient times its push and its sine to it (a finger
  // pushing along gravity gives none: the weight it adds must be carried by a push the other
  // way). Block coordinate descent over the forces and that target: each pass lowers the cost.
  const Eigen::Vector3d box = Eigen::Vector3d::Constant(share.across_n);
  BoundedVector room_per_n = BoundedVector::Zero(n);  // friction's room along g per newton
  for (int k = 0; along && k < n; ++k) {
    const double along_g = std::abs(u.col(k).dot(g));
    const double steep = share.along_friction * u.col(k).cross(g).norm();
    room_per_n[k] = along_g <= share.level_sine ? along_g : steep;
  }
  const auto room_along = [&](const BoundedVector& f) {
    double room = 0.0;
    for (int k = 0; k < n; ++k) room += f[k] * room_per_n[k];
    return room;
  };
  const auto nearest_target = [&](const BoundedVector& f) {
    const Eigen::Vector3d r = pu * f - pnet;
    Eigen::Vector3d target = pnet + (across * r).cwiseMax(-box).cwiseMin(box);
    if (along) {
      const double room = room_along(f);
      target += std::clamp(g.dot(r), -room, room) * g;
    }
    return target;
  };
  const BoundedVector nominal =
      BoundedVector::Constant(n, nominal_n).cwiseMax(minimum_n).cwiseMin(maximum_n);
  BoundedVector best =
      SolveBounded(pu, nearest_target(nominal), nominal_n, minimum_n, maximum_n, balance_weight);
  constexpr int kPasses = 4;
  for (int pass = 1; (share.across_n > 0 || along) && pass < kPasses; ++pass) {
    best = SolveBounded(pu, nearest_target(best), nominal_n, minimum_n, maximum_n, balance_weight);
  }
  for (int k = 0; k < n; ++k) plan.forces[idx[k]] = {u.col(k), best[k]};
  const Eigen::Vector3d residual = pu * best - pnet;
  Eigen::Vector3d beyond = ((across * residual).cwiseAbs() - box).cwiseMax(0.0);
  if (along) beyond += std::max(0.0, std::abs(g.dot(residual)) - room_along(best)) * g.cwiseAbs();
  plan.balanced = n >= 2 && beyond.norm() <= 0.01 * pnet.norm() + 1e-3;
  return plan;
}

}  // namespace dmpl
