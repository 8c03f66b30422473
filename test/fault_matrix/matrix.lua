-- The fault matrix (README.md): every fault x every task x the task's moments. `cobra faults matrix`
-- runs each cell (one lockstep run of the task with the fault played at the moment) and writes
-- docs/fault_matrix.md; the test fault_matrix_runs checks every cell and that the doc is current.
--
-- task "NAME" { app, scenarios (the first is the matrix's; the soak picks any), time_limit (s
--   simulated), moments = { { "NAME", state = "chart:path", after = s }, ... }, hold (ports watched
--   holding; default run.tracking's measured), commands (ports carrying the robots' commands;
--   default run.tracking's commanded) }
-- fault "NAME" { text = "...", TASK = { entries... } or na "why it does not apply", ... } where
--   the entries are faults-file entries without `on` (played `after` s after the cell's moment;
--   one with its own `on` is played then), and a task's list may add: moments = { ... } (only
--   these), before = "Lua run before the entry file", gap = "why its cells are known to fail" (or
--   gap = { MOMENT = "why", ... }: the cells of those moments only).
-- `root` is the repository (absolute).

-- Tasks -------------------------------------------------------------------------------------------

task "puncturing" {
  app = "apps/puncturing",
  scenarios = { "apps/puncturing/scenarios/two_needles", "apps/puncturing/scenarios/three_needles" },
  time_limit = 400,
  moments = {
    { "approach", state = "needle:root.InsertingNeedles.MoveToSkin.Approach", after = 1.0 },  -- a planned motion
    { "insertion", state = "needle:root.InsertingNeedles.MoveToTumor", after = 0.3 },         -- the needle in tissue
  },
}

task "suturing" {
  app = "apps/suturing",
  time_limit = 300,
  moments = {
    { "over_wound", state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound", after = 0.3 },
    { "pull", state = "suture:root.AutonomousMode.PullThread", after = 0.5 },  -- the thread in tension
  },
}

task "puma260" {
  app = "apps/puma260",
  time_limit = 120,
  moments = {
    { "path", state = "puma:root.D_StartPose", after = 1.0 },              -- free motion on the nominal path
    { "surface", state = "puma:root.F_FollowingSurface", after = 0.2 },    -- the tool in contact
  },
}

task "door" {
  app = "apps/door",
  time_limit = 60,
  moments = {
    { "turn", state = "door:root.opening.turn", after = 0.3 },
    { "pull", state = "door:root.opening.pull", after = 0.1 },
  },
  hold = { "Door.armPosition" },                                          -- m
  -- what the simulated door applies (its set-point sources' samples after its non-finite guard)
  commands = { "Door.appliedArmTarget", "Door.appliedGripCommand", "Door.appliedHandleTorque", "Door.appliedPullForce" },
}

-- Faults ------------------------------------------------------------------------------------------

local no_peer = "one process: no peer to lose (the DDS link exists only when the puncturing task is split over "
  .. "hosts; apps/puncturing/test/split_procedure_test.cpp loses one)"

-- Deployer code reconfiguring a component through its lifecycle with one property changed (a
-- property read at configure): `value` is Lua source.
local function reconfigured(component, property, value)
  return { lua = "stopComponents({'" .. component .. "'}) cleanupComponents({'" .. component .. "'}) "
    .. component .. "." .. property .. " = " .. value .. " "
    .. "configureComponents({'" .. component .. "'}) startComponents({'" .. component .. "'})" }
end
-- Every plan fails: 0.5 m of clearance required.
local function plansFail(planner) return reconfigured(planner, "min_collision_distance", "0.5") end
-- The tank restarted at its floor ε.
local function drained(admittance) return reconfigured(admittance, "tank_initial", admittance .. ".tank_min * 1.001") end

-- The baseline: each task's procedure with nothing played (one cell: at its first moment).
local function nothing(moment) return { { lua = "-- the baseline: nothing is played" }, moments = { moment } } end
fault "none" {
  text = "no fault (the baseline: each procedure as it runs without one)",
  puncturing = nothing("approach"),
  suturing = nothing("over_wound"),
  puma260 = nothing("path"),
  door = nothing("turn"),
}

fault "update_exception" {
  text = "an exception in an update hook (the admittance's; the door's torque set-point)",
  puncturing = { { throw = "NeedleAdmittance" } },
  suturing = { { throw = "RightAdmittance" } },
  puma260 = { { throw = "Admittance" } },
  door = { { throw = "TorqueCmd" }, moments = { "turn" } },
}

-- The wrench's writer stopped, then NaN (inf) written on its output: the admittance's measWrench,
-- a data input, reads it every step from then on.
local function wrench(component, value)
  return { lua = "stopComponents({'" .. component .. "'}) " .. component .. ".outWrench:write({" .. value
    .. ", 0, 0, 0, 0, 0})" }
end

-- NaN or inf (`value`, Lua source) on the admittance's measured wrench; the door's handle torque.
local function nonFinite(name, what, value)
  fault(name) {
    text = what .. " on a pure-data input port (the admittance's measured wrench; the door's handle torque)",
    puncturing = { wrench("NeedleWrench", value) },
    suturing = { wrench("RightWrench", value) },
    puma260 = { wrench("TipToBase", value) },
    door = { { lua = "stopComponents({'TorqueCmd'}) TorqueCmd.out:write(" .. value .. ")" }, moments = { "turn" } },
  }
end
nonFinite("nan_input", "NaN", "0/0")
nonFinite("inf_input", "inf", "math.huge")

fault "sensor_silent" {
  text = "a sensor that stops publishing (the force/torque chain; the door's handle angle)",
  puncturing = { { lua = "stopComponents({'NeedleWrench'})" } },
  suturing = { { lua = "stopComponents({'RightWrench'})" } },
  puma260 = { { call = "FTSensSim.setSilent", args = { true } } },
  door = { { lua = "stopComponents({'Unlatched'})" }, moments = { "turn" } },
}

fault "link_loss" {
  text = "20 % packet loss on a device link (each 1 ms EtherCAT cycle comes back with a wrong working counter "
    .. "with a 20 % chance, seeded)",
  puncturing = na "one process, no bridge: the robots' simulations are components of the run",
  suturing = na "one process, no bridge: the robots' simulations are components of the run",
  puma260 = { { every = 0.001, chance = 0.2, seed = 1, call = "World.injectWorkingCounterFault", args = { 1 } } },
  door = na "the simulated door is a component of the run: no bridge",
}

fault "planner_failure" {
  text = "a planner failure (0.5 m of clearance required: every plan fails; the surgeon recovers)",
  puncturing = { plansFail("NeedlePlanner"),
                 moments = { "approach" } },
  suturing = { plansFail("SuturePlanner"),
               { on = { state = "suture:root.WaitReaction" }, after = 1, call = "Surgeon.say", args = { "e_recover" } } },
  puma260 = na "the Puma 260 follows a fixed waypoint path: no planner",
  door = na "the door task plans nothing",
}

fault "tank_drained" {
  text = "an energy tank drained to epsilon (the admittance restarted with 1.001 tank_min in its tank)",
  puncturing = { drained("NeedleAdmittance") },
  suturing = { drained("RightAdmittance") },
  puma260 = { drained("Admittance") },
  door = na "the door task has no admittance, hence no energy tank",
}

fault "ik_discontinuity" {
  text = "an IK discontinuity (the robot slowed to 0.2 % of its joint speeds: the next command is out of reach)",
  puncturing = { { set = { property = "ISUR.speed_scaling", value = 0.002 } } },
  suturing = { { set = { property = "ISUR.speed_scaling", value = 0.002 } } },
  puma260 = { { set = { property = "Kin.speed_scaling", value = 0.002 } } },
  door = na "the door task's arm is a set-point of the simulated door: no inverse kinematics",
}

fault "drive_fault" {
  text = "a drive fault (over-current in the elbow's drive)",
  puncturing = na "the simulated I-SUR and UR5 have no drive model (joint servos without CiA 402 drives)",
  suturing = na "the simulated I-SUR has no drive model (joint servos without CiA 402 drives)",
  puma260 = { { call = "World.injectFault", args = { 2 } } },
  door = na "the simulated door has no drives",
}

fault "peer_lost" {
  text = "a lost peer host",
  puncturing = na(no_peer),
  suturing = na(no_peer),
  puma260 = na(no_peer),
  door = na(no_peer),
}

fault "silent_surgeon" {
  text = "a surgeon who never answers (after a planner failure asks for a reaction)",
  puncturing = { plansFail("NeedlePlanner"),
                 moments = { "approach" },
                 before = "surgeon_file = [[" .. root .. "/apps/puncturing/test/faults/silent_surgeon.txt]]" },
  suturing = { plansFail("SuturePlanner") },
  puma260 = na "the Puma 260 task asks no surgeon",
  door = na "the door task asks no surgeon",
}
