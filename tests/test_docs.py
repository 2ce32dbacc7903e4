"""The README tells a new user the truth: every setting is documented, with its command-line option."""

from conftest import ROOT
from seamless_ao.core.settings import setting_fields
from seamless_ao.operators.cli import build_parser, option_name


def test_readme_documents_every_setting_and_its_option():
    readme = (ROOT / "README.md").read_text()
    table = [line for line in readme.splitlines() if line.startswith("| `")]
    for f in setting_fields():
        row = next((line for line in table if line.startswith("| `{}` |".format(f.name))), None)
        assert row is not None, "README's settings table lacks {}".format(f.name)
        assert "`{}`".format(option_name(f.name)) in row
        spellings = {"`{}`".format(f.default)}
        if isinstance(f.default, float) and f.default == int(f.default):
            spellings.add("`{}`".format(int(f.default)))
        assert any(s in row for s in spellings), (f.name, f.default)


def test_every_setting_is_a_command_line_option():
    bake = build_parser()._subparsers._group_actions[0].choices["bake"]
    options = {o for action in bake._actions for o in action.option_strings}
    for f in setting_fields():
        assert option_name(f.name) in options


def test_readme_names_the_two_commands():
    readme = (ROOT / "README.md").read_text()
    assert "make demo" in readme and "make test" in readme
    assert (ROOT / ".ci" / "run").read_text().strip().endswith("make test")
