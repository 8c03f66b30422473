-- From 0.05 s on, every 10 ms the recorder forgets its samples with a 20 % chance (seed 7): the
-- same periods in every run.
return {
  { on = { time = 0.05 }, every = 0.01, chance = 0.2, seed = 7, call = "Recorder.clear" },
}
