# %% [markdown]
# # A BSSRDF profile at oblique incidence
#
# Bakes skin1 (one of the built-in measured media) in memory, then evaluates its green channel
# along the plane of incidence: forward (φ = 0) and backward (φ = π) of the entry point, at
# normal incidence and at 60°. Oblique light exits ahead of where it entered. Plots with
# matplotlib if it is installed, prints a table otherwise.
#
# Run: `python3 examples/python/profile.py [OUT.png]` after `python3 -m pip install ./python`.

# %%
import sys

import numpy as np

import bssrdf_zoo as bz

library = bz.bake_materials(["skin1"])  # the default grid, about a second
green = library.channel("skin1", "g")
r = np.geomspace(0.01, 10.0, 200)  # mm
curves = {
    f"θ = {deg}°, φ = {'0 (forward)' if phi == 0 else 'π (backward)'}": green.eval(np.radians(deg), r, phi)
    for deg in (0, 60)
    for phi in (0.0, np.pi)
}
print(f"skin1, green: rho' = {green.rho_prime:.4f}, sigma_t' = {green.sigma_t:.4f} /mm")

# %%
try:
    import matplotlib

    matplotlib.use("Agg" if len(sys.argv) > 1 else matplotlib.get_backend())
    import matplotlib.pyplot as plt
except ImportError:
    plt = None

if plt is None:
    print("r (mm)     " + "  ".join(f"{name:>26}" for name in curves))
    for i in range(0, len(r), 20):
        print(f"{r[i]:<10.4f} " + "  ".join(f"{s[i]:>26.6e}" for s in curves.values()))
else:
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, s in curves.items():
        ax.loglog(r, r * s, label=name)
    ax.set_xlabel("r (mm)")
    ax.set_ylabel("r · S(r, φ; θ)  (mm⁻¹)")
    ax.set_title("skin1, green channel")
    ax.legend()
    fig.tight_layout()
    if len(sys.argv) > 1:
        fig.savefig(sys.argv[1], dpi=120)
        print(f"wrote {sys.argv[1]}")
    else:
        plt.show()
