-- The surgeon's hand in a take-over's test (take_over_in_tissue.lua, take_over_on_skin.lua): 1 s
-- into the teleoperation (chart state `active`) it moves the master 2 mm down from `position`
-- (m, in the scripted hand's Frame property `property`), then turns it 10 degrees about z, a
-- degree every 0.1 s (about 0.17 rad/s), and holds it there.
--   local faults = dofile(here .. "hand_motion.lua")(active, property, position)
return function(active, property, position)
  local faults = {}
  for k = 0, 10 do
    local half = math.rad(k) / 2  -- rad: half the turn about z (quaternion 0, 0, sin, cos)
    faults[#faults + 1] = { on = { state = active }, after = 1 + 0.1 * k,
                            set = { property = property, value = { position[1], position[2], position[3] - 0.002, 0, 0,
                                                                   math.sin(half), math.cos(half) } } }
  end
  return faults
end
