#!/usr/bin/python3
"""The GP-LVM's predictive variance over its maps (docs/methods/gplvm.md, docs/gplvm-variance.png):
(sigma^2(x) - s) / (sigma_f^2 + sigma_b^2) from each map file's /model/gplvm (numpy, dense), with
the contours tau = 0.05, 0.1, 0.2, 0.5, the trajectory and (sparse maps) the inducing inputs.
Not used by the tests.

    motionmap map ../shared/data/cmu/64_08.bvh --method gplvm --save /tmp/g64.mmap.h5 -o /tmp/g64.csv
    motionmap map ../shared/data/bandai/dataset-1_walk_*.bvh --method gplvm --save /tmp/walks.mmap.h5 -o /tmp/walks.csv
    /usr/bin/python3 tests/reference/gplvm_variance_figure.py docs/gplvm-variance.png /tmp/g64.mmap.h5 /tmp/walks.mmap.h5
"""
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LEVELS = [0.05, 0.1, 0.2, 0.5]
COLORS = ["#1a9850", "#d73027", "#fc8d59", "#4575b4"]


def variance_fraction(P, B, C, sf2, l, sb2):
    out = np.empty(len(P))
    for s in range(0, len(P), 4000):
        d2 = ((P[s:s + 4000, None, :] - B[None]) ** 2).sum(-1)
        k = sf2 * np.exp(-d2 / (2 * l * l)) + sb2
        out[s:s + 4000] = (sf2 + sb2 - np.einsum("ij,jk,ik->i", k, C, k)) / (sf2 + sb2)
    return out


def panel(ax, path):
    with h5py.File(path, "r") as f:
        xy = np.array(f["/coordinates"])
        g = f["/model/gplvm"]
        B, C = np.array(g["basis"]), np.array(g["C"])
        sf2, l, sb2 = (float(g.attrs[k]) for k in ("rbf_variance", "lengthscale", "bias_variance"))
    lo, hi = xy.min(0), xy.max(0)
    lo, hi = lo - 0.12 * (hi - lo), hi + 0.12 * (hi - lo)
    gx, gy = np.linspace(lo[0], hi[0], 320), np.linspace(lo[1], hi[1], 320)
    V = variance_fraction(np.stack(np.meshgrid(gx, gy), -1).reshape(-1, 2), B, C, sf2, l, sb2)
    V = V.reshape(len(gy), len(gx))
    im = ax.imshow(V, origin="lower", extent=[lo[0], hi[0], lo[1], hi[1]], cmap="Greys",
                   vmin=0, vmax=1)
    ax.contour(gx, gy, V, levels=LEVELS, colors=COLORS, linewidths=1.0)
    ax.plot(xy[:, 0], xy[:, 1], "-", color="#2166ac", lw=0.4)
    ax.plot(xy[:, 0], xy[:, 1], ".", color="#2166ac", ms=1.2)
    if len(B) != len(xy):
        ax.plot(B[:, 0], B[:, 1], "x", color="#762a83", ms=3.5)
    ax.set_title("%s: %d frames, %s, ℓ = %.3f" % (
        path.split("/")[-1].replace(".mmap.h5", ""), len(xy),
        "full" if len(B) == len(xy) else "sparse (%d inducing, ×)" % len(B), l), fontsize=9)
    ax.set_aspect("equal")
    return im


def main():
    out, paths = sys.argv[1], sys.argv[2:]
    fig, axes = plt.subplots(1, len(paths), figsize=(5.2 * len(paths), 5))
    axes = np.atleast_1d(axes)
    for ax, path in zip(axes, paths):
        im = panel(ax, path)
    handles = [plt.Line2D([], [], color=c, label="τ = %g" % t) for t, c in zip(LEVELS, COLORS)]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=9)
    fig.colorbar(im, ax=list(axes), shrink=0.8, label="(σ²(x) − s) / (σ_f² + σ_b²)")
    fig.savefig(out, dpi=100, bbox_inches="tight")


if __name__ == "__main__":
    main()
