-- The probe scan's task chart (rFSM), run by the task Supervisor TaskSup. Like every task chart
-- of cobra it knows no port, gain or pose: each motion state asks the deployment supervisor for
-- the deployment that provides its path (e_deploy_<name>) and the configuration supervisor for how
-- fast to follow it (e_configure_<name>), then asks its peers for services (void requests answered
-- by events): the path source `askPath`, the trajectory generator `askGenerateTraj`, `askStartMove`.
--
--   Approach --e_motion_done--> Scan --e_motion_done--> Retreat --e_motion_done--> Done
--   any failure (a refused command, a failed switch or trajectory, no measured pose) --> Failed

-- A motion: switch deployment and configuration, then path -> trajectory -> move.
local function motion(deployment, configuration, path_source)
  local want = {}  -- the answers of the two supervisors still awaited
  return rfsm.state {
    Switching = rfsm.state { entry = function()
      want = { ["e_deployed_" .. deployment] = true, ["e_configured_" .. configuration] = true }
      emit("e_deploy_" .. deployment)
      emit("e_configure_" .. configuration)
    end },
    AskingPath = rfsm.state { entry = function() _G[path_source]:askPath() end },
    Generating = rfsm.state { entry = function() TrajGen:askGenerateTraj() end },
    Moving = rfsm.state { entry = function() TrajGen:askStartMove() end },

    rfsm.trans { src = 'initial', tgt = 'Switching' },
    rfsm.trans { src = 'Switching', tgt = 'AskingPath', guard = function(_, events)
      for _, e in ipairs(events) do want[e] = nil end
      return next(want) == nil
    end },
    rfsm.trans { src = 'AskingPath', tgt = 'Generating', events = { 'e_path_ready' } },  -- TrajGen has the path
    rfsm.trans { src = 'Generating', tgt = 'Moving', events = { 'e_trajectory_ready' } },
  }
end

local failures = { 'e_ik_discontinuity', 'e_ik_failed', 'e_traj_failed', 'e_no_data' }
for _, name in ipairs({ 'approach', 'scan', 'retreat' }) do failures[#failures + 1] = 'e_deploy_failed_' .. name end
for _, name in ipairs({ 'fast', 'slow' }) do failures[#failures + 1] = 'e_configure_failed_' .. name end

-- The Supervisor runs this when it goes to Exception (a callback failed or ran past its budget):
-- the generator stops and the robot holds its last command.
function exceptionHook() TrajGen:askStopMove() end

return rfsm.state {
  Approach = motion("approach", "fast", "ApproachPath"),  -- above the part's first scan line
  Scan = motion("scan", "slow", "ScanPath"),              -- the raster, at scanning speed
  Retreat = motion("retreat", "fast", "RetreatPath"),     -- back to where the robot started
  Done = rfsm.state { entry = function() emit("e_scan_done") end },
  -- The robot holds its last valid command (the simulated UR5 refuses what it cannot follow
  -- continuously); the generator is stopped and the task ends here, saying so.
  Failed = rfsm.state { entry = function() TrajGen:askStopMove() emit("e_scan_failed") end },

  rfsm.trans { src = 'initial', tgt = 'Approach' },
  rfsm.trans { src = 'Approach', tgt = 'Scan', events = { 'e_motion_done' } },
  rfsm.trans { src = 'Scan', tgt = 'Retreat', events = { 'e_motion_done' } },
  rfsm.trans { src = 'Retreat', tgt = 'Done', events = { 'e_motion_done' } },
  rfsm.trans { src = 'Approach', tgt = 'Failed', events = failures },
  rfsm.trans { src = 'Scan', tgt = 'Failed', events = failures },
  rfsm.trans { src = 'Retreat', tgt = 'Failed', events = failures },
}
