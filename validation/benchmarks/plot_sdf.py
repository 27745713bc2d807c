#!/usr/bin/python3
"""Plot SDF build time against max |error| (in h, vs the oracle) from ci/bench-sdf.sh's results.tsv,
and print the results as a Markdown table. Needs numpy-free matplotlib (Debian python3-matplotlib).
Usage: plot_sdf.py results.tsv out.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
FLOOR = 1e-16  # errors of exactly 0 (the oracle itself) are drawn at this level on the log axis

fig, ax = plt.subplots(figsize=(8, 5.5))
markers = {"bunny_closed": "o", "dragon_100k": "s", "bunny": "^"}
colours = {}
for r in rows:
    if r["status"] != "ok" or r["seconds"] == "-":
        continue
    method = r["method"]
    colour = colours.setdefault(method, "C%d" % len(colours))
    err = max(float(r["max_all_h"]), FLOOR)
    size = {"64": 30, "128": 60, "256": 110}.get(r["n"], 40)
    ax.scatter(float(r["seconds"]), err, c=colour, marker=markers.get(r["mesh"], "x"), s=size,
               label=method, alpha=0.8, edgecolors="k", linewidths=0.4)
handles, labels = ax.get_legend_handles_labels()
unique = dict(zip(labels, handles))
ax.legend(unique.values(), unique.keys(), fontsize=8, loc="center right")
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("build time on 2 cores [s] (log)")
ax.set_ylabel("max |phi - oracle| over all nodes [h] (log; exact 0 drawn at 1e-16)")
ax.set_title("SDF builders: time vs max error\n(o bunny_closed, s dragon, ^ open bunny; marker size = 64/128/256^3)")
ax.grid(True, which="both", alpha=0.3)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)

cols = ["mesh", "n", "method", "threads", "precision", "seconds", "nodes_per_second", "peak_rss_bytes",
        "max_all_h", "rms_all_h", "max_band_h", "rms_band_h", "sign_mismatches", "oracle", "status"]
print("| " + " | ".join(cols) + " |")
print("|" + "---|" * len(cols))
for r in rows:
    cells = []
    for c in cols:
        v = r[c]
        if c == "peak_rss_bytes" and v not in ("-", ""):
            v = "%.0f MiB" % (float(v) / 2**20)
        elif c in ("seconds",) and v not in ("-", ""):
            v = "%.2f" % float(v)
        elif c == "nodes_per_second" and v not in ("-", ""):
            v = "%.3g" % float(v)
        elif c.startswith(("max_", "rms_")) and v not in ("-", ""):
            v = "%.2g" % float(v)
        cells.append(v)
    print("| " + " | ".join(cells) + " |")
