"""Meshes from numpy arrays render exactly as the same mesh from an OBJ file."""
import numpy as np
import pytest

import glint

SCENE = {
    "render": {"width": 48, "height": 36},
    "camera": {"position": [0, 2.2, 3.2], "look_at": [0, 0, 0]},
    "materials": {"clay": {"ambient": 0.1, "diffuse": [0.7, 0.5, 0.3], "specular": 0.4, "shininess": 30}},
    "lights": [{"type": "point", "position": [-2, 4, 3]}],
    "objects": [],
}


def bumpy_grid(n=6):
    """An (n+1)^2 grid over [-1, 1]^2 with a bump, in dyadic coordinates
    (exact as float32 and in the OBJ's decimal text), and its triangles."""
    xs = np.arange(n + 1) / n * 2 - 1
    xs = np.round(xs * 64) / 64
    x, z = np.meshgrid(xs, xs)
    y = np.round(0.5 * np.exp(-3 * (x * x + z * z)) * 64) / 64
    vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    tris = []
    for r in range(n):
        for c in range(n):
            a, b, d, e = r * (n + 1) + c, r * (n + 1) + c + 1, (r + 1) * (n + 1) + c, (r + 1) * (n + 1) + c + 1
            tris += [[a, d, b], [b, d, e]]
    uvs = np.stack([(x.ravel() + 1) / 2, (z.ravel() + 1) / 2], axis=1)
    return vertices, np.array(tris), uvs


def write_obj(path, vertices, triangles, uvs=None, normals=None):
    with open(path, "w") as f:
        for v in vertices:
            f.write("v %r %r %r\n" % tuple(float(c) for c in v))
        for t in uvs if uvs is not None else []:
            f.write("vt %r %r\n" % tuple(float(c) for c in t))
        for n in normals if normals is not None else []:
            f.write("vn %r %r %r\n" % tuple(float(c) for c in n))
        for t in triangles + 1:
            if uvs is not None and normals is not None:
                f.write("f " + " ".join(f"{i}/{i}/{i}" for i in t) + "\n")
            elif uvs is not None:
                f.write("f " + " ".join(f"{i}/{i}" for i in t) + "\n")
            else:
                f.write("f %d %d %d\n" % tuple(t))


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


@pytest.mark.parametrize("vdtype,idtype", [(np.float32, np.int32), (np.float64, np.int64)])
@pytest.mark.parametrize("smooth", [True, False])
def test_mesh_from_arrays_renders_as_the_same_obj(tmp_path, vdtype, idtype, smooth):
    vertices, triangles, _ = bumpy_grid()
    write_obj(tmp_path / "grid.obj", vertices, triangles)
    from_file = glint.Scene.from_dict(SCENE, base_dir=tmp_path)
    from_file.objects.append({"type": "mesh", "file": "grid.obj", "material": "clay", "smooth": smooth})
    from_arrays = glint.Scene.from_dict(SCENE)
    obj = from_arrays.add_mesh(vertices.astype(vdtype), triangles.astype(idtype), material="clay", smooth=smooth)
    assert obj.type == "mesh" and len(obj.vertices) == len(vertices)
    a, b = glint.render(from_file).image, glint.render(from_arrays).image
    assert a.max() > 0.1
    assert np.array_equal(bits(a), bits(b))


def test_normals_and_uvs_from_arrays_are_those_of_the_obj(tmp_path):
    vertices, triangles, uvs = bumpy_grid()
    normals = vertices * [0.5, 1, 0.5] + [0, 1, 0]  # any non-zero field: glint normalizes it, as for a file
    normals = np.round(normals * 64) / 64
    write_obj(tmp_path / "grid.obj", vertices, triangles, uvs, normals)
    checker = {"checker": {"even": [0.9, 0.9, 0.9], "odd": [0.1, 0.2, 0.6], "scale": 4}}
    scene = dict(SCENE, materials={"clay": {"diffuse": checker, "specular": 0.3, "shininess": 20}})
    from_file = glint.Scene.from_dict(scene, base_dir=tmp_path)
    from_file.objects.append({"type": "mesh", "file": "grid.obj", "material": "clay"})
    from_arrays = glint.Scene.from_dict(scene)
    from_arrays.add_mesh(vertices, triangles, normals=normals, uvs=uvs, material="clay")
    a, b = glint.render(from_file).image, glint.render(from_arrays).image
    assert np.array_equal(bits(a), bits(b))
    # The checker shows: the UVs are used.
    assert len(np.unique(a.round(2).reshape(-1, 3), axis=0)) > 10


def test_a_transformed_mesh_and_its_round_trip(tmp_path):
    vertices, triangles, _ = bumpy_grid(3)
    scene = glint.Scene.from_dict(SCENE)
    scene.add_mesh(vertices, triangles, material="clay", transform={"scale": 0.5, "translate": [0.2, 0, 0]},
                   name="grid")
    again = glint.Scene.from_dict(scene.to_dict())
    assert np.array_equal(bits(glint.render(scene).image), bits(glint.render(again).image))
    assert scene.objects[0].name == "grid" and scene.objects[0].transform["scale"] == 0.5


def test_a_degenerate_triangle_is_dropped_with_a_warning():
    scene = glint.Scene.from_dict(SCENE)
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1], [2, 0, 0]], np.float32)
    scene.add_mesh(v, np.array([[0, 2, 1], [0, 1, 3]]))
    assert scene.warnings == ["objects[0]: dropped 1 degenerate triangle"]
