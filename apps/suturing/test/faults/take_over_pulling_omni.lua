-- The surgeon takes over with the Omnis while the Endo Stitch pulls the thread (1.3 s into the
-- first PullThread: the thread tensioned, a few N): through the two-layer coupling the right
-- Omni feels the thread's pull. 1 s into the teleoperation his right hand moves the stylus 8 mm
-- along -y (away from the stick) and 3 mm down (towards the wound: the thread slackens), then
-- turns it 10 degrees about z, a degree every 0.1 s (about 0.17 rad/s: the Endo Stitch's wrist,
-- near where its two representations meet, is not asked to turn faster than its joints go), and
-- from 3 s back the same way (the resumed pull would otherwise turn the wrist back near its
-- joints' velocity limit); 4.5 s into the teleoperation he gives the arms back and the pull
-- resumes.
local active = "suture:root.TeleoperatedMode.TeleoperationActive"
local faults = {
  { on = { state = "suture:root.AutonomousMode.PullThread.Moving" }, after = 1.3,
    call = "Surgeon.say", args = { "e_take_over" } },
}
for k = 0, 20 do  -- turned by 2 s into the teleoperation, turned back by 3 s
  local half = math.rad(k <= 10 and k or 20 - k) / 2  -- rad: half the turn about z (quaternion 0, 0, sin, cos)
  faults[#faults + 1] = { on = { state = active }, after = (k <= 10 and 1 or 2) + 0.1 * k,
                          set = { property = "RightOmni.hand_motion",
                                  value = { 0, -0.008, -0.003, 0, 0, math.sin(half), math.cos(half) } } }
end
faults[#faults + 1] = { on = { state = active }, after = 4.5, call = "Surgeon.say", args = { "e_teleop_done" } }
return faults
