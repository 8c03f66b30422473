#pragma once
/// @file
/// What the studio server serves (studio/PROTOCOL.md): a live run (VisualizerBridge) or a recorded
/// one (Replay). Every function is called on the server's thread only.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace cobra::studio {

/// The answer to an input: HTTP status 200 ({"ok":true}) or an error message for 400 / 409.
struct InputAnswer {
  int status = 200;
  std::string error;
};

class StudioSource {
 public:
  virtual ~StudioSource() = default;
  /// GET /api/model: the model JSON; `status` 500 with {"error": ...} when the run cannot be shown.
  virtual std::string model(int& status) = 0;
  /// GET /api/recording: {"frames":[...]} (a live run: its bounded history, the newest frames and
  /// events the server's thread kept: BridgeOptions; a long run's start is dropped).
  virtual std::string recording() = 0;
  /// The newest frame message when it is newer than `seq` (which it then updates); false otherwise.
  virtual bool latestFrame(std::uint64_t& seq, std::string& message) = 0;
  /// Appends the event and end messages since the last call.
  virtual void takeMessages(std::vector<std::string>& messages) = 0;
  /// POST /api/input and the WebSocket's input message.
  virtual InputAnswer input(const std::string& name) = 0;
  /// GET /api/mesh/NAME: the mesh file of scene object `name`; "" when it has none.
  virtual std::filesystem::path mesh(const std::string& name) = 0;
};

}  // namespace cobra::studio
