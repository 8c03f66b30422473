-- 10 ms after the start the chart enters `stuck`, whose entry says so on stderr and never returns.
return rfsm.state {
  waiting = rfsm.state {},
  stuck = rfsm.state { entry = function()
    io.stderr:write("stuck: looping\n") io.stderr:flush()
    while true do end
  end },
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'waiting' },
  rfsm.trans { src = 'waiting', tgt = 'stuck', events = { 'e_after(0.01)' } },
}
