#!/usr/bin/env python3
"""walks.csv from the walks of walks.sh: summarise.py OUT_DIR > walks.csv"""
import glob, json, os, re, sys

print('run,keyframes,fixed10_keyframes,keyframes_change_pct,psnr_median,target_psnr,median_minus_target,'
      'planned_keyframes,optimism_db,window_frames,rounds,converged,median_guaranteed,frames_measured,'
      'path_frames,calibration_s,plan_s,verify_s,wall_s')
for rep in sorted(glob.glob(os.path.join(sys.argv[1], '*', 'report.json'))):
    run = os.path.basename(os.path.dirname(rep))
    s = json.load(open(rep))['summary']
    p = s['planner']
    v = p['verify'] or {}
    c = p['calibration'] or {}
    fixed10 = [w['keyframes'] for w in c.get('walks', []) if w['spacing'] == 10]
    wall = ''
    log = os.path.join(sys.argv[1], run + '.log')
    if os.path.exists(log):
        m = re.findall(r'^([0-9.]+) s$', open(log).read(), re.M)
        wall = m[-1] if m else ''
    win = (c.get('window') or {}).get('frames', 0)
    k = s['keyframes']
    f10 = fixed10[0] if fixed10 else ''
    print(','.join(str(x) for x in [
        run, k, f10, '%.0f' % (100 * (k / f10 - 1)) if f10 else '', '%.3f' % s['psnr']['median'],
        '%.3f' % p['target_psnr'], '%+.3f' % (s['psnr']['median'] - p['target_psnr']),
        v.get('planned_keyframes', ''), v.get('optimism_db', ''), win, len(v.get('rounds', [None])) - 1,
        v.get('converged', ''), v.get('median_guaranteed', ''), v.get('frames_measured', ''), s['frames'],
        '%.1f' % (c.get('ms', 0) / 1000), '%.1f' % (p['plan_ms'] / 1000), '%.1f' % (v.get('ms', 0) / 1000), wall]))
