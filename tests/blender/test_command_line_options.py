"""The command line: every setting's option (as docs/settings.md lists them, written from the same fields)
parses to that setting, and the README names the two commands CI runs."""

import pytest

from package import ROOT
from seamless_ao.core.settings import RESAMPLE_FIELDS, export_fields, setting_fields
from seamless_ao.operators.launchers.command_line import build_parser, given_options, option_name


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
