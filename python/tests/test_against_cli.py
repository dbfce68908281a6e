"""Values bit for bit as the Rust API gives them, through the `bssrdf` command: its output
prints every float in its shortest round-trip form, which Python parses back exactly."""

import csv
import io
import json
import math
import warnings

import numpy as np
import pytest

import bssrdf_zoo as bz
from conftest import SplitMix64, radians


def points(rng, count, rho_range=(0.05, 1.0)):
    """Random (rho, theta_deg, r, phi_deg), with a few edge cases (nodes, r = 0, the axis ends)."""
    rho = rng.uniform(*rho_range, count)
    theta_deg = rng.uniform(0.0, 90.0, count)
    r = np.exp(rng.uniform(np.log(1e-4), np.log(300.0), count))
    phi_deg = rng.uniform(-180.0, 180.0, count)
    rho[:3], theta_deg[:3], r[:3], phi_deg[:3] = [0.0, 1.0, 0.5], [0.0, 90.0, 60.0], [0.0, 1.0, 0.0], [0.0, 180.0, -180.0]
    return rho, theta_deg, r, phi_deg


def write_points(path, rho, theta_deg, r, phi_deg):
    with open(path, "w") as f:
        f.write("rho,theta_deg,r,phi_deg\n")
        for row in zip(rho, theta_deg, r, phi_deg):
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def cli_values(cli, *args):
    """The values of `bssrdf eval … --json`; where it diverges (+inf at r = 0), its `limit`."""
    rows = [json.loads(line) for line in cli("eval", *args, "--json").splitlines()]
    return np.array([float(row["limit"]) if row["value"] is None else row["value"] for row in rows])


@pytest.mark.parametrize("which", ["table", "two_lobe_table"])
def test_eval_equals_the_command_bit_for_bit(cli, library_path, request, tmp_path, which):
    table = request.getfixturevalue(which)
    rho, theta_deg, r, phi_deg = points(np.random.default_rng(1), 400)
    path = tmp_path / "points.csv"
    write_points(path, rho, theta_deg, r, phi_deg)
    expected = cli_values(cli, library_path, "--eta", table.eta, "--points", path)
    theta = np.array([radians(t) for t in theta_deg])
    phi = np.array([radians(p) for p in phi_deg])
    got = table.eval(rho, theta, r, phi)
    assert got.tobytes() == expected.tobytes()


def test_perpendicular_and_table_models_equal_the_command(cli, library_path, table, tmp_path):
    rho, theta_deg, r, phi_deg = points(np.random.default_rng(2), 60)
    path = tmp_path / "points.csv"
    write_points(path, rho, theta_deg, r, phi_deg)
    theta = [radians(t) for t in theta_deg]
    phi = [radians(p) for p in phi_deg]
    for model in ["table", "perpendicular"]:
        expected = cli_values(cli, library_path, "--eta", table.eta, "--model", model, "--points", path)
        got = bz.models.eval(model, rho, theta, r, phi, table=table)
        assert got.tobytes() == expected.tobytes(), model


@pytest.mark.parametrize("model", ["dipole", "dirpole", "burley", "pbd", "pbd-fast"])
def test_models_equal_the_command(cli, tmp_path, model):
    rho, theta_deg, r, phi_deg = points(np.random.default_rng(3), 40)
    path = tmp_path / "points.csv"
    write_points(path, rho, theta_deg, r, phi_deg)
    expected = cli_values(cli, "--model", model, "--eta", 1.2, "--points", path)
    got = bz.models.eval(
        model, rho, [radians(t) for t in theta_deg], r, [radians(p) for p in phi_deg], eta=1.2
    )
    assert got.tobytes() == expected.tobytes()


def test_the_walk_model_equals_the_command(cli, tmp_path):
    path = tmp_path / "points.csv"
    write_points(path, [0.8, 0.8], [30.0, 30.0], [0.5, 2.0], [0.0, 90.0])
    expected = cli_values(cli, "--model", "mc", "--points", path)
    got = bz.models.eval("mc", 0.8, radians(30.0), [0.5, 2.0], [0.0, radians(90.0)])
    assert got.tobytes() == expected.tobytes()


def test_dirpole_with_the_authors_fits_equals_the_command(cli):
    out = cli("eval", "--model", "dirpole", "--fresnel-moments", "authors", "--rho", 0.7, "--theta", 40, "--r", 0.3, "--phi", 20, "--json")
    expected = json.loads(out)["value"]
    got = bz.models.eval("dirpole", 0.7, radians(40), 0.3, radians(20), moments="authors")
    assert got == expected


def test_samples_equal_the_command(cli, library_path, table):
    rows = list(csv.DictReader(io.StringIO(cli("sample", library_path, "--eta", table.eta, "--rho", 0.9, "--theta", 35, "-n", 200, "--seed", 7))))
    rng = SplitMix64(7)
    u = np.array([[rng.next_f64(), rng.next_f64()] for _ in rows])
    r, phi, pdf = table.sample(0.9, radians(35), u[:, 0], u[:, 1])
    assert all(pdf > 0)
    assert r.tolist() == [float(row["r"]) for row in rows]
    assert [math.degrees(p) for p in phi] == [float(row["phi_deg"]) for row in rows]
    assert pdf.tolist() == [float(row["pdf"]) for row in rows]


def test_path_samples_equal_the_command(cli, library_path, table):
    out = cli("sample", library_path, "--eta", table.eta, "--rho", 0.6, "--path-tracing", "-n", 100, "--seed", 3)
    rows = list(csv.DictReader(io.StringIO(out)))
    rng = SplitMix64(3)
    u = np.array([[rng.next_f64() for _ in range(4)] for _ in rows])
    theta, r, phi, phi_prime, pdf_theta, pdf = table.sample_path(0.6, *u.T)
    assert [math.degrees(t) for t in theta] == [float(row["theta_deg"]) for row in rows]
    assert r.tolist() == [float(row["r"]) for row in rows]
    assert [math.degrees(p) for p in phi_prime] == [float(row["phi_prime_deg"]) for row in rows]
    assert pdf.tolist() == [float(row["pdf"]) for row in rows]


def test_walk_equals_the_command(cli, tmp_path):
    profile = tmp_path / "profile.csv"
    cli("walk", "--albedo", 0.95, "--g", 0.3, "--eta", 1.4, "--theta", 45, "--photons", 5000, "--seed", 11, "--bins", "0.05,20,12,8", "--profile", profile, "--quiet")
    w = bz.walk(0.95, g=0.3, eta=1.4, theta=radians(45), photons=5000, seed=11, bins=(0.05, 20.0, 12, 8))
    rows = list(csv.DictReader(open(profile)))
    assert len(rows) == w.total.size
    for name in ["single", "single_stderr", "multiple", "multiple_stderr", "total", "total_stderr"]:
        assert getattr(w, name).ravel().tolist() == [float(row[name]) for row in rows], name
    assert w.r_edges[:-1].tolist() == [float(row["r_lo"]) for row in rows[:: w.total.shape[1]]]


def test_a_bake_writes_the_commands_file_byte_for_byte(cli, tmp_path):
    ours, theirs = tmp_path / "ours.bssrdf", tmp_path / "theirs.bssrdf"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bz.bake_materials(["skin1"], "coarse", path=ours)
    cli("bake", "skin1", "--grid", "coarse", "--accept-error", "-o", theirs, "--quiet")
    assert ours.read_bytes() == theirs.read_bytes()
