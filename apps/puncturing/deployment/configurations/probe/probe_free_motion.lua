-- The probe robot's free motion (thesis §4.7, replicated for the UR5): the admittance of
-- components/control/configurations/puncturing/free_motion.lua, on ProbeAdmittance.
local here = debug.getinfo(1, "S").source:match("^@(.*/)")
return { ProbeAdmittance = dofile(here .. "../../../../../components/control/configurations/puncturing/free_motion.lua").Admittance }
