"""talkinghead: speech in, a talking face's animation out, on a CPU.

    import talkinghead
    animation = talkinghead.animate("speech.wav")          # a whole recording
    arrays = animation.arrays()                            # numpy: faps, arkit, visemes, vrm, head, ...
    for frame in animation: ...                            # a dict a frame (len(animation), animation[i])
    animation.write("speech.tsv")                          # any format `talkinghead animate` writes
    animation.write_avatar("talk.glb", "me.vrm")           # a character with the speech as its glTF animation

    stream = talkinghead.Stream(sample_rate=48000)         # live: samples in as they come
    stream.push(block)                                     # float32 mono
    frames = stream.pull()                                 # the frames ready, 30 a second

    models = talkinghead.Models()                          # the model files read once, shared
    talkinghead.Stream(models=models); talkinghead.animate("speech.wav", models=models)
    talkinghead.export("speech.wav", "talk.mp4", progress=lambda done: False)   # True cancels: Cancelled

talkinghead.batch runs animate and export over many recordings on a Dask cluster.
"""

from ._talkinghead import (Animation, Cancelled, Error, Models, Stream, __version__, animate,  # noqa: F401
                           arkit_names, export, format_extension, formats, viseme_names, vrm_names)
