"""Per-mesh figures of a `meshflow eval generate` JSON as the CSV that bench/paired.py reads:
    python3 to_csv.py RUN.json > RUN.per_mesh.csv"""
import csv
import json
import sys

run = json.load(open(sys.argv[1]))
out = csv.writer(sys.stdout)
out.writerow(["name", "cd", "nc", "ecd", "ef1", "faces", "holes"])
for m in run["per_mesh"]:
    o = m["ours"]
    if not o:
        out.writerow([m["name"]] + [""] * 6)
        continue
    out.writerow([m["name"], o["chamfer_x100"], o["normal_consistency"], o["sharp"]["edge_chamfer_x100"],
                  o["sharp"]["edge_f_score"]["f_score"], m["faces_made"], o["pred_topology"]["holes"]])
