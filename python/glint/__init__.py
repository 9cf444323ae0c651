"""glint: an exact Whitted/Phong ray tracer, from Python.

    >>> import glint
    >>> scene = glint.load("scenes/showcase.json")
    >>> scene.materials["floor"].shininess = 100     # checked as the loader checks
    >>> r = glint.render(scene, width=320, height=240, passes=["specular"])
    >>> r.image.shape, r.image.dtype                 # exact linear values
    ((240, 320, 3), dtype('float32'))
    >>> r.save("out.png", exposure=0.5)

A :class:`Scene` *is* its JSON document (docs/scene-format.md): every edit,
through the typed views (``scene.materials``, ``scene.lights``,
``scene.objects``, ``scene.camera``, ``scene.render_settings``) or by path
(:meth:`Scene.set`), is checked by glint's own scene loader. A bad value
raises :class:`SceneError` naming its path, and the scene stays as it was.

:func:`render` releases the GIL, stops on Ctrl-C (KeyboardInterrupt) within
a row of pixels, and hands the image to numpy without copying it. Each
render works on a snapshot of the scene taken when it is called, so another
thread may edit the scene meanwhile: the render shows the scene as it was at
the call, never a mix. A re-render after editing materials, lights, the
camera or settings reuses the prepared geometry (``render.stats["builds"]``).

See docs/python.md for a worked example.
"""


import json as _json
import os as _os
import threading as _threading
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterator, Optional, Sequence

import numpy as _np

from . import _glint
from ._glint import CancelToken, SceneError

if TYPE_CHECKING:  # for the annotations only
    import os

__version__: str = _glint.__version__

__all__ = [
    "Scene", "SceneError", "Render", "CancelToken", "load", "loads", "render", "explain",
    "read_image", "write_image", "embree_available", "PASSES", "__version__",
    # the typed views a scene hands out (for annotations)
    "Material", "Light", "Object", "Camera", "RenderSettings", "Materials", "Lights", "Objects",
]

#: The passes :func:`render` can fill besides the image.
PASSES = ("ambient", "diffuse", "specular", "reflection", "transmission", "normal", "depth", "albedo")

#: True when this build of glint has the Embree accelerator (``accel="embree"``).
embree_available: bool = bool(_glint.embree_available)


# --------------------------------------------------------------------------
# values between Python and the scene document
# --------------------------------------------------------------------------

def _plain(value: Any) -> Any:
    """A value as plain JSON data: tuples and numpy arrays become lists,
    numpy scalars Python numbers. Anything else JSON cannot hold is a TypeError."""
    if isinstance(value, (str, bool)) or value is None:
        return value
    if isinstance(value, _np.ndarray):
        return [_plain(v) for v in value.tolist()] if value.ndim else _plain(value.item())
    if isinstance(value, _np.generic):
        return value.item()
    if isinstance(value, (int, float)):
        return value
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, _View):
        return value.to_dict()
    raise TypeError(f"{type(value).__name__} is not a scene value (expected numbers, strings, "
                    "booleans, sequences or dicts)")


def _dumps(value: Any, path: str) -> str:
    try:
        plain = _plain(value)
    except TypeError as e:
        raise TypeError(f"{path}: {e}") from None
    # NaN and infinity are not JSON: the loader would never see them.
    try:
        return _json.dumps(plain, allow_nan=False)
    except ValueError:
        raise ValueError(f"{path}: must be a finite number (got {value!r})") from None


def _from_json(text: str) -> Any:
    value = _json.loads(text)
    return tuple(value) if isinstance(value, list) and all(not isinstance(v, (list, dict)) for v in value) else value


def _key_path(parent: str, key: str) -> str:
    """parent.key, or parent["key"] for a key the plain form cannot hold."""
    if key and all(c.isalnum() or c in "_-$ " for c in key) and not key[0].isdigit():
        return f"{parent}.{key}" if parent else key
    return f"{parent}[{_json.dumps(key)}]"


# --------------------------------------------------------------------------
# typed views
# --------------------------------------------------------------------------

class _View:
    """A part of a scene (a material, a light, an object, the camera...) read
    and written by its path in the scene document. Reading a key that is not
    set gives None (glint uses its default); assigning checks the whole scene;
    ``del view.key`` returns a key to its default."""

    __slots__ = ("_scene", "_path")
    _fields: tuple = ()

    def __init__(self, scene: "Scene", path: str):
        object.__setattr__(self, "_scene", scene)
        object.__setattr__(self, "_path", path)

    def _field_path(self, key: str) -> str:
        return f"{self._path}.{key}"

    def __getattr__(self, key: str) -> Any:
        if key in type(self)._fields:
            path = self._field_path(key)
            core = self._scene._core
            return _from_json(core.get(path)) if core.has(path) else None
        raise AttributeError(f"{type(self).__name__} has no field {key!r} "
                             f"(fields: {', '.join(type(self)._fields)})")

    def __setattr__(self, key: str, value: Any) -> None:
        # A key glint does not know goes to the loader all the same: its
        # SceneError names the path and the nearest key ("did you mean").
        if key.startswith("_"):
            raise AttributeError(f"{type(self).__name__} has no field {key!r}")
        path = self._field_path(key)
        self._scene._set_json(path, _dumps(value, path))

    def __delattr__(self, key: str) -> None:
        if key not in type(self)._fields:
            raise AttributeError(key)
        path = self._field_path(key)
        if self._scene._core.has(path):
            self._scene._erase(path)

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(type(self)._fields))

    def to_dict(self) -> Dict[str, Any]:
        """This part of the document as a dict (a copy)."""
        return _json.loads(self._scene._core.get(self._path))

    def update(self, **values: Any) -> None:
        """Sets several fields at once, checked together (one edit): all or none."""
        self._scene._core.update_json(self._path, _dumps(values, self._path))

    def __eq__(self, other: object) -> bool:
        if isinstance(other, _View):
            return self.to_dict() == other.to_dict()
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        try:
            return f"<glint.{type(self).__name__} {self._path}: {self._scene._core.get(self._path)}>"
        except SceneError:
            return f"<glint.{type(self).__name__} {self._path}: (gone)>"


class Material(_View):
    """A material of ``scene.materials``: Phong coefficients (a number is a
    gray color), ``shininess`` (> 0), ``reflectivity``, ``transparency``,
    ``ior`` and ``fresnel``. A color may also be a texture dict (see
    docs/scene-format.md)."""
    __slots__ = ()
    _fields = ("ambient", "diffuse", "specular", "shininess", "reflectivity", "transparency", "ior", "fresnel")


class Light(_View):
    """A light of ``scene.lights``: ``type`` ("ambient", "point",
    "directional", "spot", "area") and the keys that type takes."""
    __slots__ = ()
    _fields = ("type", "name", "ambient", "diffuse", "specular", "color", "position", "direction", "attenuation",
               "cutoff", "falloff", "corner", "edge_u", "edge_v", "samples", "occlusion")


class Object(_View):
    """An object of ``scene.objects``: ``type`` ("sphere", "plane",
    "triangle", "box", "mesh", "cylinder", "cone", "disk", "polygon",
    "torus", "csg"), ``material``, ``transform``, ``name`` and the shape's
    keys."""
    __slots__ = ()
    _fields = ("type", "material", "transform", "name", "center", "radius", "point", "normal", "vertices", "uv",
               "min", "max", "file", "smooth", "triangles", "normals", "uvs", "base", "apex", "base_radius",
               "apex_radius", "caps", "inner_radius", "axis", "major_radius", "minor_radius", "operation",
               "children")


class Camera(_View):
    """``scene.camera``: ``position``, ``look_at``, ``up``, ``fov_y``
    (degrees), ``type`` ("perspective", "orthographic", "fisheye",
    "equirectangular"), ``view_height``, ``fov`` (fisheye), ``aperture`` and
    ``focus_distance`` (thin lens), ``stereo``."""
    __slots__ = ()
    _fields = ("type", "position", "look_at", "up", "fov_y", "view_height", "fov", "aperture", "focus_distance",
               "stereo")


class RenderSettings(_View):
    """``scene.render_settings`` (the document's "render" section):
    ``width``, ``height``, ``samples_per_pixel``, ``max_depth``,
    ``background``, ``epsilon``, ``shading_model``, ``pixel_filter``,
    ``adaptive``, ``fog``, ``environment``."""
    __slots__ = ()
    _fields = ("width", "height", "samples_per_pixel", "max_depth", "shading_model", "background", "epsilon",
               "pixel_filter", "adaptive", "fog", "environment")


class Materials:
    """``scene.materials``: a dict-like view, by name.

    ``scene.materials["gold"]`` is a :class:`Material`;
    ``scene.materials["gold"] = {"diffuse": [0.8, 0.6, 0.2]}`` adds or
    replaces one; ``del scene.materials["gold"]`` removes one no object uses.
    """
    __slots__ = ("_scene",)

    def __init__(self, scene: "Scene"):
        self._scene = scene

    def _path(self, name: str) -> str:
        if not isinstance(name, str):
            raise TypeError(f"material names are strings, not {type(name).__name__}")
        return _key_path("materials", name)

    def __getitem__(self, name: str) -> Material:
        if name not in self:
            raise KeyError(name)
        return Material(self._scene, self._path(name))

    def __setitem__(self, name: str, material: Any) -> None:
        path = self._path(name)
        self._scene._set_json(path, _dumps(material, path))

    def __delitem__(self, name: str) -> None:
        if name not in self:
            raise KeyError(name)
        self._scene._erase(self._path(name))

    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and name in self._scene._core.material_names

    def __iter__(self) -> Iterator[str]:
        return iter(self._scene._core.material_names)

    def __len__(self) -> int:
        return len(self._scene._core.material_names)

    def keys(self):
        """The material names, in the document's order."""
        return list(self)

    def items(self):
        """(name, Material) pairs, in the document's order."""
        return [(n, self[n]) for n in self]

    def __repr__(self) -> str:
        return f"<glint.Materials {list(self)}>"


class _Items:
    """A list-like view of "lights" or "objects", by index."""
    __slots__ = ("_scene",)
    _key = ""
    _item: type = _View

    def __init__(self, scene: "Scene"):
        self._scene = scene

    def __len__(self) -> int:
        core = self._scene._core
        return core.light_count if self._key == "lights" else core.object_count

    def _index(self, i: int) -> int:
        if not isinstance(i, (int, _np.integer)):
            raise TypeError(f"{self._key} are indexed by integers, not {type(i).__name__}")
        n = len(self)
        j = int(i) + n if i < 0 else int(i)
        if not 0 <= j < n:
            raise IndexError(f"{self._key}[{i}]: there are {n}")
        return j

    def __getitem__(self, i: int):
        return self._item(self._scene, f"{self._key}[{self._index(i)}]")

    def __setitem__(self, i: int, value: Any) -> None:
        path = f"{self._key}[{self._index(i)}]"
        self._scene._set_json(path, _dumps(value, path))

    def __delitem__(self, i: int) -> None:
        self._scene._erase(f"{self._key}[{self._index(i)}]")

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def append(self, item: Any) -> None:
        """Adds one (a dict as in the scene file), checked as the loader does."""
        self._scene._append_json(self._key, _dumps(item, f"{self._key}[{len(self)}]"))

    def __repr__(self) -> str:
        return f"<glint.{type(self).__name__} {len(self)}>"


class Lights(_Items):
    """``scene.lights``: ``scene.lights[0].position = (1, 5, 2)``,
    ``scene.lights.append({"type": "point", "position": [0, 4, 0]})``,
    ``del scene.lights[1]``."""
    __slots__ = ()
    _key = "lights"
    _item = Light


class Objects(_Items):
    """``scene.objects``: ``scene.objects[2].radius = 0.7``,
    ``scene.objects.append({"type": "sphere", ...})``, ``del scene.objects[0]``;
    meshes from arrays with :meth:`Scene.add_mesh`."""
    __slots__ = ()
    _key = "objects"
    _item = Object


# --------------------------------------------------------------------------
# the scene
# --------------------------------------------------------------------------

class Scene:
    """A glint scene: its JSON document, checked by glint's loader.

    Make one with :func:`load`, :func:`loads` or :meth:`Scene.from_dict`.
    Edit it through ``materials``, ``lights``, ``objects``, ``camera`` and
    ``render_settings`` or by path with :meth:`get` / :meth:`set`; every
    edit is checked as the scene file would be, and a refused one raises
    :class:`SceneError` (naming the path) and changes nothing.

    Threads: edits are atomic (each replaces the scene's state as a whole),
    and a render works on a snapshot taken when it starts, so editing a scene
    while another thread renders it is safe; that render shows the scene as it
    was when the render was called.
    """

    __slots__ = ("_core", "_lock", "_renderer", "_renderer_key", "__weakref__")

    def __init__(self, _core: "_glint.Scene"):
        if not isinstance(_core, _glint.Scene):
            raise TypeError("make a Scene with glint.load, glint.loads or glint.Scene.from_dict")
        self._core = _core
        self._lock = _threading.Lock()  # one render or explain of this scene at a time
        self._renderer: Optional[_glint.Renderer] = None
        self._renderer_key: Optional[tuple] = None  # (accel, frame) it was made for

    # -- making and writing ------------------------------------------------
    @classmethod
    def from_dict(cls, d: Dict[str, Any], base_dir: "str | os.PathLike[str] | None" = None,
                  name: str = "<dict>") -> "Scene":
        """A scene from ``d``, a dict shaped as the scene file
        (docs/scene-format.md; tuples and numpy arrays may stand for lists).
        Relative mesh and texture paths resolve against ``base_dir``
        (default: the current directory); ``name`` is what error messages
        call it."""
        if not isinstance(d, dict):
            raise TypeError(f"Scene.from_dict: expected a dict, got {type(d).__name__}")
        return loads(_dumps(d, "scene"), base_dir=base_dir, name=name)

    def to_dict(self) -> Dict[str, Any]:
        """The scene's document as a new dict. ``json.dump`` it to a file and
        that file renders with the glint CLI exactly as this scene does
        (relative paths as seen from :attr:`base_dir`)."""
        return _json.loads(self._core.to_json(-1))

    def to_json(self, indent: int = 2) -> str:
        """The scene's document as JSON text (what :meth:`to_dict` holds)."""
        return self._core.to_json(indent)

    def copy(self) -> "Scene":
        """An independent copy (cheap: it shares state until edited)."""
        return Scene(self._core.copy())

    __copy__ = copy

    def __deepcopy__(self, memo: dict) -> "Scene":
        return self.copy()

    @property
    def base_dir(self) -> str:
        """The folder relative mesh and texture paths resolve against."""
        return self._core.base_dir

    @property
    def name(self) -> str:
        """The file or name the scene came from, as error messages give it."""
        return self._core.name

    @property
    def warnings(self) -> list:
        """The loader's warnings (missing .mtl, dropped degenerate triangles...)."""
        return list(self._core.warnings)

    @property
    def width(self) -> int:
        """The image width the scene renders at (its render.width, or the default)."""
        return self._core.width

    @property
    def height(self) -> int:
        """The image height the scene renders at (its render.height, or the default)."""
        return self._core.height

    # -- typed views -------------------------------------------------------
    @property
    def materials(self) -> Materials:
        """The materials, by name (dict-like)."""
        return Materials(self)

    @property
    def lights(self) -> Lights:
        """The lights, by index (list-like)."""
        return Lights(self)

    @property
    def objects(self) -> Objects:
        """The objects, by index (list-like)."""
        return Objects(self)

    @property
    def camera(self) -> Camera:
        """The camera."""
        return Camera(self, "camera")

    @property
    def render_settings(self) -> RenderSettings:
        """The document's "render" section: size, samples, depth, background..."""
        return RenderSettings(self, "render")

    # -- by path -----------------------------------------------------------
    def get(self, path: str) -> Any:
        """The value at ``path`` ("materials.floor.shininess", "lights[0].position",
        'materials["my.gold"].diffuse'); SceneError when it is not set."""
        return _from_json(self._core.get(path))

    def has(self, path: str) -> bool:
        """Whether ``path`` is set in the document."""
        return self._core.has(path)

    def set(self, path: str, value: Any) -> None:
        """Sets the value at ``path`` (adding a missing last key), checked by
        the loader: SceneError naming the path, and no change, if refused."""
        self._set_json(path, _dumps(value, path))

    def erase(self, path: str) -> None:
        """Removes a key (back to its default), a material, a light or an object."""
        self._erase(path)

    def _set_json(self, path: str, text: str) -> None:
        self._core.set_json(path, text)

    def _erase(self, path: str) -> None:
        self._core.erase(path)

    def _append_json(self, path: str, text: str) -> None:
        self._core.append_json(path, text)

    # -- meshes from arrays ------------------------------------------------
    def add_mesh(self, vertices: Any, triangles: Any, normals: Any = None, uvs: Any = None, *,
                 material: Optional[str] = None, transform: Optional[Dict[str, Any]] = None,
                 smooth: bool = True, name: Optional[str] = None) -> Object:
        """Adds a triangle mesh given as arrays and returns its object.

        vertices: (n, 3) float32 or float64; triangles: (m, 3) int32 or int64
        vertex indices (0-based); normals: optional (n, 3) per-vertex normals
        (else computed, angle-weighted, as for a mesh file); uvs: optional
        (n, 2) per-vertex texture coordinates. Any strides; other integer or
        float dtypes are accepted too (converted first). Shapes, dtypes,
        index range and finite values (that fit a float32) are checked:
        ValueError / TypeError naming the argument and row, e.g.
        ``triangles[4]: vertex index 12 out of range (12 vertices)``.

        material: a material name of the scene (else glint's default
        material); transform: the object's transform, a dict as in the scene
        file ({"scale": .., "rotate": .., "translate": ..}); smooth: False for
        flat shading (face normals); name: the object's name (animation keys
        name objects by it). These are checked as the loader checks an object
        (SceneError naming ``objects[n]...``).

        Each array is read once, straight into the scene's own float32 /
        uint32 arrays (the one copy: later edits of the scene and renders do
        not copy it again, and changing your arrays afterwards does not change
        the scene). :meth:`to_dict` writes the mesh out as an inline mesh
        (docs/scene-format.md), so it stays one self-contained scene that the
        CLI renders identically. Zero-area triangles are dropped with a
        warning, as in a mesh file.
        """
        obj: Dict[str, Any] = {"type": "mesh"}
        if material is not None:
            obj["material"] = material
        if transform is not None:
            obj["transform"] = transform
        if not smooth:
            obj["smooth"] = False
        if name is not None:
            obj["name"] = name
        self._core.add_mesh(_dumps(obj, "objects"), vertices, triangles, normals, uvs)
        return self.objects[-1]

    # -- rendering ---------------------------------------------------------
    def _prepared(self, core: "_glint.Scene", threads: int, accel: str, frame: int) -> "_glint.Renderer":
        """This scene's renderer, updated to `core` (a private snapshot): the
        acceleration structure is rebuilt only when the geometry changed.
        Called with self._lock held."""
        if self._renderer is None or self._renderer_key != (accel, frame):
            self._renderer = None  # free the old one first
            self._renderer = _glint.Renderer(core, threads, accel, frame)
            self._renderer_key = (accel, frame)
        else:
            self._renderer.update(core)
        return self._renderer

    def __repr__(self) -> str:
        c = self._core
        return (f"<glint.Scene {c.name!r}: {c.width}x{c.height}, {c.object_count} objects, "
                f"{c.light_count} lights, {len(c.material_names)} materials>")


def load(path: "str | os.PathLike[str]") -> Scene:
    """Loads the scene file at ``path``: any file glint renders, by its
    extension: a JSON scene (docs/scene-format.md), an NFF file (docs/nff.md)
    or a bare mesh file (.obj .ply .gltf .glb, framed as ``glint render``
    frames it). Relative mesh and texture paths resolve against the file's
    folder. Raises SceneError with the file, line and column of the problem,
    as the CLI reports it."""
    return Scene(_glint.Scene.load(_os.fspath(path)))


def loads(text: str, base_dir: "str | os.PathLike[str] | None" = None, name: str = "<string>") -> Scene:
    """A scene from ``text``, scene JSON (str or UTF-8 bytes). Relative mesh
    and texture paths resolve against ``base_dir`` (default: the current
    directory); ``name`` is what error messages call the text."""
    if isinstance(text, (bytes, bytearray)):
        text = text.decode("utf-8")
    if not isinstance(text, str):
        raise TypeError(f"loads: expected JSON text, got {type(text).__name__}")
    return Scene(_glint.Scene.from_json(text, _os.fspath(base_dir) if base_dir is not None else "", name))


# --------------------------------------------------------------------------
# rendering
# --------------------------------------------------------------------------

class Render:
    """What :func:`render` returns.

    image:  float32 array (height, width, 3) of exact linear RGB, row 0 at the
            top; its buffer is the renderer's own (no copy was made).
    passes: dict of float32 arrays by pass name, (height, width, 3) each;
            "depth" is (height, width).
    stats:  dict: camera_rays, shadow_rays, reflection_rays, refraction_rays,
            rays, render_seconds, build_seconds, builds (acceleration
            structures this scene's renderer has built), threads, complete.
    """

    __slots__ = ("image", "passes", "stats", "_buffer_address")

    def __init__(self, image: _np.ndarray, passes: Dict[str, _np.ndarray], stats: Dict[str, Any],
                 buffer_address: int = 0):
        self.image = image
        self.passes = passes
        self.stats = stats
        self._buffer_address = buffer_address

    def save(self, path: "str | os.PathLike[str]", exposure: float = 0.0, tonemap: str = "clamp",
             pass_name: Optional[str] = None) -> None:
        """Writes the image (or the pass ``pass_name``) to ``path`` as the CLI
        writes it, byte for byte: the format by the extension (.png .jpg .ppm:
        8-bit, sRGB, after ``exposure`` (EV) and ``tonemap`` ("clamp",
        "reinhard", "aces"); .pfm .exr .hdr: the exact linear values). A depth
        pass is written in all three channels. Atomic: an existing file is
        replaced only by a complete new one."""
        image = self.image if pass_name is None else self.passes[pass_name]
        if image.ndim == 2:
            image = _np.repeat(image[:, :, None], 3, axis=2)
        _glint.write_image(image, _os.fspath(path), float(exposure), tonemap)

    def _repr_png_(self) -> bytes:
        """The image as PNG bytes (clamped, sRGB): how notebooks show a Render."""
        return _glint.encode_image(self.image, "png")

    def __repr__(self) -> str:
        h, w = self.image.shape[:2]
        return (f"<glint.Render {w}x{h}, passes {sorted(self.passes)}, "
                f"{self.stats['rays']} rays in {self.stats['render_seconds']:.3f} s>")


_MAX_SIDE = 1 << 20  # the loader's limit on render.width and render.height


def _int_arg(value: Any, name: str, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name}: expected an int, got {type(value).__name__}")
    if not lo <= value <= hi:
        raise ValueError(f"{name}: must be from {lo} to {hi} (got {value})")
    return int(value)


def _snapshot(scene: Scene, spp) -> "_glint.Scene":
    """A private snapshot of the scene (the caller's scene is untouched), with
    ``spp`` set as the CLI's --spp sets it (adaptive sampling, if any, kept)."""
    core = scene._core.copy()
    if spp is not None:
        if isinstance(spp, bool) or not isinstance(spp, (int, _np.integer)):
            raise TypeError(f"spp: expected an int, got {type(spp).__name__}")
        core.set_json("render.samples_per_pixel", str(int(spp)))
    return core


def render(scene: Scene, *, width: Optional[int] = None, height: Optional[int] = None,
           spp: Optional[int] = None, threads: int = 0, accel: str = "bvh", frame: int = 0,
           passes: Sequence[str] = (), progress: Optional[Callable[[float], Any]] = None,
           cancel: Optional[CancelToken] = None) -> Render:
    """Renders a scene and returns a :class:`Render`.

    width, height: render at this size instead of the scene's (for this
        render only; the scene is not changed), as ``glint render --width
        --height`` does: the camera's aspect follows, and an NFF scene's view
        keeps following its rows (docs/nff.md).
    spp: samples per pixel for this render, as ``glint render --spp``.
    threads: worker threads, 0 for all cores; the image is bit-identical for
        any count.
    accel: "bvh" (glint's own) or "embree" (when :data:`embree_available`).
    frame: of an animated scene, the frame to render (as ``glint render
        --frames N``); a still scene has frame 0 only.
    passes: any of :data:`PASSES`, filled besides the image; the light
        passes ambient + diffuse + specular + reflection + transmission sum to
        the image.
    progress: called on this thread with the fraction done (0 first, then
        about ten times a second, 1 at the end); an exception it raises
        stops the render and is raised here.
    cancel: a :class:`CancelToken`; another thread calling ``cancel.cancel()``
        stops the render within a row of pixels, and what was rendered is
        returned (``stats["complete"]`` False, the rest of the image 0).

    The GIL is released while the pixels are rendered. Ctrl-C stops the
    render within a row of pixels and raises KeyboardInterrupt. The render
    uses a snapshot of the scene taken now; edits made meanwhile (from other
    threads) apply to the next render. The scene keeps its prepared geometry
    between renders: after editing materials, lights, the camera or the
    settings nothing is rebuilt (``stats["builds"]`` stays the same).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"render: expected a glint.Scene, got {type(scene).__name__}")
    if isinstance(passes, str):
        passes = [passes]
    passes = list(passes)
    for p in passes:
        if p not in PASSES:
            raise ValueError(f"passes: unknown pass {p!r} (expected any of {', '.join(PASSES)})")
    if isinstance(threads, bool) or not isinstance(threads, (int, _np.integer)) or threads < 0:
        raise ValueError(f"threads: expected an int >= 0, got {threads!r}")
    if isinstance(frame, bool) or not isinstance(frame, (int, _np.integer)):
        raise TypeError(f"frame: expected an int, got {type(frame).__name__}")
    if cancel is not None and not isinstance(cancel, CancelToken):
        raise TypeError(f"cancel: expected a glint.CancelToken, got {type(cancel).__name__}")
    if progress is not None and not callable(progress):
        raise TypeError("progress: expected a callable taking the fraction done")
    w = _int_arg(width, "width", 1, _MAX_SIDE) if width is not None else 0
    h = _int_arg(height, "height", 1, _MAX_SIDE) if height is not None else 0
    core = _snapshot(scene, spp)
    if w or h:  # the size as --width / --height give it: the other side stays
        w, h = w or core.width, h or core.height
    with scene._lock:
        renderer = scene._prepared(core, int(threads), accel, int(frame))
        image, pass_arrays, stats, address = renderer.render(passes, int(threads), progress, cancel, w, h)
    return Render(image, dict(pass_arrays), stats, address)


def explain(scene: Scene, x: int, y: int, *, width: Optional[int] = None, height: Optional[int] = None,
            frame: int = 0, text: bool = False) -> Any:
    """What is behind pixel (x, y): its whole ray tree at one sample through
    the pixel's center, as ``glint explain --json`` prints it, as Python
    objects: a dict with "pixel" [x, y], "color" [r, g, b] (that pixel of a
    1-spp render) and "ray", the tree of rays with each term of the shading
    formula. ``text=True`` gives the CLI's text instead.

    width, height: the pixel of the view rendered at this size, as
        ``glint explain --width --height`` (and :func:`render`'s width, height).
    frame: of an animated scene, the frame (as ``--frame``).

    A pixel outside the image raises SceneError.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"explain: expected a glint.Scene, got {type(scene).__name__}")
    for n, v in (("x", x), ("y", y), ("frame", frame)):
        if isinstance(v, bool) or not isinstance(v, (int, _np.integer)):
            raise TypeError(f"{n}: expected an int, got {type(v).__name__}")
    w = _int_arg(width, "width", 1, _MAX_SIDE) if width is not None else 0
    h = _int_arg(height, "height", 1, _MAX_SIDE) if height is not None else 0
    core = scene._core.copy()
    if w or h:
        w, h = w or core.width, h or core.height
    with scene._lock:
        accel = scene._renderer_key[0] if scene._renderer_key else "bvh"
        renderer = scene._prepared(core, 0, accel, int(frame))
        if text:
            return renderer.explain_text(int(x), int(y), w, h)
        return _json.loads(renderer.explain_json(int(x), int(y), w, h))


def read_image(path: "str | os.PathLike[str]") -> _np.ndarray:
    """Reads the image file at ``path`` in any format glint writes (.png
    .jpg .ppm .pfm .exr .hdr, by its extension) as a float32 (height, width,
    3) array of linear values, row 0 at the top; 8-bit formats are
    sRGB-decoded. Raises SceneError if it cannot be read."""
    return _glint.read_image(_os.fspath(path))


def write_image(image: Any, path: "str | os.PathLike[str]", exposure: float = 0.0, tonemap: str = "clamp") -> None:
    """Writes ``image``, a float (height, width, 3) array of linear values, to
    ``path`` as the CLI writes images, the format by the extension: .png .jpg
    .ppm are 8-bit sRGB after ``exposure`` (EV: values times 2**exposure) and
    ``tonemap`` ("clamp", "reinhard" or "aces"); .pfm .exr .hdr hold the
    exact values. Atomic: an existing file is replaced only by a complete one."""
    _glint.write_image(image, _os.fspath(path), float(exposure), tonemap)
