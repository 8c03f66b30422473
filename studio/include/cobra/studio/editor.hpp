#pragma once
/// @file
/// The deployment editor's server side (thesis §3.2.1, OroEdit): the routes under
/// /api/editor/ of studio/PROTOCOL.md "The editor (v1)". The palette (every component type of
/// every package cobra can load, each made once and introspected) is built on a thread of its own
/// when the Editor is made, never on a run's thread; files are opened in a Configurator of their
/// own on the simulation clock, never advanced; projects are saved with the writer `cobra
/// describe` uses (deploy/description.hpp).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/deploy/description.hpp"
#include "cobra/run/runner.hpp"
#include "cobra/studio/source.hpp"

namespace cobra::studio {

/// An answer: HTTP status and JSON body.
struct EditorAnswer {
  int status = 200;
  std::string body;
};

struct EditorOptions {
  /// Directories searched for shared-library packages, before COBRA_PACKAGE_PATH.
  std::vector<std::filesystem::path> package_path;
  /// Built-in packages besides cobra's own (a program's, a test's): name and registration.
  std::vector<std::pair<std::string, deploy::PackageRegistrar>> packages;
};

/// What is in force in a run now: each scope's deployment, the configuration, which components
/// run and which connections exist (those made outside the named deployments, then those of the
/// deployments in force).
struct InForce {
  double t = 0.0;            ///< s of run time of the last switch seen (0: none since setup)
  std::uint64_t switches = 0;  ///< switches seen since setup
  std::vector<std::pair<std::string, std::string>> deployments;  ///< scope ("" default), deployment ("" none)
  std::string configuration;                                      ///< applied last ("" none)
  std::vector<std::string> running;                               ///< components in state Running
  std::vector<deploy::ConnectionSpec> connections;
};

/// The running deployment for GET /api/editor/running (`cobra run --studio`): a run observer
/// that wraps the run's own observer (cobra studio's bridge) and passes every call on. At
/// attach, on the run's thread before the first step, it describes the run's Configurator
/// (components, connections, the named deployments and configurations). It follows the run's
/// deployment switches: at each step it reads the Configurator's switch count (an atomic load;
/// nothing else when nothing switched) and, after a switch, each scope's deployment and the
/// configuration in force (the run's thread, between two instants), handed over with a lock it
/// only tries, never waits for (when a request holds it, the next step hands them over). A
/// deployment not in the attach-time description (defined during the run) makes it describe
/// the Configurator again there. When asked, it adds the property values and component states of
/// the moment, read through the components' thread-safe snapshots (core::describe), so the run's
/// thread is never blocked while it steps. After the run (finished) those of its last instant stay.
class RunningDeployment final : public run::RunObserver {
 public:
  explicit RunningDeployment(run::RunObserver* inner = nullptr);
  ~RunningDeployment() override;

  void attach(const run::RunContext& run) override;
  void step(const run::StepView& now) override;
  void event(double t, const std::string& source, const std::string& name) override;
  bool nextInput(std::size_t& index) override;
  std::vector<std::string> finished(const run::RunResult& result) override;

  /// The description as of now (applied deployments and configuration in force, current property
  /// values); nullopt before attach. `live`: false once the run has finished. `now`, when given:
  /// what is in force.
  std::optional<deploy::DeploymentDescription> snapshot(bool& live, InForce* now = nullptr) const;

 private:
  void refreshValues(deploy::DeploymentDescription& d, std::vector<std::string>* running) const;  // holding mutex_
  void stageSwitch(double t);  // the run's thread
  void handOver();            // staged_ into in_force_, holding mutex_
  run::RunObserver* inner_;
  mutable std::mutex mutex_;
  std::optional<deploy::DeploymentDescription> description_;
  std::vector<std::pair<std::string, std::string>> attach_values_;  // "Comp.prop" -> text at attach
  const core::ComponentRegistry* registry_ = nullptr;            // null after finished
  InForce in_force_;                                             // `running` filled after finished
  // The run's thread only.
  const deploy::Configurator* configurator_ = nullptr;
  std::uint64_t switches_seen_ = 0;
  bool pending_ = false;  // staged_ not handed over yet (the lock was held)
  InForce staged_;
  std::optional<deploy::DeploymentDescription> staged_description_;  // described again at a switch
};

/// What a server serving only the editor (`cobra edit`) has of a run: none. GET /api/model
/// answers 404 saying so, inputs 409; no frame, event or mesh.
class NoRunSource final : public StudioSource {
 public:
  std::string model(int& status) override;
  std::string recording() override;
  bool latestFrame(std::uint64_t& seq, std::string& message) override;
  void takeMessages(std::vector<std::string>& messages) override;
  InputAnswer input(const std::string& name) override;
  std::filesystem::path mesh(const std::string& name) override;
};

class Editor {
 public:
  /// Starts building the palette on a thread of its own (GET /api/editor/palette waits for it).
  explicit Editor(EditorOptions options = {});
  ~Editor();
  Editor(const Editor&) = delete;
  Editor& operator=(const Editor&) = delete;

  /// Opens `path` (a Lua deployment file, or an application folder holding `<name>.lua`) as the
  /// project of GET /api/editor/project. Returns "" when it loaded, else its error line
  /// ("FILE:LINE: ..."): the editor then shows the error and never saves over the file.
  std::string open(const std::string& path);

  /// Serves GET /api/editor/running from `running` (nullptr: 404 saying it is `cobra run
  /// --studio`'s). It must outlive the Editor's use.
  void setRunning(const RunningDeployment* running);

  /// Answers `method` ("GET", "POST") on `route` (the path after "/api/editor/", e.g. "palette")
  /// with request `body`. Thread-safe (requests are answered one at a time).
  EditorAnswer handle(std::string_view method, std::string_view route, std::string_view body);

  struct Impl;  ///< editor*.cpp's

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace cobra::studio
