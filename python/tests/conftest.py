"""Fixtures of the Python package's tests: small libraries baked once per session, the
repository's test data, and the `bssrdf` command (the Rust reference the values are held to).

The command comes from BSSRDF_BIN, else from the Cargo target folder (CARGO_TARGET_DIR or
target/, debug then release). Without it the comparisons skip, unless BSSRDF_REQUIRE_CLI=1
(.ci/run sets it), where they fail.
"""

import math
import os
import shutil
import subprocess
import warnings
from pathlib import Path

import pytest

import bssrdf_zoo as bz

REPO = Path(__file__).resolve().parents[2]

# A grid small enough to bake in a fraction of a second: (n_rho, n_theta, n_r).
SMALL_GRID = (12, 6, 16)


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return REPO / "tests" / "data"


@pytest.fixture(scope="session")
def library_path(tmp_path_factory) -> Path:
    """skin1 (eta 1.3, two lobes) and a bare table at eta 1.33 (one lobe), small grid."""
    path = tmp_path_factory.mktemp("lib") / "small.bssrdf"
    with warnings.catch_warnings():  # a grid this coarse misses the bake check's bound
        warnings.simplefilter("ignore")
        bz.bake_materials(["skin1"], SMALL_GRID, etas=[1.33], path=path)
    return path


@pytest.fixture(scope="session")
def library(library_path) -> bz.Library:
    return bz.Library.open(library_path)


@pytest.fixture(scope="session")
def table(library) -> bz.Table:
    """The one-lobe table, eta 1.33."""
    return next(t for t in library.tables if t.eta == 1.33)


@pytest.fixture(scope="session")
def two_lobe_table(library) -> bz.Table:
    """skin1's table, eta 1.3, two lobes."""
    return library.table(library.material("skin1").tables[0])


def _find_cli():
    given = os.environ.get("BSSRDF_BIN")
    if given:
        return given
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("debug", "release"):
        candidate = target / profile / "bssrdf"
        if candidate.exists():
            return str(candidate)
    return shutil.which("bssrdf")


@pytest.fixture(scope="session")
def cli():
    """Runs `bssrdf ARGS…` and returns its standard output."""
    binary = _find_cli()
    if binary is None:
        if os.environ.get("BSSRDF_REQUIRE_CLI") == "1":
            pytest.fail("BSSRDF_REQUIRE_CLI=1 but no bssrdf binary (set BSSRDF_BIN)")
        pytest.skip("no bssrdf binary: set BSSRDF_BIN to compare with the Rust command")

    def run(*args: str) -> str:
        done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done.stdout

    return run


class SplitMix64:
    """The command's random stream (crates/zoo/src/rng.rs), to replay `bssrdf sample`."""

    GAMMA = 0x9E3779B97F4A7C15
    MASK = (1 << 64) - 1

    def __init__(self, seed: int):
        self.state = seed

    def next_u64(self) -> int:
        self.state = (self.state + self.GAMMA) & self.MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & self.MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & self.MASK
        return z ^ (z >> 31)

    def next_f64(self) -> float:
        return (self.next_u64() >> 11) * (1.0 / (1 << 53))


def radians(deg: float) -> float:
    """Degrees to radians as Rust's f64::to_radians rounds it (x · (π/180))."""
    return math.radians(deg)
