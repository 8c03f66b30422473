-- The curved scenario (§5.1: "a curved or slanted cut"): a 36 mm cut along an arc of
-- 80 mm radius bulging towards the stick's side (+y), its direction turning from +12.9 degrees to
-- -12.9 degrees; 5 mm open at its middle: 3 stitches at the 8 mm spacing and margins, each at its
-- own direction. The arc as 9 points of the centreline (the wound model's polyline, each segment
-- 4.5 mm). Same fields as straight_cut/wound.lua.
local radius, length, points = 0.08, 0.036, 9
local cut = {}
for i = 0, points - 1 do
  local phi = (i / (points - 1) - 0.5) * length / radius  -- rad: from the arc's middle
  cut[#cut + 1] = radius * math.sin(phi)
  cut[#cut + 1] = radius * (math.cos(phi) - 1)
end
return {
  cut = cut,
  wound_pose = { 0.178, 0.0, 0.06, 0, 0, 0, 1 },
  max_gap = 0.005,
  closed_gap = 0.0005,
  stitches = 3,
}
