-- Recorder.clear takes no argument.
return {
  { on = { time = 0.01 }, call = "Recorder.clear", args = { 1 } },
}
