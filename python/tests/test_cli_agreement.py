"""Python renders against the glint CLI: bit-identical .pfm for every
example scene, to_dict() written to a file renders the same (and validates
against docs/scene.schema.json), passes sum to the image, explain's color is
the pixel of a 1-spp render."""
import json
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import glint

W, H = 64, 40  # small: the whole suite stays quick; the same for both sides


def example_scenes(root):
    return sorted(p for p in (root / "scenes").rglob("*.json"))


def cli_render(cli, scene_path, out_dir, *extra, sized=True):
    """The CLI's image of a scene at W x H (sized) or its own size, as exact
    floats from its .pfm."""
    p = pathlib.Path(scene_path)
    animated = p.suffix == ".json" and "animation" in json.loads(p.read_text(encoding="utf-8-sig"))
    out = out_dir / ("frame_%d.pfm" if animated else "out.pfm")
    cmd = [cli, "render", str(scene_path), "-o", str(out), "--threads", "2"]
    if sized:
        cmd += ["--width", str(W), "--height", str(H)]
    if animated:
        cmd += ["--frames", "0"]
    subprocess.run(cmd + list(extra), check=True, capture_output=True)
    return glint.read_image(out_dir / ("frame_0.pfm" if animated else "out.pfm"))


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


@pytest.fixture(scope="module")
def scenes_copy(root, tmp_path_factory):
    """A copy of scenes/ (its meshes and textures too), to write to_dict()
    files beside the scenes they came from."""
    dst = tmp_path_factory.mktemp("scenes") / "scenes"
    shutil.copytree(root / "scenes", dst)
    return dst


def test_every_example_scene_renders_bit_identical_to_the_cli(root, cli, tmp_path):
    scenes = example_scenes(root)
    assert len(scenes) >= 10
    for path in scenes:
        scene = glint.load(path)
        ours = glint.render(scene, width=W, height=H).image
        out = tmp_path / path.stem
        out.mkdir()
        theirs = cli_render(cli, path, out)
        assert ours.shape == (H, W, 3), path
        assert np.array_equal(bits(ours), bits(theirs)), f"{path}: differs from the CLI"
        assert ours.max() > 0, path


def test_an_nff_scene_renders_bit_identical_to_the_cli(root, cli, tmp_path):
    path = root / "bench" / "spd" / "tetra.nff"
    if not path.exists():
        pytest.skip("no NFF scene in this tree")
    ours = glint.render(glint.load(path), spp=1).image
    theirs = cli_render(cli, path, tmp_path, "--spp", "1", sized=False)
    assert np.array_equal(bits(ours), bits(theirs)) and ours.max() > 0


@pytest.mark.parametrize("size", [(64, 40), (40, 64), (33, 1)])
def test_an_nff_view_follows_the_rendered_height_as_in_the_cli(root, cli, tmp_path, size):
    """NFF's angle spans the centers of the first and last pixel rows
    (docs/nff.md): render(width=, height=) derives fov_y for the height
    rendered, exactly as the CLI's --width/--height (a one-row image takes the
    angle edge to edge)."""
    path = root / "bench" / "spd" / "tetra.nff"
    if not path.exists():
        pytest.skip("no NFF scene in this tree")
    w, h = size
    scene = glint.load(path)
    ours = glint.render(scene, width=w, height=h, spp=1).image
    theirs = cli_render(cli, path, tmp_path, "--width", str(w), "--height", str(h), "--spp", "1", sized=False)
    assert ours.shape == (h, w, 3)
    assert np.array_equal(bits(ours), bits(theirs)) and ours.max() > 0
    # The file's fov_y kept fixed (its JSON document, as `glint convert`
    # writes it) gives another image at another height: the test tells them apart.
    converted = glint.loads(scene.to_json(), base_dir=path.parent)
    assert h == 1 or not np.array_equal(bits(glint.render(converted, width=w, height=h, spp=1).image), bits(ours))
    # Edits elsewhere keep the NFF view: it holds while the camera and the
    # height are the file's.
    name = next(iter(scene.materials))
    shininess = scene.materials[name].shininess
    scene.materials[name].shininess = 7
    scene.lights.append({"type": "point", "position": [0, 0, 9], "diffuse": 0.1})
    del scene.lights[-1]
    scene.materials[name].shininess = shininess
    assert np.array_equal(bits(glint.render(scene, width=w, height=h, spp=1).image), bits(theirs))


def test_an_nff_scene_with_its_height_edited_is_its_json_document(root, cli, tmp_path):
    """After an edit of the camera or the height the scene is its document, as
    a converted file: to_dict() written out renders with the CLI alike, at any
    --width (fov_y fixed)."""
    path = root / "bench" / "spd" / "tetra.nff"
    if not path.exists():
        pytest.skip("no NFF scene in this tree")
    scene = glint.load(path)
    scene.render_settings.height = 40
    written = tmp_path / "written.json"
    written.write_text(json.dumps(scene.to_dict()))
    theirs = cli_render(cli, written, tmp_path, "--width", "64", "--spp", "1", sized=False)
    assert np.array_equal(bits(glint.render(scene, width=64, spp=1).image), bits(theirs))


def test_to_dict_written_to_a_file_renders_identically_and_validates(root, cli, scenes_copy, tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((root / "docs" / "scene.schema.json").read_text())
    for path in example_scenes(scenes_copy):
        scene = glint.load(path)
        scene.materials  # noqa: B018 (views do not change the document)
        d = scene.to_dict()
        jsonschema.validate(d, schema)
        again = path.with_name(path.stem + ".from-python.json")
        again.write_text(json.dumps(d))
        a, b = tmp_path / (path.stem + "-a"), tmp_path / (path.stem + "-b")
        a.mkdir(), b.mkdir()
        assert np.array_equal(bits(cli_render(cli, path, a)), bits(cli_render(cli, again, b))), path


def test_an_edited_scene_written_back_renders_as_python_rendered_it(cli, small, tmp_path):
    small.materials["red"].shininess = 7
    small.lights[0].position = (2, 4, 3)
    small.add_mesh(np.array([[-2, 0.01, -1], [2, 0.01, -1], [0, 2, -2]], np.float32), np.array([[0, 1, 2]]),
                   material="floor")
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(small.to_dict()))
    assert np.array_equal(bits(glint.render(small, width=W, height=H).image), bits(cli_render(cli, path, tmp_path)))


def test_passes_sum_to_the_image(root):
    scene = glint.load(root / "scenes" / "showcase.json")
    light = ["ambient", "diffuse", "specular", "reflection", "transmission"]
    r = glint.render(scene, width=W, height=H, passes=light + ["depth", "normal"])
    total = sum(r.passes[p].astype(np.float64) for p in light)
    assert np.allclose(total, r.image, rtol=0, atol=1e-5)
    for p in light:
        assert r.passes[p].shape == (H, W, 3) and r.passes[p].dtype == np.float32
    assert r.passes["depth"].shape == (H, W)
    assert r.passes["diffuse"].max() > 0.05 and r.passes["specular"].max() > 0.05
    # depth of a pixel on the floor: positive and finite where something is hit
    assert np.isfinite(r.passes["depth"]).any() and r.passes["depth"].max() > 0


def test_explain_color_is_the_pixel_of_a_one_sample_render(root):
    scene = glint.load(root / "scenes" / "showcase.json")
    scene.render_settings.width, scene.render_settings.height = W, H
    image = glint.render(scene, spp=1).image
    for x, y in [(10, 30), (32, 20), (50, 5), (0, 0)]:
        e = glint.explain(scene, x, y)
        assert e["pixel"] == [x, y]
        assert [np.float32(c) for c in e["color"]] == list(image[y, x]), (x, y)
    assert "pixel" in glint.explain(scene, 3, 4, text=True)


def test_a_bare_mesh_file_renders_as_the_cli_frames_it(root, cli, tmp_path):
    path = root / "scenes" / "meshes" / "bunny.obj"
    ours = glint.render(glint.load(path), width=W, height=H).image
    assert np.array_equal(bits(ours), bits(cli_render(cli, path, tmp_path))) and ours.max() > 0


@pytest.mark.parametrize("ext", ["png", "jpg", "ppm", "pfm", "exr", "hdr"])
def test_save_writes_the_bytes_the_cli_writes(root, cli, tmp_path, ext):
    path = root / "scenes" / "showcase.json"
    r = glint.render(glint.load(path), width=W, height=H)
    r.save(tmp_path / f"ours.{ext}", exposure=0.5, tonemap="reinhard")
    subprocess.run([cli, "render", str(path), "-o", str(tmp_path / f"cli.{ext}"), "--width", str(W), "--height",
                    str(H), "--exposure", "0.5", "--tonemap", "reinhard"], check=True, capture_output=True)
    ours, theirs = (tmp_path / f"ours.{ext}").read_bytes(), (tmp_path / f"cli.{ext}").read_bytes()
    assert len(ours) > 100 and ours == theirs
    if ext == "png":  # and a notebook shows the PNG the CLI writes without options
        r.save(tmp_path / "plain.png")
        assert r._repr_png_() == (tmp_path / "plain.png").read_bytes()


def test_explain_is_the_clis_explain_json(root, cli):
    for path, size in [(root / "scenes" / "showcase.json", (W, H)), (root / "bench" / "spd" / "tetra.nff", (48, 30))]:
        if not path.exists():
            continue
        scene = glint.load(path)
        for x, y in [(20, 12), (0, 0), (size[0] - 1, size[1] - 1)]:
            out = subprocess.run([cli, "explain", str(path), "--pixel", str(x), str(y), "--json", "--width",
                                  str(size[0]), "--height", str(size[1])], check=True, capture_output=True, text=True)
            assert glint.explain(scene, x, y, width=size[0], height=size[1]) == json.loads(out.stdout), (path, x, y)


def test_every_example_scenes_passes_sum_to_its_image(root):
    light = ["ambient", "diffuse", "specular", "reflection", "transmission"]
    for path in example_scenes(root):
        r = glint.render(glint.load(path), width=32, height=20, passes=light)
        total = sum(r.passes[p].astype(np.float64) for p in light)
        assert np.allclose(total, r.image, rtol=1e-6, atol=1e-6), path


def test_a_scene_with_meshes_from_arrays_validates_and_renders_with_the_cli(root, cli, small, tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((root / "docs" / "scene.schema.json").read_text())
    v = np.array([[-2, 0.01, -1], [2, 0.01, -1], [0, 2, -2], [0, 0.5, 1]], np.float64) * 0.9
    t = np.array([[0, 1, 2], [0, 3, 1]], np.int64)
    small.add_mesh(v, t, normals=np.tile([0.1, 1, 0.2], (4, 1)), uvs=v[:, :2] / 2, material="floor",
                   transform={"rotate": {"axis": [0, 1, 0], "angle": 20}}, name="tent")
    small.add_mesh(v[:, [2, 1, 0]].astype(np.float32), t[:, ::-1].astype(np.int32), material="red", smooth=False)
    d = small.to_dict()
    jsonschema.validate(d, schema)
    path = tmp_path / "arrays.json"
    path.write_text(json.dumps(d))
    assert np.array_equal(bits(glint.render(small, width=W, height=H).image), bits(cli_render(cli, path, tmp_path)))
    assert glint.render(small).image.max() > 0


def test_stats_count_the_rays_the_cli_counts(root, cli, tmp_path):
    path = root / "scenes" / "showcase.json"
    r = glint.render(glint.load(path), width=W, height=H, spp=2, threads=2)
    subprocess.run([cli, "render", str(path), "-o", str(tmp_path / "x.pfm"), "--width", str(W), "--height", str(H),
                    "--spp", "2", "--threads", "2", "--stats-json", str(tmp_path / "s.json")], check=True,
                   capture_output=True)
    rays = json.loads((tmp_path / "s.json").read_text())["rays"]
    s = r.stats
    assert s["camera_rays"] == W * H * 2 == rays["camera"]
    assert (s["shadow_rays"], s["reflection_rays"], s["refraction_rays"]) == (rays["shadow"], rays["reflection"],
                                                                             rays["refraction"])
    assert s["rays"] == rays["total"] == s["camera_rays"] + s["shadow_rays"] + s["reflection_rays"] + \
        s["refraction_rays"]
    assert s["threads"] == 2 and s["complete"] is True and s["builds"] == 1
    assert s["render_seconds"] > 0 and s["build_seconds"] >= 0
