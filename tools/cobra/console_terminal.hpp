#pragma once
// The terminal in front of the console: libedit line editing, history and tab completion when
// standard input is a terminal, plain line reading when it is a pipe or a file (scripts).

#include "console.hpp"

namespace cobra::tools {

/// Reads commands until `quit`, Ctrl-D or the end of the input, and runs them in `console`.
/// History is kept in $COBRA_HISTORY, else ~/.cobra_history (terminal only). Returns 0.
int runConsoleTerminal(Console& console);

}  // namespace cobra::tools
