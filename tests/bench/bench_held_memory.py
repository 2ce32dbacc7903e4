"""Benchmark: A big bake's freed memory held for its next stage, against handed back to the system (issue 56).

    .venv/5.0/bin/python tests/bench/bench_held_memory.py [--runs 5] [--rounds 2] [--meshes million_suzanne]

Bakes each 1M-triangle mesh of bench_million.py at its cheapest setting (256², 1 ray) through the operator,
in processes of their own: in one, the bake holds what it frees (core/freed_memory.py's freed_memory_held,
as it ships); in the other, that hold does nothing, so glibc hands every freed block of more than its mmap
threshold back, and the next stage's arrays fault in fresh pages.  Each process bakes once unseen, then --runs
times; --rounds pairs of processes take turns.  Seconds are the median bake; system seconds and page faults
(Linux's minor faults: a transparent huge page counts once) are the main thread's in each bake (where the
layout's arrays are made; Blender's worker threads yield to each other in system calls of their own), medians
too.
"""

import argparse
import contextlib
import resource
import statistics
import time

from common import child_result, finish, markdown_table, print_result, say

import bench_million  # noqa: E402
import report  # noqa: E402

SETTING = (256, 1)
#: The calling thread alone (Linux); elsewhere the whole process.
MAIN_THREAD = getattr(resource, "RUSAGE_THREAD", resource.RUSAGE_SELF)


def child(name, held, runs):
    """In this process: bake ``name`` once unseen, then ``runs`` times; print the medians as a RESULT line."""
    import seamless_ao.core.pipeline as pipeline
    import seamless_ao.operators.adapters.session as session
    if not held:
        for module in (pipeline, session):
            module.freed_memory_held = lambda triangles: contextlib.nullcontext(False)
    report.MESHES.update(bench_million.MILLION_MESHES)
    ob = report.fresh(name)
    size, rays = SETTING
    report.seamless_bake(ob, image_size=size, rays=rays)
    rows = []
    for _ in range(runs):
        before, start = resource.getrusage(MAIN_THREAD), time.perf_counter()
        report.seamless_bake(ob, image_size=size, rays=rays)
        after = resource.getrusage(MAIN_THREAD)
        rows.append((time.perf_counter() - start, after.ru_stime - before.ru_stime,
                     after.ru_minflt - before.ru_minflt))
    print_result([statistics.median(row[k] for row in rows) for k in range(3)])


def measure(name, held, runs):
    try:
        return child_result(__file__, "--child", name, "held" if held else "handed-back", "--runs", str(runs),
                            timeout=1800)
    except RuntimeError as error:
        raise RuntimeError("the bake of {} failed: {}".format(name, error)) from None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=["million_suzanne", "million_scan"],
                        choices=list(bench_million.MILLION_MESHES))
    parser.add_argument("--runs", type=int, default=5, help="timed bakes in each process")
    parser.add_argument("--rounds", type=int, default=2, help="pairs of processes, taking turns")
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child[0], args.child[1] == "held", args.runs)
        return
    headers = ["mesh", "freed memory", "seconds", "main thread's system s", "its page faults"]
    rows = []
    for name in args.meshes:
        results = {True: [], False: []}
        for _ in range(args.rounds):
            for held in (True, False):
                results[held].append(measure(name, held, args.runs))
        for held in (True, False):
            seconds, system, faults = (statistics.median(r[k] for r in results[held]) for k in range(3))
            rows.append([name, "held (as shipped)" if held else "handed back", "{:.2f}".format(seconds),
                         "{:.2f}".format(system), "{:,.0f}".format(faults)])
        print(markdown_table(headers, rows[-2:]), flush=True)
    say("{}², {} ray; median of {} rounds of {} bakes.".format(*SETTING, args.rounds, args.runs))
    say()
    say(markdown_table(headers, rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
