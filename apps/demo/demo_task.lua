-- The basic demo's task chart: it watches the detector's events; done 20 ms after the signal fell
-- back under the detector's threshold.
return rfsm.state {
  watching = rfsm.state {},
  above = rfsm.state {},
  below = rfsm.state {},
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'watching' },
  rfsm.trans { src = 'watching', tgt = 'above', events = { 'e_above_threshold' } },
  rfsm.trans { src = 'above', tgt = 'below', events = { 'e_below_threshold' } },
  rfsm.trans { src = 'below', tgt = 'done', events = { 'e_after(0.02)' } },
}
