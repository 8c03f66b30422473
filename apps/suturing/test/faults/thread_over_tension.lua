-- The Endo Stitch pulls the first stitch's thread 8 cm up instead of 3.7 cm: the thread goes past
-- its breaking tension (15 N) and breaks; the chart stops safely.
return {
  { on = { time = 0 }, set = { property = "SutureFrames.pull_offset", value = { 0, 0, 0.08 } } },
}
