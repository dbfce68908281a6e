"""The type stubs (bssrdf_zoo/_native.pyi) name exactly what the native module has."""

import ast
import inspect
from pathlib import Path

import bssrdf_zoo as bz
from bssrdf_zoo import _native

STUB = Path(__file__).resolve().parents[1] / "bssrdf_zoo" / "_native.pyi"


def public(names):
    return {n for n in names if not n.startswith("_") or n == "__version__"}


def test_the_stubs_name_every_class_function_and_member():
    tree = ast.parse(STUB.read_text())
    stubbed = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = {
                n.target.id if isinstance(n, ast.AnnAssign) else n.name
                for n in node.body
                if isinstance(n, (ast.FunctionDef, ast.AnnAssign))
            }
            stubbed[node.name] = public(members)
        elif isinstance(node, ast.FunctionDef):
            stubbed[node.name] = None
        elif isinstance(node, ast.AnnAssign):
            stubbed[node.target.id] = None
    module = public(dir(_native)) - {"FormatError"}
    assert module <= set(stubbed), module - set(stubbed)
    for name, members in stubbed.items():
        if members is None or name == "FormatError":
            continue
        cls = getattr(_native, name)
        assert public(m for m in dir(cls) if not m.startswith("__")) == members, name


def test_the_package_exports_what_its_stubs_type():
    assert set(bz.__all__) - {"models"} <= public(dir(_native))
    assert inspect.isbuiltin(bz.models.eval) and bz.models.names() == _native.model_names()
