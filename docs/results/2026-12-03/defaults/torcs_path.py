#!/usr/bin/env python3
"""Hand-made camera path along a TORCS track's road, from the .acc geometry.

For tracks whose default path fails (no texture named road*, or the centreline
trace stops). Reads the AC3D file, keeps the vertices of objects whose texture
name starts with one of --road stems (world positions: object `loc`s
accumulated; TORCS .acc files are Y-up like hybridwalk), starts at --start
(x,z) or at the road vertex nearest the road's centroid, and marches --step
metres at a time, re-centring on the mean of the road vertices within --radius
of the step's end. Eye --eye-height above the road there, look_at --look-ahead
metres along the way.
  python3 torcs_path.py TRACK.acc out.json --road asphalt-e2 --length 48 --pace 0.2
"""
import argparse, json, math, os

ap = argparse.ArgumentParser()
ap.add_argument("acc")
ap.add_argument("out")
ap.add_argument("--road", action="append", required=True)
ap.add_argument("--start", default="")
ap.add_argument("--heading", type=float, default=None, help="initial heading, degrees from +x toward +z")
ap.add_argument("--length", type=float, default=48.0)
ap.add_argument("--pace", type=float, default=0.2)
ap.add_argument("--step", type=float, default=2.0)
ap.add_argument("--radius", type=float, default=7.0)
ap.add_argument("--eye-height", type=float, default=1.7)
ap.add_argument("--look-ahead", type=float, default=8.0)
a = ap.parse_args()
stems = [s.lower() for s in a.road]

lines = [l.strip() for l in open(a.acc, errors="replace")]
pos = 0
road = []

def obj(off):
    global pos
    tex, loc, verts, kids = "", [0.0, 0.0, 0.0], [], 0
    pos += 1
    while pos < len(lines):
        l = lines[pos]; kw = l.split(" ", 1)[0]
        if kw == "texture" and not tex:  # the first is the base texture (.acc: base, tiled, skids, shad)
            tex = os.path.basename(l.split(" ", 1)[1].strip('"')).lower()
        elif kw == "loc":
            loc = [float(x) for x in l.split()[1:4]]
        elif kw == "numvert":
            n = int(l.split()[1])
            verts = [[float(x) for x in lines[pos + 1 + i].split()[:3]] for i in range(n)]
            pos += n
        elif kw == "numsurf":
            n = int(l.split()[1]); pos += 1
            for _ in range(n):  # SURF, mat, refs K, K lines
                while not lines[pos].startswith("refs"):
                    pos += 1
                pos += int(lines[pos].split()[1]) + 1
            continue
        elif kw == "kids":
            kids = int(l.split()[1]); pos += 1
            o = [off[i] + loc[i] for i in range(3)]
            if any(tex.startswith(s) for s in stems):
                road.extend([[v[i] + o[i] for i in range(3)] for v in verts])
            for _ in range(kids):
                obj(o)
            return
        pos += 1

while pos < len(lines):
    if lines[pos].startswith("OBJECT"):
        obj([0.0, 0.0, 0.0])
    else:
        pos += 1
if not road:
    raise SystemExit("no road vertices for " + ",".join(stems))

def near(p, r):
    return [v for v in road if (v[0] - p[0]) ** 2 + (v[2] - p[2]) ** 2 < r * r]

def mean(vs):
    return [sum(v[i] for v in vs) / len(vs) for i in range(3)]

if a.start:
    sx, sz = (float(x) for x in a.start.split(","))
    p = mean(near([sx, 0, sz], a.radius))
else:
    c = mean(road)
    p = min(road, key=lambda v: (v[0] - c[0]) ** 2 + (v[2] - c[2]) ** 2)
    p = mean(near(p, a.radius))
if a.heading is not None:
    d = [math.cos(math.radians(a.heading)), math.sin(math.radians(a.heading))]
else:  # principal direction of the road around p
    vs = near(p, 3 * a.radius)
    m = mean(vs)
    sxx = sum((v[0] - m[0]) ** 2 for v in vs); szz = sum((v[2] - m[2]) ** 2 for v in vs)
    sxz = sum((v[0] - m[0]) * (v[2] - m[2]) for v in vs)
    ang = 0.5 * math.atan2(2 * sxz, sxx - szz)
    d = [math.cos(ang), math.sin(ang)]
pts = [p]
walked = 0.0
while walked < a.length + a.look_ahead + a.step:
    q = [p[0] + a.step * d[0], p[1], p[2] + a.step * d[1]]
    vs = near(q, a.radius)
    if len(vs) < 3:
        raise SystemExit(f"road lost {walked:.0f} m along, at x={q[0]:.1f} z={q[2]:.1f}")
    c = mean(vs)
    nd = [c[0] - p[0], c[2] - p[2]]
    n = math.hypot(*nd)
    if n < 1e-6:
        nd = d
    else:
        nd = [nd[0] / n, nd[1] / n]
        nd = [0.5 * d[0] + 0.5 * nd[0], 0.5 * d[1] + 0.5 * nd[1]]
        n = math.hypot(*nd); nd = [nd[0] / n, nd[1] / n]
    p = [p[0] + a.step * nd[0], c[1], p[2] + a.step * nd[1]]
    d = nd
    pts.append(p)
    walked += a.step
keys = []
k_look = int(round(a.look_ahead / a.step))
nkeys = int(round(a.length / a.step)) + 1
for i in range(nkeys):
    e = pts[i]; t = pts[i + k_look]
    keys.append({"eye": [e[0], e[1] + a.eye_height, e[2]], "look_at": [t[0], t[1] + a.eye_height, t[2]]})
frames = int(round(a.length / a.pace / 10)) * 10
path = {"width": 512, "height": 512, "fov_y_deg": 60.0, "near": 0.5, "far": 1000.0, "up": [0.0, 1.0, 0.0],
        "keys": keys, "frames": frames, "keyframe_every": 10}
json.dump(path, open(a.out, "w"), indent=2)
print(f"{a.out}: {len(keys)} keys from x={pts[0][0]:.1f} z={pts[0][2]:.1f}, {a.length:.0f} m, {frames} frames")
