#!/usr/bin/env python3
"""Camera path JSON (paths/*.json format) from a `hybridwalk export-keyframes` cameras.json.

The default path of a scene (e.g. an OpenArena map's spawn walk) is exported with
  hybridwalk export-keyframes --scene q3:MAP --out DIR
and resampled here to a steady pace: keys every --key-spacing metres along the
eye track (Catmull-Rom in the program goes through them), look_at 5 m ahead along
each camera's view direction, frames = length / pace (multiple of keyframe_every,
at most --max-frames).
  python3 make_path.py DIR/cameras.json out.json [--pace 0.2] [--key-spacing 2]
"""
import argparse, json, math

ap = argparse.ArgumentParser()
ap.add_argument("cameras")
ap.add_argument("out")
ap.add_argument("--pace", type=float, default=0.2, help="metres per frame")
ap.add_argument("--key-spacing", type=float, default=2.0, help="metres between keys")
ap.add_argument("--max-frames", type=int, default=240)
ap.add_argument("--keyframe-every", type=int, default=10)
ap.add_argument("--lift", type=float, default=0.0, help="raise every eye and look_at by this (metres)")
a = ap.parse_args()

d = json.load(open(a.cameras))
cams = []
for group in ("keyframes", "in_between"):
    cams += d.get(group, [])
cams.sort(key=lambda c: c["frame"])
first = cams[0]
eyes, fwds = [], []
for c in cams:
    m = c["world_from_camera"]
    eyes.append([m[0][3], m[1][3] + a.lift, m[2][3]])
    fwds.append([m[0][2], m[1][2], m[2][2]])  # OpenCV z = forward
cum = [0.0]
for i in range(1, len(eyes)):
    cum.append(cum[-1] + math.dist(eyes[i - 1], eyes[i]))
L = min(cum[-1], a.max_frames * a.pace)  # a long track is cut to what max_frames walks at the pace
n = next(i for i in range(len(cum)) if cum[i] >= L - 1e-9) + 1
eyes, fwds, cum = eyes[:n], fwds[:n], cum[:n]
L = cum[-1]
keys, nextS = [], 0.0
for i, e in enumerate(eyes):
    if cum[i] + 1e-9 >= nextS or i == len(eyes) - 1:
        if keys and math.dist(keys[-1]["eye"], e) < 0.25 * a.key_spacing and i != len(eyes) - 1:
            continue
        keys.append({"eye": e, "look_at": [e[k] + 5.0 * fwds[i][k] for k in range(3)]})
        nextS = cum[i] + a.key_spacing
frames = int(round(L / a.pace / a.keyframe_every)) * a.keyframe_every
frames = max(a.keyframe_every * 6, min(a.max_frames, frames))
path = {"width": first["width"], "height": first["height"],
        "fov_y_deg": round(math.degrees(2 * math.atan(first["height"] / 2 / first["fy"])), 6),
        "near": first["near"], "far": first["far"], "up": [0.0, 1.0, 0.0],
        "keys": keys, "frames": frames, "keyframe_every": a.keyframe_every}
json.dump(path, open(a.out, "w"), indent=2)
print(f"{a.out}: {len(keys)} keys, {L:.1f} m, {frames} frames, {L / frames:.3f} m/frame")
