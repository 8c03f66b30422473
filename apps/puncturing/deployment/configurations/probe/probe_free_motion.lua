-- The probe robot's free motion (thesis §4.7, replicated for the UR5): the admittance of
-- deployment/admittance/free_motion.lua, on ProbeAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { ProbeAdmittance = dofile(here .. "../../admittance/free_motion.lua").Admittance }
