"""Edits change exactly what the formulas say; every bad input raises
(SceneError or ValueError / TypeError) naming its path, and leaves the scene
as it was."""
import copy
import json

import numpy as np
import pytest

import glint

LIGHT = ["ambient", "diffuse", "specular", "reflection", "transmission"]


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


def test_views_read_and_write_the_document(small):
    m = small.materials["red"]
    assert m.shininess == 40 and m.diffuse == (0.8, 0.2, 0.1) and m.reflectivity is None
    m.shininess = 100
    small.lights[0].position = (1, 5, 2)
    small.camera.look_at = np.array([0.0, 0.4, 0.0])
    small.render_settings.samples_per_pixel = 16
    d = small.to_dict()
    assert d["materials"]["red"]["shininess"] == 100
    assert d["lights"][0]["position"] == [1, 5, 2]
    assert d["camera"]["look_at"] == [0.0, 0.4, 0.0]
    assert d["render"]["samples_per_pixel"] == 16
    assert small.get("materials.red.shininess") == 100
    del m.shininess  # back to the default
    assert "shininess" not in small.to_dict()["materials"]["red"]
    assert list(small.materials) == ["red", "floor"] and "red" in small.materials and len(small.lights) == 1


def test_adding_and_removing_materials_lights_objects(small):
    before = small.to_dict()
    small.materials["blue"] = {"diffuse": [0.1, 0.1, 0.9]}
    small.lights.append({"type": "directional", "direction": [0, -1, -1], "diffuse": 0.3})
    small.objects.append({"type": "sphere", "center": [0, 2, -2], "radius": 0.4, "material": "blue"})
    assert len(small.lights) == 2 and len(small.objects) == 4 and small.objects[3].material == "blue"
    with pytest.raises(glint.SceneError) as e:
        del small.materials["blue"]  # still in use
    assert "blue" in str(e.value)
    del small.objects[3]
    del small.materials["blue"]
    del small.lights[1]
    assert small.to_dict() == before


def test_specular_zero_zeroes_the_specular_pass_and_nothing_else(small):
    a = glint.render(small, passes=LIGHT)
    for name in small.materials:
        small.materials[name].specular = 0
    b = glint.render(small, passes=LIGHT)
    assert a.passes["specular"].max() > 0.05
    assert not b.passes["specular"].any()
    for p in ("ambient", "diffuse"):
        assert np.array_equal(bits(a.passes[p]), bits(b.passes[p])), p


def test_doubling_the_one_lights_diffuse_doubles_the_diffuse_pass(small):
    small.lights[0].diffuse = 0.5
    a = glint.render(small, passes=LIGHT)
    small.lights[0].diffuse = 1.0
    b = glint.render(small, passes=LIGHT)
    assert a.passes["diffuse"].max() > 0.05
    assert np.array_equal(bits(2 * a.passes["diffuse"]), bits(b.passes["diffuse"]))
    assert np.array_equal(bits(a.passes["ambient"]), bits(b.passes["ambient"]))
    assert np.array_equal(bits(a.passes["specular"]), bits(b.passes["specular"]))


def test_a_material_or_light_edit_reuses_the_geometry(small):
    assert glint.render(small).stats["builds"] == 1
    small.materials["red"].diffuse = (0.1, 0.9, 0.1)
    small.lights[0].position = (2, 5, 1)
    small.camera.position = (0.5, 1, 6)
    r = glint.render(small, width=20, height=10, spp=2)
    assert r.stats["builds"] == 1
    assert np.array_equal(bits(r.image), bits(glint.render(small.copy(), width=20, height=10, spp=2).image))
    small.objects[1].radius = 0.7  # geometry: built again
    assert glint.render(small).stats["builds"] == 2


def test_update_sets_several_keys_in_one_checked_edit(small):
    small.objects[0].update(radius=0.6, material="floor")
    assert (small.objects[0].radius, small.objects[0].material) == (0.6, "floor")
    before = small.to_json()
    with pytest.raises(glint.SceneError) as e:
        small.objects[0].update(radius=0.5, center=(0, 1))  # the second is bad: neither is set
    assert e.value.path == "objects[0].center" and small.to_json() == before
    bare = glint.loads('{"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": []}')
    bare.render_settings.update(width=12, height=8)  # no "render" section yet
    assert bare.to_dict()["render"] == {"width": 12, "height": 8} and glint.render(bare).image.shape == (8, 12, 3)


def test_render_overrides_leave_the_scene_alone(small):
    r = glint.render(small, width=12, height=8, spp=2)
    assert r.image.shape == (8, 12, 3)
    assert small.render_settings.width == 40 and small.render_settings.samples_per_pixel is None


# Each: an edit (a function of the scene), the exception class, the path named.
BAD_EDITS = [
    ("negative", lambda s: setattr(s.materials["red"], "shininess", -3), glint.SceneError,
     "materials.red.shininess"),
    ("wrong type", lambda s: setattr(s.materials["red"], "shininess", "shiny"), glint.SceneError,
     "materials.red.shininess"),
    ("NaN", lambda s: setattr(s.materials["red"], "shininess", float("nan")), ValueError,
     "materials.red.shininess"),
    ("inf", lambda s: setattr(s.lights[0], "position", (1, float("inf"), 2)), ValueError, "lights[0].position"),
    ("numpy NaN", lambda s: setattr(s.camera, "look_at", np.array([0, np.nan, 0])), ValueError, "camera.look_at"),
    ("two numbers", lambda s: setattr(s.lights[0], "position", (1, 2)), glint.SceneError, "lights[0].position"),
    ("not JSON", lambda s: setattr(s.lights[0], "position", object()), TypeError, "lights[0].position"),
    ("unknown key", lambda s: setattr(s.materials["red"], "shinyness", 3), glint.SceneError,
     'materials.red: unknown key "shinyness" (did you mean "shininess"?)'),
    ("unknown material", lambda s: setattr(s.objects[0], "material", "gold"), glint.SceneError,
     "objects[0].material"),
    ("camera at look_at", lambda s: setattr(s.camera, "position", (0, 0.5, 0)), glint.SceneError, "camera"),
    ("zero width", lambda s: setattr(s.render_settings, "width", 0), glint.SceneError, "render.width"),
    ("huge width", lambda s: setattr(s.render_settings, "width", 2**40), glint.SceneError, "render.width"),
    ("fraction", lambda s: setattr(s.render_settings, "samples_per_pixel", 1.5), glint.SceneError,
     "render.samples_per_pixel"),
    ("bad light", lambda s: s.lights.append({"type": "point"}), glint.SceneError, "lights[1]"),
    ("bad object", lambda s: s.objects.append({"type": "sphere", "radius": 1}), glint.SceneError, "objects[3]"),
    ("bad material", lambda s: s.materials.__setitem__("m", {"diffuse": -1}), glint.SceneError,
     "materials.m.diffuse"),
    ("in use", lambda s: s.materials.__delitem__("floor"), glint.SceneError, "floor"),
    ("by path", lambda s: s.set("objects[0].radius", -1), glint.SceneError, "objects[0].radius"),
    ("no such object", lambda s: s.set("objects[9].radius", 1), glint.SceneError, "objects[9].radius"),
    ("render width", lambda s: glint.render(s, width=-5), ValueError, "width: must be from 1 to 1048576 (got -5)"),
    ("render huge height", lambda s: glint.render(s, height=2**40), ValueError, "height"),
    ("render width type", lambda s: glint.render(s, width=3.5), TypeError, "width"),
    ("render spp type", lambda s: glint.render(s, spp="many"), TypeError, "spp"),
    ("render pass", lambda s: glint.render(s, passes=["difuse"]), ValueError, "passes"),
    ("render accel", lambda s: glint.render(s, accel="kd-tree"), ValueError, "accel"),
    ("explain outside", lambda s: glint.explain(s, 40, 0), glint.SceneError, "40"),
    ("mesh shape", lambda s: s.add_mesh(np.zeros((3, 2)), np.array([[0, 1, 2]])), ValueError, "vertices"),
    ("mesh dtype", lambda s: s.add_mesh(np.zeros((3, 3)), np.array([[0.0, 1, 2]])), TypeError, "triangles"),
    ("mesh index", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 3]], np.int32)), ValueError, "triangles[0]"),
    ("mesh negative", lambda s: s.add_mesh(np.eye(3), np.array([[0, -1, 2]])), ValueError, "triangles[0]"),
    ("mesh NaN", lambda s: s.add_mesh(np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), np.array([[0, 1, 2]])),
     ValueError, "vertices[1]"),
    ("mesh too big for float", lambda s: s.add_mesh(np.array([[0, 0, 0], [1e300, 0, 0], [0, 1, 0]]),
                                                    np.array([[0, 1, 2]])), ValueError, "vertices[1]"),
    ("mesh normals", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 2]]), normals=np.zeros((2, 3))), ValueError,
     "normals"),
    ("mesh strings", lambda s: s.add_mesh(np.array([["a", "b", "c"]] * 3), np.array([[0, 1, 2]])), TypeError,
     "vertices"),
    ("mesh degenerate", lambda s: s.add_mesh(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]]), np.array([[0, 1, 2]])),
     glint.SceneError, "objects[3]"),
    ("mesh material", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 2]]), material="gold"), glint.SceneError,
     "objects[3].material"),
    ("mesh uvs NaN", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 2]]), uvs=np.array([[0, 0], [1, 0], [0, np.nan]])),
     ValueError, "uvs[2]: not a finite number"),
    ("mesh quads", lambda s: s.add_mesh(np.eye(4)[:, :3], np.array([[0, 1, 2, 3]])), ValueError,
     "triangles: expected shape (m, 3) with m > 0, got (1, 4)"),
    ("mesh no triangles", lambda s: s.add_mesh(np.eye(3), np.zeros((0, 3), np.int32)), ValueError, "triangles"),
    ("mesh no vertices", lambda s: s.add_mesh(np.zeros((0, 3)), np.array([[0, 1, 2]])), ValueError, "vertices"),
    ("mesh bool vertices", lambda s: s.add_mesh(np.ones((3, 3), bool), np.array([[0, 1, 2]])), TypeError, "vertices"),
    ("mesh uint64 index", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 2**63 + 5]], np.uint64)), ValueError,
     "triangles[0]: vertex index 9223372036854775813 out of range (3 vertices)"),
    ("mesh 1-d", lambda s: s.add_mesh(np.zeros(9), np.array([[0, 1, 2]])), ValueError,
     "vertices: expected shape (n, 3), got (9,)"),
    ("mesh transform", lambda s: s.add_mesh(np.eye(3), np.array([[0, 1, 2]]), transform={"scale": 0}),
     glint.SceneError, "objects[3].transform.scale"),
    ("mesh not arrays", lambda s: s.add_mesh("abc", np.array([[0, 1, 2]])), TypeError, "vertices"),
]


@pytest.mark.parametrize("what,edit,error,path", BAD_EDITS, ids=[b[0] for b in BAD_EDITS])
def test_bad_input_raises_naming_the_path_and_changes_nothing(small, what, edit, error, path):
    before = small.to_json()
    with pytest.raises(error) as e:
        edit(small)
    assert path in str(e.value), f"{what}: {e.value}"
    if isinstance(e.value, glint.SceneError) and e.value.path is not None:
        assert str(e.value).endswith(e.value.message)
    assert small.to_json() == before
    assert glint.render(small).image.max() > 0  # and it still renders


def test_scene_error_carries_the_clis_message(cli, tmp_path):
    import subprocess
    bad = tmp_path / "bad.json"
    bad.write_text('{\n  "camera": { "position": [0, 0, 5], "look_at": [0, 0, 0] },\n'
                   '  "materials": { "m": { "shininess": -1 } },\n  "objects": []\n}\n')
    with pytest.raises(glint.SceneError) as e:
        glint.load(bad)
    err = e.value
    assert (err.file, err.line, err.column, err.path) == (str(bad), 3, 38, "materials.m.shininess")
    assert err.message == "materials.m.shininess: must be > 0 (got -1)"
    out = subprocess.run([cli, "render", str(bad), "-o", str(tmp_path / "x.png")], capture_output=True, text=True)
    assert out.returncode != 0
    assert out.stderr.strip() == f"error: {err}"


def test_loading_problems_are_scene_errors(tmp_path):
    with pytest.raises(glint.SceneError) as e:
        glint.loads('{ "camera": { "position": [0, 0, 5], ', name="t.json")
    assert e.value.file == "t.json" and e.value.line == 1 and e.value.path is None
    with pytest.raises(glint.SceneError) as e:
        glint.load(tmp_path / "missing.json")
    assert "missing.json" in str(e.value)
    with pytest.raises(TypeError):
        glint.Scene.from_dict([1, 2])
    with pytest.raises(TypeError):
        glint.loads(42)


def test_from_dict_resolves_relative_files_against_base_dir(root):
    d = json.loads((root / "scenes" / "meshes" / "bunny.json").read_text())
    with pytest.raises(glint.SceneError) as e:
        glint.Scene.from_dict(d, base_dir=root)
    assert e.value.path.endswith(".file")
    scene = glint.Scene.from_dict(d, base_dir=root / "scenes" / "meshes")
    assert scene.to_dict() == d
    assert copy.deepcopy(scene).to_dict() == d


def test_an_animated_scenes_material_edit_reuses_the_geometry(root):
    """An animated scene is posed at the frame; a material, light or camera
    edit poses it again over the same acceleration structure (builds stays
    1), and renders exactly what a fresh scene with that edit renders."""
    scene = glint.load(root / "scenes" / "animation" / "rolling.json")
    first = glint.render(scene, width=48, height=27, frame=30)
    assert first.stats["builds"] == 1
    scene.materials["red"].diffuse = (0.1, 0.8, 0.2)
    scene.lights[1].position = (-3, 5, 6)
    scene.camera.fov_y = 35  # the camera's keys move its position, not its fov
    edited = glint.render(scene, width=48, height=27, frame=30)
    assert edited.stats["builds"] == 1
    fresh = glint.render(scene.copy(), width=48, height=27, frame=30)
    assert fresh.stats["builds"] == 1
    assert np.array_equal(bits(edited.image), bits(fresh.image))
    assert not np.array_equal(bits(edited.image), bits(first.image))
    # Geometry (an object, or the animation): built again.
    scene.objects[1].radius = 0.8
    assert glint.render(scene, width=48, height=27, frame=30).stats["builds"] == 2
    scene.set("animation.keys[1].objects[\"red ball\"].translate", [0, 1, 2])
    assert glint.render(scene, width=48, height=27, frame=30).stats["builds"] == 3
    # Another frame is another renderer (as glint render --frames).
    assert glint.render(scene, width=48, height=27, frame=31).stats["builds"] == 1


def test_cameras_fog_occlusion_and_solids_beyond_the_seed(small):
    """The contract's version 1 additions through the views: each edit is
    checked as the loader checks it and changes the image."""
    plain = glint.render(small).image
    small.camera.type = "fisheye"
    small.camera.fov = 200
    fish = glint.render(small).image
    assert fish.shape == plain.shape and not np.array_equal(bits(fish), bits(plain))
    with pytest.raises(glint.SceneError) as e:
        small.camera.fov = 400
    assert "camera.fov" in str(e.value) and small.camera.fov == 200
    # The fisheye's key goes before the type changes back (the loader refuses it on a perspective camera).
    del small.camera.fov
    small.camera.type = "perspective"
    assert np.array_equal(bits(glint.render(small).image), bits(plain))
    small.camera.stereo = {"eye_separation": 0.2}
    pair = glint.render(small).image
    assert pair.shape[1] == 2 * plain.shape[1]
    del small.camera.stereo
    small.render_settings.fog = {"type": "exp", "density": 0.2, "color": [0.5, 0.5, 0.5]}
    foggy = glint.render(small).image
    assert not np.array_equal(bits(foggy), bits(plain))
    with pytest.raises(glint.SceneError):
        small.render_settings.fog = {"type": "exp", "density": 0}
    del small.render_settings.fog
    small.objects.append({"type": "torus", "center": [0, 1, 0], "axis": [0, 1, 0], "major_radius": 0.6,
                          "minor_radius": 0.2, "material": "red"})
    small.objects.append({"type": "csg", "operation": "difference", "material": "red", "children": [
        {"type": "box", "min": [-0.3, 0, -0.3], "max": [0.3, 0.6, 0.3]},
        {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.25}]})
    assert small.objects[len(small.objects) - 2].major_radius == 0.6
    solids = glint.render(small).image
    assert not np.array_equal(bits(solids), bits(plain))
    with pytest.raises(glint.SceneError) as e:
        small.objects[len(small.objects) - 1].operation = "xor"
    assert "operation" in str(e.value)
