// The editor's routes (studio/PROTOCOL.md "The editor (v1)"): palette, project, open, check,
// validate, save, generate, running.

#include "cobra/studio/editor.hpp"

#include <fstream>
#include <future>
#include <sstream>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/studio/component_generator.hpp"
#include "cobra/studio/json.hpp"
#include "editor_internal.hpp"

namespace cobra::studio {

using editor::Refusal;

namespace {

/// cobra's built-in packages and the options' own.
void addPackages(deploy::PackageRegistry& packages, const EditorOptions& options) {
  components::addBuiltinPackages(packages);
  for (const auto& [name, registrar] : options.packages) packages.addBuiltin(name, registrar);
}

std::string errorJson(const std::string& message) { return json::errorBody(message); }

std::string readText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The line of "FILE:LINE: ..." when `message` starts with `file` (or names it first), else 0.
int lineIn(const std::string& message, const std::string& file) {
  const auto at = message.find(file + ":");
  if (at == std::string::npos) return 0;
  std::size_t i = at + file.size() + 1;
  int line = 0;
  while (i < message.size() && std::isdigit(static_cast<unsigned char>(message[i]))) line = line * 10 + (message[i++] - '0');
  return i < message.size() && message[i] == ':' ? line : 0;
}

const json::Json& required(const json::Json& body, const char* key, const char* route) {
  const json::Json* v = body.is_object() ? json::find(body, key) : nullptr;
  if (v == nullptr) throw Refusal(400, std::string("POST /api/editor/") + route + ": the body has no '" + key + "'");
  return *v;
}

std::string requiredText(const json::Json& body, const char* key, const char* route) {
  const json::Json& v = required(body, key, route);
  if (!v.is_string() || v.get<std::string>().empty())
    throw Refusal(400, std::string("POST /api/editor/") + route + ": '" + key + "' must be a non-empty string, got " + json::describe(v));
  return v.get<std::string>();
}

std::vector<InterfaceItem> interfaceItems(const json::Json& component, const char* key) {
  std::vector<InterfaceItem> items;
  const json::Json* list = json::find(component, key);
  if (list == nullptr || list->is_null()) return items;
  if (!list->is_array()) throw Refusal(400, std::string("component.") + key + " must be an array, got " + json::describe(*list));
  for (const json::Json& item : *list) {
    const json::Json* name = json::find(item, "name");
    const json::Json* type = json::find(item, "type");
    const json::Json* unit = json::find(item, "unit");
    if (name == nullptr || type == nullptr || !name->is_string() || !type->is_string())
      throw Refusal(400, std::string("component.") + key + ": each item needs a \"name\" and a \"type\" (strings)");
    const std::string unit_text = unit != nullptr && unit->is_string() ? unit->get<std::string>() : "";
    try {
      items.push_back(parseInterfaceItem(name->get<std::string>() + ":" + type->get<std::string>() + (unit_text.empty() ? "" : ":" + unit_text),
                                         std::string("component.") + key));
    } catch (const std::runtime_error& e) {
      throw Refusal(400, e.what());
    }
  }
  return items;
}

}  // namespace

struct Editor::Impl {
  EditorOptions options;
  std::shared_future<std::shared_ptr<const editor::Palette>> palette_future;
  std::mutex mutex;  // one request at a time
  const RunningDeployment* running = nullptr;

  /// What was opened last (or saved last): the file the editor may write over.
  struct Opened {
    std::filesystem::path path;  // absolute; empty: nothing opened
    std::string text;            // the file's text when opened (or saved)
    std::filesystem::file_time_type mtime{};
    std::string error;  // "" when it loaded
    int line = 0;
    std::string project;  // Project JSON when it loaded
  } opened;

  const editor::Palette& palette() { return *palette_future.get(); }

  EditorAnswer projectAnswer() const {
    if (opened.path.empty())
      return {200, "{\"path\":\"\",\"text\":\"\",\"project\":" +
                       editor::projectJson(deploy::DeploymentDescription{}, {}) + "}"};
    if (!opened.error.empty())
      return {422, "{\"error\":" + json::quoted(opened.error) + ",\"path\":" + json::quoted(opened.path.string()) +
                       ",\"line\":" + std::to_string(opened.line) + ",\"text\":" + json::quoted(opened.text) + "}"};
    return {200, "{\"path\":" + json::quoted(opened.path.string()) + ",\"text\":" + json::quoted(opened.text) +
                     ",\"project\":" + opened.project + "}"};
  }

  std::string open(const std::string& path) {
    Opened next;
    std::filesystem::path file;
    try {
      file = run::entryFile(path);
    } catch (const std::exception& e) {
      next.path = std::filesystem::absolute(path);
      next.error = e.what();
      opened = std::move(next);
      return opened.error;
    }
    std::error_code ignored;
    next.path = std::filesystem::weakly_canonical(file, ignored);
    next.text = readText(next.path);
    next.mtime = std::filesystem::last_write_time(next.path, ignored);
    try {
      deploy::ConfiguratorOptions configurator_options;  // simulation: the clock never advances here
      configurator_options.package_path = options.package_path;
      deploy::Configurator configurator(configurator_options);
      addPackages(configurator.packages(), options);
      script::LuaState lua;
      deploy::LuaDeployer deployer(configurator, lua);
      deployer.runFile(next.path.string());
      const editor::Layout layout = editor::parseLayout(readText(next.path.string() + ".layout.json"));
      next.project = editor::projectJson(deploy::describe(configurator), layout);
    } catch (const std::exception& e) {
      next.error = e.what();
      next.line = lineIn(next.error, next.path.string());
      if (next.line == 0) next.line = lineIn(next.error, file.string());
    }
    opened = std::move(next);
    return opened.error;
  }

  EditorAnswer save(const json::Json& body) {
    const std::filesystem::path target = std::filesystem::absolute(requiredText(body, "path", "save"));
    editor::Layout layout;
    const deploy::DeploymentDescription d =
        deploy::canonical(editor::fromProjectJson(required(body, "project", "save"), palette(), layout));
    std::string text;
    try {
      text = deploy::toLua(d);
    } catch (const std::exception& e) {
      throw Refusal(422, e.what());
    }
    std::error_code ignored;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(target, ignored);
    if (std::filesystem::exists(target)) {
      if (canonical != opened.path)
        throw Refusal(409, target.string() + " exists and is not the file opened in the editor; not overwritten "
                                             "(open it first, or save under another name)");
      if (!opened.error.empty())
        throw Refusal(409, target.string() + " did not load when it was opened (" + opened.error +
                               "); not overwritten: mend it by hand, or save under another name");
      if (readText(target) != opened.text || std::filesystem::last_write_time(target, ignored) != opened.mtime)
        throw Refusal(409, target.string() + " changed on disk since it was opened; not overwritten "
                                             "(open it again, or save under another name)");
    }
    const std::string layout_path = target.string() + ".layout.json";
    {
      std::ofstream out(target, std::ios::binary);
      if (!(out << text)) throw Refusal(422, "cannot write " + target.string());
    }
    std::ofstream(layout_path, std::ios::binary) << editor::layoutJson(layout);
    opened = Opened{std::filesystem::weakly_canonical(target, ignored), text, std::filesystem::last_write_time(target, ignored),
                    "", 0, editor::projectJson(d, layout)};
    return {200, "{\"path\":" + json::quoted(target.string()) + ",\"text\":" + json::quoted(text) + "}"};
  }

  EditorAnswer generate(const json::Json& body) {
    const std::string folder = requiredText(body, "folder", "generate");
    const json::Json& component = required(body, "component", "generate");
    if (!component.is_object()) throw Refusal(400, "POST /api/editor/generate: 'component' must be an object");
    ComponentTemplate t;
    for (auto [key, field] : {std::pair{"name", &t.name}, std::pair{"role", &t.role}, std::pair{"package", &t.package}}) {
      const json::Json* v = json::find(component, key);
      if (v == nullptr || !v->is_string()) throw Refusal(400, std::string("component.") + key + " must be a string");
      *field = v->get<std::string>();
    }
    if (const json::Json* doc = json::find(component, "doc"); doc != nullptr && doc->is_string()) t.doc = doc->get<std::string>();
    t.inputs = interfaceItems(component, "inputs");
    t.event_inputs = interfaceItems(component, "event_inputs");
    t.outputs = interfaceItems(component, "outputs");
    t.properties = interfaceItems(component, "properties");
    std::vector<std::filesystem::path> files;
    try {
      validate(t);
      files = generateComponent(t, folder);
    } catch (const std::runtime_error& e) {
      throw Refusal(400, e.what());
    }
    std::string out = "{\"files\":[";
    for (std::size_t i = 0; i < files.size(); ++i) out += (i ? "," : "") + json::quoted(files[i].string());
    return {200, out + "]}"};
  }

  EditorAnswer runningAnswer() const {
    if (running == nullptr)
      return {404, errorJson("no run here: GET /api/editor/running is served by `cobra run APP --studio`")};
    bool live = false;
    InForce now;
    const auto d = running->snapshot(live, &now);
    if (!d) return {503, errorJson("the run has not started yet; ask again in a moment")};
    return {200, std::string("{\"live\":") + (live ? "true" : "false") +
                     ",\"taken\":\"components, connections and named deployments and configurations as at the run's "
                     "setup; deployments and configuration in force, running components and property values of now\""
                     ",\"now\":" + editor::inForceJson(now) + ",\"project\":" + editor::projectJson(*d, {}) + "}"};
  }

  EditorAnswer route(std::string_view method, std::string_view name, std::string_view body_text) {
    const auto expect = [&](std::string_view wanted) {
      if (method != wanted && !(wanted == "GET" && method == "HEAD"))
        throw Refusal(405, "use " + std::string(wanted) + " /api/editor/" + std::string(name));
    };
    const auto body = [&] {
      try {
        return json::parse(body_text);
      } catch (const std::runtime_error& e) {
        throw Refusal(400, "POST /api/editor/" + std::string(name) + ": the body is not JSON: " + e.what());
      }
    };
    if (name == "palette") {
      expect("GET");
      return {200, palette().json()};
    }
    if (name == "project") {
      expect("GET");
      return projectAnswer();
    }
    if (name == "open") {
      expect("POST");
      open(requiredText(body(), "path", "open"));
      return projectAnswer();
    }
    if (name == "check") {
      expect("POST");
      const json::Json request = body();
      editor::Layout layout;
      const auto d = editor::fromProjectJson(required(request, "project", "check"), palette(), layout);
      const auto verdict = editor::checkConnection(d, editor::connectionFrom(required(request, "connection", "check"), "connection"),
                                                   palette());
      return {200, std::string("{\"ok\":") + (verdict.reason.empty() ? "true" : "false") +
                       ",\"reason\":" + json::quoted(verdict.reason) + ",\"lint\":" + editor::lintJson(verdict.lint) + "}"};
    }
    if (name == "validate") {
      expect("POST");
      const json::Json request = body();
      editor::Layout layout;
      const auto d = editor::fromProjectJson(required(request, "project", "validate"), palette(), layout);
      std::vector<editor::LintItem> lint;
      const auto problems = editor::validate(d, palette(), lint);
      std::string out = "{\"problems\":[";
      for (std::size_t i = 0; i < problems.size(); ++i)
        out += std::string(i ? "," : "") + "{\"where\":" + json::quoted(problems[i].where) +
               ",\"message\":" + json::quoted(problems[i].message) + "}";
      return {200, out + "],\"lint\":" + editor::lintJson(lint) + "}"};
    }
    if (name == "save") {
      expect("POST");
      return save(body());
    }
    if (name == "generate") {
      expect("POST");
      return generate(body());
    }
    if (name == "running") {
      expect("GET");
      return runningAnswer();
    }
    throw Refusal(404, "no editor route '" + std::string(name) +
                           "'; the routes: GET palette, GET project, POST open, POST check, POST validate, POST save, "
                           "POST generate, GET running");
  }
};

std::string NoRunSource::model(int& status) {
  status = 404;
  return errorJson("no run: cobra edit serves the deployment editor (editor.html) only");
}
std::string NoRunSource::recording() { return "{\"frames\":[]}"; }
bool NoRunSource::latestFrame(std::uint64_t&, std::string&) { return false; }
void NoRunSource::takeMessages(std::vector<std::string>&) {}
InputAnswer NoRunSource::input(const std::string&) { return {409, "no run: cobra edit has no inputs"}; }
std::filesystem::path NoRunSource::mesh(const std::string&) { return {}; }

Editor::Editor(EditorOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  impl_->palette_future = std::async(std::launch::async, [options = impl_->options] {
                            auto packages = std::make_unique<deploy::PackageRegistry>(options.package_path);
                            addPackages(*packages, options);
                            return std::shared_ptr<const editor::Palette>(std::make_shared<editor::Palette>(std::move(packages)));
                          }).share();
}

Editor::~Editor() {
  if (impl_->palette_future.valid()) impl_->palette_future.wait();
}

std::string Editor::open(const std::string& path) {
  const std::lock_guard lock(impl_->mutex);
  return impl_->open(path);
}

void Editor::setRunning(const RunningDeployment* running) {
  const std::lock_guard lock(impl_->mutex);
  impl_->running = running;
}

EditorAnswer Editor::handle(std::string_view method, std::string_view route, std::string_view body) {
  const std::lock_guard lock(impl_->mutex);
  try {
    return impl_->route(method, route, body);
  } catch (const Refusal& r) {
    return {r.status, errorJson(r.what())};
  } catch (const std::exception& e) {
    return {500, errorJson(e.what())};
  }
}

}  // namespace cobra::studio
