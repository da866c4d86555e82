#include "supervisor/supervisor_types.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace dmpl {

std::string Fixed(double value, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << value;
  return os.str();
}

bool FingerView::SensesPoint() const {
  constexpr double kMinForceN = 0.05;
  constexpr double kMinRadiusM = 0.002, kMaxRadiusM = 0.03;
  const double radius = (contact - tip).norm();
  return in_contact && force >= kMinForceN && radius > kMinRadiusM && radius < kMaxRadiusM;
}

double FingerView::ContactAngle() const {
  const Eigen::Vector3d into = contact - tip;
  if (!SensesPoint()) return 0.0;
  return std::acos(std::clamp(tip_axis.dot(into.normalized()), -1.0, 1.0));
}

const char* ToString(GraspState s) {
  switch (s) {
    case GraspState::ObjectHeld: return "ObjectHeld";
    case GraspState::Approaching: return "Approaching";
    case GraspState::Gripping: return "Gripping";
    case GraspState::Releasing: return "Releasing";
    case GraspState::Settling: return "Settling";
    case GraspState::Tasks: return "Tasks";
    case GraspState::Recovering: return "Recovering";
    case GraspState::Holding: return "Holding";
    case GraspState::Done: return "Done";
    case GraspState::Failed: return "Failed";
  }
  return "?";
}

const char* ToString(GraspEvent e) {
  switch (e) {
    case GraspEvent::Start: return "Start";
    case GraspEvent::AllTouching: return "AllTouching";
    case GraspEvent::GraspStable: return "GraspStable";
    case GraspEvent::ReleaseDue: return "ReleaseDue";
    case GraspEvent::Settled: return "Settled";
    case GraspEvent::TaskDone: return "TaskDone";
    case GraspEvent::TaskFailed: return "TaskFailed";
    case GraspEvent::ContactLost: return "ContactLost";
    case GraspEvent::LinkRest: return "LinkRest";
    case GraspEvent::Slip: return "Slip";
    case GraspEvent::Recovered: return "Recovered";
    case GraspEvent::ProcessLost: return "ProcessLost";
    case GraspEvent::ProcessBack: return "ProcessBack";
    case GraspEvent::GraspLost: return "GraspLost";
    case GraspEvent::Timeout: return "Timeout";
  }
  return "?";
}

}  // namespace dmpl
