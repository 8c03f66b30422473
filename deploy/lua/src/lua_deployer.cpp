#include "cobra/deploy/lua_deployer.hpp"

#include <lua.hpp>

#include <algorithm>
#include <cstring>
#include <map>
#include <utility>

#include "cobra/deploy/install_layout.hpp"
#include "cobra/deploy/lua_configuration.hpp"
#include "cobra/script/bindings.hpp"
#include "configuration_table.hpp"
#include "lua_placement.hpp"
#include "source_lines.hpp"

namespace cobra::deploy {

/// What the Lua functions need: the Configurator, the state, and the source of each chunk.
struct LuaDeployer::Impl {
  Configurator& configurator;
  script::LuaState& lua;
  std::map<std::string, detail::SourceLines> sources;  // by file name as errors show it
  std::string entry;  // the first file run: the one that declares the placement
};

namespace {

// Lua errors longjmp: a C function Lua calls keeps its C++ work (which may throw) in an
// `impl` that calls only Lua functions that cannot raise, and `guarded` raises the Lua error
// after every C++ object of the impl is gone.
constexpr std::size_t kMessageBytes = 4096;

template <int (*Impl)(lua_State*)>
int guarded(lua_State* L) {
  char message[kMessageBytes];
  try {
    return Impl(L);
  } catch (const std::exception& e) {
    std::strncpy(message, e.what(), kMessageBytes - 1);
  } catch (...) {
    std::strncpy(message, "unknown C++ exception", kMessageBytes - 1);
  }
  message[kMessageBytes - 1] = '\0';
  lua_pushstring(L, message);
  return lua_error(L);
}

LuaDeployer::Impl& implOf(lua_State* L) {
  return *static_cast<LuaDeployer::Impl*>(lua_touserdata(L, lua_upvalueindex(1)));
}

/// Where the Lua code calling us is, and how to find its table entries' lines.
class CallSite {
 public:
  CallSite(lua_State* L, LuaDeployer::Impl& impl) {
    lua_Debug ar{};
    if (lua_getstack(L, 1, &ar) != 0 && lua_getinfo(L, "Sl", &ar) != 0) {
      const std::string source = ar.source ? ar.source : "";
      file_ = (!source.empty() && (source[0] == '@' || source[0] == '=')) ? source.substr(1) : source;
      line_ = ar.currentline;
    }
    auto it = impl.sources.find(file_);
    if (it == impl.sources.end()) it = impl.sources.emplace(file_, detail::SourceLines(file_)).first;
    lines_ = &it->second;
  }

  SourceLocation here() const { return {file_, line_}; }
  const detail::SourceLines& lines() const { return *lines_; }
  /// Starts a new list: the entries of the list passed to this call.
  void beginList() {
    const int start = lines_->listStart(line_);
    cursor_ = start > 0 ? start : line_;
  }
  /// The location of the next entry of the current list, identified by `quoted` strings.
  SourceLocation entry(const std::vector<std::string>& quoted) {
    for (const char quote : {'"', '\''}) {
      std::vector<std::string> needles;
      for (const std::string& q : quoted) needles.push_back(quote + q + quote);
      if (const int line = lines_->find(cursor_, needles); line > 0) {
        cursor_ = line;
        return {file_, line};
      }
    }
    return here();
  }

 private:
  std::string file_;
  int line_ = 0;
  int cursor_ = 0;
  const detail::SourceLines* lines_ = nullptr;
};

[[noreturn]] void fail(const SourceLocation& where, const std::string& what) {
  throw core::Error(where.text() + ": " + what);
}

/// Fails naming `head` and the first key of the table at `index` that is not in `keys` (its
/// `expected` list of them, for the message).
template <std::size_t N>
void requireKnownFields(lua_State* L, int index, const char* const (&keys)[N], const SourceLocation& where,
                        const std::string& head, const char* expected) {
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    lua_pop(L, 1);
    const char* key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : nullptr;
    if (key == nullptr || std::none_of(std::begin(keys), std::end(keys), [&](const char* k) { return std::strcmp(k, key) == 0; })) {
      const std::string name = key ? key : "(not a name)";
      lua_pop(L, 1);
      fail(where, head + "unknown field '" + name + "'; expected " + expected);
    }
  }
}

void requireTable(lua_State* L, int index, const SourceLocation& where, const char* what) {
  if (!lua_istable(L, index)) fail(where, std::string(what) + " must be a table, got " + luaL_typename(L, index));
}

/// Pushes t[key] (raw, no metamethods).
void rawField(lua_State* L, int table, const char* key) {
  lua_pushstring(L, key);
  lua_rawget(L, table);
}

/// t[key] as a string (a string value only); "" and false `found` when nil.
std::string stringField(lua_State* L, int table, const char* key, const SourceLocation& where, bool required) {
  rawField(L, table, key);
  std::string value;
  const int type = lua_type(L, -1);
  if (type == LUA_TSTRING) {
    std::size_t n = 0;
    const char* s = lua_tolstring(L, -1, &n);
    value.assign(s, n);
  } else if (type != LUA_TNIL || required) {
    const std::string got = luaL_typename(L, -1);
    lua_pop(L, 1);
    fail(where, std::string("field '") + key + "' must be a string, got " + got);
  }
  lua_pop(L, 1);
  return value;
}

/// t[key] as a number; `fallback` when nil.
double numberField(lua_State* L, int table, const char* key, const SourceLocation& where, double fallback) {
  rawField(L, table, key);
  double value = fallback;
  if (lua_type(L, -1) == LUA_TNUMBER) {
    value = lua_tonumber(L, -1);
  } else if (!lua_isnil(L, -1)) {
    const std::string got = luaL_typename(L, -1);
    lua_pop(L, 1);
    fail(where, std::string("field '") + key + "' must be a number, got " + got);
  }
  lua_pop(L, 1);
  return value;
}

/// Reads a list table at `index` entry by entry: `read(entry_index)` with the entry pushed.
template <class Read>
void forEachEntry(lua_State* L, int index, Read read) {
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, index));
  for (lua_Integer i = 1; i <= n; ++i) {
    lua_rawgeti(L, index, i);
    const int entry = lua_gettop(L);
    read(entry);
    lua_settop(L, entry - 1);
  }
}

std::vector<NameEntry> readNames(lua_State* L, int index, CallSite& site, const char* what) {
  requireTable(L, index, site.here(), what);
  site.beginList();
  std::vector<NameEntry> names;
  forEachEntry(L, index, [&](int entry) {
    if (lua_type(L, entry) != LUA_TSTRING)
      fail(site.here(), std::string("every entry of ") + what + " must be a name (string), got " + luaL_typename(L, entry));
    std::size_t n = 0;
    const char* s = lua_tolstring(L, entry, &n);
    std::string name(s, n);
    names.push_back({name, site.entry({name})});
  });
  return names;
}

std::vector<ComponentSpec> readComponents(lua_State* L, int index, CallSite& site) {
  requireTable(L, index, site.here(), "components_list");
  site.beginList();
  std::vector<ComponentSpec> specs;
  forEachEntry(L, index, [&](int entry) {
    requireTable(L, entry, site.here(), "an entry of components_list");
    const std::string peer = stringField(L, entry, "peer_name", site.here(), true);
    const SourceLocation where = site.entry({peer});
    specs.push_back({peer, stringField(L, entry, "component_type", where, true), where});
  });
  return specs;
}

std::vector<PeerSpec> readPeers(lua_State* L, int index, CallSite& site) {
  requireTable(L, index, site.here(), "peers_list");
  site.beginList();
  std::vector<PeerSpec> specs;
  forEachEntry(L, index, [&](int entry) {
    requireTable(L, entry, site.here(), "an entry of peers_list");
    PeerSpec spec;
    spec.peer_name = stringField(L, entry, "peer_name", site.here(), true);
    spec.where = site.entry({spec.peer_name});
    rawField(L, entry, "peers_to_add");
    const int peers = lua_gettop(L);
    requireTable(L, peers, spec.where, "peers_to_add");
    forEachEntry(L, peers, [&](int peer) {
      if (lua_type(L, peer) != LUA_TSTRING) fail(spec.where, "every entry of peers_to_add must be a name (string)");
      spec.peers_to_add.emplace_back(lua_tostring(L, peer));
    });
    specs.push_back(std::move(spec));
  });
  return specs;
}

std::vector<ActivitySpec> readActivities(lua_State* L, int index, CallSite& site) {
  requireTable(L, index, site.here(), "activities_list");
  site.beginList();
  std::vector<ActivitySpec> specs;
  forEachEntry(L, index, [&](int entry) {
    requireTable(L, entry, site.here(), "an entry of activities_list");
    ActivitySpec spec;
    spec.peer_name = stringField(L, entry, "peer_name", site.here(), true);
    spec.where = site.entry({spec.peer_name});
    spec.period = numberField(L, entry, "period", spec.where, 0.0);
    const double priority = numberField(L, entry, "priority", spec.where, 0.0);
    if (priority != static_cast<double>(static_cast<int>(priority)))
      fail(spec.where, "field 'priority' must be an integer, got " + std::to_string(priority));
    spec.priority = static_cast<int>(priority);
    const std::string scheduler = stringField(L, entry, "scheduler", spec.where, false);
    if (!scheduler.empty()) spec.scheduler = scheduler;
    static const char* const kKeys[] = {"peer_name", "period", "priority", "scheduler", "own_pace", "max_age"};
    requireKnownFields(L, entry, kKeys, spec.where, "activity of '" + spec.peer_name + "': ",
                       "peer_name, period, priority, scheduler, own_pace or max_age");
    rawField(L, entry, "own_pace");
    if (lua_type(L, -1) == LUA_TBOOLEAN) spec.own_pace = lua_toboolean(L, -1) != 0;
    else if (!lua_isnil(L, -1)) fail(spec.where, "field 'own_pace' must be true or false");
    lua_pop(L, 1);
    spec.max_age = numberField(L, entry, "max_age", spec.where, 0.0);
    specs.push_back(std::move(spec));
  });
  return specs;
}

ConnPolicySpec readPolicy(lua_State* L, int entry, const SourceLocation& where) {
  rawField(L, entry, "conn_policy");
  const int policy = lua_gettop(L);
  ConnPolicySpec spec;
  if (lua_isnil(L, policy)) return spec;
  requireTable(L, policy, where, "conn_policy");
  rawField(L, policy, "type");
  if (lua_type(L, -1) == LUA_TNUMBER) {  // RTT's numeric ConnPolicy types
    const lua_Integer type = lua_tointeger(L, -1);
    if (type < 0 || type > 2) fail(where, "conn_policy.type must be 0 (data), 1 (buffer) or 2 (circular)");
    spec.type = type == 0 ? "data" : type == 1 ? "buffer" : "circular";
  } else if (lua_type(L, -1) == LUA_TSTRING) {
    spec.type = lua_tostring(L, -1);
  } else if (!lua_isnil(L, -1)) {
    fail(where, std::string("conn_policy.type must be a string or a number, got ") + luaL_typename(L, -1));
  }
  const double size = numberField(L, policy, "size", where, 1.0);
  if (size != static_cast<double>(static_cast<int>(size))) fail(where, "conn_policy.size must be an integer");
  spec.size = static_cast<int>(size);
  spec.transport = stringField(L, policy, "transport", where, false);
  spec.topic = stringField(L, policy, "topic", where, false);
  rawField(L, policy, "qos");
  const int qos = lua_gettop(L);
  if (!lua_isnil(L, qos)) {
    requireTable(L, qos, where, "conn_policy.qos");
    lua_pushnil(L);
    while (lua_next(L, qos) != 0) {  // key at -2, value at -1
      if (lua_type(L, -2) != LUA_TSTRING)
        fail(where, std::string("conn_policy.qos keys must be names, e.g. reliability = \"reliable\"; got a ") +
                        luaL_typename(L, -2));
      const std::string key = lua_tostring(L, -2);
      const int type = lua_type(L, -1);
      if (type != LUA_TSTRING && type != LUA_TNUMBER)
        fail(where, "conn_policy.qos." + key + " must be a string or a number, got " + luaL_typename(L, -1));
      lua_pushvalue(L, -1);  // lua_tostring converts in place: convert a copy, not the value lua_next needs
      spec.qos.emplace_back(key, lua_tostring(L, -1));
      lua_pop(L, 2);
    }
    // Lua's table order is not the file's: sort, so that messages and comparisons are stable.
    std::sort(spec.qos.begin(), spec.qos.end());
  }
  lua_pop(L, 1);
  return spec;
}

std::vector<ConnectionSpec> readConnections(lua_State* L, int index, CallSite& site) {
  requireTable(L, index, site.here(), "connections_list");
  site.beginList();
  std::vector<ConnectionSpec> specs;
  forEachEntry(L, index, [&](int entry) {
    requireTable(L, entry, site.here(), "an entry of connections_list");
    ConnectionSpec spec;
    spec.output = stringField(L, entry, "output", site.here(), true);
    spec.input = stringField(L, entry, "input", site.here(), true);
    spec.where = site.entry({spec.output, spec.input});
    spec.conn_policy = readPolicy(L, entry, spec.where);
    specs.push_back(std::move(spec));
  });
  return specs;
}

/// Leaves the role warnings where a script can read them: returns them as a Lua list.
int pushWarnings(lua_State* L, const std::vector<LintViolation>& violations) {
  lua_createtable(L, static_cast<int>(violations.size()), 0);
  int i = 0;
  for (const LintViolation& v : violations) {
    lua_pushstring(L, v.message.c_str());
    lua_rawseti(L, -2, ++i);
  }
  return 1;
}

/// Puts the global `placement` in force when this process is one host of a split application and
/// none is yet (the Configurator refuses to create components without one).
void readPlacementOnce(lua_State* L, LuaDeployer::Impl& impl) {
  if (impl.configurator.host().empty() || impl.configurator.placement() != nullptr) return;
  lua_getglobal(L, "placement");
  const int index = lua_gettop(L);
  if (!lua_isnil(L, index)) {
    PlacementSpec spec = detail::readPlacement(L, index, impl.entry);
    lua_settop(L, index - 1);
    impl.configurator.setPlacement(std::move(spec));
  }
  lua_settop(L, index - 1);
}

int initConfiguratorImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  readPlacementOnce(L, impl);
  CallSite site(L, impl);
  const auto packages = readNames(L, 1, site, "packages_list");
  const auto components = readComponents(L, 2, site);
  std::string folder;
  if (lua_type(L, 3) == LUA_TSTRING) folder = lua_tostring(L, 3);
  else if (!lua_isnoneornil(L, 3)) fail(site.here(), "configuration_folder_path must be a string");
  // Lua-table configurations (*.lua) of the folder, read and checked for name clashes before
  // anything is created, so a bad file leaves nothing half-made; *.cfg files are the
  // Configurator's own.
  std::vector<ConfigurationSpec> lua_configurations;
  if (!folder.empty() && std::filesystem::is_directory(folder)) {
    lua_configurations = loadLuaConfigurationFolder(folder);
    for (const ConfigurationSpec& c : lua_configurations) {
      const auto twin = std::filesystem::path(folder) / (c.name + ".cfg");
      if (std::filesystem::exists(twin) || impl.configurator.deploymentSet().findConfiguration(c.name) != nullptr)
        fail(c.where, "a configuration named '" + c.name + "' already exists (" + twin.string() + " or an earlier call)");
    }
  }
  impl.configurator.initConfigurator(packages, components, folder);
  for (ConfigurationSpec& c : lua_configurations) impl.configurator.deploymentSet().addConfiguration(std::move(c));
  return 0;
}

template <void (Configurator::*Call)(const std::vector<NameEntry>&)>
int nameListImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  (impl.configurator.*Call)(readNames(L, 1, site, "the list of component names"));
  return 0;
}

int addPeersImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  impl.configurator.addPeers(readPeers(L, 1, site));
  return 0;
}

int setActivitiesImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  impl.configurator.setActivities(readActivities(L, 1, site));
  return 0;
}

int setExecutorImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  const SourceLocation where = site.here();
  requireTable(L, 1, where, "setExecutor's table { period = s, priority = 1..99, ... }");
  static const char* const kKeys[] = {"period", "priority", "scheduler", "cpu", "lock_memory", "on_deadline_miss",
                                      "safe_stop_after"};
  requireKnownFields(L, 1, kKeys, where, "setExecutor: ",
                     "period, priority, scheduler, cpu, lock_memory, on_deadline_miss or safe_stop_after");
  ExecutorSpec spec;
  spec.where = where;
  spec.declared = true;
  spec.period = numberField(L, 1, "period", where, 0.0);
  const auto integer = [&](const char* key, double fallback) {
    const double value = numberField(L, 1, key, where, fallback);
    if (value != static_cast<double>(static_cast<int>(value)))
      fail(where, std::string("setExecutor: field '") + key + "' must be an integer, got " + std::to_string(value));
    return static_cast<int>(value);
  };
  spec.priority = integer("priority", spec.priority);
  spec.cpu = integer("cpu", spec.cpu);
  spec.safe_stop_after = integer("safe_stop_after", spec.safe_stop_after);
  if (const std::string s = stringField(L, 1, "scheduler", where, false); !s.empty()) spec.scheduler = s;
  if (const std::string s = stringField(L, 1, "on_deadline_miss", where, false); !s.empty()) spec.on_deadline_miss = s;
  rawField(L, 1, "lock_memory");
  if (lua_type(L, -1) == LUA_TBOOLEAN) spec.lock_memory = lua_toboolean(L, -1) != 0;
  else if (!lua_isnil(L, -1)) fail(where, "setExecutor: field 'lock_memory' must be true or false");
  lua_pop(L, 1);
  impl.configurator.setExecutor(std::move(spec));
  return 0;
}

int connectPortsImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  return pushWarnings(L, impl.configurator.connectPorts(readConnections(L, 1, site)));
}

int getReferencesImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  // A remote component's shadow takes what the files set on it (and ignores it): the same files
  // run on every host.
  for (core::Component* shadow : impl.configurator.remoteComponents().components())
    script::exposeComponent(impl.lua, *shadow);
  script::getReferences(impl.lua, impl.configurator.getReferences());
  // script::getReferences defines a Lua getReferences of its own registry; keep this one.
  lua_pushlightuserdata(L, &impl);
  lua_pushcclosure(L, guarded<getReferencesImpl>, 1);
  lua_setglobal(L, "getReferences");
  return 0;
}

int defineDeploymentImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  if (lua_type(L, 1) != LUA_TSTRING) fail(site.here(), "defineDeployment(name, table): name must be a string");
  requireTable(L, 2, site.here(), "the deployment");
  DeploymentSpec spec;
  spec.name = lua_tostring(L, 1);
  spec.where = site.here();
  rawField(L, 2, "scope");
  if (lua_type(L, -1) == LUA_TSTRING) spec.scope = lua_tostring(L, -1);
  else if (!lua_isnil(L, -1)) fail(site.here(), "defineDeployment: scope must be a string (one switch group per robot)");
  lua_pop(L, 1);
  for (const char* key : {"components", "activities", "connections"}) {
    rawField(L, 2, key);
    const int list = lua_gettop(L);
    if (!lua_isnil(L, list)) {
      if (std::strcmp(key, "components") == 0) spec.components = readNames(L, list, site, "components");
      else if (std::strcmp(key, "activities") == 0) spec.activities = readActivities(L, list, site);
      else spec.connections = readConnections(L, list, site);
    }
    lua_settop(L, list - 1);
  }
  impl.configurator.deploymentSet().addDeployment(std::move(spec));
  return 0;
}

int defineConfigurationImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  CallSite site(L, impl);
  if (lua_type(L, 1) != LUA_TSTRING) fail(site.here(), "defineConfiguration(name, table): name must be a string");
  requireTable(L, 2, site.here(), "the configuration { Component = { property = value } }");
  impl.configurator.deploymentSet().addConfiguration(
      detail::configurationFromTable(L, 2, lua_tostring(L, 1), site.here(), site.lines()));
  return 0;
}

int applyDeploymentImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  if (lua_type(L, 1) != LUA_TSTRING) throw core::Error("applyDeployment(name): name must be a string");
  return pushWarnings(L, impl.configurator.applyDeployment(lua_tostring(L, 1)));
}

int applyConfigurationImpl(lua_State* L) {
  LuaDeployer::Impl& impl = implOf(L);
  if (lua_type(L, 1) != LUA_TSTRING) throw core::Error("applyConfiguration(name): name must be a string");
  impl.configurator.applyConfiguration(lua_tostring(L, 1));
  return 0;
}

constexpr const char* kRttShims = R"(
rtt = rtt or {}
rtt.globals = rtt.globals or {}
rtt.globals.ORO_SCHED_RT = "ORO_SCHED_RT"
rtt.globals.ORO_SCHED_OTHER = "ORO_SCHED_OTHER"
function rtt.Variable(type_name)
  if type_name ~= "ConnPolicy" then
    error("rtt.Variable: only \"ConnPolicy\" is supported, got " .. tostring(type_name), 2)
  end
  return { type = "data", size = 1 }
end
)";

}  // namespace

LuaDeployer::LuaDeployer(Configurator& configurator, script::LuaState& lua)
    : configurator_(configurator), lua_(lua), impl_(std::make_unique<Impl>(Impl{configurator, lua, {}, {}})) {
  lua_State* L = lua.get();
  const std::pair<const char*, lua_CFunction> functions[] = {
      {"initConfigurator", guarded<initConfiguratorImpl>},
      {"configureComponents", guarded<nameListImpl<&Configurator::configureComponents>>},
      {"startComponents", guarded<nameListImpl<&Configurator::startComponents>>},
      {"stopComponents", guarded<nameListImpl<&Configurator::stopComponents>>},
      {"cleanupComponents", guarded<nameListImpl<&Configurator::cleanupComponents>>},
      {"addPeers", guarded<addPeersImpl>},
      {"setActivities", guarded<setActivitiesImpl>},
      {"setExecutor", guarded<setExecutorImpl>},
      {"connectPorts", guarded<connectPortsImpl>},
      {"getReferences", guarded<getReferencesImpl>},
      {"defineDeployment", guarded<defineDeploymentImpl>},
      {"defineConfiguration", guarded<defineConfigurationImpl>},
      {"applyDeployment", guarded<applyDeploymentImpl>},
      {"applyConfiguration", guarded<applyConfigurationImpl>},
  };
  for (const auto& [name, function] : functions) {
    lua_pushlightuserdata(L, impl_.get());
    lua_pushcclosure(L, function, 1);
    lua_setglobal(L, name);
  }
  lua.run(kRttShims, "=rtt shims");
  // One host of an application split over hosts: the files see which (placement.hpp).
  if (!configurator.host().empty()) {
    lua_pushstring(L, configurator.host().c_str());
    lua_setglobal(L, "host");
  }
  if (const auto data = dataDirectory(); !data.empty()) {
    lua_pushstring(L, ((data / "charts").string() + "/").c_str());
    lua_setglobal(L, "COBRA_CHARTS");
  }
}

LuaDeployer::~LuaDeployer() = default;

void LuaDeployer::runFile(const std::string& path) {
  if (impl_->entry.empty()) impl_->entry = path;
  lua_.runFile(path);
}

void LuaDeployer::run(const std::string& code, const std::string& chunk_name) {
  std::vector<std::string> lines;
  std::string line;
  for (char c : code) {
    if (c == '\n') lines.push_back(std::exchange(line, {}));
    else line += c;
  }
  lines.push_back(line);
  impl_->sources.insert_or_assign(chunk_name, detail::SourceLines(std::move(lines)));
  lua_.run(code, "=" + chunk_name);
}

}  // namespace cobra::deploy
