// Reading the fault matrix's table (matrix.lua) into tasks, faults and cells, and writing a cell's
// faults file. The table is Lua: `task "NAME" { ... }` and `fault "NAME" { ... }` calls, whose
// lines the prelude notes (Lua keeps no line per table entry); keys inside are found on the lines
// after them. Every name is checked here, one line each: FILE:LINE, what is wrong, what was expected.

#include "cobra/fault_matrix/matrix.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <stdexcept>

#include <lua.hpp>

#include "cobra/deploy/suggest.hpp"

namespace cobra::fault_matrix {
namespace {

// Notes each task and fault with its line; serialises a fault entry's fields as Lua source.
constexpr const char* kPrelude = R"lua(
local tasks, faults = {}, {}
local function at() return debug.getinfo(3, "l").currentline end
function task(name)
  local line = at()
  return function(t) tasks[#tasks + 1] = { name = name, line = line, t = t } end
end
function fault(name)
  local line = at()
  return function(t) faults[#faults + 1] = { name = name, line = line, t = t } end
end
function na(why) return { na = why } end
local function source(v)
  local kind = type(v)
  if kind == "string" then return string.format("%q", v) end
  if kind == "number" then
    if v ~= v then return "0/0" end
    if v == math.huge or v == -math.huge then return (v < 0 and "-" or "") .. "math.huge" end
    return math.type(v) == "integer" and tostring(v) or string.format("%.17g", v)
  end
  if kind == "boolean" then return tostring(v) end
  if kind ~= "table" then error("a " .. kind .. " cannot be written in a faults file", 0) end
  local parts = {}
  for i = 1, #v do parts[#parts + 1] = source(v[i]) end
  local keys = {}
  for k in pairs(v) do if type(k) == "string" then keys[#keys + 1] = k end end
  table.sort(keys)
  for _, k in ipairs(keys) do parts[#parts + 1] = k .. " = " .. source(v[k]) end
  return "{ " .. table.concat(parts, ", ") .. " }"
end
-- An entry's fields but `after` (a faults file entry without its braces), its `after` and
-- whether it names its own trigger.
local function fields(v)
  local copy = {}
  for k, x in pairs(v) do if k ~= "after" then copy[k] = x end end
  local after = v.after or 0
  if type(after) ~= "number" then error("`after` must be a number of s", 0) end
  return source(copy):sub(3, -3), after, v.on ~= nil
end
cobra_matrix = { tasks = tasks, faults = faults, fields = fields }
)lua";

// The table's lines, to find where a key is written (Lua keeps no line per table entry).
std::vector<std::string> linesOf(const std::filesystem::path& file) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> lines;
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

// Reads the table's values off the Lua stack, naming file:line in every error.
class Reader {
 public:
  Reader(lua_State* L, std::filesystem::path file) : L_(L), file_(std::move(file)), lines_(linesOf(file_)) {}

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw std::runtime_error(file_.string() + ":" + std::to_string(line) + ": " + what);
  }
  // The first line at or after `from` where `key` is given (`key =` or "key"), else `from`.
  int lineOf(int from, const std::string& key) const {
    for (std::size_t i = static_cast<std::size_t>(std::max(from - 1, 0)); i < lines_.size(); ++i) {
      const std::string& l = lines_[i];
      for (std::size_t p = l.find(key); p != std::string::npos; p = l.find(key, p + 1)) {
        const bool word_start = p == 0 || !(std::isalnum(static_cast<unsigned char>(l[p - 1])) || l[p - 1] == '_');
        const std::size_t e = p + key.size();
        const bool word_end = e >= l.size() || !(std::isalnum(static_cast<unsigned char>(l[e])) || l[e] == '_');
        if (word_start && word_end) return static_cast<int>(i + 1);
      }
    }
    return from;
  }
  // The string keys of the table at the top.
  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    lua_pushnil(L_);
    while (lua_next(L_, -2) != 0) {
      if (lua_type(L_, -2) == LUA_TSTRING) out.push_back(lua_tostring(L_, -2));
      lua_pop(L_, 1);
    }
    std::sort(out.begin(), out.end());
    return out;
  }
  // Field `key` of the table at the top as a string ("" absent).
  std::string string(const char* key, int line, const std::string& what) const {
    lua_getfield(L_, -1, key);
    std::string out;
    if (lua_type(L_, -1) == LUA_TSTRING) out = lua_tostring(L_, -1);
    else if (!lua_isnil(L_, -1)) fail(lineOf(line, key), what + ": `" + key + "` must be a string");
    lua_pop(L_, 1);
    return out;
  }
  double number(const char* key, double fallback, int line, const std::string& what) const {
    lua_getfield(L_, -1, key);
    double out = fallback;
    if (lua_type(L_, -1) == LUA_TNUMBER) out = lua_tonumber(L_, -1);
    else if (!lua_isnil(L_, -1)) fail(lineOf(line, key), what + ": `" + key + "` must be a number");
    lua_pop(L_, 1);
    return out;
  }
  std::vector<std::string> strings(const char* key, int line, const std::string& what) const {
    lua_getfield(L_, -1, key);
    std::vector<std::string> out;
    if (lua_istable(L_, -1)) {
      for (lua_Integer i = 1, n = luaL_len(L_, -1); i <= n; ++i) {
        lua_rawgeti(L_, -1, i);
        if (lua_type(L_, -1) != LUA_TSTRING) fail(lineOf(line, key), what + ": `" + key + "` must be a list of strings");
        out.push_back(lua_tostring(L_, -1));
        lua_pop(L_, 1);
      }
    } else if (!lua_isnil(L_, -1)) {
      fail(lineOf(line, key), what + ": `" + key + "` must be a list of strings");
    }
    lua_pop(L_, 1);
    return out;
  }
  void allowOnly(const std::vector<std::string>& allowed, int line, const std::string& what) const {
    for (const std::string& k : keys())
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        fail(lineOf(line, k), what + ": unknown field '" + k + "'" + deploy::suggestionText(k, allowed, "fields"));
  }

  lua_State* L_;
  std::filesystem::path file_;
  std::vector<std::string> lines_;
};

std::filesystem::path fromRoot(const std::filesystem::path& root, const std::string& path) {
  return path.empty() ? std::filesystem::path() : (root / path).lexically_normal();
}

Task readTask(const Reader& r, const std::string& name, int line, const std::filesystem::path& root) {
  const std::string what = "task '" + name + "'";
  r.allowOnly({"app", "scenarios", "time_limit", "moments", "hold", "commands"}, line, what);
  Task t;
  t.name = name;
  t.line = line;
  const std::string app = r.string("app", line, what);
  if (app.empty()) r.fail(line, what + ": needs `app = \"apps/NAME\"` (an application folder or entry file)");
  t.app = fromRoot(root, app);
  for (const std::string& s : r.strings("scenarios", line, what)) t.scenarios.push_back(fromRoot(root, s));
  if (t.scenarios.empty()) t.scenarios.emplace_back();
  t.time_limit = r.number("time_limit", 300.0, line, what);
  t.hold = r.strings("hold", line, what);
  t.commands = r.strings("commands", line, what);
  lua_State* L = r.L_;
  lua_getfield(L, -1, "moments");
  if (!lua_istable(L, -1)) r.fail(line, what + ": needs `moments = { { \"NAME\", state = \"chart:path\", after = s }, ... }`");
  for (lua_Integer i = 1, n = luaL_len(L, -1); i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    Moment m;
    m.line = line;
    if (!lua_istable(L, -1)) r.fail(r.lineOf(line, "moments"), what + ": moment " + std::to_string(i) +
                                                                   " must be { \"NAME\", state = \"chart:path\", after = s }");
    lua_rawgeti(L, -1, 1);
    if (lua_type(L, -1) == LUA_TSTRING) m.name = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (m.name.empty()) r.fail(r.lineOf(line, "moments"), what + ": moment " + std::to_string(i) + " needs its name first: { \"NAME\", state = ... }");
    m.line = r.lineOf(line, "\"" + m.name + "\"") ;
    m.state = r.string("state", m.line, what + ", moment '" + m.name + "'");
    if (m.state.find(':') == std::string::npos)
      r.fail(m.line, what + ", moment '" + m.name + "': needs `state = \"chart:path\"` (the chart of run.charts and a state path)");
    m.after = r.number("after", 0.0, m.line, what + ", moment '" + m.name + "'");
    t.moments.push_back(m);
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  if (t.moments.empty()) r.fail(line, what + ": needs at least one moment");
  return t;
}

std::vector<std::string> taskNames(const std::vector<Task>& tasks) {
  std::vector<std::string> names;
  for (const Task& t : tasks) names.push_back(t.name);
  return names;
}

std::string namesText(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

FaultForTask readFaultForTask(const Reader& r, const Fault& f, const Task& task, int line) {
  const std::string what = "fault '" + f.name + "', task '" + task.name + "'";
  lua_State* L = r.L_;
  FaultForTask out;
  out.task = task.name;
  out.line = line;
  if (!lua_istable(L, -1)) r.fail(line, what + ": give a list of faults-file entries { { call = ... }, ... } or na \"why\"");
  r.allowOnly({"na", "gap", "before", "moments"}, line, what);
  out.na = r.string("na", line, what);
  lua_getfield(L, -1, "gap");
  const bool per_moment = lua_istable(L, -1);
  lua_pop(L, 1);
  if (!per_moment) {
    if (std::string gap = r.string("gap", line, what); !gap.empty()) out.gaps.emplace_back("", gap);
  } else {
    lua_getfield(L, -1, "gap");
    for (const std::string& m : r.keys()) out.gaps.emplace_back(m, r.string(m.c_str(), r.lineOf(line, "gap"), what + ", gap"));
    lua_pop(L, 1);
  }
  out.before_lua = r.string("before", line, what);
  out.moments = r.strings("moments", line, what);
  std::vector<std::string> named = out.moments;
  for (const auto& [m, why] : out.gaps)
    if (!m.empty()) named.push_back(m);
  for (const std::string& m : named) {
    std::vector<std::string> known;
    for (const Moment& each : task.moments) known.push_back(each.name);
    if (std::find(known.begin(), known.end(), m) == known.end())
      r.fail(r.lineOf(line, m), what + ": unknown moment '" + m + "'" + deploy::suggestionText(m, known, "moments"));
  }
  const lua_Integer n = luaL_len(L, -1);
  if (out.na.empty() && n == 0) r.fail(line, what + ": no entry: give the faults-file entries to play, or na \"why it does not apply\"");
  if (!out.na.empty() && n > 0) r.fail(line, what + ": both entries and na: give one");
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    if (!lua_istable(L, -1)) r.fail(line, what + ": entry " + std::to_string(i) + " must be a table { call = ... }");
    lua_getglobal(L, "cobra_matrix");
    lua_getfield(L, -1, "fields");
    lua_pushvalue(L, -3);
    if (lua_pcall(L, 1, 3, 0) != LUA_OK) r.fail(line, what + ": entry " + std::to_string(i) + ": " + lua_tostring(L, -1));
    out.entries.push_back(Entry{lua_tostring(L, -3), lua_tonumber(L, -2), static_cast<bool>(lua_toboolean(L, -1))});
    lua_pop(L, 5);
  }
  return out;
}

}  // namespace

const Task& Table::task(const std::string& name) const {
  for (const Task& t : tasks)
    if (t.name == name) return t;
  throw std::runtime_error("unknown task '" + name + "'; expected one of " + namesText(taskNames(tasks)));
}

Table readTable(const std::filesystem::path& file, const std::filesystem::path& root) {
  if (!std::filesystem::is_regular_file(file)) throw std::runtime_error(file.string() + ": no such file (the fault matrix's table)");
  Table table;
  table.file = file;
  table.root = root;
  lua_State* L = luaL_newstate();
  struct Close {
    lua_State* L;
    ~Close() { lua_close(L); }
  } close{L};
  luaL_openlibs(L);
  if (luaL_dostring(L, kPrelude) != LUA_OK) throw std::runtime_error(std::string("fault matrix prelude: ") + lua_tostring(L, -1));
  lua_pushstring(L, root.c_str());
  lua_setglobal(L, "root");
  if (luaL_dofile(L, file.c_str()) != LUA_OK) throw std::runtime_error(lua_tostring(L, -1));
  const Reader r(L, file);
  lua_getglobal(L, "cobra_matrix");
  lua_getfield(L, -1, "tasks");
  for (lua_Integer i = 1, n = luaL_len(L, -1); i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    lua_getfield(L, -1, "line");
    const int line = static_cast<int>(lua_tointeger(L, -1));
    lua_getfield(L, -2, "name");
    const std::string name = lua_tostring(L, -1) ? lua_tostring(L, -1) : "";
    lua_getfield(L, -3, "t");
    if (!lua_istable(L, -1)) r.fail(line, "task '" + name + "': write task \"NAME\" { app = ..., moments = { ... } }");
    for (const Task& t : table.tasks)
      if (t.name == name) r.fail(line, "task '" + name + "' is defined twice (also at line " + std::to_string(t.line) + ")");
    table.tasks.push_back(readTask(r, name, line, root));
    lua_pop(L, 4);
  }
  lua_pop(L, 1);
  const std::vector<std::string> names = taskNames(table.tasks);
  lua_getfield(L, -1, "faults");
  for (lua_Integer i = 1, n = luaL_len(L, -1); i <= n; ++i) {
    lua_rawgeti(L, -1, i);
    Fault f;
    lua_getfield(L, -1, "line");
    f.line = static_cast<int>(lua_tointeger(L, -1));
    lua_getfield(L, -2, "name");
    f.name = lua_tostring(L, -1) ? lua_tostring(L, -1) : "";
    lua_getfield(L, -3, "t");
    const std::string what = "fault '" + f.name + "'";
    if (!lua_istable(L, -1)) r.fail(f.line, what + ": write fault \"NAME\" { text = \"...\", TASK = { ... } or na \"why\", ... }");
    for (const Fault& other : table.faults)
      if (other.name == f.name) r.fail(f.line, what + " is defined twice (also at line " + std::to_string(other.line) + ")");
    f.text = r.string("text", f.line, what);
    if (f.text.empty()) r.fail(f.line, what + ": needs `text = \"what the fault is\"`");
    for (const std::string& k : r.keys())
      if (k != "text" && std::find(names.begin(), names.end(), k) == names.end())
        r.fail(r.lineOf(f.line, k), what + ": unknown task '" + k + "' (a fault's fields are `text` and its tasks)" +
                                        deploy::suggestionText(k, names, "tasks"));
    for (const Task& t : table.tasks) {
      lua_getfield(L, -1, t.name.c_str());
      if (lua_isnil(L, -1))
        r.fail(f.line, what + " says nothing of task '" + t.name + "'; give its entries or " + t.name + " = na \"why it does not apply\"");
      f.tasks.push_back(readFaultForTask(r, f, t, r.lineOf(f.line, t.name)));
      lua_pop(L, 1);
    }
    table.faults.push_back(std::move(f));
    lua_pop(L, 4);
  }
  lua_pop(L, 2);
  if (table.tasks.empty()) throw std::runtime_error(file.string() + ": no task (task \"NAME\" { app = ..., moments = { ... } })");
  return table;
}

std::string Cell::id() const { return fault->name + "/" + task->name + "/" + moment->name; }

std::string Cell::gap() const {
  for (const auto& [m, why] : what->gaps)
    if (m.empty() || m == moment->name) return why;
  return "";
}

std::vector<Cell> cells(const Table& table, const std::vector<std::string>& tasks) {
  for (const std::string& t : tasks) (void)table.task(t);  // throws for an unknown name
  std::vector<Cell> out;
  for (const Fault& f : table.faults)
    for (const FaultForTask& ft : f.tasks) {
      if (!ft.na.empty()) continue;
      if (!tasks.empty() && std::find(tasks.begin(), tasks.end(), ft.task) == tasks.end()) continue;
      const Task& task = table.task(ft.task);
      for (const Moment& m : task.moments)
        if (ft.moments.empty() || std::find(ft.moments.begin(), ft.moments.end(), m.name) != ft.moments.end())
          out.push_back(Cell{&f, &task, &ft, &m});
    }
  return out;
}

std::string faultsFileText(const Table& table, const Cell& cell) {
  char after[32];
  std::string text = "-- The fault matrix's cell " + cell.id() + ": " + table.file.string() + ":" +
                     std::to_string(cell.what->line) + " played at moment '" + cell.moment->name + "' (line " +
                     std::to_string(cell.moment->line) + ").\nreturn {\n";
  for (const Entry& entry : cell.what->entries) {
    // An entry naming its own trigger keeps it (e.g. a restoration on a reaction state); the
    // others are played at the moment, their own `after` counted from the moment's.
    std::snprintf(after, sizeof after, "%.17g", entry.own_trigger ? entry.after : cell.moment->after + entry.after);
    if (entry.own_trigger) text += "  { " + entry.fields + ", after = " + after + " },\n";
    else text += "  { on = { state = \"" + cell.moment->state + "\" }, after = " + after + ", " + entry.fields + " },\n";
  }
  return text + "}\n";
}

}  // namespace cobra::fault_matrix
