-- The puncturing application with a studio table whose fixed shapes are wrong in one way each; the
-- global `shape_case` (set by the test before this file runs) picks it (studio/test/bridge_extras_test.cpp).
local here = debug.getinfo(1, "S").source:match("^@(.*/)") or "./"
dofile(here .. "../../../apps/puncturing/puncturing.lua")
local cases = {
  unknown = { tumour_a = { spheres = "Patient.tumor" } },
  type = { tumour_b = { spheres = "Patient.iceball_max_radius" } },
  count = { regions_c = { spheres = "NeedleMonitor.forbidden_regions" } },
  box = { layers_d = { slabs = "Patient.layer_depths", pose = "Patient.phantom_pose", size = "phantm" } },
  frame = { layers_e = { slabs = "Patient.layer_depths", pose = "Patient.tumour", size = { 0.3, 0.2 } } },
  noscene = { layers_f = { slabs = "Patient.layer_depths", pose = "Patient.phantom_pose", size = "phantom" } },
}
run.studio = { scene = shape_case ~= "noscene" and "NeedlePlanner" or nil, extras = cases[shape_case] }
