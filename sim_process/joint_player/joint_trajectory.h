#pragma once
// A joint-space trajectory through waypoints, like a joint trajectory controller's: between
// waypoints the joints move on a smoothstep (zero velocity at each waypoint), after the last one
// they hold.
#include <map>
#include <string>
#include <vector>

#include "components/hand/hand_model.h"
#include "components/runtime/params.h"

namespace dmpl {

struct JointWaypoint {
  double t = 0.0;                                   // s
  std::map<std::string, std::vector<double>> q;     // finger -> joint angles; omitted: as before
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(t));
    a->Visit(DMPL_NVP(q));
  }
};

// Section `joint_player`.
struct JointPlayerParams {
  std::vector<JointWaypoint> waypoints;
  double release_at_s = -1.0;   // send SIM_CONTROL RELEASE at this sim time (< 0: never)
  double stop_at_s = -1.0;      // send SIM_CONTROL STOP at this sim time (< 0: never)
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(waypoints));
    a->Visit(DMPL_NVP(release_at_s));
    a->Visit(DMPL_NVP(stop_at_s));
  }
};

class JointTrajectory {
 public:
  // Checks the waypoints against the hand (fingers, counts, limits, increasing times); throws
  // ConfigError naming the waypoint and what is wrong.
  JointTrajectory(const HandModel& model, const std::vector<JointWaypoint>& waypoints,
                  const std::string& source);
  // Joint vector (HandModel order) at time t.
  std::vector<double> At(double t) const;

 private:
  std::vector<double> times_;
  std::vector<std::vector<double>> points_;
};

}  // namespace dmpl
