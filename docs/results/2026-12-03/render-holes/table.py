import json,statistics as st,sys,os
root=sys.argv[1]
names=[]
for d in sorted(os.listdir(root)):
  if d.endswith('_base'): names.append(d[:-5])
print("| scene | PSNR median base → holes | p5 base → holes | stale px median | hole rects / area median | render_holes ms median | frame/ref median base → holes | p95 base → holes |")
print("|---|---|---|---|---|---|---|---|")
for n in names:
  row=[]
  R={}
  for v in ['base','holes']:
    try: R[v]=json.load(open(f'{root}/{n}_{v}/report.json'))
    except: pass
  if len(R)<2: continue
  def stats(r):
    fs=[f for f in r['frames'] if f['mode']=='warp']
    ps=sorted(f['psnr'] if f['psnr'] is not None else 99 for f in fs)
    ratio=sorted(f['ms']['frame']/f['reference_ms'] for f in r['frames'] if f.get('reference_ms'))
    allr=sorted(f['ms']['frame']/f['reference_ms'] for f in r['frames'] if f.get('reference_ms'))
    return dict(med=st.median(ps),p5=ps[int(0.05*len(ps))],stale=st.median(f['stale_pixels'] for f in fs),
      rects=st.median(f.get('hole_rects',0) for f in fs),area=st.median(f.get('hole_rect_pixels',0) for f in fs),
      rh=st.median(f['ms'].get('render_holes',0) for f in fs),rmed=st.median(allr),r95=allr[int(0.95*(len(allr)-1))])
  b=stats(R['base']);h=stats(R['holes'])
  print(f"| {n} | {b['med']:.2f} → {h['med']:.2f} | {b['p5']:.2f} → {h['p5']:.2f} | {b['stale']:.0f} → {h['stale']:.0f} | {h['rects']:.0f} / {h['area']:.0f} | {h['rh']:.1f} | {b['rmed']:.2f} → {h['rmed']:.2f} | {b['r95']:.2f} → {h['r95']:.2f} |")
