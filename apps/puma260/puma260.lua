-- The retrofitted Puma 260 task (thesis ch. 6, §6.3-6.4) in simulation: the world
-- (deployment/world.lua), the controller of Fig. 6.5 (deployment/controller.lua) with its one
-- configuration (configurations/puma260_task.lua) and the task chart A-H (charts/puma260_task.lua).
-- Run it with `cobra run apps/puma260` (what `./do demo puma260` does); the `run` table at the end
-- says what ends the run and what to observe (run/README.md).
-- `scenario` may be set before this file runs; default: scenarios/closed_form. A scenario's
-- scenario.lua sets `kinematics_solver`, the one line between the closed-form and the KDL variant
-- (cobra run apps/puma260 --scenario apps/puma260/scenarios/kdl), and may set `world_file`.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
scenario = scenario or (here .. "scenarios/closed_form")
world_file = nil
dofile(scenario .. "/scenario.lua")

dofile(here .. "deployment/" .. (world_file or "world.lua"))
dofile(here .. "deployment/controller.lua")
-- On the wall clock (cobra run --realtime) the real-time executor runs this deployment's schedule
-- every 1 ms on one SCHED_FIFO thread, memory locked; a missed period is an event in the log, and
-- 50 in a row (50 ms without the controllers keeping time) end the run in a safe stop.
setExecutor({ period = 0.001, priority = 80, on_deadline_miss = "event", safe_stop_after = 50 })

local phases = { { "A", "puma:root.A_Nest" }, { "B", "puma:root.B_Ready" }, { "C", "puma:root.C_TaskPose" },
                 { "D", "puma:root.D_StartPose" }, { "E", "puma:root.E_Contact" },
                 { "F", "puma:root.F_FollowingSurface" }, { "G", "puma:root.G_BackToPath" },
                 { "H", "puma:root.H_FinalPose" } }
local failures = { "e_drive_fault", "e_bus_error", "e_bus_fault", "e_force_over_limit", "e_ik_failed", "e_ik_discontinuity",
                   "e_traj_failed", "e_tank_empty", "e_request_refused", "e_no_data", "e_comm_timeout",
                   "e_drives_timeout", "e_sensor_timeout",  -- a device did not answer (charts/puma260_task.lua)
                   "e_component_error", "e_input_not_finite", "e_command_not_finite" }
run = {
  title = "Retrofitted Puma 260: a linear path across an unexpected surface (thesis §6.3-6.4)",
  charts = { { name = "puma", supervisor = "TaskSup", done = "root.H_FinalPose", safe_stop = "root.SafeStop" } },
  fold = { "AskingPath", "Generating", "Moving" },
  failures = failures,
  -- s a component in error has to end in the chart's safe stop: stopped in contact, the chart
  -- retreats first (charts/puma260_task.lua: at most its retreat_wait, 20 s, after the stop).
  safe_stop_linger = 25,
  record = { period = 0.01, ports = { "TrajGen.desCartPose_1", "Admittance.admPose", "Kin.cartPose", "TipToBase.outWrench",
                                      "Admittance.tankEnergy", "Puma.measJointVelocity", table.unpack(world.record) } },
  plots = {
    { title = "Fig. 6.7: nominal and actual tool path in the y-z plane", unit = "m", x_unit = "m",
      paths = {
        { label = "nominal (trajectory generator)", x = "TrajGen.desCartPose_1.y", y = "TrajGen.desCartPose_1.z",
          dashed = true },
        { label = "actual (measured tool tip)", x = "Kin.cartPose.y", y = "Kin.cartPose.z", marks = phases },
      } },
    { title = "Fig. 6.7 from D: the linear path across the surface", unit = "m", x_unit = "m",
      from = "puma:root.D_StartPose",
      paths = {
        { label = "nominal (trajectory generator)", x = "TrajGen.desCartPose_1.y", y = "TrajGen.desCartPose_1.z",
          dashed = true },
        { label = "actual (measured tool tip)", x = "Kin.cartPose.y", y = "Kin.cartPose.z", marks = phases },
      } },
    { title = "Tool tip height: nominal, commanded (admittance) and measured", unit = "m",
      series = { "TrajGen.desCartPose_1.z", "Admittance.admPose.z", "Kin.cartPose.z" } },
    { title = "Measured contact force at the tool tip (base axes)", unit = "N",
      series = { "TipToBase.outWrench.fz", "TipToBase.outWrench.fy" } },
    { title = "Energy tank of the variable admittance", unit = "J", series = { "Admittance.tankEnergy" } },
  },
  summary = {
    { name = "measured tool tip from the nominal path at H", unit = "mm", scale = 1000, say = true,
      distance = { "Kin.cartPose", "TrajGen.desCartPose_1" }, on_enter = "puma:root.H_FinalPose" },
    { name = "contacts", count = { "e_contact" } },
    { name = "faults detected", count = failures },
  },
  tracking = {
    { name = "Puma 260 tool", commanded = "Admittance.admPose", measured = "Kin.cartPose", joints = "Puma.measJointPosition",
      max_velocity = { 2, 2, 2, 2, 2, 2 }, chart = "puma", counts_while = { deployments = { "compliant_control" } } },
  },
  -- cobra studio (studio/README.md): no planning scene (no Puma 260 robot model in the planner): the
  -- arm drawn from the kinematics solver's DH chain (Kin: base frame, the Puma 260's DH table, the
  -- tool frame) at the measured joints, the tool's commanded and measured points, and the contact
  -- surface of the world that has one (deployment/world.lua: the MuJoCo world's cylinder, base frame).
  studio = { robots = { puma = { "Puma.measJointPosition", kinematics = "Kin" } },
             extras = { nominal = { points = "TrajGen.desCartPose_1" }, tool = { points = "Kin.cartPose" },
                        surface = world.surface and { cylinders = world.surface } } },
}
-- The world's ground truth, when it has contact (deployment/world.lua): what the tests check.
if #world.record > 0 then
  run.plots[#run.plots + 1] = { title = "Contact force between the tool and the surface (the world's truth)", unit = "N",
                                series = { "World.contactForce" } }
  run.plots[#run.plots + 1] = { title = "Depth of the tool's ball in the surface (the world's truth)", unit = "m",
                                series = { "World.penetration" } }
end
