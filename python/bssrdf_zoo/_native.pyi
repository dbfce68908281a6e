"""Type stubs of the native module (python/src/*.rs). Lookups broadcast their array arguments as
numpy does and return a float when every argument is a scalar, else an array of the broadcast
shape."""

from os import PathLike
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

Values = Union[float, NDArray[np.float64]]
StrPath = Union[str, "PathLike[str]"]
ChannelName = Union[str, int]
Grid = Union[str, Tuple[int, int, int], Dict[str, Sequence[float]]]
MaterialArg = Union[str, Dict[str, Any]]

class FormatError(ValueError):
    """A file that is not a valid bssrdf library file; the message names the check it failed."""

class Library:
    """A library file, opened and validated, with its tables and material records."""

    @staticmethod
    def open(path: StrPath, mmap: bool = True) -> Library: ...
    @staticmethod
    def read(path: StrPath) -> Library: ...
    @property
    def path(self) -> Optional[Path]: ...
    @property
    def is_mapped(self) -> bool: ...
    @property
    def version(self) -> Tuple[int, int]: ...
    @property
    def tables(self) -> List[Table]: ...
    def table(self, index: int) -> Table: ...
    @property
    def materials(self) -> List[Material]: ...
    def material(self, name: str) -> Material: ...
    def channel(self, name: str, channel: ChannelName) -> Channel: ...
    @property
    def provenance(self) -> Optional[Dict[str, Any]]: ...
    def write(self, path: StrPath) -> None: ...

class Material:
    """A material record: RGB coefficients (mm⁻¹), η, and the table of each channel."""

    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def sigma_s(self) -> Tuple[float, float, float]: ...
    @property
    def sigma_a(self) -> Tuple[float, float, float]: ...
    @property
    def g(self) -> Tuple[float, float, float]: ...
    @property
    def eta(self) -> float: ...
    @property
    def tables(self) -> Tuple[int, int, int]: ...
    @property
    def albedo_range(
        self,
    ) -> Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float]]]: ...
    def channel(self, channel: ChannelName) -> Channel: ...

class Table:
    """One table (one η): lookups in reduced units, or in world units with ``sigma_t=``."""

    @property
    def index(self) -> int: ...
    @property
    def eta(self) -> float: ...
    @property
    def dims(self) -> Tuple[int, int, int]: ...
    @property
    def has_theta_sampling(self) -> bool: ...
    @property
    def two_lobes(self) -> bool: ...
    @property
    def model(self) -> str: ...
    @property
    def walk_g(self) -> Optional[float]: ...
    @property
    def walk_component(self) -> Optional[str]: ...
    @property
    def ridge(self) -> bool: ...
    @property
    def ridge_kind(self) -> str: ...
    @property
    def rho_nodes(self) -> NDArray[np.float32]: ...
    @property
    def theta_nodes(self) -> NDArray[np.float32]: ...
    @property
    def r_nodes(self) -> NDArray[np.float32]: ...
    @property
    def params(self) -> NDArray[np.float32]: ...
    @property
    def radial_cdf(self) -> NDArray[np.float32]: ...
    @property
    def theta_cdf(self) -> Optional[NDArray[np.float32]]: ...
    @property
    def harmonics(self) -> Optional[NDArray[np.float32]]: ...
    def eval(
        self,
        rho: ArrayLike,
        theta: ArrayLike,
        r: ArrayLike,
        phi: ArrayLike,
        *,
        sigma_t: Optional[ArrayLike] = None,
    ) -> Values: ...
    def pdf(
        self,
        rho: ArrayLike,
        theta: ArrayLike,
        r: ArrayLike,
        phi: ArrayLike,
        *,
        sigma_t: Optional[ArrayLike] = None,
    ) -> Values: ...
    def sample(
        self,
        rho: ArrayLike,
        theta: ArrayLike,
        u1: ArrayLike,
        u2: ArrayLike,
        *,
        sigma_t: Optional[ArrayLike] = None,
    ) -> Tuple[Values, Values, Values]: ...
    def sample_path(
        self,
        rho: ArrayLike,
        u1: ArrayLike,
        u2: ArrayLike,
        u3: ArrayLike,
        u4: ArrayLike,
        *,
        sigma_t: Optional[ArrayLike] = None,
    ) -> Tuple[Values, Values, Values, Values, Values, Values]: ...
    def pdf_theta(self, rho: ArrayLike, theta: ArrayLike) -> Values: ...
    def effective_albedo(self, rho: ArrayLike, theta: ArrayLike) -> Values: ...
    def medium(self, rho_prime: float, sigma_t: float) -> Channel: ...

class Channel:
    """One medium on one table (a material's colour channel): world units, r in mm."""

    @property
    def rho_prime(self) -> float: ...
    @property
    def sigma_t(self) -> float: ...
    @property
    def table(self) -> Table: ...
    def eval(self, theta: ArrayLike, r: ArrayLike, phi: ArrayLike) -> Values: ...
    def pdf(self, theta: ArrayLike, r: ArrayLike, phi: ArrayLike) -> Values: ...
    def sample(
        self, theta: ArrayLike, u1: ArrayLike, u2: ArrayLike
    ) -> Tuple[Values, Values, Values]: ...
    def sample_path(
        self, u1: ArrayLike, u2: ArrayLike, u3: ArrayLike, u4: ArrayLike
    ) -> Tuple[Values, Values, Values, Values, Values, Values]: ...
    def pdf_theta(self, theta: ArrayLike) -> Values: ...
    def effective_albedo(self, theta: ArrayLike) -> Values: ...

class Walk:
    """A random walk's tallies: lengths in mean free paths, per unit power entering."""

    r_edges: NDArray[np.float64]
    phi_edges: NDArray[np.float64]
    single: NDArray[np.float64]
    single_stderr: NDArray[np.float64]
    multiple: NDArray[np.float64]
    multiple_stderr: NDArray[np.float64]
    total: NDArray[np.float64]
    total_stderr: NDArray[np.float64]
    reflectance: Tuple[float, float]
    single_reflectance: Tuple[float, float]
    multiple_reflectance: Tuple[float, float]
    transmittance: Optional[Tuple[float, float]]
    truncated_weight: Tuple[float, float]
    photons: int
    scattering_events: int

def bake(
    eta: Union[float, Sequence[float], None] = None,
    grid: Optional[Grid] = None,
    *,
    lobes: Optional[int] = None,
    moments: str = "exact",
    theta_sampling: bool = True,
    threads: Optional[int] = None,
    path: Optional[StrPath] = None,
) -> Library: ...
def bake_materials(
    materials: Sequence[MaterialArg],
    grid: Optional[Grid] = None,
    *,
    etas: Sequence[float] = (),
    lobes: Optional[int] = None,
    moments: str = "exact",
    theta_sampling: bool = True,
    threads: Optional[int] = None,
    path: Optional[StrPath] = None,
) -> Library: ...
def builtin_materials() -> List[str]: ...
def walk(
    albedo: float,
    *,
    g: float = 0.0,
    eta: float = 1.33,
    theta: float = 0.0,
    photons: int = 1_000_000,
    seed: int = 0,
    bins: Optional[Tuple[float, float, int, int]] = None,
    slab: Optional[float] = None,
    threads: Optional[int] = None,
) -> Walk: ...
def model_names() -> List[str]: ...
def model_eval(
    name: str,
    rho: ArrayLike,
    theta: ArrayLike,
    r: ArrayLike,
    phi: ArrayLike,
    *,
    eta: Optional[float] = None,
    g: Optional[float] = None,
    sigma_t: Optional[ArrayLike] = None,
    moments: Optional[str] = None,
    table: Optional[Table] = None,
    grid: Optional[Grid] = None,
    photons: Optional[int] = None,
    seed: Optional[int] = None,
) -> Values: ...
