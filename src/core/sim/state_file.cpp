// A simulation's state on disk, to resume a run where it was saved (a late
// failure or a slow phase studied from its step, with other options or another
// build): `evsim run SCENE --load-state F --save-state G`. Declared and
// documented in endovascular_sim/sim/state_file.h.
#include "endovascular_sim/sim/state_file.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "endovascular_sim/core/load_error.h"

namespace evsim {
namespace {

constexpr int kVersion = 4;  // 1: without the sleep fields of `clock` (read as awake); 2:
                             // without a pair contact's own point (read as its sample);
                             // 3: without the wall's shape (read as at rest)

/// One record per line: a key, then fields read in order; every error names
/// the file, the line and the field. A wrong value that leaves the file
/// readable (not a finite number, out of its range) is kept and reading goes
/// on, so that finish() reports every such problem at once; a broken
/// structure (a missing or unexpected record, a count) stops at once.
class Reader {
 public:
  /// Reads `in`; errors name `path` (the file, or what stands for the text).
  Reader(const std::string& path, std::istream& in) : path_(path), in_(in) {}

  /// The next line, which must start with `key`.
  void record(const std::string& key) {
    std::string text;
    if (!std::getline(in_, text)) fail(key, "missing (the file ends early)", line_ + 1);
    ++line_;
    fields_.clear();
    fields_.str(text);
    std::string got;
    if (!(fields_ >> got) || got != key) fail(key, "expected a '" + key + "' record");
  }

  double real(const std::string& field) {
    std::string token = word(field);
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (*end == '\0' && std::isfinite(v)) return v;
    problem(field, "not a finite number: '" + token + "'");
    return 0.0;
  }

  long integer(const std::string& field, long lo, long hi) {
    std::string token = word(field);
    char* end = nullptr;
    const long v = std::strtol(token.c_str(), &end, 10);
    if (*end != '\0' || v < lo || v > hi)
      fail(field, "expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                      "], got '" + token + "'");
    return v;
  }

  Vec3 vec3(const std::string& field) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) v(k) = real(field);
    return v;
  }

  std::string word(const std::string& field) {
    std::string token;
    if (!(fields_ >> token)) fail(field, "missing");
    return token;
  }

  /// Nothing may follow the record's last field.
  void end(const std::string& key) {
    std::string extra;
    if (fields_ >> extra) fail(key, "unexpected '" + extra + "' after the record's fields");
  }

  [[noreturn]] void fail(const std::string& field, const std::string& message, int line = -1) {
    problems_.emplace_back(path_, line < 0 ? line_ : line, field, message);
    throwLoadErrors(problems_);
    throw problems_.back();  // (not reached)
  }

  /// A wrong value on the current line: kept, reading goes on.
  void problem(const std::string& field, const std::string& message) {
    if (problems_.size() < 100) problems_.emplace_back(path_, line_, field, message);
  }
  /// Whether the current line has a kept problem (its other checks would
  /// see the 0 read in place of the wrong value).
  bool lineHasProblem() const { return !problems_.empty() && problems_.back().line() == line_; }
  /// Throws every kept problem (LoadErrors when several).
  void finish() { throwLoadErrors(problems_); }

 private:
  std::string path_;
  std::istream& in_;
  std::istringstream fields_;
  int line_{0};
  std::vector<LoadError> problems_;
};

/// Appends printf-formatted text to *out.
template <typename... Args>
void appendf(std::string* out, const char* format, Args... args) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof(buf), format, args...);
  if (n > 0 && n < static_cast<int>(sizeof(buf))) {
    out->append(buf, static_cast<size_t>(n));
    return;
  }
  std::string big(static_cast<size_t>(std::max(n, 0)) + 1, '\0');
  std::snprintf(big.data(), big.size(), format, args...);
  out->append(big.c_str());
}

void appendVec3(std::string* out, const Vec3& v) {
  appendf(out, " %.17g %.17g %.17g", v.x(), v.y(), v.z());
}

}  // namespace

std::string stateText(const SceneModel& model, const SimData& data) {
  std::string f;
  appendf(&f, "evsim_state %d\nscene %s\nclock %.17g %ld %zu %d %d\n", kVersion, model.name.c_str(),
          data.time, data.step, data.next_script_entry, data.resting_steps, data.asleep ? 1 : 0);
  for (size_t d = 0; d < data.devices.size(); ++d) {
    const DeviceState& s = data.devices[d];
    appendf(&f, "device %s %zu %.17g %.17g %d %d\n", model.devices[d].name.c_str(),
            s.position.size(), s.inserted_length, s.rotation_angle, s.released ? 1 : 0,
            s.cut_element);
    for (size_t i = 0; i < s.position.size(); ++i) {
      f += "node";
      appendVec3(&f, s.position[i]);
      const Quat& q = s.rotation[i];
      appendf(&f, " %.17g %.17g %.17g %.17g", q.w(), q.x(), q.y(), q.z());
      appendVec3(&f, s.velocity[i]);
      appendVec3(&f, s.angular_velocity[i]);
      f += '\n';
    }
  }
  for (const DriveCommand& c : data.commands)
    appendf(&f, "command %d %.17g %.17g\n", c.mode == DriveCommand::Mode::kPosition ? 1 : 0,
            c.insertion, c.rotation);
  appendf(&f, "contacts %zu\n", data.contacts.size());
  for (const Contact& c : data.contacts) {
    appendf(&f, "contact %d %d", c.device, c.sample);
    appendVec3(&f, c.point);
    appendVec3(&f, c.normal);
    appendf(&f, " %.17g %.17g %d %d", c.gap, c.force, c.other_device, c.other_sample);
    appendVec3(&f, c.friction);
    appendf(&f, " %d %.17g %.17g %.17g %.17g %d", c.other.element, c.other.xi, c.other.radius,
            c.other.friction, c.separation, c.lumen ? 1 : 0);
    appendf(&f, " %d %.17g %.17g %.17g\n", c.self.element, c.self.xi, c.self.radius,
            c.self.friction);
  }
  const size_t wall_points = data.wall ? data.wall->displacement.size() : 0;
  appendf(&f, "wall %zu\n", wall_points);
  for (size_t i = 0; i < wall_points; ++i) {
    appendf(&f, "wall_point");
    appendVec3(&f, data.wall->displacement[i]);
    appendf(&f, " %.17g\n", data.wall->radius_change[i]);
  }
  return f;
}

bool saveState(const SceneModel& model, const SimData& data, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return false;
  out << stateText(model, data);
  out.close();
  return static_cast<bool>(out);
}

namespace {

/// A state read whole before it replaces the data's (on any error the data
/// are unchanged).
struct LoadedState {
  double time{0.0};
  long step{0};
  size_t next_script_entry{0};
  std::vector<DeviceState> devices;
  std::vector<DriveCommand> commands;
  std::vector<Contact> contacts;
  int resting_steps{0};
  bool asleep{false};
  std::shared_ptr<const WallShape> wall;  // effect 'vessel_deformation' (null: at rest)
};

/// The `clock` record: time, step, script position (and from version 2
/// the sleep counters).
void readClock(const SceneModel& model, long version, Reader* r, LoadedState* next) {
  r->record("clock");
  next->time = r->real("time");
  if (next->time < 0.0) r->problem("time", "must not be negative");
  next->step = r->integer("step", 0, 1L << 50);
  next->next_script_entry = static_cast<size_t>(
      r->integer("next script entry", 0, static_cast<long>(model.script.size())));
  if (version >= 2) {
    next->resting_steps = static_cast<int>(r->integer("resting steps", 0, 1000000000));
    next->asleep = r->integer("asleep", 0, 1) == 1;
  }
  r->end("clock");
}

/// Device d's `device` record and its nodes' records.
void readDevice(const SceneModel& model, int d, Reader* r, DeviceState* s) {
  r->record("device");
  const std::string name = r->word("device name");
  if (name != model.devices[d].name)
    r->fail("device name", "'" + name + "', the scene's device " + std::to_string(d) + " is '" +
                               model.devices[d].name + "'");
  const long nodes = static_cast<long>(s->position.size());
  r->integer("nodes", nodes, nodes);
  s->inserted_length = r->real("inserted length");
  if (s->inserted_length < 0.0 || s->inserted_length > model.devices[d].length * (1.0 + 1e-12))
    r->problem("inserted length", "must lie in [0, " + std::to_string(model.devices[d].length) +
                                      "] m (the device's length)");
  s->rotation_angle = r->real("rotation angle");
  s->released = r->integer("released", 0, 1) == 1;
  s->cut_element = static_cast<int>(r->integer("cut element", -1, nodes - 2));
  r->end("device");
  for (long i = 0; i < nodes; ++i) {
    r->record("node");
    s->position[i] = r->vec3("position");
    const double w = r->real("rotation"), x = r->real("rotation"), y = r->real("rotation"),
                 z = r->real("rotation");
    s->rotation[i] = Quat(w, x, y, z);
    if (!r->lineHasProblem() && std::abs(s->rotation[i].norm() - 1.0) > 1e-9)
      r->problem("rotation", "not a unit quaternion");
    s->velocity[i] = r->vec3("velocity");
    s->angular_velocity[i] = r->vec3("angular velocity");
    r->end("node");
  }
}

/// Device d's `command` record, checked against the device's limits.
void readCommand(const SceneModel& model, int d, Reader* r, DriveCommand* c) {
  r->record("command");
  c->mode =
      r->integer("mode", 0, 1) == 1 ? DriveCommand::Mode::kPosition : DriveCommand::Mode::kVelocity;
  c->insertion = r->real("insertion");
  c->rotation = r->real("rotation");
  const std::string why = validateDriveCommand(*c, model.devices[d]);
  if (!why.empty() && !r->lineHasProblem()) r->problem("command", why);
  r->end("command");
}

/// The `contacts` count and one `contact` record each.
std::vector<Contact> readContacts(const SceneModel& model, long version, Reader* r) {
  const int nd = static_cast<int>(model.devices.size());
  r->record("contacts");
  // At most a wall, a pair and a lumen contact per sample point, and their
  // second planes: a larger count is damage, not a state (and would
  // allocate gigabytes).
  long samples = 0;
  for (const auto& s : model.samples) samples += static_cast<long>(s.size());
  const long count = r->integer("contacts", 0, 6 * samples + 16);
  r->end("contacts");
  std::vector<Contact> contacts(count);
  for (Contact& c : contacts) {
    r->record("contact");
    c.device = static_cast<int>(r->integer("device", 0, nd - 1));
    c.sample = static_cast<int>(
        r->integer("sample", 0, static_cast<long>(model.samples[c.device].size()) - 1));
    c.point = r->vec3("point");
    c.normal = r->vec3("normal");
    c.gap = r->real("gap");
    c.force = r->real("force");
    c.other_device = static_cast<int>(r->integer("other device", -1, nd - 1));
    const long other_samples =
        c.other_device < 0 ? 0 : static_cast<long>(model.samples[c.other_device].size());
    c.other_sample = static_cast<int>(r->integer("other sample", -1, other_samples - 1));
    c.friction = r->vec3("friction");
    const long other_elements =
        c.other_device < 0 ? 1 : static_cast<long>(model.devices[c.other_device].elements.size());
    c.other.element = static_cast<int>(r->integer("other element", 0, other_elements - 1));
    c.other.xi = r->real("other xi");
    c.other.radius = r->real("other radius");
    c.other.friction = r->real("other mu");
    c.separation = r->real("separation");
    c.lumen = r->integer("lumen", 0, 1) == 1;
    c.self = model.samples[c.device][c.sample];
    if (version >= 3) {
      c.self.element = static_cast<int>(
          r->integer("element", 0, static_cast<long>(model.devices[c.device].elements.size()) - 1));
      c.self.xi = r->real("xi");
      c.self.radius = r->real("radius");
      c.self.friction = r->real("mu");
    }
    r->end("contact");
  }
  return contacts;
}

/// The `wall` count and one `wall_point` record each (version 4): the
/// shape of a wall that gives way, none (0) when it is at rest.
std::shared_ptr<const WallShape> readWall(const SceneModel& model, Reader* r) {
  r->record("wall");
  const long points = model.wall ? model.wall->numNodes() : 0;
  const long count = r->integer("wall points", 0, points);
  if (count != 0 && count != points)
    r->fail("wall points", "0 or the vessels' " + std::to_string(points) + " centreline points");
  r->end("wall");
  if (count == 0) return nullptr;
  auto shape = std::make_shared<WallShape>();
  shape->version = newWallShapeVersion();
  shape->displacement.resize(count);
  shape->radius_change.resize(count);
  for (long i = 0; i < count; ++i) {
    r->record("wall_point");
    shape->displacement[i] = r->vec3("displacement");
    shape->radius_change[i] = r->real("radius change");
    if (shape->displacement[i].norm() > model.wall_reach * (1 + 1e-12) ||
        shape->radius_change[i] < 0.0 || shape->radius_change[i] > model.wall_reach * (1 + 1e-12))
      r->problem("wall_point", "beyond the scene's vessels.wall.reach");
    r->end("wall_point");
  }
  return shape;
}

/// Reads a state from `in` (errors name `path`) into `data`, unchanged on error.
void readState(const SceneModel& model, const std::string& path, std::istream& in, SimData* data) {
  Reader r(path, in);
  LoadedState next;
  next.devices = data->devices;
  next.commands = data->commands;
  r.record("evsim_state");
  const long version = r.integer("version", 1, kVersion);
  r.end("evsim_state");
  r.record("scene");
  const std::string scene = r.word("scene");
  if (scene != model.name) r.fail("scene", "saved from '" + scene + "', not '" + model.name + "'");
  r.end("scene");
  readClock(model, version, &r, &next);
  const int nd = static_cast<int>(model.devices.size());
  for (int d = 0; d < nd; ++d) readDevice(model, d, &r, &next.devices[d]);
  for (int d = 0; d < nd; ++d) readCommand(model, d, &r, &next.commands[d]);
  next.contacts = readContacts(model, version, &r);
  if (version >= 4) next.wall = readWall(model, &r);
  r.finish();  // every wrong value, before anything of the data changes
  // Copied into the data's own buffers: views of them (the Python front's
  // arrays) stay valid.
  for (size_t d = 0; d < next.devices.size(); ++d) copyState(next.devices[d], &data->devices[d]);
  data->commands = next.commands;
  data->contacts.swap(next.contacts);
  data->time = next.time;
  data->step = next.step;
  data->next_script_entry = next.next_script_entry;
  data->resting_steps = next.resting_steps;
  data->asleep = next.asleep;
  data->wall = next.wall;
  data->targets.clear();  // progress is not saved: it restarts at the loaded state
  locateTips(model, data);
  measureForces(model, data);
}

}  // namespace

void loadState(const SceneModel& model, const std::string& path, SimData* data) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LoadError(path, 0, "", "cannot open the state file");
  readState(model, path, in, data);
}

void loadStateText(const SceneModel& model, const std::string& text, const std::string& source,
                   SimData* data) {
  std::istringstream in(text);
  readState(model, source, in, data);
}

}  // namespace evsim
