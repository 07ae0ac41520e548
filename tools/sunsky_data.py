#!/usr/bin/env python3
"""Writes crates/lancer/src/light/sunsky/hosek_wilkie.bin, the tables of lancer's `sunsky` light.

Sources (data only, both under the 3-clause BSD licence; see hosek_wilkie.LICENSE beside the
output):
- the sky model's coefficients, from Hosek & Wilkie's published implementation (version 1.4a,
  https://cgg.mff.cuni.cz/projects/SkylightModelling/), as pbrt-v4 carries it in
  src/ext/skymodel/ArHosekSkyModelData_Spectral.h and ArHosekSkyModelData_RGB.h (the same
  numbers as Mitsuba 3's data/sunsky/sunsky_datasets.bin, which this script can check);
- the sun's irradiance per turbidity, solar elevation and wavelength, from Mitsuba 3's
  data/sunsky/sampling_data.bin (field `sun_irradiance`): what its `sunsky` emitter divides by
  the sun's solid angle for its (default, uniform) solar disk.

Layout: little-endian f32, in this order (row-major, last index fastest):
  sky_params_spec [turbidity 10][albedo 2][control point 6][wavelength 11][parameter 9]
  sky_rad_spec    [10][2][6][11]
  sky_params_rgb  [10][2][6][channel 3][9]
  sky_rad_rgb     [10][2][6][3]
  sun_irradiance  [turbidity 10][elevation 30: 2, 5, ..., 89 degrees][wavelength 11]
Wavelengths are 320, 360, ..., 720 nm; turbidities 1..10; albedos 0 and 1.

usage: tools/sunsky_data.py PBRT_V4_SKYMODEL_DIR MITSUBA_DATA_SUNSKY_DIR [OUT]
  (PBRT_V4_SKYMODEL_DIR holds the two headers; MITSUBA_DATA_SUNSKY_DIR holds the .bin files of
  the mitsuba wheel, e.g. site-packages/mitsuba/data/sunsky)
"""
import re
import struct
import sys
from pathlib import Path

import numpy as np

WAVELENGTHS = list(range(320, 721, 40))


def c_arrays(path):
    """The `double name[] = { ... };` arrays of a C header, by name."""
    text = Path(path).read_text()
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    out = {}
    for m in re.finditer(r"double\s+(\w+)\[\]\s*=\s*\{(.*?)\};", text, re.S):
        items = [x.strip() for x in m.group(2).split(",") if x.strip()]
        try:
            out[m.group(1)] = np.array([float(x) for x in items])
        except ValueError:
            pass  # the arrays of pointers
    return out


def tensor_file(path):
    """The fields of a Mitsuba 3 tensor file: name -> array (its format: src/core/tensor.cpp)."""
    b = Path(path).read_bytes()
    assert b[:12] == b"tensor_file\0", path
    (n,) = struct.unpack_from("<I", b, 14)
    o, out = 18, {}
    for _ in range(n):
        (nl,) = struct.unpack_from("<H", b, o)
        name = b[o + 2 : o + 2 + nl].decode()
        o += 2 + nl
        ndim, dtype, off = struct.unpack_from("<HBQ", b, o)
        o += 11
        shape = struct.unpack_from("<%dQ" % ndim, b, o)
        o += 8 * ndim
        dt = {10: "<f4", 11: "<f8"}[dtype]
        out[name] = np.frombuffer(b, dt, int(np.prod(shape)), off).reshape(shape)
    return out


def main():
    pbrt, mitsuba = Path(sys.argv[1]), Path(sys.argv[2])
    out = Path(sys.argv[3]) if len(sys.argv) > 3 else (
        Path(__file__).resolve().parent.parent / "crates/lancer/src/light/sunsky/hosek_wilkie.bin")
    spec = c_arrays(pbrt / "ArHosekSkyModelData_Spectral.h")
    rgb = c_arrays(pbrt / "ArHosekSkyModelData_RGB.h")
    # The published arrays are [albedo][turbidity][control point](parameter) per wavelength.
    params_spec = np.stack([spec["dataset%d" % w].reshape(2, 10, 6, 9) for w in WAVELENGTHS], 3)
    rad_spec = np.stack([spec["datasetRad%d" % w].reshape(2, 10, 6) for w in WAVELENGTHS], 3)
    params_rgb = np.stack([rgb["datasetRGB%d" % c].reshape(2, 10, 6, 9) for c in (1, 2, 3)], 3)
    rad_rgb = np.stack([rgb["datasetRGBRad%d" % c].reshape(2, 10, 6) for c in (1, 2, 3)], 3)
    tables = [a.swapaxes(0, 1) for a in (params_spec, rad_spec, params_rgb, rad_rgb)]
    ms = tensor_file(mitsuba / "sunsky_datasets.bin")
    for a, name in zip(tables, ["sky_params_spec", "sky_rad_spec", "sky_params_rgb", "sky_rad_rgb"]):
        assert a.shape == ms[name].shape and np.array_equal(a, ms[name]), name
    sun = tensor_file(mitsuba / "sampling_data.bin")["sun_irradiance"]
    assert sun.shape == (10, 30, 11)
    blob = b"".join(np.ascontiguousarray(a, "<f4").tobytes() for a in tables + [sun])
    out.write_bytes(blob)
    print("wrote", out, len(blob), "bytes")


if __name__ == "__main__":
    main()
