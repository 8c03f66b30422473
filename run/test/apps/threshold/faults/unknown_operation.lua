-- An operation the component does not have.
return {
  { on = { state = "task:root.high" }, call = "Sine.strat" },
}
