#pragma once
// Small helpers shared by cobra's unit tests (not part of any library).

#include <gtest/gtest.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

#include <unistd.h>

/// Checks that `text` contains `part`, printing `text` when it does not.
#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

namespace cobra::test_support {

/// The message of the exception `f` throws, or "(no error)" when it throws none.
inline std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

/// A path in the temporary folder that belongs to this test process alone:
/// temp/cobra_test_<pid>_<name>. ctest runs the tests of one file side by side in separate
/// processes, and two fixed names would have one test read the other's file half written.
inline std::filesystem::path scratchPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("cobra_test_" + std::to_string(::getpid()) + "_" + name);
}

/// Polls `done` every millisecond for at most 5 s (threaded activities); returns its last value.
/// A bounded wait for a result, never a timing assertion.
template <class Pred>
bool waitUntil(Pred done) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (std::chrono::steady_clock::now() > give_up) return done();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace cobra::test_support
