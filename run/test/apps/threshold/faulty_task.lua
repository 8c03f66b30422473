-- The chart of faulty_safe_stop.lua: the heater's component error is its failure (the runner's
-- e_component_error, named with its source).
return rfsm.state {
  working = rfsm.state {},
  stopped = rfsm.state {},
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'working' },
  rfsm.trans { src = 'working', tgt = 'stopped', events = { 'e_component_error@Heater' } },
}
