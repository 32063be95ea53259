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


def test_stubs_are_the_signatures():
    """Every function of __init__.pyi takes the parameters of the package's
    function, in order, each of the same kind and with a default where it
    has one."""
    import inspect

    tree = ast.parse(pathlib.Path(va.__file__).with_name("__init__.pyi").read_text())
    checked = 0
    for node in tree.body:
        if not isinstance(node, ast.FunctionDef) or node.name.startswith("_"):
            continue
        a = node.args
        stub = [(p.arg, "POSITIONAL_ONLY") for p in a.posonlyargs] + [(p.arg, "POSITIONAL_OR_KEYWORD") for p in a.args]
        stub += [(a.vararg.arg, "VAR_POSITIONAL")] if a.vararg else []
        stub += [(p.arg, "KEYWORD_ONLY") for p in a.kwonlyargs]
        stub += [(a.kwarg.arg, "VAR_KEYWORD")] if a.kwarg else []
        positional = a.posonlyargs + a.args
        defaults = {p.arg for p in positional[len(positional) - len(a.defaults):]}
        defaults |= {p.arg for p, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None}
        signature = inspect.signature(getattr(va, node.name)).parameters.values()
        real = [(p.name, p.kind.name) for p in signature]
        assert stub == real, f"{node.name}: the stub takes {stub}, the function {real}"
        real_defaults = {p.name for p in signature if p.default is not inspect.Parameter.empty}
        assert defaults == real_defaults, f"{node.name}: defaults {defaults} in the stub, {real_defaults} in it"
        checked += 1
    assert checked >= 10, checked
