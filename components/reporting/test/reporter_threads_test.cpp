// Reporter with real threads: a 1 kHz writer never waits for it, whether the Reporter stops and
// starts, or its disk is stuck. The deadlines below are generous safety nets against a hang,
// not timing claims.

#include "cobra/components/reporting/reporter.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "cobra/components/signal/sine_generator.hpp"
#include "cobra/core/core.hpp"
#include "test_files.hpp"

namespace cobra::components {
namespace {

using namespace std::chrono_literals;

/// Waits until `done()` or 30 s; returns done().
template <class F>
bool eventually(F&& done) {
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (!done() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(1ms);
  return done();
}

/// True once `component` made `n` more updates than when this was called.
bool updatesFurther(const core::Component& component, std::uint64_t n) {
  const std::uint64_t start = component.updateCount();
  return eventually([&] { return component.updateCount() >= start + n; });
}

TEST(ReporterThreads, AWriterAt1kHzKeepsRunningWhileTheReporterStopsAndStarts) {
  test::ScratchDir dir;
  SineGenerator sine("Sine");
  Reporter reporter("Rep");
  reporter.reportPort(sine.port("out"));
  reporter.setProperty("file_path", dir.file("threads.csv"));
  reporter.setProperty("flush_period", 0.0);
  sine.setActivity(std::make_unique<core::PeriodicActivity>(1ms, 50, core::Scheduler::Other));
  reporter.setActivity(std::make_unique<core::PeriodicActivity>(5ms, 50, core::Scheduler::Other));
  ASSERT_TRUE(sine.configure() && sine.start());
  ASSERT_TRUE(reporter.configure());
  for (int round = 0; round < 5; ++round) {
    ASSERT_TRUE(reporter.start());
    EXPECT_TRUE(updatesFurther(reporter, 3));
    EXPECT_TRUE(updatesFurther(sine, 20)) << "the writer stalled while the reporter ran";
    ASSERT_TRUE(reporter.stop());
    EXPECT_TRUE(updatesFurther(sine, 20)) << "the writer stalled while the reporter was stopped";
  }
  ASSERT_TRUE(sine.stop());
  const auto lines = test::readLines(dir.file("threads.csv"));
  ASSERT_GE(lines.size(), 1u + 5u * 3u);
  EXPECT_EQ(lines[0], "time [s],Sine.out [1]");
  double last = -1.0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const double t = std::stod(lines[i].substr(0, lines[i].find(',')));
    EXPECT_GT(t, last) << "row " << i << ": " << lines[i];
    last = t;
  }
}

TEST(ReporterThreads, DestroyingARunningReporterStopsItAndCompletesTheFile) {
  test::ScratchDir dir;
  SineGenerator sine("Sine");
  sine.setActivity(std::make_unique<core::PeriodicActivity>(1ms, 50, core::Scheduler::Other));
  auto reporter = std::make_unique<Reporter>("Rep");
  reporter->reportPort(sine.port("out"));
  reporter->setProperty("file_path", dir.file("destroyed.csv"));
  reporter->setActivity(std::make_unique<core::PeriodicActivity>(2ms, 50, core::Scheduler::Other));
  ASSERT_TRUE(sine.configure() && sine.start());
  ASSERT_TRUE(reporter->configure() && reporter->start());
  // A sample written after the reporter started, then updates of the reporter after it: it has
  // queued a row for it, whatever the scheduler did (an update writes a row only on new data, so
  // a count of rows per update depends on how often the loaded machine ran the sine between two).
  EXPECT_TRUE(updatesFurther(sine, 1));
  EXPECT_TRUE(updatesFurther(*reporter, 5));
  reporter.reset();  // while Running: stops, drains, joins, disconnects
  EXPECT_FALSE(sine.port("out").connected());
  EXPECT_TRUE(updatesFurther(sine, 5));
  ASSERT_TRUE(sine.stop());
  const std::string text = test::readFile(dir.file("destroyed.csv"));
  EXPECT_EQ(text.back(), '\n');
  EXPECT_GE(test::readLines(dir.file("destroyed.csv")).size(), 2u);  // the header and the queued rows
}

/// Writes a wide vector every update, so a few rows fill a pipe.
class Wide : public core::Component {
 public:
  explicit Wide(std::string name) : Component(std::move(name), core::Role::Calculation, "wide output") {
    addPort(out_);
    out_.setDataSample(values_);
  }

 protected:
  void updateHook() override {
    values_[0] += 1.0;
    out_.write(values_);
  }

 private:
  std::vector<double> values_ = std::vector<double>(500, 0.123456789);
  core::OutputPort<std::vector<double>> out_{"out", "500 numbers", "1"};
};

TEST(ReporterThreads, AStuckDiskDropsRowsAndBlocksNobody) {
  test::ScratchDir dir;
  // A pipe nobody reads stands for a disk that stopped answering: once its buffer and the
  // file buffer are full, the writer thread blocks in fwrite.
  const std::string fifo = dir.file("stuck.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int read_end = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(read_end, 0);

  Wide wide("Wide");
  Reporter reporter("Rep");
  reporter.reportPort(wide.port("out"), 500);
  reporter.setProperty("file_path", fifo);
  reporter.setProperty("queue_rows", 4);
  wide.setActivity(std::make_unique<core::PeriodicActivity>(1ms, 50, core::Scheduler::Other));
  reporter.setActivity(std::make_unique<core::PeriodicActivity>(1ms, 50, core::Scheduler::Other));
  ASSERT_TRUE(wide.configure() && wide.start());
  ASSERT_TRUE(reporter.configure() && reporter.start());
  // ~10 kB rows: the pipe (64 kB) and the file buffer (64 kB) hold fewer than 20 of them.
  EXPECT_TRUE(updatesFurther(reporter, 200));
  EXPECT_TRUE(updatesFurther(wide, 200)) << "the writer stalled behind the stuck disk";

  // Unstick the disk so that stop can drain the queue and join the writer thread.
  std::atomic<bool> eof{false};
  std::size_t newlines = 0;
  std::thread drain([&] {
    char buffer[1 << 16];
    for (;;) {
      const ssize_t n = ::read(read_end, buffer, sizeof buffer);
      if (n == 0) break;  // the Reporter closed the file (cleanup)
      if (n < 0) {
        std::this_thread::sleep_for(1ms);
        continue;
      }
      for (ssize_t i = 0; i < n; ++i) newlines += buffer[i] == '\n' ? 1 : 0;
    }
    eof = true;
  });
  ASSERT_TRUE(reporter.stop());
  const int dropped = reporter.getProperty<int>("rows_dropped");
  ASSERT_TRUE(reporter.cleanup());
  drain.join();
  ::close(read_end);
  ASSERT_TRUE(wide.stop());
  EXPECT_TRUE(eof);
  EXPECT_GT(dropped, 0);
  EXPECT_GE(newlines, 2u);  // the header and at least one row
}

}  // namespace
}  // namespace cobra::components
