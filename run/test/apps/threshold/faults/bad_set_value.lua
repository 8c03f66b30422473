-- A value the property cannot take (a word where the gain, a number, is expected).
return {
  { on = { time = 0.5 }, set = { property = "Gain.k", value = "twice" } },
}
