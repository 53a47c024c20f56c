"""Type stubs of the native module ``woven._woven`` (re-exported by ``woven``)."""

import os
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
PARALLEL_MIN: int
"""Batches at least this long run on all cores with the GIL released (the calling thread
checking for Ctrl-C meanwhile: a KeyboardInterrupt stops the batch within ~0.1 s and a pair's
evaluation)."""
BATCH_BUDGET_BYTES: int
"""The most memory one array of a call may take, bytes (2 GiB): an argument's float64 copy or a
result. A larger batch raises MemoryError, naming the budget and the excess, before allocating."""
UNIT_TOLERANCE: float
MAX_DYED_DIFFUSE: float
JIT_LAYOUT_VERSION: int
"""How far from 1 a direction's length may be (1e-6); a direction off by more raises ValueError
naming the argument, the row and its length."""
SURFACE_KEYS: Tuple[Dict[str, str], ...]
"""The keys of a woven surface (``woven.Surface``, ``woven render`` scenes, the Mitsuba plugin),
from the library's table: one dict per key, ``{"name", "default", "valid", "meaning"}``."""

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
PathLike = Union[str, "os.PathLike[str]"]

def presets() -> List[str]:
    """The names of the built-in presets."""

def open_material(preset_or_path: PathLike) -> Union["Material", "Microcylinder"]:
    """A preset or material file of either model: a ``Material`` (woven) or a ``Microcylinder``
    (a ``microcylinder-*`` preset, or a file with ``model = "microcylinder"``)."""

def gonio(
    material: Union["Material", "Model", "Bsdf"],
    azimuth_deg: Optional[ArrayLike] = None,
    tilt_deg: Optional[ArrayLike] = None,
    wavelength_nm: float = 550.0,
) -> Dict[str, FloatArray]:
    """The paper's virtual goniometer: a dict of (M,) arrays ``azimuth_deg``, ``tilt_deg``,
    ``theta_i``, ``theta_r`` (radians) and ``radiance`` = f cos θi (sr⁻¹) over every azimuth
    (outer) × tilt (inner). Defaults: azimuths 0, 45, 90; the paper's tilts −42° to 42° by 3°.
    A colour ``Bsdf`` (a ``Microcylinder``) reads as its luminance (Rec. 709), as ``woven gonio``."""

def from_spherical(theta: ArrayLike, phi: ArrayLike) -> FloatArray:
    """Unit directions (N, 3) (or (3,)) from polar angles and azimuths, radians."""

def to_spherical(d: ArrayLike) -> Tuple[Union[float, FloatArray], Union[float, FloatArray]]:
    """``(theta, phi)`` of directions (N, 3) or (3,), radians."""

def export_merl(source: Union["Table", "Model"], path: PathLike, threads: int = 0) -> None:
    """Writes an isotropic BRDF in the MERL binary layout, atomically."""

def fit(
    data: str,
    model: str = "cloth",
    *,
    init: Optional[str] = None,
    fix: Optional[List[str]] = None,
    free: Optional[List[str]] = None,
    seed: int = 1,
    starts: Optional[int] = None,
    refine: Optional[int] = None,
    max_iterations: Optional[int] = None,
    subset: Optional[int] = None,
    final_subset: Optional[int] = None,
    residual: str = "log",
    saturation: Optional[float] = None,
) -> Dict[str, Any]:
    """Fits ``model`` to the measurements ``data`` (a path or ``FILE#N``), as ``woven fit --data``:
    a dict ``dataset``, ``model``, ``points``, ``rms_log``, ``relative_rms``, ``material_toml``
    (what ``woven fit -o`` writes), ``parameters`` (name → value), ``seconds``."""

def datasets(path: str) -> List[str]:
    """The datasets of a measurement file, each as ``FILE#NAME`` (the path itself for a file of one)."""

def comparison_table(rows: List[Tuple[str, List[Tuple[Any, ...]]]]) -> str:
    """The Markdown table ``woven fit --compare`` writes, from ``(data, [(model, rms_log,
    relative_rms) or (model, error)])`` rows."""

def render(
    scene: PathLike,
    output: Optional[PathLike] = None,
    *,
    spp: Optional[int] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    cache: bool = True,
) -> Dict[str, Any]:
    """Renders a scene file as ``woven render SCENE -o OUTPUT``: a dict ``scene``, ``width``,
    ``height``, ``spp``, ``seconds``, ``invalid_samples``, ``pixels`` ((height, width, 3) linear RGB)."""

def set_threads(threads: int) -> int:
    """Sizes rayon's global pool if this process has not used it yet; returns its size."""

def threads() -> int:
    """The size of rayon's global thread pool in this process."""

class Section:
    """One section of a material file; its keys read as attributes or items."""

    def __getattr__(self, key: str) -> Any: ...
    def __getitem__(self, key: str) -> Any: ...
    def __contains__(self, key: str) -> bool: ...
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterator[str]: ...
    def keys(self) -> List[str]:
        """The keys present in the file."""
    def to_dict(self) -> Dict[str, Any]:
        """A copy as a plain dict."""

class Material:
    """A cloth material: the contents of a woven material file (TOML)."""

    @staticmethod
    def preset(name: str) -> "Material":
        """The built-in preset ``name`` (ValueError for an unknown name)."""
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> "Material":
        """A material from a material file's text (ValueError with the library's message)."""
    @staticmethod
    def load(path: PathLike) -> "Material":
        """A material file (OSError if unreadable, ValueError if invalid)."""
    @staticmethod
    def open(preset_or_path: str) -> "Material":
        """A preset name or a material file path, as ``--material`` takes."""
    def to_toml(self, self_contained: bool = False) -> str:
        """The material file's text."""
    @property
    def name(self) -> Optional[str]: ...
    @property
    def fiber(self) -> Section:
        """The ``[fiber]`` section."""
    @property
    def yarn(self) -> Optional[Section]:
        """The ``[yarn]`` section (None for a flat fiber surface)."""
    @property
    def weave(self) -> Optional[Section]:
        """The ``[weave]`` section (None: γ = 1)."""
    @property
    def weft_fraction(self) -> float:
        """γ, the visible fraction of weft."""
    def to_dict(self) -> Dict[str, Any]:
        """The material as nested dicts."""
    def replace(self, changes: Dict[str, Any]) -> "Material":
        """A copy with dotted keys (``"fiber.roughness"``) changed; None removes a key."""
    def pattern(self) -> Optional[npt.NDArray[np.bool_]]:
        """The weave pattern's cells (rows, cols), True where the weft is on top; None without."""
    def yarn_family(self) -> "Material":
        """The material's yarn alone (its weave removed)."""
    def build(self, wavelength_nm: float = 550.0) -> "Model":
        """The material prepared at ``wavelength_nm``: the exact BRDF."""
    def __eq__(self, other: object) -> bool: ...

class Model:
    """A material prepared at one wavelength: the exact BRDF."""

    def eval(self, wi: ArrayLike, wo: ArrayLike) -> Union[float, FloatArray]:
        """f(wi, wo) in sr⁻¹ without the cosine; (N, 3) or (3,) directions, broadcast; (N,)
        out, a float for two (3,) directions."""
    def albedo(
        self, theta_i: ArrayLike, phi_i: Optional[ArrayLike] = None
    ) -> Union[float, FloatArray]:
        """The directional albedo for light from (θi, φi), radians."""
    def transmittance(
        self, theta_i: ArrayLike, phi_i: Optional[ArrayLike] = None
    ) -> Union[float, FloatArray]:
        """All the light from (θi, φi) that reaches the far side; 0 for an opaque cloth."""
    @property
    def transmits(self) -> bool: ...
    @property
    def material(self) -> Material: ...
    @property
    def wavelength_nm(self) -> float: ...

class Table:
    """A tabulated, importance-sampled BRDF (``.wtab`` files)."""

    @staticmethod
    def build(
        material: Union[Material, str, PathLike],
        wavelength_nm: float = 550.0,
        *,
        grid: str = "model",
        n_theta: Optional[int] = None,
        theta_max_deg: Optional[float] = None,
        n_phi: Optional[int] = None,
        n_h: Optional[int] = None,
        n_h_isotropic: Optional[int] = None,
        azimuth_nodes: Optional[int] = None,
        colour: Optional[bool] = None,
        exact_regions: Optional[bool] = None,
        threads: int = 0,
        progress: Union[bool, None, Callable[[int, int], Any]] = None,
    ) -> "Table":
        """Tabulates ``material``; ``grid`` is "model", "render" or "default"."""
    @staticmethod
    def cached(
        material: Union[Material, str, PathLike],
        wavelength_nm: float = 550.0,
        *,
        grid: str = "render",
        progress: Union[bool, None, Callable[[int, int], Any]] = None,
    ) -> "Table":
        """The table from the user's table cache (shared with ``woven render``), or built there."""
    @staticmethod
    def load(path: PathLike) -> "Table":
        """A table file (OSError if unreadable, ValueError if invalid)."""
    def save(self, path: PathLike) -> None:
        """Writes the table atomically."""
    def eval(self, wi: ArrayLike, wo: ArrayLike) -> Union[float, FloatArray]:
        """f(wi, wo), sr⁻¹, without the cosine."""
    def eval_interpolated(self, wi: ArrayLike, wo: ArrayLike) -> Union[float, FloatArray]:
        """As ``eval``, interpolated also in the exact near-forward region."""
    def eval_dyed(self, wi: ArrayLike, wo: ArrayLike, albedos: ArrayLike) -> FloatArray:
        """f for (C, 2) albedos (ρ0, ρ) per channel: (N, C)."""
    def sample(
        self, known: ArrayLike, u: ArrayLike, mode: str = "radiance"
    ) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """``(drawn, weight, pdf)`` with uniforms ``u`` (N, 2): ``wi`` for a known ``wo``
        ("radiance") or ``wo`` for a known ``wi`` ("importance", drawn ∝ f cos θo)."""
    def sample_direction(self, wi: ArrayLike, u: ArrayLike) -> Tuple[FloatArray, FloatArray]:
        """``(wo, pdf)``: the draw of ``sample`` without f."""
    def pdf(self, wi: ArrayLike, wo: ArrayLike, mode: str = "radiance") -> Union[float, FloatArray]:
        """The density with which ``sample`` in ``mode`` draws the unknown direction, per unit
        solid angle."""
    @property
    def material(self) -> Optional[Material]: ...
    @property
    def wavelength_nm(self) -> float: ...
    @property
    def dims(self) -> Tuple[int, int, int]: ...
    @property
    def symmetry(self) -> str: ...
    @property
    def is_dyeable(self) -> bool: ...
    @property
    def values(self) -> npt.NDArray[np.float32]:
        """f at every node, (2, n_theta, n_phi, n_h, n_h)."""
    def raw(self) -> Dict[str, Any]:
        """The arrays and grid the Mitsuba plugin reads."""

class Surface:
    """A woven material laid on a surface: see the native docstring (``help(woven.Surface)``)."""

    def __init__(
        self,
        material: Union["Material", str, PathLike, None] = None,
        *,
        table: Optional["Table"] = None,
        pattern: Union[str, Sequence[Sequence[int]], Dict[str, str], None] = None,
        weft_fraction: Optional[float] = None,
        yarns_per_unit: Union[float, Tuple[float, float], None] = None,
        weft_color: Optional[ArrayLike] = None,
        warp_color: Optional[ArrayLike] = None,
        u_max_deg: Optional[float] = None,
        gap: Optional[float] = None,
        detail: Optional[str] = None,
        irregularity: Union[float, Tuple[float, float], None] = None,
        irregularity_length: Optional[float] = None,
        wavelength_nm: Optional[float] = None,
        footprint_filter: Optional[bool] = None,
        progress: Any = None,
    ) -> None: ...
    def eval(
        self,
        uv: ArrayLike,
        wi: ArrayLike,
        wo: ArrayLike,
        footprint: Optional[ArrayLike] = None,
        weft_color: Optional[ArrayLike] = None,
        warp_color: Optional[ArrayLike] = None,
    ) -> FloatArray: ...
    def pdf(
        self,
        uv: ArrayLike,
        wi: ArrayLike,
        wo: ArrayLike,
        footprint: Optional[ArrayLike] = None,
        mode: str = "radiance",
    ) -> FloatArray: ...
    def sample(
        self,
        uv: ArrayLike,
        known: ArrayLike,
        uc: ArrayLike,
        u: ArrayLike,
        footprint: Optional[ArrayLike] = None,
        mode: str = "radiance",
        weft_color: Optional[ArrayLike] = None,
        warp_color: Optional[ArrayLike] = None,
    ) -> Tuple[FloatArray, FloatArray, FloatArray]: ...
    def lobes(
        self, uv: ArrayLike, footprint: Optional[ArrayLike] = None
    ) -> Tuple[FloatArray, FloatArray, FloatArray, FloatArray]: ...
    def layout(self) -> Dict[str, Any]: ...
    @property
    def table(self) -> "Table": ...
    @property
    def float_table(self) -> Optional["Table"]: ...
    @property
    def material(self) -> Optional["Material"]: ...
    @property
    def uses_footprint(self) -> bool: ...
    @property
    def transmits(self) -> bool: ...
    def pass_through(self, uv: ArrayLike, d: ArrayLike, footprint: Optional[ArrayLike] = None) -> "np.ndarray": ...
    @property
    def back(self) -> Optional["Surface"]: ...
    @property
    def footprint_filter(self) -> bool: ...
    @property
    def route(self) -> Optional[str]: ...


class Bsdf:
    """A reflectance model in colour (the library's ``Bsdf`` trait, RGB values): the base of
    ``Microcylinder``, ``Sheen`` and ``RoughPlastic``; not made directly. ``wi`` toward the light,
    ``wo`` toward the viewer; f in sr⁻¹ without the cosine, 0 below the surface."""

    def eval(self, wi: ArrayLike, wo: ArrayLike) -> FloatArray:
        """f(wi, wo) per channel: (N, 3), or (3,) when both are (3,)."""
    def pdf(self, wi: ArrayLike, wo: ArrayLike, mode: str = "radiance") -> Union[float, FloatArray]:
        """The density with which ``sample`` in ``mode`` draws the unknown direction: ``wi`` for
        a known ``wo`` ("radiance"), ``wo`` for a known ``wi`` ("importance"). (N,) or a float."""
    def sample(
        self, known: ArrayLike, uc: ArrayLike, u: ArrayLike, mode: str = "radiance"
    ) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """``(drawn (N, 3), f (N, 3), pdf (N,))``: ``wi`` for a known ``wo`` ("radiance") or
        ``wo`` for a known ``wi`` ("importance"); all zeros for a failed draw."""
    def albedo(self, theta_i: ArrayLike, phi_i: Optional[ArrayLike] = None) -> FloatArray:
        """The directional albedo ∫ f cos θo dωo per channel: (N, 3), or (3,) for scalars."""
    @property
    def lobes(self) -> List[str]:
        """A subset of "reflection", "glossy", "diffuse", "anisotropic"."""

class Microcylinder(Bsdf):
    """A microcylinder fabric (Sadeghi et al. 2013) in colour: a preset's name
    (``Microcylinder.preset_names()``) or a fabric file's path. ValueError for an unknown name or a
    woven material, OSError for an unreadable file."""

    def __init__(self, material: PathLike) -> None: ...
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> "Microcylinder":
        """A fabric from a fabric file's text (``model = "microcylinder"``)."""
    @staticmethod
    def preset_names() -> List[str]:
        """The six fabrics of the paper's Table II."""
    @property
    def name(self) -> str:
        """The fabric's name."""
    @property
    def tangent_counts(self) -> Tuple[int, int]:
        """Tangents (quadrature nodes) along each thread's curve."""
    def eval_unguarded(self, wi: ArrayLike, wo: ArrayLike) -> FloatArray:
        """The printed model without the energy guard, per channel (as ``eval``)."""

class Sheen(Bsdf):
    """The Charlie sheen over a Lambertian base (a baseline). Colours: a number or (r, g, b) in
    [0, 1]; ``roughness`` in [0.1, 1]."""

    def __init__(
        self,
        *,
        diffuse: Optional[ArrayLike] = None,
        sheen_color: Optional[ArrayLike] = None,
        roughness: Optional[float] = None,
    ) -> None: ...

class RoughPlastic(Bsdf):
    """Mitsuba 3's ``roughplastic`` (a baseline), with Mitsuba's defaults."""

    def __init__(
        self,
        *,
        distribution: str = "beckmann",
        alpha: Optional[float] = None,
        int_ior: Optional[float] = None,
        ext_ior: Optional[float] = None,
        diffuse_reflectance: Optional[ArrayLike] = None,
        specular_reflectance: Optional[ArrayLike] = None,
        nonlinear: bool = False,
    ) -> None: ...

def portable_scene(
    scene: str, *, width: Optional[int] = None, height: Optional[int] = None
) -> Dict[str, Any]:
    """A ``woven render`` scene (or ``"showcase"``) as plain data for another renderer."""

STANDARD_VERSION: int
"""The version of what ``standard_surface`` gives (a cache of it is keyed by it)."""

def standard_surface(
    surface: Surface,
    folder: Optional[PathLike] = None,
    stem: str = "woven",
    texels_per_cell: int = 16,
) -> Dict[str, Any]:
    """A woven surface on the standard lobes (Lambert + anisotropic GGX along each yarn
    family), and its layout as 16-bit PNG textures of one tile (written into ``folder``)."""

def standard_eval(family: Dict[str, Any], wi: ArrayLike, wo: ArrayLike) -> FloatArray:
    """A family's standard lobes per channel at ``wi``, ``wo`` (the yarn along x), (N, 3)."""

def write_image(pixels: ArrayLike, path: PathLike, scene: Optional[str] = None) -> None:
    """Writes linear RGB (height, width, 3) as ``woven render`` writes its images."""
