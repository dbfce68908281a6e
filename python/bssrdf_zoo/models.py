"""The model zoo: every model of the Rust registry (``bssrdf models``), evaluated at numpy
points.

Each model gives R(r, φ; θ), the power leaving per unit area at (r, φ) per unit power entering
the medium at the origin (docs/zoo.md), in reduced units (r in reduced mean free paths, R per
reduced mfp²) or, with ``sigma_t=`` (σ′t, mm⁻¹), in world units (r in mm, R per mm²).
"""

from __future__ import annotations

from typing import Optional, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from . import _native
from ._native import Table

__all__ = ["eval", "names"]


def names() -> list[str]:
    """The models' names, in the registry's order."""
    return _native.model_names()


def eval(  # noqa: A001 - the zoo's verb, as on the command line (`bssrdf eval --model`)
    name: str,
    rho: ArrayLike,
    theta: ArrayLike,
    r: ArrayLike,
    phi: ArrayLike = 0.0,
    *,
    eta: Optional[float] = None,
    g: float = 0.0,
    sigma_t: Optional[ArrayLike] = None,
    moments: Optional[str] = None,
    table: Optional[Table] = None,
    grid: Optional[Tuple[int, int, int]] = None,
    photons: int = 100_000,
    seed: int = 1,
) -> Union[float, np.ndarray]:
    """R of model ``name`` at every point of the broadcast of ρ′, θ, r and φ.

    ``eta`` defaults to the table's η for the table models given ``table``, else 1.33;
    ``moments`` is "exact" (default; the table's with ``table``), "pbrt", or for ``dirpole``
    "authors". The table models (``table``, ``perpendicular``) look up ``table`` or a table baked
    once at η on ``grid`` (counts (nρ, nθ, nr); default: the default grid). ``mc`` runs a walk
    of ``photons`` photons from ``seed`` for each (ρ′, θ), as ``bssrdf eval --model mc`` does.
    A model is built once for each run of points sharing its parameters. Where no light enters
    (η < 1 beyond the critical angle) every model gives 0.
    """
    return _native.model_eval(
        name,
        rho,
        theta,
        r,
        phi,
        eta=eta,
        g=g,
        sigma_t=sigma_t,
        moments=moments,
        table=table,
        grid=grid,
        photons=photons,
        seed=seed,
    )
