-- The test application's task chart: done once the signal has gone above the threshold and back.
return rfsm.state {
  waiting = rfsm.state {},
  high = rfsm.state {},
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'waiting' },
  rfsm.trans { src = 'waiting', tgt = 'high', events = { 'e_above_threshold' } },
  rfsm.trans { src = 'high', tgt = 'done', events = { 'e_below_threshold' } },
}
