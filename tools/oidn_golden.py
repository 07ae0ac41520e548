"""Writes the denoiser's golden test data: Intel Open Image Denoise's own output on a small
synthetic image, which `crates/lancer-denoise/tests/it/oidn.rs` compares lancer's denoiser with.

usage: PEERS/bin/python tools/oidn_golden.py crates/lancer-denoise/tests/data/oidn_40x36.f32
(PEERS: the peers' virtualenv with the `pyoidn` wheel, ~/.cache/lancer-peers.)

The input is made exactly as the test makes it (the same float32 operations, the same xorshift
sequence): a slanted edge between two colours under a vertical gradient, multiplied per pixel
by 3u² (u uniform in [0, 1), mean 1), with its albedo and a normal per region. The file holds
OIDN's three outputs (colour; colour + albedo; colour + albedo + normal; "rt" filter, hdr,
quality "high"), each H x W x 3 float32, little-endian, in that order.
"""
import sys

import numpy as np
import pyoidn

W, H, SEED = 40, 36, 7
MASK = (1 << 64) - 1


def uniform(n, seed):
    """The test's xorshift64 sequence in [0, 1)."""
    s = ((seed * 0x9E3779B97F4A7C15) & MASK) | 1
    out = np.empty(n, np.float32)
    for i in range(n):
        s ^= (s << 13) & MASK
        s ^= s >> 7
        s ^= (s << 17) & MASK
        out[i] = np.float32(s >> 40) / np.float32(1 << 24)
    return out


def scene(w, h):
    """The clean image, its albedo and its normal (H x W x 3 float32)."""
    y, x = np.mgrid[0:h, 0:w]
    left = (3 * x + y < 2 * w)[..., None]
    albedo = np.where(left, np.float32([0.8, 0.3, 0.2]), np.float32([0.2, 0.5, 0.8])).astype(np.float32)
    normal = np.where(left, np.float32([0.0, 0.0, -1.0]), np.float32([0.6, 0.0, -0.8])).astype(np.float32)
    light = np.float32(0.5) + np.float32(0.5) * y.astype(np.float32) / np.float32(h)
    clean = albedo * light[..., None].astype(np.float32)
    return clean.astype(np.float32), albedo, normal


clean, albedo, normal = scene(W, H)
u = uniform(W * H, SEED).reshape(H, W, 1)
noisy = (clean * (np.float32(3.0) * u * u)).astype(np.float32)
outs = [
    pyoidn.denoise(noisy, hdr=True, quality="high"),
    pyoidn.denoise(noisy, albedo, hdr=True, quality="high"),
    pyoidn.denoise(noisy, albedo, normal, hdr=True, quality="high"),
]
with open(sys.argv[1], "wb") as f:
    for o in outs:
        f.write(np.ascontiguousarray(o, dtype="<f4").tobytes())
for name, o in zip(("colour", "+albedo", "+normal"), outs):
    print(f"{name}: mean {o.mean((0, 1))}, noisy mean {noisy.mean((0, 1))}")
