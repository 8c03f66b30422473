-- The probe robot driven by the surgeon's master (thesis §4.6, teleoperated): the admittance of
-- deployment/admittance/teleoperation.lua, on ProbeAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { ProbeAdmittance = dofile(here .. "../../admittance/teleoperation.lua").Admittance }
