"""The package's surface: what `dir(vibroatlas)` lists is the API its type
stubs declare, and nothing else (no modules or helpers it uses)."""
import ast
import pathlib

import vibroatlas as va


def stub_names():
    """Top-level public functions, classes and values of __init__.pyi, the
    stubs mypy checks the examples against (type aliases aside)."""
    tree = ast.parse(pathlib.Path(va.__file__).with_name("__init__.pyi").read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
        elif isinstance(node, ast.ImportFrom) and node.module in (None, "") and node.level == 1:
            names.update(a.asname or a.name for a in node.names)
    return {n for n in names if not n.startswith("_") or n == "__version__"}


def test_dir_lists_the_api_of_the_stubs():
    listed = set(dir(va))
    assert {"os", "shutil", "tempfile", "_native", "_run"}.isdisjoint(listed), listed
    assert listed == set(va.__all__) | {"__version__"}
    assert stub_names() == listed
    for name in listed:
        assert getattr(va, name) is not None, name
