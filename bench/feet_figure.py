#!/usr/bin/python3
"""Clean feet, measured and drawn: the skating table of docs/synthesis.md and docs/feet.png.

    /usr/bin/python3 bench/feet_figure.py                 # table on stdout, picture docs/feet.png
    /usr/bin/python3 bench/feet_figure.py --png /tmp/feet.png --motionmap build/apps/cli/motionmap
    /usr/bin/python3 bench/feet_figure.py --smooth 0.1 --png /tmp/feet-smooth.png

Two real 30 fps walks of one performer (Bandai Namco's normal and proud walks) are mapped
together (pca); `motionmap synth` then makes three motions: along the normal walk's own map
trajectory at its own timing; the same on the map of every other frame (`--stride 2`: half the
frames lie between samples, where the path follows the walk's curve at its pace and the blend
interpolates the walk's own two samples); and along the path halfway between the two walks (point k
of it the midpoint of the two walks' points at the same fraction of their length, timed like the
normal walk). Each is written raw (`--no-clean-feet`) and cleaned (the default), and `motionmap info
--skating --json` measures every clip: the skating ratio (the fraction of frame transitions where
a foot in contact moves faster than 0.5 m/s over the floor) and the ankles' mean horizontal speed
in contact. The picture shows the halfway motion's left ankle, raw and cleaned: the
distance it has travelled on the floor over time (flat while it stands), and its horizontal speed
with the frames where it is under 5 cm shaded. With `--smooth σ` the normal walk's own trajectory
traced by hand (every point off by seeded noise, a quarter of the median step on each axis) is
also synthesized with its blend weights smoothed over time (`synth --smooth σ`), and the
picture shows that motion's left ankle instead, raw, cleaned and as captured: its height above
its lowest point (the measure's 5 cm contact line drawn) and its horizontal speed.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(" ".join(cmd) + "\n" + out.stderr)
    return out.stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionmap", default=os.path.join(ROOT, "build/apps/cli/motionmap"))
    parser.add_argument("--python", default=os.path.join(ROOT, "build/python"))
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    parser.add_argument("--png", default=os.path.join(ROOT, "docs", "feet.png"))
    parser.add_argument("--smooth", type=float, default=0.0,
                        help="also synthesize the own trajectory traced by hand (each point "
                        "off by seeded noise of a quarter of the median step) with the weights "
                        "smoothed (σ in seconds) and draw its ankle's height and speed")
    args = parser.parse_args()
    sys.path.insert(0, args.python)
    import motionmap

    normal = os.path.join(args.data, "other", "BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh")
    proud = os.path.join(args.data, "bandai", "dataset-1_walk_proud_001.bvh")
    mm = args.motionmap
    with tempfile.TemporaryDirectory() as work:
        csv = os.path.join(work, "walks.csv")
        run([mm, "map", normal, proud, "-m", "pca", "-o", csv, "-q"])
        rows = np.array([[float(v) for v in line.split(",")] for line in open(csv)
                         if line[0].isdigit() or line[0] == "-"])
        a = rows[rows[:, 0] == 0][:, 2:4]
        b = rows[rows[:, 0] == 1][:, 2:4]
        dt = motionmap.load(normal).frame_time
        # Both walks at the same fractions of their length, sampled at the normal walk's frames.
        s = np.linspace(0.0, 1.0, len(a))
        b_at = np.stack([np.interp(s, np.linspace(0.0, 1.0, len(b)), b[:, i]) for i in range(2)], 1)
        paths = {"own": (a, dt, []), "halfway": (0.5 * (a + b_at), dt, [])}
        # The normal walk's trajectory on the map of every other frame, at its own timing: half
        # the frames are blends of their neighbours.
        csv2 = os.path.join(work, "walks2.csv")
        run([mm, "map", normal, proud, "-m", "pca", "--stride", "2", "-o", csv2, "-q"])
        rows2 = np.array([[float(v) for v in line.split(",")] for line in open(csv2)
                          if line[0].isdigit() or line[0] == "-"])
        paths["stride"] = (rows2[rows2[:, 0] == 0][:, 2:4], 2 * dt, ["--stride", "2", "--fps", str(1 / dt)])
        clips = {"normal walk (captured)": normal, "proud walk (captured)": proud}
        names = {"own": "own trajectory", "halfway": "halfway path",
                 "stride": "own trajectory, map of every other frame"}
        if args.smooth > 0:
            # Traced by hand: every point of the own trajectory off by seeded noise, σ a quarter
            # of the median step between its points on each axis, as a drawn copy would be.
            jitter = 0.25 * np.median(np.linalg.norm(np.diff(a, axis=0), axis=1))
            traced = a + np.random.default_rng(23).normal(0.0, jitter, a.shape)
            paths["smooth"] = (traced, dt, ["--smooth", repr(args.smooth)])
            names["smooth"] = f"own trajectory traced by hand, weights smoothed (σ {args.smooth:g} s)"
        for name, (points, step, extra) in paths.items():
            path = os.path.join(work, name + ".csv")
            with open(path, "w") as f:
                f.write("t,x,y\n")
                for k, (x, y) in enumerate(points):
                    f.write(f"{k * step!r},{x!r},{y!r}\n")
            for cleaned in (False, True):
                out = os.path.join(work, f"{name}-{'clean' if cleaned else 'raw'}.bvh")
                run([mm, "synth", normal, proud, "-m", "pca", "--path", path, "-o", out, "-q"]
                    + extra + ([] if cleaned else ["--no-clean-feet"]))
                clips[names[name] + (", cleaned" if cleaned else ", raw")] = out

        print("| clip | skating ratio | ankle speed in contact (cm/s) |")
        print("|---|---:|---:|")
        info = {}
        for label, path in clips.items():
            info[label] = json.loads(run([mm, "info", path, "--skating", "--contacts", "--json"]))
            k = info[label]["skating"]
            print(f"| {label} | {k['ratio']:.2f} | {k['contact_speed_cm_s']:.0f} |")

        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        if args.smooth > 0:
            draw_smoothed(motionmap, plt, clips, info, names["smooth"], normal, args.png)
            return 0
        fig, (top, speed) = plt.subplots(1, 2, figsize=(11, 4.2))
        lines = {}
        shown = "halfway path"
        for label, style in ((shown + ", raw", dict(color="tab:red", lw=1.0, alpha=0.7)),
                             (shown + ", cleaned", dict(color="tab:blue", lw=1.6))):
            clip = motionmap.load(clips[label])
            ankle = np.asarray(clip.positions())[:, clip.skeleton.names.index("Foot_L")]
            fps = clip.fps
            horizontal = np.linalg.norm(np.diff(ankle[:, [0, 2]], axis=0), axis=1) * fps
            low = ankle[:, 1] - ankle[:, 1].min() < 5.0  # the measure's contact: under 5 cm
            k = info[label]["skating"]
            name = f"{label.split(', ')[-1]}: skating {k['ratio']:.2f}, " \
                f"{k['contact_speed_cm_s']:.0f} cm/s in contact"
            # Distance along the floor from the start: flat while the foot stands.
            travelled = np.concatenate([[0.0], np.cumsum(horizontal / fps)])
            top.plot(np.arange(len(travelled)) / fps, travelled, label=name, **style)
            t = np.arange(len(horizontal)) / fps
            lines[label] = speed.plot(t, horizontal, label=name, **style)
            if label.endswith("cleaned"):
                both = low[:-1] & low[1:]
                speed.fill_between(t, 0, 1, where=both, color="0.85",
                                   transform=speed.get_xaxis_transform(), lw=0,
                                   label="cleaned ankle under 5 cm (in contact)")
        top.set_xlabel("time (s)")
        top.set_ylabel("distance along the floor (cm)")
        top.set_title("left ankle's path: flat where the foot stands", fontsize=10)
        speed.axhline(50.0, color="k", lw=0.8, ls="--", label="0.5 m/s: skating above")
        speed.set_xlabel("time (s)")
        speed.set_ylabel("horizontal speed (cm/s)")
        speed.set_ylim(0, 300)
        speed.set_title("left ankle speed: planted feet stand still", fontsize=10)
        speed.legend(fontsize=8, loc="upper right")
        top.legend(fontsize=8, loc="upper left")
        fig.suptitle("A path halfway between two captured walks' map trajectories, synthesized "
                     "raw and with clean feet", fontsize=11)
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)
        print(f"\nwrote {args.png}")
    return 0


def draw_smoothed(motionmap, plt, clips, info, shown, captured, png):
    """The smoothed motion's left ankle, raw, cleaned and captured: height and speed."""
    fig, (height, speed) = plt.subplots(2, 1, figsize=(11, 6.4), sharex=True)
    for label, path, style in (
            ("captured", captured, dict(color="0.45", lw=1.0, ls="--")),
            ("raw", clips[shown + ", raw"], dict(color="tab:red", lw=1.0, alpha=0.8)),
            ("cleaned", clips[shown + ", cleaned"], dict(color="tab:blue", lw=1.6))):
        clip = motionmap.load(path)
        ankle = np.asarray(clip.positions())[:, clip.skeleton.names.index("Foot_L")]
        fps = clip.fps
        up = ankle[:, 1] - ankle[:, 1].min()
        horizontal = np.linalg.norm(np.diff(ankle[:, [0, 2]], axis=0), axis=1) * fps
        if label == "captured":
            name = "captured"
        else:
            k = info[shown + ", " + label]["skating"]
            name = (f"{label}: skating {k['ratio']:.2f}, "
                    f"{k['contact_speed_cm_s']:.0f} cm/s in contact")
        t = np.arange(len(up)) / fps
        height.plot(t, up, label=name, **style)
        speed.plot(t[:-1] + 0.5 / fps, horizontal, label=name, **style)
        if label == "cleaned":
            both = (up[:-1] < 5.0) & (up[1:] < 5.0)
            speed.fill_between(t[:-1] + 0.5 / fps, 0, 1, where=both, color="0.85",
                               transform=speed.get_xaxis_transform(), lw=0,
                               label="cleaned ankle under 5 cm (in contact)")
    height.axhline(5.0, color="k", lw=0.8, ls=":", label="5 cm: the measure's contact below")
    height.set_ylabel("height above its lowest (cm)")
    height.set_title("left ankle's height", fontsize=10)
    height.legend(fontsize=8, loc="upper right")
    speed.axhline(50.0, color="k", lw=0.8, ls=":", label="0.5 m/s: skating above")
    speed.set_xlabel("time (s)")
    speed.set_ylabel("horizontal speed (cm/s)")
    speed.set_ylim(0, 300)
    speed.set_title("left ankle's horizontal speed", fontsize=10)
    speed.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"The normal walk's map trajectory {shown.split(' ', 2)[2]}: raw, cleaned "
                 "and captured", fontsize=11)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"\nwrote {png}")


if __name__ == "__main__":
    sys.exit(main())
