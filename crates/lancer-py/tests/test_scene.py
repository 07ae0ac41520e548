"""Loading scenes: files, text, errors with their place, warnings, info()."""

import warnings

import pytest

import lancer


def test_info_describes_the_cornell_box(cbox):
    info = lancer.load_file(cbox).info()
    assert info["name"] == str(cbox)
    assert info["resolution"] == (256, 256)
    assert info["spp"] == 64 and info["seed"] == 0
    cam = info["camera"]
    assert cam["projection"] == "perspective"
    assert cam["fov"] == pytest.approx(39.3077)
    # LookAt 0 0 3.9 towards the origin.
    assert cam["eye"] == pytest.approx((0.0, 0.0, 3.9), abs=1e-5)
    assert cam["forward"] == pytest.approx((0.0, 0.0, -1.0), abs=1e-5)
    # Light, 5 walls and 2 boxes: 8 meshes; 2 + 5*2 + 2*12 triangles; one area light.
    assert info["shapes"] == {"trianglemesh": 8} and info["shape_count"] == 8
    assert info["triangles"] == 36
    assert info["lights"] == {"area": 1} and info["light_count"] == 1
    assert info["material_count"] >= 3
    assert info["warnings"] == []
    assert info["files"] == [str(cbox.resolve())]


def test_a_malformed_scene_raises_scene_error_with_its_place():
    text = 'WorldBegin\nShape "sphere" "float radius" [oops]\n'
    with pytest.raises(lancer.SceneError) as caught:
        lancer.load_string(text)
    e = caught.value
    assert isinstance(e, ValueError)
    first, *excerpt = str(e).splitlines()
    # As `lancer render` prints it: file:line:column: message, then the line and a caret.
    assert first.startswith("<string>:2:"), first
    assert (e.file, e.line) == ("<string>", 2)
    assert excerpt[1] == '2 | Shape "sphere" "float radius" [oops]'
    assert excerpt[2].index("^") - excerpt[1].index("S") == e.column - 1
    assert text.splitlines()[1][e.column - 1 :].startswith("oops")


def test_a_missing_file_is_a_scene_error_naming_it(tmp_path):
    missing = tmp_path / "nowhere.pbrt"
    with pytest.raises(lancer.SceneError, match="nowhere.pbrt"):
        lancer.load_file(missing)
    with pytest.raises(lancer.SceneError, match="unknown scene format"):
        lancer.load_file(tmp_path / "scene.blend")


def test_load_string_finds_relative_files_in_base_dir(cbox):
    text = f'Include "{cbox.name}"\n'
    with pytest.raises(lancer.SceneError, match=cbox.name):
        lancer.load_string(text)  # not in the current folder
    scene = lancer.load_string(text, base_dir=cbox.parent)
    assert scene.info()["triangles"] == 36


def test_warnings_are_scene_warnings_with_their_place(tmp_path):
    text = 'Film "rgb" "integer xresolution" [8] "integer yresolution" [8]\nWorldBegin\nShape "sphere" "float radius" [1] "float wobble" [2]\n'
    with pytest.warns(lancer.SceneWarning, match=r'<string>:3:35: .*"float wobble"'):
        scene = lancer.load_string(text)
    assert len(scene.info()["warnings"]) == 1
    assert scene.info()["warnings"][0].startswith("<string>:3:35: ")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lancer.SceneWarning)
        img = lancer.render(lancer.load_string(text), spp=1)
    assert img.shape == (8, 8, 3)


def test_repr_names_the_scene(cbox):
    r = repr(lancer.load_file(cbox))
    assert r.startswith("<lancer.Scene ") and "cbox.pbrt" in r and "256x256" in r and "64 spp" in r
