// The real-time side of a dds connection makes no system call: OutputPort::write into a writer's
// end only pushes into the channel and sets a flag (the end's thread polls it). Counted with
// ptrace on the writing thread alone: a forked child traces itself, sets up a dds connection
// (Fast DDS's threads, not traced), then writes 1,000 KDL.Frames between two markers while its
// parent counts the system calls the thread enters.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/ptrace.h>
#include <sys/syscall.h>
#include <sys/user.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <thread>
#include <vector>

#include "cobra/core/port.hpp"
#include "dds_test_support.hpp"

namespace cobra::dds {
namespace {

using namespace std::chrono_literals;

constexpr int kWrites = 1000;

/// The child: traced by its parent; writes between SIGUSR1 (start counting) and getppid (stop).
[[noreturn]] void writer() {
  if (ptrace(PTRACE_TRACEME, 0, nullptr, nullptr) != 0) _exit(10);
  raise(SIGSTOP);  // the parent sets its options, then lets the set-up run untraced
  test::RegisteredTransport a("dds_sys_a", 135, "cobra_sys_a");
  test::RegisteredTransport b("dds_sys_b", 135, "cobra_sys_b");
  core::OutputPort<KDL::Frame> out("pose", "", "m");
  core::InputPort<KDL::Frame> in("pose", "", "m");
  core::connectToTransport(out, a.policy("sys/pose"));
  core::connectToTransport(in, b.policy("sys/pose"));
  if (!a.transport->waitForMatch("sys/pose", 5s)) _exit(11);
  KDL::Frame frame;
  out.write(frame);  // warm
  raise(SIGUSR1);
  for (int i = 0; i < kWrites; ++i) {
    frame.p.x(0.001 * i);
    out.write(frame);
  }
  syscall(SYS_getppid);
  const bool arrived = test::pollUntil([&] { return in.read(frame) != core::FlowStatus::NoData && frame.p.x() > 0.9; });
  _exit(arrived ? 0 : 12);
}

TEST(DdsSystemCalls, WritingIntoTheWritersEndMakesNoSystemCall) {
#if !defined(__x86_64__)
  GTEST_SKIP() << "reads the system call number from x86-64's registers";
#endif
#if defined(__SANITIZE_THREAD__)
  // ThreadSanitizer's runtime guards its own bookkeeping of each atomic with locks of its own,
  // which wait in futex when Fast DDS's thread touches the same channel at that moment (1 of 1000
  // writes, in about one run in four): its system calls, not the product's. The release build
  // (and the ASan one) count the writing thread's calls.
  GTEST_SKIP() << "under ThreadSanitizer its runtime's own locks make system calls";
#endif
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) writer();
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSTOPPED(status) && WSTOPSIG(status) == SIGSTOP) << "the child could not be traced";
  ASSERT_EQ(ptrace(PTRACE_SETOPTIONS, child, nullptr, PTRACE_O_TRACESYSGOOD | PTRACE_O_EXITKILL), 0);
  ASSERT_EQ(ptrace(PTRACE_CONT, child, nullptr, nullptr), 0);
  // The set-up runs untraced until the start marker.
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSTOPPED(status) && WSTOPSIG(status) == SIGUSR1) << "the child failed before writing";
  int calls = 0;
  std::vector<long> numbers;
  bool entering = true;
  for (;;) {
    ASSERT_EQ(ptrace(PTRACE_SYSCALL, child, nullptr, nullptr), 0);  // SIGUSR1 suppressed
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSTOPPED(status) && WSTOPSIG(status) == (SIGTRAP | 0x80));
    if (!entering) {
      entering = true;
      continue;
    }
    entering = false;
    long number = -1;
#if defined(__x86_64__)
    user_regs_struct regs{};
    ASSERT_EQ(ptrace(PTRACE_GETREGS, child, nullptr, &regs), 0);
    number = static_cast<long>(regs.orig_rax);
#endif
    if (number == SYS_getppid) break;  // the end marker
    ++calls;
    numbers.push_back(number);
  }
  // Untraced again to its end; a signal stops a traced thread: passed on.
  int signal = 0;
  for (;;) {
    ASSERT_EQ(ptrace(PTRACE_CONT, child, nullptr, signal), 0);
    ASSERT_EQ(waitpid(child, &status, 0), child);
    if (!WIFSTOPPED(status)) break;
    signal = WSTOPSIG(status);
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status << ": the samples did not travel";
  std::string called;
  for (const long n : numbers) called += " " + std::to_string(n);
  EXPECT_EQ(calls, 0) << "system calls (numbers) during " << kWrites << " writes:" << called;
}

}  // namespace
}  // namespace cobra::dds
