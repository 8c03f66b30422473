// Unit tests of operations (operation.hpp and Component::call): registration from lambdas and
// member functions, calls by name with conversions, error messages, text calls, failures, and
// the thread an operation runs in.

#include <gtest/gtest.h>

#include "cobra/test_support/test_support.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"

namespace cobra::core {
namespace {

using cobra::test_support::messageOf;
using cobra::test_support::waitUntil;

using namespace std::chrono_literals;

class Calc : public Component {
 public:
  explicit Calc(std::string name = "Calc") : Component(std::move(name), Role::Calculation, "arithmetic") {
    addOperation("add", std::function<double(double, double)>([](double a, double b) { return a + b; }), "a + b")
        .arg("a", "m", "first")
        .arg("b", "m", "second");
    addOperation("greet", std::function<std::string(std::string)>([](std::string who) { return "hello " + who; }),
                 "greets");
    addOperation("scale", &Calc::scale, this, "multiplies the stored value").arg("factor", "1", "scale factor");
    addOperation("reset", &Calc::reset, this, "sets the stored value to 0");
    addOperation("total", &Calc::total, this, "the stored value", ExecutionThread::Client);
    addOperation("fail", std::function<void(int)>([](int code) { throw std::runtime_error("code " + std::to_string(code)); }),
                 "always throws")
        .arg("code", "1", "error code");
    addOperation("failOddly", std::function<void()>([] { throw 42; }), "throws a non-standard exception");
    addOperation("refuse", std::function<void()>([this] { throw Error("component '" + this->name() + "': not now"); }),
                 "throws a cobra error");
  }
  double value = 1.0;

 private:
  void scale(double factor) { value *= factor; }
  void reset() { value = 0.0; }
  double total() { return value; }
};

// --- registration and calls -------------------------------------------------------------------

TEST(Operation, SignatureShowsTypesNamesAndUnits) {
  Calc c;
  EXPECT_EQ(c.operation("add").signature(), "double add(double a [m], double b [m])");
  EXPECT_EQ(c.operation("greet").signature(), "string greet(string)");
  EXPECT_EQ(c.operation("scale").signature(), "void scale(double factor [1])");
  EXPECT_EQ(c.operation("reset").signature(), "void reset()");
  EXPECT_EQ(c.operation("add").where(), "component 'Calc': operation 'double add(double a [m], double b [m])'");
  EXPECT_EQ(c.operation("add").doc(), "a + b");
  EXPECT_EQ(c.operation("add").resultType()->name, "double");
  EXPECT_EQ(c.operation("reset").resultType(), nullptr);
  EXPECT_EQ(c.operation("add").thread(), ExecutionThread::Own);
  EXPECT_EQ(c.operation("total").thread(), ExecutionThread::Client);
  ASSERT_EQ(c.operation("add").arguments().size(), 2U);
  EXPECT_EQ(c.operation("add").arguments()[1].doc, "second");
}

TEST(Operation, LambdaCalledByName) {
  Calc c;
  EXPECT_EQ(c.call<double>("add", 1.5, 2.25), 3.75);
}

TEST(Operation, MemberFunctionsCalledByName) {
  Calc c;
  c.call("scale", 4.0);
  EXPECT_EQ(c.value, 4.0);
  EXPECT_EQ(c.call<double>("total"), 4.0);
  c.call("reset");
  EXPECT_EQ(c.value, 0.0);
}

TEST(Operation, IntWidensToADoubleAndCharPointerBecomesAString) {
  Calc c;
  EXPECT_EQ(c.call<double>("add", 1, 2), 3.0);
  EXPECT_EQ(c.call<double>("add", 1, 0.5), 1.5);
  EXPECT_EQ(c.call<std::string>("greet", "world"), "hello world");
  const char* who = "you";
  EXPECT_EQ(c.call<std::string>("greet", who), "hello you");
  EXPECT_EQ(c.call<std::string>("greet", std::string("me")), "hello me");
}

TEST(Operation, InvokeWithAnyArguments) {
  Calc c;
  const std::any result = c.operation("add").invoke({std::any(2.0), std::any(3)});
  EXPECT_EQ(std::any_cast<double>(result), 5.0);
  EXPECT_FALSE(c.operation("reset").invoke({}).has_value());
}

TEST(Operation, DuplicateNamesAndExtraArgumentNamesAreRefused) {
  class Twice : public Component {
   public:
    Twice() : Component("Twice", Role::Calculation, "") {
      addOperation("f", std::function<void()>([] {}), "");
      msg = messageOf([this] { addOperation("f", std::function<void()>([] {}), ""); });
      extra = messageOf([this] { operation("f").arg("x", "m", ""); });
    }
    std::string msg;
    std::string extra;
  };
  Twice t;
  EXPECT_CONTAINS(t.msg, "component 'Twice' already has an operation named 'f'");
  EXPECT_CONTAINS(t.extra, "operation 'void f()' has 0 argument(s), all already named; cannot add 'x'");
}

TEST(Operation, UnknownOperationListsTheExistingOnes) {
  Calc c;
  const std::string msg = messageOf([&] { c.call("sub", 1.0); });
  EXPECT_CONTAINS(msg, "component 'Calc' has no operation 'sub'");
  EXPECT_CONTAINS(msg, "its operations are: add, greet, scale, reset, total, fail, failOddly, refuse");
  EXPECT_EQ(c.findOperation("sub"), nullptr);
}

// --- errors -----------------------------------------------------------------------------------

TEST(Operation, WrongArityNamesTheSignatureAndCounts) {
  Calc c;
  const std::string msg = messageOf([&] { (void)c.call<double>("add", 1.0); });
  EXPECT_CONTAINS(msg, "component 'Calc'");
  EXPECT_CONTAINS(msg, "double add(double a [m], double b [m])");
  EXPECT_CONTAINS(msg, "expects 2 argument(s), got 1");
  EXPECT_CONTAINS(messageOf([&] { c.call("reset", 1); }), "expects 0 argument(s), got 1");
}

TEST(Operation, WrongArgumentTypeNamesIndexNameAndExpectedType) {
  Calc c;
  const std::string msg = messageOf([&] { (void)c.call<double>("add", 1.0, "two"); });
  EXPECT_CONTAINS(msg, "component 'Calc'");
  EXPECT_CONTAINS(msg, "double add(double a [m], double b [m])");
  EXPECT_CONTAINS(msg, "argument 2 ('b') must be a double, got a string");
  const std::string unnamed = messageOf([&] { (void)c.call<std::string>("greet", 3); });
  EXPECT_CONTAINS(unnamed, "argument 1 must be a string, got a int");
  EXPECT_CONTAINS(messageOf([&] { (void)c.call<double>("add", true, 1.0); }), "argument 1 ('a') must be a double, got a bool");
}

TEST(Operation, WrongResultTypeIsReported) {
  Calc c;
  EXPECT_CONTAINS(messageOf([&] { (void)c.call<int>("add", 1.0, 2.0); }), "returns double, not int");
  EXPECT_CONTAINS(messageOf([&] { (void)c.call<double>("reset"); }), "returns void, not double");
}

TEST(Operation, InvokeFromTextParsesArgumentsAndPrintsTheResult) {
  Calc c;
  EXPECT_EQ(c.operation("add").invokeFromText({"1.5", " 2 "}), "3.5");
  EXPECT_EQ(c.operation("greet").invokeFromText({"text with spaces"}), "hello text with spaces");
  EXPECT_EQ(c.operation("scale").invokeFromText({"3"}), "");
  EXPECT_EQ(c.value, 3.0);
}

TEST(Operation, InvokeFromTextReportsParseErrorsAndArity) {
  Calc c;
  const std::string msg = messageOf([&] { (void)c.operation("add").invokeFromText({"1", "two"}); });
  EXPECT_CONTAINS(msg, "component 'Calc': operation 'double add(double a [m], double b [m])'");
  EXPECT_CONTAINS(msg, "argument 2 ('b') must be a double: cannot read \"two\"; expected a number, e.g. 1.5");
  EXPECT_CONTAINS(messageOf([&] { (void)c.operation("add").invokeFromText({"1"}); }), "expects 2 argument(s), got 1");
  EXPECT_CONTAINS(messageOf([&] { (void)c.operation("fail").invokeFromText({"1.5"}); }),
                  "argument 1 ('code') must be a int: cannot read \"1.5\"");
}

TEST(Operation, AThrowingOperationGivesAnErrorAndLeavesTheComponentRunning) {
  Calc c;
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  const std::string msg = messageOf([&] { c.call("fail", 7); });
  EXPECT_CONTAINS(msg, "component 'Calc': operation 'void fail(int code [1])' failed: code 7");
  EXPECT_EQ(c.state(), State::Running);
  EXPECT_EQ(c.lastError(), "");
  EXPECT_CONTAINS(messageOf([&] { c.call("failOddly"); }), "operation 'void failOddly()' failed: unknown exception");
  EXPECT_EQ(c.state(), State::Running);
  EXPECT_EQ(messageOf([&] { c.call("refuse"); }), "component 'Calc': not now") << "cobra errors pass unchanged";
  EXPECT_EQ(c.call<double>("add", 1.0, 1.0), 2.0);
  ASSERT_TRUE(c.stop());
}

// --- execution thread -------------------------------------------------------------------------

/// Records the thread of its updates and operations.
class ThreadProbe : public Component {
 public:
  ThreadProbe() : Component("Probe", Role::Calculation, "records threads") {
    addOperation("own", std::function<int(int)>([this](int x) {
                   own_thread = std::this_thread::get_id();
                   return x + 1;
                 }),
                 "runs in the component's activity");
    addOperation("client", std::function<void()>([this] { client_thread = std::this_thread::get_id(); }),
                 "runs in the caller's thread", ExecutionThread::Client);
  }
  std::thread::id own_thread;
  std::thread::id client_thread;
  std::atomic<std::thread::id> update_thread{};

 protected:
  void updateHook() override { update_thread.store(std::this_thread::get_id()); }
};

TEST(Operation, OwnThreadOperationRunsOnTheEventActivityThread) {
  ThreadProbe p;
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  EXPECT_EQ(p.call<int>("own", 41), 42);
  ASSERT_TRUE(waitUntil([&] { return p.update_thread.load() != std::thread::id(); }));
  EXPECT_NE(p.own_thread, std::this_thread::get_id());
  EXPECT_EQ(p.own_thread, p.update_thread.load()) << "the operation ran in the activity thread";
  p.call("client");
  EXPECT_EQ(p.client_thread, std::this_thread::get_id());
  ASSERT_TRUE(p.stop());
}

TEST(Operation, OwnThreadOperationRunsOnThePeriodicActivityThread) {
  ThreadProbe p;
  p.setActivity(std::make_unique<PeriodicActivity>(1ms, 0, Scheduler::Other));
  ASSERT_TRUE(p.configure());
  ASSERT_TRUE(p.start());
  ASSERT_TRUE(waitUntil([&] { return p.update_thread.load() != std::thread::id(); }));
  EXPECT_EQ(p.call<int>("own", 1), 2);
  EXPECT_EQ(p.own_thread, p.update_thread.load());
  EXPECT_NE(p.own_thread, std::this_thread::get_id());
  ASSERT_TRUE(p.stop());
}

TEST(Operation, OwnThreadOperationRunsInTheCallerWhenNoThreadSteps) {
  ThreadProbe p;
  p.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  EXPECT_EQ(p.call<int>("own", 1), 2);  // PreOperational: the activity thread is not running
  EXPECT_EQ(p.own_thread, std::this_thread::get_id());
  ThreadProbe slave;  // default SlaveActivity: no thread of its own
  ASSERT_TRUE(slave.configure());
  ASSERT_TRUE(slave.start());
  EXPECT_EQ(slave.call<int>("own", 1), 2);
  EXPECT_EQ(slave.own_thread, std::this_thread::get_id());
  ASSERT_TRUE(slave.stop());
}

TEST(Operation, AThrowingOwnThreadOperationReportsToTheCaller) {
  Calc c;
  c.setActivity(std::make_unique<EventActivity>(0, Scheduler::Other));
  ASSERT_TRUE(c.configure());
  ASSERT_TRUE(c.start());
  EXPECT_CONTAINS(messageOf([&] { c.call("fail", 3); }), "failed: code 3");
  EXPECT_CONTAINS(messageOf([&] { c.call("failOddly"); }), "failed: unknown exception");
  EXPECT_EQ(c.state(), State::Running);
  EXPECT_EQ(c.call<double>("add", 2, 2), 4.0);
  ASSERT_TRUE(c.stop());
}

}  // namespace
}  // namespace cobra::core
