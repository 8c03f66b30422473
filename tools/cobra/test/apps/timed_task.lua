-- A task chart for `cobra fsm run --until` (tools/cobra/CMakeLists.txt): it asks a peer for a goal
-- on entry, moves on its answer, and gives up after 1.5 s without the next one (e_after).
return rfsm.state {
  asking = rfsm.state { entry = function() Frames:askCurrentGoal() emit("e_asked") end },
  moving = rfsm.state { entry = function() emit("e_moving") end },
  timed_out = rfsm.state { entry = function() emit("e_timeout") end },
  rfsm.trans { src = 'initial', tgt = 'asking' },
  rfsm.trans { src = 'asking', tgt = 'moving', events = { 'e_goal_ready' } },
  rfsm.trans { src = 'moving', tgt = 'timed_out', events = { 'e_after(1.5)' } },
}
