// Proves the Reporter's update is real-time safe for the built-in types (ARCHITECTURE §4): once
// configured and started, stepping writers and the Reporter allocates nothing. A counting
// global operator new replaces the library one for this test executable only.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include "cobra/components/reporting/reporter.hpp"
#include "cobra/core/core.hpp"
#include "cobra/test_support/counting_new.hpp"
#include "test_files.hpp"


namespace cobra::components {
namespace {

using namespace std::chrono_literals;

/// Writes one sample of every kind the Reporter flattens, at every update.
class Writer : public core::Component {
 public:
  explicit Writer(std::string name) : Component(std::move(name), core::Role::Bridge, "writes everything") {
    for (core::PortBase* p : std::initializer_list<core::PortBase*>{&d_, &q_, &j_, &f_, &t_, &w_, &s_}) addPort(*p);
    q_.setDataSample(q_value_);
    j_.setDataSample(j_value_);
  }

 protected:
  void updateHook() override {
    x_ += 0.5;
    q_value_[0] = x_;
    j_value_(1) = -x_;
    d_.write(x_);
    q_.write(q_value_);
    j_.write(j_value_);
    f_.write(KDL::Frame(KDL::Rotation::RotZ(x_), KDL::Vector(x_, 0, 1)));
    t_.write(KDL::Twist(KDL::Vector(x_, 1, 2), KDL::Vector(3, 4, 5)));
    w_.write(KDL::Wrench(KDL::Vector(x_, 1, 2), KDL::Vector(3, 4, 5)));
    s_.write(text_);
    emitEvent("e_tick");
  }

 private:
  double x_ = 0.0;
  std::vector<double> q_value_ = std::vector<double>(6, 0.0);
  KDL::JntArray j_value_ = KDL::JntArray(7);
  std::string text_ = "short text";
  core::OutputPort<double> d_{"d", "", "m"};
  core::OutputPort<std::vector<double>> q_{"q", "", "rad"};
  core::OutputPort<KDL::JntArray> j_{"j", "", "rad"};
  core::OutputPort<KDL::Frame> f_{"f", "", "m"};
  core::OutputPort<KDL::Twist> t_{"t", "", ""};
  core::OutputPort<KDL::Wrench> w_{"w", "", ""};
  core::OutputPort<std::string> s_{"s", "", ""};
};

TEST(ReporterAlloc, UpdatesAllocateNothingOnceStarted) {
  test::ScratchDir dir;
  core::LockstepClock clock;
  Writer writer("W");
  Reporter reporter("Rep");
  reporter.reportPort(writer.port("q"), 6);
  reporter.reportPort(writer.port("j"), 7);
  reporter.reportComponent(writer, true);
  reporter.setProperty("file_path", dir.file("alloc.csv"));
  reporter.setProperty("queue_rows", 100000);  // no drops: every update formats a full row
  clock.add(writer, 1ms);
  clock.add(reporter, 1ms);
  ASSERT_TRUE(writer.configure() && writer.start());
  const long at_configure = cobra::test_support::newCalls();
  ASSERT_TRUE(reporter.configure());
  EXPECT_GT(cobra::test_support::newCalls() - at_configure, 0) << "the counter must see the queue being allocated";
  ASSERT_TRUE(reporter.start());
  clock.advance(10ms);  // warm-up: first reads fill the readers' values

  const long before = cobra::test_support::newCalls();
  clock.advance(1000ms);
  const long during = cobra::test_support::newCalls() - before;
  EXPECT_EQ(during, 0) << "allocations in 1000 updates of the writer and the reporter";

  ASSERT_TRUE(reporter.stop());
  EXPECT_EQ(reporter.getProperty<int>("rows_dropped"), 0);
  EXPECT_EQ(test::readLines(dir.file("alloc.csv")).size(), 1u + 1010u);
}

}  // namespace
}  // namespace cobra::components
