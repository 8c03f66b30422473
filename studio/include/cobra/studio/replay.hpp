#pragma once
/// @file
/// A recorded run served again (`cobra studio RUN_DIR`): the run folder's studio/recording.json
/// (written by `cobra run APP --report DIR` for an application with a `run.studio` table).

#include <filesystem>
#include <string>

#include "cobra/studio/source.hpp"

namespace cobra::studio {

class Replay final : public StudioSource {
 public:
  /// Loads RUN_DIR/studio/recording.json.
  /// @throws std::runtime_error one line naming the folder and what is missing, e.g.
  ///         "build/x: not a run folder: no studio/recording.json (written by cobra run APP --report DIR
  ///         for an application with a run.studio table)".
  explicit Replay(const std::filesystem::path& run_folder);

  std::string model(int& status) override;
  std::string recording() override;
  /// A replay streams nothing: the page scrubs /api/recording.
  bool latestFrame(std::uint64_t& seq, std::string& message) override;
  void takeMessages(std::vector<std::string>& messages) override;
  /// 409 "replay: no inputs".
  InputAnswer input(const std::string& name) override;
  /// RUN_DIR/studio/meshes/NAME when the recording copied it.
  std::filesystem::path mesh(const std::string& name) override;

 private:
  std::filesystem::path folder_;
  std::string model_, frames_;
};

}  // namespace cobra::studio
