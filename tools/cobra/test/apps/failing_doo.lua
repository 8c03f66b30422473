-- cobra fsm run stops at a failing callback (tools/cobra/CMakeLists.txt, cli_fsm_run_*): on e_go
-- the chart enters `failing`, whose doo calls a function that does not exist.
return rfsm.state {
  waiting = rfsm.state {},
  failing = rfsm.state { doo = function() undefined_action() end },
  rfsm.trans { src = 'initial', tgt = 'waiting' },
  rfsm.trans { src = 'waiting', tgt = 'failing', events = { 'e_go' } },
}
