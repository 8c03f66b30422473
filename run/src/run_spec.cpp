#include "cobra/run/run_spec.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <lua.hpp>

namespace cobra::run {
namespace {

// The lines of `file` (to find where an entry is written: Lua keeps no line per table entry).
std::vector<std::string> linesOf(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Reads one Lua table (at the top of the stack while it lives) with its path for messages.
class Reader {
 public:
  Reader(lua_State* L, const std::string& file, std::vector<std::string> lines, std::string path, int line)
      : L_(L), file_(file), lines_(std::move(lines)), path_(std::move(path)), line_(line) {}

  Where where() const { return {file_, line_}; }
  const std::string& path() const { return path_; }

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(where().text() + ": " + path_ + ": " + what);
  }

  // The first line at or after this entry's that contains `text` (quoted), for its children.
  int lineOf(const std::string& text) const {
    for (std::size_t i = static_cast<std::size_t>(std::max(line_ - 1, 0)); i < lines_.size(); ++i)
      if (lines_[i].find("\"" + text + "\"") != std::string::npos || lines_[i].find("'" + text + "'") != std::string::npos)
        return static_cast<int>(i + 1);
    return line_;
  }

  bool has(const char* key) const {
    lua_getfield(L_, -1, key);
    const bool present = !lua_isnil(L_, -1);
    lua_pop(L_, 1);
    return present;
  }

  std::string string(const char* key, bool required, const std::string& fallback = {}) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      if (required) fail("needs `" + std::string(key) + "` (a string)");
      return fallback;
    }
    if (lua_type(L_, -1) != LUA_TSTRING) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a string");
    }
    std::string value = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    return value;
  }

  double number(const char* key, double fallback, bool positive = false) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return fallback;
    }
    if (!lua_isnumber(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a number");
    }
    const double value = lua_tonumber(L_, -1);
    lua_pop(L_, 1);
    if (!std::isfinite(value) || (positive && value <= 0.0)) fail("`" + std::string(key) + "` must be a finite" +
                                                                   (positive ? " positive" : "") + " number");
    return value;
  }

  bool boolean(const char* key, bool fallback) const {
    lua_getfield(L_, -1, key);
    const bool value = lua_isnil(L_, -1) ? fallback : lua_toboolean(L_, -1) != 0;
    lua_pop(L_, 1);
    return value;
  }

  // A list of strings (or a single string) under `key`.
  std::vector<std::string> strings(const char* key) const {
    std::vector<std::string> out;
    lua_getfield(L_, -1, key);
    if (lua_type(L_, -1) == LUA_TSTRING) {
      out.push_back(lua_tostring(L_, -1));
    } else if (lua_istable(L_, -1)) {
      const lua_Integer n = luaL_len(L_, -1);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L_, -1, i);
        if (lua_type(L_, -1) != LUA_TSTRING) {
          lua_pop(L_, 2);
          fail("`" + std::string(key) + "` must be a list of strings (entry " + std::to_string(i) + " is not)");
        }
        out.push_back(lua_tostring(L_, -1));
        lua_pop(L_, 1);
      }
    } else if (!lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a string or a list of strings");
    }
    lua_pop(L_, 1);
    return out;
  }

  // A list of positive numbers under `key`.
  std::vector<double> numbers(const char* key) const {
    std::vector<double> out;
    lua_getfield(L_, -1, key);
    const lua_Integer n = luaL_len(L_, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L_, -1, i);
      const bool number = lua_isnumber(L_, -1) != 0;
      const double value = number ? lua_tonumber(L_, -1) : 0.0;
      lua_pop(L_, 1);
      if (!number || !(value > 0.0) || !std::isfinite(value)) {
        lua_pop(L_, 1);
        fail("`" + std::string(key) + "` must be a list of positive numbers (entry " + std::to_string(i) + " is not)");
      }
      out.push_back(value);
    }
    lua_pop(L_, 1);
    return out;
  }

  // Calls `each` with a Reader on every entry of the list under `key` (tables), their line
  // found from the string `identify` returns for the entry.
  template <class F>
  void list(const char* key, F&& each, const char* identify = "name") const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return;
    }
    if (!lua_istable(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a list of tables");
    }
    const lua_Integer n = luaL_len(L_, -1);
    int line = line_;
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L_, -1, i);
      Reader entry(L_, file_, lines_, path_ + "." + key + "[" + std::to_string(i) + "]", line);
      if (!lua_istable(L_, -1)) entry.fail("must be a table");
      const std::string id = identify ? entry.string(identify, false) : std::string();
      if (!id.empty()) entry.line_ = line = lineOf(id);
      each(entry);
      lua_pop(L_, 1);
    }
    lua_pop(L_, 1);
  }

  // Calls `f` with a Reader on the table under `key` when there is one.
  template <class F>
  bool table(const char* key, F&& f) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return false;
    }
    if (!lua_istable(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a table");
    }
    Reader sub(L_, file_, lines_, path_ + "." + key, line_);
    f(sub);
    lua_pop(L_, 1);
    return true;
  }

  // Calls `each(name, entry)` on every `name = value` of the table under `key`, in the order of
  // their lines (Lua keeps none), each entry's line the first at or after this one writing `name =`.
  template <class F>
  void entries(const char* key, F&& each) const {
    std::vector<std::pair<int, std::string>> names;
    table(key, [&](const Reader& t) {
      lua_pushnil(L_);
      while (lua_next(L_, -2) != 0) {
        lua_pop(L_, 1);
        if (lua_type(L_, -1) != LUA_TSTRING) {
          lua_pop(L_, 1);
          t.fail("entries must be written name = ...");
        }
        const std::string name = lua_tostring(L_, -1);
        names.emplace_back(t.lineOfKey(name), name);
      }
      std::sort(names.begin(), names.end());
      for (const auto& [line, name] : names) {
        lua_getfield(L_, -1, name.c_str());
        Reader entry(L_, file_, lines_, t.path_ + "." + name, line);
        each(name, entry);
        lua_pop(L_, 1);
      }
    });
  }

  // The first line at or after this entry's that writes `name =` (a key of a table).
  int lineOfKey(const std::string& name) const {
    for (std::size_t i = static_cast<std::size_t>(std::max(line_ - 1, 0)); i < lines_.size(); ++i) {
      for (std::size_t at = lines_[i].find(name); at != std::string::npos; at = lines_[i].find(name, at + 1)) {
        const bool starts = at == 0 || !(std::isalnum(static_cast<unsigned char>(lines_[i][at - 1])) || lines_[i][at - 1] == '_');
        std::size_t after = at + name.size();
        while (after < lines_[i].size() && lines_[i][after] == ' ') ++after;
        if (starts && after < lines_[i].size() && lines_[i][after] == '=') return static_cast<int>(i + 1);
      }
    }
    return line_;
  }

  lua_State* state() const { return L_; }
  int line() const { return line_; }
  void setLine(int line) { line_ = line; }

 private:
  lua_State* L_;
  std::string file_;
  std::vector<std::string> lines_;
  std::string path_;
  int line_;
};

// "Comp.member" -> (Comp, member).
std::pair<std::string, std::string> split(const Reader& r, const std::string& path, const char* member) {
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    r.fail("'" + path + "' must be written Component." + member);
  return {path.substr(0, dot), path.substr(dot + 1)};
}

// "chart:state path" -> (chart, state).
std::pair<std::string, std::string> chartState(const Reader& r, const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    r.fail("state '" + text + "' must be written chart:state path, e.g. needle:root.WaitCryoCycle");
  return {text.substr(0, colon), text.substr(colon + 1)};
}

// A path's `marks = { { "A", "chart:state path" }, ... }`.
std::vector<PathSpec::Mark> readMarks(const Reader& entry) {
  std::vector<PathSpec::Mark> marks;
  lua_State* L = entry.state();
  lua_getfield(L, -1, "marks");
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    return marks;
  }
  // Pops the marks table before failing, as the Reader's own checks do.
  const auto bad = [&](const std::string& what) {
    lua_pop(L, 1);
    entry.fail("`marks` " + what + "; write marks = { { \"A\", \"chart:state path\" }, ... }");
  };
  if (!lua_istable(L, -1)) bad("must be a list");
  const lua_Integer n = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    std::string pair[2];
    bool ok = lua_istable(L, -1) && luaL_len(L, -1) == 2;
    for (int k = 0; ok && k < 2; ++k) {
      lua_rawgeti(L, -1, k + 1);
      ok = lua_type(L, -1) == LUA_TSTRING;
      if (ok) pair[k] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
    if (!ok) bad("entry " + std::to_string(i) + " is not a pair of strings");
    PathSpec::Mark mark;
    mark.label = pair[0];
    std::tie(mark.chart, mark.state) = chartState(entry, pair[1]);
    marks.push_back(std::move(mark));
  }
  lua_pop(L, 1);
  return marks;
}

Trigger readTrigger(const Reader& entry) {
  Trigger t;
  const bool found = entry.table("on", [&](const Reader& on) {
    const int kinds = on.has("event") + on.has("state") + on.has("time");
    if (kinds != 1) on.fail("give exactly one of event = \"NAME\", state = \"chart:path\", time = s");
    if (on.has("event")) {
      t.kind = Trigger::Kind::Event;
      t.event = on.string("event", true);
      t.source = on.string("source", false);
    } else if (on.has("state")) {
      t.kind = Trigger::Kind::State;
      std::tie(t.chart, t.state) = chartState(on, on.string("state", true));
    } else {
      t.kind = Trigger::Kind::Time;
      t.time = on.number("time", 0.0);
    }
  });
  if (!found) entry.fail("needs `on = { event = ... | state = ... | time = ... }`");
  return t;
}

// One action or fault entry; its table is kept in the registry for the runner to play.
ActionSpec readAction(Reader& entry, bool repeat_default) {
  ActionSpec a;
  a.on = readTrigger(entry);
  a.after = entry.number("after", 0.0);
  if (a.after < 0.0) entry.fail("`after` must be >= 0 s");
  a.repeat = entry.boolean("repeat", repeat_default);
  const int kinds = entry.has("call") + entry.has("write") + entry.has("set") + entry.has("lua");
  if (kinds != 1) entry.fail("give exactly one of call = \"Comp.operation\", write = { port = , value = }, "
                             "set = { property = , value = }, lua = \"deployer code\"");
  if (entry.has("call")) {
    a.kind = ActionSpec::Kind::Call;
    const std::string target = entry.string("call", true);
    entry.setLine(entry.lineOf(target));
    std::tie(a.component, a.member) = split(entry, target, "operation");
    a.text = "call " + target;
  } else if (entry.has("lua")) {
    a.kind = ActionSpec::Kind::Lua;
    a.text = "lua: " + entry.string("lua", true);
  } else {
    const bool write = entry.has("write");
    a.kind = write ? ActionSpec::Kind::Write : ActionSpec::Kind::Set;
    entry.table(write ? "write" : "set", [&](const Reader& what) {
      const std::string target = what.string(write ? "port" : "property", true);
      entry.setLine(entry.lineOf(target));
      std::tie(a.component, a.member) = split(what, target, write ? "port" : "property");
      if (!what.has("value")) what.fail("needs `value`");
      a.text = std::string(write ? "write " : "set ") + target;
    });
  }
  a.where = entry.where();
  lua_pushvalue(entry.state(), -1);
  a.lua_ref = luaL_ref(entry.state(), LUA_REGISTRYINDEX);
  return a;
}

// The identifying string of an action entry, for its line.
void placeAction(Reader& entry) {
  for (const char* key : {"call", "lua"})
    if (entry.has(key)) entry.setLine(entry.lineOf(entry.string(key, false)));
}

// A Frame or double port name: the value of an entry, a string "Comp.port".
std::string portName(const Reader& entry, const std::string& what) {
  if (lua_type(entry.state(), -1) != LUA_TSTRING) entry.fail("must be a port name \"Comp.port\" (" + what + ")");
  std::string port = lua_tostring(entry.state(), -1);
  split(entry, port, "port");
  return port;
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
    const double max = entry.number("max", extra.max, true);
    if (max != std::floor(max)) entry.fail("`max` must be a whole number of points");
    extra.max = static_cast<int>(max);
  }
  if (extra.kind == "polyline") {
    const double strands = entry.number("strands", 1.0, true);
    if (strands != std::floor(strands)) entry.fail("`strands` must be a whole number of lines");
    extra.strands = static_cast<int>(strands);
  }
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
void readStudio(const Reader& run, StudioSpec& studio) {
  lua_State* L = run.state();
  studio.declared = run.table("studio", [&](const Reader& s) {
    studio.scene = s.string("scene", false);
    studio.scene_where = {s.where().file, studio.scene.empty() ? s.line() : s.lineOf(studio.scene)};
    s.entries("robots", [&](const std::string& name, const Reader& entry) {
      const char* what = "the robot's measured joints, KDL.JntArray; or { \"Comp.port\", joints = N }";
      if (!lua_istable(L, -1)) {
        studio.robots.push_back({name, portName(entry, what), 0, entry.where()});
        return;
      }
      lua_rawgeti(L, -1, 1);
      const std::string port = portName(entry, what);
      lua_pop(L, 1);
      const double joints = entry.number("joints", 0.0, true);
      if (joints != std::floor(joints)) entry.fail("`joints` must be a whole number");
      studio.robots.push_back({name, port, static_cast<int>(joints), entry.where()});
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
  });
}

}  // namespace

std::string Trigger::text() const {
  switch (kind) {
    case Kind::Event: return "event " + event + (source.empty() ? "" : " from " + source);
    case Kind::State: return "state " + chart + ":" + state;
    case Kind::Time: break;
  }
  char text[48];
  std::snprintf(text, sizeof text, "time %.3f s", time);
  return text;
}

RunSpec readRunSpec(lua_State* L, const std::string& file) {
  RunSpec spec;
  std::vector<std::string> lines = linesOf(file);
  int run_line = 1;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].rfind("run = {", 0) == 0 || lines[i].rfind("run={", 0) == 0) run_line = static_cast<int>(i + 1);
  lua_getglobal(L, "run");
  Reader run(L, file, lines, "run", run_line);
  if (lua_isnil(L, -1)) {
    lua_pop(L, 1);
    throw std::runtime_error(file + ": no `run = { charts = { ... } }` table: the runner needs to know which task "
                             "charts end the run (run/README.md)");
  }
  if (!lua_istable(L, -1)) run.fail("must be a table");
  spec.title = run.string("title", false, "Run of " + file);
  spec.step = run.number("step", spec.step, true);
  spec.fold = run.strings("fold");
  spec.failures = run.strings("failures");
  spec.safe_stop_reason = run.string("safe_stop_reason", false);
  spec.safe_stop_linger = run.number("safe_stop_linger", spec.safe_stop_linger);
  run.table("explain", [&](const Reader& explain) {
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
      if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING)
        explain.fail("entries must be event = \"operation\"");
      spec.explain[lua_tostring(L, -2)] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
  });
  run.list("charts", [&](Reader& c) {
    ChartSpec chart;
    chart.name = c.string("name", true);
    chart.supervisor = c.string("supervisor", true);
    chart.done = c.string("done", true);
    chart.safe_stop = c.string("safe_stop", false);
    chart.scope = c.string("scope", false);
    chart.sources = c.strings("sources");
    chart.where = c.where();
    for (const ChartSpec& other : spec.charts)
      if (other.name == chart.name) c.fail("a second chart called '" + chart.name + "'");
    spec.charts.push_back(std::move(chart));
  });
  if (spec.charts.empty()) run.fail("needs `charts = { { name = , supervisor = , done = } }`: the charts that end the run");
  run.list(
      "actions",
      [&](Reader& entry) {
        placeAction(entry);
        spec.actions.push_back(readAction(entry, true));
      },
      nullptr);
  run.table("record", [&](const Reader& record) {
    spec.record.period = record.number("period", spec.record.period, true);
    for (const std::string& port : record.strings("ports")) spec.record.ports.emplace_back(port, Where{file, record.lineOf(port)});
  });
  run.list(
      "plots",
      [&](Reader& p) {
        PlotSpec plot;
        plot.title = p.string("title", true);
        plot.unit = p.string("unit", false);
        plot.x = p.string("x", false);
        plot.x_unit = p.string("x_unit", false);
        plot.series = p.strings("series");
        p.list(
            "paths",
            [&](Reader& entry) {
              PathSpec path;
              path.label = entry.string("label", true);
              path.x = entry.string("x", true);
              path.y = entry.string("y", true);
              path.dashed = entry.boolean("dashed", false);
              path.marks = readMarks(entry);
              plot.paths.push_back(std::move(path));
            },
            "label");
        if (plot.series.empty() == plot.paths.empty())
          p.fail("needs either `series = { \"Comp.port\", ... }` or `paths = { { label = , x = , y = }, ... }`");
        if (!plot.paths.empty() && !plot.x.empty())
          p.fail("`x` is for series; each path names its own x and y columns");
        if (p.has("from")) {
          if (plot.paths.empty()) p.fail("`from` is for paths");
          std::tie(plot.from_chart, plot.from_state) = chartState(p, p.string("from", true));
        }
        plot.where = p.where();
        spec.plots.push_back(std::move(plot));
      },
      "title");
  run.list("summary", [&](Reader& s) {
    SummarySpec value;
    value.name = s.string("name", true);
    value.unit = s.string("unit", false);
    value.scale = s.number("scale", 1.0);
    value.of = s.string("of", false);
    value.say = s.boolean("say", false);
    if (s.has("count")) {
      value.kind = SummarySpec::Kind::Count;
      value.events = s.strings("count");
    } else {
      value.kind = s.has("distance") ? SummarySpec::Kind::Distance : SummarySpec::Kind::Port;
      value.ports = s.strings(s.has("distance") ? "distance" : "port");
      if (value.kind == SummarySpec::Kind::Distance && value.ports.size() != 2)
        s.fail("`distance` must name two Frame ports");
      if (value.kind == SummarySpec::Kind::Port && value.ports.size() != 1)
        s.fail("give one of count = { events }, distance = { two Frame ports }, port = \"Comp.port\"");
      const bool enter = s.has("on_enter"), leave = s.has("on_leave");
      if (enter == leave) s.fail("give one of on_enter = \"chart:state\", on_leave = \"chart:state\" (when to sample)");
      value.leave = leave;
      std::tie(value.chart, value.state) = chartState(s, s.string(leave ? "on_leave" : "on_enter", true));
    }
    value.where = s.where();
    spec.summary.push_back(std::move(value));
  });
  run.list("tracking", [&](Reader& t) {
    TrackingSpec tracking;
    tracking.name = t.string("name", true);
    tracking.commanded = t.string("commanded", true);
    tracking.measured = t.string("measured", true);
    tracking.joints = t.string("joints", false);
    lua_getfield(L, -1, "max_velocity");
    const bool listed = lua_istable(L, -1);
    lua_pop(L, 1);
    if (listed) {
      tracking.max_velocity_values = t.numbers("max_velocity");
    } else {
      tracking.max_velocity = t.string("max_velocity", false);
    }
    if (!tracking.joints.empty() && tracking.max_velocity.empty() && tracking.max_velocity_values.empty())
      t.fail("`joints` needs `max_velocity = \"Comp.property\"` or { limits } (the joints' velocity limits, rad/s or "
             "m/s)");
    tracking.chart = t.string("chart", false);
    tracking.accept_mm = t.number("accept_mm", tracking.accept_mm, true);
    tracking.accept_deg = t.number("accept_deg", tracking.accept_deg, true);
    t.table("counts_while", [&](const Reader& counts) {
      tracking.scope = counts.string("scope", false);
      tracking.counts_while = counts.strings("deployments");
    });
    tracking.where = t.where();
    spec.tracking.push_back(std::move(tracking));
  });
  spec.clearance.declared = run.table("clearance", [&](const Reader& c) {
    ClearanceSpec& clearance = spec.clearance;
    clearance.port = c.string("port", true);
    clearance.where = {file, c.lineOf(clearance.port)};
    lua_getfield(L, -1, "threshold");
    if (lua_type(L, -1) == LUA_TNUMBER) {
      clearance.threshold = lua_tonumber(L, -1);
    } else if (lua_type(L, -1) == LUA_TSTRING) {
      clearance.threshold_operation = lua_tostring(L, -1);
    } else {
      lua_pop(L, 1);
      c.fail("needs `threshold` (m, a number, or \"Comp.operation\" returning it)");
    }
    lua_pop(L, 1);
    c.list("contacts", [&](Reader& contact) {
      clearance.contacts.emplace_back(contact.string("name", true), contact.string("port", true));
    });
    c.list("pauses", [&](Reader& pause) {
      clearance.pauses.push_back(
          {pause.string("name", true), pause.string("chart", true), pause.strings("from"), pause.strings("to")});
    });
  });
  readStudio(run, spec.studio);
  lua_pop(L, 1);
  return spec;
}

std::vector<ActionSpec> readFaults(lua_State* L, const std::string& file) {
  if (luaL_loadfile(L, file.c_str()) != LUA_OK || lua_pcall(L, 0, 1, 0) != LUA_OK) {
    std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(no message)";
    lua_pop(L, 1);
    throw std::runtime_error(message);
  }
  if (!lua_istable(L, -1)) {
    lua_pop(L, 1);
    throw std::runtime_error(file + ": a faults file returns a list: return { { on = { ... }, call = ... }, ... }");
  }
  std::vector<ActionSpec> out;
  const std::vector<std::string> lines = linesOf(file);
  std::vector<int> starts;  // entry i starts on the line of the i-th `on = {`
  for (std::size_t l = 0; l < lines.size(); ++l)
    if (lines[l].find("on = {") != std::string::npos || lines[l].find("on={") != std::string::npos)
      starts.push_back(static_cast<int>(l + 1));
  const lua_Integer n = luaL_len(L, -1);
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    const int line = static_cast<std::size_t>(i) <= starts.size() ? starts[static_cast<std::size_t>(i - 1)] : 1;
    Reader entry(L, file, lines, "fault " + std::to_string(i), line);
    if (!lua_istable(L, -1)) entry.fail("must be a table { on = { ... }, call/write/set/lua = ... }");
    placeAction(entry);
    out.push_back(readAction(entry, false));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return out;
}

}  // namespace cobra::run
