#!/usr/bin/python3
"""Plots of the port check (docs/port-validation.md).

    plot_port.py scores SCORES.csv OUT.png SIGMA SCENE
        the PC scores of the port's runs (columns run1..runN) against +-SIGMA
    plot_port.py growth GROWTH.csv OUT.png 0 SCENE
        the growth diagnostic: port-vs-reference RMS over the members' pairwise envelope
"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def scores(path, png, sigma, scene):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    runs = [k for k in rows[0] if k.startswith("run")]
    pcs = [int(float(r["pc"])) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for i, run in enumerate(runs):
        ax.plot([p + 0.15 * (i - 1) for p in pcs], [float(r[run]) for r in rows], "o", label=run)
    for s in (sigma, -sigma):
        ax.axhline(s, color="red", lw=1, ls="--")
    ax.axhline(0, color="gray", lw=0.5)
    ax.set_xlabel("principal component")
    ax.set_ylabel("score [ensemble sigma]")
    ax.set_title(f"{scene}: port runs on the ensemble's PCs (dashed: +-{sigma:g} sigma)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def growth(path, png, scene):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    step = [float(r["step"]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.fill_between(step, [float(r["low"]) for r in rows], [float(r["high"]) for r in rows], color="0.85",
                    label="reference members, pairwise (min-max)")
    ax.plot(step, [float(r["median"]) for r in rows], color="0.5", lw=1, label="median")
    port = [(s, float(r["port"])) for s, r in zip(step, rows) if float(r["port"]) > 0]
    if port:
        ax.plot(*zip(*port), "o-", color="C3", label="port vs reference (same seed)")
    ax.set_yscale("log")
    ax.set_xlabel("step")
    ax.set_ylabel("RMS position difference [m]")
    ax.set_title(f"{scene}: growth diagnostic (a bitwise-equal port has no points)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    if sys.argv[1] == "scores":
        scores(sys.argv[2], sys.argv[3], float(sys.argv[4]), sys.argv[5])
    elif sys.argv[1] == "growth":
        growth(sys.argv[2], sys.argv[3], sys.argv[5])
    else:
        sys.exit("unknown plot kind " + sys.argv[1])
