#!/usr/bin/env python3
"""The verified planner replayed on a schedule-oracle table (no GL needed).

Usage: table_verify.py SEGMENTS.csv FEATURES.csv PROBE_ERROR.csv
(from `hybridwalk schedule-oracle ... --out DIR`, as ../calibration_window/table_study.py).

The table holds the measured PSNR of every (k0, k1, frame), so "measuring" a
segment is reading it. As `walk --verify-rounds`: probe-psnr+features fitted on
the calibration frames (fixed every 10 and 20 frames, whose segments start out
measured), target fixed-10's median; each round, path offsets (Gaussian of W
frames, prior 2) and the empirical error model (held out by segment) from
every measured frame; measured segments count exactly, unmeasured ones as
their probability (+ optimism dB); the plan's unmeasured segments are
measured; stop when the plan is all measured, needs no fewer keyframes than
the guaranteed schedule (measured frames alone > half, unmeasured counting
as below), or after 40 rounds. Two searches: `fewest` (the fewest keyframes
the optimistic count allows) and `step` (keyframe_planner.cpp: aim one below
the guaranteed schedule). Prints the guaranteed schedule's keyframes, its
true median minus the target, rounds and frames measured (in path lengths).
Needs numpy (python3-numpy).
"""
import math, os, sys
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'calibration_window'))
from table_study import load, regressors, fixed, fewest_for_median as fewest

def run(D, W, optimism, step, rounds=40):
    keys = list(D); n = max(k[1] for k in keys) + 1
    idx = {k: i for i, k in enumerate(keys)}
    P = np.array([D[k]['psnr'] for k in keys])
    segs = lambda ks: list(zip(ks, ks[1:]))
    frames_of = lambda S: [idx[(a, b, f)] for a, b in S for f in range(a + 1, b)]
    med = lambda ks: float(np.median(P[frames_of(segs(ks))]))
    f10 = fixed(n, 10); T = med(f10)
    X = regressors(D, keys)
    measured = set(segs(fixed(n, 10)) + segs(fixed(n, 20)))
    cal0 = frames_of(sorted(measured))
    coef, *_ = np.linalg.lstsq(X[cal0], P[cal0], rcond=None)
    raw = X @ coef
    fr_all = np.array([k[2] for k in keys])
    good = lambda a, b: sum(1.0 for f in range(a + 1, b) if P[idx[(a, b, f)]] >= T)
    guaranteed = lambda: fewest(n, 20, lambda a, b: (good(a, b) if (a, b) in measured else 0.0, b - a - 1))
    nmeas = 0
    for r in range(rounds + 1):
        cal = frames_of(sorted(measured))
        res = P[cal] - raw[cal]
        pred, held = raw.copy(), res.copy()
        if W > 0:
            fr = fr_all[cal]
            seg = np.array([keys[i][0] * 1000 + keys[i][1] for i in cal])
            offset = np.zeros(n)
            for f in range(n):
                d = (fr - f) / W
                w = np.where(d * d > 25, 0.0, np.exp(-0.5 * d * d))
                offset[f] = (w * res).sum() / (w.sum() + 2.0)
            pred = raw + offset[fr_all]
            for j in range(len(cal)):
                d = (fr - fr[j]) / W
                w = np.where(d * d > 25, 0.0, np.exp(-0.5 * d * d))
                w[seg == seg[j]] = 0
                held[j] = res[j] - (w * res).sum() / (w.sum() + 2.0)
        rs = np.sort(held)
        pe = (len(rs) - np.searchsorted(rs, T - pred - optimism, side='left')) / len(rs)
        safe = guaranteed()
        cnt = lambda a, b: (good(a, b) if (a, b) in measured else sum(pe[idx[(a, b, f)]] for f in range(a + 1, b)), b - a - 1)
        ks = fewest(n, 20, cnt, at_least=(len(safe) - 1 if (safe and step) else 0))
        new = [s for s in segs(ks) if s not in measured]
        if not new or (safe and len(ks) >= len(safe)) or r == rounds:
            break
        measured.update(new)
        nmeas += sum(b - a - 1 for a, b in new)
    safe = guaranteed()
    return len(f10), len(safe), med(safe) - T, r, nmeas / n

def main():
    D = load(*sys.argv[1:4])
    print('search  W optimism | keyframes (fixed-10)  median-target  rounds  measured')
    for step in (0, 1):
        for W in (0, 3):
            for d in (0.0, 0.5, 1.0):
                f10, k, m, r, p = run(D, W, d, step)
                print('%-6s %2d %5.1f dB | %2d (%d, %+.0f %%)  %+.2f dB  %2d  %4.1f paths' % (
                    'step' if step else 'fewest', W, d, k, f10, 100 * (k / f10 - 1), m, r, p))

if __name__ == '__main__':
    main()
