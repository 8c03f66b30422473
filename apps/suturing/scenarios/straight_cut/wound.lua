-- The default scenario: a straight 40 mm cut on the phantom's skin along the world's x
-- axis, 6 mm open at its middle; the StitchPlanner's 8 mm spacing and margins give 4 stitches.
-- cut: x, y pairs (m) in the wound frame; wound_pose: the wound frame in the world ({x, y, z, qx, qy,
-- qz, qw}, m: skin z = 0, +z out of the skin); closed_gap (m): the gap every stitch must end below.
return {
  cut = { -0.02, 0.0, 0.02, 0.0 },
  wound_pose = { 0.178, 0.0, 0.06, 0, 0, 0, 1 },
  max_gap = 0.006,
  closed_gap = 0.0005,
  stitches = 4,
}
