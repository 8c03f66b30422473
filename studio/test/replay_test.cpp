// A recorded run served again (studio/src/replay.cpp): a folder that is not a run folder is one
// line naming it and what is missing; a recording's model, frames and end are served as recorded.

#include <gtest/gtest.h>

#include <fstream>

#include "cobra/studio/bridge.hpp"
#include "cobra/studio/replay.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::studio {
namespace {

std::string openingError(const std::filesystem::path& folder) {
  return test_support::messageOf([&] { Replay replay(folder); });
}

TEST(Replay, AFolderThatIsNotARunFolderIsOneLineNamingItAndWhatIsMissing) {
  const auto none = ::cobra::test_support::scratchPath("cobra_studio_no_such_run");
  std::filesystem::remove_all(none);
  EXPECT_EQ(openingError(none), none.string() + ": no such folder (give a run folder of cobra run APP --report DIR)");
  std::filesystem::create_directories(none);
  EXPECT_EQ(openingError(none), none.string() + ": not a run folder with a recording: no studio/recording.json (cobra run APP "
                                           "--report " + none.string() + " writes it for an application with a run.studio table)");
  std::filesystem::create_directories(none / "studio");
  std::ofstream(none / "studio" / "recording.json") << "{\"frames\": 3}";
  EXPECT_EQ(openingError(none), (none / "studio" / "recording.json").string() +
                               ": not a studio recording: expected {\"model\": {...}, \"frames\": [...], \"events\": [...]}");
}

TEST(Replay, ServesTheRecordedModelAndFramesAndRefusesInputs) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_studio_replay");
  std::filesystem::remove_all(folder);
  const std::string recording = R"({"model":{"protocol":1,"mode":"replay","duration":2},"frames":[{"type":"frame","t":0}],"events":[]})";
  const auto mesh = ::cobra::test_support::scratchPath("cobra_studio_replay_phantom.stl");
  std::ofstream(mesh) << "solid phantom\nendsolid phantom\n";
  EXPECT_EQ(writeReplayFolder(folder / "studio", recording, {}, {{"phantom", mesh}}), "studio/recording.json");
  Replay replay(folder);
  EXPECT_EQ(replay.mesh("phantom"), folder / "studio" / "meshes" / "phantom.stl");
  EXPECT_EQ(replay.mesh("table"), std::filesystem::path());
  int status = 0;
  EXPECT_EQ(replay.model(status), R"({"protocol":1,"mode":"replay","duration":2})");
  EXPECT_EQ(status, 200);
  EXPECT_EQ(replay.recording(), R"({"frames":[{"type":"frame","t":0}],"events":[]})");
  const InputAnswer answer = replay.input("needle_mounted");
  EXPECT_EQ(answer.status, 409);
  EXPECT_EQ(answer.error, "replay: no inputs");
}

TEST(Replay, ServesHowTheRunEndedWithTheFrames) {
  const auto folder = ::cobra::test_support::scratchPath("cobra_studio_replay_end");
  std::filesystem::remove_all(folder);
  const std::string end = R"({"type":"end","t":2,"outcome":"safe stop","message":"why","status":1,"line":"cobra run: safe stop: why","states":{"task":"root.SafeStop"}})";
  writeReplayFolder(folder / "studio", R"({"model":{"protocol":1},"frames":[{"type":"frame","t":0}],"events":[],"end":)" + end + "}", {});
  EXPECT_EQ(Replay(folder).recording(), R"({"frames":[{"type":"frame","t":0}],"events":[],"end":)" + end + "}");
}

}  // namespace
}  // namespace cobra::studio
