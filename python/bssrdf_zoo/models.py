"""The model zoo: every model of the Rust registry, evaluated at numpy points.

Each model gives R(r, φ; θ), the power leaving per unit area at (r, φ) per unit power entering
the medium at the origin (docs/zoo.md), in reduced units (r in reduced mean free paths, R per
reduced mfp²) or, with ``sigma_t=`` (σ′t, mm⁻¹), in world units (r in mm, R per mm²).
``names()`` lists them; ``eval(name, rho, theta, r, phi, …)`` evaluates one.
"""

from ._native import model_eval as eval  # noqa: A001 - the zoo's verb, as in `bssrdf eval`
from ._native import model_names as names

__all__ = ["eval", "names"]
