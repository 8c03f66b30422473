-- The task chart of force_sample_run.lua: done after 1 s of filtering (simulated time).
return rfsm.state {
  filtering = rfsm.state {},
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'filtering' },
  rfsm.trans { src = 'filtering', tgt = 'done', events = { 'e_after(1)' } },
}
