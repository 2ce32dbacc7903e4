"""The test session's watchdog (tests/conftest.py, tests/support/watchdog.py): a test that hangs ends the
run with the test's id and every thread's stacks on the terminal, instead of sitting until CI's limit kills
it without a word of where."""

import os
import pathlib
import subprocess
import sys
import textwrap

TESTS = pathlib.Path(__file__).resolve().parents[1]

#: The session run: its tests, indented here (docs/tested.md counts this file's own tests by their "def").
HANGING_TESTS = textwrap.dedent('''
    import time

    def test_before_the_hang():
        time.sleep(2)              # shorter than the stall: not reported

    def test_that_hangs_in_a_native_wait():
        time.sleep(120)            # a C-level wait, as a thread join that never returns would be

    def test_after_the_hang():
        pass
    ''')


def test_a_hanging_test_ends_the_session_with_its_id_and_stacks(tmp_path):
    (tmp_path / "test_hang.py").write_text(HANGING_TESTS)
    environment = dict(os.environ, SEAMLESS_AO_TEST_STALL="4", PYTHONPATH=str(TESTS))
    finished = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "conftest", "--rootdir", str(tmp_path), "-c", os.devnull,
         "-p", "no:cacheprovider", str(tmp_path / "test_hang.py")],
        cwd=tmp_path, env=environment, capture_output=True, text=True, timeout=200)
    output = finished.stdout + finished.stderr
    assert finished.returncode != 0, output
    last = output.strip().splitlines()[-1]
    assert last.startswith("[watchdog] the test session hung in test_hang.py::test_that_hangs_in_a_native_wait"), output
    assert "test_before_the_hang" not in output, output
    assert 'test_hang.py", line 8 in test_that_hangs_in_a_native_wait' in output, output   # Python stack
    assert "passed" not in output, output
