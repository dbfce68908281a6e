"""The conformance vectors of tests/data/ and the parser generated from format/bssrdf.ksy,
shared by the tests of this folder."""

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
FORMAT = REPO / "format"
DATA = REPO / "tests" / "data"
VALID = sorted((DATA / "valid").glob("*.bssrdf"))
INVALID = sorted((DATA / "invalid").glob("*.bssrdf"))

# The generated parser is a module of its own folder, not a package.
sys.path.insert(0, str(FORMAT / "python"))
from bssrdf import Bssrdf  # noqa: E402  (needs the path above)

MAGIC = b"\x89BSSRDF\r\n\x1a\n\0"


def ids(paths):
    """Test ids: the vector's name without folder and extension."""
    return [p.stem for p in paths]


def parse_fully(path):
    """Parses a file with the generated parser, including every section body (Kaitai reads
    instances lazily, so the bodies are only parsed when touched)."""
    lib = Bssrdf.from_file(str(path))
    for entry in lib.directory:
        entry.body
    return lib


def kind_name(kind):
    """A section kind as format-spec.md and `bssrdf inspect` name it."""
    if isinstance(kind, Bssrdf.SectionKind):
        return kind.name.replace("_", "-")
    return f"extension 0x{kind:04x}"
