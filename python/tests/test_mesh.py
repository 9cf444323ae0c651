"""Meshes from numpy arrays render exactly as the same mesh from an OBJ file,
are copied once, and are written out whole."""
import ctypes
import gc
import json
import tracemalloc

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


# --- one copy ---------------------------------------------------------------

class _MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks",
                 "keepcost")]


def heap_in_use():
    """Bytes malloc has handed out and not had back (glibc's mallinfo2): what
    the process holds, exactly, whatever the allocator keeps cached."""
    try:
        mallinfo2 = ctypes.CDLL(None).mallinfo2
    except AttributeError:
        pytest.skip("needs glibc's mallinfo2")
    mallinfo2.restype = _MallInfo2
    gc.collect()
    m = mallinfo2()
    return m.uordblks + m.hblkhd


def big_grid(n):
    """An (n+1)^2-vertex grid of 2 n^2 triangles, none degenerate."""
    xs = np.arange(n + 1, dtype=np.float64) / n
    x, z = np.meshgrid(xs, xs)
    vertices = np.stack([x.ravel(), 0.1 * np.sin(7 * x.ravel()) * z.ravel(), z.ravel()], axis=1)
    a = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    triangles = np.concatenate([np.stack([a, a + n + 1, a + 1], 1), np.stack([a + 1, a + n + 1, a + n + 2], 1)])
    return vertices, triangles


def write_ply(path, vertices, triangles):
    """A binary PLY of the mesh: the same mesh, read from a file."""
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
                 "property float x\nproperty float y\nproperty float z\n"
                 f"element face {len(triangles)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        f.write(vertices.astype("<f4").tobytes())
        faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<i4", 3)])
        faces["n"], faces["i"] = 3, triangles
        f.write(faces.tobytes())


@pytest.mark.parametrize("kind", ["float32/int32", "float64/int64", "strided float64/int64"])
def test_add_mesh_keeps_exactly_one_copy_of_the_arrays(tmp_path, kind):
    """A mesh from arrays costs what the same mesh from a file costs (the
    renderer's mesh) plus ONE copy of the arrays in glint's own types (float32
    vertices, uint32 indices): 12 bytes a vertex and 12 a triangle, whatever
    the dtypes given. Two copies (or the arrays kept as JSON, as before) would
    cost 2x (or ~15x) that. Later edits and renders add nothing, and no numpy
    temporary is made on the way (tracemalloc sees numpy's allocations)."""
    vertices, triangles = big_grid(300)
    if kind == "float32/int32":
        vertices, triangles = vertices.astype(np.float32), triangles.astype(np.int32)
    elif kind.startswith("strided"):  # views with gaps: read through their strides
        wide = np.zeros((len(vertices), 6))
        wide[:, ::2] = vertices
        vertices = wide[:, ::2]
        triangles = np.asfortranarray(triangles)
        assert not vertices.flags.c_contiguous and not triangles.flags.c_contiguous
    one_copy = 12 * len(vertices) + 12 * len(triangles)
    write_ply(tmp_path / "grid.ply", vertices, triangles)

    from_file = glint.Scene.from_dict(SCENE, base_dir=tmp_path)
    before = heap_in_use()
    from_file.objects.append({"type": "mesh", "file": "grid.ply", "material": "clay", "smooth": False})
    file_cost = heap_in_use() - before

    from_arrays = glint.Scene.from_dict(SCENE)
    before = heap_in_use()
    tracemalloc.start()
    from_arrays.add_mesh(vertices, triangles, material="clay", smooth=False)
    numpy_peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    arrays_cost = heap_in_use() - before

    assert file_cost > one_copy  # the renderer's mesh: positions, indices, materials
    assert abs((arrays_cost - file_cost) - one_copy) < 0.05 * one_copy, (arrays_cost, file_cost, one_copy)
    assert numpy_peak < 0.01 * one_copy, numpy_peak

    # Edits re-check the scene from the kept arrays without copying them again.
    steady = heap_in_use()
    for s in (10, 20, 30):
        from_arrays.materials["clay"].shininess = s
        from_arrays.lights[0].position = (-2, 4, s / 10)
    assert abs(heap_in_use() - steady) < 0.02 * one_copy
    # And the two are the same mesh.
    a = glint.render(from_file, width=24, height=18).image
    b = glint.render(from_arrays, width=24, height=18).image
    from_file.materials["clay"].shininess = 30
    from_file.lights[0].position = (-2, 4, 3)
    assert np.array_equal(bits(glint.render(from_file, width=24, height=18).image),
                          bits(glint.render(from_arrays, width=24, height=18).image))
    assert a.max() > 0.1 and b.max() > 0.1


def test_the_scene_keeps_its_own_copy_and_writes_it_out_whole(tmp_path):
    vertices, triangles, uvs = bumpy_grid(4)
    normals = np.tile([0.0, 1.0, 0.0], (len(vertices), 1))
    scene = glint.Scene.from_dict(SCENE)
    obj = scene.add_mesh(vertices, triangles.astype(np.int32), normals=normals, uvs=uvs, material="clay", name="g")
    image = glint.render(scene).image
    vertices[:] = 0  # the caller's arrays are theirs: the scene does not change
    triangles[:] = 0
    assert np.array_equal(bits(glint.render(scene).image), bits(image))
    d = scene.to_dict()["objects"][0]
    assert list(d) == ["type", "material", "name", "vertices", "triangles", "normals", "uvs"]
    _, want_t, want_uv = bumpy_grid(4)
    want_v = bumpy_grid(4)[0].astype(np.float32)
    assert np.array_equal(np.array(d["vertices"]), want_v) and np.array_equal(np.array(d["triangles"]), want_t)
    assert np.array_equal(np.array(d["uvs"]), want_uv.astype(np.float32)) and np.array(d["normals"]).shape == (25, 3)
    assert obj.vertices == d["vertices"] and obj.name == "g"
    assert scene.get("objects[0].triangles[3]") == tuple(want_t[3])
    assert scene.has("objects[0].uvs") and not scene.has("objects[0].$arrays")
    assert "$arrays" not in scene.to_json() and "$arrays" not in json.dumps(obj.to_dict())
    # Coordinates are kept as float32 (what glint renders with) and written as
    # the shortest decimal that reads back to that float: 0.1, not 0.10000000149011612.
    tri = glint.Scene.from_dict(SCENE)
    tri.add_mesh(np.array([[0.1, 0, 0], [1, 0.3, 0], [0, 0, 1 / 3]]), np.array([[0, 1, 2]]), uvs=[[0.7, 0], [1, 1], [0, 1]])
    o = tri.to_dict()["objects"][0]
    assert o["vertices"] == [[0.1, 0, 0], [1, 0.3, 0], [0, 0, 0.33333334]] and o["uvs"][0] == [0.7, 0]
    assert tri.objects[0].vertices == o["vertices"] and json.loads(tri.to_json(indent=1))["objects"][0] == o
    assert np.float32(0.33333334) == np.float32(1 / 3)
    # A negative zero stays one (a sign can matter to a cross product).
    tri.add_mesh(np.array([[-0.0, 0, 0], [1, 0, 0], [0, 0, 1]], np.float32), np.array([[0, 2, 1]]))
    z = tri.to_dict()["objects"][1]["vertices"][0][0]
    assert z == 0 and np.signbit(z) and np.signbit(tri.objects[1].vertices[0][0])
    # Written out and loaded back (the CLI's view of it): the same image.
    again = glint.loads(json.dumps(scene.to_dict()))
    assert np.array_equal(bits(glint.render(again).image), bits(image))


def test_editing_a_mesh_from_arrays(small):
    v = np.array([[-1, 0.2, 0], [1, 0.2, 0], [0, 1.5, -0.5], [0, 0.2, 1]], np.float32)
    t = np.array([[0, 1, 2], [0, 3, 1]])
    obj = small.add_mesh(v, t, material="red")
    assert glint.render(small).stats["builds"] == 1
    # Keys beside the arrays: the arrays stay held (the same geometry: no
    # rebuild for another material).
    obj.material = "floor"
    r = glint.render(small)
    assert r.stats["builds"] == 1
    obj.update(name="tent", material="red")
    assert obj.name == "tent" and obj.material == "red"
    # The arrays themselves: the object becomes plain JSON, edited as such.
    small.set("objects[3].vertices[2]", [0, 1.8, -0.5])
    assert small.get("objects[3].vertices[2]") == (0, 1.8, -0.5)
    del obj.transform
    with pytest.raises(glint.SceneError) as e:
        small.set("objects[3].triangles[1]", [0, 3, 9])
    assert e.value.path == "objects[3].triangles[1][2]"
    plain = small.to_dict()["objects"][3]
    assert plain["vertices"][2] == [0, 1.8, -0.5] and plain["name"] == "tent"
    same = glint.loads(small.to_json())
    assert np.array_equal(bits(glint.render(same).image), bits(glint.render(small).image))
    del small.objects[3]
    assert len(small.objects) == 3
