// Boost.MSM: three states cycling on three events, each transition with a functor guard.
#include "statechart_msm_peer.hpp"

#include <boost/msm/back/state_machine.hpp>
#include <boost/msm/front/functor_row.hpp>
#include <boost/msm/front/state_machine_def.hpp>

namespace {

namespace msm = boost::msm;
namespace mpl = boost::mpl;
struct EvAB {};
struct EvBSlow {};
struct EvSlowA {};
struct Always {
  template <class Event, class Fsm, class Source, class Target>
  bool operator()(const Event&, Fsm&, Source&, Target&) const {
    return true;
  }
};
struct Front : msm::front::state_machine_def<Front> {
  struct A : msm::front::state<> {};
  struct B : msm::front::state<> {};
  struct Slow : msm::front::state<> {};
  using initial_state = A;
  using none = msm::front::none;
  struct transition_table
      : mpl::vector<msm::front::Row<A, EvAB, B, none, Always>, msm::front::Row<B, EvBSlow, Slow, none, Always>,
                    msm::front::Row<Slow, EvSlowA, A, none, Always>> {};
};

}  // namespace

struct MsmPeer : msm::back::state_machine<Front> {};

MsmPeer* msmCreate() {
  auto* m = new MsmPeer();
  m->start();
  return m;
}

void msmDispatch(MsmPeer* m, int event) {
  switch (event) {
    case 0: m->process_event(EvAB{}); break;
    case 1: m->process_event(EvBSlow{}); break;
    default: m->process_event(EvSlowA{}); break;
  }
}

void msmDestroy(MsmPeer* m) { delete m; }
