"""Zero-copy, read-only views of a table's stored arrays."""

import gc
import re
import os

import numpy as np
import pytest

import bssrdf_zoo as bz


def test_views_have_the_tables_shapes_and_values(table, two_lobe_table):
    n_rho, n_theta, n_r = table.dims
    assert table.params.shape == (n_rho, n_theta, n_r, 3) and table.params.dtype == np.float32
    assert table.radial_cdf.shape == (n_rho, n_theta, n_r)
    assert table.theta_cdf.shape == (n_rho, n_theta)
    assert table.harmonics is None and not table.two_lobes
    assert two_lobe_table.harmonics.shape == two_lobe_table.dims + (2,)
    assert table.rho_nodes.shape == (n_rho,) and table.r_nodes.shape == (n_r,)
    # At a node every stored value comes back exactly (docs/table.md): the last node of the
    # radial CDF is the effective albedo there.
    rho, theta = table.rho_nodes.astype(float), table.theta_nodes.astype(float)
    looked_up = table.effective_albedo(rho[:, None], theta[None, :])
    assert np.array_equal(looked_up, np.maximum(table.radial_cdf[:, :, -1].astype(float), 0))


def test_views_are_read_only_and_stay_so(table):
    view = table.params
    assert not view.flags.writeable and not view.flags.owndata
    with pytest.raises(ValueError):
        view[0, 0, 0, 0] = 1.0
    with pytest.raises(ValueError):
        view.flags.writeable = True


def test_views_share_the_files_memory(library_path):
    library = bz.Library.open(library_path)
    a, b = library.tables[0].params, library.tables[0].params
    assert np.shares_memory(a, b)
    if os.path.exists("/proc/self/maps"):
        # The view's data lies in a mapping of the file itself.
        address = a.ctypes.data
        spans = [
            [int(x, 16) for x in line.split()[0].split("-")]
            for line in open("/proc/self/maps")
            if line.rstrip().endswith(str(library_path))
        ]
        assert any(lo <= address < hi for lo, hi in spans)
    read = bz.Library.read(library_path)
    assert not read.is_mapped and library.is_mapped
    assert np.array_equal(read.tables[0].params, a)


def test_a_view_keeps_the_file_alive(library_path):
    library = bz.Library.open(library_path)
    view = library.tables[0].radial_cdf
    expected = view.copy()
    del library
    gc.collect()
    assert np.array_equal(view, expected)
    assert view.base is not None


def test_every_valid_vector_opens_and_a_table_without_lookups_says_why(data_dir):
    # The format allows a table no lookup can interpolate (the spec's example has one albedo
    # node): the file opens, its record and arrays read, and only its lookups are refused
    for path in sorted((data_dir / "valid").glob("*.bssrdf")):
        bz.Library.open(path)
    library = bz.Library.open(data_dir / "valid" / "spec-example.bssrdf")
    (table,) = library.tables
    assert table.dims == (1, 1, 2)
    assert table.r_nodes.tolist() == [0.5, 1.0]
    assert "no lookups" in repr(table)
    reason = "table 0: axis rho has 1 node(s): lookups interpolate along every axis and need at least 2"
    with pytest.raises(bz.FormatError, match=re.escape(reason)):
        table.eval(0.5, 0.0, 1.0, 0.0)
    with pytest.raises(bz.FormatError, match=re.escape(reason)):
        table.medium(0.5, 1.0)
    with pytest.raises(bz.FormatError, match=re.escape(reason)):
        library.channel("wax", "r")
    with pytest.raises(bz.FormatError, match=re.escape(reason)):
        bz.models.eval("table", 0.5, 0.0, 1.0, 0.0, table=table)


def test_a_walk_angular_table_names_its_model_and_walk(data_dir, table):
    # Format 1.5: the walk's g and component from the table's record; None for PBD tables
    (walk,) = bz.Library.open(data_dir / "valid" / "walk-table.bssrdf").tables
    assert (walk.model, walk.walk_g, walk.walk_component) == ("walk-angular", 0.75, "total")
    assert walk.two_lobes and "walk g 0.75 total" in repr(walk)
    assert walk.eval(0.6, 0.5, 0.05, 0.0) > 0
    assert (table.model, table.walk_g, table.walk_component) == ("pbd-angular", None, None)
    assert "walk" not in repr(table)


def test_a_table_says_whether_its_nodes_hold_the_profile_less_the_ridge(data_dir, table):
    # Format 1.6: the record's ridge, 1 (flux) or 2 (flux and fluence); False and "none" for
    # tables of files without it
    for name, kind in [("ridge", "flux"), ("ridge-fluence", "flux+fluence")]:
        (ridge,) = bz.Library.open(data_dir / "valid" / f"{name}.bssrdf").tables
        assert ridge.ridge is True and ridge.ridge_kind == kind and ridge.eta == 1.0
        assert f", ridge {kind}" in repr(ridge)
        assert ridge.eval(0.6, 0.5, 0.05, 0.0) > 0
    assert table.ridge is False and table.ridge_kind == "none" and "ridge" not in repr(table)
    (walk,) = bz.Library.open(data_dir / "valid" / "walk-table.bssrdf").tables
    assert walk.ridge is False and walk.ridge_kind == "none"
