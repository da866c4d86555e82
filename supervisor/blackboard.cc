#include "supervisor/blackboard.h"

#include <algorithm>

#include "components/runtime/check.h"

namespace dmpl {

Blackboard::Blackboard(std::vector<std::string> finger_names)
    : fingers(std::move(finger_names)),
      reached(fingers.size(), false),
      link_touched(fingers.size(), false),
      on_link(fingers.size(), false),
      on_link_since(fingers.size(), 0.0),
      home(fingers.size(), Eigen::Vector3d::Zero()) {
  out.task.fingers.resize(fingers.size());
  out.task.name = "idle";
}

int Blackboard::Finger(const std::string& name) const {
  const auto it = std::find(fingers.begin(), fingers.end(), name);
  DMPL_DEMAND(it != fingers.end());
  return static_cast<int>(it - fingers.begin());
}

void Blackboard::NewTask(const std::string& name) {
  out.task.task_id = next_task_id++;
  out.task.name = name;
  out.changed = true;
}

void Blackboard::SetFinger(int f, Role role, Primitive primitive, const Eigen::Vector3d* target,
                           double force) {
  FingerTask& t = out.task.fingers[f];
  t.role = role;
  t.primitive = primitive;
  t.has_target = target != nullptr;
  t.target = target ? *target : Eigen::Vector3d::Zero();
  t.force_n = force;
}

Eigen::Vector3d Blackboard::LiftedOff(int f, double by) const {
  const Eigen::Vector3d& tip = view.fingers[f].tip;
  Eigen::Vector3d out = tip - view.object.translation();
  if (out.norm() < 1e-6) out = home[f] - home_centre;
  return tip + by * out.normalized();
}

void Blackboard::AllGrip() {
  for (int f = 0; f < num_fingers(); ++f) SetFinger(f, Role::kGrip, Primitive::kComposite);
}

void Blackboard::Note(const std::string& text) {
  note = text;
  out.changed = true;
}

Eigen::Quaterniond Blackboard::SensedOrientation() const {
  return Eigen::Quaterniond(view.object.linear()).normalized();
}

int Blackboard::Explorer() const {
  for (size_t k = 0; k < out.task.fingers.size(); ++k) {
    if (out.task.fingers[k].role == Role::kExplore) return static_cast<int>(k);
  }
  return -1;
}

void Blackboard::LearnSurface() {
  if (edge_detectors.size() != view.fingers.size()) edge_detectors.resize(view.fingers.size());
  if (flat_detectors.size() != view.fingers.size()) flat_detectors.resize(view.fingers.size());
  for (size_t k = 0; k < view.fingers.size(); ++k) {
    const FingerView& f = view.fingers[k];
    const Eigen::Vector3d into = f.contact - f.tip;  // into the object
    const double radius = into.norm();
    const bool explores =
        k < out.task.fingers.size() && out.task.fingers[k].role == Role::kExplore;
    if (!f.SensesPoint()) {
      edge_detectors[k].Reset();
      flat_detectors[k].Reset();
      continue;
    }
    tip_radius_m = tip_radius_m > 0 ? 0.99 * tip_radius_m + 0.01 * radius : radius;
    const Eigen::Vector3d outward = -into / radius;
    surface.Add(view.object, f.contact, outward, now);
    const Eigen::Isometry3d to_object = view.object.inverse();
    // Only a sliding explorer: a grip finger's contact moves in the object frame by the pose
    // estimate's drift alone.
    if (!explores) {
      flat_detectors[k].Reset();
    } else if (auto face = flat_detectors[k].Add(now, to_object * f.contact,
                                                  to_object.linear() * outward)) {
      constexpr size_t kMaxFlatFaces = 64;
      if (flat_faces.size() >= kMaxFlatFaces) flat_faces.erase(flat_faces.begin());
      flat_faces.push_back(*face);
    }
    if (auto edge = edge_detectors[k].Add(now, to_object * f.contact,
                                          to_object.linear() * outward)) {
      if (edge->continues) {  // the one this finger found last, turned further
        for (auto it = edges.rbegin(); it != edges.rend(); ++it) {
          if (it->finger == static_cast<int>(k)) {
            it->edge = *edge;
            break;
          }
        }
      } else {
        edges.push_back({static_cast<int>(k), *edge});
      }
    }
  }
}

}  // namespace dmpl
