-- Small geometry helpers for the puncturing deployment files (m, rad). Frames are written as cobra's
-- Lua frames {x, y, z, qx, qy, qz, qw}; rotations follow KDL's RPY: R = Rz(yaw) Ry(pitch) Rx(roll).
local G = {}

function G.quat(roll, pitch, yaw)
  local cr, sr = math.cos(roll / 2), math.sin(roll / 2)
  local cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
  local cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
  return { sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
           cr * cp * cy + sr * sp * sy }
end

function G.frame(x, y, z, roll, pitch, yaw)
  local q = G.quat(roll or 0, pitch or 0, yaw or 0)
  return { x, y, z, q[1], q[2], q[3], q[4] }
end

-- v rotated by the unit quaternion of frame f.
local function rotate(f, v)
  local qx, qy, qz, qw = f[4], f[5], f[6], f[7]
  local tx = 2 * (qy * v[3] - qz * v[2])
  local ty = 2 * (qz * v[1] - qx * v[3])
  local tz = 2 * (qx * v[2] - qy * v[1])
  return { v[1] + qw * tx + (qy * tz - qz * ty), v[2] + qw * ty + (qz * tx - qx * tz),
           v[3] + qw * tz + (qx * ty - qy * tx) }
end
G.rotate = rotate

-- Point p (frame f's coordinates) in the frame f is given in.
function G.apply(f, p)
  local r = rotate(f, p)
  return { f[1] + r[1], f[2] + r[2], f[3] + r[3] }
end

-- The abdomen pose and forbidden regions of a scenario's preoperative.txt (format:
-- apps/puncturing/README.md). The Frame Generator reads the file itself (cobra::puncturing); the
-- deployment needs only these two for the monitor and the planner's phantom.
function G.preoperative(path)
  local file = assert(io.open(path, "r"), "puncturing: cannot open " .. path)
  local info = { abdomen = G.frame(0, 0, 0), regions = {} }
  local function vec(text) local a, b, c = text:match("^([^,]+),([^,]+),([^,]+)$") return { tonumber(a), tonumber(b), tonumber(c) } end
  for line in file:lines() do
    line = line:gsub("#.*", "")
    local kind = line:match("^%s*(%a+)")
    local fields = {}
    for k, v in line:gmatch("(%w+)=(%S+)") do fields[k] = v end
    if kind == "abdomen" then
      local p, r = vec(fields.xyz), vec(fields.rpy or "0,0,0")
      info.abdomen = G.frame(p[1], p[2], p[3], r[1], r[2], r[3])
    elseif kind == "capsule" then
      info.regions[#info.regions + 1] = { vec(fields.a), vec(fields.b), tonumber(fields.radius) }
    elseif kind == "sphere" then
      local c = vec(fields.center)
      info.regions[#info.regions + 1] = { c, c, tonumber(fields.radius) }
    end
  end
  file:close()
  return info
end

-- The forbidden regions in the world frame, 7 numbers per capsule (a, b, radius), as the
-- NeedleInsertionMonitor's forbidden_regions property wants them.
function G.regionsInWorld(info)
  local out = {}
  for _, r in ipairs(info.regions) do
    local a, b = G.apply(info.abdomen, r[1]), G.apply(info.abdomen, r[2])
    for _, v in ipairs({ a[1], a[2], a[3], b[1], b[2], b[3], r[3] }) do out[#out + 1] = v end
  end
  return out
end

return G
