-- The simulated world of the puncturing task (thesis §4.3, §4.5.6-4.5.8): the I-SUR robot holding
-- the needle, the UR5 holding the ultrasound probe, the patient (abdomen phantom, needle-tissue
-- interaction, iceball, ultrasound image), the situation awareness (two Decision components), the
-- cryoablation console and the scripted surgeon. Swapping a simulated bridge for a real one changes its component_type
-- here (the sim-only ports trueCartPose, contactWrench, handTarget stay unconnected then).
-- Geometry as apps/puncturing/deployment/puncturing.scene: world z up, table top z = 0, phantom top z = 0.1.
-- Needs the global `scenario` (a folder of apps/puncturing/scenarios).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
local G = dofile(here .. "geometry.lua")
local info = G.preoperative(scenario .. "/preoperative.txt")

initConfigurator({ "cobra_sim", "cobra_monitoring", "cobra_puncturing" }, {
  { peer_name = "ISUR", component_type = "SimulatedISURRobot" },
  { peer_name = "UR5", component_type = "SimulatedUR5Robot" },
  { peer_name = "Patient", component_type = "PatientSimulator" },
  { peer_name = "NeedleMonitor", component_type = "NeedleInsertionMonitor" },
  { peer_name = "USMonitor", component_type = "UltrasoundMonitor" },
  { peer_name = "Surgeon", component_type = "ScriptedSurgeon" },
  { peer_name = "Cryo", component_type = "CryoConsole" },
})
getReferences()

ISUR.base_frame = G.frame(0, -0.05, 1.0)            -- m: the I-SUR base above the table
ISUR.tool_frame = needle_tool_frame                 -- tool z = the needle (puncturing.lua)
ISUR.initial_joints = { 0.00202, 0.00249, 0.204398, 0, 0, 0.85, 0.55, 0 }  -- m, rad: needle 10 deg from vertical at (-0.05, 0.05, 0.26) m, out of the probe's way; q6 - q7 = 0.3 rad, which the IK keeps (pitch share): with 0 the delta cannot bring the needle down to the skin without turning the base a half turn
UR5.base_frame = G.frame(0.3, -0.5, 0, 0, 0, math.pi / 2)
UR5.tool_frame = G.frame(0, 0, 0.12)                 -- m: the probe's face, z = the beam
UR5.initial_joints = { 0.798, -1.4495, -1.714, 1.5925, -1.571, -2.344 }  -- rad: probe down at (0.2, -0.25, 0.3) m, elbow up (the other elbow laid the upper arm on the phantom)
Patient.scenario_file = scenario .. "/phantom.txt"
Patient.phantom_pose = info.abdomen
Patient.tip_to_needle = G.frame(0, 0, 0)             -- ISUR's tool frame already has z along the needle
Patient.freeze_time_constant = 5                     -- s: the iceball grows and thaws fast (a
Patient.thaw_time_constant = 8                       -- s  simulation speed-up of a 10-minute cycle)
Patient.hold_stiffness = 3000                        -- N/m: the ice holds the needle through the tissue's
                                                     -- elasticity; 2e4 makes the insertion admittance's
                                                     -- coupled loop ring with the servo lag (unstable)
Patient.freeze_duration = 0                          -- s: the patient freezes until the console thaws it
-- The console (asked by the needle chart in WaitCryoCycle; needle_robot.lua wires its events):
-- 5 s of freezing grow the iceball to 9.5 mm; it reports the thaw at 1.5 mm, below the patient's
-- 2 mm release radius, about 15 s later, so the extraction check finds the needle free.
Cryo.freeze_duration = 5                             -- s
Cryo.thawed_radius = 0.0015                          -- m
NeedleMonitor.needle_axis = { 0, 0, 1 }
NeedleMonitor.forbidden_regions = G.regionsInWorld(info)
NeedleMonitor.forbidden_margin = 0.001               -- m
NeedleMonitor.extraction_threshold = 4               -- N: the 6 mm test pull against the ice gives about 6 N
NeedleMonitor.release_force = 1                      -- N
USMonitor.contact_lost_time = 0.2                    -- s: the force dips while the probe's reference moves
-- surgeon_file: a test's script; `interactive` (cobra run --interactive): a person gives the
-- surgeon's events with cobra studio's buttons, so the script says nothing.
Surgeon.script_file = surgeon_file or (interactive and here .. "../interactive_surgeon.txt" or scenario .. "/surgeon.txt")
-- m/s, rad/s: the robots' joint velocity limits (the simulated servos' defaults, stated here because
-- the procedure runner's joint-jump check reads them: apps/puncturing/README.md, Fidelity).
ISUR.max_velocity = { 0.1, 0.1, 0.1, 1.5, 1.5, 1.5, 1.5, 1.5 }
UR5.max_velocity = { 3.14, 3.14, 3.14, 3.14, 3.14, 3.14 }

local world = { "ISUR", "UR5", "Patient", "NeedleMonitor", "USMonitor", "Surgeon", "Cryo" }
local activities = {}
for _, name in ipairs(world) do activities[#activities + 1] = { peer_name = name, period = 0.001 } end
setActivities(activities)
connectPorts({
  { output = "ISUR.trueCartPose", input = "Patient.needleTipPose" },
  { output = "UR5.trueCartPose", input = "Patient.probePose" },
  { output = "Patient.needleWrench", input = "ISUR.contactWrench" },
  { output = "Patient.probeWrench", input = "UR5.contactWrench" },
  { output = "ISUR.measWrench", input = "NeedleMonitor.measWrench" },
  { output = "ISUR.measCartPose", input = "NeedleMonitor.measCartPose" },
  { output = "Patient.needlePlaneDistance", input = "USMonitor.needlePlaneDistance" },
  { output = "Patient.needleInImage", input = "USMonitor.needleInImage" },
  { output = "Patient.probeContactForce", input = "USMonitor.probeContactForce" },
  { output = "Cryo.freezeCommand", input = "Patient.freezeCommand" },
  { output = "Patient.iceballRadius", input = "Cryo.iceballRadius" },
})
configureComponents(world)
startComponents(world)
