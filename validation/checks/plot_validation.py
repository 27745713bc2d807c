#!/usr/bin/python3
"""Plots of `ppohdem validate` (validation/checks): measured points against reference curves.

usage: plot_validation.py KIND CSV PNG [labels...]
Called by the check groups (plot.cpp) with the CSV they wrote; run with /usr/bin/python3
(numpy + matplotlib, Debian python3-matplotlib).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    return np.atleast_1d(data)


def force_overlap(d, png, labels):
    fig, axes = plt.subplots(1, 4, figsize=(16, 3.8))
    for case, ax in enumerate(axes):
        sel = d[d["case"] == case]
        if len(sel) == 0:
            continue
        order = np.argsort(sel["overlap"])
        ax.plot(sel["overlap"][order] * 1e6, sel["hertz"][order] / 1e3, "k-", lw=1,
                label="Hertz F = (4/3) E* R*^1/2 delta^3/2")
        ax.plot(sel["overlap"] * 1e6, sel["force"] / 1e3, ".", ms=3, label="engine (loading + unloading)")
        ax.set_title(labels[case] if case < len(labels) else str(case))
        ax.set_xlabel("overlap [um]")
        ax.set_ylabel("normal force [kN]")
    axes[0].legend(fontsize=7)
    fig.suptitle("Chung & Ooi tests 1-2: force-overlap of elastic normal impacts")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def restitution(d, png, labels):
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    ax.plot([0, 1], [0, 1], "k-", lw=1, label="e_out = e_in")
    markers = {0: "o", 1: "s"}
    for m in np.unique(d["material"]):
        for law, name in ((0, "Hertz-Mindlin"), (1, "linear")):
            sel = d[(d["material"] == m) & (d["law"] == law)]
            lab = labels[int(m)] if int(m) < len(labels) else str(m)
            ax.plot(sel["e_in"], sel["e_out"], markers[law], mfc="none", ms=6 + 3 * int(m),
                    label=f"{lab}, {name}")
    ax.set_xlabel("input restitution e")
    ax.set_ylabel("measured restitution")
    ax.set_title("Chung & Ooi test 3 (R 2.5 mm, 3.9 m/s)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def oblique(d, png, labels):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    cols = (("e_t", "e_t_ref", "tangential restitution v_t'/v_t"),
            ("omega", "omega_ref", "rebound spin [rad/s]"),
            ("angle", "angle_ref", "contact-point rebound angle [deg]"))
    for ax, (c, r, title) in zip(axes, cols):
        for m in np.unique(d["material"]):
            sel = d[d["material"] == m]
            lab = labels[int(m)] if int(m) < len(labels) else str(m)
            ax.plot(sel["theta"], sel[r], "-", lw=1, label=f"{lab}: two-body Hertz-Mindlin solution")
            ax.plot(sel["theta"], sel[c], "o", mfc="none", ms=5, label=f"{lab}: engine")
        ax.set_xlabel("incident angle [deg]")
        ax.set_title(title)
    axes[0].legend(fontsize=7)
    fig.suptitle("Chung & Ooi test 4: oblique impacts at 3.9 m/s on a rigid plane (R 2.5 mm, mu 0.092, e 0.98)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def psi(d, png, labels):
    """Tests 5-8: Psi2 vs Psi1 per test and material; labels = [spin CSV, "test:material:name"...]."""
    spin = load(labels[0]) if labels else None
    names = {}
    for item in labels[1:]:
        t, m, name = item.split(":", 2)
        names[(int(t), int(m))] = name
    fig, axes = plt.subplots(1, 5, figsize=(22, 4.4))
    titles = {5: "test 5: v_n 5 m/s, varied v_t (mu 0.3, e 1)", 6: "test 6: sphere-plane with spin (mu 0.4, e 0.5)",
              7: "test 7: two spheres, spins +w +w (slip 2wR)", 8: "test 8: R 0.1 m on R 0.5 m with spin"}
    for ax, t in zip(axes, (5, 6, 7, 8)):
        sel_t = d[d["test"] == t]
        for k, m in enumerate(np.unique(sel_t["material"])):
            sel = sel_t[sel_t["material"] == m]
            lab = names.get((t, int(m)), str(m))
            color = "C%d" % k
            ax.plot(sel["psi1"], sel["psi2_ref"], "-", color=color, lw=1, label=f"{lab}: two-body solution")
            ax.plot(sel["psi1"], sel["psi2"], "o", color=color, mfc="none", ms=5, label=f"{lab}: engine")
            s2 = sel["slide"][0]
            if sel["psi1"].max() > s2:
                x = np.linspace(s2, sel["psi1"].max(), 50)
                ax.plot(x, x - s2, "--", color=color, lw=0.8, label=f"{lab}: sliding Psi1 - 2chi(1+e)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.set_title(titles[t], fontsize=9)
        ax.set_xlabel("Psi1 = 4 G* v_c / (mu E* v_n)")
        ax.legend(fontsize=6)
    axes[0].set_ylabel("Psi2 = 4 G* v_c' / (mu E* v_n)")
    ax = axes[4]
    if spin is not None and len(spin):
        for k, m in enumerate(np.unique(spin["material"])):
            sel = spin[spin["material"] == m]
            lab = names.get((7, int(m)), str(m))
            ax.plot(sel["omega"], sel["omega_a"], "o", mfc="none", color="C%d" % k, label=f"{lab}: w_A'")
            ax.plot(sel["omega"], sel["omega_b"], "x", color="C%d" % k, label=f"{lab}: -w_B'")
        w = np.linspace(0, spin["omega"].max(), 10)
        ax.plot(w, w, "k-", lw=1, label="w' = w (no slip: exact)")
    ax.set_title("test 7 as published: spins +w, -w", fontsize=9)
    ax.set_xlabel("initial spin w [rad/s]")
    ax.set_ylabel("rebound spin [rad/s]")
    ax.legend(fontsize=6)
    fig.suptitle("Chung & Ooi tests 5-8 with the published materials, radii and velocities")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def series(d, png, labels):
    """Generic: first column x, the others y (log scale if labels[0] == 'log')."""
    names = d.dtype.names
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for n in names[1:]:
        ax.plot(d[names[0]], np.abs(d[n]) if labels and labels[0] == "log" else d[n], ".-", label=n)
    if labels and labels[0] == "log":
        ax.set_yscale("log")
    ax.set_xlabel(names[0])
    if len(labels) > 1:
        ax.set_title(labels[1])
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


KINDS = {"force_overlap": force_overlap, "restitution": restitution, "oblique": oblique, "psi": psi,
         "series": series}

if __name__ == "__main__":
    kind, csv, png = sys.argv[1:4]
    KINDS[kind](load(csv), png, sys.argv[4:])
