// Which file `cobra run APP` loads (runner.hpp: entryFile): a file as given, a folder's
// <folder name>.lua, and one line naming what is missing.

#include "cobra/run/runner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cobra/test_support/test_support.hpp"

namespace cobra::run {
namespace {

using test_support::messageOf;

const std::filesystem::path kApps = std::filesystem::path(COBRA_SOURCE_DIR) / "run" / "test" / "apps";

TEST(EntryFile, AFileIsItsOwnEntry) {
  EXPECT_EQ(entryFile(kApps / "threshold" / "bad_record.lua"), kApps / "threshold" / "bad_record.lua");
}

TEST(EntryFile, AFolderHoldsTheFileNamedAfterIt) {
  EXPECT_EQ(entryFile(kApps / "threshold"), kApps / "threshold" / "threshold.lua");
  EXPECT_EQ(entryFile(kApps / "threshold/"), kApps / "threshold" / "threshold.lua");
  const std::filesystem::path puncturing = std::filesystem::path(COBRA_SOURCE_DIR) / "apps" / "puncturing";
  EXPECT_EQ(entryFile(puncturing), puncturing / "puncturing.lua");
}

TEST(EntryFile, AFolderWithoutItsEntryFileIsOneLineSayingWhatAFolderHolds) {
  const std::filesystem::path folder = ::cobra::test_support::scratchPath("cobra_run_entry") / "x";
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "other.lua") << "-- not the entry\n";
  const std::string message = messageOf([&] { entryFile(folder); });
  EXPECT_EQ(message, folder.string() + ": no entry file " + (folder / "x.lua").string() +
                         " (an application folder holds <name>.lua)");
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(EntryFile, NeitherFileNorFolderIsSaidSo) {
  EXPECT_EQ(messageOf([] { entryFile("/nonexistent/cobra_app"); }), "/nonexistent/cobra_app: no such file or folder");
}

}  // namespace
}  // namespace cobra::run
