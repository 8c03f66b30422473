-- At 50 ms a spike of 2 is written on the sine's output (the detector fires at once, the sine's
-- next sample brings the signal back down); at 60 ms the recorder is cleared by its operation.
return {
  { on = { time = 0.05 }, write = { port = "Sine.out", value = 2.0 } },
  { on = { time = 0.06 }, call = "Recorder.clear" },
}
