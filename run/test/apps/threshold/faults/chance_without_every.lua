-- A chance without a period: refused.
return {
  { on = { time = 0.05 }, chance = 0.2, call = "Recorder.clear" },
}
