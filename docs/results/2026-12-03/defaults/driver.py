#!/usr/bin/env python3
"""Issue 20 measurement driver: LOD option grid x scenes, one `hybridwalk walk` per cell.

Standard library only. Resumable: a cell whose report.json exists is not run again.

  python3 driver.py --phase 1 --runs /tmp/hw-defaults-runs   # tau ladder, every scene
  python3 driver.py --phase 2 --runs /tmp/hw-defaults-runs   # option variants at the centre tau-px
  python3 driver.py --csv-only --runs /tmp/hw-defaults-runs  # rebuild runs.csv from the reports

Run from the worktree root with LP_NUM_THREADS=2 exported (recorded in every report).
"""
import argparse, csv, json, os, subprocess, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))
BIN = "build/bin/hybridwalk"

# scene label -> (--scene, --path or None, --frames cap (0 = whole path))
SCENES = [
    ("indoor:100k", "indoor:100k", None, 0),
    ("indoor:1M", "indoor:1M", None, 0),
    ("outdoor:100k", "outdoor:100k", None, 0),
    ("outdoor:1M", "outdoor:1M", None, 0),
    ("q3:oa_dm5", "q3:oa_dm5", "paths/oa_dm5.json", 0),
    ("torcs:forza", "torcs:forza", "paths/forza.json", 0),
    ("morse:trees", "morse:land-1/trees", "paths/trees.json", 0),
]
EXTRA_SCENES_FILE = os.path.join(HERE, "extra_scenes.json")  # more maps/tracks, same layout

RL_MERGE = ["--planarity", "region-local", "--merge-strips"]
CENTRE_PX = os.environ.get("HW_CENTRE_PX", "0.125")

# config name -> walk options (besides --scene/--path/--out)
PHASE1 = [
    ("paper", []),  # tau 2^11, stencil, five-point, overlay, no merge/near/subdivision
    ("rl+m tau2^9", RL_MERGE + ["--tau", "2^9"]),
    ("rl+m px0.03", RL_MERGE + ["--tau-px", "0.03"]),
    ("rl+m px0.06", RL_MERGE + ["--tau-px", "0.06"]),
    ("rl+m px0.125", RL_MERGE + ["--tau-px", "0.125"]),
    ("rl+m px0.25", RL_MERGE + ["--tau-px", "0.25"]),
    ("rl+m px0.5", RL_MERGE + ["--tau-px", "0.5"]),
]
def phase2():
    c = CENTRE_PX
    return [
        (f"stencil px{c}", ["--tau-px", c]),
        (f"rl px{c}", ["--planarity", "region-local", "--tau-px", c]),
        (f"rl+m px{c} depth-merge", RL_MERGE + ["--tau-px", c, "--compose", "depth-merge"]),
        (f"rl+m px{c} subdiv-adaptive", RL_MERGE + ["--tau-px", c, "--subdivide", "adaptive"]),
        (f"rl+m px{c} near1", RL_MERGE + ["--tau-px", c, "--near", "1"]),
        (f"rl+m px{c} per-axis-max", RL_MERGE + ["--tau-px", c, "--criterion", "per-axis-max"]),
    ]

def slug(s):
    return "".join(ch if ch.isalnum() or ch in ".-" else "_" for ch in s)

def scenes():
    out = list(SCENES)
    if os.path.exists(EXTRA_SCENES_FILE):
        for e in json.load(open(EXTRA_SCENES_FILE)):
            out.append((e["label"], e["scene"], e.get("path"), e.get("frames", 0)))
    return out

def run_cell(runs, label, scene, path, frames, cname, opts, log):
    d = os.path.join(runs, slug(label), slug(cname))
    rep = os.path.join(d, "report.json")
    if os.path.exists(rep):
        return "cached"
    cmd = [BIN, "walk", "--scene", scene, "--out", d, "--quiet", "--strips", "0"]
    if path:
        cmd += ["--path", path]
    if frames:
        cmd += ["--frames", str(frames)]
    cmd += opts
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    line = {"label": label, "config": cname, "cmd": cmd, "rc": p.returncode, "wall_s": round(wall, 1),
            "stderr": p.stderr[-2000:]}
    log.write(json.dumps(line) + "\n"); log.flush()
    print(f"{time.strftime('%H:%M:%S')} {label:16s} {cname:32s} rc={p.returncode} {wall:6.1f}s", flush=True)
    return p.returncode

def med(s, k, q="median"):
    v = s.get(k)
    return None if not isinstance(v, dict) else v.get(q)

FIELDS = ["scene", "config", "triangles", "frames", "in_between_frames", "tau", "tau_px", "planarity",
          "merge_strips", "criterion", "compose", "near", "subdivision",
          "psnr_median", "psnr_p5", "ssim_median", "in_between_ms_median", "in_between_ms_p95",
          "frame_ms_median", "frame_ms_p95", "in_between_frame_ms_median", "reference_ms_median",
          "quads_median", "drawn_quads_median", "keyframe_build_ms_median", "lod_build_ms_median",
          "holes_before_median", "lp_num_threads", "commit", "wall_s"]

def collect(runs, out_csv):
    walls = {}
    logp = os.path.join(runs, "log.jsonl")
    if os.path.exists(logp):
        for l in open(logp):
            r = json.loads(l)
            walls[(r["label"], r["config"])] = r["wall_s"]
    rows = []
    for label, *_ in scenes():
        for cname, _ in PHASE1 + phase2():
            rep = os.path.join(runs, slug(label), slug(cname), "report.json")
            if not os.path.exists(rep):
                continue
            s = json.load(open(rep))["summary"]
            m = s.get("machine", {})
            r = lambda x: None if x is None else round(x, 3)
            rows.append({
                "scene": label, "config": cname, "triangles": s["scene"]["triangles"],
                "frames": s["frames"], "in_between_frames": s["in_between_frames"],
                "tau": s["tau"], "tau_px": s["tau_parallax_px"], "planarity": s["planarity"],
                "merge_strips": s["merge_strips"], "criterion": s["criterion"],
                "compose": s["compose_mode"], "near": s["near_distance"], "subdivision": s["subdivision"],
                "psnr_median": r(med(s, "psnr")), "psnr_p5": r(med(s, "psnr", "p5")),
                "ssim_median": r(med(s, "ssim")),
                "in_between_ms_median": r(med(s, "in_between_ms")),
                "in_between_ms_p95": r(med(s, "in_between_ms", "p95")),
                "frame_ms_median": r(med(s, "frame_ms")), "frame_ms_p95": r(med(s, "frame_ms", "p95")),
                "in_between_frame_ms_median": r(med(s, "in_between_frame_ms")),
                "reference_ms_median": r(med(s, "reference_ms")),
                "quads_median": med(s, "quads_per_keyframe"),
                "drawn_quads_median": med(s, "drawn_quads_per_keyframe"),
                "keyframe_build_ms_median": r(med(s, "keyframe_build_ms")),
                "lod_build_ms_median": r(med(s, "lod_build_ms")),
                "holes_before_median": r(med(s, "holes_before_fallback")),
                "lp_num_threads": m.get("lp_num_threads"), "commit": m.get("commit", m.get("git_commit")),
                "wall_s": walls.get((label, cname)),
            })
    with open(out_csv, "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        w.writerows(rows)
    print(f"{len(rows)} rows -> {out_csv}")

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", default="/tmp/hw-defaults-runs")
    ap.add_argument("--phase", type=int, default=0)
    ap.add_argument("--only", default="", help="comma-separated scene labels")
    ap.add_argument("--configs", default="", help="comma-separated config names")
    ap.add_argument("--csv-only", action="store_true")
    ap.add_argument("--csv", default=os.path.join(HERE, "runs.csv"))
    a = ap.parse_args()
    if os.environ.get("LP_NUM_THREADS") != "2":
        sys.exit("export LP_NUM_THREADS=2 first")
    os.makedirs(a.runs, exist_ok=True)
    if not a.csv_only:
        cfgs = {1: PHASE1, 2: phase2()}.get(a.phase, PHASE1 + phase2())
        if a.configs:
            keep = set(a.configs.split(","))
            cfgs = [c for c in cfgs if c[0] in keep]
        only = set(a.only.split(",")) if a.only else None
        with open(os.path.join(a.runs, "log.jsonl"), "a") as log:
            for label, scene, path, frames in scenes():
                if only and label not in only:
                    continue
                for cname, opts in cfgs:
                    run_cell(a.runs, label, scene, path, frames, cname, opts, log)
    collect(a.runs, a.csv)

if __name__ == "__main__":
    main()
