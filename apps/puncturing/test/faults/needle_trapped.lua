-- The freeze lasts 15 s: the needle is still frozen when the surgeon says the cycle is done.
return {
  { on = { time = 0 }, set = { property = "Patient.freeze_duration", value = 15 } },  -- s
}
