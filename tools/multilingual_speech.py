#!/usr/bin/python3
"""Synthesise multilingual test speech with espeak-ng and write each utterance's phone alignment.

Purpose: check the audio->mouth model on speech in languages other than English: bilabial closures
(/p b m/) against open vowels, and a mouth-openness curve derived from the phones.

Run with Debian's interpreter (standard library + python3-numpy only, no network):

    /usr/bin/python3 tools/multilingual_speech.py [-o build/multilingual] [--lang de,fr,...]
                                                  [--rate WPM] [--raw-times] [--report] [-j N]

It drives espeak-ng's C library (libespeak-ng.so.1, Debian 12's espeak-ng 1.51) through ctypes:
espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 50 ms, NULL, espeakINITIALIZE_PHONEME_EVENTS), a synth
callback collecting the 16-bit samples (at the rate espeak_Initialize returns, 22050 Hz) and every
espeakEVENT_PHONEME event (mnemonic in the event's id.string, position in its `sample` field).

Output in DIR (-o, default build/multilingual):
  LANG_NN.wav         mono 16-bit PCM at espeak's rate: the speech with espeak's own leading and
                      trailing silence trimmed, then 0.3 s of digital silence added before and after.
  LANG_NN.phones.csv  start_s,end_s,phone,class; contiguous rows covering the whole file, times in
                      seconds of the WAV (the 0.3 s padding is included: rows `_`/silence).
  index.csv           file,language,text,seconds (seconds = length of the WAV, padding included).
Exits non-zero with one line if libespeak-ng cannot be loaded or initialised, or if a voice fails.

Phone classes: the table PHONE_CLASSES below (first matching rule wins), matched against espeak's
own mnemonic (Kirshenbaum-like ASCII, e.g. `p`, `p:` long, `ph`/`p#` aspirated, `p;` palatalised,
`m-` syllabic, `A:`, `aI`, `@U`):
  silence        espeak's pauses `_`, `_:`, `_!`, `_|`, `||` ..., and the 0.3 s padding (`_`).
  bilabial       p, b, m followed only by the marks : # h ; ' - w (p: ph p# p; b bh b# m m: m; m-).
                 Not the bilabial fricatives Spanish `B` and Japanese `p\` (lips not closed).
  labiodental    f, v with the same marks.
  open_vowel     a-like vowels: starting with `a`, `A`, `&` (a a: a# aI aU A A: A~ &), and Russian
                 `ja` (ya).
  rounded_vowel  starting with `o`, `O`, `u`, `U`, `y`, `Y`, `W`, `8`, or `@U`/`@u` (English "go"),
                 and Russian `ju` (yu).
  spread_vowel   starting with `i`, `I`, `e`, `E` (also diphthongs such as eI, iE, iou).
  other_vowel    other vowels: `@` (schwa, @-diphthongs), `3` (nurse), `V` (strut), `0` (lot).
  consonant      everything else, including the syllabic l- n- r-, the palatal glide `;` that
                 Russian/Polish voices emit after palatalised consonants, and Arabic `A` (ain,
                 a pharyngeal fricative: the one language-specific rule).
The rules were checked against espeak's own phoneme tables (phontab: type and place of articulation)
for every phone these sentences produce: all vowel classes are espeak vowels, bilabial/labiodental
are espeak's bilabial/labiodental stops, nasals and fricatives.

Timing (what espeak's events mean, checked against the samples; see --report):
  * The event's `sample` field is the sample index, counted from the start of this espeak_Synth
    call, at which the phone's synthesis starts: it always lies inside the buffer delivered with
    the event, and audio_position == (int)(sample * 1000 / rate), i.e. the same instant truncated
    to whole ms. Times here are taken from `sample`. A phone lasts until the next phoneme event.
  * espeak emits the event AFTER a phone's pre-pause: the silent closure of a voiceless stop
    (20-150 ms of exact zeros) ends exactly at the stop's event, whose position is the burst. With
    raw event times the closure would belong to the previous phone. Unless --raw-times is given, a
    run of digital silence (>= 5 ms, |x| <= 16) that ends exactly at an event is moved into that
    event's phone when the previous phone is not a pause, so a /p/ row starts at the lip closure.
  * For a vowel after a nasal or liquid espeak emits the event after the vowel's onset transition:
    the amplitude rise of m->vowel lies ~15-60 ms (median ~20) before the vowel's event, so /m/
    rows end with the lip opening. This is left as espeak reports it.
  * Language-switch markers that espeak reports as phoneme events, e.g. `(en)` for a word it reads
    as English, are skipped; zero-length phones (several events at one sample) are dropped.

Determinism: espeak keeps state across utterances in one process (the same text synthesised twice
in one process gives different samples), so every utterance is synthesised in a fresh process
(this script re-run as a worker); files are then the same for the same input, whatever -j or --lang.
"""

import argparse
import base64
import concurrent.futures
import csv
import ctypes
import io
import json
import os
import re
import subprocess
import sys
import wave

import numpy as np

LIBRARY = "libespeak-ng.so.1"
PAD_SECONDS = 0.3
SILENCE_ABS = 16            # |sample| at or below this counts as digital silence
MIN_CLOSURE_SECONDS = 0.005  # shortest silent run moved into the following phone

# --------------------------------------------------------------------------------------------
# The one phone -> class table: (languages or None for all, pattern, class). Patterns are Python
# regular expressions matched against the whole espeak mnemonic; the first matching rule wins.
_MARKS = r"[:#h;'\-w]*"     # length, aspiration, breathy, palatalisation, syllabic, labialisation
PHONE_CLASSES = [
    (None, r"_|_[:!|^;X].*|\|\|", "silence"),    # espeak's pause phonemes (not _j: a glide)
    (("ar",), r"A", "consonant"),                 # Arabic `A` is the pharyngeal fricative (ain)
    (None, r"[pbm]" + _MARKS, "bilabial"),        # p p: p# ph p; b bh b; m m: m; m- ...
    (None, r"[fv]" + _MARKS, "labiodental"),
    (None, r"[aA&].*|j[aA&].*", "open_vowel"),     # a A: aI aU &, Russian ja (ya)
    (None, r"@[Uu].*|[oOuUyYW8].*|j[oOuUyY].*", "rounded_vowel"),  # Russian ju (yu)
    (None, r"[iIeE].*|j[eEiI].*", "spread_vowel"),
    (None, r"[@3V0].*", "other_vowel"),           # schwa, @-diphthongs, nurse, strut, lot
    (None, r".*", "consonant"),
]
_COMPILED_CLASSES = [(langs, re.compile(pattern, re.S), cls) for langs, pattern, cls in PHONE_CLASSES]
CLASS_NAMES = ["silence", "bilabial", "labiodental", "open_vowel", "rounded_vowel",
               "spread_vowel", "other_vowel", "consonant"]


def phone_class(phone, lang=None):
    for langs, pattern, cls in _COMPILED_CLASSES:
        if (langs is None or lang in langs) and pattern.fullmatch(phone):
            return cls
    return "consonant"


# espeak reports a switch of language inside an utterance, e.g. "(en)" for an English word in
# another language's text, as a phoneme event: such markers are not phones and are skipped.
LANGUAGE_SWITCH = re.compile(r"\(.*\)")

# Voiceless stops (for the closure-energy check of --report).
VOICELESS_STOP = re.compile(r"[ptkcq][:#h;'w]*")

# --------------------------------------------------------------------------------------------
# Test sentences: language code -> (espeak voice, description, sentences). Everyday text with
# several /p b m/ and open vowels; each is 2-5 s at espeak's default rate.
LANGUAGES = {
    "en": ("en-us", "English (comparison), Germanic", [
        "My mum bought a basket of apples at the market.",
        "Paul parked the van by the bank at about five.",
        "Bob and Pam swam past the boats in the bay.",
        "Maybe we can grab a map and a pack of batteries.",
    ]),
    "de": ("de", "German, Germanic", [
        "Papa bringt am Montag einen Apfelkuchen mit.",
        "Mama backt bei Sabine ein Brot mit Marmelade.",
        "Am Abend spazieren wir am Bahnhof vorbei zum Park.",
        "Das kleine Mädchen lacht, wenn Paul mit dem Ball spielt.",
    ]),
    "fr": ("fr", "French, Romance", [
        "Papa a mis la baguette et le fromage dans le panier.",
        "Ma maman prépare un bon gâteau aux pommes pour le repas.",
        "Le bateau part à midi pour Marseille avec mon papa.",
        "Nous mangeons des pâtes avec Pascal et Martin samedi.",
    ]),
    "es": ("es", "Spanish, Romance", [
        "Mi papá compra pan en la panadería cada mañana.",
        "La mamá de Pablo baila en la playa por la mañana.",
        "Bajamos al mercado para comprar manzanas.",
        "El barco pasa por el puerto a las ocho.",
    ]),
    "it": ("it", "Italian, Romance", [
        "La mamma prepara la pasta per il pranzo.",
        "Il bambino mangia una banana al parco con il papà.",
        "Papà parte per Bari con la macchina dopo pranzo.",
        "Abbiamo comprato mele e patate al mercato.",
    ]),
    "pl": ("pl", "Polish, Slavic", [
        "Mama kupiła mleko i chleb w sklepie.",
        "Paweł pamięta o urodzinach babci w maju.",
        "Pada deszcz, więc bierzemy parasol.",
        "Mam małego psa, który bawi się piłką.",
    ]),
    "ru": ("ru", "Russian, Slavic", [
        "Мама купила папе большую банку малины на базаре.",
        "Мы пошли в парк погулять с собакой после обеда.",
        "Бабушка пекла пироги с капустой и мясом.",
        "Папа любит пить крепкий чай по утрам.",
    ]),
    "fi": ("fi", "Finnish, Uralic", [
        "Pappa maalaa vanhaa taloa pihalla aamupäivällä.",
        "Matti ja Pekka menivät kauppaan ostamaan banaaneja.",
        "Aamulla juon kupin kahvia ja syön leipää.",
        "Mummo paistaa pannukakkua isälle.",
    ]),
    "tr": ("tr", "Turkish, Turkic", [
        "Babam bana pazardan bir kitap ve bir kalem aldı.",
        "Annem pazardan elma ve patates aldı.",
        "Bu akşam parkta top oynamak istiyoruz.",
        "Sabah erkenden otobüse bindim.",
    ]),
    # Debian's espeak-ng 1.51 reads Hanzi with the "cmn" voice as pinyin whose tone digits are
    # spoken as English numbers ("ma one ma one ..."), so Mandarin is given as tone-marked pinyin
    # to the "cmn-Latn-pinyin" voice (same phoneme table and dictionary).
    "cmn": ("cmn-Latn-pinyin", "Mandarin Chinese, Sino-Tibetan", [
        "Māma zài shìchǎng mǎile bā gè píngguǒ.",      # 妈妈在市场买了八个苹果。
        "Bàba míngtiān zuò fēijī qù Běijīng.",         # 爸爸明天坐飞机去北京。
        "Wǒmen wǎnshang chī mǐfàn hé miànbāo.",        # 我们晚上吃米饭和面包。
        "Péngyou bāng wǒ ná bāo, wǒ hěn gāoxìng.",     # 朋友帮我拿包，我很高兴。
    ]),
    "ja": ("ja", "Japanese, Japonic", [
        "ぱぱは まいばん ばななを ふたつ たべます。",
        "けさ ぱんやで あまい ぱんを みっつ かいました。",
        "あさから あめが ずっと つよく ふって います。",
        "ははは まいあさ こうえんで さんぽを します。",
    ]),
    "hi": ("hi", "Hindi, Indo-Aryan", [
        "मेरी माँ बाज़ार से मीठे आम और पपीते लाई।",
        "पापा बाहर बाग में बैठकर अख़बार पढ़ते हैं।",
        "हम शाम को पानी पीने बाहर जाएँगे।",
        "बच्चे मैदान में बल्ला लेकर खेलते हैं।",
    ]),
    "ar": ("ar", "Arabic, Semitic", [
        "بَابَا ذَهَبَ إِلَى البَحْرِ مَعَ أَصْحَابِهِ.",
        "أُمِّي تَشْرَبُ المَاءَ مَعَ البِنْتِ.",
        "مَرْحَبًا، اِسْمِي مَرْيَم، وَأَنَا مِنْ بَغْدَاد.",
        "بَابُ البَيْتِ مَفْتُوحٌ مُنْذُ الصَّبَاحِ.",
    ]),
    "sw": ("sw", "Swahili, Bantu", [
        "Mama anapika chakula cha mchana pamoja na baba.",
        "Baba amekwenda sokoni kununua mahindi.",
        "Watoto wanacheza mpira pamoja.",
    ]),
}

# --------------------------------------------------------------------------------------------
# espeak-ng through ctypes (speak_lib.h, API revision 12)
AUDIO_OUTPUT_SYNCHRONOUS = 2
ESPEAK_INITIALIZE_PHONEME_EVENTS = 0x0001
ESPEAK_CHARS_UTF8 = 1
POS_CHARACTER = 1
ESPEAK_RATE = 1
EVENT_LIST_TERMINATED = 0
EVENT_PHONEME = 7


class _EventId(ctypes.Union):
    _fields_ = [("number", ctypes.c_int), ("name", ctypes.c_char_p), ("string", ctypes.c_char * 8)]


class _Event(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int),
                ("unique_identifier", ctypes.c_uint),
                ("text_position", ctypes.c_int),
                ("length", ctypes.c_int),
                ("audio_position", ctypes.c_int),   # ms, truncated
                ("sample", ctypes.c_int),           # sample index within this synthesis
                ("user_data", ctypes.c_void_p),
                ("id", _EventId)]


_SYNTH_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_short), ctypes.c_int,
                                   ctypes.POINTER(_Event))


def fail(message, code=1):
    print(f"multilingual_speech.py: error: {message}", file=sys.stderr)
    sys.exit(code)


def load_library(name):
    try:
        return ctypes.CDLL(name)
    except OSError as exc:
        fail(f"cannot load {name} ({exc}); install Debian's libespeak-ng1")


def synthesise(library, voice, text, rate_wpm):
    """In this process: returns (rate, int16 samples, phoneme events). Call once per process."""
    lib = load_library(library)
    lib.espeak_Initialize.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_char_p, ctypes.c_int]
    lib.espeak_Initialize.restype = ctypes.c_int
    lib.espeak_SetSynthCallback.argtypes = [_SYNTH_CALLBACK]
    lib.espeak_SetVoiceByName.argtypes = [ctypes.c_char_p]
    lib.espeak_SetVoiceByName.restype = ctypes.c_int
    lib.espeak_SetParameter.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int]
    lib.espeak_SetParameter.restype = ctypes.c_int
    lib.espeak_Synth.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_uint, ctypes.c_int,
                                 ctypes.c_uint, ctypes.c_uint, ctypes.c_void_p, ctypes.c_void_p]
    lib.espeak_Synth.restype = ctypes.c_int
    lib.espeak_Synchronize.restype = ctypes.c_int

    rate = lib.espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, 50, None, ESPEAK_INITIALIZE_PHONEME_EVENTS)
    if rate <= 0:
        fail(f"espeak_Initialize failed ({rate}): is espeak-ng-data installed?")

    chunks = []
    events = []
    received = [0]

    def on_synth(wav, count, event_list):
        start = received[0]
        if wav and count > 0:
            chunks.append(ctypes.string_at(wav, 2 * count))
            received[0] += count
        i = 0
        while event_list[i].type != EVENT_LIST_TERMINATED:
            ev = event_list[i]
            if ev.type == EVENT_PHONEME:
                name = bytes(ev.id.string).split(b"\0", 1)[0].decode("utf-8", "replace")
                # the buffer [start, start + count) is what this callback delivered with the event
                events.append({"phone": name, "sample": ev.sample, "ms": ev.audio_position,
                               "buffer_start": start, "buffer_count": max(count, 0)})
            i += 1
        return 0

    callback = _SYNTH_CALLBACK(on_synth)   # keep a reference while espeak may call it
    lib.espeak_SetSynthCallback(callback)
    if lib.espeak_SetVoiceByName(voice.encode()) != 0:
        fail(f"espeak-ng has no voice '{voice}'", 3)
    lib.espeak_SetParameter(ESPEAK_RATE, rate_wpm, 0)
    data = text.encode("utf-8")
    status = lib.espeak_Synth(data, len(data) + 1, 0, POS_CHARACTER, 0, ESPEAK_CHARS_UTF8, None, None)
    if status != 0:
        fail(f"espeak_Synth failed ({status}) for voice '{voice}'", 3)
    lib.espeak_Synchronize()
    samples = np.frombuffer(b"".join(chunks), dtype="<i2").copy()
    return rate, samples, events


def worker_main(library, voice, rate_wpm):
    text = sys.stdin.buffer.read().decode("utf-8")
    rate, samples, events = synthesise(library, voice, text, rate_wpm)
    json.dump({"rate": rate, "samples": base64.b64encode(samples.astype("<i2").tobytes()).decode("ascii"),
               "events": events}, sys.stdout)


def run_worker(library, voice, text, rate_wpm):
    cmd = [sys.executable, os.path.abspath(__file__), "--library", library, "--rate", str(rate_wpm),
           "--_worker", voice]
    proc = subprocess.run(cmd, input=text.encode("utf-8"), capture_output=True)
    if proc.returncode != 0:
        message = proc.stderr.decode("utf-8", "replace").strip().splitlines()
        raise RuntimeError(message[-1] if message else f"worker exited with {proc.returncode}")
    out = json.loads(proc.stdout)
    samples = np.frombuffer(base64.b64decode(out["samples"]), dtype="<i2").copy()
    return out["rate"], samples, out["events"]


# --------------------------------------------------------------------------------------------
# Alignment
def silent_run_before(samples, end, limit):
    """Start of the run of digital silence ending at sample `end` (not before `limit`)."""
    quiet = np.abs(samples[limit:end].astype(np.int32)) <= SILENCE_ABS
    if quiet.size == 0 or not quiet[-1]:
        return end
    loud = np.flatnonzero(~quiet)
    return limit + (loud[-1] + 1 if loud.size else 0)


def align(samples, rate, events, raw_times, lang):
    """Phones as (start, end, phone, raw_start) in samples of the unpadded, untrimmed signal."""
    n = len(samples)
    events = [e for e in events if not LANGUAGE_SWITCH.fullmatch(e["phone"])]
    starts = [min(max(int(e["sample"]), 0), n) for e in events]
    phones = []
    for k, e in enumerate(events):
        end = starts[k + 1] if k + 1 < len(events) else n
        phones.append([starts[k], end, e["phone"], starts[k]])
    if not raw_times:
        min_run = int(round(MIN_CLOSURE_SECONDS * rate))
        for k in range(1, len(phones)):
            prev = phones[k - 1]
            if phone_class(prev[2], lang) == "silence" or prev[1] - prev[0] <= 0:
                continue
            limit = prev[0] + 1          # the previous phone keeps at least one sample
            run_start = silent_run_before(samples, phones[k][0], limit)
            if phones[k][0] - run_start >= min_run:
                prev[1] = run_start
                phones[k][0] = run_start
    return [tuple(p) for p in phones]


def trim_and_pad(samples, rate, phones, lang):
    """Trim espeak's leading/trailing silence, pad PAD_SECONDS, return (signal, rows, offset)."""
    loud = np.flatnonzero(np.abs(samples.astype(np.int32)) > SILENCE_ABS)
    speech = [p for p in phones if phone_class(p[2], lang) != "silence" and p[1] > p[0]]
    if not speech or loud.size == 0:
        raise RuntimeError("espeak produced no speech")
    begin = min(int(loud[0]), speech[0][0])
    end = max(int(loud[-1]) + 1, speech[-1][1])
    pad = int(round(PAD_SECONDS * rate))
    signal = np.concatenate([np.zeros(pad, np.int16), samples[begin:end], np.zeros(pad, np.int16)])
    rows = [(0, pad, "_")]
    for start, stop, phone, _raw in phones:
        start, stop = max(start, begin), min(stop, end)
        if stop > start:
            rows.append((start - begin + pad, stop - begin + pad, phone))
    rows.append((end - begin + pad, len(signal), "_"))
    # rows are contiguous: fill any gap (espeak's phones cover the signal, so none expected)
    fixed = [rows[0]]
    for row in rows[1:]:
        if row[0] != fixed[-1][1]:
            raise RuntimeError(f"phone rows not contiguous at sample {row[0]}")
        fixed.append(row)
    return signal, fixed, pad - begin


def check_events(events, rate, n_samples):
    """Consistency of espeak's event positions with the delivered samples."""
    outside = 0
    ms_error = 0.0
    ms_mismatch = 0
    previous = 0
    order_errors = 0
    for e in events:
        if not (e["buffer_start"] <= e["sample"] <= e["buffer_start"] + e["buffer_count"]):
            outside += 1
        ms_error = max(ms_error, abs(e["ms"] - e["sample"] * 1000.0 / rate))
        if e["ms"] != int(e["sample"] * 1000.0 / rate):   # espeak: (int)(sample * 1000.0 / rate)
            ms_mismatch += 1
        if e["sample"] < previous or e["sample"] > n_samples:
            order_errors += 1
        previous = e["sample"]
    return {"outside_buffer": outside, "max_ms_error": ms_error, "ms_mismatch": ms_mismatch,
            "order_errors": order_errors}


# --------------------------------------------------------------------------------------------
def write_wav(path, signal, rate):
    with wave.open(path, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(signal.astype("<i2").tobytes())


def write_phones(path, rows, rate, lang):
    buf = io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    out.writerow(["start_s", "end_s", "phone", "class"])
    for start, stop, phone in rows:
        out.writerow([f"{start / rate:.6f}", f"{stop / rate:.6f}", phone, phone_class(phone, lang)])
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(buf.getvalue())


def rms_db(x):
    if x.size == 0:
        return None
    value = float(np.sqrt(np.mean(x.astype(np.float64) ** 2)))
    return 20.0 * np.log10(value / 32768.0) if value > 0 else float("-inf")


def middle(start, stop, fraction=0.5):
    half = (stop - start) * fraction / 2.0
    centre = (start + stop) / 2.0
    return int(round(centre - half)), int(round(centre + half))


def utterance_stats(samples, rate, events, phones, rows, signal, lang):
    """Numbers for --report (on the unpadded signal and on the written rows)."""
    stats = {"classes": {c: 0 for c in CLASS_NAMES}, "closure": [], "open": [], "bilabial": [],
             "stop_offsets": [], "stops": 0, "stops_silent_before": 0}
    for start, stop, phone in rows:
        cls = phone_class(phone, lang)
        stats["classes"][cls] += 1
        a, b = middle(start, stop)
        if cls == "open_vowel":
            stats["open"].append(signal[a:b])
        elif cls == "bilabial":
            stats["bilabial"].append(signal[a:b])
    ten_ms = int(0.010 * rate)
    for k, (start, stop, phone, raw) in enumerate(phones):
        if k == 0 or not VOICELESS_STOP.fullmatch(phone):
            continue
        stats["stops"] += 1
        # closure = the silent run just before espeak's event (raw position)
        run = silent_run_before(samples, raw, max(raw - int(0.3 * rate), 0))
        if raw - run >= ten_ms:
            stats["stops_silent_before"] += 1
            a, b = middle(run, raw)
            stats["closure"].append(samples[a:b])
            # the burst: first sample above the silence level at or after the event
            loud = np.flatnonzero(np.abs(samples[raw:raw + ten_ms].astype(np.int32)) > SILENCE_ABS)
            stats["stop_offsets"].append(int(loud[0]) if loud.size else ten_ms)
    stats["events"] = check_events(events, rate, len(samples))
    return stats


def print_report(results, rate):
    print(f"\nsample rate {rate} Hz; RMS in dBFS over the middle half of each segment")
    head = ("lang", "utt", "sec") + tuple(c[:8] for c in CLASS_NAMES) + (
        "closure", "bilab", "openV", "stops", "silent<", "burst", "evt_bad", "ms_err")
    print(" ".join(f"{h:>9}" for h in head))
    for lang, items in results.items():
        if not items:
            continue
        classes = {c: sum(s["classes"][c] for _, s in items) for c in CLASS_NAMES}
        cat = lambda key: np.concatenate([x for _, s in items for x in s[key]] or [np.zeros(0)])
        offsets = [o for _, s in items for o in s["stop_offsets"]]
        off = f"{int(np.median(offsets))}/{max(offsets)}" if offsets else "-"
        fmt = lambda v: "-" if v is None else f"{v:.1f}"
        row = (lang, len(items), f"{sum(sec for sec, _ in items):.1f}") + tuple(classes[c] for c in CLASS_NAMES) + (
            fmt(rms_db(cat("closure"))), fmt(rms_db(cat("bilabial"))), fmt(rms_db(cat("open"))),
            sum(s["stops"] for _, s in items), sum(s["stops_silent_before"] for _, s in items), off,
            sum(s["events"]["outside_buffer"] + s["events"]["order_errors"] + s["events"]["ms_mismatch"]
                for _, s in items),
            f"{max(s['events']['max_ms_error'] for _, s in items):.2f}")
        print(" ".join(f"{str(v):>9}" for v in row))
    print("closure: voiceless stops' silent closure before espeak's event; bilab/openV: bilabial and open"
          " vowel rows as written; stops: voiceless stops\n(p t k c q + marks); silent<: of them with"
          " >= 10 ms of silence ending exactly at the event; burst: median/max samples from the event to"
          " the first\nsample above the silence level (the burst), for those; evt_bad: events"
          " outside the callback buffer that delivered them, out of order, or with audio_position !="
          " int(sample*1000/rate);\nms_err: max |audio_position - sample*1000/rate| in ms; -inf dB:"
          " digital silence (all samples 0)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", default="build/multilingual", help="output folder")
    parser.add_argument("--lang", default=",".join(LANGUAGES),
                        help="comma-separated language codes (default: all): " + ",".join(LANGUAGES))
    parser.add_argument("--rate", type=int, default=175, help="speaking rate, words/minute (espeak's default 175)")
    parser.add_argument("--raw-times", action="store_true",
                        help="keep espeak's event times (stop closures then belong to the previous phone)")
    parser.add_argument("--report", action="store_true", help="print per-language counts and timing checks")
    parser.add_argument("-j", "--jobs", type=int, default=2, help="parallel espeak processes")
    parser.add_argument("--library", default=LIBRARY, help=argparse.SUPPRESS)
    parser.add_argument("--_worker", metavar="VOICE", help=argparse.SUPPRESS)
    args = parser.parse_args()

    if args._worker:
        worker_main(args.library, args._worker, args.rate)
        return 0

    load_library(args.library)   # one clear line and exit 1 when it is missing
    langs = [l.strip() for l in args.lang.split(",") if l.strip()]
    unknown = [l for l in langs if l not in LANGUAGES]
    if unknown:
        fail(f"unknown language(s) {','.join(unknown)}; known: {','.join(LANGUAGES)}", 2)
    os.makedirs(args.output, exist_ok=True)

    jobs = [(lang, i + 1, text) for lang in langs for i, text in enumerate(LANGUAGES[lang][2])]
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(run_worker, args.library, LANGUAGES[lang][0], text, args.rate)
                   for lang, _, text in jobs]
        outcomes = []
        for future in futures:
            try:
                outcomes.append(future.result())
            except RuntimeError as exc:
                outcomes.append(exc)

    index = []
    results = {lang: [] for lang in langs}
    failed = []
    rate_seen = None
    for (lang, number, text), outcome in zip(jobs, outcomes):
        name = f"{lang}_{number:02d}"
        if isinstance(outcome, Exception):
            failed.append(f"{name}: {outcome}")
            continue
        rate, samples, events = outcome
        rate_seen = rate
        try:
            check = check_events(events, rate, len(samples))
            if check["outside_buffer"] or check["order_errors"] or check["ms_mismatch"]:
                raise RuntimeError(f"espeak's event positions disagree with the samples: {check}")
            phones = align(samples, rate, events, args.raw_times, lang)
            signal, rows, _offset = trim_and_pad(samples, rate, phones, lang)
        except RuntimeError as exc:
            failed.append(f"{name}: {exc}")
            continue
        write_wav(os.path.join(args.output, name + ".wav"), signal, rate)
        write_phones(os.path.join(args.output, name + ".phones.csv"), rows, rate, lang)
        seconds = len(signal) / rate
        index.append([name + ".wav", lang, text, f"{seconds:.3f}"])
        if args.report:
            results[lang].append((seconds, utterance_stats(samples, rate, events, phones, rows, signal, lang)))

    buf = io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    out.writerow(["file", "language", "text", "seconds"])
    out.writerows(index)
    with open(os.path.join(args.output, "index.csv"), "w", encoding="utf-8", newline="") as f:
        f.write(buf.getvalue())
    print(f"wrote {len(index)} utterances in {len(langs)} languages to {args.output}")
    if args.report and rate_seen:
        print_report(results, rate_seen)
    for line in failed:
        print(f"multilingual_speech.py: failed: {line}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
