-- A value the port cannot carry (a table where the signal, a number, is expected).
return {
  { on = { time = 0.5 }, write = { port = "Sine.out", value = { 1, 2 } } },
}
