#pragma once
// `cobra run APP` (run/README.md), with cobra studio live (--studio) or recorded (--report), and
// `cobra studio RUN_DIR` (studio/README.md).

#include <atomic>
#include <filesystem>
#include <string>

#include "cobra/run/runner.hpp"

namespace cobra::tools {

/// The studio options of `cobra run` and `cobra studio`.
struct StudioCommandOptions {
  bool live = false;               ///< cobra run --studio: serve the run while it runs
  unsigned short port = 0;         ///< 0: any free port
  std::string bind = "127.0.0.1";
  /// PEM certificate and key: TLS (HTTPS, WSS); required for a bind address beyond loopback.
  std::filesystem::path tls_cert, tls_key;
  double linger = -1.0;            ///< s the server stays after the run; < 0: until Ctrl-C
  std::filesystem::path executable;  ///< argv[0], to find the web front end
};

/// Runs `options` printing state, switch and progress lines (unless `quiet`), then the summary
/// values, the fidelity figures and the report's path. Returns the exit status: 0 when the task
/// charts reached their done states, 1 otherwise (with one line on stderr saying why), 2 for a bad
/// file. With studio.live it first prints "studio: URL" and serves the run, and after it (also
/// a bad file's error) until `interrupted` or studio.linger s.
int runApplication(run::RunOptions options, bool quiet, const StudioCommandOptions& studio,
                   const std::atomic<bool>& interrupted);

/// `cobra studio RUN_DIR`: serves a recorded run until `interrupted`. Exit status 2 and one line
/// for a folder that is not a run folder.
int serveRecording(const std::filesystem::path& folder, const StudioCommandOptions& studio,
                   const std::atomic<bool>& interrupted);

}  // namespace cobra::tools
