#!/usr/bin/env python3
"""Shrink a reference EXR for the test suite: box-filter by an integer factor, store as half float.

usage: shrink_reference.py IN.exr OUT.exr FACTOR

The test suite keeps small copies of the shared references (../shared/references) so that it
runs on a clone without them. Box filtering keeps channel means exact and averages the noise
away; tests shrink their own renders by the same factor before comparing.
Needs numpy and OpenEXR (pip install numpy OpenEXR).
"""
import sys

import numpy as np
import OpenEXR

src, dst, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
with OpenEXR.File(src) as f:
    ch = f.channels()
    a = np.asarray(ch["RGB"].pixels if "RGB" in ch else ch["RGBA"].pixels[..., :3], dtype=np.float64)
h, w = a.shape[0] // k * k, a.shape[1] // k * k
a = a[:h, :w].reshape(h // k, k, w // k, k, 3).mean((1, 3)).astype(np.float16)
header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
OpenEXR.File(header, {"RGB": a}).write(dst)
