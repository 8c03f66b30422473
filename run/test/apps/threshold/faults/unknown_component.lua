-- A misspelt component.
return {
  { on = { time = 0.05 }, set = { property = "Gain.k", value = 2 } },
  { on = { event = "e_above_threshold" }, after = 0.01,
    set = { property = "Gian.k", value = 0 } },
}
