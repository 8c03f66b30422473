-- Example 03: the hooks of a LuaComponent. Top-level code declares the interface; the hook
-- functions run in the component's activity (here the lockstep clock), with Lua memory from a
-- bounded pool, so a running hook never calls the system allocator.
self:addEventPort("u", "double", "signal to rectify", "1")
self:addOutputPort("y", "double", "rectified and scaled signal", "1")
self:addProperty("k", "double", 1.0, "1", "scale factor", {min = 0, max = 100})

function configureHook()
  print(string.format("  [lua] configureHook: k = %g", self.k))
  return true
end

function updateHook()
  local fs, u = self.u:read()
  while fs == "NewData" do
    self.y:write(self.k * math.abs(u))
    fs, u = self.u:read()
  end
end
