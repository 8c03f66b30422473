-- The surgeon takes the probe over on the skin (with take_over_probe_surgeon.txt: his first
-- reaction is a take-over, e_teleop_done 4 s after it): 0.5 s after the probe first tracks the
-- needle, the ultrasound monitor's contact_lost_force is raised to 50 N (the probe "loses" the
-- skin: e_probe_contact_lost after its 0.2 s), and back to 1 N once the surgeon has it; his hand
-- pushes the master 2 mm down (the probe into the skin) and turns it 10 degrees
-- (hand_motion.lua); the resumed state presses on again.
--   return dofile(here .. "take_over_on_skin.lua")(property, position)
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return function(property, position)
  local faults = dofile(here .. "hand_motion.lua")("us:root.USTeleoperation.TeleoperationActive", property, position)
  faults[#faults + 1] = { on = { state = "us:root.USPositioned.NeedleTracked" }, after = 0.5,
                          set = { property = "USMonitor.contact_lost_force", value = 50 } }  -- N
  faults[#faults + 1] = { on = { state = "us:root.USTeleoperation" }, after = 0.1,
                          set = { property = "USMonitor.contact_lost_force", value = 1.0 } } -- N
  return faults
end
