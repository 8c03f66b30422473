#include "cobra/components/coordination/supervisor.hpp"

#include <lua.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/install_layout.hpp"
#include "cobra/script/bindings.hpp"

namespace cobra::components {
namespace {

/// Prints and counts the chart's failing callbacks, and keeps the first of each update (its
/// text in a fixed buffer: nothing allocated here beyond what printing does).
class ChartErrors : public statechart::Observer {
 public:
  ChartErrors(std::string owner, core::Property<int>& count) : owner_(std::move(owner)), count_(&count) {}
  void callbackFailed(std::string_view callback, std::string_view element, std::string_view what) override {
    std::fprintf(stderr, "[cobra] supervisor '%s': %.*s of %.*s failed: %.*s\n", owner_.c_str(),
                 static_cast<int>(callback.size()), callback.data(), static_cast<int>(element.size()), element.data(),
                 static_cast<int>(what.size()), what.data());
    count_->setFromOwner((*count_)() + 1);
    if (failed_) return;
    failed_ = true;
    std::snprintf(first_, sizeof first_, "%.*s of %.*s failed: %.*s", static_cast<int>(callback.size()),
                  callback.data(), static_cast<int>(element.size()), element.data(), static_cast<int>(what.size()),
                  what.data());
  }
  bool failed() const noexcept { return failed_; }
  const char* first() const noexcept { return first_; }
  void clear() noexcept { failed_ = false; }

 private:
  std::string owner_;
  core::Property<int>* count_;
  bool failed_ = false;
  char first_[2048] = {};
};

std::chrono::nanoseconds seconds(double s) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s));
}

}  // namespace

/// The chart's Lua functions. Each takes only string arguments and calls noexcept C++: no C++
/// object with a destructor is alive when luaL_error longjmps.
struct SupervisorLua {
  static Supervisor& self(lua_State* L) { return *static_cast<Supervisor*>(lua_touserdata(L, lua_upvalueindex(1))); }
  static std::string_view name(lua_State* L, const char* function) {
    if (lua_type(L, 1) != LUA_TSTRING) luaL_error(L, "%s(name): name must be a string", function);
    std::size_t length = 0;
    const char* text = lua_tolstring(L, 1, &length);
    return {text, length};
  }
  static int emit(lua_State* L) {
    self(L).emitChartEvent(name(L, "emit"));
    return 0;
  }
  static int raise(lua_State* L) {
    const std::string_view event = name(L, "raise");
    if (self(L).machine_->raise(event) != statechart::RaiseStatus::Queued)
      return luaL_error(L, "raise('%s'): the chart's event queue is full or the name too long", event.data());
    return 0;
  }
  template <deploy::SwitchRequest::Kind Kind>
  static int request(lua_State* L) {
    const std::string_view target =
        name(L, Kind == deploy::SwitchRequest::Kind::Deployment ? "applyDeployment" : "applyConfiguration");
    lua_pushboolean(L, self(L).requestSwitch(Kind, target));
    return 1;
  }
  /// Defines the functions above as globals (protected: it allocates).
  static int install(lua_State* L) {
    void* supervisor = lua_touserdata(L, 1);
    const luaL_Reg functions[] = {{"emit", emit},
                                  {"raise", raise},
                                  {"applyDeployment", request<deploy::SwitchRequest::Kind::Deployment>},
                                  {"applyConfiguration", request<deploy::SwitchRequest::Kind::Configuration>}};
    for (const luaL_Reg& f : functions) {
      lua_pushlightuserdata(L, supervisor);
      lua_pushcclosure(L, f.func, 1);
      lua_setglobal(L, f.name);
    }
    return 0;
  }
};

Supervisor::Supervisor(std::string name)
    : Component(std::move(name), core::Role::Supervision,
                "Supervisor (thesis §4.5.10): runs an rFSM chart on its events, emits events, calls peers, switches "
                "deployments and configurations") {
  addProperty(fsm_path_);
  addProperty(pool_size_.range(0, 1 << 30));
  addProperty(max_steps_.range(1, 1000000));
  addProperty(chart_errors_.readOnly());
  addProperty(budget_.range(0.0, 3600.0));
  addProperty(load_budget_.range(0.0, 3600.0));
  addEventPort(input_events_);
  addPort(output_events_);
  addPort(task_state_);
  answers_.connectTo(input_events_, core::ConnPolicy::buffer(2 * kQueueCapacity));
}

Supervisor::~Supervisor() {
  if (chart_) chart_->bind(nullptr);
}

std::string_view Supervisor::activeState() const { return machine_ ? machine_->activeLeaf() : std::string_view(); }

const statechart::Chart* Supervisor::chart() const noexcept { return machine_ ? &machine_->chart() : nullptr; }

bool Supervisor::configureHook() {
  cleanupHook();
  if (fsm_path_().empty()) return refuse("set fsm_path to the chart file (an rFSM file: return rfsm.state{ ... })");
  try {
    script::LuaMemory memory;
    memory.pool_bytes = static_cast<std::size_t>(pool_size_());
    memory.owner = "component '" + name() + "'";
    memory.hint = "raise its lua_pool_size property";
    lua_ = std::make_unique<script::LuaState>(std::move(memory));
    lua_->setBudget(seconds(load_budget_()), "raise its lua_load_budget property");
    lua_->startStep();
    lua_State* L = lua_->get();
    lua_pushcfunction(L, SupervisorLua::install);
    lua_pushlightuserdata(L, this);
    lua_->call(1, 0, "component '" + name() + "'");
    // Helpers next to the chart can be required (the switch supervisors' charts do), then cobra's
    // own chart parts (its data folder's charts/: task_steps.lua, the steps of a task chart).
    std::string folder = std::filesystem::path(fsm_path_()).parent_path().string();
    if (folder.empty()) folder = ".";
    const auto quoted = [](const std::string& text) {  // as a Lua string literal's contents
      std::string out;
      for (char c : text) out += (c == '\\' || c == '\'') ? std::string("\\") + c : std::string(1, c);
      return out;
    };
    std::string path = quoted(folder) + "/?.lua;";
    if (const auto data = deploy::dataDirectory(); !data.empty()) path += quoted((data / "charts").string()) + "/?.lua;";
    lua_->run("package.path = '" + path + "' .. package.path", "=supervisor setup");
    script::exposeComponent(*lua_, *this, "self");
    if (deploy::Configurator* configurator = this->configurator()) {
      for (const std::string& peer : configurator->peersOf(name()))
        if (core::Component* c = configurator->getReferences().find(peer)) script::exposeComponent(*lua_, *c);
    }
    chart_ = script::RfsmChart::loadFile(*lua_, fsm_path_());
  } catch (const std::exception& e) {
    cleanupHook();
    return refuse(std::string("chart ") + fsm_path_() + ": " + e.what());
  }
  lua_->setBudget(seconds(budget_()), "raise its lua_budget property if the chart needs that long");
  machine_ = std::make_unique<statechart::Machine>(chart_->chart(), [this] { return now(); }, 64);
  observer_ = std::make_unique<ChartErrors>(name(), chart_errors_);
  machine_->setObserver(observer_.get());
  chart_->bind(machine_.get());
  chart_errors_.setFromOwner(0);
  return true;
}

bool Supervisor::startHook() {
  machine_->reset();
  published_ = nullptr;
  runChart();  // enters the chart: its entry functions run now
  publishState();
  return true;
}

void Supervisor::runChart() {
  auto& errors = static_cast<ChartErrors&>(*observer_);
  errors.clear();
  lua_->startStep();
  for (int i = 0; i < max_steps_(); ++i) {
    const statechart::StepResult r = machine_->step();
    if (errors.failed()) {
      publishState();
      // Real-time code returns status; here the failure must reach core, which turns a throwing
      // hook into Exception (and e_exception): this is the boundary where it is converted.
      throw core::Error(errors.first());
    }
    if (r == statechart::StepResult::Idle || r == statechart::StepResult::CannotEnter) return;
  }
}

void Supervisor::exceptionHook() {
  if (!lua_ || !machine_) return;
  lua_->startStep();
  try {
    lua_->run("if type(exceptionHook) == 'function' then exceptionHook() end", "=" + name() + " exceptionHook");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "[cobra] supervisor '%s': %s\n", name().c_str(), e.what());
  }
}

void Supervisor::cleanupHook() {
  if (chart_) chart_->bind(nullptr);
  machine_.reset();
  observer_.reset();
  chart_.reset();
  lua_.reset();
  published_ = nullptr;
}

void Supervisor::raiseJoined(std::string_view a, std::string_view b) noexcept {
  char text[statechart::Machine::kMaxEventName];
  if (a.size() + (b.empty() ? 0 : 1 + b.size()) > sizeof text) return;
  std::memcpy(text, a.data(), a.size());
  std::size_t length = a.size();
  if (!b.empty()) {
    text[length++] = '@';
    std::memcpy(text + length, b.data(), b.size());
    length += b.size();
  }
  (void)machine_->raise(std::string_view(text, length));
}

void Supervisor::updateHook() {
  if (!machine_) return;
  core::Event event;
  while (input_events_.readNew(event) == core::FlowStatus::NewData) {
    raiseJoined(event.name, {});
    if (!event.source.empty() && event.name.view().find('@') == std::string_view::npos) raiseJoined(event.name, event.source);
  }
  runChart();
  publishState();
}

void Supervisor::publishState() noexcept {
  const std::string_view leaf = machine_->activeLeaf();
  if (leaf.data() == published_) return;  // fqns are stored once in the chart: same pointer, same state
  published_ = leaf.data();
  core::TaskState state;
  state.path = leaf;
  task_state_.write(state);
}

void Supervisor::emitChartEvent(std::string_view name) noexcept {
  core::Event event;
  event.name = name;
  event.source.assign(this->name());
  event.stamp = now();
  output_events_.write(event);
}

void Supervisor::onRequestDone(const deploy::SwitchRequest& request, bool ok, std::string_view message) {
  (void)message;  // the Configurator keeps it in its warnings
  const bool deployment = request.kind == deploy::SwitchRequest::Kind::Deployment;
  if (ok && !deployment) last_configuration_ = request.name;
  std::string name = std::string(deployment ? "e_deployment_" : "e_configuration_") + (ok ? "done@" : "failed@") +
                     request.name.str();
  core::Event answer;
  answer.name.assign(name);
  answer.source = "configurator";
  answer.stamp = now();
  answers_.write(answer);
}

}  // namespace cobra::components
