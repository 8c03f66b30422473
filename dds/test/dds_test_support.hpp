#pragma once
// Helpers of the dds tests: a transport registered for one test, an event, and polling with a deadline.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/core/event.hpp"
#include "cobra/core/transport.hpp"
#include "cobra/dds/dds_transport.hpp"

namespace cobra::dds::test {

/// A DdsTransport registered as `name` on `domain` for the life of the object. Each test uses
/// its own domain id: ctest runs tests in parallel, and DDS would match their topics otherwise.
struct RegisteredTransport {
  RegisteredTransport(const std::string& transport_name, int domain, const std::string& participant)
      : name(transport_name), transport(registerDdsTransport({domain, participant, false}, transport_name)) {}
  ~RegisteredTransport() { core::TransportRegistry::remove(name); }
  RegisteredTransport(const RegisteredTransport&) = delete;
  RegisteredTransport& operator=(const RegisteredTransport&) = delete;

  /// A policy of kind `base` over this transport on `topic`.
  core::ConnPolicy policy(const std::string& topic, core::ConnPolicy base = core::ConnPolicy::data()) const {
    base.transport = name;
    base.topic = topic;
    return base;
  }

  std::string name;
  std::shared_ptr<DdsTransport> transport;
};

/// An event named `name` from source "test", as the tests send them across.
inline core::Event event(const std::string& name) {
  core::Event e;
  e.name.assign(name);
  e.source = "test";
  return e;
}

/// Polls `done` every millisecond until it is true or `timeout` passed; returns its last value.
inline bool pollUntil(const std::function<bool()>& done, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return done();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

/// A child process running `args` (args[0]: the program's path); killed and reaped unless
/// waited for.
class ChildProcess {
 public:
  /// `output`: a file for the child's stdout and stderr ("": the test's own).
  explicit ChildProcess(std::vector<std::string> args, const std::string& output = "") {
    pid_ = fork();
    if (pid_ == 0) {
      if (!output.empty()) {
        const int fd = open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, 1);
        dup2(fd, 2);
      }
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  ~ChildProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  void killHard() { kill(pid_, SIGKILL); }
  /// Asks it to end (SIGTERM); wait() for its status.
  void terminate() { kill(pid_, SIGTERM); }
  /// Stalls the process for `pause` (SIGSTOP, then SIGCONT): none of its threads runs meanwhile.
  void stall(std::chrono::milliseconds pause) {
    kill(pid_, SIGSTOP);
    std::this_thread::sleep_for(pause);
    kill(pid_, SIGCONT);
  }
  /// The exit status, or -1 when it did not exit within `timeout`.
  int wait(std::chrono::milliseconds timeout) {
    int status = 0;
    if (!pollUntil([&] { return waitpid(pid_, &status, WNOHANG) == pid_; }, timeout)) return -1;
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
};

}  // namespace cobra::dds::test
