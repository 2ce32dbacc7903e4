"""Issue 57: the batch's own tests (``tests/blender/test_batch.py``) with the real ``blender`` binary, so that
its workers are what they are for a user: ``blender --background --factory-startup --disable-autoexec``; and
the farm's (``tests/blender/test_farm.py``, issue 54), whose task starts the same Blender on a worker (its Dask
tests are Blender 5.0's, so here only the task itself and the sentence for a missing Dask run).

The suite runs inside that Blender (``tests/run.py``) on the repository's package, with the zip's xatlas
wheel for the root's Python unpacked into a folder of its own, and with user folders of its own (the
extension the other tests installed is never touched).
"""

import re
import sys
import zipfile

from real_blender import REPO

SUITES = ("tests/blender/test_batch.py", "tests/blender/test_farm.py")


def unpacked_wheel(real_blender):
    """The manylinux xatlas wheel for the root's Python, unpacked; its folder inside the root."""
    proc = real_blender.run("python3", "-c", "import sys; print('cp{}{}'.format(*sys.version_info[:2]))")
    tag = proc.stdout.strip()
    wheels = sorted((REPO / "wheels").glob("xatlas-*-{}-{}-manylinux*.whl".format(tag, tag)))
    assert wheels, "no xatlas wheel for {} in wheels/: run make wheels/.downloaded".format(tag)
    site = real_blender.scratch / "suite_site"
    with zipfile.ZipFile(wheels[0]) as wheel:
        wheel.extractall(site)
    return real_blender.inside(site)


def test_the_batch_tests_pass_in_the_real_blender(real_blender):
    user = real_blender.scratch / "suite_user"
    user.mkdir()
    proc = real_blender.run(
        "blender", "--background", "--factory-startup", "--python", real_blender.inside(REPO / "tests" / "run.py"),
        "--", *(real_blender.inside(REPO / suite) for suite in SUITES), "-q",
        env={"SEAMLESS_AO_PATHS": unpacked_wheel(real_blender), "BLENDER_USER_RESOURCES": real_blender.inside(user),
             "PYTHONDONTWRITEBYTECODE": "1"}, timeout=1800)
    sys.stdout.write(proc.stdout[-6000:])
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-3000:]
    summary = re.findall(r"(\d+) passed", proc.stdout)
    assert summary and int(summary[-1]) >= 14, proc.stdout[-3000:]
