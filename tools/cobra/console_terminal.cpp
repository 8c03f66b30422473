#include "console_terminal.hpp"

#include <editline/readline.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace cobra::tools {
namespace {

Console* g_console = nullptr;          // the console libedit's callbacks complete for
std::vector<std::string> g_matches;    // completions of the word being typed, for the generator

// libedit asks for the matches one at a time; it frees each string with free().
char* nextMatch(const char*, int state) {
  static std::size_t next = 0;
  if (state == 0) next = 0;
  return next < g_matches.size() ? strdup(g_matches[next++].c_str()) : nullptr;
}

char** completeWord(const char* text, int, int) {
  rl_attempted_completion_over = 1;  // never fall back to file names
  const std::string line(rl_line_buffer, static_cast<std::size_t>(rl_point));
  g_matches.clear();
  for (std::string& match : g_console->complete(line))
    if (match.rfind(text, 0) == 0) g_matches.push_back(std::move(match));
  // "Gain." completes on to a member: no space after it.
  rl_completion_append_character = g_matches.size() == 1 && g_matches[0].back() == '.' ? '\0' : ' ';
  return g_matches.empty() ? nullptr : rl_completion_matches(text, nextMatch);
}

std::string historyFile() {
  if (const char* path = std::getenv("COBRA_HISTORY")) return path;
  if (const char* home = std::getenv("HOME")) return std::string(home) + "/.cobra_history";
  return {};
}

int runPlain(Console& console) {
  std::string line;
  while (std::getline(std::cin, line))
    if (!console.execute(line)) break;
  return 0;
}

}  // namespace

int runConsoleTerminal(Console& console) {
  if (isatty(STDIN_FILENO) == 0) return runPlain(console);
  g_console = &console;
  static char word_breaks[] = " \t=(,";
  rl_completer_word_break_characters = word_breaks;
  rl_attempted_completion_function = completeWord;
  using_history();
  stifle_history(1000);
  const std::string history = historyFile();
  if (!history.empty()) read_history(history.c_str());  // a missing file is a first run, not an error
  std::cout << "cobra console: type help for the commands, Tab to complete, quit or Ctrl-D to leave\n";
  while (true) {
    char* raw = readline(console.prompt().c_str());
    if (raw == nullptr) {  // Ctrl-D
      std::cout << "\n";
      break;
    }
    const std::string line(raw);
    std::free(raw);
    if (line.find_first_not_of(" \t") != std::string::npos) add_history(line.c_str());
    if (!console.execute(line)) break;
  }
  if (!history.empty()) write_history(history.c_str());
  g_console = nullptr;
  return 0;
}

}  // namespace cobra::tools
