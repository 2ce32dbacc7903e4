"""Fixtures of the tests that run a real ``blender`` binary (see ``tests/support/real_blender.py``).

They run once per ``make test`` (not once per ``bpy`` wheel), on the root ``make test`` builds; run alone
(``pytest tests/real_blender``) without ``SEAMLESS_AO_BLENDER_ROOT`` they skip with a sentence.
"""

import pytest

from extension_zip import build_zips_as_the_readme
from real_blender import ROOT_VARIABLE, RealBlender, root_from_environment


@pytest.fixture(scope="session")
def real_blender(tmp_path_factory):
    """The real Blender, mounted over a scratch folder that is its HOME; unmounted after the session."""
    root = root_from_environment()
    if root is None:
        pytest.skip("no real Blender binary: `make test` builds its root (as root, with debootstrap) and names "
                    "it in {}".format(ROOT_VARIABLE))
    with RealBlender(root, tmp_path_factory.mktemp("real_blender")) as blender:
        yield blender


@pytest.fixture(scope="session")
def zips(real_blender):
    """The extension zips, built into ``dist/`` of the scratch folder as the README builds them (``python
    build.py``; tests/blender/test_extension.py holds them to ``make extension``'s, byte for byte)."""
    return build_zips_as_the_readme(real_blender.scratch / "dist")
