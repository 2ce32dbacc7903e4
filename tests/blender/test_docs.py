"""The README tells a new user the truth: every setting is documented with its command-line option, and
every option the README names parses to that setting."""

import pytest

from package import ROOT
from seamless_ao.core.settings import RESAMPLE_FIELDS, export_fields, setting_fields
from seamless_ao.operators.cli import build_parser, given_options, option_name

#: Export settings whose command-line option is not simply their name.
EXPORT_OPTIONS = {"domain": "--color-attribute"}


def readme_row(name, after="### Settings"):
    """The README's table row of a setting: the first after the text ``after`` (bake and export settings
    both have a ``padding``)."""
    text = (ROOT / "README.md").read_text()
    table = [line for line in text[text.index(after):].splitlines() if line.startswith("| `")]
    row = next((line for line in table if line.startswith("| `{}` |".format(name))), None)
    assert row is not None, "README's settings tables lack {}".format(name)
    return row


def spellings(default):
    """How the README may write a default: `1.0` or `1`, `""` for empty text."""
    if default == "":
        return {'`""`'}
    found = {"`{}`".format(default)}
    if isinstance(default, float) and default == int(default):
        found.add("`{}`".format(int(default)))
    return found


def test_readme_documents_every_bake_setting_and_its_option():
    for f in setting_fields():
        row = readme_row(f.name)
        assert "`{}`".format(option_name(f.name)) in row
        assert any(s in row for s in spellings(f.default)), (f.name, f.default)


def test_readme_documents_every_export_setting_and_its_option():
    for f in export_fields():
        row = readme_row(f.name, after="Export settings (")
        assert "`{}`".format(EXPORT_OPTIONS.get(f.name, option_name(f.name))) in row, f.name
        assert any(s in row for s in spellings(f.default)), (f.name, f.default)


def other_value(f):
    """A valid value that is not the default, and how to write it on the command line."""
    meta = f.metadata
    if isinstance(f.default, bool):
        return (not f.default), [option_name(f.name) if not f.default else "--no-" + option_name(f.name)[2:]]
    if "items" in meta:
        value = next(item[0] for item in meta["items"] if item[0] != f.default)
    elif isinstance(f.default, str):
        value = "UVMap.001"
    elif isinstance(f.default, int):
        value = f.default + 1 if f.default + 1 <= meta.get("max", f.default + 1) else f.default - 1
    else:
        value = f.default * 0.5 if f.default else 0.25
    return value, [option_name(f.name), str(value)]


@pytest.mark.parametrize("action, fields", [("bake", setting_fields()), ("export", export_fields(RESAMPLE_FIELDS))])
def test_every_option_parses_to_its_setting(action, fields):
    """Each option, given a non-default value, yields exactly that setting with that value (typed)."""
    parser = build_parser()
    for f in fields:
        value, argv = other_value(f)
        args = parser.parse_args([action, *argv])
        given = given_options(args, fields)
        assert given == {f.name: value} and type(given[f.name]) is type(f.default), (f.name, given)
    assert given_options(parser.parse_args([action]), fields) == {}      # nothing given: the scene's settings


def test_readme_names_the_two_commands():
    readme = (ROOT / "README.md").read_text()
    assert "make demo" in readme and "make test" in readme
    assert (ROOT / ".ci" / "run").read_text().strip().endswith("make test")
