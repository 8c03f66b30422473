-- The gain drops to 0 at 0.05 s: the detector never fires, the task never completes.
return {
  { on = { time = 0.05 }, set = { property = "Gain.k", value = 0 } },
}
