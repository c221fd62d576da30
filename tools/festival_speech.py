#!/usr/bin/python3
"""Phone-aligned English speech from Festival's voices, for training the mouth network's classes on more voices.

    /usr/bin/python3 tools/festival_speech.py -o DIR [--sentences 150] [--seed 1]

Festival (Debian's `festival`, with `festvox-kallpc16k`, `festvox-kdlpc16k` and `festvox-us-slt-hts`: two
diphone voices cut from a man's recorded speech each, and a statistical voice trained on a woman's) speaks
sentences made from the Wall Street Journal word list Festival ships (`dicts/wsj.wp39.poslexR`: words with their
parts of speech and frequencies), each drawn by its frequency into one of a few sentence frames. Festival knows
every phone's time, so the labels are exact. Per utterance it writes `VOICE_NNN.wav` (as the voice speaks,
16 or 32 kHz) and `VOICE_NNN.phones.csv` (`start_s,end_s,phone`: ARPAbet, SIL for pauses), and `index.csv`
(`file,voice,text`). The folder is made anew; the same seed gives the same sentences.
"""
import argparse
import csv
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

VOICES = {"kal": "voice_kal_diphone", "ked": "voice_ked_diphone", "slt": "voice_cmu_us_slt_arctic_hts"}
POSLEX = "/usr/share/festival/dicts/wsj.wp39.poslexR"

# Festival's US phone set (radio) to ARPAbet.
PHONES = {"pau": "SIL", "h#": "SIL", "brth": "SIL", "ax": "AH", "axr": "ER", "dx": "D", "el": "L", "em": "M",
          "en": "N", "nx": "N", "hv": "HH"}

FRAMES = [
    ["dt", "jj", "nn", "vbd", "in", "dt", "nn"],
    ["dt", "nn", "md", "vb", "dt", "jj", "nns", "rb"],
    ["prp", "vbd", "dt", "nn", "cc", "vbd", "dt", "jj", "nn"],
    ["dt", "jj", "nns", "vbp", "in", "dt", "nn", "in", "nn"],
    ["nnp", "vbd", "dt", "nn", "in", "dt", "jj", "nn"],
    ["rb", "dt", "nn", "vbz", "jj", "cc", "jj"],
]


def read_lexicon():
    by_tag = {}
    entry = re.compile(r'^\("([a-z]+)" \(\((.*)\) \) \(\) \)$')
    with open(POSLEX, encoding="latin-1") as lexicon:
        for line in lexicon:
            match = entry.match(line.strip())
            if not match:
                continue
            word = match.group(1)
            if len(word) < 2 or word == "nt":  # letters and contractions' pieces read oddly alone
                continue
            for tag, logp in re.findall(r"\((\w+) (-?[\d.]+)\)", "(" + match.group(2) + ")"):
                by_tag.setdefault(tag, []).append((word, math.exp(float(logp))))
    return by_tag


def sentences(count, seed):
    by_tag = read_lexicon()
    rng = random.Random(seed)
    out = []
    for _ in range(count):
        frame = rng.choice(FRAMES)
        words = []
        for tag in frame:
            choices = by_tag.get(tag)
            if not choices:
                continue
            total = sum(p for _, p in choices)
            pick = rng.random() * total
            for word, p in choices:
                pick -= p
                if pick <= 0:
                    words.append(word)
                    break
        out.append(" ".join(words).capitalize() + ".")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--sentences", type=int, default=150, help="per voice")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if shutil.which("festival") is None:
        sys.exit("festival_speech.py: festival is not installed (apt-get install festival festvox-kallpc16k "
                 "festvox-kdlpc16k festvox-us-slt-hts)")
    if os.path.isdir(args.output):
        shutil.rmtree(args.output)
    os.makedirs(args.output)
    index = []
    for v, (name, voice) in enumerate(VOICES.items()):
        texts = sentences(args.sentences, args.seed * 100 + v)
        with tempfile.NamedTemporaryFile("w", suffix=".scm", delete=False) as script:
            script.write(f"({voice})\n")
            for i, text in enumerate(texts):
                stem = os.path.join(args.output, f"{name}_{i:03d}")
                quoted = text.replace("\\", "").replace('"', "")
                script.write(f'(set! u (utt.synth (Utterance Text "{quoted}")))\n')
                script.write(f'(utt.save.wave u "{stem}.wav" \'riff)\n(utt.save.segs u "{stem}.segs")\n')
                index.append((f"{name}_{i:03d}", name, text))
            path = script.name
        result = subprocess.run(["festival", "-b", path], capture_output=True, text=True)
        os.unlink(path)
        if result.returncode != 0:
            sys.exit(f"festival_speech.py: festival failed for {name}: {result.stderr.strip()[-300:]}")
    for stem, _, _ in index:
        segs = os.path.join(args.output, stem + ".segs")
        rows = []
        start = 0.0
        with open(segs) as f:
            for line in f:
                parts = line.split()
                if len(parts) != 3 or parts[0] == "#":
                    continue
                end = float(parts[0])
                phone = PHONES.get(parts[2], parts[2].upper())
                rows.append((f"{start:.4f}", f"{end:.4f}", phone))
                start = end
        os.unlink(segs)
        with open(os.path.join(args.output, stem + ".phones.csv"), "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["start_s", "end_s", "phone"])
            writer.writerows(rows)
    with open(os.path.join(args.output, "index.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["file", "voice", "text"])
        writer.writerows(index)
    print(f"wrote {len(index)} utterances of {len(VOICES)} voices to {args.output}")


if __name__ == "__main__":
    main()
