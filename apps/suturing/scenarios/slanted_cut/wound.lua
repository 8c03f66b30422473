-- The second scenario: a 36 mm cut slanted -15 degrees from the world's x axis, 5 mm open
-- at its middle: 3 stitches at the 8 mm spacing and margins. Same fields as straight_cut/wound.lua.
-- Its mirror at +15 degrees: slanted_cut_positive.
local a = math.rad(-15)
local h = 0.018
return {
  cut = { -h * math.cos(a), -h * math.sin(a), h * math.cos(a), h * math.sin(a) },
  wound_pose = { 0.178, 0.0, 0.06, 0, 0, 0, 1 },
  max_gap = 0.005,
  closed_gap = 0.0005,
  stitches = 3,
}
