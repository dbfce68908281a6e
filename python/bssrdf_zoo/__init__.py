"""Tabulated BSSRDFs from numpy: the library files of bssrdf-zoo, the angular table's lookups,
the bake, the model zoo and the Monte Carlo random walk, over the Rust library.

Units: coefficients in mm⁻¹, distances in mm; in reduced units (a table's lookups without
``sigma_t=``, the models without it) distances are in reduced mean free paths (σ′t = 1) and
ρ′ = σ′s/σ′t. Angles in radians: θ is the incidence before refraction, φ = 0 forward (in the
plane of incidence, on the side the refracted beam travels to).

Every lookup broadcasts its arguments as numpy does and returns arrays of the broadcast shape
(a float when every argument is a scalar), computed with the GIL released; the values are
those of the Rust API, bit for bit.
"""

from . import models
from ._native import (
    Channel,
    FormatError,
    Library,
    Material,
    Table,
    Walk,
    __version__,
    bake,
    bake_materials,
    builtin_materials,
    walk,
)

__all__ = [
    "Channel",
    "FormatError",
    "Library",
    "Material",
    "Table",
    "Walk",
    "__version__",
    "bake",
    "bake_materials",
    "builtin_materials",
    "models",
    "walk",
]
