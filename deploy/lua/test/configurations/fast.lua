-- A configuration as a Lua table: property values per component (ARCHITECTURE §6).
return {
  Sine = {
    frequency = 20.0,  -- Hz
    amplitude = 2,
  },
  Amp = { k = 0.5 },
}
