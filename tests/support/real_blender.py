"""A real ``blender`` binary for the tests: Debian's Blender in the root ``tests/scripts/make_blender_root.sh``
builds (outside the repository, once per machine), run with ``chroot``.

    with RealBlender(root, scratch) as blender:      # mounts; on leaving, ends its processes and unmounts
        blender.run("blender", "--background", "--command", "extension", "install-file", ...)
        blender.inside(scratch / "scene.blend")          # -> "/scratch/scene.blend"

Inside the root the repository is ``/seamless_ao`` (read-only) and ``scratch`` is ``/scratch``, which is
also ``HOME``: the Blender preferences and extensions of these tests live there, never in the user's.
``make test`` builds the root and names it in ``SEAMLESS_AO_BLENDER_ROOT``.
"""

import contextlib
import os
import pathlib
import signal
import subprocess
import time

REPO = pathlib.Path(__file__).resolve().parents[2]
#: The environment variable through which ``make test`` names the root.
ROOT_VARIABLE = "SEAMLESS_AO_BLENDER_ROOT"
#: The Blender the root holds (Debian trixie's ``blender`` package), and its Python: docs/tested.md names
#: them, and a test checks the root's binary is this one.
BLENDER_VERSION = "4.3.2"
BLENDER_PYTHON = "3.13"
REPO_INSIDE = "/seamless_ao"
SCRATCH_INSIDE = "/scratch"
PATH = "/usr/local/bin:/usr/bin:/bin"
#: The X display and screen the window tests run Blender on (Xvfb inside the root).
DISPLAY = ":99"
SCREEN = "1600x900x24"


def root_from_environment():
    """The root ``make test`` built, or None (the tests then skip)."""
    root = os.environ.get(ROOT_VARIABLE)
    return pathlib.Path(root) if root and (pathlib.Path(root) / "usr" / "bin" / "blender").exists() else None


def _is_mount(path):
    return subprocess.run(["mountpoint", "-q", str(path)]).returncode == 0


class RealBlender:
    """Run commands with the root's Blender; see the module's docstring."""

    def __init__(self, root, scratch):
        self.root = pathlib.Path(root).resolve()
        self.scratch = pathlib.Path(scratch).resolve()
        self.mounts = []

    def __enter__(self):
        stale = [self.root / inside.lstrip("/") for inside in ("proc", "dev", REPO_INSIDE, SCRATCH_INSIDE)]
        if any(_is_mount(target) for target in stale) and not self.processes():
            for target in reversed(stale):              # left by a run that was killed: nothing uses them
                subprocess.run(["umount", "-l", str(target)], check=False, stderr=subprocess.DEVNULL)
        try:
            self._mount("proc", ["-t", "proc", "proc"])
            self._mount("dev", ["--bind", "/dev"])
            self._mount(REPO_INSIDE, ["--bind", str(REPO)], read_only=True)
            self._mount(SCRATCH_INSIDE, ["--bind", str(self.scratch)])
        except BaseException:
            self.__exit__(None, None, None)
            raise
        return self

    def _mount(self, inside, arguments, read_only=False):
        target = self.root / inside.lstrip("/")
        target.mkdir(exist_ok=True)
        if _is_mount(target):
            raise RuntimeError("{} is mounted and a process runs in the root: another run of the tests uses "
                               "it".format(target))
        subprocess.run(["mount", *arguments, str(target)], check=True)
        self.mounts.append(target)
        if read_only:
            subprocess.run(["mount", "-o", "remount,bind,ro", str(target)], check=True)

    def __exit__(self, *exc):
        self.end_processes()
        for target in reversed(self.mounts):
            subprocess.run(["umount", str(target)], check=False)
            if _is_mount(target):
                subprocess.run(["umount", "-l", str(target)], check=False)
        self.mounts = []

    def processes(self):
        """Process ids of everything running inside the root."""
        found = []
        for entry in pathlib.Path("/proc").iterdir():
            if entry.name.isdigit():
                try:
                    if os.readlink(entry / "root") == str(self.root):
                        found.append(int(entry.name))
                except OSError:
                    pass
        return found

    def end_processes(self):
        for pid in self.processes():
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass

    def inside(self, host_path):
        """The path inside the root of ``host_path`` (under the scratch folder or the repository)."""
        host_path = pathlib.Path(host_path).resolve()
        for outside, inside in ((self.scratch, SCRATCH_INSIDE), (REPO, REPO_INSIDE)):
            if host_path == outside or outside in host_path.parents:
                return str(pathlib.PurePosixPath(inside) / host_path.relative_to(outside))
        raise ValueError("{} is seen neither in the scratch folder nor in the repository".format(host_path))

    def run(self, *command, cwd=None, timeout=600, env=None):
        """Run ``command`` inside the root in ``cwd`` (a host path; default the scratch folder), with a clean
        environment (``HOME`` the scratch folder) plus ``env``; the finished process, output as text.  A
        command past ``timeout`` is killed with everything it started, and ``TimeoutExpired`` raised."""
        environment = ["HOME=" + SCRATCH_INSIDE, "PATH=" + PATH, "LANG=C.UTF-8"]
        environment += ["{}={}".format(*item) for item in (env or {}).items()]
        where = self.inside(cwd or self.scratch)
        process = subprocess.Popen(
            ["chroot", str(self.root), "env", "-i", *environment, "sh", "-c", 'cd "$0" && exec "$@"', where,
             *command], stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
            start_new_session=True)
        try:
            stdout, stderr = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
            raise
        return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)

    def blender_python(self, code, *args, timeout=600):
        """Run ``code`` (a Python script's text) in a background Blender with factory settings; the script
        gets ``args`` after ``--``."""
        script = self.scratch / "script_{}.py".format(len(list(self.scratch.glob("script_*.py"))))
        script.write_text(code)
        return self.run("blender", "--background", "--factory-startup", "--python", self.inside(script), "--",
                        *args, timeout=timeout)

    @contextlib.contextmanager
    def display(self):
        """An X server (Xvfb) inside the root for the duration; yields the environment a window needs."""
        socket = self.root / "tmp" / ".X11-unix" / "X{}".format(DISPLAY.lstrip(":"))
        if socket.exists():
            socket.unlink()                    # left by a server that was killed
        server = subprocess.Popen(["chroot", str(self.root), "Xvfb", DISPLAY, "-screen", "0", SCREEN, "-nolisten",
                                   "tcp"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                  start_new_session=True)
        try:
            deadline = time.monotonic() + 30
            while not socket.exists():
                if server.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError("Xvfb did not start in the root (exit code {})".format(server.poll()))
                time.sleep(0.1)
            yield {"DISPLAY": DISPLAY}
        finally:
            os.killpg(server.pid, signal.SIGKILL)
            server.wait()
