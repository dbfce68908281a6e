"""The magic(5) entry format/bssrdf.magic, run by file(1) over the conformance vectors.

Valid vectors are named with their version and table count; an invalid vector that keeps the
magic is still named (file(1) tells the type, not the validity) with the version its bytes
hold; files without the magic, those of tests/data/ and a few made here, are not.
Without file(1) the tests skip, saying so, unless BSSRDF_REQUIRE_FILE is set (as .ci/run
does), when they fail.
"""

import os
import shutil
import struct
import subprocess

import pytest

from vectors import DATA, FORMAT, INVALID, MAGIC, VALID, ids

NAME = "bssrdf-zoo table library"


@pytest.fixture(scope="session")
def file_cmd():
    found = shutil.which("file")
    if found is None:
        if os.environ.get("BSSRDF_REQUIRE_FILE"):
            pytest.fail("file(1) is not installed, and BSSRDF_REQUIRE_FILE is set")
        pytest.skip("file(1) is not installed: the magic(5) entry is not tested")
    return found


def describe(file_cmd, path, *options):
    """What `file -b -m format/bssrdf.magic` says of `path`; the entry must load cleanly."""
    run = subprocess.run(
        [file_cmd, "-b", *options, "-m", str(FORMAT / "bssrdf.magic"), str(path)],
        check=True, capture_output=True, text=True,
    )
    assert run.stderr == ""
    return run.stdout.strip()


# tests/data/README.md: versions; every vector but empty has one table; tiny-packed is zstd.
VALID_DESCRIPTIONS = {
    "aligned-4096": f"{NAME}, format 1.6, 1 table",
    "empty": f"{NAME}, format 1.6, 0 tables",
    "merged-roots": f"{NAME}, format 1.4, 1 table",
    "newer-minor": f"{NAME}, format 1.7, 1 table",
    "older-minor": f"{NAME}, format 1.0, 1 table",
    "ridge": f"{NAME}, format 1.6, 1 table",
    "ridge-fluence": f"{NAME}, format 1.6, 1 table",
    "signed-lobes": f"{NAME}, format 1.3, 1 table",
    "spec-example": f"{NAME}, format 1.6, 1 table",
    "tiny": f"{NAME}, format 1.6, 1 table",
    "tiny-packed": f"{NAME}, format 1.6, 1 table, zstd-compressed",
    "two-lobes": f"{NAME}, format 1.2, 1 table",
    "walk-table": f"{NAME}, format 1.6, 1 table",
}


def test_every_valid_vector_has_a_description():
    assert set(ids(VALID)) == set(VALID_DESCRIPTIONS)


@pytest.mark.parametrize("path", VALID, ids=ids(VALID))
def test_valid_vector(file_cmd, path):
    assert describe(file_cmd, path) == VALID_DESCRIPTIONS[path.stem]
    assert describe(file_cmd, path, "--mime-type") == "application/x-bssrdf"
    assert describe(file_cmd, path, "--extension") == "bssrdf"


@pytest.mark.parametrize("path", INVALID, ids=ids(INVALID))
def test_invalid_vector(file_cmd, path):
    data = path.read_bytes()
    said = describe(file_cmd, path)
    if data.startswith(MAGIC):
        major, minor = struct.unpack_from("<HH", data, 12)
        assert said.startswith(f"{NAME}, format {major}.{minor}")
    else:
        assert NAME not in said


def test_named_invalid_vectors(file_cmd):
    """The header faults file(1) shows: a newer major, a big-endian writer, no magic."""
    said = {p.stem: describe(file_cmd, p) for p in INVALID}
    assert said["unsupported-major"] == f"{NAME}, format 2.6"
    assert said["wrong-byte-order"] == f"{NAME}, format 1.6, big-endian (unsupported)"
    assert NAME not in said["bad-magic"]


OTHER_FILES = sorted(p for p in DATA.iterdir() if p.is_file())
ALMOST = {
    "png": b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR" + bytes(128),
    "last-magic-byte-changed": MAGIC[:-1] + b"\x01" + bytes(128),
    "magic-cut-short": MAGIC[:-1],
    "magic-after-one-byte": b"\0" + MAGIC + bytes(128),
    "empty": b"",
}


@pytest.mark.parametrize("path", OTHER_FILES, ids=[p.name for p in OTHER_FILES])
def test_other_test_data_is_not_named(file_cmd, path):
    assert NAME not in describe(file_cmd, path)


@pytest.mark.parametrize("name", sorted(ALMOST))
def test_almost_magic_is_not_named(file_cmd, tmp_path, name):
    path = tmp_path / name
    path.write_bytes(ALMOST[name])
    assert NAME not in describe(file_cmd, path)
