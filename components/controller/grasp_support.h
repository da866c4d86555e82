#pragma once
// What a set of contacts can hold: grasp force optimisation over friction cones (a linear
// programme, GLPK's simplex). A contact pushes into the object along its normal and may pull
// sideways by friction, up to `friction` times its push; the cone is a pyramid of kConeEdges
// faces inscribed in it, so every force found lies inside the true cone.
//
// Used where a finger is about to leave the grasp: whether the ones that stay can carry the
// object's weight along the sensed gravity (and how much they could), and with what forces.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross, unitOrthogonal

namespace dmpl {

struct SupportContact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // where it touches (any frame, all alike)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, into the object
};

struct SupportLimits {
  double friction = 0.5;   // the friction coefficient the plan may rely on (> 0)
  double min_push_n = 0.0;  // every contact pushes at least this much
  double max_push_n = 5.0;  // and at most this much (what a finger's servo can give)
};

struct SupportPlan {
  bool feasible = false;
  std::vector<Eigen::Vector3d> forces;  // per contact, on the object; empty when infeasible
  double total_push_n = 0.0;            // the sum of the forces' normal parts (the squeeze)
};

// The contact forces, least total push first, that hold `load` (the force the world puts on
// the object: its weight) with no net moment about `centre` (where the load acts), each inside
// its friction cone and within the push limits.
SupportPlan PlanSupport(const std::vector<SupportContact>& contacts, const Eigen::Vector3d& load,
                        const Eigen::Vector3d& centre, const SupportLimits& limits);

// The largest load along `direction` (unit; a weight's direction) the contacts can hold about
// `centre` within the limits (min_push_n ignored): the grasp's support along it, N. 0 when
// they hold none; a grasp that pins the object (contacts all around) still has a finite
// support, set by max_push_n and the friction.
double SupportAlong(const std::vector<SupportContact>& contacts, const Eigen::Vector3d& direction,
                    const Eigen::Vector3d& centre, const SupportLimits& limits);

}  // namespace dmpl
