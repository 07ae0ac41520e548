"""lancer.render: shapes, values against the reference and the command line, overrides,
threads, the GIL and Ctrl-C."""

import re
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import lancer
from conftest import lancer_binary

# Channel means of pbrt-v4's 256x256 render of cbox.pbrt (the team's reference,
# shared/references/pt/cbox.exr), which lancer's spectral mode is checked against.
CBOX_REFERENCE_MEANS = np.array([0.23426, 0.14047, 0.05813])


def test_render_gives_float32_rows_top_down(cbox):
    scene = lancer.load_file(cbox)
    img = lancer.render(scene, spp=2, resolution=(40, 24))
    assert isinstance(img, np.ndarray)
    assert img.dtype == np.float32 and img.shape == (24, 40, 3)
    assert img.flags["C_CONTIGUOUS"]
    # Finite everywhere (spectral samples converted to RGB may dip a little below 0).
    assert np.isfinite(img).all() and img.mean() > 0.05
    # Row 0 is the top of the image: the light (at y = 0.99, the ceiling's middle) is in the
    # top rows and the brightest pixels are there; the floor at the bottom is much darker.
    rows = img.mean(axis=(1, 2))
    assert rows[:4].max() > rows[-4:].max()


def test_cbox_means_agree_with_pbrt_reference(cbox):
    scene = lancer.load_file(cbox)
    img = lancer.render(scene, spp=64, resolution=(64, 64))
    means = img.mean(axis=(0, 1))
    rel = np.abs(means - CBOX_REFERENCE_MEANS) / CBOX_REFERENCE_MEANS
    assert rel.max() < 0.03, (means, rel)


def test_same_pixels_as_the_command_line(cbox, tmp_path):
    binary = lancer_binary()
    if binary is None:
        pytest.skip("no lancer binary (set LANCER_BIN or build it with cargo build)")
    assert binary.exists(), binary
    out = tmp_path / "cli.exr"
    help_text = subprocess.run([binary, "render", "--help"], capture_output=True, text=True).stdout
    spectral = [] if "--rgb" in help_text else ["--spectral"]  # spectral is the default once --rgb exists
    cmd = [binary, "render", cbox, "-o", out, "--quiet", "--spp", "8", "--resolution", "48x32", "--seed", "5"]
    subprocess.run(cmd + spectral, check=True)
    cli = lancer.read_image(out)
    img = lancer.render(lancer.load_file(cbox), spp=8, resolution=(48, 32), seed=5)
    # Sums of samples are exact integers in lancer's film: the same options give the same bits.
    np.testing.assert_array_equal(img, cli)


def test_threads_do_not_change_the_image_and_seeds_do(cbox):
    scene = lancer.load_file(cbox)
    one = lancer.render(scene, spp=3, resolution=(32, 32), threads=1)
    two = lancer.render(scene, spp=3, resolution=(32, 32), threads=2)
    np.testing.assert_array_equal(one, two)
    other_seed = lancer.render(scene, spp=3, resolution=(32, 32), seed=1)
    assert not np.array_equal(one, other_seed)


def test_crop_renders_that_window_only(cbox):
    scene = lancer.load_file(cbox)
    full = lancer.render(scene, spp=2, resolution=(32, 32))
    part = lancer.render(scene, spp=2, resolution=[32, 32], crop=[0.25, 0.75, 0.0, 0.5])
    # pbrt's rounding: columns ceil(32*0.25)=8 .. ceil(32*0.75)=24, rows 0 .. 16.
    assert part.shape == (16, 16, 3)
    np.testing.assert_array_equal(part, full[0:16, 8:24])


def test_spectral_and_rgb_modes_differ_but_agree_on_average(cbox):
    scene = lancer.load_file(cbox)
    spectral = lancer.render(scene, spp=16, resolution=(32, 32))
    rgb = lancer.render(scene, spp=16, resolution=(32, 32), spectral=False)
    assert not np.array_equal(spectral, rgb)
    assert lancer.mean_rel_error(rgb, spectral) < 0.1


def test_bad_arguments_raise_value_errors(cbox):
    scene = lancer.load_file(cbox)
    for kwargs, words in [
        ({"spp": 0}, "spp must be at least 1"),
        ({"resolution": (0, 10)}, "width 0"),
        ({"resolution": (10, 100000)}, "height 100000"),
        ({"crop": (0.5, 0.25, 0.0, 1.0)}, "x0 < x1"),
        ({"crop": (0.0, 1.0, 0.0, 1.5)}, "in [0, 1]"),
        ({"resolution": (10, 10, 3)}, "resolution is (width, height)"),
        ({"crop": [0.0, 1.0]}, "crop is (x0, x1, y0, y1)"),
    ]:
        with pytest.raises(ValueError, match=re.escape(words)):
            lancer.render(scene, **kwargs)
    with pytest.raises(ValueError, match="selects no pixel"):
        lancer.render(scene, resolution=(4, 4), crop=(0.1, 0.2, 0.0, 1.0))
    with pytest.raises(OverflowError):
        lancer.render(scene, spp=-1)


def test_the_gil_is_released_while_rendering(cbox):
    scene = lancer.load_file(cbox)
    result = {}
    worker = threading.Thread(target=lambda: result.update(img=lancer.render(scene, spp=64, resolution=(128, 128), threads=1)))
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.01)
    worker.join()
    assert result["img"].shape == (128, 128, 3)
    # The render takes well over 0.2 s on one thread; Python code ran all along.
    assert ticks >= 20, ticks


def test_ctrl_c_stops_a_render_with_keyboard_interrupt(cbox):
    child = textwrap.dedent(
        f"""
        import signal, sys, time, lancer
        # An interactive Python turns Ctrl-C into KeyboardInterrupt; a child of a batch job
        # may inherit SIGINT ignored (bash ignores it for background commands), so restore it.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        scene = lancer.load_file({str(cbox)!r})
        print("rendering", flush=True)
        t = time.monotonic()
        try:
            lancer.render(scene, spp=100000, resolution=(64, 64), threads=1)
            print("finished")
        except KeyboardInterrupt:
            print(f"interrupted after {{time.monotonic() - t:.2f}} s", flush=True)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", child], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    try:
        out, _ = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        raise AssertionError("the render went on after Ctrl-C")
    assert out.startswith("interrupted after"), out
    assert p.returncode == 0
