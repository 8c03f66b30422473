// The section `studio` of the run table: what cobra studio shows of the run and the surgeon's
// inputs (StudioSpec; format: studio/README.md). The runner checks its inputs like actions and
// hands it to the RunObserver (cobra studio's bridge), which connects to the rest by name.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include <lua.hpp>

#include "builtin_observers.hpp"
#include "lua_reader.hpp"

namespace cobra::run {
namespace {

using detail::Reader;
using detail::split;

// A Frame or double port name: the value of an entry, a string "Comp.port".
std::string portName(const Reader& entry, const std::string& what) {
  if (lua_type(entry.state(), -1) != LUA_TSTRING) entry.fail("must be a port name \"Comp.port\" (" + what + ")");
  std::string port = lua_tostring(entry.state(), -1);
  split(entry, port, "port");
  return port;
}

// Bounds of the counts of run.studio: points of a vector port an extra shows (the studio keeps
// and sends them every frame), the lines a polyline deals them to, a robot's joints.
constexpr int kMaxPoints = 100000, kMaxStrands = 1000, kMaxJoints = 64;

// The whole number `key` of `entry` (`fallback` when absent), from 1 to `most`: Lua gives a
// double, and one beyond int's range must not be converted (1e20 is finite and positive).
int wholeCount(const Reader& entry, const char* key, double fallback, int most, const char* what) {
  const double value = entry.number(key, fallback, true);
  if (value != std::floor(value) || value > most) {
    char got[32];
    std::snprintf(got, sizeof got, "%.17g", value);
    entry.fail("`" + std::string(key) + "` must be a whole number of " + what + " from 1 to " + std::to_string(most) +
               ", got " + got);
  }
  return static_cast<int>(value);
}

// One entry of run.studio.extras (StudioSpec::Extra; format: studio/README.md).
StudioSpec::Extra readExtra(const std::string& name, const Reader& entry) {
  static constexpr const char* kKinds[] = {"sphere", "plane", "points", "polyline", "segments", "spheres", "capsules", "cylinders", "slabs"};
  static constexpr const char* kForms =
      "sphere = \"Comp.framePort\" (the centre, with radius = \"Comp.port\"), plane = \"Comp.framePort\", "
      "points, polyline or segments = \"Comp.port\" (x y z triples), spheres, capsules or cylinders = \"Comp.property\", "
      "slabs = \"Comp.property\" (depth pairs, with pose and size)";
  if (!lua_istable(entry.state(), -1)) entry.fail(std::string("must be a table with one of ") + kForms);
  StudioSpec::Extra extra;
  extra.name = name;
  for (const char* kind : kKinds)
    if (entry.has(kind)) {
      if (!extra.kind.empty()) entry.fail("give one kind, not both " + extra.kind + " and " + kind);
      extra.kind = kind;
      extra.pose = entry.string(kind, true);
    }
  if (extra.kind.empty()) entry.fail(std::string("needs one of ") + kForms);
  const bool property = extra.kind == "spheres" || extra.kind == "capsules" || extra.kind == "cylinders" || extra.kind == "slabs";
  split(entry, extra.pose, property ? "property" : "port");
  if (extra.kind == "sphere") {
    extra.radius = entry.string("radius", true);
    split(entry, extra.radius, "port");
  }
  if (extra.kind == "points" || extra.kind == "polyline" || extra.kind == "segments") {
    extra.max = wholeCount(entry, "max", extra.max, kMaxPoints, "points");
  }
  if (extra.kind == "polyline") extra.strands = wholeCount(entry, "strands", 1.0, kMaxStrands, "lines");
  if (extra.kind == "slabs") {
    extra.frame = entry.string("pose", true);
    split(entry, extra.frame, "property");
    if (!entry.has("size")) entry.fail("slabs need `size = { width, height }` in m or `size = \"object\"` (a box of run.studio.scene)");
    lua_getfield(entry.state(), -1, "size");
    const bool named = lua_type(entry.state(), -1) == LUA_TSTRING;
    lua_pop(entry.state(), 1);
    if (named) extra.footprint = entry.string("size", true);
  }
  if (extra.kind == "plane" || (extra.kind == "slabs" && extra.footprint.empty())) {
    if (!entry.has("size")) entry.fail("a plane needs `size = { width, height }` in m");
    const std::vector<double> size = entry.numbers("size");
    if (size.size() != 2) entry.fail("`size` must be { width, height } in m");
    extra.width = size[0], extra.height = size[1];
  }
  extra.where = entry.where();
  return extra;
}

// run.studio (StudioSpec; format: studio/README.md).
void readStudio(const Reader& s, StudioSpec& studio) {
  lua_State* L = s.state();
  if (!lua_istable(L, -1)) s.fail("must be a table");
  studio.declared = true;
  {
    studio.scene = s.string("scene", false);
    studio.scene_where = {s.where().file, studio.scene.empty() ? s.line() : s.lineOf(studio.scene)};
    s.entries("robots", [&](const std::string& name, const Reader& entry) {
      const char* what = "the robot's measured joints, KDL.JntArray; or { \"Comp.port\", joints = N } or { \"Comp.port\", kinematics = \"Comp\" }";
      if (!lua_istable(L, -1)) {
        studio.robots.push_back({name, portName(entry, what), 0, {}, entry.where()});
        return;
      }
      lua_rawgeti(L, -1, 1);
      const std::string port = portName(entry, what);
      lua_pop(L, 1);
      studio.robots.push_back({name, port, wholeCount(entry, "joints", 0.0, kMaxJoints, "joints"), entry.string("kinematics", false),
                               entry.where()});
    });
    s.entries("extras", [&](const std::string& name, const Reader& entry) { studio.extras.push_back(readExtra(name, entry)); });
    for (const std::string& signal : s.strings("signals")) studio.signals.emplace_back(signal, Where{s.where().file, s.lineOf(signal)});
    s.entries("inputs", [&](const std::string& name, const Reader& entry) {
      StudioSpec::Input input;
      input.name = name;
      if (!lua_istable(L, -1) || luaL_len(L, -1) < 1)
        entry.fail("must be { \"Comp.operation\", args..., label = \"...\" }, e.g. { \"Surgeon.say\", \"e_needle_mounted\" }");
      const lua_Integer n = luaL_len(L, -1);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L, -1, i);
        const bool text = lua_type(L, -1) == LUA_TSTRING;
        std::string value = text ? lua_tostring(L, -1) : std::string();
        lua_pop(L, 1);
        if (!text) entry.fail("entry " + std::to_string(i) + " must be a string (the operation, then its arguments)");
        if (i == 1) input.call = value;
        else input.args.push_back(std::move(value));
      }
      split(entry, input.call, "operation");
      input.label = entry.string("label", false);
      input.event = entry.string("event", false, input.args.empty() ? std::string() : input.args.front());
      if (input.label.empty()) {
        input.label = name;
        std::replace(input.label.begin(), input.label.end(), '_', ' ');
        input.label[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(input.label[0])));
      }
      input.where = entry.where();
      // The action the runner plays: { call = "Comp.operation", args = { ... } }.
      lua_newtable(L);
      lua_pushstring(L, input.call.c_str());
      lua_setfield(L, -2, "call");
      lua_newtable(L);
      for (std::size_t i = 0; i < input.args.size(); ++i) {
        lua_pushstring(L, input.args[i].c_str());
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      lua_setfield(L, -2, "args");
      input.lua_ref = luaL_ref(L, LUA_REGISTRYINDEX);
      studio.inputs.push_back(std::move(input));
    });
  }
}


// Nothing to do at a step: the RunObserver shows the run.
class StudioSection final : public Observer {
 public:
  void attach(ObserverContext& /*run*/) override {}
};

}  // namespace

ObserverRegistry::Kind studioObserver() {
  return {"studio", "what cobra studio shows of the run and the surgeon's inputs (studio/README.md)", "cobra",
          [](const Section& section) -> std::unique_ptr<Observer> {
            readStudio(section.reader(), section.spec().studio);
            return std::make_unique<StudioSection>();
          }};
}

void addBuiltinObservers(std::vector<ObserverRegistry::Kind>& kinds) {
  for (auto make : {recordObserver, plotsObserver, summaryObserver, trackingObserver, clearanceObserver, studioObserver})
    kinds.push_back(make());
}

}  // namespace cobra::run
