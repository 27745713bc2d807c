#!/usr/bin/python3
"""False-positive rate of candidate rules on a baseline's stored members (docs/port-validation.md
"False-positive rate"): the stored held-out split, then random 100 / 30 resplits of all members
(the ensemble is refitted on the 100 and every triple of the 30 is judged; a triple of seeds
fails if any scene fails).

    /usr/bin/python3 validation/port/rule_study.py fixtures/port-baseline [RESAMPLES]
"""
import glob
import itertools
import os
import sys

import numpy as np


def load(path):
    with open(path) as f:
        rows = [line.strip().split(",") for line in f if line.strip()]
    data = np.array([[float(x) for x in r[2:]] for r in rows[1:]])
    held = np.array([r[1] == "held-out" for r in rows[1:]])
    return data, held


def fit(x, keep=0.95):
    mean, sd = x.mean(0), x.std(0, ddof=1)
    z = (x - mean) / sd
    w, v = np.linalg.eigh(z.T @ z / (len(x) - 1))
    w, v = w[::-1], v[:, ::-1]
    k = int(np.searchsorted(np.cumsum(w) / w.sum(), keep)) + 1
    return mean, sd, w[:k], v[:, :k]


def scores(b, x):
    mean, sd, w, v = b
    return ((x - mean) / sd) @ v / np.sqrt(w)


def failures(s, triples, sigma, min_pcs):
    beyond = (np.abs(s) > sigma).astype(int)
    count = beyond[triples[:, 0]] + beyond[triples[:, 1]] + beyond[triples[:, 2]]
    return (count >= 2).sum(1) >= min_pcs


def main():
    folder = sys.argv[1]
    resamples = int(sys.argv[2]) if len(sys.argv) > 2 else 40
    scenes = {os.path.basename(p)[:-12]: load(p) for p in sorted(glob.glob(os.path.join(folder, "*.members.csv")))}
    rules = [(2.5, 1), (2.5, 2), (3.0, 1), (3.0, 2), (3.5, 1)]
    n_held = int(next(iter(scenes.values()))[1].sum())
    triples = np.array(list(itertools.combinations(range(n_held), 3)))
    print("| sigma | failing PCs | " + " | ".join(scenes) + " | whole check | resampled mean (min-max) |")
    print("|---|---|" + "---|" * len(scenes) + "---|---|")
    rng = np.random.default_rng(1)
    splits = []
    for _ in range(resamples):
        perm = rng.permutation(len(next(iter(scenes.values()))[0]))
        splits.append((perm[n_held:], perm[:n_held]))
    fitted = [{name: scores(fit(d[f]), d[h]) for name, (d, _) in scenes.items()} for f, h in splits]
    stored = {name: scores(fit(d[~held]), d[held]) for name, (d, held) in scenes.items()}
    for sigma, min_pcs in rules:
        per = {name: failures(s, triples, sigma, min_pcs) for name, s in stored.items()}
        whole = np.logical_or.reduce(list(per.values()))
        rates = []
        for s in fitted:
            rates.append(np.logical_or.reduce([failures(x, triples, sigma, min_pcs) for x in s.values()]).mean())
        print(f"| {sigma} | {min_pcs} | " + " | ".join(f"{100 * f.mean():.2f} %" for f in per.values()) +
              f" | {100 * whole.mean():.2f} % | {100 * np.mean(rates):.2f} % ({100 * min(rates):.2f}-{100 * max(rates):.2f} %) |")


if __name__ == "__main__":
    main()
