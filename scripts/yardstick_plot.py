#!/usr/bin/env python3
"""Accuracy against seconds from real-texture yardstick runs, as an SVG (no plotting library).

Each argument is LABEL=LOG, LOG the standard output of one ps_bench_real_textures run. From each
log's summary it takes, for one half (--half, default tune): the category accuracy on the parts
of at least 2000 px, the texture distance ratio (fitted / offset truth), the masked RMSE of the
fit and of the pixel-median baseline, and the mean seconds per case of the select stage. It
prints a table and writes an SVG with two panels against select seconds: category accuracy and
distance ratio, one labelled point per run.

  python3 scripts/yardstick_plot.py --out sweep.svg "vote=vote.log" "2/2/8=s2c2k8.log" ...
"""
import argparse
import re
import sys


def read_summary(path, half):
    text = open(path).read()
    m = re.search(rf"^{half}\s+parts\s+(\d+) \| category right\s+(\d+)/\s*(\d+) =\s*([\d.nan]+) %.*?"
                  r"ratio ([\d.nan]+).*?masked RMSE \(sRGB 0-255\) fit ([\d.]+) vs pixel-median ([\d.]+)",
                  text, re.M)
    s = re.search(r"seconds per case \(mean\): method ([\d.]+) \((.*?)\)", text)
    if not m or not s:
        sys.exit(f"{path}: no '{half}' summary or seconds line (did the run finish?)")
    stages = dict((k, float(v)) for k, v in re.findall(r"(\w+) ([\d.]+)", s.group(2)))
    return {
        "right": int(m.group(2)), "parts": int(m.group(3)), "accuracy": float(m.group(4)),
        "ratio": float(m.group(5)), "rmse": float(m.group(6)), "rmse_median": float(m.group(7)),
        "method_s": float(s.group(1)), "select_s": stages.get("select", 0.0),
    }


def panel(x0, y0, w, h, runs, key, label, fmt, bar=None):
    xs = [r["select_s"] for r in runs]
    ys = [r[key] for r in runs]
    xmax = max(xs) * 1.15 or 1
    ymin, ymax = 0.0, max(max(ys) * 1.2, bar or 0) or 1
    sx = lambda x: x0 + 50 + (w - 70) * x / xmax
    sy = lambda y: y0 + h - 30 - (h - 50) * (y - ymin) / (ymax - ymin)
    out = [f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="white" stroke="#ccc"/>',
           f'<text x="{x0 + w / 2}" y="{y0 + 16}" text-anchor="middle" font-size="13">{label}</text>',
           f'<line x1="{sx(0)}" y1="{sy(ymin)}" x2="{sx(xmax)}" y2="{sy(ymin)}" stroke="black"/>',
           f'<line x1="{sx(0)}" y1="{sy(ymin)}" x2="{sx(0)}" y2="{sy(ymax)}" stroke="black"/>',
           f'<text x="{x0 + w / 2}" y="{y0 + h - 6}" text-anchor="middle" font-size="11">'
           f'select seconds per case (mean)</text>']
    for i in range(5):
        yv = ymin + (ymax - ymin) * i / 4
        xv = xmax * i / 4
        out.append(f'<text x="{sx(0) - 4}" y="{sy(yv) + 4}" text-anchor="end" font-size="10">'
                   f'{fmt.format(yv)}</text>')
        out.append(f'<text x="{sx(xv)}" y="{sy(ymin) + 13}" text-anchor="middle" font-size="10">'
                   f'{xv:.0f}</text>')
    if bar is not None and bar <= ymax:
        out.append(f'<line x1="{sx(0)}" y1="{sy(bar)}" x2="{sx(xmax)}" y2="{sy(bar)}" stroke="#d62728"'
                   f' stroke-dasharray="5,4"/><text x="{sx(xmax)}" y="{sy(bar) - 4}" text-anchor="end"'
                   f' font-size="10" fill="#d62728">issue 17 bar {fmt.format(bar)}</text>')
    for r in runs:
        out.append(f'<circle cx="{sx(r["select_s"])}" cy="{sy(r[key])}" r="4" fill="#1f77b4"/>')
        out.append(f'<text x="{sx(r["select_s"]) + 6}" y="{sy(r[key]) - 5}" font-size="10">'
                   f'{r["label"]}</text>')
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", help="LABEL=LOG")
    ap.add_argument("--half", default="tune", choices=["tune", "check", "all"])
    ap.add_argument("--out", required=True, help="SVG to write")
    a = ap.parse_args()
    runs = []
    for arg in a.runs:
        label, _, path = arg.partition("=")
        if not path:
            sys.exit(f"{arg}: expected LABEL=LOG")
        r = read_summary(path, a.half)
        r["label"] = label
        runs.append(r)
    print(f"| run | category right ({a.half}, >= 2000 px) | distance ratio | masked RMSE fit / median"
          " | select s / method s per case |")
    print("|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['label']} | {r['right']} / {r['parts']} = {r['accuracy']:.1f} % | {r['ratio']:.2f}"
              f" | {r['rmse']:.2f} / {r['rmse_median']:.2f} | {r['select_s']:.1f} / {r['method_s']:.1f} |")
    w, h = 420, 300
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * w + 10}" height="{h}" '
           'font-family="sans-serif">']
    svg += panel(0, 0, w, h, runs, "accuracy", f"category right, % ({a.half} half)", "{:.1f}")
    svg += panel(w + 10, 0, w, h, runs, "ratio", "texture distance / offset truth's", "{:.1f}",
                 bar=1.5)
    svg.append("</svg>")
    with open(a.out, "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
