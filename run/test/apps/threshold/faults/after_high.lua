-- 0.05 s after the task enters root.high the gain doubles (the run completes all the same), and on
-- the first e_below_threshold the sine's offset is written.
return {
  { on = { state = "task:root.high" }, after = 0.05, set = { property = "Gain.k", value = 2 } },
  { on = { event = "e_below_threshold", source = "Detector" }, set = { property = "Sine.offset", value = 0.5 } },
}
