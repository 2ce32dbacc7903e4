"""This process's memory as Linux reports it (/proc/self/status): what the benchmarks print and the tests of
core/freed_memory.py check."""

import resource


def _status_mb(field):
    """A memory figure of this process from Linux's /proc/self/status (``VmRSS``, ``VmHWM``), MB; None where
    there is no such file."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith(field + ":"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def resident_mb():
    """Resident memory of this process now, MB (0 where /proc is missing)."""
    return _status_mb("VmRSS") or 0.0


def process_peak_mb():
    """Peak resident memory of this process so far, MB: Linux's VmHWM, the high-water mark of this
    process's own memory.  Not ``ru_maxrss``: Linux carries a process's ru_maxrss over from the process
    that started it (exec keeps the larger of the two), so a child started by a bench that had baked a
    1M-triangle mesh reported that bench's 2.1 to 2.5 GB instead of its own 1.65."""
    peak = _status_mb("VmHWM")
    return peak if peak is not None else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
