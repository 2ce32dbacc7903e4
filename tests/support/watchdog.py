"""A process that watches the test session and ends it when one test hangs, saying where it stood.

    python watchdog.py SESSION_PID STALL_SECONDS     (started by tests/conftest.py; reads its stdin)

The session writes a line per test to this process's stdin: the test's id when it starts, ``-`` when it
ends.  A test still running after ``STALL_SECONDS`` is taken for hung (a native thread that never wakes,
say, which no Python thread of the session could report: the hung call may hold the GIL).  This process
then writes, on its stderr (the session's terminal):

1. the native stack of every thread of the session, from gdb where the machine has it;
2. every thread's Python stack: it sends the session ``STACK_SIGNAL``, which conftest.py has
   faulthandler answer (a C handler, which needs no GIL);
3. last, so that a log cut to its tail still shows it, one line naming the test and how long it ran;

and kills the session, whose run fails.  When the session ends, its end of the pipe closes and so does
this process.
"""

import os
import select
import shutil
import signal
import subprocess
import sys
import time

#: The signal on which the session's faulthandler writes every thread's Python stack.
STACK_SIGNAL = signal.SIGUSR1
#: Seconds gdb may take to attach and write the native stacks.
GDB_TIMEOUT = 120
#: Frames of each thread's native stack that gdb writes.
GDB_FRAMES = 25


def native_stacks(pid):
    """Every thread's native stack of process ``pid`` (str), or a sentence saying why there is none."""
    gdb = shutil.which("gdb")
    if gdb is None:
        return "(no gdb on this machine: no native stacks)\n"
    try:
        finished = subprocess.run(
            [gdb, "-p", str(pid), "-batch", "-nx", "-ex", "set pagination off",
             "-ex", "thread apply all bt {}".format(GDB_FRAMES)],
            capture_output=True, text=True, timeout=GDB_TIMEOUT, stdin=subprocess.DEVNULL)
    except (OSError, subprocess.TimeoutExpired) as error:
        return "(gdb gave no native stacks: {})\n".format(error)
    lines = [line for line in finished.stdout.splitlines() if line.startswith(("Thread ", "#"))]
    return "\n".join(lines) + "\n" if lines else "(gdb gave no native stacks)\n" + finished.stderr


def report_hang(pid, test, seconds, out):
    out.write("\n[watchdog] {} has run {:.0f} s: taken for hung. Native stacks:\n".format(test, seconds))
    out.write(native_stacks(pid))
    out.write("[watchdog] Python stacks:\n")
    out.flush()
    try:
        os.kill(pid, STACK_SIGNAL)
        time.sleep(2.0)                            # faulthandler writes from the session's own process
    except OSError:
        pass
    out.write("\n[watchdog] the test session hung in {} ({:.0f} s); killed\n".format(test, seconds))
    out.flush()
    try:
        os.kill(pid, signal.SIGKILL)
    except OSError:
        pass


def watch(pid, stall, source=sys.stdin, out=sys.stderr):
    """Follow the session's lines on ``source`` until it closes; report and kill on a test past ``stall``."""
    test, started = None, None
    pending = ""
    while True:
        wait = None if test is None else max(0.0, started + stall - time.monotonic())
        ready, _, _ = select.select([source], [], [], wait)
        if not ready:
            report_hang(pid, test, time.monotonic() - started, out)
            return 1
        chunk = os.read(source.fileno(), 4096).decode("utf-8", "replace")
        if not chunk:
            return 0                               # the session ended
        pending += chunk
        *lines, pending = pending.split("\n")
        for line in lines:
            test, started = (None, None) if line == "-" else (line, time.monotonic())


if __name__ == "__main__":
    sys.exit(watch(int(sys.argv[1]), float(sys.argv[2])))
