-- A state the task chart does not have (root.hihg for root.high): it would never fire.
return {
  { on = { state = "task:root.hihg" }, set = { property = "Gain.k", value = 2 } },
}
