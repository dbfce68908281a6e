"""The parser generated from format/bssrdf.ksy against the conformance vectors.

Every valid vector parses, shows what tests/data/README.md (and format-spec.md section 16 for
spec-example) says it holds, and agrees field for field with the Rust reader's view of it
(`bssrdf inspect --json`). Every invalid vector either fails to parse, at the field given
below, or parses, for the reason given below: the .ksy checks single fields and shapes, not
CRCs, placement, feature bits or rules across fields (see its top-level doc).
"""

import hashlib
import io
import json
import os
import subprocess

import kaitaistruct
import pytest
import zstandard

from vectors import FORMAT, INVALID, REPO, VALID, Bssrdf, ids, kind_name, parse_fully

FILE_LEVEL = 0xFFFFFFFF


def test_generated_parser_is_current():
    """format/python/bssrdf.py was generated from the committed .ksy."""
    recorded = (FORMAT / "python" / "GENERATED_FROM").read_text().split()[0]
    actual = hashlib.sha256((FORMAT / "bssrdf.ksy").read_bytes()).hexdigest()
    assert recorded == actual, "format/bssrdf.ksy changed: regenerate (format/README.md)"


# --- What the manifest says of each valid vector ------------------------------------------

TINY_KINDS = [
    "tables", "materials", "provenance",
    "axis-rho", "axis-theta", "axis-r", "gwc-params", "radial-cdf", "theta-cdf",
]
TABLE_KINDS = ["axis-rho", "axis-theta", "axis-r", "gwc-params", "radial-cdf"]
TINY = {
    "version": (1, 6),
    "required_features": 0,
    "optional_features": 0,
    "alignment": 256,
    "section_kinds": TINY_KINDS,
    "codecs": {"none"},
    "table_dims": [(2, 2, 4)],
    "materials": 2,
    "albedo_ranges": 1,
    "table_record_size": 64,
    "table_walks": [("pbd-angular", None, None)],
    "table_ridges": ["none"],
}

# tests/data/README.md, table "valid/", one line per vector; section 16 of format-spec.md for
# spec-example. Keys a line does not state are left out.
MANIFEST = {
    "spec-example": {
        "version": (1, 6),
        "required_features": 1 << 1,
        "optional_features": 0,
        "alignment": 256,
        "section_kinds": ["tables", "materials"] + TABLE_KINDS,
        "codecs": {"none"},
        "table_dims": [(1, 1, 2)],
        "materials": 1,
    },
    "tiny": TINY,
    "tiny-packed": {**TINY, "required_features": 1 << 0, "codecs": {"zstd"}},
    "newer-minor": {
        **{k: v for k, v in TINY.items() if k != "optional_features"},
        "version": (1, 7),
        "optional_features_set": 1,
        "header_reserved_zero": False,
        "unknown_entry_flags": True,
        "table_record_size": 96,
        "section_kinds": TINY_KINDS + ["extension 0x7001"],
        "optional_extension": True,
    },
    "older-minor": {**TINY, "version": (1, 0)},
    "two-lobes": {
        **TINY,
        "version": (1, 2),
        "required_features": 1 << 2,
        "section_kinds": TINY_KINDS + ["gwc-harmonics"],
    },
    "signed-lobes": {
        **TINY,
        "version": (1, 3),
        "required_features": (1 << 2) | (1 << 3),
        "section_kinds": TINY_KINDS + ["gwc-harmonics"],
    },
    "merged-roots": {
        **TINY,
        "version": (1, 4),
        "required_features": (1 << 2) | (1 << 3) | (1 << 4),
        "section_kinds": TINY_KINDS + ["gwc-harmonics"],
    },
    "walk-table": {
        **TINY,
        "required_features": (1 << 2) | (1 << 4) | (1 << 5),
        "section_kinds": TINY_KINDS + ["gwc-harmonics"],
        "table_walks": [("walk-angular", "total", 0.75)],
    },
    "ridge": {
        **TINY,
        "required_features": 1 << 6,
        "table_ridges": ["flux"],
    },
    "ridge-fluence": {
        **TINY,
        "required_features": 1 << 6,
        "table_ridges": ["flux+fluence"],
    },
    "aligned-4096": {
        "alignment": 4096,
        "section_kinds": ["tables", "materials"] + TABLE_KINDS,
        "n_rho": [1],
        "materials": 0,
    },
    "empty": {
        "section_kinds": ["tables", "materials"],
        "table_dims": [],
        "materials": 0,
        "empty_sections": 2,
    },
}


def decoded_body(entry):
    """A section's body parsed by kind: as the generated parser gives it for codec 0; for
    codec 1, the zstd frames decoded and parsed with `section_body`, as the .ksy's doc says."""
    if entry.codec == Bssrdf.Codec.none:
        return entry.body
    reader = zstandard.ZstdDecompressor().stream_reader(
        io.BytesIO(entry.body), read_across_frames=True
    )
    raw = reader.read()
    assert len(raw) == entry.raw_len
    return Bssrdf.SectionBody(entry.kind, entry.dims, kaitaistruct.KaitaiStream(io.BytesIO(raw)))


def bodies(lib):
    """Every section's parsed body by (kind name, table index or None)."""
    out = {}
    for e in lib.directory:
        table = None if e.table == FILE_LEVEL else e.table
        out[(kind_name(e.kind), table)] = decoded_body(e).content
    return out


def records(lib, kind):
    section = bodies(lib).get((kind, None))
    return section.records if section is not None else []


# A table record's `ridge` code by the name `bssrdf inspect` gives it (`ridge_kind`).
RIDGE_KINDS = {0: "none", 1: "flux", 2: "flux+fluence"}


def walk_of(record):
    """A table record's model, and its walk's component and g (None but for walk-angular)."""
    model = record.model.name.replace("_", "-")
    if record.model != Bssrdf.Model.walk_angular:
        return (model, None, None)
    return (model, record.component.name, record.g)


def facts(lib):
    """The manifest's keys, read with the generated parser."""
    h, entries = lib.header, lib.directory
    (tables_entry,) = [e for e in entries if e.kind == Bssrdf.SectionKind.tables]
    tables = records(lib, "tables")
    mats = records(lib, "materials")
    return {
        "version": (h.major, h.minor),
        "required_features": h.required_features,
        "optional_features": h.optional_features,
        "optional_features_set": bin(h.optional_features).count("1"),
        "alignment": h.alignment,
        "header_reserved_zero": h.reserved == bytes(72),
        "section_kinds": [kind_name(e.kind) for e in entries],
        "codecs": {e.codec.name for e in entries},
        "unknown_entry_flags": any(e.flags & ~1 for e in entries),
        "optional_extension": all(
            not e.required for e in entries if not isinstance(e.kind, Bssrdf.SectionKind)
        ),
        "table_dims": [(t.n_rho, t.n_theta, t.n_r) for t in tables],
        "table_walks": [walk_of(t) for t in tables],
        "table_ridges": [RIDGE_KINDS[t.ridge] for t in tables],
        "n_rho": [t.n_rho for t in tables],
        "table_record_size": tables_entry.dims[1],
        "materials": len(mats),
        "albedo_ranges": sum(m.has_albedo_range for m in mats),
        "empty_sections": sum(e.stored_len == 0 for e in entries),
    }


@pytest.mark.parametrize("path", VALID, ids=ids(VALID))
def test_valid_vector_is_as_the_manifest_says(path):
    expected = MANIFEST[path.stem]
    got = facts(parse_fully(path))
    assert {k: got[k] for k in expected} == expected


def test_every_valid_vector_is_in_the_manifest():
    assert set(ids(VALID)) == set(MANIFEST)


def test_spec_example_as_section_16_states():
    lib = parse_fully(REPO / "tests" / "data" / "valid" / "spec-example.bssrdf")
    h = lib.header
    assert (h.section_count, h.file_size, h.header_crc) == (7, 2568, 0x4208F077)
    placed = [(e.offset, e.stored_len) for e in lib.directory]
    assert placed == [
        (0x300, 64), (0x400, 512), (0x600, 4), (0x700, 4), (0x800, 8), (0x900, 24), (0xA00, 8)
    ]
    b = bodies(lib)
    (table,) = b[("tables", None)].records
    assert (table.model, table.fresnel, table.eta, table.ridge) == (
        Bssrdf.Model.pbd_angular, Bssrdf.Fresnel.exact, 1.5, 0
    )
    axes = [b[(k, 0)].values for k in ("axis-rho", "axis-theta", "axis-r")]
    assert axes == [[0.5], [0.0], [0.5, 1.0]]
    nodes = [(n.e, n.e_beta, n.c) for n in b[("gwc-params", 0)].nodes]
    assert nodes == [(1.0, 2.0, 0.25), (0.5, 2.0, 0.125)]
    assert b[("radial-cdf", 0)].values == [0.5, 1.0]
    (wax,) = b[("materials", None)].records
    assert (wax.name, wax.source, wax.table, wax.flags) == ("wax", "example", [0, 0, 0], 0)
    assert (wax.sigma_s, wax.sigma_a, wax.g, wax.eta) == ([1.0] * 3, [0.5] * 3, [0.0] * 3, 1.5)


# --- Against the Rust reader --------------------------------------------------------------


@pytest.fixture(scope="session")
def bssrdf_bin():
    """The `bssrdf` command: $BSSRDF_BIN, or built by cargo (a no-op after `cargo test`)."""
    given = os.environ.get("BSSRDF_BIN")
    if given:
        return given
    built = subprocess.run(
        ["cargo", "build", "--quiet", "-p", "bssrdf-cli", "--message-format=json"],
        cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout
    for line in built.splitlines():
        msg = json.loads(line)
        if msg.get("reason") == "compiler-artifact" and msg["target"]["name"] == "bssrdf":
            return msg["executable"]
    pytest.fail("cargo build -p bssrdf-cli made no bssrdf executable")


def kaitai_view(lib):
    """The file as `bssrdf inspect --json` shows it, from the generated parser alone (and zstd
    for compressed sections)."""
    h = lib.header
    b = bodies(lib)
    sections = [
        {
            "kind": kind_name(e.kind),
            "table": None if e.table == FILE_LEVEL else e.table,
            "dtype": e.dtype.name,
            "codec": e.codec.name,
            "required": e.required,
            "dims": e.dims[: e.ndim],
            "offset": e.offset,
            "stored_len": e.stored_len,
            "raw_len": e.raw_len,
            "crc32": f"{e.crc32:08x}",
        }
        for e in lib.directory
    ]
    tables = [
        {
            "index": t,
            "model": walk_of(rec)[0],
            "walk_component": walk_of(rec)[1],
            "walk_g": walk_of(rec)[2],
            "ridge": rec.ridge != 0,
            "ridge_kind": RIDGE_KINDS[rec.ridge],
            "fresnel_moments": rec.fresnel.name,
            "eta": rec.eta,
            "dims": [rec.n_rho, rec.n_theta, rec.n_r],
            "rho": b[("axis-rho", t)].values,
            "theta": b[("axis-theta", t)].values,
            "r": b[("axis-r", t)].values,
            "theta_sampling": ("theta-cdf", t) in b,
            "lobes": 2 if ("gwc-harmonics", t) in b else 1,
        }
        for t, rec in enumerate(records(lib, "tables"))
    ]
    materials = [
        {
            "name": m.name,
            "source": m.source,
            "sigma_s": m.sigma_s,
            "sigma_a": m.sigma_a,
            "g": m.g,
            "eta": m.eta,
            "tables": m.table,
            "albedo_range": (
                {"min": m.albedo_min, "max": m.albedo_max} if m.has_albedo_range else None
            ),
        }
        for m in records(lib, "materials")
    ]
    provenance = b.get(("provenance", None))
    return {
        "version": [h.major, h.minor],
        "file_size": h.file_size,
        "alignment": h.alignment,
        "compressed": h.zstd_sections,
        "required_features": h.required_features,
        "optional_features": h.optional_features,
        "sections": sections,
        "tables": tables,
        "materials": materials,
        "provenance": json.loads(provenance.json) if provenance is not None else {},
    }


def same_keys_as(view, rust):
    """`rust` cut down to the keys of `view`, in dicts and lists of dicts alike."""
    if isinstance(view, dict):
        return {k: same_keys_as(view[k], rust[k]) for k in view}
    if isinstance(view, list) and isinstance(rust, list) and len(view) == len(rust):
        return [same_keys_as(v, r) for v, r in zip(view, rust)]
    return rust


@pytest.mark.parametrize("path", VALID, ids=ids(VALID))
def test_valid_vector_agrees_with_the_rust_reader(path, bssrdf_bin):
    rust = json.loads(
        subprocess.run(
            [bssrdf_bin, "inspect", "--json", str(path)],
            check=True, capture_output=True, text=True,
        ).stdout
    )
    view = kaitai_view(parse_fully(path))
    assert view == same_keys_as(view, rust)


# --- Invalid vectors: what the description rejects and what it cannot ---------------------

# Rejected by a `valid` or `contents` key: the field's path in the .ksy, as the error names it.
REJECTED_BY_VALIDATION = {
    "bad-magic": "/types/header/seq/0",  # magic
    "unsupported-major": "/types/header/seq/1",  # major
    "wrong-byte-order": "/types/header/seq/3",  # byte_order
    "directory-out-of-bounds": "/types/header/seq/4",  # section_count > 65536
    "too-short": "/types/header/seq/5",  # file_size against the real size
    "truncated": "/types/header/seq/5",
    "trailing-bytes": "/types/header/seq/5",
    "bad-alignment": "/types/header/seq/8",  # alignment
    "unknown-dtype": "/types/dir_entry/seq/2",  # dtype
    "unknown-codec": "/types/dir_entry/seq/3",  # codec
    "bad-shape": "/types/dir_entry/seq/5",  # ndim
    "unknown-model": "/types/table_record/seq/0",  # model
    "unknown-component": "/types/table_record/seq/6",  # component (walk-angular)
    "table-g": "/types/table_record/seq/7",  # g (walk-angular)
    "unknown-ridge": "/types/table_record/seq/8",  # ridge
    "unknown-fresnel": "/types/table_record/seq/1",  # fresnel
    "table-eta": "/types/table_record/seq/2",  # eta
    "table-dims": "/types/table_record/seq/3",  # n_rho
    "empty-name": "/types/material_record/seq/0",  # name_len
    "string-too-long": "/types/material_record/seq/1",  # source_len
    "material-value": "/types/material_record/seq/5",  # sigma_a
}

# Rejected because the bytes run out: a section's dims ask for more than it stores, or it
# runs past the end of the file.
REJECTED_AT_END_OF_STREAM = {
    "record-size": "table records of 32 bytes, where a record needs 64",
    "section-too-large": "gwc-params dims of 2^32 nodes in 192 stored bytes",
    "wrong-dtype": "axis-rho read as its dims[0] = 8 f32 values in 8 bytes",
    "misaligned-section": "the last section, moved 4 bytes on, runs past the end",
    "section-gap": "the last section, moved 256 bytes on, starts at the end",
    "section-out-of-bounds": "theta-cdf of 528 bytes runs past the end",
}

# Rejected by the Python runtime, which decodes `str` fields strictly.
REJECTED_AS_TEXT = {"invalid-utf8": UnicodeDecodeError}

# Parsed: the rule broken is one the .ksy does not express.
NOT_REJECTED = {
    "header-crc": "checksums are described, not verified",
    "section-crc": "checksums are described, not verified",
    "unsupported-features": "feature bits are not checked",
    "feature-not-declared": "feature bits are not checked",
    "harmonics-not-declared": "feature bits are not checked",
    "walk-tables-not-declared": "feature bits are not checked",
    "ridge-not-declared": "feature bits are not checked",
    "signed-lobes-not-declared": "feature bits and node values are not checked",
    "signed-floor-not-declared": "feature bits and node values are not checked",
    "reserved-not-zero": "reserved bytes depend on the minor",
    "section-flags": "reserved bits depend on the minor",
    "raw-length-mismatch": "raw_len is not checked",
    "stored-length-mismatch": "stored_len is not checked",
    "sections-out-of-order": "placement is not checked",
    "sections-overlap": "placement is not checked",
    "non-zero-padding": "padding is not described",
    "data-after-last-section": "placement is not checked (file_size counts the extra bytes)",
    "unknown-required-section": "an extension kind is bytes, required or not",
    "section-table-index": "section ownership is not checked",
    "duplicate-section": "uniqueness is not checked",
    "missing-section": "presence of sections is not checked",
    "section-dims": "radial-cdf dims [4, 2, 2] hold as many values as [2, 2, 4]",
    "zstd": "compressed sections are bytes",
    "decoded-length": "compressed sections are bytes",
    "too-many-records": "compressed sections are bytes",
    "non-finite": "values in table sections are not checked",
    "negative-lobe": "values in table sections are not checked",
    "concentration-out-of-range": "values in table sections are not checked",
    "negative-profile": "values in table sections are not checked",
    "radial-cdf-decreasing": "values in table sections are not checked",
    "theta-cdf-decreasing": "values in table sections are not checked",
    "axis-not-increasing": "values in table sections are not checked",
    "axis-out-of-range": "values in table sections are not checked",
    "control-character": "control characters are valid UTF-8",
    "duplicate-name": "rules across records are not checked",
    "material-table": "table indices are not checked against the tables",
    "provenance-json": "provenance is described as text",
    "provenance-duplicate-key": "provenance is described as text",
}


def test_every_invalid_vector_has_one_expectation():
    groups = [REJECTED_BY_VALIDATION, REJECTED_AT_END_OF_STREAM, REJECTED_AS_TEXT, NOT_REJECTED]
    named = [code for g in groups for code in g]
    assert len(named) == len(set(named)), "a vector is in two groups"
    assert set(named) == set(ids(INVALID))


@pytest.mark.parametrize("path", INVALID, ids=ids(INVALID))
def test_invalid_vector(path):
    code = path.stem
    if code in REJECTED_BY_VALIDATION:
        with pytest.raises(kaitaistruct.ValidationFailedError) as err:
            parse_fully(path)
        assert err.value.src_path == REJECTED_BY_VALIDATION[code]
    elif code in REJECTED_AT_END_OF_STREAM:
        with pytest.raises(kaitaistruct.EndOfStreamError):
            parse_fully(path)
    elif code in REJECTED_AS_TEXT:
        with pytest.raises(REJECTED_AS_TEXT[code]):
            parse_fully(path)
    else:
        assert code in NOT_REJECTED, f"new vector {code}: say what the .ksy does with it"
        parse_fully(path)
