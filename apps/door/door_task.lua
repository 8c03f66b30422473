-- The "door task" of the thesis (§2.2, Fig. 2.5) as the task supervisor's rFSM chart. Each state
-- asks the deployment supervisor for the deployment that provides its actions (e_deploy_<name>)
-- and the configuration supervisor for how to perform them (e_configure_<name>); the task
-- advances on the events of the Decision components (ThresholdDetectors named AtHandle, Gripped,
-- Unlatched, DoorOpen). It knows nothing of ports, gains or forces: that is the point.

local function ask(deployment, configuration)
  return function()
    emit("e_deploy_" .. deployment)
    if configuration then emit("e_configure_" .. configuration) end
  end
end

return rfsm.state {
  opening = rfsm.state {
    approach = rfsm.state { entry = ask("approach", "gentle") },
    grasp = rfsm.state { entry = ask("grasp") },
    turn = rfsm.state { entry = ask("turn") },
    pull = rfsm.state { entry = ask("pull") },

    rfsm.trans { src = 'initial', tgt = 'approach' },
    rfsm.trans { src = 'approach', tgt = 'grasp', events = { 'e_above_threshold@AtHandle' } },
    rfsm.trans { src = 'grasp', tgt = 'turn', events = { 'e_above_threshold@Gripped' } },
    rfsm.trans { src = 'turn', tgt = 'pull', events = { 'e_above_threshold@Unlatched' } },
    -- A handle that does not give within 2 s is turned harder: same deployment, firm configuration.
    rfsm.trans { src = 'turn', tgt = 'turn', events = { 'e_after(2)' },
                 effect = function() emit("e_configure_firm") end },
    -- The gripper slipped: grasp again.
    rfsm.trans { src = 'pull', tgt = 'grasp', events = { 'e_below_threshold@Gripped' } },
  },
  release = rfsm.state { entry = ask("release") },
  done = rfsm.state {},
  failed = rfsm.state { entry = function() emit("e_door_task_failed") end },

  rfsm.trans { src = 'initial', tgt = 'opening' },
  rfsm.trans { src = 'opening', tgt = 'release', events = { 'e_above_threshold@DoorOpen' } },
  rfsm.trans { src = 'release', tgt = 'done', events = { 'e_below_threshold@Gripped' } },
  -- Outer transitions win over inner ones: a failed switch ends the task wherever it is.
  rfsm.trans { src = 'opening', tgt = 'failed', events = { 'e_deploy_failed_approach', 'e_deploy_failed_grasp',
                                                          'e_deploy_failed_turn', 'e_deploy_failed_pull' } },
  -- A component in Exception (the runner's e_component_error) or a non-finite set-point the door
  -- refused (e_command_not_finite): the task ends in its safe stop.
  rfsm.trans { src = 'opening', tgt = 'failed', events = { 'e_component_error', 'e_command_not_finite' } },
  rfsm.trans { src = 'release', tgt = 'failed', events = { 'e_component_error', 'e_command_not_finite' } },
}
