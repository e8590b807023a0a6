"""A study directory cut by seed: the rows of some replicate seeds written as the study of
those seeds (study.json's sweep lists them, its case count theirs), so that `pgt compare` can
be tried on studies that differ in their seeds only (analysis/compare_calibration.py, the
tests)."""
import copy
import csv
import io
import json
import os


def read_rows(directory):
    """DIR/results.csv as a list of dicts (every field as written)."""
    with open(os.path.join(directory, "results.csv"), newline="") as f:
        return list(csv.DictReader(f))


def write_study(directory, identity, rows, seeds):
    """DIR holding `rows` of the given seeds, with the identity of a study of those seeds."""
    os.makedirs(directory)
    ident = copy.deepcopy(identity)
    ident["sweep"].pop("replicates", None)
    ident["sweep"]["seed"] = [int(s) for s in seeds]
    kept = [r for r in rows if float(r["seed"]) in seeds]
    labels = {r["label"] for r in kept}
    ident["cases"] = len(kept) // max(1, len(labels))
    with open(os.path.join(directory, "study.json"), "w") as f:
        json.dump(ident, f, indent=2)
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=list(rows[0].keys()), lineterminator="\n")
    w.writeheader()
    w.writerows(kept)
    with open(os.path.join(directory, "results.csv"), "w") as f:
        f.write(out.getvalue())


def scaled(rows, factor):
    """Rows with `mean` multiplied by factor(row): a change made by hand."""
    out = []
    for r in rows:
        r = dict(r)
        r["mean"] = repr(float(r["mean"]) * factor(r))
        out.append(r)
    return out
