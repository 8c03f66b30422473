#include "cobra/studio/bridge.hpp"

#include <algorithm>
#include <iterator>
#include <atomic>
#include <chrono>
#include <deque>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/planning/planning_scene_component.hpp"
#include "cobra/core/bounded_string.hpp"
#include "cobra/core/spsc_ring.hpp"
#include "cobra/core/triple_buffer.hpp"
#include "cobra/planning/robot_adapters.hpp"
#include "cobra/run/port_tap.hpp"
#include "cobra/run/run_spec.hpp"
#include "cobra/statechart/description.hpp"
#include "cobra/studio/json.hpp"
#include "chain_robot.hpp"
#include "extras.hpp"

namespace cobra::studio {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using State = core::BoundedString<127>;

// What the server's thread reads: every number of a frame in one vector laid out by the Layout,
// the charts' active states, each scope's deployment and configuration in force.
struct Snapshot {
  double t = 0.0;
  std::uint64_t seq = 0;
  std::vector<double> values;
  std::vector<State> states, deployments, configurations;
  double clearance = kNaN;
};

struct RobotView {
  std::string name;
  std::size_t joints = 0, links = 0, tools = 0;
  std::shared_ptr<planning::RobotModel> model;  // nullptr: no scene (the chain, or joints only)
  // Without a scene: the DH chain of the kinematics solver the studio table names (link frames in
  // the world: its base frame included); nullptr: joints only.
  std::unique_ptr<kinematics::SerialChainModel> chain;
  KDL::Frame base = KDL::Frame::Identity();
  std::unique_ptr<run::Tap<KDL::JntArray>> tap;
  KDL::JntArray q;                  // the last sample (sized once: reading it allocates nothing)
  std::vector<KDL::Frame> frames;   // link frames in the base frame
  bool have_frames = false;         // frames_world holds the link poses for the joints frames_q
  std::vector<double> frames_q, frames_world;
  std::size_t offset = 0;           // q at values[offset], then 7 per link
};

struct SignalView {
  std::string name, unit;
  std::unique_ptr<run::NumericTap> tap;
  std::size_t field = 0;
  std::vector<double> row;  // capacity reserved: reading allocates nothing
  std::size_t offset = 0;
};

struct EventItem {
  double t = 0.0;
  core::BoundedString<63> source;
  core::BoundedString<127> name;
};

void appendPose(std::string& out, const double* p) {
  out += '[';
  for (int i = 0; i < 7; ++i) {
    if (i) out += ',';
    json::appendNumber(out, p[i]);
  }
  out += ']';
}

void writePose(const KDL::Frame& f, double* out) {
  out[0] = f.p.x(), out[1] = f.p.y(), out[2] = f.p.z();
  f.M.GetQuaternion(out[3], out[4], out[5], out[6]);
}

// A chart's members of the model after its name: its scope, its states (connectors left out:
// never active) and the transitions leaving them.
std::string chartMembers(const std::string& scope, const statechart::ChartDescription& d) {
  std::string out = "\"scope\":" + json::quoted(scope) + ",\"states\":[";
  std::vector<std::string> states;
  for (const statechart::ChartDescription::Node& n : d.nodes) {
    if (n.connector) continue;
    out += (states.empty() ? "" : ",") + json::quoted(n.path);
    states.push_back(n.path);
  }
  out += "],\"transitions\":[";
  bool first = true;
  for (const statechart::ChartDescription::Transition& t : d.transitions) {
    if (std::find(states.begin(), states.end(), t.src) == states.end()) continue;
    out += std::string(first ? "" : ",") + "{\"src\":" + json::quoted(t.src) + ",\"tgt\":" + json::quoted(t.tgt) +
           ",\"events\":[";
    for (std::size_t e = 0; e < t.events.size(); ++e) out += (e ? "," : "") + json::quoted(t.events[e]);
    out += std::string("],\"guarded\":") + (t.guarded ? "true" : "false") + "}";
    first = false;
  }
  return out + "]";
}

}  // namespace

struct VisualizerBridge::Impl {
  BridgeOptions options;
  // Set by attach (the run's thread) before the server reads any of it (`attached` releases it).
  std::atomic<bool> attached{false};
  std::string app, scenario, model_body;  // model_body: the model's members after "mode" and "duration"
  std::filesystem::path report_folder;
  double threshold = 0.0;
  std::vector<std::string> charts, scopes, input_names;
  std::vector<std::pair<std::string, std::filesystem::path>> meshes;  // scene object -> its mesh file
  std::vector<RobotView> robots;
  std::vector<planning::ObjectDescription> chain_shapes;  // the shapes drawn on the chains' links (model objects)
  Extras extras;  // what is drawn beside the robots (extras.hpp)
  std::vector<SignalView> signals;
  std::size_t width = 0;
  std::unique_ptr<core::TripleBuffer<Snapshot>> snapshots;
  std::uint64_t seq = 0;
  double next_frame = 0.0;
  std::chrono::steady_clock::time_point next_wall{};
  bool recording_on = false;

  // The recording: snapshots copied by the run's thread into `pending`, moved into `recorded`
  // when the lock is free, turned into JSON only when asked (/api/recording, the replay files).
  std::vector<Snapshot> pending;
  std::string events;
  std::mutex shared_mutex;  // the server's side; the run's thread only try_locks it
  std::vector<Snapshot> recorded;
  std::string error;  // fail() or finished()'s end message
  std::string end_message;
  bool ended = false;

  // A late page's history (studio/PROTOCOL.md, "History"): the frames and event messages the
  // server's thread took last, kept by that thread (never the run's), at most the options'
  // history_frames and history_events; the oldest go first.
  std::mutex history_mutex;
  std::deque<std::string> history_frames, history_events;
  // The run's first frame, kept apart: the server's thread takes the latest frame on its own wall
  // clock (server.hpp, frame_rate), so its first take can fall a few frames into the run; the
  // history starts with this one all the same. Written once by the run's thread (a copy into a
  // snapshot sized in attach(): no allocation), then only read.
  Snapshot first_frame;
  std::atomic<bool> first_ready{false};
  bool first_remembered = false;  // the server's thread's
  template <class Text>
  void remember(std::deque<std::string>& kept, std::size_t bound, Text&& message) {
    const std::lock_guard<std::mutex> lock(history_mutex);
    kept.emplace_back(std::forward<Text>(message));
    if (kept.size() > bound) kept.pop_front();
  }

  core::SpscRing<EventItem> event_queue{1024};
  core::SpscRing<std::size_t> input_queue{64};
  std::atomic<long> published{0}, recorded_count{0}, events_dropped{0};

  std::unique_ptr<planning::SceneDescription> attachScene(const run::RunContext& run);
  void attachRobots(const run::RunContext& run, const planning::SceneDescription* scene, planning::RobotModels& models);
  void attachExtras(const run::RunContext& run, const planning::SceneDescription* scene);
  void attachSignals(const run::RunContext& run);
  void buildModel(const planning::SceneDescription* scene, const run::RunContext& run);
  // One entry of the model's objects (a mesh's file is served: `meshes`).
  void appendObject(std::string& out, const planning::ObjectDescription& o, bool& first);
  // The model's charts: each one's scope, states and the transitions leaving them (run.charts order).
  std::vector<std::string> chart_json;
  void fill(Snapshot& s, const run::StepView& now);
  void appendFrame(std::string& out, const Snapshot& s) const;
  // [FRAME, ...] of `recorded`.
  std::string framesJson() const {
    std::string out = "[";
    for (std::size_t i = 0; i < recorded.size(); ++i) {
      if (i) out += ',';
      appendFrame(out, recorded[i]);
    }
    return out + "]";
  }
  // The model; `states`: each chart's states (a replay: those the run entered; live: none yet).
  std::string modelJson(const char* mode, double duration, const std::map<std::string, std::vector<std::string>>& states) const;
  std::size_t model_charts_at = 0;  // in model_body: just after "charts":[
};

VisualizerBridge::VisualizerBridge(BridgeOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
}

VisualizerBridge::~VisualizerBridge() = default;

void VisualizerBridge::attach(const run::RunContext& run) {
  Impl& m = *impl_;
  m.app = run.entry.stem().string();
  m.scenario = run.scenario.empty() ? std::string() : run.scenario.filename().string();
  m.report_folder = run.report_folder;
  m.threshold = run.clearance_threshold;
  m.recording_on = m.options.record || !run.report_folder.empty();
  for (const run::ChartSpec& c : run.spec.charts) m.charts.push_back(c.name);
  m.scopes = run.scopes;
  for (const run::StudioSpec::Input& i : run.spec.studio.inputs) m.input_names.push_back(i.name);
  const std::unique_ptr<planning::SceneDescription> scene = m.attachScene(run);
  m.attachExtras(run, scene.get());
  m.attachSignals(run);
  m.buildModel(scene.get(), run);
  Snapshot initial;
  initial.values.assign(m.width, kNaN);
  initial.states.resize(m.charts.size());
  initial.deployments.resize(m.scopes.size());
  initial.configurations.resize(m.scopes.size());
  m.first_frame = initial;
  m.snapshots = std::make_unique<core::TripleBuffer<Snapshot>>(initial);
  m.next_wall = std::chrono::steady_clock::now();
  m.attached.store(true, std::memory_order_release);
}

std::unique_ptr<planning::SceneDescription> VisualizerBridge::Impl::attachScene(const run::RunContext& run) {
  const run::StudioSpec& studio = run.spec.studio;
  std::unique_ptr<planning::SceneDescription> scene;
  planning::RobotModels models;
  if (!studio.scene.empty()) {
    const std::string at = studio.scene_where.text() + ": run.studio.scene: ";
    const core::Component* c = run.registry.find(studio.scene);
    const auto* owner = dynamic_cast<const components::PlanningSceneComponent*>(c);
    if (owner == nullptr)
      throw std::runtime_error(at + (c == nullptr ? "unknown component '" + studio.scene + "'"
                                                  : "component '" + studio.scene + "' has no planning scene") +
                               "; name a MotionPlanner or StateValidator (its scene is drawn)");
    try {
      scene = std::make_unique<planning::SceneDescription>(owner->sceneDescription());
      models = planning::makeRobotModels(*scene);
    } catch (const std::exception& e) {
      throw std::runtime_error(at + "component '" + studio.scene + "': " + e.what());
    }
  }
  attachRobots(run, scene.get(), models);
  return scene;
}

void VisualizerBridge::Impl::attachRobots(const run::RunContext& run, const planning::SceneDescription* scene,
                                         planning::RobotModels& models) {
  for (const run::StudioSpec::Robot& r : run.spec.studio.robots) {
    const std::string at = r.where.text(), use = "run.studio.robots." + r.name;
    RobotView view;
    view.name = r.name;
    view.tap = std::make_unique<run::Tap<KDL::JntArray>>(run.registry, r.joints, at, use, "KDL.JntArray (the joints)");
    if (scene != nullptr) {
      const std::size_t index = scene->robotIndex(r.name);
      if (index == planning::SceneDescription::npos) {
        std::string names;
        for (const planning::RobotPlacement& p : scene->robots) names += (names.empty() ? "" : ", ") + p.name;
        throw std::runtime_error(at + ": " + use + ": the scene of " + run.spec.studio.scene + " has no robot '" + r.name +
                                 "'; its robots: " + names);
      }
      if (!r.kinematics.empty())
        throw std::runtime_error(at + ": " + use + ": kinematics = \"" + r.kinematics + "\" draws a robot no scene models; " +
                                 r.name + " is a robot of the scene of " + run.spec.studio.scene + " (drawn from its model)");
      view.model = models.at(r.name);
      view.base = scene->robots[index].base_in_world;
      view.joints = view.model->jointCount();
      view.links = view.model->linkCount();
      view.tools = view.model->toolCount();
      view.frames.assign(view.links, KDL::Frame::Identity());
    }
    if (scene == nullptr && !r.kinematics.empty()) {
      view.chain = std::make_unique<kinematics::SerialChainModel>(kinematicsChain(run.registry, r.kinematics, at, use));
      view.joints = view.chain->jointCount();
      if (r.count != 0 && static_cast<std::size_t>(r.count) != view.joints)
        throw std::runtime_error(at + ": " + use + ": joints = " + std::to_string(r.count) + " but the chain of " +
                                 r.kinematics + " has " + std::to_string(view.joints) + " joints");
      view.links = view.chain->linkCount();
      view.tools = 1;
      view.frames.assign(view.links, KDL::Frame::Identity());
      const std::vector<planning::ObjectDescription> shapes = chainShapes(r.name, *view.chain);
      chain_shapes.insert(chain_shapes.end(), shapes.begin(), shapes.end());
    } else if (scene == nullptr) {
      view.joints = static_cast<std::size_t>(r.count);
      if (view.joints == 0)
        throw std::runtime_error(at + ": " + use + ": without run.studio.scene no robot model gives the joints; write " +
                                 r.name + " = { \"" + r.joints + "\", joints = N } or { \"" + r.joints +
                                 "\", kinematics = \"KinematicsSolver component\" }");
    }
    view.q.resize(static_cast<unsigned>(view.joints));
    view.frames_q.assign(view.joints, kNaN);
    view.frames_world.assign(7 * view.links, kNaN);
    view.offset = width;
    width += view.joints + 7 * view.links;
    robots.push_back(std::move(view));
  }
}

void VisualizerBridge::Impl::attachExtras(const run::RunContext& run, const planning::SceneDescription* scene) {
  extras.attach(run, scene, width);
  width += extras.width();
}

void VisualizerBridge::Impl::attachSignals(const run::RunContext& run) {
  for (const auto& [name, where] : run.spec.studio.signals) {
    const std::string use = "run.studio.signals";
    const auto dot = name.find('.');
    const auto end = dot == std::string::npos ? std::string::npos : name.find_first_of(".[", dot + 1);
    SignalView view;
    view.name = name;
    view.tap = std::make_unique<run::NumericTap>(run.registry, name.substr(0, end), where.text(), use);
    const std::string field = end == std::string::npos ? std::string() : name.substr(end + (name[end] == '.' ? 1 : 0));
    const std::vector<run::NumericTap::Column> columns = view.tap->columns(0);
    if (field.size() > 2 && field.front() == '[' && field.back() == ']' && columns.empty()) {
      view.field = static_cast<std::size_t>(std::stoul(field.substr(1, field.size() - 2)));
      view.unit = view.tap->columns(view.field + 1).back().unit;
    } else {
      const auto found = std::find_if(columns.begin(), columns.end(), [&](const auto& c) { return c.field == field; });
      if (found == columns.end()) {
        std::string known;
        for (const run::NumericTap::Column& c : columns) known += (known.empty() ? "" : ", ") + c.name;
        throw std::runtime_error(where.text() + ": " + use + ": " +
                                 (field.empty() ? name + " has several values; name one: " : "no field '" + field + "' in " + name.substr(0, end) + "; fields: ") +
                                 (known.empty() ? "[0], [1], ..." : known));
      }
      view.field = static_cast<std::size_t>(found - columns.begin());
      view.unit = found->unit;
    }
    view.row.reserve(64);
    view.offset = width++;
    signals.push_back(std::move(view));
  }
}

void VisualizerBridge::Impl::buildModel(const planning::SceneDescription* scene, const run::RunContext& run) {
  const run::StudioSpec& studio = run.spec.studio;
  for (std::size_t c = 0; c < run.spec.charts.size(); ++c)
    chart_json.push_back(chartMembers(run.spec.charts[c].scope, c < run.charts.size() ? run.charts[c] : statechart::ChartDescription{}));
  std::string& out = model_body;
  out += ",\"app\":" + json::quoted(app) + ",\"scenario\":" + json::quoted(scenario) + ",\"robots\":[";
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotView& r = robots[i];
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(r.name) + ",\"joints\":[";
    for (std::size_t j = 0; j < r.joints; ++j) out += std::string(j ? "," : "") + "\"q" + std::to_string(j + 1) + "\"";
    out += "],\"links\":" + std::to_string(r.links) + ",\"tools\":" + std::to_string(r.tools) + "}";
  }
  out += "],\"objects\":[";
  bool first = true;
  if (scene != nullptr)
    for (const planning::ObjectDescription& o : scene->objects) appendObject(out, o, first);
  for (const planning::ObjectDescription& o : chain_shapes) appendObject(out, o, first);
  out += "],\"scopes\":[";
  for (std::size_t i = 0; i < scopes.size(); ++i) out += (i ? "," : "") + json::quoted(scopes[i]);
  out += "],\"failures\":[";  // run.failures: the events the console names as what led to a choice
  for (std::size_t i = 0; i < run.spec.failures.size(); ++i) out += (i ? "," : "") + json::quoted(run.spec.failures[i]);
  out += "],\"charts\":[";
  model_charts_at = out.size();  // modelJson writes the charts' list here
  out += "],\"signals\":[";
  for (std::size_t i = 0; i < signals.size(); ++i)
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(signals[i].name) + ",\"unit\":" + json::quoted(signals[i].unit) + "}";
  out += "],\"inputs\":[";
  for (std::size_t i = 0; i < studio.inputs.size(); ++i)
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(studio.inputs[i].name) + ",\"label\":" +
           json::quoted(studio.inputs[i].label) + ",\"target\":" + json::quoted(studio.inputs[i].call) +
           ",\"event\":" + json::quoted(studio.inputs[i].event) + "}";
  out += "],\"extras\":[";
  extras.appendModel(out);
  out += "]}";
}

void VisualizerBridge::Impl::appendObject(std::string& out, const planning::ObjectDescription& o, bool& first) {
  out += std::string(first ? "" : ",") + "{\"name\":" + json::quoted(o.name) + ",\"group\":" + json::quoted(o.group) +
         ",\"robot\":" + json::quoted(o.attached_to.robot_name) + ",\"link\":" +
         (o.attached_to.isWorld() ? std::string("-1") : std::to_string(o.attached_to.link_index)) +
         ",\"shape\":{\"type\":\"" + planning::toString(o.shape.kind) + "\"";
  first = false;
  if (o.shape.kind == planning::ShapeKind::Mesh) {
    out += ",\"file\":" + json::quoted("/api/mesh/" + o.name) + ",\"scale\":";
    meshes.emplace_back(o.name, o.shape.mesh_path);
    json::appendNumber(out, o.shape.mesh_scale);
  } else {
    // Box: x, y, z lengths; cylinder and capsule: radius, length; sphere: radius (m).
    const int n = o.shape.kind == planning::ShapeKind::Box ? 3 : (o.shape.kind == planning::ShapeKind::Sphere ? 1 : 2);
    out += ",\"size\":[";
    for (int k = 0; k < n; ++k) {
      if (k) out += ',';
      json::appendNumber(out, o.shape.dimensions[static_cast<std::size_t>(k)]);
    }
    out += ']';
  }
  double pose[7];
  writePose(o.offset, pose);
  out += "},\"pose\":";
  appendPose(out, pose);
  out += '}';
}

std::string VisualizerBridge::Impl::modelJson(const char* mode, double duration,
                                              const std::map<std::string, std::vector<std::string>>& states) const {
  std::string out = std::string("{\"protocol\":1,\"mode\":\"") + mode + "\"";
  // Whether a person gives the surgeon's inputs (cobra run --interactive): the console offers the
  // charts' choices only then (a replay never).
  out += std::string(",\"interactive\":") + (options.interactive && std::string(mode) == "live" ? "true" : "false");
  if (duration >= 0.0) {
    out += ",\"duration\":";
    json::appendNumber(out, duration);
  }
  out.append(model_body, 0, model_charts_at);
  for (std::size_t i = 0; i < charts.size(); ++i) {
    out += std::string(i ? "," : "") + "{\"name\":" + json::quoted(charts[i]) + "," + chart_json[i];
    const auto found = states.find(charts[i]);
    if (found != states.end()) {
      out += ",\"entered\":[";
      for (std::size_t k = 0; k < found->second.size(); ++k) out += (k ? "," : "") + json::quoted(found->second[k]);
      out += "]";
    }
    out += "}";
  }
  return out.append(model_body, model_charts_at, std::string::npos);
}

void VisualizerBridge::Impl::fill(Snapshot& s, const run::StepView& now) {
  s.t = now.t;
  s.seq = ++seq;
  double* v = s.values.data();
  for (RobotView& r : robots) {
    double* q = v + r.offset;
    if (!r.tap->read(r.q) || r.q.rows() != r.joints) {
      std::fill(q, q + r.joints + 7 * r.links, kNaN);
      continue;
    }
    for (std::size_t j = 0; j < r.joints; ++j) q[j] = r.q(static_cast<unsigned>(j));
    double* links = q + r.joints;
    // A robot at rest (often one of two) keeps its link frames: the forward kinematics runs only
    // when a joint moved since the frames were computed.
    if (r.have_frames && std::equal(q, q + r.joints, r.frames_q.begin())) {
      std::copy(r.frames_world.begin(), r.frames_world.end(), links);
      continue;
    }
    const std::span<const double> joints(r.q.data.data(), r.joints);
    r.have_frames = r.model ? r.model->linkFramesAt(joints, r.frames) : r.chain && r.chain->linkFrames(joints, r.frames);
    if (r.have_frames) {
      for (std::size_t l = 0; l < r.links; ++l) writePose(r.base * r.frames[l], links + 7 * l);
      std::copy(q, q + r.joints, r.frames_q.begin());
      std::copy(links, links + 7 * r.links, r.frames_world.begin());
    } else {
      std::fill(links, links + 7 * r.links, kNaN);
    }
  }
  extras.fill(v);
  for (SignalView& sig : signals) {
    sig.tap->read(sig.row);
    v[sig.offset] = sig.field < sig.row.size() ? sig.row[sig.field] : kNaN;
  }
  for (std::size_t c = 0; c < s.states.size(); ++c) s.states[c].assign(*now.states[c]);
  for (std::size_t k = 0; k < s.deployments.size(); ++k) {
    s.deployments[k].assign(now.deployments[k]);
    s.configurations[k].assign(now.configurations[k]);
  }
  s.clearance = now.clearance;
}

void VisualizerBridge::Impl::appendFrame(std::string& out, const Snapshot& s) const {
  const double* v = s.values.data();
  out += "{\"type\":\"frame\",\"t\":";
  json::appendNumber(out, s.t);
  out += ",\"robots\":{";
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const RobotView& r = robots[i];
    out += std::string(i ? "," : "") + json::quoted(r.name) + ":{\"q\":[";
    for (std::size_t j = 0; j < r.joints; ++j) {
      if (j) out += ',';
      json::appendNumber(out, v[r.offset + j]);
    }
    out += "],\"links\":[";
    for (std::size_t l = 0; l < r.links; ++l) {
      if (l) out += ',';
      appendPose(out, v + r.offset + r.joints + 7 * l);
    }
    out += "]}";
  }
  out += "},\"extras\":{";
  extras.appendFrame(out, v);
  out += "},\"charts\":{";
  for (std::size_t c = 0; c < charts.size(); ++c) out += std::string(c ? "," : "") + json::quoted(charts[c]) + ":" + json::quoted(s.states[c].view());
  out += "},\"deployments\":{";
  for (std::size_t k = 0; k < scopes.size(); ++k)
    out += std::string(k ? "," : "") + json::quoted(scopes[k]) + ":" + json::quoted(s.deployments[k].view());
  out += "},\"configurations\":{";
  for (std::size_t k = 0; k < scopes.size(); ++k)
    out += std::string(k ? "," : "") + json::quoted(scopes[k]) + ":" + json::quoted(s.configurations[k].view());
  out += "},\"signals\":{";
  for (std::size_t i = 0; i < signals.size(); ++i) {
    out += std::string(i ? "," : "") + json::quoted(signals[i].name) + ":";
    json::appendNumber(out, v[signals[i].offset]);
  }
  out += "},\"clearance\":{\"min\":";
  json::appendNumber(out, s.clearance);
  out += ",\"threshold\":";
  json::appendNumber(out, threshold);
  out += ",\"valid\":";
  out += std::isnan(s.clearance) ? "null" : (s.clearance > threshold ? "true" : "false");
  out += "}}";
}

void VisualizerBridge::step(const run::StepView& now) {
  Impl& m = *impl_;
  const bool sim_tick = now.t + 1e-9 >= m.next_frame;
  const auto wall = std::chrono::steady_clock::now();
  if (!sim_tick && wall < m.next_wall) return;
  Snapshot& s = m.snapshots->back();
  m.fill(s, now);
  if (s.seq == 1) {
    m.first_frame = s;
    m.first_ready.store(true, std::memory_order_release);
  }
  const auto period = std::chrono::duration<double>(1.0 / m.options.frame_rate);
  m.next_wall = wall + std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
  if (sim_tick) {
    while (m.next_frame <= now.t + 1e-9) m.next_frame += 1.0 / m.options.frame_rate;
    if (m.recording_on) {
      // The replay's frames: copies that grow with the run (as the runner's recorders grow).
      m.pending.push_back(s);
      m.recorded_count.fetch_add(1, std::memory_order_relaxed);
      if (m.shared_mutex.try_lock()) {
        std::move(m.pending.begin(), m.pending.end(), std::back_inserter(m.recorded));
        m.shared_mutex.unlock();
        m.pending.clear();
      }
    }
  }
  m.snapshots->publish();
  m.published.fetch_add(1, std::memory_order_relaxed);
}

void VisualizerBridge::event(double t, const std::string& source, const std::string& name) {
  Impl& m = *impl_;
  EventItem item;
  item.t = t;
  item.source.assign(source);
  item.name.assign(name);
  if (!m.event_queue.push(item)) m.events_dropped.fetch_add(1, std::memory_order_relaxed);
  if (!m.recording_on) return;
  std::string& out = m.events;
  if (!out.empty()) out += ',';
  out += "{\"type\":\"event\",\"t\":";
  json::appendNumber(out, t);
  out += ",\"source\":" + json::quoted(source) + ",\"name\":" + json::quoted(name) + "}";
}

bool VisualizerBridge::nextInput(std::size_t& index) { return impl_->input_queue.pop(index); }

std::vector<std::string> VisualizerBridge::finished(const run::RunResult& result) {
  Impl& m = *impl_;
  // How the run ended, as `cobra run` says it: outcome, exit status, its last line, the final states.
  std::string end = "{\"type\":\"end\",\"t\":";
  json::appendNumber(end, result.duration);
  end += ",\"outcome\":" + json::quoted(run::toString(result.outcome)) + ",\"message\":" + json::quoted(result.reason) +
         ",\"status\":" + std::to_string(run::exitStatus(result)) + ",\"line\":" + json::quoted(run::endLine(result)) +
         ",\"states\":{";
  for (std::size_t c = 0; c < result.final_states.size(); ++c)
    end += (c ? "," : "") + json::quoted(result.final_states[c].first) + ":" + json::quoted(result.final_states[c].second);
  end += "}";
  // On the wall clock: how the executor kept time (the console's outcome section shows it).
  if (result.executor.ran) end += ",\"executor\":" + json::quoted(run::executorLine(result.executor));
  end += "}";
  {
    const std::lock_guard<std::mutex> lock(m.shared_mutex);
    std::move(m.pending.begin(), m.pending.end(), std::back_inserter(m.recorded));
    m.pending.clear();
    m.end_message = end;
  }
  if (m.report_folder.empty() || !m.attached.load()) return {};
  // No more frames come: `recorded` is read here and by the server only.
  const std::string recording = "{\"model\":" + m.modelJson("replay", result.duration, result.states_entered) +
                                ",\"frames\":" + m.framesJson() + ",\"events\":[" + m.events + "],\"end\":" + end + "}";
  return {writeReplayFolder(m.report_folder / "studio", recording, m.options.web_folder, m.meshes)};
}

void VisualizerBridge::fail(const std::string& message) {
  const std::lock_guard<std::mutex> lock(impl_->shared_mutex);
  impl_->error = message;
}

std::string VisualizerBridge::model(int& status) {
  Impl& m = *impl_;
  {
    const std::lock_guard<std::mutex> lock(m.shared_mutex);
    if (!m.error.empty()) {
      status = 500;
      return "{\"error\":" + json::quoted(m.error) + "}";
    }
  }
  if (!m.attached.load(std::memory_order_acquire)) {
    status = 503;
    return "{\"error\":\"the run is loading; ask again\"}";
  }
  status = 200;
  return m.modelJson("live", -1.0, {});
}

std::string VisualizerBridge::recording() {
  Impl& m = *impl_;
  const std::lock_guard<std::mutex> lock(m.history_mutex);
  std::string out = "{\"frames\":[";
  for (std::size_t i = 0; i < m.history_frames.size(); ++i) (out += i ? "," : "") += m.history_frames[i];
  out += "],\"events\":[";
  for (std::size_t i = 0; i < m.history_events.size(); ++i) (out += i ? "," : "") += m.history_events[i];
  return out + "]}";
}

bool VisualizerBridge::latestFrame(std::uint64_t& seq, std::string& message) {
  Impl& m = *impl_;
  if (!m.attached.load(std::memory_order_acquire)) return false;
  m.snapshots->update();
  const Snapshot& s = m.snapshots->front();
  if (s.seq == 0 || s.seq == seq) return false;
  seq = s.seq;
  if (!m.first_remembered && m.first_ready.load(std::memory_order_acquire)) {
    m.first_remembered = true;
    if (m.first_frame.seq != s.seq) {
      message.clear();
      m.appendFrame(message, m.first_frame);
      m.remember(m.history_frames, m.options.history_frames, message);
    }
  }
  message.clear();
  m.appendFrame(message, s);
  m.remember(m.history_frames, m.options.history_frames, message);
  return true;
}

void VisualizerBridge::takeMessages(std::vector<std::string>& messages) {
  Impl& m = *impl_;
  EventItem item;
  while (m.event_queue.pop(item)) {
    std::string out = "{\"type\":\"event\",\"t\":";
    json::appendNumber(out, item.t);
    out += ",\"source\":" + json::quoted(item.source.view()) + ",\"name\":" + json::quoted(item.name.view()) + "}";
    m.remember(m.history_events, m.options.history_events, out);
    messages.push_back(std::move(out));
  }
  const std::lock_guard<std::mutex> lock(m.shared_mutex);
  if (!m.end_message.empty() && !m.ended) {
    m.ended = true;
    messages.push_back(m.end_message);
  }
}

InputAnswer VisualizerBridge::input(const std::string& name) {
  Impl& m = *impl_;
  if (!m.attached.load(std::memory_order_acquire)) return {409, "the run is loading: no inputs yet"};
  const auto found = std::find(m.input_names.begin(), m.input_names.end(), name);
  if (found == m.input_names.end()) {
    std::string list;
    for (const std::string& n : m.input_names) list += (list.empty() ? "" : ", ") + n;
    return {400, "no input '" + name + "': expected one of " + (list.empty() ? "(none: the application declares no run.studio.inputs)" : list)};
  }
  if (!m.input_queue.push(static_cast<std::size_t>(found - m.input_names.begin()))) return {409, "too many inputs waiting"};
  return {};
}

std::filesystem::path VisualizerBridge::mesh(const std::string& name) {
  if (!impl_->attached.load(std::memory_order_acquire)) return {};
  for (const auto& [object, file] : impl_->meshes)
    if (object == name) return file;
  return {};
}

BridgeStats VisualizerBridge::stats() const {
  return {impl_->published.load(), impl_->recorded_count.load(), impl_->events_dropped.load()};
}

}  // namespace cobra::studio
