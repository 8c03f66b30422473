-- The suturing application's tool frames (m, rad): the one place they are given. Each is the
-- frame of a tool's datums (z into the skin, x along the cut: the Frame Generator's) in the robot
-- model's frame of that tool. The robot is commanded and measured in them
-- (deployment/world.lua: ISUR.right_tool_frame, ISUR.left_tool_frame), the planner and the State
-- Validator plan and check in them (deployment/controller.lua: first_tool_frame,
-- second_tool_frame, the frames of the suturing scene's I-SUR tools 0 and 1), so the Frame
-- Generator's goals and the WoundSimulator's tips are the robot's tool poses themselves.
-- Returns { right_tool = frame, left_tool = frame }, frames as cobra's Lua frames {x, y, z, qx, qy, qz, qw}.

-- A frame at x, y, z turned by roll, pitch, yaw (KDL's RPY: R = Rz(yaw) Ry(pitch) Rx(roll)).
local function frame(x, y, z, roll, pitch, yaw)
  local cr, sr = math.cos(roll / 2), math.sin(roll / 2)
  local cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
  local cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
  return { x, y, z, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
           cr * cp * cy + sr * sp * sy }
end

local frames = {}
-- The Endo Stitch: its tip frame has the instrument along its x axis; pointing straight down it
-- would sit where its wrist's two representations meet, so its datum frame holds it 21 deg from
-- the vertical (its initial pitch).
frames.right_tool = frame(0, 0, 0, math.pi, -1.2, 0)
-- The stick the gripper holds: its tip 0.15 m along the gripper's axis (z of the gripper frame;
-- the object `stick` of apps/suturing/deployment/suturing.scene ends there), the gripper leaning LEAN rad
-- from the datum's z, turned TURN rad about its axis (a pose from which the left arm reaches every
-- stick position around a stitch with its stick clear of the Endo Stitch, searched with the split
-- IK and the scene): the datum's rotation in the gripper frame is RotY(-LEAN) * RotZ(TURN).
local function rotYZ(y_angle, z_angle)  -- the quaternion of RotY(y_angle) * RotZ(z_angle)
  local sy, cy, sz, cz = math.sin(y_angle / 2), math.cos(y_angle / 2), math.sin(z_angle / 2), math.cos(z_angle / 2)
  return { sy * sz, sy * cz, cy * sz, cy * cz }
end
local LEAN, TURN = 0.6, -0.6
local q = rotYZ(-LEAN, TURN)
frames.left_tool = { 0, 0, 0.15, q[1], q[2], q[3], q[4] }
return frames
