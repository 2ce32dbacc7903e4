"""Benchmark: Rays in proportion to the blend weight, on and off.

    .venv/5.0/bin/python tests/bench/bench_weighted.py [--image-size 512] [--rays 8 16 32 64]

Suzanne subdivided twice, baked at each ray count with weighted rays off and
on (denoiser and adaptive sampling on, the defaults otherwise), compared at
2,000 visible points with the plain 4096-ray reference
(tests/support/plain_reference.py).  Prints rays cast, seconds (median of
``--runs`` warm runs), RMSE and 99th percentile; then, for each weighted run,
the rays and seconds an unweighted bake needs for the same RMSE
(interpolated in log rays between the measured ray counts).
"""

import argparse
import statistics

import numpy as np

from common import finish, markdown_table, say, suzanne_with_reference

import bpy

import package
from accuracy import errors, shown_seamless


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--image-size", type=int, default=512)
    parser.add_argument("--rays", type=int, nargs="+", default=[8, 16, 32, 64])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    ob, loops, triangle, bary, normals, reference = suzanne_with_reference()
    package.seamless_ao.bake([ob], image_size=args.image_size, rays=8)           # warm-up
    results = {}
    rows = []
    for rays in args.rays:
        for weighted in (False, True):
            seconds = []
            for _ in range(args.runs):
                report = package.seamless_ao.bake([ob], image_size=args.image_size, rays=rays, weighted_rays=weighted)
                seconds.append(report.seconds)
            shown = shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)
            rmse, p99 = errors(shown, reference)
            results[rays, weighted] = (report.rays, statistics.median(seconds), rmse)
            rows.append([rays, "on" if weighted else "off", "{:,.0f}".format(report.rays),
                         "{:.2f}".format(statistics.median(seconds)), "{:.4f}".format(rmse), "{:.4f}".format(p99),
                         "{:.4f}".format(report.noise)])
    say(markdown_table(["rays", "weighted", "rays cast", "seconds", "RMSE", "p99", "noise estimate"], rows))
    # unweighted RMSE as a function of log rays cast, for "what would the same error cost without weighting"
    plain = sorted((results[r, False] for r in args.rays), key=lambda item: item[0])
    cast, secs, err = (np.array(column, dtype=float) for column in zip(*plain))
    say()
    for rays in args.rays:
        weighted_cast, weighted_seconds, weighted_rmse = results[rays, True]
        if not err.min() <= weighted_rmse <= err.max():
            say("{} rays, weighted: RMSE {:.4f} outside the unweighted range".format(rays, weighted_rmse))
            continue
        # err falls with rays: interpolate log(cast) and seconds at the weighted RMSE
        order = np.argsort(err)
        need_cast = float(np.exp(np.interp(weighted_rmse, err[order], np.log(cast[order]))))
        need_seconds = float(np.interp(weighted_rmse, err[order], secs[order]))
        say("{} rays, weighted: RMSE {:.4f} with {:,.0f} rays in {:.2f} s; unweighted needs about {:,.0f} rays "
              "({:.0%} more) and {:.2f} s".format(rays, weighted_rmse, weighted_cast, weighted_seconds, need_cast,
                                                   need_cast / weighted_cast - 1.0, need_seconds))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
