-- editor_switch.lua's task chart: deployment "first", 20 ms later "second", done 20 ms after that.
return rfsm.state {
  first = rfsm.state { entry = function() emit("e_deploy_first") end },
  second = rfsm.state { entry = function() emit("e_deploy_second") end },
  done = rfsm.state {},
  rfsm.trans { src = 'initial', tgt = 'first' },
  rfsm.trans { src = 'first', tgt = 'second', events = { 'e_after(0.02)' } },
  rfsm.trans { src = 'second', tgt = 'done', events = { 'e_after(0.02)' } },
}
