// `cobra console` driven through a pseudo-terminal, as a person would type into it: line
// editing, Tab completion and history come from libedit, so only a real terminal tests them.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include "cobra/test_support/test_support.hpp"

namespace {

/// Generous: only a hung console ever waits this long (a guard, not a timing assertion).
constexpr auto kPatience = std::chrono::seconds(30);

/// A child program on a pseudo-terminal: type keys into it, wait for text to appear.
class Terminal {
 public:
  Terminal(const std::vector<std::string>& command, const std::string& history) {
    pid_ = forkpty(&master_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      setenv("TERM", "vt100", 1);
      setenv("COBRA_HISTORY", history.c_str(), 1);
      std::vector<char*> argv;
      for (const std::string& word : command) argv.push_back(const_cast<char*>(word.c_str()));
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  ~Terminal() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (master_ >= 0) close(master_);
  }
  bool started() const { return pid_ > 0; }

  /// Types `keys` once the program has had a moment to put the terminal in raw mode after its
  /// prompt (keys typed earlier are read in canonical mode, where Ctrl-D or Tab mean other things).
  void type(const std::string& keys) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_EQ(write(master_, keys.data(), keys.size()), static_cast<ssize_t>(keys.size()));
  }

  /// Waits until `text` has appeared since the last match; returns what came before it.
  std::string waitFor(const std::string& text) {
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    while (true) {
      if (const auto at = pending_.find(text); at != std::string::npos) {
        std::string before = pending_.substr(0, at);
        pending_.erase(0, at + text.size());
        return before;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        ADD_FAILURE() << "waited " << kPatience.count() << " s for \"" << text << "\"; the terminal shows:\n" << pending_;
        return {};
      }
      pollfd fd{master_, POLLIN, 0};
      if (poll(&fd, 1, 100) > 0) {
        char buffer[4096];
        const ssize_t n = read(master_, buffer, sizeof buffer);
        if (n <= 0) continue;  // EIO once the child has gone: the deadline reports it
        pending_.append(buffer, static_cast<std::size_t>(n));
      }
    }
  }

  /// Waits for the program to end and returns its exit status (-1 on a signal or a hang).
  int exitStatus() {
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      char buffer[4096];
      pollfd fd{master_, POLLIN, 0};
      if (poll(&fd, 1, 50) > 0 && read(master_, buffer, sizeof buffer) > 0) continue;  // drain
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int master_ = -1;
  bool exited_ = false;
  std::string pending_;
};

TEST(ConsoleOnATerminal, ListSetCallTraceWithCompletionAndHistory) {
  const std::string history = ::cobra::test_support::scratchPath("cobra_console_history").string();
  std::filesystem::remove(history);
  const std::string listing = std::string(COBRA_SOURCE_DIR) + "/apps/examples/signal_listing.lua";
  Terminal terminal({COBRA_CLI, "console", listing, "--sim"}, history);
  ASSERT_TRUE(terminal.started());
  terminal.waitFor("loaded ");
  terminal.waitFor("cobra> ");

  terminal.type("ls\n");  // list
  const std::string components = terminal.waitFor("cobra> ");
  EXPECT_NE(components.find("TrajGen"), std::string::npos) << components;
  EXPECT_NE(components.find("Reporter"), std::string::npos) << components;

  terminal.type("cd Traj\t\n");  // Tab completes the component's name
  terminal.waitFor("cobra:TrajGen> ");

  terminal.type("set k 2\n");  // set
  EXPECT_NE(terminal.waitFor("cobra:TrajGen> ").find("TrajGen.k = 2"), std::string::npos);

  terminal.type("trace out 3\n");  // trace: MotPlan's sine (1 Hz, every 10 ms) times 2
  const std::string trace = terminal.waitFor("cobra:TrajGen> ");
  EXPECT_NE(trace.find("t = 0.0010 s  TrajGen.out = 0\r\n"), std::string::npos) << trace;
  EXPECT_NE(trace.find("t = 0.0110 s  TrajGen.out = 0.1255810390586"), std::string::npos) << trace;
  EXPECT_NE(trace.find("t = 0.0210 s  TrajGen.out = 0.2506664671286"), std::string::npos) << trace;

  terminal.type("Reporter.cou\t\n");  // call, the operation's name completed
  EXPECT_NE(terminal.waitFor("cobra:TrajGen> ").find("Reporter.count() = 3"), std::string::npos);
  terminal.type("call Reporter.clear\n");
  terminal.waitFor("cobra:TrajGen> ");
  terminal.type("\x1b[A\x1b[A\n");  // history: two lines up is Reporter.count() again
  EXPECT_NE(terminal.waitFor("cobra:TrajGen> ").find("Reporter.count() = 0"), std::string::npos);

  terminal.type("quit\n");
  EXPECT_EQ(terminal.exitStatus(), 0);
  std::ifstream saved(history);
  std::stringstream lines;
  lines << saved.rdbuf();
  std::string text = lines.str();  // libedit writes a space as \040
  for (auto at = text.find("\\040"); at != std::string::npos; at = text.find("\\040")) text.replace(at, 4, " ");
  EXPECT_NE(text.find("\nset k 2\n"), std::string::npos) << "history file:\n" << lines.str();
}

TEST(ConsoleOnATerminal, CtrlDLeavesAndErrorsDoNotEndTheSession) {
  const std::string history = ::cobra::test_support::scratchPath("cobra_console_history_2").string();
  Terminal terminal({COBRA_CLI, "console", "--sim"}, history);
  ASSERT_TRUE(terminal.started());
  terminal.waitFor("cobra> ");
  terminal.type("ls\n");
  EXPECT_NE(terminal.waitFor("cobra> ").find("no components (load a deployment file: load FILE)"), std::string::npos);
  terminal.type("start Nobody\n");
  EXPECT_NE(terminal.waitFor("cobra> ").find("error: no component named 'Nobody'"), std::string::npos);
  terminal.type("\x04");  // Ctrl-D on an empty line
  EXPECT_EQ(terminal.exitStatus(), 0);
}

}  // namespace
