#!/usr/bin/env python3
"""One walk's report.json as one JSON line: scene, mode, warper, round and
the medians over its warped in-between frames (ms.frame, the two layers,
readback, hole pass, PSNR), frames by mode, frame / geometry and the floor.
Usage: summarise.py SCENE MODE WARPER ROUND REPORT_JSON
       summarise.py --table RESULTS.jsonl   (the page's tables, Markdown)"""
import json
import statistics as st
import sys


def med(values):
    return round(st.median(values), 3) if values else None


def summarise(scene, mode, warper, rnd, path):
    r = json.load(open(path))
    s = r["summary"]
    warped = [f for f in r["frames"] if f.get("mode") == "warp"]
    ms = lambda k: med([f["ms"].get(k, 0.0) for f in warped])
    psnr = [f["psnr"] for f in warped if f.get("psnr") is not None]
    fr = s.get("frame_over_reference") or {}
    return {
        "scene": scene, "mode": mode, "warper": warper, "round": int(rnd),
        "warper_used": s.get("warper"),
        "warped_frames": len(warped), "in_between_frames": s["in_between_frames"],
        "frame_ms": ms("frame"), "warp_a_ms": ms("warp_a"), "warp_b_ms": ms("warp_b"),
        "readback_ms": ms("readback"), "holes_ms": ms("render_holes"),
        "psnr_mean": round(st.mean(psnr), 3) if psnr else None,
        "frame_over_geometry_median": fr.get("median"),
        "frame_over_geometry_p95": fr.get("p95"),
        "floor_one_layer_ms": s["floor_ms"]["one_layer"],
        "floor_two_layers_ms": s["floor_ms"]["two_layers"],
        # per frame: k keyframe, w warped, g drawn as geometry (auto's choice)
        "modes": "".join(f.get("mode", "?")[0] for f in r["frames"]),
    }


def agreement(xs):
    """Share of frames on which the first two rounds chose the same mode."""
    if len(xs) < 2 or len(xs[0]["modes"]) != len(xs[1]["modes"]):
        return float("nan")
    a, b = xs[0]["modes"], xs[1]["modes"]
    return sum(x == y for x, y in zip(a, b)) / len(a)


def table(path):
    rows = [json.loads(l) for l in open(path) if l.strip()]
    for mode in ("hybrid", "auto"):
        sel = [x for x in rows if x["mode"] == mode]
        if not sel:
            continue
        print(f"\n`--mode {mode}`:\n")
        if mode == "hybrid":
            print("| scene | in-between ms.frame gl | cpu | cpu / gl | layers (a+b) gl | cpu | larger layer / GL one-layer floor, gl | cpu | readback gl | cpu | PSNR gl | cpu |")
            print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
        else:
            print("| scene | frames warped gl | cpu | frame / geometry median gl | cpu | p95 gl | cpu | same mode in both rounds gl | cpu |")
            print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
        for scene in dict.fromkeys(x["scene"] for x in sel):
            g = [x for x in sel if x["scene"] == scene and x["warper"] == "gl"]
            c = [x for x in sel if x["scene"] == scene and x["warper"] == "cpu"]
            if not g or not c:
                continue
            m = lambda xs, k: st.median([x[k] for x in xs if x[k] is not None] or [float("nan")])
            if mode == "hybrid":
                lg = m(g, "warp_a_ms") + m(g, "warp_b_ms")
                lc = m(c, "warp_a_ms") + m(c, "warp_b_ms")
                quad = m(g, "floor_one_layer_ms")  # floor_ms.one_layer of the gl walks
                big = lambda xs: max(m(xs, "warp_a_ms"), m(xs, "warp_b_ms")) / quad
                print(f"| {scene} | {m(g,'frame_ms'):.2f} | {m(c,'frame_ms'):.2f} | {m(c,'frame_ms')/m(g,'frame_ms'):.2f} "
                      f"| {lg:.2f} | {lc:.2f} | {big(g):.2f} | {big(c):.2f} "
                      f"| {m(g,'readback_ms'):.2f} | {m(c,'readback_ms'):.2f} "
                      f"| {m(g,'psnr_mean'):.2f} | {m(c,'psnr_mean'):.2f} |")
            else:
                wg = "/".join(str(x["warped_frames"]) for x in g)
                wc = "/".join(str(x["warped_frames"]) for x in c)
                print(f"| {scene} | {wg} of {g[0]['in_between_frames']} | {wc} | "
                      f"{m(g,'frame_over_geometry_median'):.2f} | {m(c,'frame_over_geometry_median'):.2f} | "
                      f"{m(g,'frame_over_geometry_p95'):.2f} | {m(c,'frame_over_geometry_p95'):.2f} | "
                      f"{agreement(g):.0%} | {agreement(c):.0%} |")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(sys.argv[2])
    elif len(sys.argv) == 6:
        print(json.dumps(summarise(*sys.argv[1:])))
    else:
        sys.exit(__doc__)
