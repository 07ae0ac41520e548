"""lancer.write_image and lancer.read_image."""

import numpy as np
import pytest

import lancer


def test_exr_round_trip_is_exact(tmp_path):
    rng = np.random.default_rng(7)
    img = (rng.random((5, 7, 3)) * 10).astype(np.float32)
    img[0, 0] = [0.0, 1e-8, 65504.0]
    path = tmp_path / "a.exr"
    lancer.write_image(path, img)
    back = lancer.read_image(path)
    assert back.dtype == np.float32 and back.shape == (5, 7, 3)
    np.testing.assert_array_equal(back, img)


def test_png_is_srgb_encoded_and_decoded(tmp_path):
    # Linear 0.5 is sRGB 0.7354 -> 8-bit 188 -> back to linear ((188/255 + 0.055)/1.055)^2.4.
    img = np.full((2, 3, 3), 0.5)
    img[1, 2] = [0.0, 1.0, 4.0]  # 4.0 is clamped to 1
    path = tmp_path / "a.png"
    lancer.write_image(str(path), img)  # float64 and str paths are accepted
    back = lancer.read_image(path)
    expected = ((188 / 255 + 0.055) / 1.055) ** 2.4
    assert back[0, 0, 0] == pytest.approx(expected, abs=1e-6)
    np.testing.assert_allclose(back[1, 2], [0.0, 1.0, 1.0], atol=1e-6)


def test_bad_images_and_paths_raise(tmp_path):
    with pytest.raises(ValueError, match=r"\(height, width, 3\)"):
        lancer.write_image(tmp_path / "a.exr", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="unknown image format"):
        lancer.write_image(tmp_path / "a.bmp", np.zeros((4, 4, 3)))
    with pytest.raises(OSError, match="no/such/folder"):
        lancer.write_image(tmp_path / "no/such/folder/a.exr", np.zeros((4, 4, 3)))
    with pytest.raises(FileNotFoundError, match="missing.exr"):
        lancer.read_image(tmp_path / "missing.exr")
    (tmp_path / "junk.png").write_bytes(b"not a png")
    with pytest.raises(ValueError, match="junk.png"):
        lancer.read_image(tmp_path / "junk.png")
