#!/usr/bin/python3
"""Tracks every video of a folder with `talkinghead track` and reports, per clip and on average, how closely the
face model fits dlib's landmarks (the fit's residual, pixels) and how well the tracked mouth follows the sound:
the correlation, frame by frame, of the sound's level (dB) with the lips' opening (the three inner-lip gaps over
the outer eye corners' distance) and with the fitted jaw (FAP 3).

    /usr/bin/python3 tools/track_report.py ../shared/data/grid/s1 [--cli build/talkinghead]
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile
import wave

import numpy as np


def read_track(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(header)}


def read_wav(path):
    with wave.open(str(path)) as w:
        rate = w.getframerate()
        samples = np.frombuffer(w.readframes(w.getnframes()), dtype="<i2").astype(float) / 32768.0
    return samples, rate


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", type=pathlib.Path)
    parser.add_argument("--cli", default="build/talkinghead")
    args = parser.parse_args()
    videos = sorted(p for p in args.folder.iterdir() if p.suffix.lower() in (".mpg", ".mp4", ".avi", ".mkv"))
    if not videos:
        sys.exit(f"{args.folder}: no videos")
    results = []
    with tempfile.TemporaryDirectory() as work:
        for video in videos:
            out = pathlib.Path(work) / (video.stem + ".csv")
            run = subprocess.run([args.cli, "track", str(video), "-o", str(out)], capture_output=True, text=True)
            if run.returncode != 0:
                print(f"{video.name}: {run.stderr.strip()}")
                continue
            track = read_track(out)
            samples, rate = read_wav(out.with_suffix(".wav"))
            times = track["time_s"]
            fps = 1.0 / (times[1] - times[0])
            hop = int(round(rate / fps))
            frames = min(len(times), len(samples) // hop)
            level = np.array([10 * np.log10(np.mean(samples[f * hop:(f + 1) * hop] ** 2) + 1e-10) for f in range(frames)])
            x = lambda i: track[f"x{i}"][:frames]
            y = lambda i: track[f"y{i}"][:frames]
            gap = lambda a, b: np.hypot(x(a) - x(b), y(a) - y(b))
            opening = (gap(61, 67) + gap(62, 66) + gap(63, 65)) / (3 * gap(36, 45))
            results.append((video.name, track["residual_px"].mean(), track["face"].mean(),
                            np.corrcoef(opening, level)[0, 1], np.corrcoef(track["fap3"][:frames], level)[0, 1]))
            name, residual, found, rho_open, rho_jaw = results[-1]
            print(f"{name}: residual {residual:.2f} px, face in {100 * found:.0f} % of frames, "
                  f"level vs lips' opening r = {rho_open:.3f}, vs jaw (FAP 3) r = {rho_jaw:.3f}")
    if results:
        table = np.array([r[1:] for r in results])
        print(f"{len(results)} of {len(videos)} clips: mean residual {table[:, 0].mean():.2f} px, "
              f"level vs lips' opening r = {table[:, 2].mean():.3f} (median {np.median(table[:, 2]):.3f}), "
              f"vs jaw r = {table[:, 3].mean():.3f} (median {np.median(table[:, 3]):.3f})")


if __name__ == "__main__":
    main()
