"""lancer.distributed: parts rendered to their exact sums and merged give lancer.render's bits
(in this process, and over a Dask LocalCluster of two worker processes); parts that do not
make up one render are refused; the wheel's `lancer` command is the command line itself."""

import os
import subprocess
import sys

import numpy as np
import pytest

import lancer
from lancer import _lancer
from conftest import lancer_binary

OPTS = dict(spp=8, resolution=(40, 72), seed=3)  # 5 rows of 16-pixel tiles


@pytest.mark.parametrize("split_by", ["tiles", "samples"])
def test_parts_merge_to_the_single_render_bit_for_bit(cbox, split_by):
    scene = lancer.load_file(cbox)
    one = lancer.render(scene, **OPTS)
    parts = [_lancer.render_part(scene, i, 3, split_by=split_by, **OPTS) for i in range(3)]
    assert all(isinstance(p, bytes) for p in parts)
    merged = lancer.distributed.merge_parts(parts[::-1])  # any order
    assert merged.dtype == np.float32 and merged.shape == one.shape
    np.testing.assert_array_equal(merged, one)


def test_parts_that_are_not_one_render_are_refused(cbox):
    scene = lancer.load_file(cbox)
    parts = [_lancer.render_part(scene, i, 3, **OPTS) for i in range(3)]
    with pytest.raises(ValueError, match="holes"):
        lancer.distributed.merge_parts(parts[:2])
    with pytest.raises(ValueError, match="overlap"):
        lancer.distributed.merge_parts(parts + parts[:1])
    other = _lancer.render_part(scene, 2, 3, **dict(OPTS, seed=4))
    with pytest.raises(ValueError, match="seed"):
        lancer.distributed.merge_parts(parts[:2] + [other])
    with pytest.raises(ValueError, match="not a readable EXR"):
        lancer.distributed.merge_parts(parts[:2] + [b"not a part"])
    with pytest.raises(ValueError, match="does not exist"):
        _lancer.render_part(scene, 3, 3, **OPTS)
    with pytest.raises(ValueError, match="too few"):
        _lancer.render_part(scene, 0, 20, split_by="samples", **OPTS)


class _SerialClient:
    """What lancer.distributed asks of a Dask client, run in this process, with the
    arguments pickled as Dask sends them to a worker."""

    def submit(self, fn, *args, pure=True):
        import pickle

        fn, args = pickle.loads(pickle.dumps((fn, args)))
        return fn(*args)

    def gather(self, futures):
        return list(futures)


def test_render_over_a_client_gives_the_single_render(cbox):
    img = lancer.distributed.render(cbox, 4, _SerialClient(), split_by="samples", **OPTS)
    np.testing.assert_array_equal(img, lancer.render(lancer.load_file(cbox), **OPTS))
    with pytest.raises(lancer.SceneError):
        lancer.distributed.render(cbox.parent / "no-such.pbrt", 2, _SerialClient(), **OPTS)


def test_dask_local_cluster_of_two_processes(cbox):
    distributed = pytest.importorskip(
        "distributed", reason="Dask is not installed (pip install lancer-render[dask])"
    )
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        img = lancer.distributed.render(cbox, parts=4, client=client, **OPTS)
        pids = set(client.run(os.getpid).values())
    assert len(pids) == 2 and os.getpid() not in pids
    np.testing.assert_array_equal(img, lancer.render(lancer.load_file(cbox), **OPTS))


def _cli(*args):
    """The wheel's `lancer` command (lancer._cli:main) run with `args`."""
    code = "import sys; from lancer._cli import main; sys.argv[0] = 'lancer'; main()"
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True)


def test_the_lancer_command_is_the_command_line(cbox, tmp_path):
    v = _cli("--version")
    assert v.returncode == 0 and v.stdout.startswith("lancer ") and v.stderr == "", v
    bad = _cli("render", tmp_path / "missing.pbrt", "-o", tmp_path / "x.png")
    assert bad.returncode == 2 and "error:" in bad.stderr and bad.stdout == "", bad
    usage = _cli("render", "--spp")
    assert usage.returncode == 2 and "--spp" in usage.stderr, usage
    out = tmp_path / "py.exr"
    ok = _cli("render", cbox, "-o", out, "--spp", "2", "--resolution", "24x16", "--seed", "5", "--quiet")
    assert ok.returncode == 0, ok.stderr
    img = lancer.read_image(out)
    np.testing.assert_array_equal(img, lancer.render(lancer.load_file(cbox), spp=2, resolution=(24, 16), seed=5))
    binary = lancer_binary()
    if binary is not None and binary.exists():
        b = subprocess.run([binary, "--version"], capture_output=True, text=True)
        assert b.stdout.split()[:2] == v.stdout.split()[:2]
