-- Teleoperation with the Omnis (teleop_device = "omni"): the surgeon takes over during the first
-- planned motion, the Endo Stitch about 17 cm above the table (the clutch engages: the tool follows
-- the stylus's motion from there). 1 s later the right Omni's frame drops 13 cm, as if the surgeon
-- pushed the stylus down: the admittance follows it into the phantom (its top 6 cm above the
-- table), the State Validator keeps the last valid set-points (e_state_invalid); 3 s later the frame
-- is back (e_state_valid); 2 s later the surgeon gives the arms back and the procedure goes on.
local over = { 0, 0, 0, 0, 0, 0, 1 }               -- m, quaternion: the Omni's frame as deployed
local inside = { 0, 0, -0.13, 0, 0, 0, 1 }
return {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound.Moving" }, after = 0.5,
    call = "Surgeon.say", args = { "e_take_over" } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 1,
    set = { property = "RightOmni.origin_pose_offset", value = inside } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 4,
    set = { property = "RightOmni.origin_pose_offset", value = over } },
  { on = { state = "suture:root.TeleoperatedMode.TeleoperationActive" }, after = 6,
    call = "Surgeon.say", args = { "e_teleop_done" } },
}
