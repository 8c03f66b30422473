-- The surgeon takes the needle over in the tissue (with take_over_surgeon.txt: his first reaction
-- is a take-over, e_teleop_done 4 s after it): the needle "near" the rib (forbidden_region.lua's
-- margin, 0.5 s into MoveToTumor), the margin back to 1 mm once he has it. 1 s into the
-- teleoperation his hand pushes the master 2 mm down (the needle deeper along its line, against
-- the tissue), then turns it 10 degrees about z, a degree every 0.1 s (about 0.17 rad/s), and
-- holds it there; the resumed insertion turns the needle back on its way.
--   return dofile(here .. "take_over_in_tissue.lua")(property, position)
-- `property`: the device's scripted hand (a Frame property), `position` (m): the hand's position
-- in it, pushed down.
return function(property, position)
  local active = "needle:root.NeedleTeleoperation.TeleoperationActive"
  local faults = {
    { on = { state = "needle:root.InsertingNeedles.MoveToTumor" }, after = 0.5,
      set = { property = "NeedleMonitor.forbidden_margin", value = 0.1 } },   -- m
    { on = { state = "needle:root.NeedleTeleoperation" }, after = 0.1,
      set = { property = "NeedleMonitor.forbidden_margin", value = 0.001 } }, -- m
  }
  for k = 0, 10 do
    local half = math.rad(k) / 2  -- rad: half the turn about z (quaternion 0, 0, sin, cos)
    faults[#faults + 1] = { on = { state = active }, after = 1 + 0.1 * k,
                            set = { property = property, value = { position[1], position[2], position[3], 0, 0,
                                                                   math.sin(half), math.cos(half) } } }
  end
  return faults
end
