# Type stubs for glint (python/glint/__init__.py): what editors complete.
import os
from typing import Any, Callable, Dict, Iterator, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
PASSES: Tuple[str, ...]
embree_available: bool

Vec3 = Union[Tuple[float, float, float], Sequence[float], npt.NDArray[np.floating]]
Color = Union[float, Vec3, Dict[str, Any]]
PathLike = Union[str, "os.PathLike[str]"]
PassName = Literal["ambient", "diffuse", "specular", "reflection", "transmission", "normal", "depth", "albedo"]

class SceneError(ValueError):
    """A scene (or an edit of one) that glint's loader refuses; str(e) is the CLI's message."""
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    path: Optional[str]
    message: str

class CancelToken:
    """Stops a render from another thread: glint.render(..., cancel=token); token.cancel()."""
    def __init__(self) -> None: ...
    def cancel(self) -> None: ...
    def reset(self) -> None: ...
    @property
    def cancelled(self) -> bool: ...
    @property
    def running(self) -> bool: ...

class _View:
    def to_dict(self) -> Dict[str, Any]: ...
    def update(self, **values: Any) -> None: ...

class Material(_View):
    ambient: Optional[Color]
    diffuse: Optional[Color]
    specular: Optional[Color]
    shininess: Optional[float]
    reflectivity: Optional[float]
    transparency: Optional[float]
    ior: Optional[float]
    fresnel: Optional[bool]

class Light(_View):
    type: str
    name: Optional[str]
    ambient: Optional[Color]
    diffuse: Optional[Color]
    specular: Optional[Color]
    color: Optional[Color]
    position: Optional[Vec3]
    direction: Optional[Vec3]
    attenuation: Optional[Vec3]
    cutoff: Optional[float]
    falloff: Optional[float]
    corner: Optional[Vec3]
    edge_u: Optional[Vec3]
    edge_v: Optional[Vec3]
    samples: Optional[int]
    occlusion: Optional[Dict[str, Any]]

class Object(_View):
    type: str
    material: Optional[str]
    transform: Optional[Dict[str, Any]]
    name: Optional[str]
    center: Optional[Vec3]
    radius: Optional[float]
    point: Optional[Vec3]
    normal: Optional[Vec3]
    vertices: Optional[List[Any]]
    uv: Optional[List[Any]]
    min: Optional[Vec3]
    max: Optional[Vec3]
    file: Optional[str]
    smooth: Optional[bool]
    triangles: Optional[List[Any]]
    normals: Optional[List[Any]]
    uvs: Optional[List[Any]]
    base: Optional[Vec3]
    apex: Optional[Vec3]
    base_radius: Optional[float]
    apex_radius: Optional[float]
    caps: Optional[bool]
    inner_radius: Optional[float]
    axis: Optional[Vec3]
    major_radius: Optional[float]
    minor_radius: Optional[float]
    operation: Optional[str]
    children: Optional[List[Any]]

class Camera(_View):
    type: Optional[str]
    position: Vec3
    look_at: Vec3
    up: Optional[Vec3]
    fov_y: Optional[float]
    view_height: Optional[float]
    fov: Optional[float]
    aperture: Optional[float]
    focus_distance: Optional[float]
    stereo: Optional[Dict[str, Any]]

class RenderSettings(_View):
    width: Optional[int]
    height: Optional[int]
    samples_per_pixel: Optional[int]
    max_depth: Optional[int]
    shading_model: Optional[str]
    background: Optional[Color]
    epsilon: Optional[float]
    pixel_filter: Optional[Union[str, Dict[str, Any]]]
    adaptive: Optional[Dict[str, Any]]
    fog: Optional[Dict[str, Any]]
    environment: Optional[Dict[str, Any]]

class Materials:
    def __getitem__(self, name: str) -> Material: ...
    def __setitem__(self, name: str, material: Union[Dict[str, Any], Material]) -> None: ...
    def __delitem__(self, name: str) -> None: ...
    def __contains__(self, name: object) -> bool: ...
    def __iter__(self) -> Iterator[str]: ...
    def __len__(self) -> int: ...
    def keys(self) -> List[str]: ...
    def items(self) -> List[Tuple[str, Material]]: ...

class Lights:
    def __getitem__(self, i: int) -> Light: ...
    def __setitem__(self, i: int, light: Dict[str, Any]) -> None: ...
    def __delitem__(self, i: int) -> None: ...
    def __iter__(self) -> Iterator[Light]: ...
    def __len__(self) -> int: ...
    def append(self, light: Dict[str, Any]) -> None: ...

class Objects:
    def __getitem__(self, i: int) -> Object: ...
    def __setitem__(self, i: int, obj: Dict[str, Any]) -> None: ...
    def __delitem__(self, i: int) -> None: ...
    def __iter__(self) -> Iterator[Object]: ...
    def __len__(self) -> int: ...
    def append(self, obj: Dict[str, Any]) -> None: ...

class Scene:
    @classmethod
    def from_dict(cls, d: Dict[str, Any], base_dir: Optional[PathLike] = ..., name: str = ...) -> Scene: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def to_json(self, indent: int = ...) -> str: ...
    def copy(self) -> Scene: ...
    @property
    def base_dir(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def materials(self) -> Materials: ...
    @property
    def lights(self) -> Lights: ...
    @property
    def objects(self) -> Objects: ...
    @property
    def camera(self) -> Camera: ...
    @property
    def render_settings(self) -> RenderSettings: ...
    def get(self, path: str) -> Any: ...
    def has(self, path: str) -> bool: ...
    def set(self, path: str, value: Any) -> None: ...
    def erase(self, path: str) -> None: ...
    def add_mesh(
        self,
        vertices: npt.ArrayLike,
        triangles: npt.ArrayLike,
        normals: Optional[npt.ArrayLike] = ...,
        uvs: Optional[npt.ArrayLike] = ...,
        *,
        material: Optional[str] = ...,
        transform: Optional[Dict[str, Any]] = ...,
        smooth: bool = ...,
        name: Optional[str] = ...,
    ) -> Object: ...

class Render:
    image: npt.NDArray[np.float32]
    passes: Dict[str, npt.NDArray[np.float32]]
    stats: Dict[str, Any]
    def save(self, path: PathLike, exposure: float = ..., tonemap: Literal["clamp", "reinhard", "aces"] = ...,
             pass_name: Optional[str] = ...) -> None: ...
    def _repr_png_(self) -> bytes: ...

def load(path: PathLike) -> Scene: ...
def loads(text: Union[str, bytes], base_dir: Optional[PathLike] = ..., name: str = ...) -> Scene: ...
def render(
    scene: Scene,
    *,
    width: Optional[int] = ...,
    height: Optional[int] = ...,
    spp: Optional[int] = ...,
    threads: int = ...,
    accel: Literal["bvh", "embree"] = ...,
    frame: int = ...,
    passes: Sequence[PassName] = ...,
    progress: Optional[Callable[[float], Any]] = ...,
    cancel: Optional[CancelToken] = ...,
) -> Render: ...
@overload
def explain(scene: Scene, x: int, y: int, *, width: Optional[int] = ..., height: Optional[int] = ...,
            frame: int = ..., text: Literal[False] = ...) -> Dict[str, Any]: ...
@overload
def explain(scene: Scene, x: int, y: int, *, width: Optional[int] = ..., height: Optional[int] = ...,
            frame: int = ..., text: Literal[True]) -> str: ...
def read_image(path: PathLike) -> npt.NDArray[np.float32]: ...
def write_image(image: npt.ArrayLike, path: PathLike, exposure: float = ...,
                tonemap: Literal["clamp", "reinhard", "aces"] = ...) -> None: ...
