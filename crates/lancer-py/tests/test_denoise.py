"""lancer.denoise and lancer.render(denoise=True)."""

import numpy as np
import pytest

import lancer


def _noisy_scene(h=48, w=64, seed=3):
    """A clean image (two flat colours split by an edge, a vertical gradient), its albedo, and a
    noisy copy whose brightness is multiplied per pixel by 3u² (mean 1)."""
    y, x = np.mgrid[0:h, 0:w]
    left = (3 * x + y < 2 * w)[..., None]
    albedo = np.where(left, [0.8, 0.3, 0.2], [0.2, 0.5, 0.8]).astype(np.float32)
    clean = (albedo * (0.5 + 0.5 * y / h)[..., None]).astype(np.float32)
    u = np.random.default_rng(seed).random((h, w, 1), dtype=np.float32)
    return clean, albedo, (clean * 3 * u * u).astype(np.float32)


def _relmse(a, b):
    return float(np.mean((a - b) ** 2 / (b**2 + 0.01)))


def test_denoise_removes_most_of_the_noise():
    clean, albedo, noisy = _noisy_scene()
    for aux in ({}, {"albedo": albedo}):
        out = lancer.denoise(noisy, **aux)
        assert out.dtype == np.float32 and out.shape == noisy.shape
        assert _relmse(out, clean) < 0.2 * _relmse(noisy, clean)
    # float64 input is converted
    assert lancer.denoise(noisy.astype(np.float64)).dtype == np.float32


def test_denoise_refuses_bad_inputs():
    _, albedo, noisy = _noisy_scene()
    with pytest.raises(ValueError):
        lancer.denoise(noisy, normal=albedo)  # OIDN has no colour + normal network
    with pytest.raises(ValueError):
        lancer.denoise(noisy, albedo=albedo[:10])
    with pytest.raises(ValueError):
        lancer.denoise(noisy[..., :2])


def test_denoise_agrees_with_oidn_when_it_is_installed():
    pyoidn = pytest.importorskip("pyoidn", reason="pyoidn not installed: OIDN comparison skipped")
    clean, albedo, noisy = _noisy_scene()
    normal = np.zeros_like(albedo)
    normal[..., 2] = 1.0
    ours = lancer.denoise(noisy, albedo=albedo, normal=normal)
    theirs = pyoidn.denoise(noisy, albedo, normal, hdr=True, quality="high")
    assert np.sqrt(np.mean((ours - theirs) ** 2)) <= 1e-3 * np.sqrt(np.mean(theirs**2))


def test_render_denoise(cbox):
    scene = lancer.load_file(cbox)
    noisy = lancer.render(scene, spp=2, resolution=(48, 48))
    clean = lancer.render(scene, spp=2, resolution=(48, 48), denoise=True)
    assert clean.shape == noisy.shape and clean.dtype == np.float32
    assert np.all(np.isfinite(clean)) and np.all(clean >= 0)
    # same brightness, much less pixel-to-pixel variation
    assert abs(clean.mean() / noisy.mean() - 1) < 0.1
    assert np.abs(np.diff(clean, axis=1)).mean() < 0.5 * np.abs(np.diff(noisy, axis=1)).mean()
