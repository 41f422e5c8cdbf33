"""Paired per-mesh differences between two `meshflow eval generate` runs on the same meshes,
samples and seeds (the pairing removes the meshes' own spread): shared by the experiment
log's analysis scripts (docs/experiments/data/*/analyse.py), which import it from here."""
import math


def per_mesh(o, key):
    """A per-mesh figure: the edge F-score sits under `sharp`, the rest at the top."""
    return o["sharp"]["edge_f_score"]["f_score"] if key == "edge_f_score" else o[key]


def mean_se(d):
    """The mean of the differences `d` and its standard error."""
    n = len(d)
    mean = sum(d) / n
    sd = math.sqrt(sum((x - mean) ** 2 for x in d) / (n - 1))
    return mean, sd / math.sqrt(n)


def paired(a, b, key):
    """`key` of run `a` minus run `b`, per mesh (both with faces): mean and standard error."""
    return mean_se([per_mesh(x["ours"], key) - per_mesh(y["ours"], key)
                    for x, y in zip(a["per_mesh"], b["per_mesh"])
                    if x["ours"] and y["ours"] and x["name"] == y["name"]])
