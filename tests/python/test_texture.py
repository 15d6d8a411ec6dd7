"""Textures from Python: a finger's heights as a NumPy array in a scene dict, as a .npy or a
.csv file next to the scene, alike; bad arrays and files are scene errors naming the path."""

import json

import numpy as np
import pytest

import grasp


def with_map(cube_a_dict, heights, pixel_m=(1e-3, 8e-4), finger=0):
    """Cube A with a height map on one finger (its 10 mm patch of 5 x 5 elements: centres at
    -4, -2, 0, 2, 4 mm)."""
    cube_a_dict["fingers"][finger]["texture"] = {"heights": {**heights, "pixel_m": list(pixel_m)}}
    return cube_a_dict


def heights_9_by_11():
    """9 x 11 pixels of 1 x 0.8 mm: +-4 mm both ways, exactly the element centres' span."""
    i, j = np.meshgrid(np.arange(9), np.arange(11), indexing="ij")
    return 1e-6 * np.sin(0.7 * i) * np.cos(0.4 * j)


def test_an_array_is_sampled_with_its_centre_on_the_contact_point_rows_along_t1(cube_a_dict):
    h = heights_9_by_11()
    scene = grasp.Scene(with_map(cube_a_dict, {"array": h}))
    got = scene.texture_heights_m("f1")
    assert got.shape == (5, 5)
    # Element (a, b) is centred at ((a - 2) 2 mm, (b - 2) 2 mm): pixel (2 a, 2.5 b), bilinear
    # between columns when 2.5 b is not whole. Round-off only (heights ~1e-6 m).
    for a in range(5):
        for b in range(5):
            col = 2.5 * b
            lo = int(np.floor(col))
            hi = min(lo + 1, 10)
            want = (1 - (col - lo)) * h[2 * a, lo] + (col - lo) * h[2 * a, hi]
            assert abs(got[a, b] - want) < 1e-20, (a, b)
    assert scene.texture_heights_m("f2") is None
    assert scene.to_dict()["fingers"][0]["texture"]["heights"]["file"] == "<array>"
    # Solving is not affected here: the texture is not yet part of the gap.
    assert grasp.solve(scene).status == "solved"


@pytest.mark.parametrize(
    "save",
    [
        lambda p, h: np.save(p.with_suffix(".npy"), h),
        lambda p, h: np.save(p.with_suffix(".npy"), np.asfortranarray(h)),
        lambda p, h: np.save(p.with_suffix(".npy"), h.astype(">f8")),
        lambda p, h: np.savetxt(p.with_suffix(".csv"), h, delimiter=",", fmt="%.17g"),
        lambda p, h: np.savetxt(p.with_suffix(".csv"), h, fmt="%.17g"),
    ],
    ids=["npy", "npy-fortran", "npy-big-endian", "csv", "csv-blanks"],
)
def test_files_next_to_the_scene_give_the_array_s_heights(cube_a_dict, tmp_path, save):
    h = heights_9_by_11()
    save(tmp_path / "h", h)
    (name,) = [p.name for p in tmp_path.iterdir()]
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(with_map(json.loads(json.dumps(cube_a_dict)), {"file": name})))
    from_file = grasp.Scene(path).texture_heights_m("f1")
    from_array = grasp.Scene(with_map(cube_a_dict, {"array": h})).texture_heights_m("f1")
    np.testing.assert_array_equal(from_file, from_array)


def test_integer_and_float32_maps_are_read(cube_a_dict, tmp_path):
    h = np.arange(99, dtype=np.int16).reshape(9, 11) - 50
    np.save(tmp_path / "i.npy", h)
    path = tmp_path / "s.json"
    d = with_map(json.loads(json.dumps(cube_a_dict)), {"file": "i.npy"})
    path.write_text(json.dumps(d))
    scene = grasp.Scene(with_map(cube_a_dict, {"array": h.astype(np.float64) * 1e-9}))
    # Integers are metres: -50 .. 48 m is larger than the patch, refused.
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(path)
    assert any(p["path"] == "fingers[0].texture.heights.file" and "larger than the patch" in p["message"]
               for p in e.value.problems)
    np.save(tmp_path / "f.npy", (h * 1e-9).astype(np.float32))
    d["fingers"][0]["texture"]["heights"]["file"] = "f.npy"
    path.write_text(json.dumps(d))
    got = grasp.Scene(path).texture_heights_m("f1")
    # float32 keeps 24 bits: a relative 6e-8 of the largest height, 5e-8 m.
    np.testing.assert_allclose(got, scene.texture_heights_m("f1"), rtol=0, atol=1e-7 * 5e-8)


@pytest.mark.parametrize(
    "heights, path, words",
    [
        ({"array": np.zeros(5)}, "fingers[0].texture.heights.array", "not a 2-D one"),
        ({"array": [["a", "b"]]}, "fingers[0].texture.heights.array", "not an array of numbers"),
        ({"array": np.zeros((0, 3))}, "fingers[0].texture.heights.array", "0 x 3"),
        ({"array": np.zeros((9, 11)), "file": "h.npy"}, "fingers[0].texture.heights", "both file and array"),
        ({"array": np.zeros((3, 3))}, "fingers[0].texture.heights.file", "reach +-0.004 m"),
        ({"array": np.full((9, 11), np.nan)}, "fingers[0].texture.heights.file", "row 0, column 0"),
    ],
)
def test_bad_arrays_are_scene_errors_naming_the_path(cube_a_dict, heights, path, words):
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(with_map(cube_a_dict, heights))
    assert any(p["path"] == path and words in p["message"] and p["fix"] for p in e.value.problems), e.value.problems


def test_a_complex_array_is_refused_not_stripped_of_its_imaginary_parts(cube_a_dict):
    """As the CLI refuses a complex .npy: converting would drop the imaginary parts."""
    for a in [heights_9_by_11() * (1 + 1j), heights_9_by_11().astype(complex), [[1e-6 + 0j] * 11] * 9]:
        with pytest.raises(grasp.SceneError) as e:
            grasp.Scene(with_map(json.loads(json.dumps(cube_a_dict)), {"array": a}))
        (p,) = [p for p in e.value.problems if p["path"] == "fingers[0].texture.heights.array"]
        assert "complex" in p["message"] and "a.real" in p["fix"], p


def test_a_masked_array_s_masked_heights_are_refused_not_used(cube_a_dict):
    """A masked height would be read as the value under the mask; a mask with nothing masked
    changes nothing."""
    h = heights_9_by_11()
    masked = np.ma.masked_array(h, mask=np.zeros_like(h, dtype=bool))
    masked.mask[4, 5] = True
    with pytest.raises(grasp.SceneError) as e:
        grasp.Scene(with_map(json.loads(json.dumps(cube_a_dict)), {"array": masked}))
    (p,) = [p for p in e.value.problems if p["path"] == "fingers[0].texture.heights.array"]
    assert "masked heights" in p["message"] and "filled" in p["fix"], p
    plain = grasp.Scene(with_map(json.loads(json.dumps(cube_a_dict)), {"array": h}))
    for unmasked in [np.ma.masked_array(h), np.ma.masked_array(h, mask=np.zeros_like(h, dtype=bool))]:
        got = grasp.Scene(with_map(json.loads(json.dumps(cube_a_dict)), {"array": unmasked}))
        np.testing.assert_array_equal(got.texture_heights_m("f1"), plain.texture_heights_m("f1"))


def test_bad_files_are_scene_errors_naming_the_path(cube_a_dict, tmp_path):
    np.save(tmp_path / "cube.npy", np.zeros((9, 11, 2)))
    (tmp_path / "header.csv").write_text("x,y\n1,2\n")
    for name, words in [("cube.npy", "not a 2-D one"), ("header.csv", "header line"), ("missing.npy", "relative to")]:
        d = with_map(json.loads(json.dumps(cube_a_dict)), {"file": name})
        path = tmp_path / "s.json"
        path.write_text(json.dumps(d))
        with pytest.raises(grasp.SceneError) as e:
            grasp.Scene(path)
        problem = [p for p in e.value.problems if p["path"] == "fingers[0].texture.heights.file"]
        assert problem and any(words in p["message"] + p["fix"] for p in problem), e.value.problems


def test_a_random_texture_is_the_same_for_its_seed(cube_a_dict):
    random = {"rms_m": 1e-6, "hurst": 0.8, "wavelengths_m": [2e-2, 5e-3], "seed": 4}
    cube_a_dict["fingers"][0]["texture"] = {"random": random}
    a = grasp.Scene(cube_a_dict).texture_heights_m("f1")
    b = grasp.Scene(cube_a_dict).texture_heights_m("f1")
    np.testing.assert_array_equal(a, b)
    cube_a_dict["fingers"][0]["texture"]["random"]["seed"] = 5
    c = grasp.Scene(cube_a_dict).texture_heights_m("f1")
    assert np.max(np.abs(a - c)) > 5e-7


def test_texture_heights_take_a_finger_s_index_as_well_as_its_name(cube_a_dict):
    scene = grasp.Scene(with_map(cube_a_dict, {"array": heights_9_by_11()}))
    by_name = scene.texture_heights_m("f1")
    np.testing.assert_array_equal(scene.texture_heights_m(0), by_name)
    np.testing.assert_array_equal(scene.texture_heights_m(-len(scene.finger_names)), by_name)
    assert scene.texture_heights_m(1) is None
    with pytest.raises(ValueError, match="indices 0 to"):
        scene.texture_heights_m(len(scene.finger_names))
    with pytest.raises(ValueError, match="f9"):
        scene.texture_heights_m("f9")
    for bad in [True, 1.5, None]:
        with pytest.raises(TypeError, match="name .str. or its index"):
            scene.texture_heights_m(bad)
