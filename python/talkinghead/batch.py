"""Animate and export many recordings on a Dask cluster (dask.distributed), one task per recording.

    python3 -m talkinghead.batch RECORDINGS -o OUT [--format csv --format rhubarb-tsv] [--export 640x360]
                                 [--scheduler tcp://HOST:8786 | --workers N]

RECORDINGS is a folder (its sound and video files, sorted) or a manifest: a text file with one recording per line
(blank lines and lines starting with # skipped; relative paths are relative to the manifest). Each recording's
outputs go to OUT as NAME.FORMAT.EXT (speech.csv.csv, speech.rhubarb-tsv.tsv) and NAME.mp4. Without --scheduler
a LocalCluster of --workers processes runs on this machine. The outputs equal a serial run's byte for byte: each
task is the same pure function of its recording (tests/python/test_batch.py).

From Python:

    from dask.distributed import Client
    from talkinghead.batch import recordings_in, run
    with Client("tcp://scheduler:8786") as client:
        written = run(recordings_in("takes/"), "out/", formats=["csv"], client=client)
"""

import argparse
import os
import sys

import talkinghead

RECORDING_EXTENSIONS = {".wav", ".flac", ".ogg", ".mp3", ".m4a", ".aac", ".opus", ".mp4", ".mkv", ".mov", ".avi",
                        ".mpg", ".webm"}


def recordings_in(source):
    """The recordings a folder holds (sorted), or those a manifest lists."""
    if os.path.isdir(source):
        return sorted(os.path.join(source, name) for name in os.listdir(source)
                      if os.path.splitext(name)[1].lower() in RECORDING_EXTENSIONS)
    base = os.path.dirname(os.path.abspath(source))
    recordings = []
    with open(source, encoding="utf-8") as manifest:
        for line in manifest:
            line = line.strip()
            if line and not line.startswith("#"):
                recordings.append(line if os.path.isabs(line) else os.path.join(base, line))
    return recordings


def output_path(recording, out_dir, fmt):
    name = os.path.splitext(os.path.basename(recording))[0]
    return os.path.join(out_dir, "%s.%s%s" % (name, fmt, talkinghead.format_extension(fmt)))


def animate_one(recording, out_dir, formats):
    """One task: a recording animated, written in each format; returns the paths written."""
    animation = talkinghead.animate(recording)
    written = []
    for fmt in formats:
        path = output_path(recording, out_dir, fmt)
        animation.write(path, fmt)
        written.append(path)
    return written


def export_one(recording, out_dir, width, height):
    """One task: a recording rendered to MP4; returns [its path] (as animate_one, a list)."""
    path = os.path.join(out_dir, os.path.splitext(os.path.basename(recording))[0] + ".mp4")
    talkinghead.export(recording, path, width, height)
    return [path]


def run(recordings, out_dir, formats=("csv",), export_size=None, client=None):
    """Every recording animated (and exported, given export_size = (width, height)); the paths written, in order.
    With a dask.distributed Client, one task per recording and output kind on its workers; without, here."""
    os.makedirs(out_dir, exist_ok=True)
    formats = list(formats)
    if client is None:
        written = [animate_one(r, out_dir, formats) for r in recordings]
        if export_size:
            written += [export_one(r, out_dir, *export_size) for r in recordings]
    else:
        futures = client.map(animate_one, recordings, out_dir=out_dir, formats=formats, pure=False)
        if export_size:
            futures += client.map(export_one, recordings, out_dir=out_dir, width=export_size[0],
                                  height=export_size[1], pure=False)
        written = client.gather(futures)
    return [path for paths in written for path in paths]


def main(arguments=None):
    parser = argparse.ArgumentParser(prog="python3 -m talkinghead.batch", description=__doc__.split("\n\n")[0])
    parser.add_argument("recordings", help="a folder of recordings, or a manifest (one path per line)")
    parser.add_argument("-o", "--output", required=True, help="the folder to write into")
    parser.add_argument("--format", action="append", choices=talkinghead.formats(),
                        help="an animation format (repeatable; default csv)")
    parser.add_argument("--export", metavar="WxH", help="also render each to MP4 at this size (e.g. 640x360)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (tcp://HOST:8786)")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="without --scheduler: local worker processes (default: the cores)")
    options = parser.parse_args(arguments)
    size = None
    if options.export:
        try:
            size = tuple(int(v) for v in options.export.lower().split("x"))
            assert len(size) == 2
        except (ValueError, AssertionError):
            parser.error("--export: %r is not WIDTHxHEIGHT" % options.export)
    recordings = recordings_in(options.recordings)
    if not recordings:
        parser.error("%s: no recordings" % options.recordings)
    from dask.distributed import Client, LocalCluster  # only where a cluster is used
    if options.scheduler:
        client = Client(options.scheduler)
    else:
        client = Client(LocalCluster(n_workers=options.workers, threads_per_worker=1, processes=True))
    with client:
        written = run(recordings, options.output, options.format or ["csv"], size, client)
    print("wrote %d files for %d recordings into %s" % (len(written), len(recordings), options.output))


if __name__ == "__main__":
    sys.exit(main())
