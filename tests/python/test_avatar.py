"""Animation.write_avatar: the speech as a glTF animation of a user's character, read back from the file (no glTF
library: the GLB's JSON chunk, or the .gltf's JSON with its buffer as a data URI)."""

import base64
import json
import os
import struct

import numpy as np
import pytest

import talkinghead


def read_gltf(path):
    """The file's JSON and its one buffer's bytes."""
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".gltf"):
        document = json.loads(data)
        uri = document["buffers"][0]["uri"]
        return document, base64.b64decode(uri[uri.index(",") + 1:])
    assert data[:4] == b"glTF"
    length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + length])
    binary = data[20 + length:]
    return document, binary[8:8 + struct.unpack_from("<I", binary, 0)[0]]


def floats(document, buffer, accessor):
    a = document["accessors"][accessor]
    view = document["bufferViews"][a["bufferView"]]
    size = {"SCALAR": 1, "VEC4": 4}[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    return np.frombuffer(buffer, dtype="<f4", count=a["count"] * size, offset=start).reshape(a["count"], size)


@pytest.fixture(scope="module")
def animation(data):
    return talkinghead.animate(os.path.join(data, "speech", "arctic", "arctic_a0001.wav"))


@pytest.fixture(scope="module")
def avatars(data):
    return os.path.join(data, "face", "avatars")


# Every form on one character and one form on the other (the VRoid one takes five seconds a form under the
# sanitizers): the binding passes both through to the library, whose own tests write both forms of both.
@pytest.mark.parametrize("name,form", [("brunette-t.glb", "talk.glb"), ("brunette-t.glb", "talk.gltf"),
                                       ("brunette-t.glb", "animation.gltf"), ("vroid.glb", "talk.glb")])
def test_the_character_gets_the_speech_as_its_animation(animation, avatars, tmp_path, name, form):
    out = str(tmp_path / form)
    only = form.startswith("animation")
    animation.write_avatar(out, os.path.join(avatars, name), animation_only=only)
    document, buffer = read_gltf(out)
    assert len(document["animations"]) == 1  # the test avatars have none of their own
    speech = document["animations"][0]
    assert speech["name"] == "speech"
    paths = [channel["target"]["path"] for channel in speech["channels"]]
    assert "weights" in paths and paths.count("rotation") >= 2  # the mouth, the neck and the head
    frames = animation.frames
    for sampler in speech["samplers"]:
        times = floats(document, buffer, sampler["input"])[:, 0]
        assert len(times) == frames
        np.testing.assert_allclose(times, np.arange(frames) / 30.0, atol=1e-5)
        assert document["accessors"][sampler["input"]]["max"][0] == pytest.approx((frames - 1) / 30.0, abs=1e-5)
    # The mouth opens: some weight moves by a third or more.
    weights = [floats(document, buffer, speech["samplers"][c["sampler"]]["output"])
               for c in speech["channels"] if c["target"]["path"] == "weights"]
    assert max(w.max() - w.min() for w in weights) > 0.3
    if only:
        assert "skins" not in document and "materials" not in document
    else:
        assert len(document["skins"]) >= 1


def test_errors_name_the_file_and_leave_nothing(animation, avatars, tmp_path):
    with pytest.raises(talkinghead.Error, match="missing.glb"):
        animation.write_avatar(str(tmp_path / "a.glb"), str(tmp_path / "missing.glb"))
    with pytest.raises(talkinghead.Error, match="a.csv"):
        animation.write_avatar(str(tmp_path / "a.csv"), os.path.join(avatars, "brunette-t.glb"))
    with pytest.raises(talkinghead.Error, match="a.vrm.*not a VRM"):
        animation.write_avatar(str(tmp_path / "a.vrm"), os.path.join(avatars, "brunette-t.glb"), animation_only=True)
    with pytest.raises(talkinghead.Error, match="a.vrm.*from a VRM character"):
        animation.write_avatar(str(tmp_path / "a.vrm"), os.path.join(avatars, "brunette-t.glb"))
    assert os.listdir(tmp_path) == []
