# Per walk: frames by mode, frame/reference, PSNR, and the median ms of each
# stage over warped frames. Usage: stages.py WALK_DIR...
import json,sys,statistics as st
for p in sys.argv[1:]:
    r=json.load(open(p+'/report.json'))
    s=r['summary']
    fr=[f for f in r['frames'] if f['mode']=='warp']
    keys=['frame','total','warp_a','warp_b','render_holes','readback','compose','keyframe_worker','near' ]
    out={}
    for k in sorted({k for f in fr for k in f['ms']}):
        v=[f['ms'].get(k,0) or 0 for f in fr]
        if v and st.median(v)>0.05: out[k]=round(st.median(v),2)
    print(p, s['frames_by_mode'], 'f/r', {k:round(v,3) for k,v in s['frame_over_reference'].items()}, 'psnr', round((s.get('psnr') or {}).get('median') or 0,2), round((s.get('psnr') or {}).get('p5') or 0,2), 'ref_med', round(s['reference_ms']['median'],2))
    print('   warp-frame medians', out)
