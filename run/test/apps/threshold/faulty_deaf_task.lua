-- A chart of faulty_safe_stop.lua that has a safe stop but does not react to a component error.
return rfsm.state {
  working = rfsm.state {},
  stopped = rfsm.state {},
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'working' },
  rfsm.trans { src = 'working', tgt = 'stopped', events = { 'e_stop' } },
}
