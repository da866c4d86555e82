#include "supervisor/task_description.h"

#include <algorithm>
#include <cmath>

namespace dmpl {
namespace {

// The YAML shape of a task file, read strictly by the params archive (unknown keys, wrong types
// are errors naming the file and the key); then checked and converted below.
struct FIstateYaml {
  std::string contact = "any";  // any | touching | free
  std::string role = "any";     // any | free | grip | explore
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(contact));
    a->Visit(DMPL_NVP(role));
  }
};

struct PTaskYaml {
  std::string primitive = "composite";  // hold | position | composite | hybrid
  std::string role = "grip";            // free | grip | explore
  FIstateYaml entry, exit;
  std::string until = "none";
  double duration_s = 0.0;
  std::optional<std::array<double, 3>> target;
  double force_n = 0.0;
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(primitive));
    a->Visit(DMPL_NVP(role));
    a->Visit(DMPL_NVP(entry));
    a->Visit(DMPL_NVP(exit));
    a->Visit(DMPL_NVP(until));
    a->Visit(DMPL_NVP(duration_s));
    a->Visit(DMPL_NVP(target));
    a->Visit(DMPL_NVP(force_n));
  }
};

struct MotionYaml {
  std::string reference = "current";  // current | start
  double angle = 0.0;
  std::string angle_units = "task";   // task (multiples of task.angle) | rad
  std::string axis = "task";
  double max_angular_speed = 0.0;
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(reference));
    a->Visit(DMPL_NVP(angle));
    a->Visit(DMPL_NVP(angle_units));
    a->Visit(DMPL_NVP(axis));
    a->Visit(DMPL_NVP(max_angular_speed));
  }
};

struct CTaskYaml {
  std::string name;
  std::string type = "local";
  std::map<std::string, std::vector<PTaskYaml>> fingers;
  std::optional<MotionYaml> object_motion;
  std::string done_when = "motion_done";
  double duration_s = 0.0;
  double timeout_s = 30.0;
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(name));
    a->Visit(DMPL_NVP(type));
    a->Visit(DMPL_NVP(fingers));
    a->Visit(DMPL_NVP(object_motion));
    a->Visit(DMPL_NVP(done_when));
    a->Visit(DMPL_NVP(duration_s));
    a->Visit(DMPL_NVP(timeout_s));
  }
};

struct TaskFileYaml {
  std::string name;
  GraspSpec grasp;
  std::vector<CTaskYaml> tasks;
  GaitSpec gait;
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(name));
    a->Visit(DMPL_NVP(grasp));
    a->Visit(DMPL_NVP(tasks));
    a->Visit(DMPL_NVP(gait));
  }
};

class Checker {
 public:
  explicit Checker(std::string source) : source_(std::move(source)) {}
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const {
    throw ConfigError("task file error in " + source_ + ": key '" + key + "': " + what);
  }
  template <typename E>
  E Pick(const std::string& key, const std::string& value,
         const std::vector<std::pair<std::string, E>>& choices) const {
    std::string names;
    for (const auto& [name, e] : choices) {
      if (name == value) return e;
      names += (names.empty() ? "" : ", ") + name;
    }
    Fail(key, "'" + value + "' is not one of " + names);
  }

 private:
  std::string source_;
};

Condition ParseCondition(const Checker& c, const std::string& key, const std::string& value) {
  return c.Pick<Condition>(key, value,
                           {{"none", Condition::kNone},
                            {"contact", Condition::kContact},
                            {"target_reached", Condition::kTargetReached},
                            {"grasp_stable", Condition::kGraspStable},
                            {"motion_done", Condition::kMotionDone},
                            {"duration", Condition::kDuration}});
}

FIstate ParseFIstate(const Checker& c, const std::string& key, const FIstateYaml& y) {
  FIstate s;
  s.contact = c.Pick<ContactState>(
      key + ".contact", y.contact,
      {{"any", ContactState::kAny}, {"touching", ContactState::kTouching}, {"free", ContactState::kFree}});
  if (y.role != "any") {
    s.role = c.Pick<Role>(key + ".role", y.role,
                          {{"free", Role::kFree}, {"grip", Role::kGrip}, {"explore", Role::kExplore}});
  }
  return s;
}

PTask ParsePTask(const Checker& c, const std::string& key, const PTaskYaml& y) {
  PTask p;
  p.primitive = c.Pick<Primitive>(key + ".primitive", y.primitive,
                                  {{"hold", Primitive::kHold},
                                   {"position", Primitive::kPosition},
                                   {"composite", Primitive::kComposite},
                                   {"hybrid", Primitive::kHybrid}});
  p.role = c.Pick<Role>(key + ".role", y.role,
                        {{"free", Role::kFree}, {"grip", Role::kGrip}, {"explore", Role::kExplore}});
  p.entry = ParseFIstate(c, key + ".entry", y.entry);
  p.exit = ParseFIstate(c, key + ".exit", y.exit);
  p.until = ParseCondition(c, key + ".until", y.until);
  p.duration_s = y.duration_s;
  if (p.until == Condition::kDuration && !(y.duration_s > 0)) {
    c.Fail(key + ".duration_s", "until: duration needs duration_s > 0");
  }
  if (y.target) {
    p.has_target = true;
    p.target = Eigen::Vector3d((*y.target)[0], (*y.target)[1], (*y.target)[2]);
  }
  if (p.primitive == Primitive::kPosition && !p.has_target) {
    c.Fail(key + ".target", "a position primitive needs a target point");
  }
  if (y.force_n < 0) c.Fail(key + ".force_n", "must be >= 0");
  p.force_n = y.force_n;
  return p;
}

}  // namespace

const char* ToString(Condition c) {
  switch (c) {
    case Condition::kNone: return "none";
    case Condition::kContact: return "contact";
    case Condition::kTargetReached: return "target_reached";
    case Condition::kGraspStable: return "grasp_stable";
    case Condition::kMotionDone: return "motion_done";
    case Condition::kDuration: return "duration";
  }
  return "?";
}

namespace {

// The names a task file may use for a finger: the hand's, and `all`.
void CheckFinger(const Checker& c, const std::vector<std::string>& fingers, const std::string& key,
                 const std::string& f) {
  if (f != "all" && std::find(fingers.begin(), fingers.end(), f) == fingers.end()) {
    c.Fail(key, "no finger '" + f + "' on this hand");
  }
}

// What the bounds of GraspSpec and GaitSpec cannot say: they name the hand's fingers.
void CheckGrasp(const Checker& c, const GraspSpec& g, const std::vector<std::string>& fingers) {
  for (const auto& entry : g.approach) {
    CheckFinger(c, fingers, "grasp.approach." + entry.first, entry.first);
  }
  if (!g.approach.empty() && g.approach.size() != fingers.size()) {
    c.Fail("grasp.approach", "give an approach point for every finger, or none");
  }
}

void CheckGait(const Checker& c, const GaitSpec& g, const std::vector<std::string>& fingers) {
  for (const auto& f : g.order) CheckFinger(c, fingers, "gait.order", f);
  if (g.order.size() != fingers.size()) {
    c.Fail("gait.order", "list every finger once (the exploring order)");
  }
  const auto& about = g.overlap_about;
  if (std::sqrt(about[0] * about[0] + about[1] * about[1] + about[2] * about[2]) < 1e-6) {
    c.Fail("gait.overlap_about", "must be a direction (not zero)");
  }
}

ObjectMotion ParseObjectMotion(const Checker& c, const std::string& key, const MotionYaml& m) {
  ObjectMotion om;
  om.reference = c.Pick<ObjectMotion::Reference>(
      key + ".reference", m.reference,
      {{"current", ObjectMotion::Reference::kCurrent}, {"start", ObjectMotion::Reference::kStart}});
  om.axis = c.Pick<std::string>(key + ".axis", m.axis,
                                {{"x", "x"}, {"y", "y"}, {"z", "z"}, {"task", "task"}});
  const std::string units = c.Pick<std::string>(key + ".angle_units", m.angle_units,
                                                {{"task", "task"}, {"rad", "rad"}});
  om.angle = m.angle;
  om.angle_in_task_units = units == "task";
  om.max_angular_speed = m.max_angular_speed;
  return om;
}

CTask ParseCTask(const Checker& c, const std::string& key, const CTaskYaml& ty,
                 const std::vector<std::string>& fingers) {
  CTask task;
  task.name = ty.name.empty() ? key : ty.name;
  task.type = c.Pick<TaskType>(key + ".type", ty.type,
                               {{"local", TaskType::kLocal}, {"gait", TaskType::kGait}});
  task.done_when = ParseCondition(c, key + ".done_when", ty.done_when);
  task.duration_s = ty.duration_s;
  task.timeout_s = ty.timeout_s;
  if (task.done_when == Condition::kDuration && !(ty.duration_s > 0)) {
    c.Fail(key + ".duration_s", "done_when: duration needs duration_s > 0");
  }
  if (!(ty.timeout_s > 0)) c.Fail(key + ".timeout_s", "must be > 0");
  for (const auto& [f, seq] : ty.fingers) {
    CheckFinger(c, fingers, key + ".fingers." + f, f);
    if (seq.empty()) c.Fail(key + ".fingers." + f, "an empty PTask sequence");
    for (size_t k = 0; k < seq.size(); ++k) {
      task.fingers[f].push_back(
          ParsePTask(c, key + ".fingers." + f + "[" + std::to_string(k) + "]", seq[k]));
    }
  }
  if (task.type == TaskType::kLocal && task.fingers.empty()) {
    c.Fail(key + ".fingers", "a local task needs the PTasks of its fingers");
  }
  if (ty.object_motion) {
    task.motion = ParseObjectMotion(c, key + ".object_motion", *ty.object_motion);
  } else if (task.done_when == Condition::kMotionDone && task.type == TaskType::kLocal) {
    c.Fail(key + ".done_when", "motion_done needs an object_motion");
  }
  return task;
}

}  // namespace

TaskFile ParseTaskFile(const YAML::Node& root, const std::string& source,
                       const std::vector<std::string>& fingers) {
  TaskFileYaml y;
  try {
    YamlReadArchive::Load(root, source, "", &y);
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("task file ") + e.what());
  }
  const Checker c(source);
  try {
    CheckBounds(y.grasp, source, "grasp");
    CheckBounds(y.gait, source, "gait");
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("task file ") + e.what());
  }
  CheckGrasp(c, y.grasp, fingers);
  CheckGait(c, y.gait, fingers);
  TaskFile t;
  t.source = source;
  t.name = y.name.empty() ? source : y.name;
  t.grasp = y.grasp;
  t.gait = y.gait;
  if (y.tasks.empty()) c.Fail("tasks", "a task file needs at least one task");
  for (size_t i = 0; i < y.tasks.size(); ++i) {
    t.tasks.push_back(ParseCTask(c, "tasks[" + std::to_string(i) + "]", y.tasks[i], fingers));
  }
  return t;
}

TaskFile LoadTaskFile(const std::string& path, const std::vector<std::string>& fingers) {
  return ParseTaskFile(LoadYamlFile(path), path, fingers);
}

}  // namespace dmpl
