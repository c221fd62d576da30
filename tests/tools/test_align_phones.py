"""tools/align_phones.py: PocketSphinx's phone alignment of read speech, judged against BEAT2's own phone
alignment (its TextGrids), and its corpus layouts and bad input.

Run by CTest (tests/tools/CMakeLists.txt) as `/usr/bin/python3 -m pytest tests/tools`; needs Debian's pocketsphinx,
pocketsphinx-en-us, ffmpeg and espeak-ng, and the shared data (TALKINGHEAD_DATA, default ../shared/data)."""
import csv
import json
import os
import re
import statistics
import subprocess
import wave

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(REPO, "tools", "align_phones.py")
DATA = os.environ.get("TALKINGHEAD_DATA", os.path.join(REPO, "..", "shared", "data"))


def run(*args):
    return subprocess.run(["/usr/bin/python3", TOOL, *args], capture_output=True, text=True, timeout=600)


def textgrid_tier(path, tier):
    text = open(path, encoding="utf-8").read().split("item [")[tier + 1]
    intervals = re.findall(r'xmin = ([\d.]+)\s*\n\s*xmax = ([\d.]+)\s*\n\s*text = "([^"]*)"', text)
    return [(float(a), float(b), c) for a, b, c in intervals]


def read_phones(path):
    with open(path, encoding="ascii") as table:
        rows = list(csv.reader(table))
    assert rows[0] == ["start_s", "end_s", "phone"]
    return [(float(a), float(b), p) for a, b, p in rows[1:]]


def matched_starts(reference, aligned):
    """Start-time differences of the phones both sequences share, matched by edit distance (silences left out)."""
    ref = [p for p in reference if p[2] != "SIL"]
    hyp = [p for p in aligned if p[2] != "SIL"]
    n, m = len(ref), len(hyp)
    cost = [[i + j if i == 0 or j == 0 else 0 for j in range(m + 1)] for i in range(n + 1)]
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            cost[i][j] = min(cost[i - 1][j] + 1, cost[i][j - 1] + 1,
                             cost[i - 1][j - 1] + (ref[i - 1][2] != hyp[j - 1][2]))
    pairs, i, j = [], n, m
    while i > 0 and j > 0:
        same = ref[i - 1][2] == hyp[j - 1][2]
        if cost[i][j] == cost[i - 1][j - 1] + (not same):
            if same:
                pairs.append(hyp[j - 1][0] - ref[i - 1][0])
            i, j = i - 1, j - 1
        elif cost[i][j] == cost[i - 1][j] + 1:
            i -= 1
        else:
            j -= 1
    return pairs, n


def test_beat2_phones_land_where_its_reference_alignment_puts_them(tmp_path):
    take = os.path.join(DATA, "beat2", "audio_only", "2_scott_0_4_4")
    words = [w for _, _, w in textgrid_tier(take + ".TextGrid", 1) if w]
    listing = tmp_path / "list.tsv"
    listing.write_text(f"{take}.wav\tscott\t{' '.join(words)}\n")
    result = run("--list", str(listing), "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    reference = [(a, b, re.sub(r"\d", "", p).upper() or "SIL") for a, b, p in textgrid_tier(take + ".TextGrid", 2)]
    aligned = read_phones(tmp_path / "out" / "2_scott_0_4_4.phones.csv")
    offsets, spoken = matched_starts(reference, aligned)
    assert len(offsets) >= 0.95 * spoken  # CMUdict's pronunciations are nearly the reference's
    within = sum(abs(d) <= 0.04 for d in offsets) / len(offsets)
    assert within >= 0.85, f"{within:.1%} of phones start within 40 ms of the reference"
    assert abs(statistics.median(offsets)) <= 0.015
    # Phones tile the recording: contiguous, from 0 to its end.
    assert aligned[0][0] == 0.0
    for before, after in zip(aligned, aligned[1:]):
        assert before[1] == pytest.approx(after[0], abs=1e-6)
    with wave.open(str(tmp_path / "out" / "2_scott_0_4_4.wav")) as sound:
        assert aligned[-1][1] == pytest.approx(sound.getnframes() / 16000.0, abs=0.002)
    index = list(csv.reader(open(tmp_path / "out" / "index.csv")))
    assert index == [["file", "speaker", "text"], ["2_scott_0_4_4", "scott", " ".join(w.upper() for w in words)]]


def make_speechocean(folder, wav):
    """A speechocean762 layout holding one utterance, spoken by espeak-ng."""
    for part in ("train", "test"):
        os.makedirs(folder / part)
    os.makedirs(folder / "resource")
    os.makedirs(folder / "WAVE" / "SPEAKER0001")
    subprocess.run(["espeak-ng", "-v", "en-us", "-w", str(folder / "raw.wav"), "we call it bear"], check=True)
    subprocess.run(["ffmpeg", "-nostdin", "-loglevel", "error", "-i", str(folder / "raw.wav"), "-ar", "16000",
                    str(folder / "WAVE" / "SPEAKER0001" / wav)], check=True)
    (folder / "train" / "text").write_text("000010011\tWE CALL IT BEAR\n")
    (folder / "train" / "wav.scp").write_text(f"000010011\tWAVE/SPEAKER0001/{wav}\n")
    (folder / "train" / "utt2spk").write_text("000010011\t0001\n")
    (folder / "train" / "spk2age").write_text("0001\t9\n")
    (folder / "train" / "spk2gender").write_text("0001\tf\n")
    for name in ("text", "wav.scp", "utt2spk", "spk2age", "spk2gender"):
        (folder / "test" / name).write_text("")
    (folder / "resource" / "text-phone").write_text(
        "000010011.0\tW_B IY0_E\n000010011.1\tK_B AO0_I L_E\n000010011.2\tIH0_B T_E\n000010011.3\tB_B EH0_I R_E\n")


def test_speechocean_layout_aligns_the_canonical_phones(tmp_path):
    make_speechocean(tmp_path / "so", "000010011.WAV")
    result = run("--speechocean", str(tmp_path / "so"), "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    phones = [p for _, _, p in read_phones(tmp_path / "out" / "000010011.phones.csv") if p != "SIL"]
    assert phones == ["W", "IY", "K", "AO", "L", "IH", "T", "B", "EH", "R"]
    assert list(csv.reader(open(tmp_path / "out" / "speakers.csv"))) == [["speaker", "age", "gender"],
                                                                        ["so-0001", "9", "f"]]


def test_speechocean_scores_give_the_phones_as_heard(tmp_path):
    make_speechocean(tmp_path / "so", "000010011.WAV")
    word = lambda phones, accuracy, said=(): {"phones": phones, "phones-accuracy": accuracy,
                                               "mispronunciations": [dict(zip(("index", "pronounced-phone"), m))
                                                                     for m in said]}
    scores = {"000010011": {"words": [word(["W", "IY0"], [2, 2]), word(["K", "AO0", "L"], [2, 2, 0], [(2, "<DEL>")]),
                                      word(["IH0", "T"], [2, 0.4]), word(["B", "EH0", "R"], [2, 0, 2], [(1, "AH")])]}}
    (tmp_path / "so" / "resource" / "scores.json").write_text(json.dumps(scores))
    result = run("--speechocean", str(tmp_path / "so"), "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    phones = [p for _, _, p in read_phones(tmp_path / "out" / "000010011.phones.csv") if p != "SIL"]
    # L deleted, T scored wrong with nothing named (no phone), EH heard as AH.
    assert phones == ["W", "IY", "K", "AO", "IH", "?", "B", "AH", "R"]


def test_bad_recordings_are_left_out_with_their_reason(tmp_path):
    good = os.path.join(DATA, "speech", "arctic")
    wavs = [f for f in os.listdir(good) if f.endswith(".wav")]
    (tmp_path / "text.wav").write_text("not a recording\n")
    listing = tmp_path / "list.tsv"
    listing.write_text(f"{tmp_path / 'text.wav'}\tx\thello there\n"
                       f"{tmp_path / 'missing.wav'}\tx\thello there\n"
                       f"{os.path.join(good, wavs[0])}\tx\tzzyzzx qwxq\n")
    result = run("--list", str(listing), "-o", str(tmp_path / "out"))
    assert result.returncode == 1
    assert result.stderr.strip().count("\n") == 0 and "no utterance could be aligned" in result.stderr
    assert not (tmp_path / "out").exists() and not (tmp_path / "out.partial").exists()


def test_a_list_that_is_not_three_columns_is_named(tmp_path):
    listing = tmp_path / "list.tsv"
    listing.write_text("only one column\n")
    result = run("--list", str(listing), "-o", str(tmp_path / "out"))
    assert result.returncode == 1
    assert str(listing) in result.stderr and "line 1" in result.stderr
