#!/usr/bin/env python3
"""Per-shape table and means of a hard-surface `meshflow eval generate --baseline` JSON:
   python3 hard_surface_table.py FILE.json"""
import json,sys,statistics as st
d=json.load(open(sys.argv[1]))
rows=[];brows=[]
for m in d['per_mesh']:
  o=m['ours'];b=m['baseline'];s=m['sharpen']
  gt=o['gt_topology']['faces']
  rows.append((o['chamfer_x100'],o['normal_consistency'],o['sharp']['edge_chamfer_x100'],o['sharp']['edge_f_score']['f_score'],m['faces_made']/gt,o['pred_topology']['holes']))
  brows.append((b['chamfer_x100'],b['normal_consistency'],b['sharp']['edge_chamfer_x100'],b['sharp']['edge_f_score']['f_score']))
  print('| %s | %.2f / %.3f / %.2f / %.2f / %d | %.2f / %.3f / %.2f / %.2f / %d |'%(m['name'].split('/')[-1][:-4],o['chamfer_x100'],o['normal_consistency'],o['sharp']['edge_chamfer_x100'],o['sharp']['edge_f_score']['f_score'],m['faces_made'],b['chamfer_x100'],b['normal_consistency'],b['sharp']['edge_chamfer_x100'],b['sharp']['edge_f_score']['f_score'],m['faces_made']), 'holes',o['pred_topology']['holes'],'folded',o['pred_topology']['folded_edges'], 'bfold', b['pred_topology']['folded_edges'], 'bnm', b['pred_topology']['non_manifold_edges'])
print('means ours', [round(st.mean(c),3) for c in zip(*rows)])
print('means base', [round(st.mean(c),3) for c in zip(*brows)])
