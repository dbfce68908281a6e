"""Lookups over numpy arguments: broadcasting, scalars, dtypes and layouts, world units against
the runtime's formulas, the channel handle, and the draws against their densities."""

import numpy as np
import pytest

import bssrdf_zoo as bz


def test_scalars_give_floats_and_arrays_broadcast(table):
    s = table.eval(0.9, 0.5, 1.0, 0.0)
    assert isinstance(s, float) and s > 0
    grid = table.eval(np.array([0.5, 0.9]), 0.5, np.array([[0.5], [1.0], [2.0]]), 0.0)
    assert grid.shape == (3, 2) and grid.dtype == np.float64
    assert grid[1, 1] == s
    r, phi, pdf = table.sample(0.9, [0.1, 0.7], 0.25, [[0.5], [0.75]])
    assert r.shape == phi.shape == pdf.shape == (2, 2)
    assert table.eval([], 0.5, 1.0, 0.0).shape == (0,)


def test_any_layout_and_dtype_gives_the_same_bits(table):
    rng = np.random.default_rng(5)
    rho, theta = rng.uniform(0, 1, (20, 30)), rng.uniform(0, 1.5, (20, 30))
    r, phi = rng.uniform(0, 5, (20, 30)), rng.uniform(-3, 3, (20, 30))
    expected = table.eval(rho, theta, r, phi)
    fortran = table.eval(*(np.asfortranarray(a) for a in (rho, theta, r, phi)))
    strided = table.eval(*(np.repeat(a, 2, axis=1)[:, ::2] for a in (rho, theta, r, phi)))
    listed = table.eval(rho.tolist(), theta.tolist(), r.tolist(), phi.tolist())
    assert fortran.tobytes() == strided.tobytes() == listed.tobytes() == expected.tobytes()
    pointwise = [table.eval(*p) for p in zip(rho.ravel(), theta.ravel(), r.ravel(), phi.ravel())]
    assert np.array(pointwise).tobytes() == expected.ravel().tobytes()
    as_float32 = table.eval(rho.astype(np.float32), 0.5, 1, 0)
    assert as_float32.tobytes() == table.eval(rho.astype(np.float32).astype(np.float64), 0.5, 1.0, 0.0).tobytes()
    # A float64 view at a byte offset into a buffer (not aligned) is read like any array
    misaligned = np.frombuffer(b"\0" + r.ravel().tobytes(), dtype=np.float64, offset=1, count=r.size)
    assert table.eval(rho.ravel(), theta.ravel(), misaligned, phi.ravel()).tobytes() == expected.ravel().tobytes()


def test_broadcasts_too_large_to_hold_are_errors_not_crashes(table):
    # A broadcast view needs no memory; its results would (8 TiB): MemoryError, not an abort
    with pytest.raises(MemoryError, match="no memory for 1099511627776 values"):
        table.eval(0.5, 0.3, np.broadcast_to(1.0, (2**40,)), 0.1)
    # More points than an index counts: a ValueError, not an overflow
    with pytest.raises(ValueError, match="more points than an index can count"):
        table.eval(np.broadcast_to(0.5, (2**33, 1)), 0.3, np.broadcast_to(1.0, (1, 2**33)), 0.1)


def test_world_units_are_the_runtimes_formulas(table):
    """World (crates/runtime/src/table/lookup/world.rs): S = σ′t² S(σ′t r_mm), pdf likewise."""
    rng = np.random.default_rng(6)
    rho, theta = rng.uniform(0, 1, 500), rng.uniform(0, 1.5, 500)
    r_mm, phi, st = rng.uniform(0, 3, 500), rng.uniform(-3, 3, 500), rng.uniform(0.1, 10, 500)
    world = table.eval(rho, theta, r_mm, phi, sigma_t=st)
    assert world.tobytes() == (st * st * table.eval(rho, theta, st * r_mm, phi)).tobytes()
    pdf = table.pdf(rho, theta, r_mm, phi, sigma_t=st)
    assert pdf.tobytes() == (st * st * table.pdf(rho, theta, st * r_mm, phi)).tobytes()
    assert table.eval(rho, theta, r_mm, phi, sigma_t=1.0).tobytes() == table.eval(rho, theta, r_mm, phi).tobytes()


def test_reduced_units_are_world_units_at_unit_extinction(table):
    """A medium of sigma_t' = 1 (ChannelLookup, through World) gives the reduced lookups' bits."""
    medium = table.medium(0.7, 1.0)
    rng = np.random.default_rng(11)
    theta, r, phi = rng.uniform(0, 1.5, 400), rng.uniform(0, 30, 400), rng.uniform(-3, 3, 400)
    assert medium.eval(theta, r, phi).tobytes() == table.eval(0.7, theta, r, phi).tobytes()
    assert medium.pdf(theta, r, phi).tobytes() == table.pdf(0.7, theta, r, phi).tobytes()
    u = rng.uniform(size=(4, 400))
    for got, want in zip(medium.sample(theta, u[0], u[1]), table.sample(0.7, theta, u[0], u[1])):
        assert got.tobytes() == want.tobytes()
    for got, want in zip(medium.sample_path(*u), table.sample_path(0.7, *u)):
        assert got.tobytes() == want.tobytes()


def test_a_channel_is_its_medium_on_its_table(library, two_lobe_table):
    """ChannelLookup: bit for bit World at the material's rho' and sigma_t'."""
    skin = library.material("skin1")
    assert skin.eta == two_lobe_table.eta
    rng = np.random.default_rng(7)
    theta, r_mm, phi = rng.uniform(0, 1.5, 300), rng.uniform(0, 4, 300), rng.uniform(-3, 3, 300)
    for name in ["r", "green", 2]:
        ch = library.channel("skin1", name)
        assert ch.table.index == two_lobe_table.index
        expected = two_lobe_table.eval(ch.rho_prime, theta, r_mm, phi, sigma_t=ch.sigma_t)
        assert ch.eval(theta, r_mm, phi).tobytes() == expected.tobytes()
        assert ch.pdf(theta, r_mm, phi).tobytes() == two_lobe_table.pdf(ch.rho_prime, theta, r_mm, phi, sigma_t=ch.sigma_t).tobytes()
        u = rng.uniform(0, 1, (2, 50))
        got = ch.sample(theta[:50], *u)
        want = two_lobe_table.sample(ch.rho_prime, theta[:50], *u, sigma_t=ch.sigma_t)
        assert all(g.tobytes() == w.tobytes() for g, w in zip(got, want))
        assert ch.effective_albedo(theta).tobytes() == two_lobe_table.effective_albedo(ch.rho_prime, theta).tobytes()
    medium = two_lobe_table.medium(0.8, 2.5)
    assert medium.eval(0.3, 0.5, 0.0) == two_lobe_table.eval(0.8, 0.3, 0.5, 0.0, sigma_t=2.5)
    assert skin.channel("b").rho_prime == library.channel("skin1", "blue").rho_prime


@pytest.mark.parametrize("sigma_t", [None, 3.0])
def test_draws_have_the_density_pdf_gives(table, sigma_t):
    rng = np.random.default_rng(8)
    rho, theta = rng.uniform(0.1, 1, 2000), rng.uniform(0, 1.4, 2000)
    r, phi, pdf = table.sample(rho, theta, rng.uniform(size=2000), rng.uniform(size=2000), sigma_t=sigma_t)
    drawn = pdf > 0
    assert drawn.mean() > 0.99
    again = table.pdf(rho, theta, r, phi, sigma_t=sigma_t)
    assert np.allclose(again[drawn], pdf[drawn], rtol=1e-9, atol=0)
    assert np.all((r[~drawn] == 0) & (phi[~drawn] == 0))


def test_path_draws_have_their_densities(table):
    rng = np.random.default_rng(9)
    u = rng.uniform(size=(4, 1000))
    theta, r, phi, phi_prime, pdf_theta, pdf = table.sample_path(0.7, *u)
    assert np.all(pdf > 0) and np.all((theta >= 0) & (theta <= np.pi / 2))
    assert np.allclose(pdf_theta, table.pdf_theta(0.7, theta), rtol=1e-12)
    given = table.pdf(0.7, theta, r, phi)
    assert np.allclose(pdf, pdf_theta * given / (2 * np.pi), rtol=1e-9)
    assert np.all(np.abs(phi_prime) <= np.pi)


def test_importance_weights_estimate_the_effective_albedo(table):
    """S/pdf over the draws averages ρ_eff: on the default grid to about 1e-3 (docs/table.md), on
    this coarse one, whose refined evaluation departs further from the sampler's spline, to 2 %."""
    rng = np.random.default_rng(10)
    r, phi, pdf = table.sample(0.8, 0.6, rng.uniform(size=5000), rng.uniform(size=5000))
    weights = table.eval(0.8, 0.6, r, phi) / pdf
    assert abs(weights.mean() / table.effective_albedo(0.8, 0.6) - 1) < 2e-2


def test_an_albedo_within_f32_rounding_of_an_end_row_is_the_row(cli, tmp_path):
    """A scene bake keeps rows from 0.5 to 0.9, stored in f32: the ends as numpy prints them
    (float32's shortest form) and 0.9 are looked up at the rows, bit for bit; beyond f32
    rounding they are refused, naming the albedos the lookups take."""
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[[material]]\nname = "white-grapefruit-juice"\nalbedo_range = [[0.5, 0.9], [0.5, 0.9], [0.5, 0.9]]\n'
    )
    path = tmp_path / "s.bssrdf"
    cli("bake", "--scene", scene, "--grid", "coarse", "-q", "-o", path)
    table = bz.Library.open(path).tables[0]
    nodes = table.rho_nodes
    for node in (nodes[0], nodes[-1]):
        printed = float(repr(node).removeprefix("np.float32(").removesuffix(")"))
        exact = float(node)
        assert table.eval(printed, 0.5, 1.0, 0.2) == table.eval(exact, 0.5, 1.0, 0.2) > 0
        assert table.pdf(printed, 0.5, 1.0, 0.2) == table.pdf(exact, 0.5, 1.0, 0.2) > 0
    beyond = float(nodes[-1]) + 1e-6
    with pytest.raises(ValueError, match=r"is outside \[.*\], the albedo rows the table keeps"):
        table.eval(beyond, 0.5, 1.0, 0.2)
