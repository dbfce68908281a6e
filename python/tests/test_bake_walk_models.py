"""Bakes in memory and to files, the model zoo at numpy points, the walk's arrays."""

import pathlib
import threading
import time
import warnings

import numpy as np
import pytest

import bssrdf_zoo as bz


def quiet(call, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return call(*args, **kwargs)


def test_bake_returns_a_library_and_writes_the_same_file(tmp_path):
    path = tmp_path / "two.bssrdf"
    baked = quiet(bz.bake, [1.4, 1.33], grid=(8, 5, 12), path=path, threads=1)
    assert [t.eta for t in baked.tables] == [1.33, 1.4]
    assert baked.path is None or str(baked.path) == str(path)
    opened = bz.Library.open(path)
    assert opened.tables[1].params.tobytes() == baked.tables[1].params.tobytes()
    assert opened.provenance["settings"]["grid"] == "custom"
    written = tmp_path / "again.bssrdf"
    opened.write(written)
    assert written.read_bytes() == path.read_bytes()


def test_bake_materials_by_name_coefficients_and_artists_parameters():
    lib = quiet(
        bz.bake_materials,
        [
            "marble",
            {"name": "wax", "sigma_s": [2.0, 2.1, 2.2], "sigma_a": 0.01, "g": 0.5, "eta": 1.4, "source": "made up"},
            {"name": "paint", "reflectance": [0.8, 0.5, 0.2], "mfp": [1.0, 0.5, 0.25], "eta": 1.4},
        ],
        (8, 5, 12),
    )
    names = [m.name for m in lib.materials]
    assert names == ["marble", "wax", "paint"]
    wax = lib.material("wax")
    assert wax.sigma_a == (0.01, 0.01, 0.01) and wax.source == "made up" and wax.g == (0.5,) * 3
    assert lib.channel("paint", "r").rho_prime > lib.channel("paint", "b").rho_prime
    assert "marble" in bz.builtin_materials()


def test_a_bake_above_the_checks_bound_warns():
    with pytest.warns(UserWarning, match="above the bake check's bound"):
        bz.bake(1.33, grid=(6, 4, 10))


@pytest.mark.parametrize("name", [n for n in bz.models.names() if n != "walk-table"])
def test_every_model_evaluates_at_numpy_points(table, name):
    theta = np.array([0.0, 0.5, 1.0])
    kwargs = {"table": table} if name in ("table", "perpendicular") else {"eta": 1.33}
    if name == "mc":
        kwargs["photons"] = 2000
    values = bz.models.eval(name, 0.8, theta[:, None], np.array([0.5, 1.0, 2.0]), 0.0, **kwargs)
    assert values.shape == (3, 3)
    assert np.all(np.isfinite(values)) and np.all(values >= 0)
    world = bz.models.eval(name, 0.8, theta[:, None], np.array([0.5, 1.0, 2.0]) / 2.0, 0.0, sigma_t=2.0, **kwargs)
    assert world.tobytes() == (2.0 * 2.0 * values).tobytes()


def test_the_walk_table_model_looks_up_the_walk_table_it_is_given(table):
    """The conformance vector of a walk-angular table (g 0.75): the walk-table model is its
    lookups; it needs that table, of its g, and refuses a PBD table."""
    path = pathlib.Path(__file__).parents[2] / "tests" / "data" / "valid" / "walk-table.bssrdf"
    walk = bz.Library.read(str(path)).table(0)
    assert walk.model == "walk-angular" and walk.walk_g == 0.75
    theta, r = np.array([0.0, 0.3, 0.6]), np.array([0.02, 0.03, 0.04])
    values = bz.models.eval("walk-table", 0.5, theta[:, None], r, 0.0, table=walk)
    assert values.tobytes() == walk.eval(0.5, theta[:, None], r, 0.0).tobytes()
    with pytest.raises(ValueError, match="walk-table model evaluates it"):
        bz.models.eval("table", 0.5, 0.3, 0.03, 0.0, table=walk)
    with pytest.raises(ValueError, match="needs table="):
        bz.models.eval("walk-table", 0.5, 0.3, 0.03, 0.0, g=0.75)
    with pytest.raises(ValueError, match="is a PBD table"):
        bz.models.eval("walk-table", 0.5, 0.3, 0.03, 0.0, table=table)
    with pytest.raises(ValueError, match="walk table g"):
        bz.models.eval("walk-table", 0.5, 0.3, 0.03, 0.0, table=walk, g=0.5)


def test_the_grazing_angle_a_path_draw_gives_is_taken_by_the_models(table):
    """90° as the θ axis stores it, f32(π/2), is 90° for the models too (a path draw gives
    it, and the table's own lookups take it); beyond f32 rounding it is refused."""
    grazing = float(np.float32(np.pi / 2))
    assert grazing > np.pi / 2
    at_node = bz.models.eval("table", 0.5, grazing, 1.0, 0.0, table=table)
    assert at_node == bz.models.eval("table", 0.5, np.pi / 2, 1.0, 0.0, table=table)
    assert bz.models.eval("dipole", 0.5, grazing, 1.0, 0.0, eta=1.33) >= 0
    with pytest.raises(ValueError, match="theta"):
        bz.models.eval("table", 0.5, grazing + 1e-6, 1.0, 0.0, table=table)


def test_walk_bins_at_the_ends_of_their_domain_are_finite_or_refused():
    """r_min 1e-100 below r_max 1 panicked (an f32 ratio overflowed to +inf), r_max 1e308
    gave NaN edges; the domain is [1e-150, 1e150] mean free paths."""
    w = bz.walk(0.5, photons=2000, seed=1, bins=(1e-100, 1.0, 3, 2), threads=1)
    assert np.all(np.isfinite(w.r_edges)) and np.all(np.isfinite(w.total))
    for bins in [(1e-300, 1.0, 3, 2), (0.1, 1e308, 3, 2)]:
        with pytest.raises(ValueError, match="outside"):
            bz.walk(0.5, photons=2000, bins=bins, threads=1)


def test_a_table_model_bakes_its_own_table_when_given_none():
    assert bz.models.eval("table", 0.8, 0.3, 1.0, 0.0, eta=1.33, grid=(8, 5, 12)) > 0


def test_walk_returns_bins_with_standard_errors():
    w = bz.walk(0.9, g=0.5, eta=1.33, theta=0.6, photons=4000, seed=2, bins=(0.05, 30.0, 20, 12), threads=1)
    assert w.r_edges.shape == (22,) and w.phi_edges.shape == (13,)
    assert w.total.shape == w.total_stderr.shape == w.single.shape == (21, 12)
    assert np.all(w.total_stderr >= 0)
    binned = (w.total * np.diff(w.r_edges ** 2)[:, None] / 2 * np.diff(w.phi_edges)[None, :]).sum()
    assert 0 < binned <= w.reflectance[0] + 1e-12
    assert w.photons == 4000 and w.transmittance is None
    again = bz.walk(0.9, g=0.5, eta=1.33, theta=0.6, photons=4000, seed=2, bins=(0.05, 30.0, 20, 12), threads=2)
    assert again.total.tobytes() == w.total.tobytes()
    slab = bz.walk(0.9, photons=2000, slab=1.0)
    assert slab.transmittance[0] > 0


def test_the_gil_is_released_during_lookups_and_bakes(table):
    """Another Python thread runs while a lookup or a bake runs in the native code."""
    rho = np.full(400_000, 0.8)

    def ticks_during(work):
        window, ticks = [], []

        def run():
            start = time.perf_counter()
            work()
            window.extend([start, time.perf_counter()])

        worker = threading.Thread(target=run)
        worker.start()
        while worker.is_alive():
            ticks.append(time.perf_counter())
        worker.join()
        start, end = window
        return sum(start < t < end for t in ticks)

    assert ticks_during(lambda: table.eval(rho, 0.5, 1.0, 0.0)) > 100
    assert ticks_during(lambda: quiet(bz.bake, 1.33, grid=(16, 6, 16), threads=1)) > 100


def test_a_check_that_saw_no_region_says_so_and_inspect_too(cli, tmp_path):
    """ρ′ nodes only below the check's first band (0.001): no region checked is neither a
    finding of 0 regions above the bound nor a pass."""
    grid = {"rho": [0.0, 0.0005], "theta": [0.0, 0.5, 1.0, 1.5], "r": [0.0, 0.5, 1.0, 2.0, 4.0]}
    path = tmp_path / "dark.bssrdf"
    note = "no region of the check lies in the table's albedo rows (it covers rho' from 1e-3 to 1): nothing was checked"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        library = bz.bake(1.33, grid, path=path)
    messages = [str(w.message) for w in caught]
    assert messages == [f'the table at eta = 1.33: {note}: see the library\'s provenance["accuracy"]']
    assert library.provenance["accuracy"]["tables"][0]["regions"] == []
    inspected = cli("inspect", path)
    assert "    eta 1.33: bound mean 1 %" in inspected
    assert f"      {note}\n" in inspected
    assert "theta deg" not in inspected  # no empty table of regions
