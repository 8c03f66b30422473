-- Suturing, teleoperation: both arms driven by the two-layer coupling to the surgeon's devices,
-- the admittance of ../admittance/teleoperation.lua on each arm (next to no translational stiffness).
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
local teleoperation = dofile(here .. "../admittance/teleoperation.lua").Admittance
return { RightAdmittance = teleoperation, LeftAdmittance = teleoperation }
