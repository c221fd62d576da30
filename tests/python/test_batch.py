"""The batch runner on a Dask LocalCluster of several worker processes: the files it writes equal a serial run's,
byte for byte (animations in several formats for three recordings; the MP4 export for one, as rendering it is
the slow part)."""

import filecmp
import os

from dask.distributed import Client, LocalCluster

from talkinghead import batch


def same_files(serial, parallel):
    assert len(serial) == len(parallel)
    for one, other in zip(serial, parallel):
        assert os.path.basename(one) == os.path.basename(other)
        assert filecmp.cmp(one, other, shallow=False), os.path.basename(one)


def test_a_local_cluster_writes_what_a_serial_run_writes(data, tmp_path):
    grid = os.path.join(data, "grid", "s1")
    clips = sorted(name for name in os.listdir(grid) if name.endswith(".mpg"))[:2]
    manifest = tmp_path / "manifest.txt"
    manifest.write_text("# two GRID clips and a prompt\n" +
                        "".join(os.path.join(grid, clip) + "\n" for clip in clips) +
                        os.path.join(data, "speech", "arctic", "arctic_a0001.wav") + "\n")
    recordings = batch.recordings_in(str(manifest))
    assert len(recordings) == 3
    formats = ["csv", "rhubarb-tsv", "oculus"]
    serial = batch.run(recordings, str(tmp_path / "serial"), formats)
    serial_video = batch.run(recordings[:1], str(tmp_path / "serial"), [], export_size=(64, 48))
    with LocalCluster(n_workers=3, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 3
        parallel = batch.run(recordings, str(tmp_path / "cluster"), formats, client=client)
        parallel_video = batch.run(recordings[:1], str(tmp_path / "cluster"), [], export_size=(64, 48),
                                   client=client)
    assert len(serial) == 3 * len(formats)
    same_files(serial, parallel)
    assert len(serial_video) == 1 and serial_video[0].endswith(".mp4")
    same_files(serial_video, parallel_video)


def test_a_folder_lists_its_recordings_in_order(tmp_path):
    for name in ("b.wav", "a.flac", "notes.txt", "c.mp4"):
        (tmp_path / name).write_bytes(b"")
    assert [os.path.basename(p) for p in batch.recordings_in(str(tmp_path))] == ["a.flac", "b.wav", "c.mp4"]
