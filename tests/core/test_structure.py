"""The package's shape: relative imports only, no import circle, no arrow back up to the root, no file over 450
lines, core free of bpy, one definition per class or public function name, export settings declared in
core/settings.py only, and a map of core/ that names every module."""

import ast
import pathlib
import re

from package import ROOT

PACKAGE_FOLDERS = ("core", "operators", "panels", "shaders")
#: No Python file of the repository is longer than this many lines.
MAX_LINES = 450


def package_modules():
    """``{dotted name: path}`` of every module of the package (the repository root is the package)."""
    modules = {"": ROOT / "__init__.py"}
    for folder in PACKAGE_FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return modules


def imported_modules(name, path, modules):
    """The package modules that module ``name`` imports at its top level or inside functions."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package.split(".") if package else []
            base = base[:len(base) - (node.level - 1)] if node.level > 1 else base
            target = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:                     # "from . import operators" imports a module
                child = (target + "." if target else "") + alias.name
                found.add(child if child in modules else target)
    return found & set(modules)


def test_the_package_imports_itself_only_relatively_and_core_never_imports_bpy_context():
    for name, path in package_modules().items():
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                assert not any(a.name.startswith("seamless_ao") for a in node.names), path
            if isinstance(node, ast.ImportFrom) and not node.level:
                assert not (node.module or "").startswith("seamless_ao"), path
        if name.startswith("core"):
            imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
            imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and not n.level}
            assert not any(m == "bpy" or m.startswith("bpy.") for m in imported if m), path


def test_no_import_circle():
    modules = package_modules()
    graph = {name: imported_modules(name, path, modules) - {name} for name, path in modules.items()}
    # a package imports its own children by design (``__init__`` re-exports); a circle through a parent
    # package's __init__ is one only if the child imports that __init__ back
    state = {}

    def visit(name, trail):
        state[name] = "open"
        for other in sorted(graph[name]):
            if other and name.startswith(other + "."):
                continue                               # a module's own parent package, imported first anyway
            if state.get(other) == "open":
                raise AssertionError("import circle: " + " -> ".join(trail + [other]))
            if other not in state:
                visit(other, trail + [other])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


def test_no_python_file_is_over_450_lines():
    long = {str(path.relative_to(ROOT)): count for path in ROOT.rglob("*.py")
            if ".venv" not in path.parts and "wheels" not in path.parts
            for count in [len(path.read_text().splitlines())] if count > MAX_LINES}
    assert not long, long


#: Names every module of a kind defines by protocol: Blender's module registration, and each process's entry.
PROTOCOL_NAMES = {"register", "unregister", "main"}


def test_no_two_classes_or_public_functions_share_a_name():
    """One meaning per name: a reader who meets ``Topology`` or ``set_preview`` finds one definition."""
    defined = {}
    for name, path in package_modules().items():
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, (ast.ClassDef, ast.FunctionDef)) and not node.name.startswith("_"):
                if node.name not in PROTOCOL_NAMES:
                    defined.setdefault(node.name, []).append(str(path.relative_to(ROOT)))
    shared = {name: paths for name, paths in defined.items() if len(paths) > 1}
    assert not shared, shared


#: Parameters that share a name with an export setting and mean something else: ``(module, parameter)``.
NOT_EXPORT_SETTINGS = {
    ("core.atlas.chart_atlas", "padding"), ("core.layout", "padding"), ("core.atlas.raster", "padding"),   # the atlas's, a bake's
    ("core.export.png", "bit_depth"),                                                           # the PNG writer's, an int
}


def test_export_settings_are_declared_in_core_settings_only():
    """An export or glTF setting gets its default, its choices and its command-line option from
    core/settings.py only: no function elsewhere gives one a literal default, and no option is spelt out."""
    from package import seamless_ao
    settings = seamless_ao.core.settings
    names = {f.name for f in settings.export_fields()} | {f.name for f in settings.gltf_fields()}
    options = {"--" + name.replace("_", "-") for name in names}
    declared = []
    for name, path in package_modules().items():
        if name == "core.settings":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and node.value in options:
                declared.append("{}:{} option {}".format(path.name, node.lineno, node.value))
            if isinstance(node, ast.FunctionDef):
                given = node.args.args[len(node.args.args) - len(node.args.defaults):]
                pairs = list(zip(given, node.args.defaults)) + list(zip(node.args.kwonlyargs, node.args.kw_defaults))
                declared += ["{}:{} {}={!r}".format(path.name, node.lineno, arg.arg, default.value)
                             for arg, default in pairs if arg.arg in names and isinstance(default, ast.Constant)
                             and default.value is not None and (name, arg.arg) not in NOT_EXPORT_SETTINGS]
    assert not declared, declared


def test_no_module_imports_the_package_root():
    """The root only registers and re-exports; nothing below it reaches back up (the launcher registers the add-on
    for the processes that need it)."""
    modules = package_modules()
    upward = sorted(name for name, path in modules.items() if name and "" in imported_modules(name, path, modules))
    assert not upward, upward


def test_the_core_map_names_every_core_module():
    """core/__init__.py's table is the map of core/: every module in it, and nothing that is not there."""
    core = ROOT / "core"
    mapped = set(re.findall(r":mod:`\.([\w.]+)`", (core / "__init__.py").read_text()))
    present = {".".join(path.relative_to(core).with_suffix("").parts) for path in core.rglob("*.py")
               if path.stem != "__init__"}
    assert mapped == present, (sorted(present - mapped), sorted(mapped - present))


def test_core_is_grouped_by_stage():
    """core/ holds the modules that chain the stages, and one folder per stage: no folder inside a stage, and no
    stage folder without its own docstring."""
    core = ROOT / "core"
    stages = [path for path in core.iterdir() if path.is_dir() and path.name != "__pycache__"]
    assert stages, "core/ has no stage folders"
    for stage in stages:
        assert (stage / "__init__.py").is_file(), stage
        assert ast.get_docstring(ast.parse((stage / "__init__.py").read_text())), stage
        assert not [p for p in stage.iterdir() if p.is_dir() and p.name != "__pycache__"], stage
    top = sorted(path.stem for path in core.glob("*.py") if path.stem != "__init__")
    assert len(top) <= 8, top
