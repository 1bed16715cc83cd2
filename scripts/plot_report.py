#!/usr/bin/env python3
"""Plots of an evaluation (DIR/timeseries.csv written by `evaluate`): ADD-S over time per object
(objects_add_s.png), localization error over time (localization.png), time per pipeline stage
(stage_times.png) and, with or without ground truth, each track's inlier ratio and depth residual
and the number of tracks over time (tracks.png). Usage: plot_report.py DIR"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(out):
    rows = list(csv.DictReader(open(f"{out}/timeseries.csv")))
    objects = defaultdict(lambda: ([], []))
    frames = [r for r in rows if r["kind"] == "frame"]
    for r in rows:
        if r["kind"] == "object" and r["add_s_mm"]:
            objects[r["id"]][0].append(float(r["stamp"]))
            objects[r["id"]][1].append(float(r["add_s_mm"]))
    t0 = float(frames[0]["stamp"]) if frames else 0.0

    fig, ax = plt.subplots(figsize=(9, 4))
    for name, (t, e) in sorted(objects.items()):
        ax.plot([x - t0 for x in t], e, label=name, lw=1)
    ax.set(xlabel="time (s)", ylabel="ADD-S (mm)", title="Object pose error over time")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.grid(alpha=0.3)
    if objects:
        ax.legend(fontsize=8, ncol=3)
    fig.tight_layout()
    fig.savefig(f"{out}/objects_add_s.png", dpi=110)

    loc = [(float(r["stamp"]) - t0, float(r["loc_t_mm"])) for r in frames if r["loc_t_mm"]]
    fig, ax = plt.subplots(figsize=(9, 3))
    if loc:
        ax.plot(*zip(*loc), lw=1)
    ax.set(xlabel="time (s)", ylabel="error (mm)", title="Robot localization error")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/localization.png", dpi=110)

    stages = ["localize_ms", "associate_ms", "refine_ms", "presegment_ms"]
    fig, ax = plt.subplots(figsize=(9, 4))
    t = [float(r["stamp"]) - t0 for r in frames]
    bottom = [0.0] * len(frames)
    for s in stages:
        v = [float(r[s]) for r in frames]
        ax.fill_between(t, bottom, [b + x for b, x in zip(bottom, v)], step="mid", label=s[:-3], alpha=0.7)
        bottom = [b + x for b, x in zip(bottom, v)]
    ax.set(xlabel="time (s)", ylabel="ms per frame", title="Time per pipeline stage")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out}/stage_times.png", dpi=110)

    plot_tracks(out, rows, frames, t0)


def plot_tracks(out, rows, frames, t0):
    """tracks.png: per confirmed track its inlier ratio and median depth residual; the track count."""
    ratio, residual = defaultdict(lambda: ([], [])), defaultdict(lambda: ([], []))
    count = defaultdict(int)
    for r in rows:
        if r["kind"] != "track" or r.get("confirmed") != "1":
            continue
        t = float(r["stamp"]) - t0
        count[t] += 1
        ratio[r["id"]][0].append(t), ratio[r["id"]][1].append(float(r["inlier_ratio"]))
        if r["depth_residual_mm"]:
            residual[r["id"]][0].append(t), residual[r["id"]][1].append(float(r["depth_residual_mm"]))
    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for name, (t, v) in sorted(ratio.items()):
        axes[0].plot(t, v, lw=1, label=name)
    for name, (t, v) in sorted(residual.items()):
        axes[1].plot(t, v, lw=1, label=name)
    ts = [float(r["stamp"]) - t0 for r in frames]
    axes[2].step(ts, [count.get(t, 0) for t in ts], where="mid", lw=1)
    axes[0].set(ylabel="inlier ratio", title="Tracks (no ground truth needed)")
    axes[1].set(ylabel="depth residual (mm)")
    axes[1].set_yscale("symlog", linthresh=1.0)
    axes[2].set(xlabel="time (s)", ylabel="confirmed tracks")
    for ax in axes:
        ax.grid(alpha=0.3)
    if ratio:
        axes[0].legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(f"{out}/tracks.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])
