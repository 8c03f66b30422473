-- The simulated world of the suturing task (thesis §5.1-5.3): the two-armed I-SUR (right arm: the
-- Endo Stitch, left arm: a gripper holding a stick) and the patient, a planar wound in a two-layer
-- phantom with the thread (WoundSimulator). Swapping a simulated bridge for a real one changes its
-- component_type here (the sim-only ports true*CartPose stay unconnected then).
-- Geometry as apps/suturing/deployment/suturing.scene: world z up, table top z = 0, the I-SUR's base 1 m
-- above it; the phantom (0.06 m high) placed under the wound (suturing.lua: phantom_pose).
-- Needs the globals `wound` (the scenario's wound.lua), `right_tool_frame`, `left_tool_frame`
-- (suturing.lua, from frames.lua).
-- The surgeon's console (the puncturing task's ScriptedSurgeon): its say(event) operation gives the
-- surgeon's decisions (e_take_over, e_teleop_done, e_recover) to the chart; its script is empty
-- unless `surgeon_file` names one.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
initConfigurator({ "cobra_sim", "cobra_puncturing" }, {
  { peer_name = "ISUR", component_type = "SimulatedISURSuturingRobot" },
  { peer_name = "Patient", component_type = "WoundSimulator" },
  { peer_name = "Surgeon", component_type = "ScriptedSurgeon" },
})
getReferences()

ISUR.base_frame = { 0, 0, 1.0, 0, 0, 0, 1 }         -- m: as the suturing scene's `robot isur ... base`
ISUR.right_tool_frame = right_tool_frame             -- the Endo Stitch's tip (frames.lua)
ISUR.left_tool_frame = left_tool_frame               -- the stick's tip (frames.lua)
-- m, rad: the Endo Stitch 11.5 cm above the phantom over the cut's middle, tilted 21 deg from the
-- vertical (its pitch share q6 + q7 = 1.2 rad: away from the vertical, where its wrist's two
-- representations meet); the stick's tip 9 cm above the skin, 3 cm behind and 5 cm left of the
-- Endo Stitch's (frames.lua's tool frames): clear of the Endo Stitch (apps/suturing/deployment/suturing.scene's
-- stick; a start over the cut put the stick 3.6 mm from it); the first motion, planned, takes the
-- stick aside (state_table.txt, MoveOverWound).
ISUR.initial_joints = { 0.0997079, 0.0995231, 0.0998925, 0, 0, 0.75, 0.45, 0,
                        -0.0755758, 1.01212, -0.823385, 0.541061, -0.755379, 0.171985 }
-- m/s, rad/s: the joints' velocity limits (the simulated servos' defaults, stated here because the
-- runner's joint-jump check reads them): the delta's three sliders, then eleven revolute joints.
ISUR.max_velocity = { 0.1, 0.1, 0.1, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5 }
Patient.cut = wound.cut
Patient.wound_pose = wound.wound_pose
Patient.max_gap = wound.max_gap
Patient.closed_gap = wound.closed_gap

Surgeon.script_file = surgeon_file or (here .. "surgeon.txt")

local world = { "ISUR", "Patient", "Surgeon" }
setActivities({ { peer_name = "ISUR", period = 0.001 }, { peer_name = "Patient", period = 0.001 },
                { peer_name = "Surgeon", period = 0.001 } })
connectPorts({
  { output = "ISUR.trueRightCartPose", input = "Patient.toolTipPose" },
  { output = "ISUR.trueLeftCartPose", input = "Patient.stickTipPose" },
  { output = "ISUR.endoStitchActuations", input = "Patient.endoStitchActuations" },
  -- The thread pulls on the Endo Stitch and, while hooked, on the stick (each arm's sensor measures
  -- it about its tool point, its admittance gives way).
  { output = "Patient.toolWrench", input = "ISUR.contactRightWrench" },
  { output = "Patient.stickWrench", input = "ISUR.contactLeftWrench" },
})
configureComponents(world)
startComponents(world)
