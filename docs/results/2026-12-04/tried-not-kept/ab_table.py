# Medians over warped frames of walks run as /tmp/md/NAME_{old,new}_{1,2}
# (--mode hybrid, old = /tmp/hw_old, new = the change): background (warp_b),
# readback, in-between frame, reference ms and PSNR. Usage: ab_table.py DIR.
import json,statistics as st,sys
root=sys.argv[1]
for n in ['indoor','indoor_1M','q3_oa_dm5']:
  for p in '12':
    row=[]
    for b in ['old','new']:
      r=json.load(open(f'{root}/{n}_{b}_{p}/report.json'))
      fr=[f for f in r['frames'] if f['mode']=='warp']
      g=lambda k: st.median([f['ms'].get(k,0) for f in fr])
      ref=st.median([f['reference_ms'] for f in r['frames']])
      row.append(f"{b}: wa {g('warp_a'):.2f} wb {g('warp_b'):.2f} rb {g('readback'):.2f} ib {g('frame'):.2f} ref {ref:.2f} psnr {r['summary']['psnr']['median']:.4f}/{r['summary']['psnr']['p5']:.4f}")
    print(n,p,' | '.join(row))
