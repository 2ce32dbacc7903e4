"""Write the reference pages of docs/ that are read off the code (``make docs``; a test checks they are current):

    docs/settings.md    every bake and export setting: option, default, range, meaning (core/settings.py)
    docs/constants.md   every documented constant of core/ with its value (the tolerances, limits, margins)
    docs/tested.md      which Blender, bpy, Python and numpy ``make test`` runs, which tests run where, and what
                        the real Blender binary runs

    .venv/5.0/bin/python tests/scripts/write_docs.py [--check]

``--check`` writes nothing and exits with 1 if a page differs from what it would write.
"""

import argparse
import ast
import importlib
import math
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
sys.path.insert(0, str(ROOT / "tests" / "support"))

GENERATED = "*Written by `tests/scripts/write_docs.py` from {}; `make docs` rewrites it. Do not edit.*"
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def number(value):
    """A number as the docs write it: ``1e-05`` as ``10⁻⁵``, ``2e-05`` as ``2·10⁻⁵``, others plainly."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, float) and value and not 1e-3 <= abs(value) < 1e6:
        exponent = math.floor(math.log10(abs(value)))
        mantissa = round(value / 10.0 ** exponent, 6)
        power = "10" + str(exponent).translate(SUPERSCRIPT)
        return power if mantissa == 1 else "{:g}·{}".format(mantissa, power)
    if isinstance(value, int) and abs(value) >= 10000:
        if value & (value - 1) == 0:
            return "2{} ({:,})".format(str(value.bit_length() - 1).translate(SUPERSCRIPT), value)
        return "{:,}".format(value)
    return "{:g}".format(value) if isinstance(value, float) else str(value)


def settings_page():
    from package import seamless_ao
    from seamless_ao.core.settings import export_fields, gltf_fields, setting_fields
    from seamless_ao.operators.launchers.command_line import option_name

    def default(f):
        return '`""`' if f.default == "" else "`{}`".format(f.default)

    def limits(f):
        meta = f.metadata
        if "items" in meta:
            return " / ".join("`{}`".format(item[0]) for item in meta["items"])
        span = ""
        if "min" in meta and "max" in meta:
            span = "{}–{}".format(number(meta["min"]), number(meta["max"]))
        return (span + " " + meta.get("unit", "")).strip()

    def items(fields):
        lines = []
        for f in fields:
            for identifier, label, text in f.metadata.get("items", ()):
                lines.append("| `{}` | `{}` | {} | {} |".format(f.name, identifier, label, text))
        return lines

    bake = ["| setting | command line | default | range | what it does |", "|---|---|---|---|---|"]
    bake += ["| `{}` | `{}` | {} | {} | {} |".format(f.name, option_name(f.name), default(f), limits(f),
                                                  f.metadata["description"]) for f in setting_fields()]
    options = {"domain": "--color-attribute"}
    export = ["| setting | command line | default | range | what it does |", "|---|---|---|---|---|"]
    export += ["| `{}` | `{}` | {} | {} | {} |".format(f.name, options.get(f.name, option_name(f.name)), default(f),
                                                    limits(f), f.metadata["description"]) for f in export_fields()]
    gltf = ["| setting | command line | default | range | what it does |", "|---|---|---|---|---|"]
    gltf += ["| `{}` | `{}` | {} | {} | {} |".format(f.name, option_name(f.name), default(f), limits(f),
                                                  f.metadata["description"]) for f in gltf_fields()]
    choices = ["| setting | value | label | meaning |", "|---|---|---|---|"]
    choices += items(setting_fields()) + items(export_fields()) + items(gltf_fields())
    del seamless_ao
    return "\n".join([
        "# Settings", "", GENERATED.format("`core/settings.py`"), "",
        "Every setting is defined once in `core/settings.py`: the scene's settings (`scene.seamless_ao`, the "
        "N-panel), the operators' properties, the command line's options and the Python API's keywords are all "
        "made from it.", "",
        "## Bake settings", "", *bake, "",
        "Distances are in scene units: the object's size as you see it, its scale applied.", "",
        "## Export settings", "",
        "The panel's *Export* section, the scene properties `export_<name>`, the `export` command's options and "
        "the arguments of `resample` and `to_color_attribute`.", "", *export, "",
        "## glTF settings of a batch", "",
        "The `batch` command's options and keywords of `batch()` for the assets it writes as .glb "
        "(docs/pipelines.md); the texture's settings are the export settings', under other names.", "", *gltf, "",
        "## Choices", "", *choices, ""])


def constants_page():
    """Every public numeric module-level constant of core/, with its value and its ``#:`` comment."""
    from package import seamless_ao
    rows = ["| module | constant | value | meaning |", "|---|---|---|---|"]
    for path in sorted((ROOT / "core").rglob("*.py")):
        if path.stem == "__init__":
            continue
        dotted = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        lines = path.read_text().splitlines()
        module = importlib.import_module("{}.{}".format(seamless_ao.__name__, dotted))
        for node in ast.parse("\n".join(lines)).body:
            if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
                continue
            name = node.targets[0].id
            comment = []
            line = node.lineno - 2
            while line >= 0 and lines[line].startswith("#:"):
                comment.insert(0, lines[line][2:].strip())
                line -= 1
            value = getattr(module, name, None)
            if name.startswith("_") or not name.isupper() or not isinstance(value, (int, float)) or isinstance(
                    value, bool):
                continue
            rows.append("| `{}` | `{}` | {} | {} |".format(dotted[len("core."):], name, number(value),
                                                            " ".join(comment) or "—"))
    return "\n".join(["# Constants", "", GENERATED.format("the `#:` comments of `core/`"), "",
                      "The tolerances, limits and margins the bake works with, as the code has them. Sizes "
                      "relative to an object are fractions of its bounding-box diagonal.", "", *rows, ""])


def heavy_cases(function, module_values):
    """The ids of a test function's parametrized cases marked heavy (``pytest.param(..., marks=heavy)``), in its
    decorators or in a module-level list they name (``module_values``: name -> value node).  An id is the
    case's ``id=``, or pytest's own: its literal values joined by "-"."""
    cases = []
    for decorator in function.decorator_list:
        named = [module_values[node.id] for node in ast.walk(decorator)
                 if isinstance(node, ast.Name) and node.id in module_values]
        for call in (node for tree in [decorator, *named] for node in ast.walk(tree)):
            if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr == "param"):
                continue
            keywords = {keyword.arg: keyword.value for keyword in call.keywords}
            if isinstance(keywords.get("marks"), ast.Name) and keywords["marks"].id == "heavy":
                cases.append(ast.literal_eval(keywords["id"]) if "id" in keywords
                             else "-".join(str(ast.literal_eval(value)) for value in call.args))
    return cases


def test_marks():
    """``(heavy tests, tests that may skip with why)`` as (file, test) and (file, test, reason) lists."""
    heavy, may_skip = [], []
    for path in sorted((ROOT / "tests").glob("*/test_*.py")):
        tree = ast.parse(path.read_text())
        module_values = {node.targets[0].id: node.value for node in tree.body
                         if isinstance(node, ast.Assign) and len(node.targets) == 1
                         and isinstance(node.targets[0], ast.Name)}
        for node in tree.body:
            if not isinstance(node, ast.FunctionDef) or not node.name.startswith("test_"):
                continue
            where = str(path.relative_to(ROOT / "tests"))
            if any(isinstance(d, ast.Name) and d.id == "heavy" for d in node.decorator_list):
                heavy.append((where, node.name))
            heavy += [(where, "{}[{}]".format(node.name, case)) for case in heavy_cases(node, module_values)]
            for call in ast.walk(node):
                if (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) and call.func.attr == "skip"
                        and isinstance(call.func.value, ast.Name) and call.func.value.id == "pytest"):
                    doc = " ".join((ast.get_docstring(node) or "").split())
                    reason = re.search(r"\(skipped ([^)]*)\)", doc)
                    may_skip.append((where, node.name, "skipped " + reason.group(1) if reason else doc))
    return heavy, may_skip


def documented_constants(path):
    """``[(name, value, comment)]``: the numeric module-level constants of a file with a ``#:`` comment."""
    lines = path.read_text().splitlines()
    found = []
    for node in ast.parse("\n".join(lines)).body:
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
            continue
        comment, line = [], node.lineno - 2
        while line >= 0 and lines[line].startswith("#:"):
            comment.insert(0, lines[line][2:].strip())
            line -= 1
        try:
            value = ast.literal_eval(node.value)
        except ValueError:
            continue
        if comment and isinstance(value, (int, float)) and not isinstance(value, bool):
            found.append((node.targets[0].id, value, " ".join(comment)))
    return found


def test_limits():
    """The limits the tests hold, from the ``#:`` constants of tests/support and the test files."""
    rows = ["| where | constant | value | meaning |", "|---|---|---|---|"]
    paths = sorted((ROOT / "tests" / "support").glob("*.py")) + sorted((ROOT / "tests").glob("*/test_*.py"))
    for path in paths:
        for name, value, comment in documented_constants(path):
            rows.append("| `{}` | `{}` | {} | {} |".format(path.relative_to(ROOT / "tests"), name, number(value),
                                                          comment))
    return rows


def real_blender_section():
    """What ``make test-real`` runs with the real Blender binary (``tests/real_blender``)."""
    import real_blender
    folder = ROOT / "tests" / "real_blender"
    tests = [(path.name, name) for path in sorted(folder.glob("test_*.py"))
             for name in re.findall(r"^def (test_\w+)", path.read_text(), re.M)]
    suites = re.findall(r'"(tests/[\w/]+\.py)"', (folder / "test_suite_in_blender.py").read_text())
    return ["## The real Blender binary", "",
            "`make test` then runs `tests/real_blender` once (`make test-real`) with a real `blender` binary: "
            "Debian trixie's Blender {} (Python {}, Debian's numpy), in a root that "
            "`tests/scripts/make_blender_root.sh` builds once per machine outside the repository (it needs root "
            "and debootstrap; where the machine cannot build it the tests are skipped with its sentence, and under "
            "CI that is an error). The extension is installed from its zip with Blender's own "
            "`extension install-file`; every headless command of the README, `docs/usage.md` and "
            "`docs/pipelines.md` is read from those pages and run as written; `test_gui.py` (also `make test-gui`) drives "
            "a Blender window under Xvfb with the mouse and keyboard and saves a screenshot of each step in "
            "`out/gui/`.".format(
                real_blender.BLENDER_VERSION, real_blender.BLENDER_PYTHON), "",
            *["- `real_blender/{}`: `{}`".format(where, name) for where, name in tests], "",
            "Inside that Blender (`tests/run.py`), with its own worker processes: " +
            ", ".join("`{}`".format(suite) for suite in suites) + "."]


def tested_page():
    from marks import HEAVY_BLENDER
    makefile = (ROOT / "Makefile").read_text()
    blenders = re.search(r"^BLENDERS \?= (.*)$", makefile, re.M).group(1).split()
    rows = ["| Blender | `bpy` wheel | Python | numpy |", "|---|---|---|---|"]
    for blender in blenders:
        pins = dict(re.findall(r"^([\w-]+)==(\S+)$", (ROOT / "requirements" / "blender-{}.txt".format(blender))
                               .read_text(), re.M))
        python = re.search(r"^PYVER_{} := (\S+)$".format(re.escape(blender)), makefile, re.M).group(1)
        rows.append("| {} | {} | {} | {} |".format(blender, pins["bpy"], python, pins["numpy"]))
    heavy, may_skip = test_marks()
    counts = {folder: sum(len(re.findall(r"^def test_", p.read_text(), re.M))
                          for p in (ROOT / "tests" / folder).glob("test_*.py")) for folder in ("core", "blender")}
    lines = ["# What is tested on which Blender", "",
             GENERATED.format("the Makefile, `requirements/` and the tests' marks (`tests/support/marks.py`)"), "",
             "`make test` runs the whole suite, {} test functions on arrays (`tests/core`) and {} on Blender data "
             "(`tests/blender`), once on each of these `bpy` wheels: the first in the foreground, the others one "
             "after another beside it (a session keeps about one core busy):".format(counts["core"], counts["blender"]),
             "",
             *rows, "",
             "Heavy tests run on Blender {}.{} only and are skipped on the others: those of a minute or more, and "
             "the accuracy checks beyond the cases that take each of Blender's paths (`tests/support/marks.py` says "
             "why):".format(*HEAVY_BLENDER), ""]
    lines += ["- `{}`: `{}`".format(where, name) for where, name in heavy] or ["- none"]
    lines += ["", "Tests that skip, with the reason pytest reports, where the machine cannot run them:", ""]
    lines += ["- `{}`: `{}` ({})".format(where, name, why) for where, name, why in may_skip] or ["- none"]
    lines += ["", *real_blender_section()]
    lines += ["", "Limits the tests hold:", "", *test_limits()]
    lines += ["", "CI (`.ci/run`) runs `make test` on a clean clone; there a Blender whose Python is missing fails "
              "the run, where on a workstation it is skipped with a message.", ""]
    return "\n".join(lines)


PAGES = {"settings.md": settings_page, "constants.md": constants_page, "tested.md": tested_page}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if a page is not what it would be written as")
    args = parser.parse_args()
    stale = []
    for name, page in PAGES.items():
        text = page()
        path = DOCS / name
        if args.check:
            if not path.exists() or path.read_text() != text:
                stale.append(name)
        else:
            DOCS.mkdir(exist_ok=True)
            path.write_text(text)
            print("wrote", path.relative_to(ROOT))
    if stale:
        print("out of date (run make docs):", ", ".join(stale))
    return 1 if stale else 0


if __name__ == "__main__":
    import package
    package.hard_exit(main())
