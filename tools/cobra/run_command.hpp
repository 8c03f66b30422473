#pragma once
// `cobra run APP`: an application run until its task charts are done (run/README.md).

#include "cobra/run/runner.hpp"

namespace cobra::tools {

/// Runs `options` printing state, switch and progress lines (unless `quiet`), then the summary
/// values, the fidelity figures and the report's path. Returns the exit status: 0 when the task
/// charts reached their done states, 1 otherwise (with one line on stderr saying why).
int runApplication(run::RunOptions options, bool quiet);

}  // namespace cobra::tools
