-- Teleoperation with the Omnis (teleop_device = "omni"): the surgeon takes over during the first
-- planned motion, the Endo Stitch about 17 cm above the table (the clutch engages: the tool follows
-- the stylus's motion from there). From 1 s on the right Omni's frame sinks 13.2 cm in steps of
-- 4 mm every 0.2 s, as if the surgeon pushed the stylus down and re-clutched: the coupling drags
-- the Endo Stitch's admittance after it, into the phantom (its top 6 cm above the table), where
-- the State Validator keeps the last valid set-points (e_state_invalid); from 8 s on the frame
-- rises back the same way, the set-points are valid again (e_state_valid); at 15.5 s the surgeon
-- gives the arms back and the procedure goes on. (A device jumping by cm in one step would make
-- the coupling's spring pull the tool faster than the robot follows: e_ik_discontinuity.)
local active = "suture:root.TeleoperatedMode.TeleoperationActive"
local faults = {
  { on = { state = "suture:root.AutonomousMode.ApplyRightStitch.MoveOverWound.Moving" }, after = 0.5,
    call = "Surgeon.say", args = { "e_take_over" } },
}
local step, steps = 0.004, 33  -- m
local function offset(after, z)
  faults[#faults + 1] = { on = { state = active }, after = after,
                          set = { property = "RightOmni.origin_pose_offset", value = { 0, 0, z, 0, 0, 0, 1 } } }
end
for k = 1, steps do offset(1 + 0.2 * (k - 1), -step * k) end     -- down
for k = 1, steps do offset(8 + 0.2 * (k - 1), -step * (steps - k)) end  -- and up again
faults[#faults + 1] = { on = { state = active }, after = 15.5, call = "Surgeon.say", args = { "e_teleop_done" } }
return faults
