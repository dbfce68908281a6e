"""Every refusal as a Python exception with the library's message."""

import re
import warnings

import numpy as np
import pytest

import bssrdf_zoo as bz


def test_files_the_system_refuses_are_os_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="no-such-file"):
        bz.Library.open(tmp_path / "no-such-file.bssrdf")
    with pytest.raises(OSError):
        bz.Library.read(tmp_path)


def test_every_invalid_conformance_vector_is_a_format_error(data_dir):
    vectors = sorted((data_dir / "invalid").glob("*.bssrdf"))
    assert vectors
    for path in vectors:
        for mmap in (True, False):
            with pytest.raises(bz.FormatError) as caught:
                bz.Library.open(path, mmap=mmap)
            assert isinstance(caught.value, ValueError)
            assert str(caught.value), path.name


def test_bad_values_are_value_errors_naming_them(library, table):
    with pytest.raises(ValueError, match=r"rho' = 1.5 is outside \[0, 1\]"):
        table.eval(1.5, 0.5, 1.0, 0.0)
    with pytest.raises(ValueError, match=r"at index \(1, 0\): theta = 2"):
        table.eval(0.5, np.array([[0.5, 0.5], [2.0, 0.5]]), 1.0, 0.0)
    with pytest.raises(ValueError, match="not a finite number"):
        table.pdf(np.nan, 0.5, 1.0, 0.0)
    with pytest.raises(ValueError, match="sigma_t"):
        table.eval(0.5, 0.5, 1.0, 0.0, sigma_t=0.0)
    with pytest.raises(ValueError, match="do not broadcast"):
        table.eval([0.1, 0.2], [0.1, 0.2, 0.3], 1.0, 0.0)
    # Every lookup of a channel refuses theta outside the table, pdf_theta included
    green = library.channel("skin1", "g")
    for call in (green.pdf_theta, green.effective_albedo, table.medium(0.5, 1.0).pdf_theta):
        for bad in (np.nan, 2.0, -0.1):
            with pytest.raises(ValueError, match="theta"):
                call(bad)
    # An exit point no lookup can mean: r NaN, negative or infinite, phi not finite
    for r, phi, needle in [
        (np.nan, 0.0, "r = NaN"),
        (-1.0, 0.0, "r = -1"),
        (np.inf, 0.0, "r = inf"),
        (1.0, np.nan, "phi = NaN"),
        (1.0, -np.inf, "phi = -inf"),
    ]:
        for call in (table.eval, table.pdf):
            with pytest.raises(ValueError, match=needle):
                call(0.5, 0.5, r, phi)
        with pytest.raises(ValueError, match=needle):
            green.eval(0.5, r, phi)
    assert table.eval(0.5, 0.5, 1e6, 0.0) == 0.0  # beyond the last radius node: a value, 0
    # A sampler's uniforms are in [0, 1): NaN, 1 or beyond is a broken random stream, refused
    for bad in (np.nan, 1.0, 1.5, -0.5, 2.0):
        with pytest.raises(ValueError, match=r"u2 = .* is outside \[0, 1\)"):
            table.sample(0.5, 0.5, 0.5, bad)
        with pytest.raises(ValueError, match=r"u1 = .* is outside \[0, 1\)"):
            green.sample(0.5, bad, 0.5)
        with pytest.raises(ValueError, match=r"u4 = .* is outside \[0, 1\)"):
            table.sample_path(0.5, 0.1, 0.2, 0.3, bad)
        with pytest.raises(ValueError, match=r"u3 = .* is outside \[0, 1\)"):
            green.sample_path(0.1, 0.2, bad, 0.4)
    with pytest.raises(ValueError, match="skin1"):
        library.channel("marble", "r")
    with pytest.raises(ValueError, match="channel"):
        library.channel("skin1", "x")
    with pytest.raises(ValueError, match="no table 9"):
        library.table(9)
    with pytest.raises(ValueError, match="unknown model"):
        bz.models.eval("nope", 0.5, 0.5, 1.0, 0.0)
    with pytest.raises(ValueError, match="theta"):
        bz.models.eval("dipole", 0.5, 2.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="grid"):
        bz.bake(1.33, grid="huge")
    with pytest.raises(ValueError, match=r"eta = 1.33 is given twice \(at positions 0 and 2\)"):
        bz.bake([1.33, 1.5, 1.33], grid=(4, 4, 8))
    # Grid counts are checked before anything is allocated, never silently raised
    for grid, needle in [
        ((3, 3, 2**40), r"grid's n_r = 1099511627776 is outside \[4, 65536\]"),
        ((3, 3, 70000), r"n_r = 70000 is outside"),
        ((1, 3, 6), r"grid's n_rho = 1 is outside \[2, 65536\]"),
        ((4.0, 4, 8), r"grid's n_rho = 4.0 is not a whole number \(an int in \[2, 65536\]\)"),
        ((3, 1, 6), r"n_theta = 1 is outside"),
        ((3, 3, 3), r"n_r = 3 is outside"),
        ((3, -3, 6), r"n_theta = -3 is outside"),
    ]:
        with pytest.raises(ValueError, match=needle):
            bz.bake(1.33, grid=grid)
    for threads in (0, 1025, 100000):
        with pytest.raises(ValueError, match=rf"threads = {threads} is outside \[1, 1024\]"):
            bz.bake(1.33, grid=(3, 3, 6), threads=threads)
    # A material's dict: no unknown key (a default would take its place), one kind of parameters
    wax = {"name": "wax", "sigma_s": 2.0, "sigma_a": 0.01, "eta": 1.4}
    with pytest.raises(ValueError, match='unknown key "G"'):
        bz.bake_materials([{**wax, "G": 0.9}], grid=(3, 3, 6))
    with pytest.raises(ValueError, match="both sigma_s/sigma_a and reflectance/mfp"):
        bz.bake_materials([{**wax, "reflectance": 0.5, "mfp": 1.0}], grid=(3, 3, 6))
    with pytest.raises(ValueError, match="eta"):
        bz.bake(7.0, grid=(6, 4, 10))
    with pytest.raises(ValueError, match="albedo"):
        bz.walk(1.5, photons=10)
    with pytest.raises(ValueError):
        bz.bake_materials(["no-such-material"], grid=(6, 4, 10))


def test_negative_or_huge_whole_numbers_are_value_errors_naming_the_argument(library):
    # pyo3's own conversion said OverflowError "can't convert negative int to unsigned"
    for call, needle in [
        (lambda: bz.walk(0.9, photons=10, seed=-1), "seed = -1 is negative"),
        (lambda: bz.walk(0.9, photons=-5), "photons = -5 is negative"),
        (lambda: bz.walk(0.9, photons=2**70), "photons = 1180591620717411303424 is too large"),
        (lambda: bz.walk(0.9, photons=10, threads=-1), "threads = -1 is negative"),
        (lambda: bz.models.eval("mc", 0.5, 0.0, 1.0, 0.0, photons=-1), "photons = -1 is negative"),
        (lambda: bz.bake(1.33, (4, 3, 8), threads=-2), "threads = -2 is negative"),
        (lambda: library.table(-1), "index = -1 is negative"),
        (lambda: bz.walk(0.9, photons=10, bins=(0.1, 10.0, -3, 4)), "bins[2] = -3 is negative"),
        (lambda: bz.bake(1.33, (4, 3, 8), lobes=-1), "lobes = -1 is not one of None (by eta), 1, 2"),
        (lambda: bz.bake(1.33, (4, 3, 8), lobes=2**80), "lobes = 1208925819614629174706176 is not one"),
    ]:
        with pytest.raises(ValueError, match=re.escape(needle)):
            call()
    # Not an int at all: pyo3's TypeError, which names the argument
    with pytest.raises(TypeError, match="seed"):
        bz.walk(0.9, photons=10, seed="x")
    assert bz.walk(0.9, photons=10, threads=None).photons == 10


def test_lookups_beyond_the_critical_angle_draw_nothing():
    with pytest.warns(UserWarning):  # this grid misses the check's bound
        table = bz.bake(0.8, grid=(6, 4, 10), theta_sampling=False).tables[0]
    r, phi, pdf = table.sample(0.9, 1.4, 0.5, 0.5)
    assert (r, phi, pdf) == (0.0, 0.0, 0.0)
    assert table.eval(0.9, 1.4, 1.0, 0.0) == 0.0
    with pytest.raises(ValueError, match="theta sampling"):
        table.sample_path(0.9, 0.1, 0.2, 0.3, 0.4)


def test_arguments_the_call_would_not_use_are_refused(table):
    """No argument accepted and ignored, and every point checked, lit or not."""
    for kwargs, needle in [
        ({"table": table}, "table= is the table models'"),
        ({"photons": 7}, "photons= is the mc model's"),
        ({"seed": 3}, "seed= is the mc model's"),
        ({"grid": (4, 4, 8)}, "grid= is the bake's of the table and perpendicular models"),
    ]:
        with pytest.raises(ValueError, match=re.escape(needle)):
            bz.models.eval("dipole", 0.5, 0.3, 1.0, 0.0, **kwargs)
    with pytest.raises(ValueError, match=re.escape("grid= is the bake's, and table= is given")):
        bz.models.eval("table", 0.5, 0.3, 1.0, 0.0, table=table, grid=(4, 4, 8))
    with pytest.raises(ValueError, match="conflicts with table="):
        bz.models.eval("table", 0.5, 0.3, 1.0, 0.0, table=table, moments="pbrt")
    with pytest.raises(ValueError, match="moments= is the diffusion models'"):
        bz.models.eval("mc", 0.5, 0.3, 1.0, 0.0, moments="exact")
    # The grid's counts: checked, named, whatever their size
    for grid, needle in [
        ((0, 0, 0), r"grid's n_rho = 0 is outside \[2, 65536\]"),
        ((-1, 2, 4), r"grid's n_rho = -1 is outside \[2, 65536\]"),
        ((2**70, 2, 4), r"grid's n_rho = 1180591620717411303424 is outside"),
    ]:
        with pytest.raises(ValueError, match=needle):
            bz.models.eval("table", 0.5, 0.3, 1.0, 0.0, grid=grid)
    # Points where no light enters (eta < 1 beyond the critical angle) are 0 only in the domain
    assert bz.models.eval("dipole", 0.5, 1.5, 1.0, 0.0, eta=0.8) == 0.0
    for kwargs, needle in [
        ({"rho": 5.0}, r"rho = 5 is outside \[0, 1\]"),
        ({"rho": np.nan}, "rho"),
        ({"sigma_t": np.nan}, "sigma_t = NaN is outside"),
        ({"sigma_t": -1.0}, "sigma_t = -1 is outside"),
    ]:
        args = {"rho": 0.5, **kwargs}
        rho = args.pop("rho")
        with pytest.raises(ValueError, match=needle):
            bz.models.eval("dipole", rho, 1.5, 1.0, 0.0, eta=0.8, **args)


def test_dicts_take_their_keys_only_and_bakes_need_something_to_bake():
    grid = {"rho": [0.0, 0.5, 1.0], "theta": [0.0, 0.8, 1.5707963], "r": [0.0, 0.5, 1.0, 2.0]}
    with pytest.raises(ValueError, match='the grid\'s dict has an unknown key "foo"'):
        bz.bake(1.33, {**grid, "foo": 1})

    class LooksLikeG:
        def __str__(self):
            return "g"

        def __hash__(self):
            return 1

        def __eq__(self, other):
            return other is self

    material = {"name": "m", "eta": 1.33, "sigma_s": [1.0, 1.0, 1.0], "sigma_a": [0.1, 0.1, 0.1]}
    with pytest.raises(ValueError, match="unknown key"):
        bz.bake_materials([{**material, LooksLikeG(): [0.5, 0.5, 0.5]}], "coarse")
    with pytest.raises(ValueError, match="eta is an empty sequence"):
        bz.bake([], "coarse")
    with pytest.raises(ValueError, match="materials and etas are both empty"):
        bz.bake_materials([], "coarse")


def test_arrays_of_more_dimensions_than_taken_and_negative_zero(table):
    deep = np.zeros((1,) * 33) + 0.5
    with pytest.raises(ValueError, match="rho has 33 dimensions: at most 32"):
        table.eval(deep, 0.3, 1.0, 0.0)
    # -0 in is 0, and no -0 comes out
    assert np.signbit(bz.models.eval("dipole", -0.0, 0.3, 1.0, 0.0)) == np.False_
    assert np.signbit(table.medium(-0.0, 2.0).rho_prime) == np.False_


def test_a_dict_material_takes_no_built_in_name():
    """As `bssrdf bake --name` and a scene's inline material refuse it: in any case, an alias
    too (`bssrdf eval --material SKIN1` would find the built-in, not the record)."""
    coefficients = {"sigma_s": 2.0, "sigma_a": 0.01, "eta": 1.33}
    artist = {"reflectance": 0.5, "mfp": 1.0, "eta": 1.33}
    for name, builtin in [("skin1", "skin1"), ("SKIN1", "skin1"), ("skimmilk", "skim-milk")]:
        for parameters in (coefficients, artist):
            needle = f'names the library material "{builtin}"'
            with pytest.raises(ValueError, match=re.escape(needle)):
                bz.bake_materials([{"name": name, **parameters}], "coarse")
    # The built-in by its name is the built-in material, not a shadow of it
    assert "skin1" in bz.builtin_materials()


def test_records_the_file_would_refuse_are_value_errors_before_the_bake():
    """A duplicate or a source too long is the caller's argument, not an invalid file read
    (FormatError); refused before any table is baked: the grid's own refusal, which the bake
    raises, does not come first."""
    wax = {"name": "wax", "sigma_s": 2.0, "sigma_a": 0.01, "eta": 1.4}
    unbakeable = {"rho": [0.5, 0.2], "theta": [0.0, 0.5], "r": [0.0, 0.5, 1.0, 2.0]}
    for materials, needle in [
        ([wax, wax], 'material "wax" is listed twice'),
        (["skin1", "skin1"], 'material "skin1" is listed twice'),
        (["skin1", "Skin1"], 'material "skin1" is listed twice'),
        ([{**wax, "source": "x" * 257}], 'material "wax": source is 257 bytes'),
        ([{**wax, "source": "a\nb"}], "control character"),
    ]:
        for grid in ((3, 3, 6), unbakeable):
            with pytest.raises(ValueError, match=re.escape(needle)) as caught:
                bz.bake_materials(materials, grid)
            assert not isinstance(caught.value, bz.FormatError)
    # 256 bytes are kept
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a grid this coarse misses the check's bound
        library = bz.bake_materials([{**wax, "source": "x" * 256}], (3, 3, 6))
    assert library.material("wax").source == "x" * 256


def test_g_is_refused_by_the_models_without_a_walk(table):
    """g sets the walk's phase function: the diffusion and table models have none, and took it
    without a bit of difference."""
    for name in ["dipole", "dirpole", "burley", "pbd", "pbd-fast", "table", "perpendicular"]:
        extra = {"table": table} if name in ("table", "perpendicular") else {}
        needle = f"g= is the mc and walk-table models' (the walk's anisotropy), not the {name} model's"
        for g in (0.99, 0.0):
            with pytest.raises(ValueError, match=re.escape(needle)):
                bz.models.eval(name, 0.5, 0.3, 1.0, 0.0, g=g, **extra)
        # Not given: the default call
        assert bz.models.eval(name, 0.5, 0.3, 1.0, 0.0, **extra) > 0.0
    assert bz.models.eval("mc", 0.5, 0.3, 1.0, 0.0, g=0.5, photons=100) >= 0.0


def test_an_output_path_is_checked_before_the_bake(tmp_path, library):
    """As `bssrdf bake -o`: named as given (not the temporary file), before any work (the
    grid's own refusal, raised by the bake, does not come first), nothing left behind."""
    unbakeable = {"rho": [0.5, 0.2], "theta": [0.0, 0.5], "r": [0.0, 0.5, 1.0, 2.0]}
    (tmp_path / "file").write_bytes(b"")
    (tmp_path / "folder").mkdir()
    cases = [
        (tmp_path / "nosuch" / "x.bssrdf", FileNotFoundError, "its folder"),
        (str(tmp_path / "x") + "/", IsADirectoryError, "the path names a folder (it ends in /)"),
        (tmp_path / "folder", IsADirectoryError, "it is a folder, not a regular file"),
        (tmp_path / "file" / "x.bssrdf", NotADirectoryError, "Not a directory"),
    ]
    for path, kind, reason in cases:
        needle = f"cannot write {path}: {reason}"
        for call in (
            lambda: bz.bake(1.33, unbakeable, path=path),
            lambda: bz.bake_materials(["skin1"], unbakeable, path=path),
            lambda: library.write(path),
        ):
            with pytest.raises(kind, match=re.escape(needle)) as caught:
                call()
            assert ".tmp" not in str(caught.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "folder"]
    assert list((tmp_path / "folder").iterdir()) == []
