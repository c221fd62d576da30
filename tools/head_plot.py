#!/usr/bin/python3
"""Head rotations over time: the speaker's real motion beside animations of the same speech.

    /usr/bin/python3 tools/head_plot.py SPEECH.wav HEADPOSE.csv OUT.png [--from S] [--to S] NAME=ANIMATION.csv ...

HEADPOSE.csv: 30 fps pitch/yaw/roll in degrees (BEAT2's neckhead_*_deg or StyleTalk's *_deg columns), shown
about its own mean over the stretch. Each ANIMATION.csv is `talkinghead animate` output: FAPs 48-50 (head pitch,
yaw, roll in 1e-5 rad) turned back into degrees. Pauses (frames 30 dB under the loud frames, as `eval head`
counts them) are shaded. A fourth panel marks the beats `eval head` scores Beat Align with: the speech's onsets
(peaks of the level's rise, at least 2 dB and 6 frames apart) and each motion's beats (local minima of its
angular speed smoothed over 5 frames). Needs python3-matplotlib, python3-numpy and python3-scipy (Debian packages).
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.io import wavfile  # noqa: E402


def read_pose(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    names = ["neckhead_pitch_deg", "neckhead_yaw_deg", "neckhead_roll_deg"]
    if names[0] not in rows[0]:
        names = ["pitch_deg", "yaw_deg", "roll_deg"]
    return np.array([[float(r[n]) for n in names] for r in rows])


def read_animation(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    degrees = 1e-5 * 180.0 / np.pi
    return np.array([[float(r[f"fap{n}"]) * degrees for n in (48, 49, 50)] for r in rows])


def gaussian_smoothed(x, sigma):
    radius = int(np.ceil(3 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-radius, radius + 1) / sigma) ** 2)
    kernel /= kernel.sum()
    return np.convolve(np.pad(x, radius, mode="edge"), kernel, mode="valid")


def speech_beats(level, min_rise=2.0, min_gap=6):
    rise = gaussian_smoothed(np.maximum(0.0, np.diff(level, prepend=level[0])), 1.0)
    beats = []
    for t in range(1, len(rise) - 1):
        if rise[t] < min_rise or rise[t] < rise[t - 1] or rise[t] <= rise[t + 1]:
            continue
        if beats and t - beats[-1] < min_gap:
            if rise[t] > rise[beats[-1]]:
                beats[-1] = t
            continue
        beats.append(t)
    return np.array(beats, dtype=int)


def motion_beats(rotations):
    speed = np.r_[0.0, np.linalg.norm(np.diff(rotations, axis=0), axis=1)]
    smooth = gaussian_smoothed(speed, 5.0)
    return np.array([t for t in range(1, len(smooth) - 1) if smooth[t] < smooth[t - 1] and smooth[t] <= smooth[t + 1]],
                    dtype=int)


def levels(wav, frames):
    rate, samples = wavfile.read(wav)
    samples = samples.astype(np.float64)
    if samples.ndim > 1:
        samples = samples.mean(axis=1)
    hop = rate / 30.0
    level = np.full(frames, -140.0)
    for t in range(frames):
        a, b = int(max(0, (t - 0.5) * hop)), int(min(len(samples), (t + 0.5) * hop))
        if b > a:
            level[t] = 10 * np.log10(np.mean(samples[a:b] ** 2) + 1e-12)
    return level


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("speech")
    parser.add_argument("headpose")
    parser.add_argument("output")
    parser.add_argument("animations", nargs="+", help="NAME=ANIMATION.csv")
    parser.add_argument("--from", dest="start", type=float, default=0.0)
    parser.add_argument("--to", dest="end", type=float, default=1e9)
    args = parser.parse_args()

    truth = read_pose(args.headpose)
    series = [("the speaker", truth)]
    for item in args.animations:
        name, path = item.split("=", 1)
        series.append((name, read_animation(path)))
    frames = min(len(s) for _, s in series)
    first = int(args.start * 30)
    last = min(frames, int(args.end * 30))
    time = np.arange(first, last) / 30.0
    level = levels(args.speech, frames)
    quiet = (level < np.percentile(level, 95) - 30.0)[first:last]

    fig, axes = plt.subplots(4, 1, figsize=(12, 8), sharex=True, gridspec_kw={"height_ratios": [3, 3, 3, 1.6]})
    for axis, label in enumerate(["pitch", "yaw", "roll"]):
        ax = axes[axis]
        for t, q in zip(time, quiet):
            if q:
                ax.axvspan(t - 1 / 60, t + 1 / 60, color="0.9", lw=0)
        for name, values in series:
            part = values[first:last, axis]
            ax.plot(time, part - part.mean(), label=name, lw=1.2 if name == "the speaker" else 1.0)
        ax.set_ylabel(f"{label} (deg)")
        ax.grid(alpha=0.3)
    beats = axes[3]
    onsets = [b for b in speech_beats(level[:frames]) if first <= b < last]
    for b in onsets:
        for ax in axes:
            ax.axvline(b / 30.0, color="0.75", lw=0.6, zorder=0)
    rows = [("speech onsets", np.array(onsets))] + [(name, motion_beats(values[:frames])) for name, values in series]
    for row, (name, marks) in enumerate(rows):
        marks = marks[(marks >= first) & (marks < last)]
        y = len(rows) - 1 - row
        beats.plot(marks / 30.0, np.full(len(marks), y), "|" if row == 0 else "o", ms=8 if row == 0 else 4,
                   color="0.3" if row == 0 else f"C{row - 1}")
    beats.set_yticks(range(len(rows)), [name for name, _ in reversed(rows)], fontsize=8)
    beats.set_ylim(-0.6, len(rows) - 0.4)
    beats.set_ylabel("beats")
    axes[0].legend(loc="upper right", ncol=len(series), fontsize=9)
    axes[-1].set_xlabel("time (s); grey: pauses; lines: the speech's onsets")
    fig.tight_layout()
    fig.savefig(args.output, dpi=90)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
