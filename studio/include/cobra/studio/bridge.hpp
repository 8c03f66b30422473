#pragma once
/// @file
/// The Robot Visualizer Bridge (thesis §4.5.6) as cobra studio's observer of a run: at setup it
/// connects to the ports the application names in `run.studio` (joints, extras, signals), reads the
/// properties of its fixed extras (a phantom's tumour and layers, forbidden regions) and loads
/// the planning scene of the component it names (the scene the MotionPlanner checks collisions
/// in: one source for collision and drawing); during the run it copies them, with each robot's
/// link frames (forward kinematics of the scene's robot models placed at their bases), the
/// charts' states, deployments and configuration, into a snapshot that the server's thread takes
/// without ever blocking the run (a triple buffer). It records 30 frames per simulated second for
/// the replay (DIR/studio/recording.json) and passes the console's inputs to the run.
/// Why an observer and not a component: studio/README.md.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cobra/run/runner.hpp"
#include "cobra/studio/source.hpp"

namespace cobra::studio {

struct BridgeOptions {
  /// Keep every frame and event for the replay (DIR/studio: recording.json, recording.js, the web
  /// page, written when the run has a report folder). A run with a report folder always records;
  /// a live page's history does not need it (history_frames).
  bool record = false;
  /// Frames per simulated second published and recorded; a live run also publishes at this rate
  /// of wall-clock time when its simulation runs slower [Hz].
  double frame_rate = 30.0;
  /// cobra run --interactive: a person gives the surgeon's inputs, so the console offers the
  /// charts' choices ("interactive" in the model; a replay's is false).
  bool interactive = false;
  /// A late page's history (GET /api/recording of a live run): at most this many of the newest
  /// frames and event messages the server's thread took, kept by that thread (the run's thread
  /// does nothing for it). 9000 frames: 5 min at 30 frames per s.
  std::size_t history_frames = 9000;
  std::size_t history_events = 4096;
  /// The built web front end (index.html, assets/) copied into DIR/studio; "" = none (only the
  /// recording files are written).
  std::filesystem::path web_folder;
};

/// Counts of what the bridge did, for tests and the bench.
struct BridgeStats {
  long published = 0;       ///< snapshots published
  long recorded = 0;        ///< frames recorded
  long events_dropped = 0;  ///< events the server had not taken when the queue was full
};

class VisualizerBridge final : public run::RunObserver, public StudioSource {
 public:
  explicit VisualizerBridge(BridgeOptions options = {});
  ~VisualizerBridge() override;
  VisualizerBridge(const VisualizerBridge&) = delete;
  VisualizerBridge& operator=(const VisualizerBridge&) = delete;

  // run::RunObserver (the run's thread).
  /// @throws std::runtime_error "FILE:LINE: run.studio.robots.isur: ..." for an unknown component,
  ///         port, scene robot or a port of another type.
  void attach(const run::RunContext& run) override;
  /// At most frame_rate times per simulated (or wall) second: reads the ports, computes the link
  /// frames, publishes the snapshot. Allocates nothing unless it records.
  void step(const run::StepView& now) override;
  void event(double t, const std::string& source, const std::string& name) override;
  bool nextInput(std::size_t& index) override;
  std::vector<std::string> finished(const run::RunResult& result) override;

  /// The run could not start (a bad file): /api/model answers {"error": message} with 500.
  void fail(const std::string& message);

  // StudioSource (the server's thread).
  std::string model(int& status) override;
  std::string recording() override;
  bool latestFrame(std::uint64_t& seq, std::string& message) override;
  void takeMessages(std::vector<std::string>& messages) override;
  InputAnswer input(const std::string& name) override;
  std::filesystem::path mesh(const std::string& name) override;

  BridgeStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes the replay files into `folder` (DIR/studio): recording.json = {"model","frames","events"},
/// recording.js (window.COBRA_RECORDING = ...;), the scene's mesh files as meshes/NAME (`meshes`:
/// object name -> file) and, from `web_folder` when it holds index.html, the page and its assets. Returns the file the report links ("studio/index.html" or
/// "studio/recording.json"). @throws std::runtime_error naming a file it cannot write.
std::string writeReplayFolder(const std::filesystem::path& folder, const std::string& recording_json,
                              const std::filesystem::path& web_folder,
                              const std::vector<std::pair<std::string, std::filesystem::path>>& meshes = {});

}  // namespace cobra::studio
