#!/usr/bin/python3
"""The head style judged, as a figure: per held-out speaker, the head's spread and its 95th-percentile speed over
the person's, unstyled and styled from another clip of theirs, with the targets' bands. Reads what
`talkinghead eval head --style-from` prints:

    build/talkinghead eval head --style-from > style.txt
    /usr/bin/python3 tools/head_style_plot.py style.txt docs/head_style.png
"""
import math
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def parse(path):
    speakers, current = [], None
    for line in open(path, encoding="utf-8"):
        left = re.match(r"^(\S.*) left out:", line)
        if left:
            current = {"name": left.group(1)}
            speakers.append(current)
            continue
        row = re.match(r"^  (unstyled|styled)[^0-9-]*\(\d+ seeds\)\s+(.*)$", line)
        if row and current is not None:
            numbers = row.group(2).split()
            ratios = [float(x) for x in numbers[4:7]]
            current[row.group(1)] = {"spread": math.exp(sum(math.log(r) for r in ratios) / 3),
                                     "speed": float(numbers[7])}
    return [s for s in speakers if "styled" in s and "unstyled" in s]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: head_style_plot.py EVAL_OUTPUT.txt OUT.png")
    speakers = parse(sys.argv[1])
    if not speakers:
        sys.exit(f"{sys.argv[1]}: no speaker rows of `eval head --style-from` in it")
    names = [s["name"] for s in speakers]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, key, title, band in ((axes[0], "spread", "head spread over the person's (geometric mean of the axes)",
                                  (0.8, 1.25)),
                                 (axes[1], "speed", "p95 speed over the person's", (0.0, 1.25))):
        x = range(len(names))
        ax.axhspan(band[0], band[1], color="#d8ecd8", label="target")
        ax.axhline(1.0, color="#555555", linewidth=0.8)
        ax.bar([i - 0.18 for i in x], [s["unstyled"][key] for s in speakers], 0.36, label="unstyled (the default)",
               color="#9aa7b8")
        ax.bar([i + 0.18 for i in x], [s["styled"][key] for s in speakers], 0.36,
               label="styled from another clip", color="#2f6db5")
        ax.set_xticks(list(x))
        ax.set_xticklabels(names)
        ax.set_yscale("log")
        ax.set_yticks([0.5, 0.8, 1.0, 1.25, 2.0])
        ax.set_yticklabels(["0.5", "0.8", "1", "1.25", "2"])
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_ylim(0.4, 2.6)
        ax.set_title(title, fontsize=9)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=3)
    fig.suptitle("Each speaker held out: the model trained without them, styled from a clip that is not scored",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
