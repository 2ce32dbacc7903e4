"""The README and docs/ tell the truth: every figure they state was written by a script, the pages read off
the code are current, the README is short, and every relative link resolves."""

import importlib.util
import re

import pytest

from package import ROOT

DOCS = ROOT / "docs"
#: Pages a script writes: the benchmarks' (docs/bench/*.md, assembled into docs/benchmarks.md) and those
#: read off the code (tests/scripts/write_docs.py).  Every other page is written by hand.
GENERATED = ("benchmarks.md", "settings.md", "constants.md", "tested.md")
#: The README is at most this many lines: what it is, the two commands, install, the panel, one line each of
#: the command line, the API and the batch, and links.
README_LINES = 250

_NUMBER = re.compile(r"(?<![\w.§])(?:\d{1,3}(?:,\d{3})+|\d+)(?:\.\d+)?(?:·10⁻?[⁰¹²³⁴⁵⁶⁷⁸⁹]+|⁻?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)?")


def hand_written():
    return [ROOT / "README.md"] + sorted(p for p in DOCS.glob("*.md") if p.name not in GENERATED)


def generated():
    return [DOCS / name for name in GENERATED if (DOCS / name).exists()] + sorted((DOCS / "bench").glob("*.md"))


def prose(text):
    """``text`` without fenced code, inline code and link targets: what states figures in words."""
    text = re.sub(r"```.*?```", " ", text, flags=re.S)
    text = re.sub(r"`[^`\n]*`", " ", text)
    return re.sub(r"\]\([^)]*\)", "]", text)


def figures(text):
    """The numbers stated in ``text``: thousands separators dropped, ``512²`` read as 512 (an image size),
    ``10⁻⁵`` kept whole; single digits are counts in words ("three UV maps", "step 2") and are left out."""
    found = set()
    for match in _NUMBER.finditer(text):
        token = match.group(0).replace(",", "")
        if token.endswith(("²", "³")) and "⁻" not in token and not token.startswith("10"):
            token = token[:-1]
        if re.fullmatch(r"\d", token):
            continue
        found.add(token)
    return found


def test_figures_are_read_as_the_docs_write_them():
    assert figures("RMSE 0.0159 at 512², 1,300 pieces, 10⁻⁵ of the size, 2·10⁻⁵, 3 rays, §7.3") == {
        "0.0159", "512", "1300", "10⁻⁵", "2·10⁻⁵"}
    assert figures(prose("`--rays 128` and ```\nmake 999\n``` and [a link](x/88.md)")) == set()


def paragraphs(text):
    """The paragraphs of a page (blank-line separated; a table is one), fenced code left out."""
    text = re.sub(r"```.*?```", "\n\n", text, flags=re.S)
    return [paragraph for paragraph in re.split(r"\n\s*\n", text) if paragraph.strip()]


def linked_pages(path, paragraph, pages):
    """The generated pages (of ``pages``, resolved paths) that ``paragraph`` of the page ``path`` links to."""
    targets = re.findall(r"\]\(([^)\s#]+)(?:#[^)]*)?\)", paragraph)
    return [(path.parent / target).resolve() for target in targets if (path.parent / target).resolve() in pages]


def unbacked_figures(path, pages):
    """The figures of hand-written page ``path`` that no script wrote where its sentence points: a figure in a
    paragraph that links to generated pages must be in one of those; any other in some generated page."""
    written = set().union(*pages.values())
    missing = []
    for paragraph in paragraphs(path.read_text()):
        linked = linked_pages(path, paragraph, pages)
        backing = set().union(*(pages[page] for page in linked)) if linked else written
        missing += sorted(figures(prose(paragraph)) - backing)
    return missing


def test_every_figure_in_the_readme_and_docs_was_written_by_a_script_on_the_page_it_links_to():
    pages = {path.resolve(): figures(path.read_text()) for path in generated()}
    unwritten = {}
    for path in hand_written():
        missing = unbacked_figures(path, pages)
        if missing:
            unwritten[str(path.relative_to(ROOT))] = missing
    assert not unwritten, ("figures not on the page their paragraph links to (or, with no link, on no page a "
                           "script wrote): quote the page, link the right one, or delete them: {}".format(unwritten))


def test_a_figure_is_held_to_the_page_its_paragraph_links_to(tmp_path):
    """Issue 55: "1,000-piece interior" linking a page that says 1,157 fails, though 1,000 is on another page."""
    bench = tmp_path / "bench"
    bench.mkdir()
    (bench / "meshes.md").write_text("| interior | 94,412 | 1,157 |\n")
    (bench / "other.md").write_text("1,000 rays\n")
    pages = {path.resolve(): figures(path.read_text()) for path in bench.glob("*.md")}
    page = tmp_path / "page.md"
    page.write_text("A 1,157-piece interior ([meshes](bench/meshes.md)).\n\nA 1,000-piece interior "
                    "([meshes](bench/meshes.md)).\n\nA 1,000-piece interior, no link.\n")
    assert unbacked_figures(page, pages) == ["1000"]


def test_the_pages_read_off_the_code_are_current():
    spec = importlib.util.spec_from_file_location("write_docs", ROOT / "tests" / "scripts" / "write_docs.py")
    write_docs = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(write_docs)
    for name, page in write_docs.PAGES.items():
        assert (DOCS / name).read_text() == page(), "docs/{} is out of date: run make docs".format(name)


def test_the_readme_is_short():
    assert len((ROOT / "README.md").read_text().splitlines()) <= README_LINES


@pytest.mark.parametrize("path", hand_written() + generated(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_resolves(path):
    text = re.sub(r"```.*?```", " ", path.read_text(), flags=re.S)
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        file_part, _, fragment = target.partition("#")
        linked = (path.parent / file_part).resolve()
        assert linked.exists(), "{} links to {}, which does not exist".format(path.relative_to(ROOT), target)
        if fragment and linked.suffix == ".md":
            headings = {re.sub(r"[^\w\- ]", "", h.lower()).strip().replace(" ", "-")
                        for h in re.findall(r"^#+ (.*)$", linked.read_text(), re.M)}
            assert fragment in headings, "{} links to a missing heading {}".format(path.relative_to(ROOT), target)


def package_strings():
    """Every string constant of the package's code (adjacent literals are one constant to ``ast``)."""
    import ast
    found = []
    for folder in ("core", "operators", "panels", "shaders"):
        for path in (ROOT / folder).rglob("*.py"):
            found += [node.value for node in ast.walk(ast.parse(path.read_text()))
                      if isinstance(node, ast.Constant) and isinstance(node.value, str)]
    return found


def test_every_message_the_troubleshooting_page_quotes_is_one_the_add_on_says():
    """docs/troubleshooting.md quotes messages with "…" where a name or a number goes: every piece between
    those is in one string of the code, word for word (a reworded message fails here until the page follows)."""
    strings = package_strings()
    quoted = re.findall(r'^\| "(.+?)" \|', (DOCS / "troubleshooting.md").read_text(), re.M)
    assert len(quoted) >= 30, len(quoted)
    unsaid = []
    for message in quoted:
        for piece in re.split(r'…|", "', message):
            piece = piece.strip(" .")
            if len(piece) >= 4 and not any(piece in s for s in strings):
                unsaid.append(piece)
    assert not unsaid, unsaid


def bake_defaults(settings_source):
    """``{setting: default}`` of ``BakeSettings`` in a core/settings.py source, with ``PRESETS`` (what each
    Quality bakes with), read with ``ast``: the defaults a bench page's bakes ran at."""
    import ast
    defaults = {}
    for node in ast.parse(settings_source).body:
        if isinstance(node, ast.ClassDef) and node.name == "BakeSettings":
            for item in node.body:
                if isinstance(item, ast.AnnAssign) and isinstance(item.value, ast.Call) and item.value.args:
                    defaults[item.target.id] = ast.literal_eval(item.value.args[0])
        if isinstance(node, ast.Assign) and any(getattr(target, "id", "") == "PRESETS" for target in node.targets):
            defaults["PRESETS"] = ast.literal_eval(node.value)
    return defaults


#: Bench pages written at other bake defaults and not yet rerun: none. A default change lists here the pages
#: it leaves behind (report.py alone takes about 45 minutes) until each is rerun and taken off.
STALE_PAGES = set()


def test_every_bench_page_was_written_at_todays_bake_defaults():
    """Issue 55: a page written before a default changed (the Ray Caster, a preset) describes another product;
    each page's header names its commit, whose core/settings.py must hold HEAD's bake defaults. The pages not
    yet rerun are listed (STALE_PAGES): no other page may be stale, and a rerun page leaves the list."""
    import subprocess
    today = bake_defaults((ROOT / "core" / "settings.py").read_text())
    stale = {}
    for page in sorted((DOCS / "bench").glob("*.md")):
        found = re.search(r"commit ([0-9a-f]{7,40})\+?,", page.read_text())
        assert found, "{} names no commit".format(page.name)
        shown = subprocess.run(["git", "-C", str(ROOT), "show", "{}:core/settings.py".format(found.group(1))],
                               capture_output=True, text=True)
        assert shown.returncode == 0, "{}: its commit {} is not in this clone: {}".format(
            page.name, found.group(1), shown.stderr.strip())
        then = bake_defaults(shown.stdout)
        differ = sorted(name for name in today if then.get(name, "(none)") != today[name])
        if differ:
            stale[page.stem] = differ
    assert set(stale) <= STALE_PAGES, "bench pages written at other bake defaults (rerun them): {}".format(
        {name: differ for name, differ in stale.items() if name not in STALE_PAGES})
    assert STALE_PAGES <= set(stale), "rerun at today's defaults: take {} off STALE_PAGES".format(
        sorted(STALE_PAGES - set(stale)))
