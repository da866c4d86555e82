#pragma once
// What the supervisor's parts (the grasp chart, the gait, the local tasks, the recovery) share,
// as a behaviour tree's blackboard: what the controller said and when, and the task going out.
// Each part reads it and writes its commands on it; the Supervisor sends them once per tick.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "supervisor/edge_detector.h"
#include "supervisor/supervisor_types.h"
#include "supervisor/face_bounds.h"
#include "supervisor/surface_model.h"

namespace dmpl {

struct Blackboard {
  explicit Blackboard(std::vector<std::string> finger_names);

  int Finger(const std::string& name) const;  // the index of a finger of the hand (must be one)
  int num_fingers() const { return static_cast<int>(fingers.size()); }
  // Commands: a new task (a new id), a finger's role and primitive in it.
  void NewTask(const std::string& name);
  void SetFinger(int f, Role role, Primitive primitive, const Eigen::Vector3d* target = nullptr,
                 double force = 0.0);
  void AllGrip();
  void Note(const std::string& text);  // what the supervisor says (its status, the log)
  // The controller said so since the motion began, or says so now.
  bool MotionDone() const { return motion_done_event || view.motion_done; }
  Eigen::Quaterniond SensedOrientation() const;
  // Finger f's tip moved `by` off the object, along the line from its sensed centre (along its
  // home's, where the tip stands at the centre).
  Eigen::Vector3d LiftedOff(int f, double by) const;
  // What this tick's fingertip contacts say of the object's surface (view's contact points,
  // normals from the tip centres), of its edges and of the tips' radius.
  void LearnSurface();
  // The finger the task has exploring (the first, if more), -1 when none does.
  int Explorer() const;

  std::vector<std::string> fingers;
  ControllerView view;
  double now = 0.0;                // the sensed clock less its gaps (SensedClock)
  std::vector<bool> reached;       // each finger reached its target since it was set
  std::vector<bool> link_touched;  // each finger touched with a link since it last explored
  std::vector<bool> on_link;       // each finger's links touch now (LINK_CONTACT, not yet released)
  std::vector<double> on_link_since;  // and since when (`now`), or since it grips again
  bool motion_done_event = false;  // the controller said the object motion is done
  // Where each fingertip and the object's centre were when the first task began.
  std::vector<Eigen::Vector3d> home;
  Eigen::Vector3d home_centre = Eigen::Vector3d::Zero();
  // The object's surface as the fingertips have felt it (object frame), and the fingertips'
  // radius as the contacts show it (0 until one is felt): an explorer's target is its tip centre.
  SurfaceModel surface;
  double tip_radius_m = 0.0;
  // The edges the fingertips have rolled over (object frame), with the finger that felt each.
  struct FeltEdge {
    int finger;
    Edge edge;
  };
  std::vector<EdgeDetector> edge_detectors;  // per finger
  std::vector<FeltEdge> edges;
  // The faces an explorer has slid over flat (object frame; face_bounds.h), the latest kept.
  std::vector<FlatFaceDetector> flat_detectors;  // per finger
  std::vector<FlatFace> flat_faces;
  SupervisorOutput out;
  std::string note;
  int32_t next_task_id = 1;
};

}  // namespace dmpl
