import json,sys,glob,os,csv
def q(v,p):
  v=sorted(v); return v[int(p*(len(v)-1))] if v else float('nan')
rows=[]
for d in sorted(glob.glob(sys.argv[1]+'/*_*_*')):
  if not os.path.exists(d+'/report.json'): continue
  r=json.load(open(d+'/report.json')); s=r['summary']
  name=os.path.basename(d)
  ib=[f for f in r['frames'] if not f['is_keyframe']]
  ps=[f['psnr'] for f in ib if f['psnr'] is not None]
  work=[f['ms']['frame'] for f in ib]; iv=[f['ms']['interval'] for f in ib]
  rows.append(dict(run=name, budget_ms_median=s['frame_budget_ms'], work_median=q(work,.5), work_p95=q(work,.95), work_ratio=q(work,.95)/q(work,.5),
    interval_median=q(iv,.5), interval_p95=q(iv,.95), interval_ratio=q(iv,.95)/q(iv,.5),
    psnr_median=q(ps,.5), psnr_p5=q(ps,.05), overruns_in_between=s.get('budget_overruns_in_between'), overruns_by_refresh=s.get('budget_overruns_by_refresh'),
    in_between=len(ib), refreshed_px_median=s['refreshed_pixels']['median'], stalls=s.get('keyframe_stalls')))
w=csv.DictWriter(sys.stdout, fieldnames=list(rows[0].keys())); w.writeheader()
for x in rows: w.writerow({k:(round(v,3) if isinstance(v,float) else v) for k,v in x.items()})
