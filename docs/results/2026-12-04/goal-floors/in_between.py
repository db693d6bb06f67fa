# Per walk: warped frames, median in-between frame ms, reference ms, their
# ratio, PSNR median/p5, frame/reference. Usage: in_between.py WALK_DIR...
import json,sys,statistics as st
for p in sys.argv[1:]:
    r=json.load(open(p+'/report.json'))
    s=r['summary']
    fr=[f for f in r['frames'] if f['mode']=='warp']
    if not fr:
        print(f"{p:28s} warp=0 (every frame drawn as geometry or a keyframe)  f/r={s['frame_over_reference']['median']:.2f}/{s['frame_over_reference']['p95']:.2f}")
        continue
    fm=st.median([f['ms']['frame'] for f in fr]); rm=st.median([f['reference_ms'] for f in fr])
    print(f"{p:28s} warp={len(fr)} ib_ms={fm:6.2f} ref={rm:6.2f} ib/ref={fm/rm:5.2f} psnr={s['psnr']['median']:.2f}/{s['psnr']['p5']:.2f}  f/r={s['frame_over_reference']['median']:.2f}/{s['frame_over_reference']['p95']:.2f}")
