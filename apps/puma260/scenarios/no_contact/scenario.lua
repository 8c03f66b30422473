-- The Puma 260 task in the analytic world without contact (deployment/world_analytic.lua): the
-- same controller and chart, nothing on the path (D -> H directly). For comparisons (bench/).
kinematics_solver = "closed_form"
world_file = "world_analytic.lua"
