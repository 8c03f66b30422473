-- A scenario folder's faults file, played without --faults: the gain drops to 0 at 0.05 s.
return {
  { on = { time = 0.05 }, set = { property = "Gain.k", value = 0 } },
}
