-- The surgeon takes the needle over in the tissue (with take_over_surgeon.txt: his first reaction
-- is a take-over, e_teleop_done 4 s after it): the needle "near" the rib (forbidden_region.lua's
-- margin, 0.5 s into MoveToTumor), the margin back to 1 mm once he has it; his hand pushes the
-- master 2 mm down (the needle deeper along its line, against the tissue) and turns it 10
-- degrees (hand_motion.lua); the resumed insertion turns the needle back on its way.
--   return dofile(here .. "take_over_in_tissue.lua")(property, position)
-- `property`: the device's scripted hand (a Frame property), `position` (m): the hand's position in it.
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
return function(property, position)
  local faults = dofile(here .. "hand_motion.lua")("needle:root.NeedleTeleoperation.TeleoperationActive", property,
                                                   position)
  faults[#faults + 1] = { on = { state = "needle:root.InsertingNeedles.MoveToTumor" }, after = 0.5,
                          set = { property = "NeedleMonitor.forbidden_margin", value = 0.1 } }    -- m
  faults[#faults + 1] = { on = { state = "needle:root.NeedleTeleoperation" }, after = 0.1,
                          set = { property = "NeedleMonitor.forbidden_margin", value = 0.001 } }  -- m
  return faults
end
