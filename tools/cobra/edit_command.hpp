#pragma once
// `cobra edit [FILE|APP]`: serves cobra studio's deployment editor (studio/README.md, "The
// deployment editor"; studio/PROTOCOL.md "The editor (v1)").

#include <atomic>
#include <filesystem>
#include <string>

#include "run_command.hpp"

namespace cobra::tools {

/// Serves the editor page and its routes until `interrupted`, after printing
/// "editor: http://ADDR:PORT/editor.html?token=TOKEN". `path` ("" for a new project) is opened
/// first; when it does not load, its error line goes to stderr ("cobra: FILE:LINE: ...") and the
/// editor serves it anyway (the page shows the error and never saves over the file).
/// Returns 0 (2 when the server cannot listen: the exception propagates).
int editDeployment(const std::string& path, const StudioCommandOptions& options, const std::atomic<bool>& interrupted);

}  // namespace cobra::tools
