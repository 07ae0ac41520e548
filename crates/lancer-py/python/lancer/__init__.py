"""lancer, a physically based ray tracer, from Python.

    import lancer
    scene = lancer.load_file("scene.pbrt")        # pbrt-v4, glTF, OBJ or PLY
    image = lancer.render(scene, spp=64)          # float32 array (height, width, 3), linear RGB
    lancer.write_image("image.exr", image)        # .exr (float) or .png (8-bit sRGB)

lancer.distributed.render(path, parts, client, spp=...) spreads a render over a Dask cluster
and returns the same bits. The wheel's `lancer` command is the command line itself.

Scene errors raise lancer.SceneError (a ValueError) whose message starts with
file:line:column; what lancer reads but does differently is a lancer.SceneWarning.
"""

from . import _cpu

_cpu.check()

import os as _os  # noqa: E402

import numpy as _np  # noqa: E402

from ._lancer import (  # noqa: E402
    Scene,
    SceneError,
    SceneWarning,
    __version__,
    load_file,
    load_string,
    read_image,
    render,
)
from . import _lancer  # noqa: E402
from . import distributed  # noqa: E402

__all__ = [
    "Scene",
    "SceneError",
    "SceneWarning",
    "load_file",
    "load_string",
    "render",
    "denoise",
    "distributed",
    "write_image",
    "read_image",
    "mean_rel_error",
    "relmse",
    "rmse",
    "nrmse",
    "__version__",
]


def _image(array, dtype, name="image"):
    """`array` as a C-contiguous (height, width, 3) array of `dtype`."""
    a = _np.ascontiguousarray(array, dtype=dtype)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(
            f"{name}: an image is an array of shape (height, width, 3), not {a.shape}"
        )
    return a


def _pair(image, reference):
    """Both images as float64 (height, width, 3) arrays, for the metrics."""
    return _image(image, _np.float64), _image(reference, _np.float64, "reference")


def write_image(path, array):
    """Writes a (height, width, 3) array of linear RGB, row 0 at the top, to `path`.

    The extension picks the format: .exr keeps 32-bit floats, .png clamps to [0, 1],
    sRGB-encodes and rounds to 8 bits. The file is written atomically.
    """
    _lancer.write_image(_os.fspath(path), _image(array, _np.float32))


def denoise(color, albedo=None, normal=None):
    """Denoises an HDR render with Open Image Denoise's network (lancer's own inference).

    `color`, `albedo` and `normal` are (height, width, 3) arrays (converted to float32):
    the noisy linear RGB, the albedo and the shading normal (components in [-1, 1]) of the
    first non-specular surface. Give none, `albedo`, or both: each combination has its own
    network. Returns a float32 array: OIDN 2.x's result (quality "high", hdr) up to float
    rounding.
    """
    c = _image(color, _np.float32, "color")
    a = None if albedo is None else _image(albedo, _np.float32, "albedo")
    n = None if normal is None else _image(normal, _np.float32, "normal")
    return _lancer.denoise(c, a, n)


def mean_rel_error(image, reference):
    """max over channels of |mean(image) - mean(reference)| / max(mean(reference), 1e-4).

    A bias measure that noise hardly moves; the images may differ in size.
    """
    return _lancer.mean_rel_error(*_pair(image, reference))


def relmse(image, reference):
    """Relative MSE: mean of (image - reference)^2 / (reference^2 + (0.1 m)^2), m = mean(reference)."""
    return _lancer.relmse(*_pair(image, reference))


def rmse(image, reference):
    """Root mean squared difference over every pixel and channel."""
    return _lancer.rmse(*_pair(image, reference))


def nrmse(image, reference):
    """RMSE divided by the reference's mean (floored at 1e-6)."""
    return _lancer.nrmse(*_pair(image, reference))
