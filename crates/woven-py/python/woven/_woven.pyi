"""Type stubs of the native module ``woven._woven`` (re-exported by ``woven``)."""

import os
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
PARALLEL_MIN: int
"""Batches at least this long run on all cores with the GIL released."""

ArrayLike = npt.ArrayLike
FloatArray = npt.NDArray[np.float64]
PathLike = Union[str, "os.PathLike[str]"]

def presets() -> List[str]:
    """The names of the built-in presets."""

def gonio(
    material: Union["Material", "Model"],
    azimuth_deg: Optional[ArrayLike] = None,
    tilt_deg: Optional[ArrayLike] = None,
    wavelength_nm: float = 550.0,
) -> Dict[str, FloatArray]:
    """The paper's virtual goniometer: a dict of (M,) arrays ``azimuth_deg``, ``tilt_deg``,
    ``theta_i``, ``theta_r`` (radians) and ``radiance`` = f cos θi (sr⁻¹) over every azimuth
    (outer) × tilt (inner). Defaults: azimuths 0, 45, 90; the paper's tilts −42° to 42° by 3°."""

def from_spherical(theta: ArrayLike, phi: ArrayLike) -> FloatArray:
    """Unit directions (N, 3) (or (3,)) from polar angles and azimuths, radians."""

def to_spherical(d: ArrayLike) -> Tuple[Union[float, FloatArray], Union[float, FloatArray]]:
    """``(theta, phi)`` of directions (N, 3) or (3,), radians."""

def export_merl(source: Union["Table", "Model"], path: PathLike, threads: int = 0) -> None:
    """Writes an isotropic BRDF in the MERL binary layout, atomically."""

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
    def sample(self, wi: ArrayLike, u: ArrayLike) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """``(wo, weight, pdf)`` drawn ∝ f cos θo with uniforms ``u`` (N, 2)."""
    def sample_direction(self, wi: ArrayLike, u: ArrayLike) -> Tuple[FloatArray, FloatArray]:
        """``(wo, pdf)``: the draw of ``sample`` without f."""
    def pdf(self, wi: ArrayLike, wo: ArrayLike) -> Union[float, FloatArray]:
        """The density of ``wo`` given ``wi``, per unit solid angle."""
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
        pattern: Optional[str] = None,
        weft_fraction: Optional[float] = None,
        yarns_per_unit: Union[float, Tuple[float, float], None] = None,
        weft_color: Optional[ArrayLike] = None,
        warp_color: Optional[ArrayLike] = None,
        u_max_deg: Optional[float] = None,
        gap: float = 0.0,
        detail: str = "auto",
        wavelength_nm: float = 550.0,
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
    def material(self) -> Optional["Material"]: ...
    @property
    def uses_footprint(self) -> bool: ...

