# The worked example of docs/python.md; it writes docs/img/python-example.png.
# Run from the repository: PYTHONPATH=build/python /usr/bin/python3 docs/python-example.py
import numpy as np

import glint

scene = glint.load("scenes/showcase.json")
scene.render_settings.width, scene.render_settings.height = 640, 360
print(scene)

# Edit: every assignment is checked by glint's loader.
scene.materials["red"].shininess = 400          # a tighter highlight
scene.materials["red"].specular = 1.0
scene.lights[1].position = (-3, 7, 6)            # move the key light
try:
    scene.materials["gold"].shininess = -1
except glint.SceneError as e:
    print("refused:", e.path, "->", e.message)

# A mesh from numpy arrays: a rippled disc in front of the spheres.
n = 48
r, a = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 2 * np.pi, 4 * n, endpoint=False))
x, z = r * np.cos(a), r * np.sin(a)
y = 0.08 * np.cos(10 * r) * (1 - r)
vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3)
grid = np.arange(vertices.shape[0]).reshape(4 * n, n)
nxt = np.roll(grid, -1, axis=0)
quads = np.stack([grid[:, :-1], grid[:, 1:], nxt[:, 1:], nxt[:, :-1]], axis=-1).reshape(-1, 4)
triangles = np.concatenate([quads[:, [0, 2, 1]], quads[:, [0, 3, 2]]])
scene.materials["water"] = {"ambient": 0.02, "diffuse": [0.1, 0.35, 0.4], "specular": 0.8, "shininess": 200,
                            "reflectivity": 0.3}
scene.add_mesh(vertices, triangles, material="water", transform={"scale": 1.2, "translate": [2.6, 0.05, 2.2]})
print(scene.warnings)  # the disc's centre triangles have zero area: dropped, with a warning

r = glint.render(scene, passes=["diffuse", "specular"])
print(r)
print({k: r.stats[k] for k in ("camera_rays", "shadow_rays", "builds")})

# The image and its diffuse pass side by side, as one picture.
glint.write_image(np.hstack([r.image, r.passes["diffuse"]]), "docs/img/python-example.png")

# A material edit re-renders without rebuilding the geometry.
scene.materials["water"].diffuse = (0.4, 0.15, 0.1)
print("builds after the edit:", glint.render(scene, width=64, height=36).stats["builds"])

# What is behind one pixel (the red sphere's highlight).
e = glint.explain(scene, 290, 170)
print(e["color"], [k for k in e])
