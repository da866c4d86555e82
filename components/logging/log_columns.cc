#include "components/logging/log_columns.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "components/logging/decode.h"
#include "components/logging/json_text.h"
#include "components/runtime/channels.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "dmpl/sim_status_t.hpp"
#include "dmpl/supervisor_status_t.hpp"
#include "dmpl/task_cmd_t.hpp"

namespace dmpl {
namespace fs = std::filesystem;
namespace {

template <typename T>
const char* Descr();
template <>
const char* Descr<double>() {
  return "<f8";
}
template <>
const char* Descr<int64_t>() {
  return "<i8";
}
template <>
const char* Descr<int32_t>() {
  return "<i4";
}
template <>
const char* Descr<int8_t>() {
  return "|i1";
}

}  // namespace

// The columns of one table: created by the first row, the same fields in every row.
class LogColumns::Table {
 public:
  // `prefix` names the table's columns for the fields filter ("DMPL_SENSORS_TRUE/").
  Table(std::string dir, std::string prefix, const std::regex* fields)
      : dir_(std::move(dir)), prefix_(std::move(prefix)), fields_(fields) {}

  template <typename T>
  void PutArray(const std::string& name, const T* values, std::vector<size_t> shape) {
    if (NpyColumn* col = Column(name, Descr<T>(), std::move(shape))) col->Append(values);
  }
  template <typename T>
  void Put(const std::string& name, T value) {
    if (NpyColumn* col = Column(name, Descr<T>(), {})) col->Append(&value);
  }
  void PutBools(const std::string& name, const std::vector<int8_t>& values) {
    std::vector<uint8_t> b(values.size());
    for (size_t i = 0; i < values.size(); ++i) b[i] = values[i] != 0;
    if (NpyColumn* col = Column(name, "|b1", {values.size()})) col->Append(b.data());
  }
  void PutBool(const std::string& name, int8_t value) {
    const uint8_t b = value != 0;
    if (NpyColumn* col = Column(name, "|b1", {})) col->Append(&b);
  }
  // A string as its code in the column's string table.
  void PutString(const std::string& name, const std::string& value) {
    std::vector<std::string>& table = strings_[name];
    auto& index = index_[name];
    auto it = index.find(value);
    if (it == index.end()) {
      it = index.emplace(value, static_cast<int32_t>(table.size())).first;
      table.push_back(value);
    }
    Put(name, it->second);
  }
  void EndRow() { ++rows_; }
  bool HasColumns() const {
    return std::any_of(columns_.begin(), columns_.end(),
                       [](const auto& c) { return c.second != nullptr; });
  }

  void Close() {
    for (auto& [name, col] : columns_) {
      if (col) col->Close();
    }
  }
  size_t rows() const { return rows_; }
  std::string StringsJson() const {
    std::string out = "{";
    bool first = true;
    for (const auto& [name, table] : strings_) {
      out += (first ? "" : ", ") + JsonString(name) + ": " + JsonList(table);
      first = false;
    }
    return out + "}";
  }

 private:
  // The column, created by the first row; nullptr for a field the filter leaves out.
  NpyColumn* Column(const std::string& name, const char* descr, std::vector<size_t> shape) {
    auto it = columns_.find(name);
    if (it == columns_.end()) {
      std::unique_ptr<NpyColumn> col;
      if (std::regex_match(prefix_ + name, *fields_)) {
        fs::create_directories(dir_);
        col = std::make_unique<NpyColumn>(dir_ + "/" + name + ".npy", descr, std::move(shape));
      }
      it = columns_.emplace(name, std::move(col)).first;
    }
    return it->second.get();
  }
  std::string dir_, prefix_;
  const std::regex* fields_;
  std::map<std::string, std::unique_ptr<NpyColumn>> columns_;
  std::map<std::string, std::vector<std::string>> strings_;
  std::map<std::string, std::map<std::string, int32_t>> index_;
  size_t rows_ = 0;
};

struct LogColumns::Channel {
  std::string type;
  Table table;
  std::unique_ptr<Table> events;
  int64_t messages = 0;
  bool skipped = false;                     // no field of it is asked for: counted, not decoded
  std::map<std::string, int64_t> rejected;  // by reason
  bool has_layout = false;
  std::vector<std::string> fingers, joints;  // from the first row; every row must match

  Channel(std::string t, const std::string& dir, const std::string& name, const std::regex* fields)
      : type(std::move(t)), table(dir, name + "/", fields) {}

  // Checks a row's finger (and joint) names against the first row's.
  bool SameLayout(const std::vector<std::string>& f, const std::vector<std::string>& j) {
    if (!has_layout) {
      fingers = f;
      joints = j;
      has_layout = true;
      return true;
    }
    if (f != fingers) {
      ++rejected["fingers differ from the first message's"];
      return false;
    }
    if (j != joints) {
      ++rejected["joints differ from the first message's"];
      return false;
    }
    return true;
  }
};

namespace {

// The `finger` of each element (fingertip readings, finger statuses, finger primitives).
template <typename PerFinger>
std::vector<std::string> FingerNames(const std::vector<PerFinger>& items) {
  std::vector<std::string> names;
  for (const auto& item : items) names.push_back(item.finger);
  return names;
}

template <typename Msg>
bool Decode(Msg* m, const uint8_t* data, size_t size) {
  return size <= static_cast<size_t>(INT32_MAX) && DecodeMessage(data, static_cast<uint32_t>(size), m);
}

bool AddSensors(LogColumns::Channel* ch, const hand_sensors_t& m) {
  const std::vector<std::string> fingers = FingerNames(m.tactile.fingers);
  if (!ch->SameLayout(fingers, m.joints.name)) return false;
  const size_t nf = fingers.size(), nj = m.joints.name.size();
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.PutBool("object_valid", m.object.valid);
  t.PutArray("object_position", m.object.position, {3});
  t.PutArray("object_orientation", m.object.orientation, {4});
  t.PutArray("object_linear_velocity", m.object.linear_velocity, {3});
  t.PutArray("object_angular_velocity", m.object.angular_velocity, {3});
  t.PutArray("joint_position", m.joints.position.data(), {nj});
  t.PutArray("joint_velocity", m.joints.velocity.data(), {nj});
  t.PutArray("joint_effort", m.joints.effort.data(), {nj});
  std::vector<int8_t> contact;
  std::vector<double> force, link_force, position, normal;
  for (const auto& f : m.tactile.fingers) {
    contact.push_back(f.in_contact);
    force.push_back(f.force_n);
    link_force.push_back(f.link_force_n);
    position.insert(position.end(), f.position, f.position + 3);
    normal.insert(normal.end(), f.normal, f.normal + 3);
  }
  t.PutBools("tactile_in_contact", contact);
  t.PutArray("tactile_force", force.data(), {nf});
  t.PutArray("tactile_link_force", link_force.data(), {nf});
  t.PutArray("tactile_position", position.data(), {nf, 3});
  t.PutArray("tactile_normal", normal.data(), {nf, 3});
  t.PutArray("gravity", m.gravity, {3});
  t.EndRow();
  return true;
}

bool AddControllerStatus(LogColumns::Channel* ch, const controller_status_t& m,
                         const std::string& dir, const std::string& name,
                         const std::regex* fields) {
  const std::vector<std::string> fingers = FingerNames(m.fingers);
  if (!ch->SameLayout(fingers, {})) return false;
  const size_t nf = fingers.size();
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.Put("task_id", m.task_id);
  t.PutBool("motion_done", m.motion_done);
  t.PutBool("grasp_stable", m.grasp_stable);
  t.Put("tracking_error_rad", m.tracking_error_rad);
  t.Put("tracking_error_m", m.tracking_error_m);
  t.PutArray("object_position", m.object_position, {3});
  t.PutArray("object_orientation", m.object_orientation, {4});
  t.PutArray("contact_centroid", m.contact_centroid, {3});
  t.Put("grip_force_n", m.grip_force_n);
  t.Put("load_scale", m.load_scale);
  t.Put("observed_friction", m.observed_friction);
  t.Put("observed_weight_n", m.observed_weight_n);
  std::vector<int8_t> role, primitive, contact;
  std::vector<double> force, desired;
  std::vector<double> tip, target, contact_pos, axis;
  for (const auto& f : m.fingers) {
    role.push_back(f.role);
    primitive.push_back(f.primitive);
    contact.push_back(f.in_contact);
    force.push_back(f.force_n);
    desired.push_back(f.desired_force_n);
    tip.insert(tip.end(), f.tip_position, f.tip_position + 3);
    target.insert(target.end(), f.target_position, f.target_position + 3);
    contact_pos.insert(contact_pos.end(), f.contact_position, f.contact_position + 3);
    axis.insert(axis.end(), f.tip_axis, f.tip_axis + 3);
  }
  t.PutArray("role", role.data(), {nf});
  t.PutArray("primitive", primitive.data(), {nf});
  t.PutBools("in_contact", contact);
  t.PutArray("force", force.data(), {nf});
  t.PutArray("desired_force", desired.data(), {nf});
  t.PutArray("tip_position", tip.data(), {nf, 3});
  t.PutArray("target_position", target.data(), {nf, 3});
  t.PutArray("contact_position", contact_pos.data(), {nf, 3});
  t.PutArray("tip_axis", axis.data(), {nf, 3});
  t.EndRow();
  for (const auto& e : m.events) {
    if (!ch->events) {
      ch->events = std::make_unique<LogColumns::Table>(dir + "/events", name + "/events/", fields);
    }
    auto& ev = *ch->events;
    ev.Put("utime", m.utime);
    ev.Put("seq", m.seq);
    ev.Put("type", e.type);
    ev.PutString("finger", e.finger);
    ev.Put("value", e.value);
    ev.PutString("text", e.text);
    ev.EndRow();
  }
  return true;
}

bool AddSupervisorStatus(LogColumns::Channel* ch, const supervisor_status_t& m) {
  if (!ch->SameLayout(m.finger, {})) return false;
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.PutString("grasp_state", m.grasp_state);
  t.PutString("regrasp_state", m.regrasp_state);
  t.PutString("last_action", m.last_action);
  t.PutString("task_name", m.task_name);
  t.Put("task_index", m.task_index);
  t.Put("num_tasks", m.num_tasks);
  t.PutArray("role", m.role.data(), {m.role.size()});
  t.Put("rotation_commanded_rad", m.rotation_commanded_rad);
  t.Put("rotation_goal_rad", m.rotation_goal_rad);
  t.Put("regrasps", m.regrasps);
  t.Put("recoveries", m.recoveries);
  t.PutBool("holding", m.holding);
  t.PutBool("finished", m.finished);
  t.PutBool("failed", m.failed);
  t.PutString("note", m.note);
  t.Put("num_goals", m.num_goals);
  t.Put("goals_reached", m.goals_reached);
  t.PutBool("has_orientation_goal", m.has_orientation_goal);
  t.PutArray("orientation_goal", m.orientation_goal, {4});
  t.Put("goal_error_rad", m.goal_error_rad);
  t.EndRow();
  return true;
}

bool AddTask(LogColumns::Channel* ch, const task_cmd_t& m) {
  const std::vector<std::string> fingers = FingerNames(m.fingers);
  if (!ch->SameLayout(fingers, {})) return false;
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.Put("task_id", m.task_id);
  t.PutString("name", m.name);
  t.PutBool("has_object_target", m.has_object_target);
  t.PutArray("object_position", m.object_position, {3});
  t.PutArray("object_orientation", m.object_orientation, {4});
  t.Put("max_linear_speed", m.max_linear_speed);
  t.Put("max_angular_speed", m.max_angular_speed);
  std::vector<int8_t> role, primitive;
  std::vector<double> force;
  for (const auto& f : m.fingers) {
    role.push_back(f.role);
    primitive.push_back(f.primitive);
    force.push_back(f.force_n);
  }
  t.PutArray("role", role.data(), {role.size()});
  t.PutArray("primitive", primitive.data(), {primitive.size()});
  t.PutArray("force", force.data(), {force.size()});
  t.Put("sim_command", m.sim_command);
  t.PutString("sim_command_reason", m.sim_command_reason);
  t.EndRow();
  return true;
}

bool AddSimStatus(LogColumns::Channel* ch, const sim_status_t& m) {
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.Put("sim_time_s", m.sim_time_s);
  t.PutBool("lockstep", m.lockstep);
  t.PutBool("paused", m.paused);
  t.PutBool("object_held", m.object_held);
  t.Put("steps", m.steps);
  t.Put("faults", m.faults);
  t.Put("rejected_commands", m.rejected_commands);
  t.Put("late_commands", m.late_commands);
  t.Put("step_us", m.step_us);
  t.PutString("last_fault", m.last_fault);
  t.EndRow();
  return true;
}

bool AddSimControl(LogColumns::Channel* ch, const sim_control_t& m) {
  auto& t = ch->table;
  t.Put("utime", m.utime);
  t.Put("seq", m.seq);
  t.Put("command", m.command);
  t.PutString("reason", m.reason);
  t.EndRow();
  return true;
}

}  // namespace

std::string ColumnTypeOf(std::string_view channel) {
  if (channel == channels::kSensorsTrue || channel == channels::kSensors) return "hand_sensors_t";
  if (channel == channels::kControllerStatus || channel == channels::kControllerReport) {
    return "controller_status_t";
  }
  if (channel == channels::kSupervisorStatus) return "supervisor_status_t";
  if (channel == channels::kTask) return "task_cmd_t";
  if (channel == channels::kSimStatus) return "sim_status_t";
  if (channel == channels::kSimControl) return "sim_control_t";
  return "";
}

LogColumns::LogColumns(const std::string& dir, const std::string& channels,
                       const std::string& fields)
    : dir_(dir), channels_(channels), fields_(fields) {
  fs::create_directories(dir_);
}

LogColumns::~LogColumns() = default;

LogColumns::Channel* LogColumns::ChannelFor(std::string_view name) {
  auto it = known_.find(name);
  if (it != known_.end()) return it->second.get();
  const std::string type = ColumnTypeOf(name);
  if (type.empty() || !std::regex_match(std::string(name), channels_)) return nullptr;
  auto ch =
      std::make_unique<Channel>(type, dir_ + "/" + std::string(name), std::string(name), &fields_);
  return known_.emplace(std::string(name), std::move(ch)).first->second.get();
}

bool LogColumns::Add(std::string_view channel, const uint8_t* data, size_t size) {
  Channel* ch = ChannelFor(channel);
  if (ch == nullptr) {
    auto it = others_.find(channel);
    if (it == others_.end()) it = others_.emplace(std::string(channel), 0).first;
    ++it->second;
    return true;
  }
  ++ch->messages;
  if (ch->skipped) return true;
  bool ok = false, decoded = false;
  if (ch->type == "hand_sensors_t") {
    hand_sensors_t m;
    if ((decoded = Decode(&m, data, size))) ok = AddSensors(ch, m);
  } else if (ch->type == "controller_status_t") {
    controller_status_t m;
    if ((decoded = Decode(&m, data, size))) {
      ok = AddControllerStatus(ch, m, dir_ + "/" + std::string(channel), std::string(channel),
                               &fields_);
    }
  } else if (ch->type == "supervisor_status_t") {
    supervisor_status_t m;
    if ((decoded = Decode(&m, data, size))) ok = AddSupervisorStatus(ch, m);
  } else if (ch->type == "task_cmd_t") {
    task_cmd_t m;
    if ((decoded = Decode(&m, data, size))) ok = AddTask(ch, m);
  } else if (ch->type == "sim_status_t") {
    sim_status_t m;
    if ((decoded = Decode(&m, data, size))) ok = AddSimStatus(ch, m);
  } else if (ch->type == "sim_control_t") {
    sim_control_t m;
    if ((decoded = Decode(&m, data, size))) ok = AddSimControl(ch, m);
  }
  if (!decoded) ++ch->rejected["cannot decode as " + ch->type];
  if (!ok) ++rejected_;
  // The first row shows which of the channel's fields are asked for; with none (nor any of its
  // events'), the rest of its messages need no decoding.
  if (ok && ch->table.rows() == 1 && !ch->table.HasColumns() &&
      !(ch->type == "controller_status_t" && WantsEvents(std::string(channel)))) {
    ch->skipped = true;
  }
  return ok;
}

bool LogColumns::WantsEvents(const std::string& channel) const {
  for (const char* field : {"utime", "seq", "type", "finger", "value", "text"}) {
    if (std::regex_match(channel + "/events/" + field, fields_)) return true;
  }
  return false;
}

void LogColumns::Finish(const std::string& extra) {
  if (finished_) return;
  finished_ = true;
  std::ostringstream meta;
  meta << "{\n  \"format\": 1,\n  \"channels\": {";
  bool first = true;
  for (auto& [name, ch] : known_) {
    ch->table.Close();
    if (ch->events) ch->events->Close();
    int64_t rejected = 0;
    std::string reasons = "{";
    for (const auto& [reason, n] : ch->rejected) {
      reasons += (rejected ? ", " : "") + JsonString(reason) + ": " + std::to_string(n);
      rejected += n;
    }
    reasons += "}";
    meta << (first ? "\n" : ",\n") << "    " << JsonString(name)
         << ": {\"type\": " << JsonString(ch->type) << ", \"messages\": " << ch->messages
         << ", \"rows\": " << (ch->skipped ? 0 : ch->table.rows()) << ", \"rejected\": " << rejected
         << ", \"rejected_by_reason\": " << reasons << ", \"fingers\": " << JsonList(ch->fingers)
         << ", \"joints\": " << JsonList(ch->joints) << ", \"strings\": " << ch->table.StringsJson()
         << ", \"events\": " << (ch->events ? std::to_string(ch->events->rows()) : "0")
         << ", \"event_strings\": " << (ch->events ? ch->events->StringsJson() : "{}") << "}";
    first = false;
  }
  meta << "\n  },\n  \"other_channels\": {";
  first = true;
  for (const auto& [name, n] : others_) {
    meta << (first ? "" : ", ") << JsonString(name) << ": " << n;
    first = false;
  }
  meta << "},\n  \"rejected\": " << rejected_;
  if (!extra.empty()) meta << ",\n  " << extra;
  meta << "\n}\n";
  const std::string path = dir_ + "/meta.json";
  std::ofstream out(path);
  out << meta.str();
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "' (disk full?)");
}

}  // namespace dmpl
