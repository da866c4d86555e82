// Which touching fingers are asked to turn their tips' fronts toward the surface: none on a
// sphere felt all round; on a cube felt all round, the fore and ring fingers, which touch its
// side faces with the sides of their tips.
#include <gtest/gtest.h>

#include <cmath>

#include "components/hand/testing/project_hand.h"
#include "supervisor/face_surface.h"
#include "supervisor/test/felt_objects.h"

namespace dmpl {
namespace {

constexpr double kTipRadius = 0.012;
constexpr int kT = 0, kF = 1, kM = 2, kR = 3;

// The grasp of fig10_gait_sphere at 2 s (the thumb below, the middle finger above, the fore and
// ring fingers at the sides), each tip at its home direction from the centre, touching at
// `half_width` from it; the tips' axes as the controller reported them there.
ControllerView Held(const Eigen::Vector3d& centre, double half_width) {
  const Eigen::Vector3d directions[] = {-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(),
                                        Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY()};
  ControllerView view;
  view.object.translation() = centre;
  for (int f = 0; f < 4; ++f) {
    FingerView v;
    v.tip_axis = testing::kGaitTipAxes[f].normalized();
    v.in_contact = true;
    v.force = 1.0;
    v.contact = centre + half_width * directions[f];
    v.tip = v.contact + kTipRadius * directions[f];
    view.fingers.push_back(v);
  }
  return view;
}

// Each face of a cube of half width `half` felt on a 2 mm grid.
SurfaceModel FeltCube(const ControllerView& view, double half) {
  SurfaceModel surface;
  double t = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[axis] = side;
      for (double u = -half + 0.001; u < half; u += 0.002) {
        for (double v = -half + 0.001; v < half; v += 0.002) {
          Eigen::Vector3d p = half * normal;
          p[(axis + 1) % 3] = u;
          p[(axis + 2) % 3] = v;
          surface.Add(view.object, view.object.translation() + p, normal, t += 1e-4);
        }
      }
    }
  }
  return surface;
}

TaskInput AllGrip() {
  TaskInput task;
  task.fingers.assign(4, {Role::kGrip, Primitive::kComposite});
  return task;
}

ContactChooser MakeChooser(const HandModel& model) {
  return ContactChooser(model, ContactChoiceParams{}, SupportParams{});
}

TEST(FaceSurfaceTest, OnASphereNoFingerIsAsked) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  const ControllerView view = Held(testing::kGaitCentre, 0.025);
  const SurfaceModel surface = testing::FeltSphere(view.object, 0.025, 800);
  TaskInput task = AllGrip();
  task.fingers[kM].face_surface = true;  // left over from the last task
  AskToFaceSurface(chooser, FaceSurfaceParams{true, 0.0035}, view, surface, {}, kTipRadius, &task);
  for (int f = 0; f < 4; ++f) EXPECT_FALSE(task.fingers[f].face_surface) << f;
}

// The fore and ring fingers' links stand 2.5-3.1 mm off the cube's side faces (4.2-4.6 mm off
// the sphere); the thumb's and the middle finger's, under and over it, 6.5 mm and more. A finger that senses no point is not
// asked; the explorer is asked by where it is going.
TEST(FaceSurfaceTest, OnACubeTheFingersAtItsSidesAreAsked) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  const FaceSurfaceParams params{true, 0.0035};
  ControllerView view = Held(testing::kGaitCentre, 0.025);
  const SurfaceModel surface = FeltCube(view, 0.025);
  TaskInput task = AllGrip();
  AskToFaceSurface(chooser, params, view, surface, {}, kTipRadius, &task);
  EXPECT_FALSE(task.fingers[kT].face_surface);
  EXPECT_TRUE(task.fingers[kF].face_surface);
  EXPECT_FALSE(task.fingers[kM].face_surface);
  EXPECT_TRUE(task.fingers[kR].face_surface);

  view.fingers[kF].force = 0.0;  // touching, its point not sensed yet
  task.fingers[kR] = {Role::kExplore, Primitive::kHybrid, true, view.fingers[kR].tip};
  AskToFaceSurface(chooser, params, view, surface, {}, kTipRadius, &task);
  EXPECT_FALSE(task.fingers[kF].face_surface);
  EXPECT_TRUE(task.fingers[kR].face_surface) << "exploring toward the middle of its face";

  // Grip fingers left alone: only the explorer is asked.
  AskToFaceSurface(chooser, FaceSurfaceParams{true, 0.0035, false}, view, surface, {},
                   kTipRadius, &task);
  for (int f : {kT, kF, kM}) EXPECT_FALSE(task.fingers[f].face_surface) << f;
  EXPECT_TRUE(task.fingers[kR].face_surface);

  // Asked for less room than the links have, nobody is.
  AskToFaceSurface(chooser, FaceSurfaceParams{true, 0.0}, view, surface, {}, kTipRadius, &task);
  for (int f = 0; f < 4; ++f) EXPECT_FALSE(task.fingers[f].face_surface) << f;
}

// Asked for every finger whatever its room (5 cm), but only on faces felt flat: none is asked
// before a face is felt flat; once the fore finger's is, the fore finger; once the faces under
// the thumb and the middle finger are too, they are.
TEST(FaceSurfaceTest, OnlyFingersOnAFaceFeltFlatAreAskedWhenSoAsked) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  FaceSurfaceParams params{true, 0.05};
  params.flat_faces_only = true;
  const ControllerView view = Held(testing::kGaitCentre, 0.025);
  const SurfaceModel surface = FeltCube(view, 0.025);
  const auto face = [&](const Eigen::Vector3d& normal) {
    return FlatFace{0.025 * normal, normal};  // object frame: the object unturned at the centre
  };
  TaskInput task = AllGrip();
  AskToFaceSurface(chooser, params, view, surface, {}, kTipRadius, &task);
  for (int f = 0; f < 4; ++f) EXPECT_FALSE(task.fingers[f].face_surface) << f;

  std::vector<FlatFace> flat{face(Eigen::Vector3d::UnitY())};
  AskToFaceSurface(chooser, params, view, surface, flat, kTipRadius, &task);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(task.fingers[f].face_surface, f == kF) << f;

  flat.push_back(face(-Eigen::Vector3d::UnitZ()));
  flat.push_back(face(Eigen::Vector3d::UnitZ()));
  AskToFaceSurface(chooser, params, view, surface, flat, kTipRadius, &task);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(task.fingers[f].face_surface, f != kR) << f;
}

}  // namespace
}  // namespace dmpl
