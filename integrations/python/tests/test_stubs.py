"""The type stubs describe the module as it is: every public name, and every public member of
each class, in both."""

import ast
import os

import dentbend

STUBS = os.path.join(os.path.dirname(dentbend.__file__), "__init__.pyi")
# Names the stubs define for their own annotations only.
STUB_ONLY = {"ArrayLike", "Float32x3", "UInt32"}


def stub_tree():
    with open(STUBS) as stubs:
        return ast.parse(stubs.read())


def test_the_stubs_ship_with_the_package():
    assert os.path.exists(STUBS)
    assert os.path.exists(os.path.join(os.path.dirname(STUBS), "py.typed"))


def test_the_stubs_name_every_public_name():
    names = set()
    for node in stub_tree().body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets)
    assert names - STUB_ONLY == set(dentbend.__all__)


def test_the_stubs_name_every_public_member_of_each_class():
    for node in stub_tree().body:
        if not isinstance(node, ast.ClassDef) or node.name == "DentError":
            continue
        stubbed = {n.name for n in node.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")}
        runtime = {n for n in dir(getattr(dentbend, node.name)) if not n.startswith("_")}
        assert stubbed == runtime, node.name
