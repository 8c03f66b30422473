#!/usr/bin/env python3
"""Writes a probe plan (us_plan.txt) for a cryo plan: the probe face on the skin in the vertical
plane that contains each needle, 45 mm beyond where the needle's tip lies (seen from above), its
beam pointing at the needle's target. 45 mm, not 35: nearer, the UR5 holding the probe comes
within 5 mm of the I-SUR's micro arm at the needle's target in registrations turned by tens of
degrees (apps/puncturing/README.md, "Setups vary"). Usage: probe_plan.py cryo_plan.txt > us_plan.txt
(the offline US probe planner of thesis §4.2.2, in its simplest form)."""
import math
import sys

BEYOND = 0.045  # m: probe face centre past the tip's horizontal offset from the entry


def vec(text):
    return [float(v) for v in text.split(",")]


def sub(a, b): return [a[i] - b[i] for i in range(3)]
def dot(a, b): return sum(a[i] * b[i] for i in range(3))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
def unit(a):
    n = math.sqrt(dot(a, a))
    return [v / n for v in a]


def main(path):
    print("# probe NEEDLE xyz=X,Y,Z rpy=R,P,Y  (frame A: the probe face on the skin, z along the beam)")
    print("# written by apps/puncturing/tools/probe_plan.py from " + path.split("/")[-1])
    for line in open(path):
        words = line.split("#")[0].split()
        if not words or words[0] != "needle":
            continue
        keys = dict(w.split("=") for w in words[2:])
        entry, target = vec(keys["entry"]), vec(keys["target"])
        axis = unit(sub(target, entry))
        normal = unit(cross(axis, [0.0, 0.0, 1.0]))
        u = unit(cross(normal, [0.0, 0.0, 1.0]))
        reach = dot(sub(target, entry), u)
        if reach < 0:
            u, reach = [-v for v in u], -reach
        p = [entry[i] + u[i] * (reach + BEYOND) for i in range(3)]
        p[2] = 0.0
        z = unit(sub(target, p))
        x = unit([u[i] - z[i] * dot(u, z) for i in range(3)])
        y = cross(z, x)
        # KDL RPY: R = Rz(yaw) Ry(pitch) Rx(roll); columns x, y, z.
        r = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
        roll = math.atan2(r[2][1], r[2][2])
        pitch = math.atan2(-r[2][0], math.hypot(r[2][1], r[2][2]))
        yaw = math.atan2(r[1][0], r[0][0])
        print("probe %s xyz=%.10g,%.10g,%.10g rpy=%.10g,%.10g,%.10g" % (words[1], p[0], p[1], p[2], roll, pitch, yaw))


main(sys.argv[1])
