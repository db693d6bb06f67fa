#!/usr/bin/env python3
"""What the calibration window does on a schedule-oracle table (no GL needed).

Usage: table_study.py SEGMENTS.csv FEATURES.csv PROBE_ERROR.csv
(from `hybridwalk schedule-oracle ... --out DIR`: DIR/segments.csv,
DIR/features.csv, DIR/probe_error.csv; any probe size).

Every (k0, k1, frame) of the table has a measured PSNR, so any schedule's
median follows exactly. The predictor is probe-psnr+features' six regressors,
fitted on the frames of the fixed schedules every 10 and 20 frames (what
`walk --calibrate-spacing 20 --target-psnr fixed:10` measures), and the target
is fixed-10's median. For each window: the plan (fewest keyframes with more
than half of the in-between frames reaching the target; gaps 1..20 here, 2..20
in the walk) by the plain count and by the empirical error model, and the
measured median of that plan. Last, the plain count fed the truth plus noise,
per frame or per segment, with the target scanned for the fewest keyframes
reaching the median: how precise a predictor must be.
Needs numpy (python3-numpy).
"""
import csv, math, sys
import numpy as np

def load(seg, feat, probe):
    D = {}
    for r in csv.DictReader(open(feat)):
        D[(int(r['k0']), int(r['k1']), int(r['frame']))] = dict(
            psnr=float(r['psnr']), dist=float(r['rel_distance']), ang=float(r['angle_deg']),
            holes=float(r['hole_fraction']), stretch=float(r['stretch']), dis=float(r['disagreement_mse']))
    for r in csv.DictReader(open(probe)):
        D[(int(r['k0']), int(r['k1']), int(r['frame']))]['mse'] = float(r['probe_mse'])
    for r in csv.DictReader(open(seg)):  # the measured PSNR is the table's
        D[(int(r['k0']), int(r['k1']), int(r['frame']))]['psnr'] = float(r['psnr'])
    return D

def regressors(D, keys):  # log10 of each feature, as keyframe_planner.cpp's predictorRegressors
    cols = [('mse', 1e-2), ('dist', 1e-3), ('holes', 1e-4), ('stretch', 1e-3), ('dis', 1e-1), ('ang', 1e-2)]
    return np.column_stack([np.ones(len(keys))] +
                           [np.array([math.log10(D[k][c] + e) for k in keys]) for c, e in cols])

def fixed(n, g):
    ks = list(range(0, n, g))
    return ks + [n - 1] if ks[-1] != n - 1 else ks

def fewest_for_median(n, max_gap, count, at_least=0):
    """Fewest keyframes (>= at_least) with more than half the in-between frames good; count(k0, k1) -> (good, frames)."""
    layers = [{0: (0.0, 0, None)}]
    for c in range(1, n):
        L = {}
        for last, (g, ib, _) in layers[-1].items():
            for k1 in range(last + 1, min(n - 1, last + max_gap) + 1):
                gg, cc = count(last, k1)
                v = (g + gg, ib + cc, last)
                if k1 not in L or v[0] > L[k1][0] or (v[0] == L[k1][0] and v[1] < L[k1][1]):
                    L[k1] = v
        layers.append(L)
        if c + 1 >= at_least and n - 1 in L and L[n - 1][1] > 0 and 2 * L[n - 1][0] > L[n - 1][1]:
            ks, cur = [n - 1], n - 1
            for cc in range(c, 0, -1):
                cur = layers[cc][cur][2]
                ks.append(cur)
            return ks[::-1]
    return None

def main():
    D = load(*sys.argv[1:4])
    keys = list(D)
    n = max(k[1] for k in keys) + 1
    idx = {k: i for i, k in enumerate(keys)}
    P = np.array([D[k]['psnr'] for k in keys])
    def measured_median(ks):
        return float(np.median([D[(a, b, f)]['psnr'] for a, b in zip(ks, ks[1:]) for f in range(a + 1, b)]))
    f10 = fixed(n, 10)
    T = measured_median(f10)
    cal = sorted({idx[(a, b, f)] for g in (10, 20) for a, b in zip(fixed(n, g), fixed(n, g)[1:])
                  for f in range(a + 1, b)})
    X = regressors(D, keys)
    coef, *_ = np.linalg.lstsq(X[cal], P[cal], rcond=None)
    raw = X @ coef
    res = P[cal] - raw[cal]
    fr = np.array([keys[i][2] for i in cal])
    seg = [(keys[i][0], keys[i][1]) for i in cal]
    print('%d frames; fixed-10: %d keyframes, median %.2f dB; %d calibration frames' % (n, len(f10), T, len(cal)))

    def plan(pred, residuals):
        out = []
        for mode in ('plain', 'empirical'):
            if mode == 'plain':
                pr = (pred >= T).astype(float)
            else:
                rs = np.sort(residuals)
                pr = (len(rs) - np.searchsorted(rs, T - pred, side='left')) / len(rs)
            ks = fewest_for_median(n, 20, lambda a, b: (sum(pr[idx[(a, b, f)]] for f in range(a + 1, b)), b - a - 1))
            out.append('%s %d (%+.0f %%) %+.2f dB' % (mode, len(ks), 100 * (len(ks) / len(f10) - 1),
                                                     measured_median(ks) - T))
        return ' | '.join(out)

    for W in (0, 3, 5, 8):
        pred, held = raw.copy(), res.copy()
        if W > 0:
            offset = np.zeros(n)
            for f in range(n):
                d = (fr - f) / W
                w = np.where(d * d > 25, 0.0, np.exp(-0.5 * d * d))
                offset[f] = (w * res).sum() / (w.sum() + 2.0)
            pred = raw + np.array([offset[k[2]] for k in keys])
            for j in range(len(cal)):
                d = (fr - fr[j]) / W
                w = np.where(d * d > 25, 0.0, np.exp(-0.5 * d * d))
                w[[s == seg[j] for s in seg]] = 0
                held[j] = res[j] - (w * res).sum() / (w.sum() + 2.0)
        rho = np.corrcoef(np.argsort(np.argsort(pred)), np.argsort(np.argsort(P)))[0, 1]
        print('window %d: held-out rms %.2f dB, every entry: rms %.2f dB, Spearman %.3f | %s' % (
            W, math.sqrt((held ** 2).mean()), math.sqrt(((P - pred) ** 2).mean()), rho, plan(pred, held)))
    # The truth plus noise, the target scanned (the best the count can do
    # with the target's offset known): how precise a predictor must be.
    def best_scanned(pred):  # '17 (-32 %) +0.10 dB'
        best = None
        for d in np.arange(-3.0, 3.01, 0.1):
            pr = (pred >= T + d).astype(float)
            ks = fewest_for_median(n, 20, lambda a, b: (sum(pr[idx[(a, b, f)]] for f in range(a + 1, b)), b - a - 1))
            m = measured_median(ks)
            if m >= T and (best is None or len(ks) < best[0]):
                best = (len(ks), m - T)
        if best is None:
            return 'no target within 3 dB reaches the median'
        return '%d (%+.0f %%) %+.2f dB' % (best[0], 100 * (best[0] / len(f10) - 1), best[1])
    print('best possible (the table itself): %s' % best_scanned(P))
    for s in (0.5, 1.0):
        for per in ('frame', 'segment'):
            got = []
            for seed in range(1, 6):  # one draw is noisy: five
                rng = np.random.default_rng(seed)
                if per == 'frame':
                    noise = rng.normal(0, s, len(P))
                else:
                    off = {}
                    for k in keys:
                        off.setdefault(k[:2], rng.normal(0, s))
                    noise = np.array([off[k[:2]] for k in keys])
                got.append(best_scanned(P + noise))
            print('truth + %.1f dB noise per %s, target scanned, 5 draws: %s' % (s, per, '; '.join(got)))


if __name__ == '__main__':
    main()
