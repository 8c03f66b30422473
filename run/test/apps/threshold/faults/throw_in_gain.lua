-- The gain's updateHook throws 0.05 s into the run (an injected bug): the gain goes to
-- Exception (e_exception@Gain) and the run ends with a component error.
return {
  { on = { time = 0.05 }, throw = "Gain" },
}
