-- The needle robot's free motion behaviour (thesis §4.7): the admittance of
-- deployment/admittance/free_motion.lua, on NeedleAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { NeedleAdmittance = dofile(here .. "../../admittance/free_motion.lua").Admittance }
