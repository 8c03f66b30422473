// The deployment editor's routes (studio/PROTOCOL.md "The editor (v1)"), called as the server
// calls them (Editor::handle) and through the server (token, wiring): good and bad input, the
// error texts, saving with its refusals, the round trip of a saved file through `cobra describe`'s
// writer, generating a component, and the running deployment of a real run.

#include "cobra/studio/editor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cobra/components/builtin_packages.hpp"
#include "cobra/core/record.hpp"
// A package's own type, with a C++ spelling: examples/06_package's example.ForceSample.
#include "../../examples/06_package/src/force_sample.hpp"
#include "cobra/deploy/lua_deployer.hpp"
#include "cobra/studio/json.hpp"
#include "cobra/studio/server.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "http_client.hpp"
#include "cobra/test_support/test_support.hpp"

/// A type without a C++ spelling (as TGL.MultiAxisPath): the generator cannot write its ports.
namespace test_pkg {
struct Opaque {
  double value = 0.0;
};
}  // namespace test_pkg

template <>
struct cobra::core::DataTypeTraits<test_pkg::Opaque> : cobra::core::RecordTraits<test_pkg::Opaque> {
  static constexpr std::string_view name = "test.Opaque";
  static constexpr auto fields = std::tuple{field("value", &test_pkg::Opaque::value, "1", "a value")};
};

namespace cobra::studio {
namespace {

const std::string kSource = COBRA_SOURCE_DIR;

/// A Calculation that reads events: the role linter's example of a broken rule.
class Chatty final : public core::Component {
 public:
  explicit Chatty(std::string name) : Component(std::move(name), core::Role::Calculation, "reads events (a role violation)") {
    addPort(trigger_);
  }

 private:
  core::InputPort<core::Event> trigger_{"trigger", "events it should not read", ""};
};

EditorOptions withChatty() {
  EditorOptions options;
  options.packages.emplace_back("test_roles", [](deploy::PackageBuilder& p) { p.component<Chatty>("Chatty", "test"); });
  // A package that registers data types, as a package's entry point does (in the core registry,
  // which the palette and the generator read; registerType<T> adds Lua, CSV and DDS).
  options.packages.emplace_back("test_types", [](deploy::PackageBuilder&) {
    (void)core::typeInfo<example::ForceSample>();
    (void)core::typeInfo<test_pkg::Opaque>();
  });
  return options;
}

Editor& editor() {
  // One palette for the whole test (it makes every type once), waited for before any test uses
  // it: a test that ended the program while the palette's thread still made components would
  // have the statics that thread made destroyed under it (an occasional crash at exit).
  static Editor& shared = []() -> Editor& {
    static Editor e(withChatty());
    (void)e.handle("GET", "palette", "");
    return e;
  }();
  return shared;
}

json::Json call(Editor& e, const char* method, const char* route, const std::string& body, int expected_status) {
  const EditorAnswer answer = e.handle(method, route, body);
  EXPECT_EQ(answer.status, expected_status) << route << ": " << answer.body;
  return json::parse(answer.body);
}

std::string errorMember(Editor& e, const char* method, const char* route, const std::string& body, int status) {
  const json::Json v = call(e, method, route, body, status);
  return json::stringMember(v, "error").value_or("(no error member)");
}

std::filesystem::path scratch(const std::string& name) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_editor_test");
  std::filesystem::create_directories(folder);
  std::filesystem::remove(folder / name);
  std::filesystem::remove(folder / (name + ".layout.json"));
  return folder / name;
}

std::string readText(const std::filesystem::path& file) {
  std::stringstream text;
  text << std::ifstream(file).rdbuf();
  return text.str();
}

/// A project of two signal components joined by one connection (Project JSON).
const char* kProject = R"({
  "packages": ["cobra_signal", "test_roles"],
  "components": [
    { "name": "Sine", "type": "SineGenerator", "x": 10, "y": 20, "properties": { "frequency": "2.5", "amplitude": "1" },
      "activity": { "period": 0.001, "priority": 0, "scheduler": "other" } },
    { "name": "G", "type": "Gain", "x": 300, "y": 20, "properties": { "k": "3" }, "activity": null },
    { "name": "Det", "type": "ThresholdDetector", "x": 300, "y": 200, "properties": {} },
    { "name": "Chat", "type": "Chatty", "x": 500, "y": 200 }
  ],
  "peers": [ { "component": "Det", "peers": ["G"] } ],
  "connections": [ { "output": "Sine.out", "input": "G.in", "conn_policy": { "type": "buffer", "size": 8 } } ],
  "deployments": [ { "name": "detect", "scope": "", "components": ["Det"],
                     "activities": [ { "component": "Det", "period": 0.01, "priority": 0, "scheduler": "other" } ],
                     "connections": [ { "output": "G.out", "input": "Det.in", "conn_policy": { "type": "data" } } ] } ],
  "configurations": [ { "name": "loud", "values": { "G.k": "10" } } ],
  "configure": ["Sine", "G"], "start": ["Sine", "G"], "apply": ["detect"], "configuration": ""
})";

std::string withConnection(const std::string& output, const std::string& input) {
  return std::string("{\"project\":") + kProject + ",\"connection\":{\"output\":\"" + output + "\",\"input\":\"" + input +
         "\",\"conn_policy\":{\"type\":\"data\"}}}";
}

TEST(Editor, PaletteListsEveryTypeWithItsInterface) {
  const json::Json palette = call(editor(), "GET", "palette", "", 200);
  const json::Json* gain = nullptr;
  for (const json::Json& t : palette.at("types"))
    if (t.at("type").get<std::string>() == "Gain") gain = &t;
  ASSERT_NE(gain, nullptr);
  EXPECT_EQ(gain->at("package").get<std::string>(), "cobra_signal");
  EXPECT_EQ(gain->at("role").get<std::string>(), "Calculation");
  const json::Json& ports = gain->at("ports");
  ASSERT_GE(ports.size(), 2u);
  bool saw_in = false;
  for (const json::Json& p : ports)
    if (p.at("name").get<std::string>() == "in") {
      saw_in = true;
      EXPECT_EQ(p.at("direction").get<std::string>(), "in");
      EXPECT_EQ(p.at("type").get<std::string>(), "double");
      EXPECT_TRUE(p.at("event").get<bool>());  // its data triggers an update
      EXPECT_EQ(p.at("unit").get<std::string>(), "1");
    }
  EXPECT_TRUE(saw_in);
  const json::Json& k = gain->at("properties").at(0);
  EXPECT_EQ(k.at("name").get<std::string>(), "k");
  EXPECT_EQ(k.at("default").get<std::string>(), "1");
  EXPECT_TRUE(k.at("range").is_null());
  EXPECT_FALSE(k.at("read_only").get<bool>());
  // Every package's types: the puncturing task's too.
  std::set<std::string> types;
  for (const json::Json& t : palette.at("types")) types.insert(t.at("type").get<std::string>());
  for (const char* type : {"VariableAdmittance", "Supervisor", "MotionPlanner", "Reporter", "Chatty"})
    EXPECT_EQ(types.count(type), 1u) << type;
}

TEST(Editor, ChecksAConnectionAsTheConfiguratorWouldAndLintsIt) {
  json::Json v = call(editor(), "POST", "check", withConnection("G.out", "Det.in"), 200);
  EXPECT_TRUE(v.at("ok").get<bool>());
  EXPECT_TRUE(v.at("lint").empty());
  v = call(editor(), "POST", "check", withConnection("Det.events", "G.in"), 200);
  EXPECT_FALSE(v.at("ok").get<bool>());
  EXPECT_EQ(v.at("reason").get<std::string>(), "types differ: 'Det.events' writes Event, 'G.in' reads double");
  v = call(editor(), "POST", "check", withConnection("G.in", "Det.in"), 200);
  EXPECT_EQ(v.at("reason").get<std::string>(), "'G.in' is an input port; a connection starts at an output port");
  v = call(editor(), "POST", "check", withConnection("G.outt", "Det.in"), 200);
  EXPECT_EQ(v.at("reason").get<std::string>().rfind("component 'G' (Gain) has no port 'outt'; did you mean 'out'?", 0), 0u)
      << v.at("reason").get<std::string>();
  v = call(editor(), "POST", "check", withConnection("Gg.out", "Det.in"), 200);
  EXPECT_EQ(v.at("reason").get<std::string>().rfind("no component 'Gg' in the project; did you mean 'G'?", 0), 0u)
      << v.at("reason").get<std::string>();
  v = call(editor(), "POST", "check", withConnection("Det.events", "Chat.trigger"), 200);
  EXPECT_TRUE(v.at("ok").get<bool>());
  ASSERT_EQ(v.at("lint").size(), 1u);
  EXPECT_EQ(v.at("lint")[0].at("rule").get<std::string>(), "a Calculation component may read only pure data");
  EXPECT_NE(v.at("lint")[0].at("message").get<std::string>().find("Det.events (Decision) -> Chat.trigger (Calculation)"),
            std::string::npos);
}

TEST(Editor, ValidatesPropertiesActivitiesPeersAndConnections) {
  json::Json v = call(editor(), "POST", "validate", std::string("{\"project\":") + kProject + "}", 200);
  EXPECT_TRUE(v.at("problems").empty()) << v.at("problems")[0].at("message").get<std::string>();
  std::string bad = kProject;
  bad.replace(bad.find("\"k\": \"3\""), 8, "\"k\": \"fast\", \"kk\": \"1\"");
  bad.replace(bad.find("\"scheduler\": \"other\""), 20, "\"scheduler\": \"rt\"");
  bad.replace(bad.find("\"peers\": [\"G\"]"), 14, "\"peers\": [\"Gx\"]");
  v = call(editor(), "POST", "validate", "{\"project\":" + bad + "}", 200);
  std::map<std::string, std::string> problems;
  for (const json::Json& p : v.at("problems")) problems[p.at("where").get<std::string>()] = p.at("message").get<std::string>();
  ASSERT_EQ(problems.count("component 'G' property 'k'"), 1u);
  EXPECT_NE(problems["component 'G' property 'k'"].find("\"fast\""), std::string::npos) << problems["component 'G' property 'k'"];
  EXPECT_EQ(problems["component 'G' property 'kk'"].rfind("component 'G' (Gain) has no property 'kk'; did you mean 'k'?", 0), 0u);
  EXPECT_EQ(problems["activity of 'Sine'"].rfind("unknown scheduler 'rt'", 0), 0u) << problems["activity of 'Sine'"];
  EXPECT_EQ(problems["peers of 'Det'"].rfind("no component 'Gx' in the project; did you mean 'G'?", 0), 0u);
  EXPECT_EQ(errorMember(editor(), "POST", "validate", "{\"project\": {\"components\": [ { \"name\": \"A\" } ] } }", 422),
            "component 'A': 'type' must be a string, got null");
}

TEST(Editor, SavesWhatDescribeWritesWithItsLayoutAndRefusesToOverwrite) {
  Editor e(withChatty());
  const auto file = scratch("saved.lua");
  json::Json saved = call(e, "POST", "save", "{\"path\":" + json::quoted(file.string()) + ",\"project\":" + kProject + "}", 200);
  const std::string text = saved.at("text").get<std::string>();
  EXPECT_EQ(readText(file), text);
  EXPECT_NE(text.find("Sine.frequency = 2.5\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("Sine.amplitude"), std::string::npos) << "the default value is not written";
  EXPECT_NE(text.find("defineDeployment(\"detect\""), std::string::npos);
  EXPECT_NE(text.find("defineConfiguration(\"loud\", {\n  G = { k = \"10\" },\n})"), std::string::npos) << text;
  EXPECT_NE(readText(file.string() + ".layout.json").find("\"Sine\":{\"x\":10,\"y\":20}"), std::string::npos);
  {
    // Describing the saved file gives the same text (the writer `cobra describe` uses).
    deploy::Configurator configurator;
    components::addBuiltinPackages(configurator.packages());
    configurator.packages().addBuiltin("test_roles", [](deploy::PackageBuilder& p) { p.component<Chatty>("Chatty", "test"); });
    script::LuaState lua;
    deploy::LuaDeployer deployer(configurator, lua);
    deployer.runFile(file.string());
    EXPECT_EQ(deploy::toLua(deploy::describe(configurator)), text);
  }
  // Opened again: the same project, the blocks where they were.
  json::Json opened = call(e, "POST", "open", "{\"path\":" + json::quoted(file.string()) + "}", 200);
  const json::Json& sine = opened.at("project").at("components").at(0);
  EXPECT_EQ(sine.at("name").get<std::string>(), "Sine");
  EXPECT_EQ(sine.at("x").get<double>(), 10.0);
  EXPECT_EQ(opened.at("project").at("apply").at(0).get<std::string>(), "detect");
  // Saved again after the file changed on disk: refused, naming it.
  call(e, "POST", "save", "{\"path\":" + json::quoted(file.string()) + ",\"project\":" + kProject + "}", 200);
  std::ofstream(file, std::ios::app) << "-- edited by hand\n";
  EXPECT_EQ(errorMember(e, "POST", "save", "{\"path\":" + json::quoted(file.string()) + ",\"project\":" + kProject + "}", 409),
            file.string() + " changed on disk since it was opened; not overwritten (open it again, or save under another name)");
  EXPECT_NE(readText(file).find("-- edited by hand"), std::string::npos);
  // Another existing file is not written over either.
  const auto other = scratch("other.lua");
  std::ofstream(other) << "-- mine\n";
  EXPECT_EQ(errorMember(e, "POST", "save", "{\"path\":" + json::quoted(other.string()) + ",\"project\":" + kProject + "}", 409),
            other.string() + " exists and is not the file opened in the editor; not overwritten (open it first, or save "
                             "under another name)");
}

TEST(Editor, AFileThatDoesNotLoadOpensWithItsLineAndIsNeverSavedOver) {
  Editor e(withChatty());
  const auto file = scratch("broken.lua");
  std::ofstream(file) << "packages_list = { \"cobra_signal\" }\n"
                         "components_list = {\n"
                         "  { peer_name = \"G\", component_type = \"Gian\" },\n"
                         "}\n"
                         "initConfigurator(packages_list, components_list)\n";
  const std::string before = readText(file);
  EXPECT_EQ(e.open(file.string()).rfind(file.string() + ":3: unknown component type 'Gian'; did you mean 'Gain'? known types: " +
                                            "Constant, Gain, Recorder, SineGenerator, ThresholdDetector (loaded packages: cobra_signal",
                                        0),
            0u);
  const json::Json v = call(e, "GET", "project", "", 422);
  EXPECT_EQ(v.at("line").get<double>(), 3.0);
  EXPECT_EQ(v.at("path").get<std::string>(), std::filesystem::weakly_canonical(file).string());
  EXPECT_EQ(v.at("text").get<std::string>(), before);
  EXPECT_EQ(v.at("error").get<std::string>().rfind(file.string() + ":3: unknown component type 'Gian'", 0), 0u);
  const std::string message = errorMember(e, "POST", "save", "{\"path\":" + json::quoted(file.string()) + ",\"project\":" + kProject + "}", 409);
  EXPECT_EQ(message.rfind(file.string() + " did not load when it was opened (" + file.string() + ":3: unknown component", 0), 0u)
      << message;
  EXPECT_EQ(readText(file), before);
}

TEST(Editor, OpensAnApplicationFolderWithItsDeployments) {
  Editor e(withChatty());
  const json::Json v = call(e, "POST", "open", "{\"path\":" + json::quoted(kSource + "/apps/puncturing") + "}", 200);
  EXPECT_EQ(v.at("path").get<std::string>(), std::filesystem::weakly_canonical(kSource + "/apps/puncturing/puncturing.lua").string());
  std::set<std::string> deployments;
  for (const json::Json& d : v.at("project").at("deployments")) deployments.insert(d.at("name").get<std::string>());
  EXPECT_EQ(deployments.count("needle_autonomous_planning"), 1u);
  EXPECT_EQ(deployments.count("probe_autonomous_planning"), 1u);
  EXPECT_GT(v.at("project").at("components").size(), 20u);
  const std::string no_entry = errorMember(e, "POST", "open", "{\"path\":" + json::quoted(kSource + "/run/test/apps") + "}", 422);
  EXPECT_NE(no_entry.find("run/test/apps: no entry file"), std::string::npos) << no_entry;
}

TEST(Editor, GeneratesAComponentAndRefusesWhatCobraNewRefuses) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_editor_test") / "generated_pkg";
  std::filesystem::remove_all(folder);
  const std::string request = "{\"folder\":" + json::quoted(folder.string()) + R"(,"component":{"name":"ForceFilter",
    "role":"calculation","package":"my_filters","doc":"low-pass filter of a wrench",
    "inputs":[{"name":"wrench","type":"Wrench","unit":"N"}],"event_inputs":[],
    "outputs":[{"name":"filtered","type":"Wrench"}],"properties":[{"name":"cutoff","type":"double","unit":"Hz"}]}})";
  const json::Json v = call(editor(), "POST", "generate", request, 200);
  std::vector<std::string> files;
  for (const json::Json& f : v.at("files")) files.push_back(f.get<std::string>());
  ASSERT_FALSE(files.empty());
  for (const std::string& f : files) EXPECT_TRUE(std::filesystem::is_regular_file(f)) << f;
  EXPECT_NE(readText(folder / "include/my_filters/force_filter.hpp").find("/// low-pass filter of a wrench\nclass ForceFilter"),
            std::string::npos);
  EXPECT_NE(readText(folder / "src/package.cpp").find("(\"ForceFilter\", \"low-pass filter of a wrench\");"), std::string::npos);
  EXPECT_EQ(errorMember(editor(), "POST", "generate", request, 400),
            (folder / "include/my_filters/force_filter.hpp").string() + " already exists; remove it or choose another name");
  std::string bad = request;
  bad.replace(bad.find("\"double\""), 8, "\"Matrix\"");
  EXPECT_EQ(errorMember(editor(), "POST", "generate", bad, 400).rfind("component.properties 'cutoff:Matrix:Hz': unknown type 'Matrix'", 0), 0u);
}

/// A generate request for component `name` of package my_types with one input per type.
std::string generateRequest(const std::filesystem::path& folder, const std::string& name, const std::vector<std::string>& types) {
  std::string inputs;
  for (std::size_t i = 0; i < types.size(); ++i)
    inputs += std::string(i ? "," : "") + "{\"name\":\"in" + std::to_string(i) + "\",\"type\":" + json::quoted(types[i]) + "}";
  return "{\"folder\":" + json::quoted(folder.string()) + ",\"component\":{\"name\":" + json::quoted(name) +
         ",\"role\":\"calculation\",\"package\":\"my_types\",\"inputs\":[" + inputs + "]}}";
}

TEST(Editor, ThePaletteFlagsTheDataTypesTheGeneratorWritesAPackagesToo) {
  const json::Json palette = call(editor(), "GET", "palette", "", 200);
  std::map<std::string, bool> generate;
  for (const json::Json& d : palette.at("data_types")) generate[d.at("name").get<std::string>()] = d.at("generate").get<bool>();
  // cobra's own, and those a loaded package registered: with a C++ spelling or without one.
  for (const char* known : {"double", "int", "bool", "string", "vector<double>", "KDL.Wrench", "KDL.Frame", "Event", "example.ForceSample"})
    EXPECT_TRUE(generate.count(known) == 1 && generate[known]) << known;
  ASSERT_EQ(generate.count("test.Opaque"), 1u);
  EXPECT_FALSE(generate["test.Opaque"]);
  // As the editor's browser tests' fixture has it (studio/web/test/editor_fixture_server.mjs).
  const json::Json fixture =
      json::parse(readText(kSource + "/studio/web/test/fixtures/editor/package_data_type.json"));
  const json::Json* served = nullptr;
  for (const json::Json& d : palette.at("data_types"))
    if (d.at("name") == "example.ForceSample") served = &d;
  ASSERT_NE(served, nullptr);
  EXPECT_EQ(*served, fixture) << served->dump() << "\n" << fixture.dump();

  // The flag is the generator's word: a component with an input of every flagged type is
  // generated, and each unflagged type is refused.
  const auto folder = ::cobra::test_support::scratchPath("cobra_editor_test") / "generated_types";
  std::filesystem::remove_all(folder);
  std::vector<std::string> flagged;
  std::vector<std::string> unflagged;
  for (const auto& [name, can] : generate) (can ? flagged : unflagged).push_back(name);
  call(editor(), "POST", "generate", generateRequest(folder, "EveryType", flagged), 200);
  const std::string header = readText(folder / "include/my_types/every_type.hpp");
  EXPECT_NE(header.find("#include \"force_sample.hpp\"\n"), std::string::npos) << header;
  EXPECT_NE(header.find("cobra::core::InputPort<example::ForceSample> in"), std::string::npos) << header;
  ASSERT_FALSE(unflagged.empty());
  for (const std::string& type : unflagged) {
    const std::string error = errorMember(editor(), "POST", "generate", generateRequest(folder, "Refused", {type}), 400);
    EXPECT_EQ(error.rfind("component.inputs 'in0:" + type + "': unknown type '" + type + "'; the types are: ", 0), 0u) << error;
    EXPECT_NE(error.find("example.ForceSample"), std::string::npos) << error;
  }
  EXPECT_FALSE(std::filesystem::exists(folder / "include/my_types/refused.hpp"));
}

TEST(Editor, BadRequestsAreRefusedWithTheirReason) {
  EXPECT_EQ(errorMember(editor(), "POST", "check", "{\"project\": [1, 2", 400),
            "POST /api/editor/check: the body is not JSON: JSON: line 1, column 18: expected ',' or ']' in an array");
  EXPECT_EQ(errorMember(editor(), "GET", "save", "", 405), "use POST /api/editor/save");
  EXPECT_EQ(errorMember(editor(), "POST", "open", "{}", 400), "POST /api/editor/open: the body has no 'path'");
  EXPECT_EQ(errorMember(editor(), "GET", "nothing", "", 404).rfind("no editor route 'nothing'; the routes: GET palette", 0), 0u);
  EXPECT_EQ(errorMember(editor(), "GET", "running", "", 404),
            "no run here: GET /api/editor/running is served by `cobra run APP --studio`");
  const json::Json empty = call(editor(), "GET", "project", "", 200);
  EXPECT_EQ(empty.at("path").get<std::string>(), "");
  EXPECT_TRUE(empty.at("project").at("components").empty());
}

TEST(Editor, TheServerServesTheRoutesOnlyWithTheToken) {
  NoRunSource source;
  int status = 0;
  EXPECT_EQ(source.model(status), "{\"error\":\"no run: cobra edit serves the deployment editor (editor.html) only\"}");
  EXPECT_EQ(status, 404);
  ServerOptions options;
  options.token = "0123456789abcdef0123456789abcdef";
  options.editor = &editor();
  Server server(source, options);
  EXPECT_EQ(editorUrl(server), "http://127.0.0.1:" + std::to_string(server.port()) + "/editor.html?token=" + options.token);
  EXPECT_EQ(request(server.port(), test_http::http::verb::get, "/api/editor/palette").status, 403);
  const Reply palette = request(server.port(), test_http::http::verb::get, "/api/editor/palette?token=" + options.token);
  EXPECT_EQ(palette.status, 200);
  EXPECT_NE(palette.body.find("\"type\":\"Gain\""), std::string::npos);
  const Reply check = request(server.port(), test_http::http::verb::post, "/api/editor/check", withConnection("G.out", "Det.in"),
                              {{"X-Cobra-Token", options.token}});
  EXPECT_EQ(check.status, 200);
  EXPECT_EQ(check.body, "{\"ok\":true,\"reason\":\"\",\"lint\":[]}");
  ServerOptions without = options;
  without.editor = nullptr;
  Server plain(source, without);
  const Reply refused = request(plain.port(), test_http::http::verb::get, "/api/editor/palette?token=" + options.token);
  EXPECT_EQ(refused.status, 404);
  EXPECT_EQ(refused.body, "{\"error\":\"the deployment editor is not served here (cobra edit, cobra run APP --studio)\"}");
}

TEST(Editor, DescribesTheRunningDeploymentWithItsCurrentValues) {
  RunningDeployment running;
  run::RunOptions options;
  options.app = kSource + "/apps/demo";
  options.observer = &running;
  bool live = true;
  EXPECT_FALSE(running.snapshot(live).has_value());
  (void)run::runApp(options);
  Editor e(withChatty());
  e.setRunning(&running);
  const json::Json v = call(e, "GET", "running", "", 200);
  EXPECT_FALSE(v.at("live").get<bool>());
  const auto snapshot = running.snapshot(live);
  ASSERT_TRUE(snapshot.has_value());
  EXPECT_FALSE(live);
  EXPECT_EQ(v.at("project").at("components").size(), snapshot->components.size());
  EXPECT_GT(snapshot->components.size(), 1u);
}

/// At each step where the run's deployment differs from the last step's, asks the editor's
/// running route (on the run's thread, between two instants: what a request would get then).
class SwitchWatcher final : public run::RunObserver {
 public:
  explicit SwitchWatcher(Editor& e) : editor_(e) {}
  void attach(const run::RunContext&) override {}
  void step(const run::StepView& now) override {
    if (now.deployments.empty() || now.deployments[0] == last_) return;
    last_ = now.deployments[0];
    answers[last_] = editor_.handle("GET", "running", "");
  }
  void event(double, const std::string&, const std::string&) override {}
  bool nextInput(std::size_t&) override { return false; }
  std::vector<std::string> finished(const run::RunResult&) override { return {}; }
  std::map<std::string, EditorAnswer> answers;  // by the deployment that had just come in force

 private:
  Editor& editor_;
  std::string last_;
};

std::vector<std::string> texts(const json::Json& array) {
  std::vector<std::string> out;
  for (const json::Json& v : array) out.push_back(v.get<std::string>());
  return out;
}

std::set<std::string> connectionTexts(const json::Json& array) {
  std::set<std::string> out;
  for (const json::Json& c : array) out.insert(c.at("output").get<std::string>() + " -> " + c.at("input").get<std::string>());
  return out;
}

/// Counts the allocations of RunningDeployment::step at the steps where nothing switched (the
/// run's steady state: one atomic load, nothing else).
class CountingSteps final : public run::RunObserver {
 public:
  explicit CountingSteps(RunningDeployment& running) : running_(running) {}
  void attach(const run::RunContext& run) override {
    configurator_ = run.configurator;
    running_.attach(run);
  }
  void step(const run::StepView& now) override {
    const std::uint64_t switches = configurator_->switchCount();
    const long before = test_support::threadNewCalls();
    running_.step(now);
    if (switches == seen_) {
      allocations += test_support::threadNewCalls() - before;
      ++steps;
    }
    seen_ = switches;
  }
  void event(double t, const std::string& source, const std::string& name) override { running_.event(t, source, name); }
  bool nextInput(std::size_t& index) override { return running_.nextInput(index); }
  std::vector<std::string> finished(const run::RunResult& result) override { return running_.finished(result); }
  long allocations = 0, steps = 0;

 private:
  RunningDeployment& running_;
  const deploy::Configurator* configurator_ = nullptr;
  std::uint64_t seen_ = 0;
};

TEST(Editor, TheRunningDeploymentFollowsTheSwitchesMadeAfterAttach) {
  SwitchWatcher watcher(editor());
  RunningDeployment running(&watcher);
  CountingSteps counting(running);
  editor().setRunning(&running);
  run::RunOptions options;
  options.app = kSource + "/studio/test/apps/editor_switch.lua";
  options.observer = &counting;
  const run::RunResult result = run::runApp(options);
  editor().setRunning(nullptr);
  ASSERT_TRUE(result.completed()) << result.reason;
  EXPECT_GT(counting.steps, 30);  // 40 ms at 1 kHz, less the switching steps
  EXPECT_EQ(counting.allocations, 0);
  ASSERT_EQ(watcher.answers.size(), 2u);  // "first" then "second", both applied after attach
  const std::set<std::string> always = {"TaskSup.outputEvents -> DepSup.inputEvents", "DepSup.outputEvents -> TaskSup.inputEvents"};
  for (const auto& [deployment, other, gain] :
       {std::tuple{"first", "second", "GainA"}, std::tuple{"second", "first", "GainB"}}) {
    SCOPED_TRACE(deployment);
    ASSERT_EQ(watcher.answers.count(deployment), 1u);
    const EditorAnswer& answer = watcher.answers.at(deployment);
    ASSERT_EQ(answer.status, 200) << answer.body;
    const json::Json v = json::parse(answer.body);
    EXPECT_TRUE(v.at("live").get<bool>());
    const json::Json& now = v.at("now");
    EXPECT_GT(now.at("t").get<double>(), 0.0);
    ASSERT_EQ(now.at("deployments").size(), 1u);
    EXPECT_EQ(now.at("deployments")[0].at("scope").get<std::string>(), "");
    EXPECT_EQ(now.at("deployments")[0].at("deployment").get<std::string>(), deployment);
    EXPECT_EQ(texts(v.at("project").at("apply")), std::vector<std::string>{deployment});
    std::set<std::string> expected = always;
    expected.insert(std::string("Sine.out -> ") + gain + ".in");
    expected.insert(std::string(gain) + ".out -> Recorder.in");
    EXPECT_EQ(connectionTexts(now.at("connections")), expected);
    const std::vector<std::string> runs = texts(now.at("running"));
    EXPECT_NE(std::find(runs.begin(), runs.end(), gain), runs.end());
    EXPECT_EQ(std::find(runs.begin(), runs.end(), other == std::string("first") ? "GainA" : "GainB"), runs.end());
    EXPECT_NE(std::find(runs.begin(), runs.end(), "Sine"), runs.end());
  }
  // After the run: the last deployment stays in force, the answer is no longer live.
  bool live = true;
  InForce now;
  const auto after = running.snapshot(live, &now);
  ASSERT_TRUE(after.has_value());
  EXPECT_FALSE(live);
  EXPECT_EQ(after->apply, std::vector<std::string>{"second"});
  EXPECT_EQ(now.switches, 2u);
}

}  // namespace
}  // namespace cobra::studio
