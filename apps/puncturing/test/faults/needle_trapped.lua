-- The console reports the cycle done while the iceball still holds the needle (5 mm; the needle
-- is released below 2 mm): the pull meets the ice and the chart waits for the thaw.
return {
  { on = { time = 0 }, set = { property = "Cryo.thawed_radius", value = 0.005 } },  -- m
}
