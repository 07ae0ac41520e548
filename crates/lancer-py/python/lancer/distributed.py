"""lancer.distributed: one render spread over the workers of a Dask cluster.

    from dask.distributed import Client
    import lancer

    client = Client("tcp://scheduler:8786")       # or Client(LocalCluster(...)), a SLURMCluster...
    image = lancer.distributed.render("/shared/scene.pbrt", parts=8, client=client, spp=1024)

Each worker loads the scene from `path` (a path every worker can read: a shared file system)
and renders its part, as `lancer render --split i/N` does; the parts travel back to the client
as their exact accumulators (the 64-bit fixed-point sums of each pixel, the command line's
part files as bytes), never as rounded images, and are merged as `lancer merge` does. The
result is bit for bit `lancer.render(lancer.load_file(path), ...)` with the same options,
whatever the number of parts, workers or threads.

Dask is optional: `pip install lancer-render[dask]`. This module imports nothing of Dask
itself: it only calls the client it is given (`client.submit`, `client.gather`).
"""

import os as _os

from . import _lancer

__all__ = ["render", "render_part", "merge_parts"]


def render_part(path, part, parts, options):
    """Renders part `part` of `parts` of the scene file `path` with `lancer.render`'s keyword
    `options` (and `split_by`), and returns the part's bytes (what a worker sends back)."""
    scene = _lancer.load_file(path)
    return _lancer.render_part(scene, part, parts, **options)


def merge_parts(parts):
    """Merges the bytes of every part of a render (any order) into the float32 image
    (height, width, 3); refuses parts that are not exactly one render's (a part missing,
    twice, or of another scene or options) with a ValueError."""
    return _lancer.merge_parts(list(parts))


def render(path, parts, client, *, split_by="tiles", **options):
    """Renders the scene file `path` in `parts` parts over the Dask `client`'s workers and
    returns the merged image: a float32 array (height, width, 3), bit for bit what
    `lancer.render(lancer.load_file(path), **options)` returns.

    `options` are lancer.render's: spp, resolution, seed, threads (worker threads per part;
    all of a worker's cores by default), spectral, crop. `split_by` is "tiles" (each part a
    band of tile rows with every sample: parts <= the image's rows of 16-pixel tiles) or
    "samples" (each part a range of sample indices of every pixel: parts <= spp). `path` is
    made absolute here and must name the same file on every worker. A scene error on a worker
    is raised here (lancer.SceneError), as Dask re-raises a task's exception.
    """
    parts = int(parts)
    if parts < 1:
        raise ValueError(f"parts must be at least 1, not {parts}")
    if split_by not in ("tiles", "samples"):
        raise ValueError(f'split_by is "tiles" or "samples", not {split_by!r}')
    path = _os.path.abspath(_os.fspath(path))
    options = dict(options, split_by=split_by)
    futures = [
        client.submit(render_part, path, i, parts, options, pure=False)
        for i in range(parts)
    ]
    return merge_parts(client.gather(futures))
