-- The needle robot's needle insertion behaviour (thesis §4.7): the admittance of
-- deployment/admittance/needle_insertion.lua, on NeedleAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { NeedleAdmittance = dofile(here .. "../../admittance/needle_insertion.lua").Admittance }
