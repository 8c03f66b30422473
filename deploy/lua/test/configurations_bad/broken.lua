return {
  Sine = {
    frequency = function() return 1 end,
  },
}
