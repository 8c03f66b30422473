-- The needle robot's penetration behaviour (thesis §4.7): the admittance of
-- deployment/admittance/penetration.lua, on NeedleAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { NeedleAdmittance = dofile(here .. "../../admittance/penetration.lua").Admittance }
