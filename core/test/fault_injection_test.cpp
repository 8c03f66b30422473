// Fault injection (fault_injection.hpp): an injected update exception is thrown by the named
// component's next update, once, in place of its updateHook, and handled as a real throw
// (Exception, lastError, e_exception@<name>); other components step on; an injection a component
// never throws dies with it.

#include "cobra/core/fault_injection.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

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

}  // namespace
}  // namespace cobra::core
