#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "components/controller/manipulation_controller.h"
#include "components/hand/testing/project_hand.h"
#include "components/ik/finger_ik.h"

namespace dmpl {
namespace {

using testing::LoadHand;

// A fixed sphere pressed by compliant fingertips that stick where they touch (friction): a tip
// whose target lies inside the sphere stays at its contact and presses with k times the depth of
// its target along the surface normal (a servo of bounded stiffness); a tip whose target is
// outside follows it freely.
class SpherePlant {
 public:
  SpherePlant(const HandKinematics& kin, Eigen::Vector3d centre, double radius, double k)
      : kin_(kin), centre_(centre), reach_(radius + 0.012), k_(k), anchor_(kin.num_fingers()) {}

  void Apply(const std::vector<Eigen::Vector3d>& targets, std::vector<double>* q,
             SensedInput* in) {
    for (int f = 0; f < kin_.num_fingers(); ++f) {
      SensedTip& t = in->tips[f];
      t = SensedTip{};
      Eigen::Vector3d tip = targets[f];
      if (!anchor_[f] && (targets[f] - centre_).norm() < reach_) {
        anchor_[f] = centre_ + (targets[f] - centre_).normalized() * reach_;  // touches here
      }
      if (anchor_[f]) {
        const Eigen::Vector3d normal = (*anchor_[f] - centre_).normalized();
        const double depth = (*anchor_[f] - targets[f]).dot(normal);
        if (depth > 0) {
          tip = *anchor_[f];
          t.in_contact = true;
          t.force = k_ * depth;
          t.position = *anchor_[f] - 0.012 * normal;
        } else {
          anchor_[f].reset();  // pulled away
        }
      }
      const IkResult r = SolveFingerIk(kin_.finger(f), kin_.FingerJoints(f, *q), tip, ik_);
      const auto& idx = kin_.joint_indices(f);
      for (size_t j = 0; j < idx.size(); ++j) (*q)[idx[j]] = r.q[j];
    }
    in->q = *q;
  }

 private:
  const HandKinematics& kin_;
  Eigen::Vector3d centre_;
  double reach_, k_;
  std::vector<std::optional<Eigen::Vector3d>> anchor_;
  IkParams ik_;
};

struct Fixture {
  HandModel model = LoadHand();
  HandKinematics kin{model};
  Eigen::Vector3d centre{0.09, 0.0, 0.02};
  // Tips on the sphere (the grasp of configs/bench/sim_hold.yaml).
  std::vector<double> q = {1.0805, 0.6818, 0.7742, 0.8128, -0.2086, 0.6651, 0.8474, 0.7633,
                           0.0,    0.5752, 0.7849, 0.7381, 0.2086,  0.6651, 0.8474, 0.7633};

  SensedInput Input(int64_t seq) {
    SensedInput in;
    in.seq = seq;
    in.time_s = seq * 1e-3;
    in.q = q;
    in.tips.resize(4);
    in.object_valid = true;
    in.object.translation() = centre;
    in.gravity = {-9.81, 0.0, 0.0};  // palm up
    return in;
  }
  TaskInput Grip(int explore_finger = -1) {
    TaskInput task;
    task.task_id = explore_finger < 0 ? 1 : 2;
    task.has_object_target = true;
    task.object_target.translation() = centre;
    task.fingers.resize(4);
    for (int f = 0; f < 4; ++f) task.fingers[f] = {Role::kGrip, Primitive::kComposite};
    if (explore_finger >= 0) task.fingers[explore_finger] = {Role::kExplore, Primitive::kHybrid};
    return task;
  }
};

TEST(ManipulationControllerTest, CompositeGripReachesThePlannedForcesAndReportsStable) {
  Fixture fx;
  ControllerParams params;
  ManipulationController ctl(fx.kin, params, 1e-3);
  SpherePlant plant(fx.kin, fx.centre, 0.025, 300.0);
  SensedInput in = fx.Input(0);
  plant.Apply({fx.kin.TipPosition(0, fx.q), fx.kin.TipPosition(1, fx.q), fx.kin.TipPosition(2, fx.q),
               fx.kin.TipPosition(3, fx.q)},
              &fx.q, &in);
  bool stable_event = false;
  for (int k = 0; k < 3000; ++k) {
    in.seq = k;
    in.time_s = k * 1e-3;
    const ControllerOutput& out = ctl.Step(in, fx.Grip());
    for (const auto& e : out.events) stable_event |= e.type == EventType::kGraspStable;

    std::vector<Eigen::Vector3d> targets;
    for (const auto& f : out.fingers) targets.push_back(f.target);
    plant.Apply(targets, &fx.q, &in);
  }
  const ControllerOutput& out = ctl.output();
  Eigen::Vector3d net = Eigen::Vector3d::Zero();
  for (int f = 0; f < 4; ++f) {
    const FingerOutput& o = out.fingers[f];
    EXPECT_TRUE(o.in_contact);
    EXPECT_NEAR(o.force, o.desired_force, 0.02 * o.desired_force) << "finger " << f;
    EXPECT_GE(o.desired_force, params.min_grip_force_n - 1e-9);
    net += o.force * (out.contact_centroid - o.contact).normalized();
  }
  EXPECT_LT(net.norm(), 0.05);  // the measured forces balance too
  EXPECT_TRUE(stable_event);
  EXPECT_TRUE(out.grasp_stable);
}

// The supervisor asks a finger to turn its tip's front toward the surface (face_surface): the
// IK gets the direction into the object at its contact (from the tip's centre through its
// contact point); a finger not asked gets none. An explorer gets one unasked only while
// controller.tip_front_explorer says so.
TEST(ManipulationControllerTest, AFingerAskedToFaceTheSurfaceGetsItsApproach) {
  for (const bool explorer_unasked : {true, false}) {
    Fixture fx;
    ControllerParams params;
    params.tip_front_explorer = explorer_unasked;
    ManipulationController ctl(fx.kin, params, 1e-3);
    SpherePlant plant(fx.kin, fx.centre, 0.025, 300.0);
    SensedInput in = fx.Input(0);
    std::vector<Eigen::Vector3d> tips;
    for (int f = 0; f < 4; ++f) tips.push_back(fx.kin.TipPosition(f, fx.q));
    plant.Apply(tips, &fx.q, &in);
    TaskInput task = fx.Grip(/*explore_finger=*/2);
    task.fingers[1].face_surface = true;  // F, a grip finger
    for (int k = 0; k < 300; ++k) {
      in.seq = k;
      in.time_s = k * 1e-3;
      const ControllerOutput& out = ctl.Step(in, task);
      std::vector<Eigen::Vector3d> targets;
      for (const auto& f : out.fingers) targets.push_back(f.target);
      plant.Apply(targets, &fx.q, &in);
    }
    const ControllerOutput& out = ctl.output();
    for (int f = 0; f < 4; ++f) ASSERT_TRUE(out.fingers[f].in_contact) << f;
    // On the plant's sphere the direction into the contact is the one to its centre.
    const Eigen::Vector3d to_centre = (fx.centre - out.fingers[1].tip).normalized();
    EXPECT_NEAR(out.fingers[1].approach.norm(), 1.0, 1e-9);
    EXPECT_GT(out.fingers[1].approach.dot(to_centre), 0.99);
    EXPECT_TRUE(out.fingers[3].approach.isZero()) << "R, not asked";
    EXPECT_EQ(out.fingers[2].approach.isZero(), !explorer_unasked) << "M, exploring";
  }
}

TEST(ManipulationControllerTest, ALinkContactIsReportedWhenItBeginsAndWhenItEnds) {
  Fixture fx;
  ManipulationController ctl(fx.kin, ControllerParams{}, 1e-3);
  SensedInput in = fx.Input(0);
  const int m = 2;
  const int flexion = fx.kin.joint_indices(m)[1];
  // 0.3 N m on M's first flexion joint that no tip force explains (it touches nothing), for
  // 0.1 s, then none for 0.1 s.
  std::vector<ControllerEvent> link_events;
  for (int k = 0; k < 200; ++k) {
    in.seq = k;
    in.time_s = k * 1e-3;
    in.effort.assign(fx.kin.num_joints(), 0.0);
    if (k < 100) in.effort[flexion] = 0.3;
    for (const ControllerEvent& e : ctl.Step(in, fx.Grip()).events) {
      if (e.type == EventType::kLinkContact || e.type == EventType::kLinkReleased) {
        link_events.push_back(e);
      }
    }
  }
  ASSERT_EQ(link_events.size(), 2u);
  EXPECT_EQ(link_events[0].type, EventType::kLinkContact);
  EXPECT_EQ(link_events[0].finger, m);
  EXPECT_NEAR(link_events[0].value, 0.3, 1e-9);
  EXPECT_EQ(link_events[1].type, EventType::kLinkReleased);
  EXPECT_EQ(link_events[1].finger, m);
}

TEST(ManipulationControllerTest, HybridExplorationHoldsItsSmallForce) {
  Fixture fx;
  ManipulationController ctl(fx.kin, ControllerParams{}, 1e-3);
  SpherePlant plant(fx.kin, fx.centre, 0.025, 300.0);
  SensedInput in = fx.Input(0);
  std::vector<Eigen::Vector3d> tips;
  for (int f = 0; f < 4; ++f) tips.push_back(fx.kin.TipPosition(f, fx.q));
  plant.Apply(tips, &fx.q, &in);
  const int r = fx.kin.FindFinger("R");
  for (int k = 0; k < 3000; ++k) {
    in.seq = k;
    in.time_s = k * 1e-3;
    const ControllerOutput& out = ctl.Step(in, fx.Grip(k < 1000 ? -1 : r));
    std::vector<Eigen::Vector3d> targets;
    for (const auto& f : out.fingers) targets.push_back(f.target);
    plant.Apply(targets, &fx.q, &in);
  }
  const FingerOutput& explorer = ctl.output().fingers[r];
  EXPECT_EQ(explorer.role, Role::kExplore);
  EXPECT_NEAR(explorer.force, 0.1, 0.01);
  for (int f = 0; f < 4; ++f) {
    if (f == r) continue;
    EXPECT_NEAR(ctl.output().fingers[f].force, ctl.output().fingers[f].desired_force, 0.03);
  }
}

// Runs a grip (and R exploring from tick 1000) on the plant for `ticks`; returns the last input.
SensedInput SettleOnPlant(Fixture* fx, ManipulationController* ctl, SpherePlant* plant,
                          int explorer, int ticks) {
  SensedInput in = fx->Input(0);
  std::vector<Eigen::Vector3d> tips;
  for (int f = 0; f < 4; ++f) tips.push_back(fx->kin.TipPosition(f, fx->q));
  plant->Apply(tips, &fx->q, &in);
  for (int k = 0; k < ticks; ++k) {
    in.seq = k;
    in.time_s = k * 1e-3;
    const ControllerOutput& out = ctl->Step(in, fx->Grip(k < 1000 ? -1 : explorer));
    std::vector<Eigen::Vector3d> targets;
    for (const auto& f : out.fingers) targets.push_back(f.target);
    plant->Apply(targets, &fx->q, &in);
  }
  return in;
}

// A held object that sinks along gravity, the tips stuck where they touch it: with
// carry_offset_m each grip finger's target leads its tip against gravity, in its contact's
// tangent plane (where friction carries; along the normal the force loop takes a lead back),
// by up to that much (the servo's push that carries the weight), whatever way the palm's IMU
// says gravity points.
TEST(ManipulationControllerTest, GripFingersLeadTheirTipsAgainstGravityToCarryTheWeight) {
  const std::vector<Eigen::Vector3d> downs = {{-1, 0, 0}, {0, 0, -1}, {1, 0, 0},
                                              Eigen::Vector3d(1, 1, -1).normalized()};
  for (const Eigen::Vector3d& down : downs) {
    double lead[2][4];  // [carry off, on][finger]: the target's tangential lead against gravity
    double room[4];     // how much of "up" lies in the finger's tangent plane (0..1)
    for (int on = 0; on < 2; ++on) {
      Fixture fx;
      ControllerParams params;
      params.carry_offset_m = on ? 0.012 : 0.0;
      ManipulationController ctl(fx.kin, params, 1e-3);
      SpherePlant plant(fx.kin, fx.centre, 0.025, 300.0);
      SensedInput in = fx.Input(0);
      in.gravity = 9.81 * down;
      std::vector<Eigen::Vector3d> targets;
      for (int f = 0; f < 4; ++f) targets.push_back(fx.kin.TipPosition(f, fx.q));
      plant.Apply(targets, &fx.q, &in);
      for (int k = 0; k < 3000; ++k) {
        in.seq = k;
        in.time_s = k * 1e-3;
        // Held where the task wants it for 1 s, then seen 1 cm lower (its weight pulled it
        // and the fingers gave).
        in.object.translation() = fx.centre + (k < 1000 ? 0.0 : 0.01) * down;
        const ControllerOutput& out = ctl.Step(in, fx.Grip());
        targets.clear();
        for (const auto& f : out.fingers) targets.push_back(f.target);
        plant.Apply(targets, &fx.q, &in);
      }
      for (int f = 0; f < 4; ++f) {
        const FingerOutput& out = ctl.output().fingers[f];
        ASSERT_TRUE(out.in_contact);
        const Eigen::Vector3d n = (out.tip - out.contact).normalized();
        const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - n * n.transpose();
        lead[on][f] = -(tangent * (out.target - out.tip)).dot(down);
        room[f] = (tangent * down).squaredNorm();
      }
    }
    for (int f = 0; f < 4; ++f) {
      SCOPED_TRACE("gravity " + std::to_string(down.x()) + " " + std::to_string(down.y()) + " " +
                   std::to_string(down.z()) + ", finger " + std::to_string(f) + ", room " +
                   std::to_string(room[f]));
      // 12 mm of anchor against 4 mm along up: 8 mm more, of which the tangent plane holds
      // room * 8 mm. The force loop takes the normal part of the lead back along its own
      // direction (toward the grip's centre, a few degrees off the normal): up to 2 mm more.
      EXPECT_GT(lead[1][f] - lead[0][f], 0.8 * 0.008 * room[f] - 0.0005);
      EXPECT_LT(lead[1][f] - lead[0][f], 0.008 * room[f] + 0.002);
    }
  }
}

TEST(ManipulationControllerTest, ALostReadingIsNotTakenForAContactPointWhileDebounced) {
  // A tactile sensor without contact reports no point (zeros). While the loss is debounced the
  // finger still counts as touching; its contact stays where it was, or the explorer's normal
  // and the grip's force directions would aim at the palm's origin.
  Fixture fx;
  ControllerParams params;
  params.normals_aim.enabled = true;
  ManipulationController ctl(fx.kin, params, 1e-3);
  SpherePlant plant(fx.kin, fx.centre, 0.025, 50.0);  // soft: the targets lie millimetres in
  const int r = fx.kin.FindFinger("R");
  SensedInput in = SettleOnPlant(&fx, &ctl, &plant, r, 2000);
  const int g = fx.kin.FindFinger("F");
  const ControllerOutput& settled = ctl.output();
  const Eigen::Vector3d explorer_target = settled.fingers[r].target;
  const Eigen::Vector3d grip_push =
      (settled.fingers[g].target - settled.fingers[g].tip).normalized();
  const Eigen::Vector3d centroid = settled.contact_centroid;
  for (int k = 0; k < params.contact_loss_ticks / 2; ++k) {
    in.tips[r] = SensedTip{};  // the explorer's and a grip finger's readings drop
    in.tips[g] = SensedTip{};
    in.seq = 2000 + k;
    in.time_s = in.seq * 1e-3;
    const ControllerOutput& out = ctl.Step(in, fx.Grip(r));
    EXPECT_TRUE(out.fingers[r].in_contact);  // debounced
    EXPECT_TRUE(out.fingers[g].in_contact);
    EXPECT_LT((out.fingers[r].target - explorer_target).norm(), 1e-3) << "tick " << k;
    // The grip finger pushes harder (its force reads zero), but the same way.
    const Eigen::Vector3d push = (out.fingers[g].target - out.fingers[g].tip).normalized();
    EXPECT_GT(push.dot(grip_push), std::cos(0.2)) << "tick " << k;
    EXPECT_LT((out.contact_centroid - centroid).norm(), 1e-3) << "tick " << k;
  }
}

TEST(ManipulationControllerTest, ALostGripFingerApproachesByAGuardedMove) {
  // Once its contact counts lost, a grip finger moves toward the object with its target a short
  // lead ahead of its tip (controller.guarded_approach_lead_m), not the force loop's whole reach.
  for (const double lead : {0.0, 0.004}) {
    Fixture fx;
    ControllerParams params;
    params.guarded_approach_lead_m = lead;
    ManipulationController ctl(fx.kin, params, 1e-3);
    SpherePlant plant(fx.kin, fx.centre, 0.025, 300.0);
    SensedInput in = SettleOnPlant(&fx, &ctl, &plant, -1, 1500);
    const int f = fx.kin.FindFinger("F");
    double reach = 0.0;
    for (int k = 0; k < 500; ++k) {  // F's tip held where it is, its reading gone
      in.tips[f] = SensedTip{};
      in.seq = 1500 + k;
      in.time_s = in.seq * 1e-3;
      const ControllerOutput& out = ctl.Step(in, fx.Grip());
      const FingerOutput& o = out.fingers[f];
      if (k < params.contact_loss_ticks) continue;
      EXPECT_FALSE(o.in_contact);
      const Eigen::Vector3d ahead = o.target - o.tip;
      reach = std::max(reach, ahead.norm());
      EXPECT_GT(ahead.dot(fx.centre - o.tip), 0.0) << "toward the object";
    }
    if (lead > 0) {
      EXPECT_LE(reach, lead + 1e-9);
    } else {
      EXPECT_GT(reach, 0.01);  // the force loop winds up to its integral limit
    }
  }
}

TEST(ManipulationControllerTest, NanInputIsRejectedAndTheTargetsHeld) {
  Fixture fx;
  ManipulationController ctl(fx.kin, ControllerParams{}, 1e-3);
  SensedInput in = fx.Input(0);
  const ControllerOutput first = ctl.Step(in, fx.Grip());
  in.q[3] = std::nan("");
  const ControllerOutput& out = ctl.Step(in, fx.Grip());
  ASSERT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].type, EventType::kInputRejected);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(out.fingers[f].target, first.fingers[f].target);
  in = fx.Input(2);
  in.tips[1].force = std::nan("");
  EXPECT_EQ(ctl.Step(in, fx.Grip()).events.at(0).type, EventType::kInputRejected);
}

TEST(ManipulationControllerTest, InputBeyondThePhysicalRangeIsRejectedLikeNan) {
  // Finite but impossible values (a corrupt or forged message) must not reach the control law.
  Fixture fx;
  ManipulationController ctl(fx.kin, ControllerParams{}, 1e-3);
  const ControllerOutput first = ctl.Step(fx.Input(0), fx.Grip());
  auto rejected = [&](SensedInput in) {
    const ControllerOutput& out = ctl.Step(in, fx.Grip());
    for (int f = 0; f < 4; ++f) EXPECT_EQ(out.fingers[f].target, first.fingers[f].target);
    return out.events.size() == 1 && out.events[0].type == EventType::kInputRejected;
  };
  SensedInput in = fx.Input(1);
  in.q[3] = 1e300;  // rad
  EXPECT_TRUE(rejected(in));
  in = fx.Input(2);
  const int j = fx.kin.joint_indices(1)[1];  // the forefinger's second joint
  in.q[j] = fx.kin.finger(1).upper()[1] + InputBounds::kJointMarginRad + 0.01;
  EXPECT_TRUE(rejected(in));
  in = fx.Input(3);
  in.tips[2].force = 1e9;  // N
  EXPECT_TRUE(rejected(in));
  in = fx.Input(4);
  in.object_valid = true;
  in.object.translation() = Eigen::Vector3d(3.0, 0.0, 0.0);  // m: far outside the hand
  EXPECT_TRUE(rejected(in));
  // No gravity reading (a sender that left the palm's IMU out), or one no IMU gives.
  const std::vector<Eigen::Vector3d> bad_gravity = {
      Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -300.0), Eigen::Vector3d(std::nan(""), 0, 0)};
  for (const Eigen::Vector3d& g : bad_gravity) {
    in = fx.Input(4);
    in.gravity = g;
    EXPECT_TRUE(rejected(in));
  }
  // Within the limits' margin (noise, overshoot) is accepted.
  in = fx.Input(5);
  in.q[j] = fx.kin.finger(1).upper()[1] + InputBounds::kJointMarginRad / 2;
  EXPECT_TRUE(ctl.Step(in, fx.Grip()).events.empty() ||
              ctl.output().events[0].type != EventType::kInputRejected);
}

TEST(ManipulationControllerTest, PositionPrimitiveApproachesAtBoundedSpeed) {
  Fixture fx;
  ControllerParams params;
  ManipulationController ctl(fx.kin, params, 1e-3);
  SensedInput in = fx.Input(0);
  TaskInput task;
  task.task_id = 5;
  task.fingers.resize(4);
  const int m = fx.kin.FindFinger("M");
  const Eigen::Vector3d start = fx.kin.TipPosition(m, fx.q);
  task.fingers[m] = {Role::kFree, Primitive::kPosition, true, start + Eigen::Vector3d(0, 0, 0.01)};
  Eigen::Vector3d prev = ctl.Step(in, task).fingers[m].target;
  for (int k = 1; k < 200; ++k) {
    in.seq = k;
    in.time_s = k * 1e-3;
    const Eigen::Vector3d t = ctl.Step(in, task).fingers[m].target;
    EXPECT_LE((t - prev).norm(), params.approach_speed * 1e-3 + 1e-12);
    prev = t;
  }
}

}  // namespace
}  // namespace dmpl
