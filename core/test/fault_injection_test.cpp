// Fault injection (fault_injection.hpp): an injected update exception is thrown by the named
// component's next update, once, in place of its updateHook, and handled as a real throw
// (Exception, lastError, e_exception@<name>); other components step on; an injection a component
// never throws dies with it.

#include "cobra/core/fault_injection.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cobra/core/activity.hpp"
#include "cobra/core/component.hpp"
#include "cobra/test_support/test_support.hpp"

namespace cobra::core {
namespace {

class Counting : public Component {
 public:
  explicit Counting(std::string name) : Component(std::move(name), Role::Calculation, "counts its updates") {}
  int updates = 0;

 protected:
  void updateHook() override { ++updates; }
};

void step(Component& c) { dynamic_cast<SlaveActivity&>(c.activity()).step(); }

std::unique_ptr<Counting> running(const std::string& name) {
  auto c = std::make_unique<Counting>(name);
  EXPECT_TRUE(c->configure());
  EXPECT_TRUE(c->start());
  return c;
}

TEST(FaultInjection, TheNamedComponentsNextUpdateThrowsOnceInPlaceOfItsUpdateHook) {
  const auto victim = running("Victim");
  const auto other = running("Other");
  InputPort<Event> events{"watch", "the victim's events", ""};
  connect(victim->events(), events, ConnPolicy::buffer(8));
  step(*victim);
  injectUpdateException(*victim, "injected fault (faults.lua:3)");
  EXPECT_EQ(pendingUpdateExceptions(), 1);
  step(*other);  // another component steps as before
  EXPECT_EQ(other->updates, 1);
  EXPECT_EQ(other->state(), State::Running);
  step(*victim);
  EXPECT_EQ(victim->updates, 1);  // the throw took the update's place
  EXPECT_EQ(victim->state(), State::Exception);
  EXPECT_EQ(victim->lastError(), "component 'Victim': updateHook threw: injected fault (faults.lua:3)");
  Event e;
  ASSERT_EQ(events.read(e), FlowStatus::NewData);
  EXPECT_EQ(e.name, "e_exception@Victim");
  EXPECT_EQ(pendingUpdateExceptions(), 0);
  ASSERT_TRUE(victim->recover());
  ASSERT_TRUE(victim->configure());
  ASSERT_TRUE(victim->start());
  step(*victim);  // once only
  EXPECT_EQ(victim->updates, 2);
  EXPECT_EQ(victim->state(), State::Running);
}

TEST(FaultInjection, AnInjectionTheComponentNeverThrewDiesWithIt) {
  {
    const auto never = running("Never");
    injectUpdateException(*never, "never thrown");
    EXPECT_EQ(pendingUpdateExceptions(), 1);
  }
  EXPECT_EQ(pendingUpdateExceptions(), 0);
  const auto next = running("Next");  // may get the same address: steps as ever
  step(*next);
  EXPECT_EQ(next->state(), State::Running);
  EXPECT_EQ(next->updates, 1);
}

// A fault replayed every period into a component that does not step (stopped) stays one pending
// injection, not one per period; the table's bound is said when reached.
TEST(FaultInjection, RepeatedInjectionsIntoAComponentThatDoesNotStepStayOneAndTheTableIsBounded) {
  const auto stopped = running("Stopped");
  ASSERT_TRUE(stopped->stop());
  for (int period = 0; period < 100; ++period) injectUpdateException(*stopped, "replayed");
  EXPECT_EQ(pendingUpdateExceptions(), 1);
  std::vector<std::unique_ptr<Counting>> others;
  for (int i = 0; i < 15; ++i) {
    others.push_back(running("Other" + std::to_string(i)));
    injectUpdateException(*others.back(), "pending");
  }
  EXPECT_EQ(pendingUpdateExceptions(), 16);
  const auto one_more = running("OneMore");
  try {
    injectUpdateException(*one_more, "no room");
    ADD_FAILURE() << "a 17th pending injection was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "fault injection: 16 update exceptions are pending already (components that do not step "
                           "take none): inject into running components");
  }
  for (const auto& c : others) step(*c);  // each throws its own, freeing its slot
  EXPECT_EQ(pendingUpdateExceptions(), 1);
  injectUpdateException(*one_more, "now there is room");
  step(*one_more);
  EXPECT_EQ(one_more->state(), State::Exception);
  EXPECT_EQ(one_more->updates, 0);
}

}  // namespace
}  // namespace cobra::core
