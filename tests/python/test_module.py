"""The module as a Python user meets it: numpy in and out, a stream that gives what a whole file gives, every
format, and errors as exceptions that name the file."""

import json
import os
import wave

import numpy as np
import pytest

import talkinghead


def read_wav(path):
    with wave.open(path) as w:
        pcm = np.frombuffer(w.readframes(w.getnframes()), dtype=np.int16)
        return pcm.reshape(-1, w.getnchannels())[:, 0].astype(np.float32) / 32768.0, w.getframerate()


@pytest.fixture(scope="module")
def prompt(data):
    return os.path.join(data, "speech", "arctic", "arctic_a0001.wav")


def test_names_and_formats():
    assert talkinghead.__version__.count(".") == 2
    assert len(talkinghead.arkit_names) == 52 and talkinghead.arkit_names[17] == "jawOpen"
    assert talkinghead.viseme_names == ["sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih",
                                        "oh", "ou"]
    assert talkinghead.vrm_names == ["A", "I", "U", "E", "O"]
    for name in ("csv", "json", "fap", "arkit", "oculus", "vrm", "rhubarb-tsv", "rhubarb-xml", "rhubarb-json", "moho"):
        assert name in talkinghead.formats()
    assert talkinghead.format_extension("moho") == ".dat"


def test_animate_gives_arrays_that_follow_the_speech(prompt):
    samples, rate = read_wav(prompt)
    animation = talkinghead.animate(prompt)
    arrays = animation.arrays()
    frames = animation.frames
    assert abs(frames - len(samples) / rate * 30) <= 2
    assert arrays["faps"].shape == (frames, 69) and arrays["faps"].dtype == np.float32
    assert arrays["arkit"].shape == (frames, 52)
    assert arrays["head"].shape == (frames, 3)
    np.testing.assert_allclose(np.linalg.norm(arrays["head_unity"], axis=1), 1.0, atol=1e-5)   # unit quaternions
    np.testing.assert_allclose(arrays["time"], np.arange(frames) / 30.0)
    np.testing.assert_allclose(arrays["visemes"].sum(axis=1), 1.0, atol=1e-4)
    assert ((arrays["arkit"] >= 0) & (arrays["arkit"] <= 1)).all()
    assert len(arrays["rhubarb"]) == frames and set(arrays["rhubarb"]) <= set("ABCDEFGHX")
    # The jaw opens with the voice: jawOpen against each frame's level.
    hop = rate / 30.0
    level = np.array([np.sqrt(np.mean(samples[int(max(0, i * hop - hop / 2)):int(i * hop + hop / 2)] ** 2) + 1e-12)
                      for i in range(frames)])
    assert np.corrcoef(arrays["arkit"][:, 17], 20 * np.log10(level))[0, 1] > 0.5


def test_an_animation_is_a_sequence_of_frames_as_its_arrays_have_them(prompt):
    animation = talkinghead.animate(prompt)
    arrays = animation.arrays()
    assert len(animation) == animation.frames > 0
    frames = list(animation)
    assert len(frames) == len(animation)
    for i in (0, len(animation) // 2, len(animation) - 1):
        frame = frames[i]
        assert frame["index"] == arrays["index"][i] and frame["time"] == arrays["time"][i]
        for key in ("faps", "arkit", "visemes", "vrm", "head", "head_unity"):
            np.testing.assert_array_equal(frame[key], arrays[key][i])
        assert frame["viseme"] == arrays["viseme"][i] and frame["rhubarb"] == arrays["rhubarb"][i]
    np.testing.assert_array_equal(animation[-1]["faps"], arrays["faps"][-1])
    with pytest.raises(IndexError):
        animation[len(animation)]
    with pytest.raises(IndexError):
        animation[-len(animation) - 1]


def test_a_stream_fed_in_blocks_gives_every_frame_in_order(prompt):
    samples, rate = read_wav(prompt)
    with talkinghead.Stream(sample_rate=rate) as stream:
        assert 20 < stream.latency_ms < 200
        pieces = []
        for start in range(0, len(samples), 441):
            stream.push(samples[start:start + 441])
            pieces.append(stream.pull())
        stream.finish()
        pieces.append(stream.pull())
    index = np.concatenate([p["index"] for p in pieces])
    np.testing.assert_array_equal(index, np.arange(len(index)))
    assert abs(len(index) - len(samples) / rate * 30) <= 2
    jaw = np.concatenate([p["arkit"][:, 17] for p in pieces])
    assert jaw.max() > 0.2 and jaw[:3].max() < 0.1  # opens for the speech, closed at the start's silence
    # Integers and float64 are converted: the same frames.
    with talkinghead.Stream(sample_rate=rate) as again:
        again.push((samples * 32767).astype(np.float64) / 32767)
        again.finish()
        assert len(again.pull()["index"]) == len(index)


def test_every_format_is_written(prompt, tmp_path):
    animation = talkinghead.animate(prompt)
    for name in talkinghead.formats():
        path = tmp_path / ("out" + talkinghead.format_extension(name))
        animation.write(str(path), name)
        assert path.stat().st_size > 0, name
    assert (tmp_path / "out.tsv").read_text().startswith("0.00\tX\n")
    cues = json.loads((tmp_path / "out.json").read_text())  # rhubarb-json was written last to .json
    assert cues["metadata"]["soundFile"].endswith("arctic_a0001.wav")


def test_errors_are_exceptions_naming_the_file(tmp_path):
    missing = str(tmp_path / "missing.wav")
    with pytest.raises(talkinghead.Error, match="missing.wav"):
        talkinghead.animate(missing)
    text = tmp_path / "text.wav"
    text.write_text("not audio")
    with pytest.raises(talkinghead.Error, match="text.wav"):
        talkinghead.animate(str(text))
    with pytest.raises(talkinghead.Error, match="sample rate"):
        talkinghead.Stream(sample_rate=100)
    with pytest.raises(talkinghead.Error, match="text.wav.*not valid JSON"):
        talkinghead.Stream(viseme_model=str(text))
    with pytest.raises(talkinghead.Error, match="one-dimensional"):
        talkinghead.Stream().push(np.zeros((2, 2), dtype=np.float32))


def test_export_draws_our_face_or_the_users_character(prompt, data, tmp_path):
    face = tmp_path / "face.mp4"
    talkinghead.export(prompt, str(face), 160, 120)
    character = tmp_path / "character.mp4"
    talkinghead.export(prompt, str(character), 160, 120, avatar=os.path.join(data, "face", "avatars", "vroid.glb"))
    for video in (face, character):
        assert video.stat().st_size > 10000
    assert face.read_bytes() != character.read_bytes()
    text = tmp_path / "me.glb"
    text.write_text("not a character")
    never = tmp_path / "never.mp4"
    with pytest.raises(talkinghead.Error, match="me.glb.*not a glTF file"):
        talkinghead.export(prompt, str(never), 160, 120, avatar=str(text))
    assert not never.exists()


def test_the_version_is_the_librarys():
    major, minor, patch = (int(part) for part in talkinghead.__version__.split("."))
    assert (major, minor) >= (0, 2)


def test_export_reports_progress_and_cancels_leaving_no_file(prompt, tmp_path):
    done = []
    video = tmp_path / "talk.mp4"
    talkinghead.export(prompt, str(video), 160, 120, progress=done.append)
    assert video.stat().st_size > 10000
    assert done[0] == 0.0 and done[-1] == 1.0 and done == sorted(done) and len(done) > 10

    # Returning True cancels: talkinghead.Cancelled, and no file.
    never = tmp_path / "never.mp4"
    seen = []
    with pytest.raises(talkinghead.Cancelled, match="cancelled"):
        talkinghead.export(prompt, str(never), 160, 120, progress=lambda fraction: seen.append(fraction) or
                           fraction > 0.2)
    assert 0.2 < seen[-1] < 0.5
    assert list(tmp_path.iterdir()) == [video]

    # Raising cancels too, and the exception comes out as it was.
    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        talkinghead.export(prompt, str(never), 160, 120, progress=stop)
    assert list(tmp_path.iterdir()) == [video]


def test_animate_reports_its_start_and_end_and_cancels(prompt):
    done = []
    assert talkinghead.animate(prompt, progress=done.append).frames > 0
    assert done == [0.0, 1.0]
    with pytest.raises(talkinghead.Cancelled):
        talkinghead.animate(prompt, progress=lambda fraction: True)


def test_models_read_once_give_what_each_call_reads_for_itself(prompt):
    samples, rate = read_wav(prompt)
    models = talkinghead.Models()

    def streamed(stream):
        with stream:
            stream.push(samples)
            stream.finish()
            return stream.pull()

    alone = streamed(talkinghead.Stream(sample_rate=rate))
    for _ in range(2):
        shared = streamed(talkinghead.Stream(sample_rate=rate, models=models))
        for key in ("faps", "arkit", "visemes", "head", "viseme"):
            np.testing.assert_array_equal(shared[key], alone[key])
    np.testing.assert_array_equal(talkinghead.animate(prompt, models=models).arrays()["faps"],
                                  talkinghead.animate(prompt).arrays()["faps"])
    with pytest.raises(talkinghead.Error, match="not both"):
        talkinghead.Stream(models=models, head_model="")


def test_a_head_style_moves_the_head_in_files_streams_and_shared_models(prompt, tmp_path):
    # A style that only moves the rest pose: every frame's head turns by it, whichever way the speech is animated.
    rest = np.array([6.0, -9.0, 3.0])
    measures = {"spread_deg": [1, 1, 1], "speed_p95_deg_s": 1, "pause_speech_ratio": 0, "pauses": False,
                "beats_per_second": 1, "seconds": 20}
    style = tmp_path / "rest.json"
    style.write_text(json.dumps({"format": "talkinghead-head-style", "version": 1, "source": "test",
                                 "rest_pose_deg": rest.tolist(),
                                 "synthesis": {"axis_gain": [1, 1, 1], "smoothing": 1, "variation": 1,
                                               "pause_variation": 0.4},
                                 "person": measures, "fitted": measures}))
    plain = talkinghead.animate(prompt).arrays()["head"]
    styled = talkinghead.animate(prompt, head_style=str(style)).arrays()["head"]
    np.testing.assert_allclose(styled - plain, np.tile(rest, (len(plain), 1)), atol=1e-4)
    models = talkinghead.Models(head_style=str(style))
    np.testing.assert_array_equal(talkinghead.animate(prompt, models=models).arrays()["head"], styled)

    samples, rate = read_wav(prompt)

    def streamed(stream):
        with stream:
            stream.push(samples)
            stream.finish()
            return stream.pull()["head"]

    alone = streamed(talkinghead.Stream(sample_rate=rate))
    np.testing.assert_allclose(streamed(talkinghead.Stream(sample_rate=rate, head_style=str(style))) - alone,
                               np.tile(rest, (len(alone), 1)), atol=1e-4)
    np.testing.assert_array_equal(streamed(talkinghead.Stream(sample_rate=rate, models=models)),
                                  streamed(talkinghead.Stream(sample_rate=rate, head_style=str(style))))
    with pytest.raises(talkinghead.Error, match="gone.json"):
        talkinghead.Models(head_style=str(tmp_path / "gone.json"))
