-- The Puma 260 task (thesis §6.4, Figs. 6.6-6.7) as the task supervisor's rFSM chart: phases A-H,
-- each a state entered where the phase's frame of Fig. 6.6 is taken, so that the run's timeline and
-- Fig. 6.7's letters read A-H. The first four advance on the components' answers (the EtherCAT
-- master's states of Fig. 6.4, the FTSens driver, the trajectory generator); E, F and G on the
-- ContactMonitor's events, i.e. on the measured contact force and the measured tool's distance
-- from the nominal path, never on time.
--   A  at the nest: the drives initialise (encoder initialisation), then the master moves to ready
--   B  at ready: the sensor is tared (tool down, still), Operative, a Cartesian move to C
--   C  at the default task pose: the admittance control is switched in, then the move to D
--   D  at the start pose: the nominal linear trajectory D -> H starts
--   E  contact with the surface (e_contact): the admittance keeps the tool compliant
--   F  pushed off the nominal path (e_off_path): the tool follows the surface
--   G  contact lost (e_contact_lost): the surface has left the path; back to the nominal path
--   H  at the final pose, back on the nominal path (e_on_path, e_motion_done): done
-- Faults: a drive fault or bus error (the master has quick-stopped the drives), the contact force
-- over its limit, an IK or trajectory failure, the tank empty: root.Stopping (the trajectory's stop
-- motion, the admittance holding) then root.SafeStop once the trajectory is at rest. The FTSens
-- silent (e_comm_timeout): root.Holding, the motion stopped, until the sensor is back (the nominal
-- path resumes) or `sensor_hold` s have passed (SafeStop).
-- Stopped with the tool on the surface (from E's e_contact to G's e_contact_lost), the drives not
-- quick-stopped: root.Retreating before SafeStop. A position hold pressed on the surface does not
-- hold still: the commanded pose lies a little inside the surface, the drives' integrators push on
-- against it, and with the ball tip stuck by friction the wrist hunts (stick-slip of joints 4-5,
-- about 2 mrad at 1.4 Hz, 0.3-0.8 mm at the tip). So the tool retreats first, along base z (back
-- along the tool axis, off the convex surface below it), slowly, on a path that needs none of the
-- components that may have failed: position_control (the trajectory straight to the IK: neither
-- the admittance nor the FTSens), the configuration puma260_retreat (0.5 mm/s), the path Retreat
-- (controller.lua: relative to the measured pose). Off the surface the drives hold a set-point
-- they reach. The IK refusing the retreat (it is what failed: held to 0.2 % of its joint speeds it
-- refuses the first step while the wrist hunts), or a switch refused: root.ToReady, the master's
-- own joint-space move to the ready position (no IK; it lifts the tool straight off first). The
-- drives failing, or `retreat_wait` s: SafeStop where the tool is.
local sensor_hold = 1.0    -- s
local stop_wait = 0.5      -- s: longer than the trajectory generator's stop_time
local retreat_wait = 20.0  -- s: the retreat (controller.lua, configurations/puma260_retreat.lua) takes about 7 s
-- s the chart waits for a device's answer in A and B (the drives' encoder initialisation, the
-- master's ready position, the sensor's tare, Operative) before its safe stop, emitting
-- e_drives_timeout or e_sensor_timeout (the run's safe stop names it). The simulated devices
-- answer within 5 s (the move to ready).
local device_timeout = 30

local function call(peer, operation)
  local p = _G[peer]
  if p == nil then error("puma260_task: '" .. peer .. "' is not a peer of the task supervisor") end
  p[operation](p)
end

-- A Cartesian motion along the fixed path `path` (a WaypointPath peer): its path from the measured
-- pose, the trajectory, the motion. Its end (e_motion_done) is the enclosing phase's transition.
local function motion(path)
  return rfsm.state {
    AskingPath = rfsm.state { entry = function() call(path, "askPath") end },
    Generating = rfsm.state { entry = function() call("TrajGen", "askGenerateTraj") end },
    Moving = rfsm.state { entry = function() call("TrajGen", "askStartMove") end },
    rfsm.trans { src = 'initial', tgt = 'AskingPath' },
    rfsm.trans { src = 'AskingPath', tgt = 'Generating', events = { 'e_path_ready@TrajGen' } },
    rfsm.trans { src = 'Generating', tgt = 'Moving', events = { 'e_trajectory_ready@TrajGen' } },
  }
end

local failures = { 'e_drive_fault', 'e_bus_error', 'e_bus_fault', 'e_force_over_limit', 'e_ik_failed', 'e_ik_discontinuity',
                   'e_traj_failed', 'e_tank_empty', 'e_request_refused', 'e_no_data',
                   'e_deploy_failed_position_control', 'e_deploy_failed_compliant_control',
                   -- a component in Exception (the runner's), a non-finite input or command refused
                   'e_component_error', 'e_input_not_finite', 'e_command_not_finite' }
local done = 'e_motion_done@TrajGen'
-- The retreat refused on the way by the IK (what may have failed), its path or trajectory, or a
-- switch: the joint-space move to ready instead. The drives or the master failing: SafeStop.
local ik_failures = { 'e_ik_failed', 'e_ik_discontinuity', 'e_traj_failed', 'e_no_data',
                      'e_deploy_failed_position_control', 'e_configuration_failed@puma260_retreat' }
local retreat_failures = { 'e_drive_fault', 'e_bus_error', 'e_bus_fault', 'e_request_refused', 'e_command_not_finite' }
-- The drives quick-stopped by the master (Fault): nothing can move the tool off the surface.
local drives_stopped = { e_drive_fault = true, e_bus_error = true, e_bus_fault = true }
local in_contact = false  -- the tool on the surface: from E (e_contact) to G (e_contact_lost)
local retreat = false     -- the stop under way ends with the retreat (set when the failure is taken)
-- The failure transitions' effect (rFSM passes the step's events fourth).
local function decideRetreat(_, _, _, events)
  retreat = in_contact
  for _, e in ipairs(events or {}) do
    if drives_stopped[e] then retreat = false end
  end
end

local chart = {
  A_Nest = rfsm.state {
    Initialising = rfsm.state {},
    MovingToReady = rfsm.state { entry = function() call("Puma", "askReady") end },
    rfsm.trans { src = 'initial', tgt = 'Initialising' },
    rfsm.trans { src = 'Initialising', tgt = 'MovingToReady', events = { 'e_initialized@Puma' } },
  },
  B_Ready = rfsm.state {
    Taring = rfsm.state { entry = function() call("FTSens", "tare") end },
    AskingOperative = rfsm.state { entry = function() call("Puma", "askOperative") end },
    MovingToTaskPose = motion("ToTaskPose"),
    rfsm.trans { src = 'initial', tgt = 'Taring' },
    rfsm.trans { src = 'Taring', tgt = 'AskingOperative', events = { 'e_tared@FTSens' } },
    rfsm.trans { src = 'AskingOperative', tgt = 'MovingToTaskPose', events = { 'e_operative@Puma' } },
  },
  C_TaskPose = rfsm.state {
    EnablingAdmittance = rfsm.state { entry = function() emit("e_deploy_compliant_control") end },
    MovingToStartPose = motion("ToStartPose"),
    rfsm.trans { src = 'initial', tgt = 'EnablingAdmittance' },
    rfsm.trans { src = 'EnablingAdmittance', tgt = 'MovingToStartPose', events = { 'e_deployed_compliant_control' } },
  },
  D_StartPose = motion("NominalPath"),
  -- The nominal motion goes on in E, F and G: the trajectory generator keeps moving the reference.
  E_Contact = rfsm.state { entry = function() in_contact = true end },
  F_FollowingSurface = rfsm.state {},
  G_BackToPath = rfsm.state {
    entry = function() in_contact = false end,
    Returning = rfsm.state {},
    OnPath = rfsm.state {},
    Settling = rfsm.state {},  -- the trajectory ended before the tool was back on the path
    rfsm.trans { src = 'initial', tgt = 'Returning' },
    rfsm.trans { src = 'Returning', tgt = 'OnPath', events = { 'e_on_path@Contact' } },
    rfsm.trans { src = 'Returning', tgt = 'Settling', events = { done } },
  },
  H_FinalPose = rfsm.state { entry = function() emit("e_puma_task_done") end },
  Holding = rfsm.state { entry = function() call("TrajGen", "askStopMove") emit("e_puma_holding") end },
  Resuming = motion("NominalPath"),
  Stopping = rfsm.state { entry = function() call("TrajGen", "askStopMove") end },
  -- Off the surface when the IK refused the retreat: the master's own joint-space move (no IK).
  ToReady = rfsm.state { entry = function() call("Puma", "askReady") end },
  -- Off the surface: the trajectory straight to the IK, slow, then 3 mm up from where the tool is.
  Retreating = rfsm.state {
    Switching = rfsm.state { entry = function() emit("e_deploy_position_control") end },
    Slowing = rfsm.state { entry = function() applyConfiguration("puma260_retreat") end },
    Withdrawing = motion("Retreat"),
    rfsm.trans { src = 'initial', tgt = 'Switching' },
    rfsm.trans { src = 'Switching', tgt = 'Slowing', events = { 'e_deployed_position_control' } },
    rfsm.trans { src = 'Slowing', tgt = 'Withdrawing', events = { 'e_configuration_done@puma260_retreat' } },
  },
  SafeStop = rfsm.state { entry = function() emit("e_puma_safe_stop") end },

  rfsm.trans { src = 'initial', tgt = 'A_Nest' },
  rfsm.trans { src = 'A_Nest', tgt = 'B_Ready', events = { 'e_ready_reached@Puma' } },
  rfsm.trans { src = 'B_Ready', tgt = 'C_TaskPose', events = { done } },
  rfsm.trans { src = 'C_TaskPose', tgt = 'D_StartPose', events = { done } },
  rfsm.trans { src = 'D_StartPose', tgt = 'E_Contact', events = { 'e_contact@Contact' } },
  rfsm.trans { src = 'D_StartPose', tgt = 'H_FinalPose', events = { done } },  -- nothing on the path
  rfsm.trans { src = 'E_Contact', tgt = 'F_FollowingSurface', events = { 'e_off_path@Contact' } },
  rfsm.trans { src = 'E_Contact', tgt = 'G_BackToPath', events = { 'e_contact_lost@Contact' } },  -- a touch only
  rfsm.trans { src = 'F_FollowingSurface', tgt = 'G_BackToPath', events = { 'e_contact_lost@Contact' } },
  rfsm.trans { src = 'G_BackToPath.OnPath', tgt = 'H_FinalPose', events = { done } },
  rfsm.trans { src = 'G_BackToPath.Settling', tgt = 'H_FinalPose', events = { 'e_on_path@Contact' } },
  rfsm.trans { src = 'Holding', tgt = 'Resuming', events = { 'e_comm_restored@FTSens' } },
  rfsm.trans { src = 'A_Nest', tgt = 'SafeStop', events = { 'e_after(' .. device_timeout .. ')' },
               effect = function() emit("e_drives_timeout") end },
  rfsm.trans { src = 'B_Ready.Taring', tgt = 'SafeStop', events = { 'e_after(' .. device_timeout .. ')' },
               effect = function() emit("e_sensor_timeout") end },
  rfsm.trans { src = 'B_Ready.AskingOperative', tgt = 'SafeStop', events = { 'e_after(' .. device_timeout .. ')' },
               effect = function() emit("e_drives_timeout") end },
  rfsm.trans { src = 'Holding', tgt = 'SafeStop', events = { 'e_after(' .. sensor_hold .. ')' },
               guard = function() return not in_contact end, effect = function() emit("e_sensor_lost") end },
  rfsm.trans { src = 'Holding', tgt = 'Retreating', events = { 'e_after(' .. sensor_hold .. ')' },
               guard = function() return in_contact end, effect = function() emit("e_sensor_lost") end },
  rfsm.trans { src = 'Resuming', tgt = 'H_FinalPose', events = { done } },
  -- At rest: the stop motion ended, or there was none; at most `stop_wait` s.
  rfsm.trans { src = 'Stopping', tgt = 'SafeStop', guard = function() return not retreat end,
               events = { 'e_motion_stopped@TrajGen', 'e_not_moving@TrajGen', 'e_after(' .. stop_wait .. ')' } },
  rfsm.trans { src = 'Stopping', tgt = 'Retreating', guard = function() return retreat end,
               events = { 'e_motion_stopped@TrajGen', 'e_not_moving@TrajGen', 'e_after(' .. stop_wait .. ')' } },
  rfsm.trans { src = 'Retreating', tgt = 'SafeStop', events = { done } },
  -- The IK refused the retreat (or a switch was refused): the master's own joint-space move to the
  -- ready position instead (no IK, no admittance, no FTSens); the drives down: nothing moves. At
  -- ready (or refused, or the drives down, or `retreat_wait` s): SafeStop.
  rfsm.trans { src = 'Retreating', tgt = 'ToReady', events = ik_failures, pn = 10 },
  rfsm.trans { src = 'Retreating', tgt = 'SafeStop', events = retreat_failures, pn = 10 },
  rfsm.trans { src = 'ToReady', tgt = 'SafeStop',
               events = { 'e_ready_reached@Puma', 'e_request_refused@Puma', 'e_drive_fault', 'e_bus_error', 'e_bus_fault',
                          'e_after(' .. retreat_wait .. ')' } },
  rfsm.trans { src = 'Retreating', tgt = 'SafeStop', events = { 'e_after(' .. retreat_wait .. ')' } },
}
local active = { 'A_Nest', 'B_Ready', 'C_TaskPose', 'D_StartPose', 'E_Contact', 'F_FollowingSurface', 'G_BackToPath',
                 'Holding', 'Resuming' }
for _, state in ipairs(active) do
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'Stopping', events = failures, pn = 10, effect = decideRetreat }
end
for _, state in ipairs({ 'C_TaskPose', 'D_StartPose', 'E_Contact', 'F_FollowingSurface', 'G_BackToPath', 'Resuming' }) do
  chart[#chart + 1] = rfsm.trans { src = state, tgt = 'Holding', events = { 'e_comm_timeout@FTSens' }, pn = 5 }
end

-- The Supervisor runs this when it goes to Exception (a callback failed or ran past its budget):
-- the trajectory's stop motion, the admittance holding the tool.
function exceptionHook() call("TrajGen", "askStopMove") end

return rfsm.state(chart)
