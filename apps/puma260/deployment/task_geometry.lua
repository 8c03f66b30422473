-- The task's geometry (thesis §6.4, Figs. 6.6-6.7), agreed with the world's model
-- (world/puma260.xml). Base frame of the Puma 260 (z up, the DH base of kinematics/puma260.hpp),
-- m and rad. Poses are cobra's Lua frames {x, y, z, qx, qy, qz, qw}.
local down = { 1, 0, 0, 0 }  -- the tool's orientation throughout: Rx(pi), tool z = -base z, tool x = base x
local function pose(x, y, z) return { x, y, z, down[1], down[2], down[3], down[4] } end
return {
  -- The tool: the FTSens (18 mm thick) on the flange, a contact tool with a 5 mm ball tip whose
  -- tip point is 0.10 m beyond the sensor's measuring frame along the flange z axis.
  flange_to_sensor = 0.018,  -- m
  sensor_to_tip = 0.10,      -- m
  ball_radius = 0.005,       -- m
  -- C: the default task pose, 5 cm above D; D -> H: the nominal linear trajectory.
  task_pose = pose(0.35, -0.12, 0.15),   -- C
  start_pose = pose(0.35, -0.12, 0.10),  -- D
  final_pose = pose(0.35, 0.12, 0.10),   -- H
  -- The ready position (Fig. 6.4): the tool down at (0.28, 0, 0.25) m, on the IK branch the task
  -- keeps (shoulder and elbow as at D-H, wrist not flipped), rad.
  ready_joints = { 0.4677, 1.2117, -3.2805, 0.0, -1.0727, -2.6740 },
  -- After a safe stop with the tool on the surface: this far up (base z) from where it stopped, m.
  -- The surface is convex and below the tool, so straight up leaves it; 3 mm clear the 0.1-0.2 mm
  -- the ball sinks in and the 0.6 mm a tare's offset can make, within the joints' reach at D-H.
  retreat = 0.003,
  -- The surface the path meets, unknown to the controller: a cylinder with its axis along base x,
  -- radius 0.08 m, axis at (y, z) = (0, 0.035) m: its top is 15 mm above the path over about 9 cm.
  surface = { radius = 0.08, axis_y = 0.0, axis_z = 0.035 },
}
