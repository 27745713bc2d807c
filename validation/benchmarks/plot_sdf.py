#!/usr/bin/python3
"""Plot SDF build time against max |error| (in h, vs the oracle) from ci/bench-sdf.sh's results.tsv,
and print the results as a Markdown table. Needs only matplotlib (Debian python3-matplotlib).
Usage: plot_sdf.py results.tsv out.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
FLOOR = 1e-16  # errors of exactly 0 (the oracle itself) are drawn at this level on the log axis

fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharex=True)
markers = {"bunny_closed": "o", "dragon_100k": "s", "bunny": "^"}
colours = {}
for r in rows:
    if not r["status"].startswith("ok") or r["seconds"] == "-":
        continue
    method = r["method"]
    colour = colours.setdefault(method, "C%d" % (len(colours) % 10))
    size = {"64": 30, "128": 60, "256": 110}.get(r["n"], 40)
    for ax, key in zip(axes, ("max_all_h", "max_band_h")):
        err = max(float(r[key]), FLOOR)
        ax.scatter(float(r["seconds"]), err, c=colour, marker=markers.get(r["mesh"], "x"), s=size,
                   label=method, alpha=0.8, edgecolors="k", linewidths=0.4)
for ax, what in zip(axes, ("over all nodes", "in the band |oracle| < 3 h")):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("build time [s] (log; threads as in the label)")
    ax.set_ylabel("max |phi - oracle| %s [h] (log; 0 drawn at 1e-16)" % what)
    ax.grid(True, which="both", alpha=0.3)
handles, labels = axes[0].get_legend_handles_labels()
unique = dict(zip(labels, handles))
axes[1].legend(unique.values(), unique.keys(), fontsize=8, loc="center right")
fig.suptitle("SDF builders: time vs max error (o bunny_closed, s dragon, ^ open bunny; "
             "marker size = 64/128/256^3)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)

cols = ["mesh", "n", "method", "threads", "precision", "seconds", "nodes_per_second", "peak_rss_bytes",
        "max_all_h", "rms_all_h", "max_band_h", "rms_band_h", "sign_mismatches", "oracle", "status", "load1"]
print("| " + " | ".join(cols) + " |")
print("|" + "---|" * len(cols))
for r in rows:
    cells = []
    for c in cols:
        v = r.get(c, "")
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
