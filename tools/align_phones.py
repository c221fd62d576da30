#!/usr/bin/python3
"""Phone alignment of read speech: each phone's start and end in a recording whose words are known.

    /usr/bin/python3 tools/align_phones.py --speechocean DIR -o OUT [--split train|test|all]
    /usr/bin/python3 tools/align_phones.py --grid DIR [DIR ...] -o OUT
    /usr/bin/python3 tools/align_phones.py --list FILE.tsv -o OUT      (lines: audio path, speaker, words; tabs)

Debian's PocketSphinx (`pocketsphinx`, `pocketsphinx-en-us`: the en-us acoustic model and CMUdict) aligns by
recognising each utterance with a grammar that allows only its own phones: a finite-state grammar whose words are
single phones, the transcript's words in order, each word every pronunciation CMUdict gives it (or the canonical
phones the corpus gives), an optional silence between words and at both ends. `pocketsphinx_batch` then reports
where each phone-word starts (`-hypseg`, 10 ms frames). Settings for alignment rather than recognition: no voice
activity detection (`-remove_silence no`: it cut the opening silence and misplaced the first phone), the
utterance's own cepstral mean (`-cmn batch`), wide beams. An utterance the grammar cannot explain (no hypothesis,
or one that does not reach the grammar's end) is left out and listed with its reason.

Corpora:
- `--speechocean DIR`: speechocean762 as its repository lays it out (train/ and test/ in Kaldi's layout, the WAVs
  under WAVE/, each word's canonical phones in resource/text-phone). The speaker is `so-SPEAKERID`. Where the
  annotators' scores are there (resource/scores.json, stored with Git LFS), the phones are those they heard: a
  phone they name as said instead replaces the canonical one, a deleted one is dropped, and one scored as
  mispronounced (below 1 of 2) with no name for what was said is written `?`, so that its frames teach nothing.
- `--grid DIR ...`: GRID clips (`NAME.mpg` with `NAME.align`, its word alignment); the words are the alignment's,
  less `sil` and `sp`. The speaker is the folder's (`s1` for `s1-more`).
- `--list FILE`: any recordings, one a line: the audio's path (any format FFmpeg reads), the speaker, the words.

Writes into OUT (made anew): for each utterance `NAME.wav` (16 kHz mono: a link to the original where it is that
already, else converted by FFmpeg) and `NAME.phones.csv` (`start_s,end_s,phone`: ARPAbet without stress, SIL for
silence), `index.csv` (`file,speaker,text`: the layout `train articulation --aligned` reads), `report.csv`
(every utterance: `file,status,reason`) and, for speechocean762, `speakers.csv` (`speaker,age,gender`). Phones are aligned on 2 processes by default (`--jobs`).
"""
import argparse
import contextlib
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import wave

MODEL = "/usr/share/pocketsphinx/model/en-us/en-us"
CMUDICT = "/usr/share/pocketsphinx/model/en-us/cmudict-en-us.dict"
PHONES = ("AA AE AH AO AW AY B CH D DH EH ER EY F G HH IH IY JH K L M N NG OW OY P R S SH T TH UH UW V W Y Z "
          "ZH").split()
SILENCE = "SIL"
FRAMES_PER_SECOND = 100
# A phone whose first frame is i begins between the centres of frames i-1 and i: PocketSphinx's frames are 10 ms
# apart and 25.625 ms long (410 samples at 16 kHz), so frame i's centre is 12.8 ms after 10i ms.
BOUNDARY_DELAY_S = 0.0078


def fail(message):
    print(f"align_phones: {message}", file=sys.stderr)
    sys.exit(1)


def phone_of(symbol):
    """An ARPAbet phone without its stress digit or speechocean's word-position suffix (AO0_I -> AO)."""
    phone = re.sub(r"(_[BIES])$", "", symbol.strip().upper())
    phone = re.sub(r"[0-2]$", "", phone)
    return phone


class Utterance:
    def __init__(self, name, audio, speaker, words, pronunciations=None, doubtful=None):
        self.name = name            # the output's file name, unique in the corpus
        self.audio = audio          # the recording as given
        self.speaker = speaker
        self.words = words          # the transcript's words, upper case
        self.pronunciations = pronunciations  # per word, a list of phone lists (None: from the dictionary)
        # With one pronunciation per word: for each of its phones in order, whether the annotators scored it as
        # mispronounced without saying what was said instead (written "?": its frames carry no phone).
        self.doubtful = doubtful


def read_cmudict():
    lexicon = {}
    with open(CMUDICT, encoding="utf-8") as dictionary:
        for line in dictionary:
            fields = line.split()
            if len(fields) < 2:
                continue
            word = re.sub(r"\(\d+\)$", "", fields[0]).upper()
            lexicon.setdefault(word, []).append([phone_of(p) for p in fields[1:]])
    return lexicon


def read_two_columns(path):
    table = {}
    with open(path, encoding="utf-8") as lines:
        for number, line in enumerate(lines, 1):
            line = line.rstrip("\n")
            if not line.strip():
                continue
            parts = line.split(None, 1)
            if len(parts) != 2:
                fail(f"{path}: line {number} is not 'key value'")
            table[parts[0]] = parts[1].strip()
    return table


def speechocean_utterances(folder, split):
    splits = ["train", "test"] if split == "all" else [split]
    canonical = {}
    text_phone = os.path.join(folder, "resource", "text-phone")
    if not os.path.isfile(text_phone):
        fail(f"{text_phone}: not found (is {folder} the speechocean762 repository?)")
    for key, phones in read_two_columns(text_phone).items():
        utterance, _, index = key.rpartition(".")
        canonical.setdefault(utterance, {})[int(index)] = [phone_of(p) for p in phones.split()]
    scores = {}
    scores_path = os.path.join(folder, "resource", "scores.json")
    if os.path.isfile(scores_path):
        try:
            with open(scores_path, encoding="utf-8") as table:
                scores = json.load(table)
        except ValueError:
            print(f"align_phones: {scores_path} is not JSON (a Git LFS pointer? `git lfs pull` brings the file); "
                  "aligning the canonical phones", file=sys.stderr)
    utterances = []
    for part in splits:
        text = read_two_columns(os.path.join(folder, part, "text"))
        wavs = read_two_columns(os.path.join(folder, part, "wav.scp"))
        speakers = read_two_columns(os.path.join(folder, part, "utt2spk"))
        for key in sorted(text):
            words = text[key].upper().split()
            phones = canonical.get(key, {})
            if sorted(phones) != list(range(len(words))):
                fail(f"{text_phone}: utterance {key} has phones for {len(phones)} of its {len(words)} words")
            pronunciations = [[phones[i]] for i in range(len(words))]
            doubtful = None
            if key in scores:
                pronunciations, doubtful = as_pronounced(scores[key], pronunciations)
            utterances.append(Utterance(key, os.path.join(folder, wavs[key]), "so-" + speakers[key], words,
                                        pronunciations, doubtful))
    return utterances


def as_pronounced(score, canonical):
    """The words' phones as the annotators heard them (resource/scores.json): a phone they name as pronounced
    instead replaces the canonical one, a deleted one is dropped, one scored below 1 (of 2) with no name for what
    was said is marked doubtful. The canonical phones stand where the scores do not match them."""
    words = score.get("words", [])
    if len(words) != len(canonical):
        return canonical, None
    pronunciations, doubtful = [], []
    for word, options in zip(words, canonical):
        phones = [phone_of(p) for p in word.get("phones", [])]
        accuracy = word.get("phones-accuracy", [])
        if phones != options[0] or len(accuracy) != len(phones):
            pronunciations.append(options)
            doubtful += [False] * len(options[0])
            continue
        said = {m.get("index"): m.get("pronounced-phone", "") for m in word.get("mispronunciations", []) or []}
        heard = []
        for i, phone in enumerate(phones):
            other = phone_of(said.get(i, "") or "")
            if i in said and other in PHONES:
                heard.append(other)
                doubtful.append(False)
            elif i in said and other in ("", "<DEL>", "DEL"):
                continue  # deleted: not said at all
            else:
                heard.append(phone)
                doubtful.append(accuracy[i] < 1.0)
        if not heard:  # a word wholly unsaid still needs a path through the grammar
            heard, doubtful = list(phones), doubtful + [True] * len(phones)
        pronunciations.append([heard])
    return pronunciations, doubtful


def grid_utterances(folders):
    utterances = []
    for folder in folders:
        speaker = os.path.basename(os.path.normpath(folder)).split("-")[0]
        for entry in sorted(os.listdir(folder)):
            if not entry.endswith(".mpg"):
                continue
            stem = entry[:-4]
            align = os.path.join(folder, stem + ".align")
            if not os.path.isfile(align):
                continue
            with open(align, encoding="utf-8") as lines:
                words = [line.split()[2].upper() for line in lines if len(line.split()) == 3]
            words = [w for w in words if w not in ("SIL", "SP")]
            utterances.append(Utterance(stem, os.path.join(folder, entry), "grid-" + speaker, words))
    return utterances


def write_speakers(folder, speakers, path):
    """speechocean762's speakers with their age and gender (`speaker,age,gender`), for judging adults and
    children apart."""
    age, gender = {}, {}
    for part in ("train", "test"):
        age.update(read_two_columns(os.path.join(folder, part, "spk2age")))
        gender.update(read_two_columns(os.path.join(folder, part, "spk2gender")))
    with open(path, "w", encoding="utf-8", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(["speaker", "age", "gender"])
        for speaker in sorted(speakers):
            key = speaker[len("so-"):]
            writer.writerow([speaker, age.get(key, ""), gender.get(key, "")])


def list_utterances(path):
    utterances = []
    with open(path, encoding="utf-8") as lines:
        for number, line in enumerate(lines, 1):
            if not line.strip():
                continue
            fields = line.rstrip("\n").split("\t")
            if len(fields) != 3:
                fail(f"{path}: line {number} is not audio<TAB>speaker<TAB>words")
            audio = fields[0] if os.path.isabs(fields[0]) else os.path.join(os.path.dirname(path), fields[0])
            name = os.path.splitext(os.path.basename(audio))[0]
            words = re.sub(r"[^A-Za-z' ]", " ", fields[2]).upper().split()
            utterances.append(Utterance(name, audio, fields[1], words))
    return utterances


def is_16k_mono_wav(path):
    try:
        with wave.open(path, "rb") as sound:
            return sound.getframerate() == 16000 and sound.getnchannels() == 1 and sound.getsampwidth() == 2
    except (wave.Error, EOFError, OSError):
        return False


def write_audio(utterance, wav_path):
    """The utterance's sound as 16 kHz mono 16-bit WAV at wav_path (a link where the original is that)."""
    if not os.path.isfile(utterance.audio):
        return f"{utterance.audio}: not found"
    if is_16k_mono_wav(utterance.audio):
        os.symlink(os.path.abspath(utterance.audio), wav_path)
        return None
    result = subprocess.run(["ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-i", utterance.audio, "-ac", "1",
                             "-ar", "16000", "-sample_fmt", "s16", wav_path], capture_output=True, text=True)
    if result.returncode != 0:
        last = (result.stderr.strip().splitlines() or ["no message"])[-1]
        return f"{utterance.audio}: FFmpeg could not read it ({last})"
    return None


def write_raw(wav_path, raw_path):
    """The samples alone, for pocketsphinx_batch (-adcin: headerless 16-bit little-endian)."""
    with wave.open(wav_path, "rb") as sound, open(raw_path, "wb") as raw:
        raw.write(sound.readframes(sound.getnframes()))
        return sound.getnframes()


def pronunciations_of(utterance, lexicon):
    if utterance.pronunciations is not None:
        return utterance.pronunciations, None
    out = []
    for word in utterance.words:
        options = lexicon.get(word)
        if not options:
            return None, f"the word {word} is not in CMUdict"
        out.append(options)
    return out, None


def phone_word(phone):
    return "p_" + phone.lower()


def write_grammar(path, pronunciations):
    """A Sphinx finite-state grammar: optional silence, then each word (any of its pronunciations), optional
    silence between words and at the end. Transitions with no word are free."""
    transitions = []
    states = 1
    current = 0

    def new_state():
        nonlocal states
        states += 1
        return states - 1

    def optional_silence(frm):
        to = new_state()
        transitions.append((frm, to, 0.5, phone_word(SILENCE)))
        transitions.append((frm, to, 0.5, None))
        return to

    current = optional_silence(current)
    for options in pronunciations:
        end = new_state()
        share = 1.0 / len(options)
        for phones in options:
            state = current
            for i, phone in enumerate(phones):
                to = end if i == len(phones) - 1 else new_state()
                transitions.append((state, to, share if i == 0 else 1.0, phone_word(phone)))
                state = to
        current = optional_silence(end)
    with open(path, "w", encoding="ascii") as grammar:
        grammar.write(f"FSG_BEGIN utterance\nNUM_STATES {states}\nSTART_STATE 0\nFINAL_STATE {current}\n")
        for frm, to, probability, word in transitions:
            grammar.write(f"TRANSITION {frm} {to} {probability:.6f}" + (f" {word}\n" if word else "\n"))
        grammar.write("FSG_END\n")


def write_dictionary(path):
    with open(path, "w", encoding="ascii") as dictionary:
        for phone in PHONES + [SILENCE]:
            dictionary.write(f"{phone_word(phone)} {phone}\n")


def run_batch(work, names, job):
    """pocketsphinx_batch over the utterances `names` (raw audio and grammar in work/); returns its -hypseg path."""
    ctl = os.path.join(work, f"job{job}.ctl")
    fsgctl = os.path.join(work, f"job{job}.fsgctl")
    with open(ctl, "w", encoding="utf-8") as c, open(fsgctl, "w", encoding="utf-8") as f:
        for name in names:
            c.write(f"{name}\n")
            f.write(f"{name}\n")
    hypseg = os.path.join(work, f"job{job}.hypseg")
    command = ["pocketsphinx_batch", "-hmm", MODEL, "-dict", os.path.join(work, "phones.dict"),
               "-ctl", ctl, "-cepdir", work, "-cepext", ".raw", "-adcin", "yes", "-fsgctl", fsgctl,
               "-fsgdir", work, "-fsgext", ".fsg", "-fsgusefiller", "no", "-hypseg", hypseg,
               "-remove_silence", "no", "-cmn", "batch", "-beam", "1e-80", "-wbeam", "1e-60", "-pbeam", "1e-80",
               "-logfn", os.path.join(work, f"job{job}.log")]
    return subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL), hypseg


def read_hypseg(path):
    """uttid -> [(phone, start frame)] from pocketsphinx's segmentation output."""
    out = {}
    if not os.path.isfile(path):
        return out
    with open(path, encoding="utf-8") as lines:
        for line in lines:
            fields = line.split()
            if len(fields) < 9:
                if fields:
                    out[fields[0]] = []
                continue
            segments = []
            rest = fields[9:]
            for i in range(0, len(rest) - 3, 4):  # start frame, acoustic score, language score, word
                start, word = int(rest[i]), rest[i + 3]
                if word.startswith("p_"):
                    segments.append((word[2:].upper(), start))
            out[fields[0]] = segments
    return out


def expected_phone_counts(pronunciations):
    return sum(min(len(p) for p in options) for options in pronunciations), \
        sum(max(len(p) for p in options) for options in pronunciations)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--speechocean", metavar="DIR", help="the speechocean762 repository's folder")
    source.add_argument("--grid", metavar="DIR", nargs="+", help="GRID folders of NAME.mpg and NAME.align")
    source.add_argument("--list", metavar="FILE", help="lines of audio<TAB>speaker<TAB>words")
    parser.add_argument("--split", choices=["train", "test", "all"], default="train",
                        help="speechocean762's speakers to align (default train)")
    parser.add_argument("-o", "--output", required=True, help="the folder to write (made anew)")
    parser.add_argument("--jobs", type=int, default=2, help="pocketsphinx processes at once (default 2)")
    parser.add_argument("--limit", type=int, default=0, help="align only the first N utterances (0: all)")
    parser.add_argument("--keep", metavar="DIR", help="keep PocketSphinx's inputs, outputs and logs in DIR")
    args = parser.parse_args()

    if shutil.which("pocketsphinx_batch") is None or not os.path.isdir(MODEL):
        fail("PocketSphinx is not installed: apt-get install pocketsphinx pocketsphinx-en-us")
    if args.speechocean:
        utterances = speechocean_utterances(args.speechocean, args.split)
    elif args.grid:
        utterances = grid_utterances(args.grid)
    else:
        utterances = list_utterances(args.list)
    if args.limit > 0:
        utterances = utterances[:args.limit]
    if not utterances:
        fail("no utterances found in the corpus given")
    if len({u.name for u in utterances}) != len(utterances):
        fail("two utterances share a file name")

    lexicon = read_cmudict() if any(u.pronunciations is None for u in utterances) else {}
    output = os.path.abspath(args.output)
    partial = output + ".partial"
    shutil.rmtree(partial, ignore_errors=True)
    os.makedirs(partial)
    report = {}
    if args.keep:
        shutil.rmtree(args.keep, ignore_errors=True)
        os.makedirs(args.keep)
    with (contextlib.nullcontext(os.path.abspath(args.keep)) if args.keep
          else tempfile.TemporaryDirectory(prefix="align_phones.")) as work:
        write_dictionary(os.path.join(work, "phones.dict"))
        ready = []
        samples = {}
        for u in utterances:
            pronunciations, problem = pronunciations_of(u, lexicon)
            if problem is None:
                problem = write_audio(u, os.path.join(partial, u.name + ".wav"))
            if problem is not None:
                report[u.name] = ("failed", problem)
                continue
            u.pronunciations = pronunciations
            samples[u.name] = write_raw(os.path.join(partial, u.name + ".wav"), os.path.join(work, u.name + ".raw"))
            write_grammar(os.path.join(work, u.name + ".fsg"), pronunciations)
            ready.append(u)
        jobs = max(1, min(args.jobs, len(ready)))
        chunks = [[u.name for u in ready[j::jobs]] for j in range(jobs)]
        running = [run_batch(work, chunk, j) for j, chunk in enumerate(chunks) if chunk]
        segments = {}
        for process, hypseg in running:
            process.wait()
            segments.update(read_hypseg(hypseg))

        index = []
        for u in ready:
            found = segments.get(u.name)
            low, high = expected_phone_counts(u.pronunciations)
            spoken = [s for s in found or [] if s[0] != SILENCE]
            if not found:
                report[u.name] = ("failed", "the grammar does not explain the recording (no hypothesis)")
                os.remove(os.path.join(partial, u.name + ".wav"))
                continue
            if not low <= len(spoken) <= high:
                report[u.name] = ("failed", f"the hypothesis has {len(spoken)} phones, the words {low}-{high}")
                os.remove(os.path.join(partial, u.name + ".wav"))
                continue
            if u.doubtful is not None and len(u.doubtful) == len(spoken):
                marks = iter(u.doubtful)
                found = [(phone if phone == SILENCE or not next(marks) else "?", start) for phone, start in found]
            seconds = samples[u.name] / 16000.0
            with open(os.path.join(partial, u.name + ".phones.csv"), "w", encoding="ascii") as phones:
                phones.write("start_s,end_s,phone\n")
                starts = [min(s[1] / FRAMES_PER_SECOND + (BOUNDARY_DELAY_S if s[1] > 0 else 0.0), seconds)
                          for s in found]
                if starts[0] > 0:
                    phones.write(f"0.000,{starts[0]:.3f},{SILENCE}\n")
                for i, (phone, _) in enumerate(found):
                    end = starts[i + 1] if i + 1 < len(found) else seconds
                    phones.write(f"{starts[i]:.3f},{end:.3f},{phone}\n")
            index.append(u)
            report[u.name] = ("aligned", "")

    with open(os.path.join(partial, "index.csv"), "w", encoding="utf-8", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(["file", "speaker", "text"])
        for u in index:
            writer.writerow([u.name, u.speaker, " ".join(u.words)])
    if args.speechocean:
        write_speakers(args.speechocean, {u.speaker for u in index}, os.path.join(partial, "speakers.csv"))
    with open(os.path.join(partial, "report.csv"), "w", encoding="utf-8", newline="") as out:
        writer = csv.writer(out)
        writer.writerow(["file", "status", "reason"])
        for u in utterances:
            writer.writerow([u.name, *report.get(u.name, ("failed", "not reached"))])
    failed = sum(1 for status, _ in report.values() if status != "aligned")
    if not index:
        shutil.rmtree(partial, ignore_errors=True)
        first = next(f"{name}: {reason}" for name, (status, reason) in report.items() if status != "aligned")
        fail(f"no utterance could be aligned ({failed} of {len(utterances)} failed; first: {first})")
    shutil.rmtree(output, ignore_errors=True)
    os.rename(partial, output)
    print(f"aligned {len(index)} of {len(utterances)} utterances into {output} ({failed} left out: report.csv)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
