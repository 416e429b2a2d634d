#!/usr/bin/env python3
"""Where the real-texture yardstick's category choice goes wrong: the vote or the short fits.

Reads a yardstick run (ps_bench_real_textures --work WORK --csv CSV) and, per part the fit view
sees with at least --min-pixels pixels, the select stage's record in the method's materials file
(fit.candidates: the kNN vote's top 5; fit.finalists: every finalist's short-fit loss and whether
it passed the pixel-error and contrast tests). Prints the finalists per part (lowest loss first,
'*' = failed the tests) and counts, on those parts:

  vote top 1      the vote's best graph has the true category
  vote top 5      some graph of the true category is in the vote's top 5
  in finalists    some textured finalist has the true category
  best textured   the textured finalist with the lowest loss has it
  best passing    the lowest-loss textured finalist that passes the tests has it
  chosen          the part's graph has it (what the yardstick's summary counts)

Categories come from the library's graph files (modules/graph/library/*.json).

  python3 scripts/yardstick_finalists.py --work W --csv W.csv [--library DIR] [--quiet]
"""
import argparse
import csv
import glob
import json
import os
import sys


def load_categories(library):
    cats = {}
    for f in glob.glob(os.path.join(library, "*.json")):
        with open(f) as fh:
            cats[os.path.splitext(os.path.basename(f))[0]] = json.load(fh).get("category", "")
    if not cats:
        sys.exit(f"{library}: no graph files (*.json)")
    return cats


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--work", required=True, help="the yardstick's --work folder")
    ap.add_argument("--csv", required=True, help="the yardstick's --csv file")
    ap.add_argument("--library", default=os.path.join(here, "..", "modules", "graph", "library"))
    ap.add_argument("--min-pixels", type=int, default=2000, help="the yardstick's category bar")
    ap.add_argument("--quiet", action="store_true", help="counts only")
    a = ap.parse_args()
    cats = load_categories(a.library)
    with open(a.csv) as fh:
        rows = list(csv.DictReader(fh))
    keys = ["vote top 1", "vote top 5", "in finalists", "best textured", "best passing", "chosen"]
    count = {(split, k): 0 for split in ("tune", "check") for k in keys}
    parts = {"tune": 0, "check": 0}
    for r in rows:
        if int(r["fit_pixels"]) < a.min_pixels:
            continue
        f = os.path.join(a.work, "runs", r["material"], r["lighting"], "method", "materials",
                         r["part"] + ".json")
        if not os.path.exists(f):
            print(f"{f}: missing (run the yardstick first)", file=sys.stderr)
            continue
        with open(f) as fh:
            fit = json.load(fh).get("fit", {})
        truth, split = r["category"], r["split"]
        parts[split] += 1
        votes = [cats.get(c["graph"], "?") for c in fit.get("candidates", [])]
        fins = sorted(fit.get("finalists", []), key=lambda x: x["loss"])
        textured = [x for x in fins if x["graph"] != "homogeneous"]
        passing = [x for x in textured if x.get("qualifies", True)]
        hit = {
            "vote top 1": bool(votes) and votes[0] == truth,
            "vote top 5": truth in votes[:5],
            "in finalists": any(x["category"] == truth for x in textured),
            "best textured": bool(textured) and textured[0]["category"] == truth,
            "best passing": bool(passing) and passing[0]["category"] == truth,
            "chosen": r["category_right"] == "1",
        }
        for k in keys:
            count[(split, k)] += hit[k]
        if not a.quiet:
            line = " ".join(f"{x['graph']}:{x['loss']:.4g}{'' if x.get('qualifies', True) else '*'}"
                            for x in fins)
            print(f"{r['material'][:28]:28s} {truth[:9]:9s} {r['part'][:11]:11s} {line}")
    for split in ("tune", "check"):
        n = parts[split]
        if n == 0:
            continue
        cells = ", ".join(f"{k} {count[(split, k)]}/{n}" for k in keys)
        print(f"{split}: {n} parts >= {a.min_pixels} px: {cells}")


if __name__ == "__main__":
    main()
