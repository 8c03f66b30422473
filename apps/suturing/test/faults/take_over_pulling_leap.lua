-- As take_over_pulling_omni.lua with the Leap Motion: the surgeon's right hand, 20 cm above the
-- device (the simulator's scripted hand, LeapSim.right_hand), moves 8 mm along -y and 3 mm down
-- 1 s into the teleoperation, then turns 10 degrees about z, a degree every 0.1 s, and from 3 s
-- back; the arms are given back at 4.5 s. The Leap
-- renders no force (its side's Passivity layer renders and pays nothing): the master's wrench as it
-- arrives over the link (RightLink.linkedSlaveWrench) is what a haptic device would be given.
local active = "suture:root.TeleoperatedMode.TeleoperationActive"
local faults = {
  { on = { state = "suture:root.AutonomousMode.PullThread.Moving" }, after = 1.3,
    call = "Surgeon.say", args = { "e_take_over" } },
}
for k = 0, 20 do  -- turned by 2 s into the teleoperation, turned back by 3 s
  local half = math.rad(k <= 10 and k or 20 - k) / 2
  faults[#faults + 1] = { on = { state = active }, after = (k <= 10 and 1 or 2) + 0.1 * k,
                          set = { property = "LeapSim.right_hand",
                                  value = { 0.050, -0.008, 0.197, 0, 0, math.sin(half), math.cos(half) } } }
end
faults[#faults + 1] = { on = { state = active }, after = 4.5, call = "Surgeon.say", args = { "e_teleop_done" } }
return faults
