"""Speed against error: Seamless AO and Blender's own route (Smart UV Project + Cycles AO bake).

    .venv/5.0/bin/python tests/bench/report.py [--meshes suzanne dense scan interior] [--runs 3] [--gpu TYPE]

For each mesh it computes the plain reference (tests/support/plain_reference.py: no
code shared with either baker) at random visible surface points with many
rays (cached on disk, keyed by the mesh, the points and the reference's code;
the maximum distance is fixed: half the object's diagonal), then bakes with Seamless AO and with Cycles at several
settings, and evaluates what each shows at those points: for Seamless AO the
normal-squared blend through AO_X/Y/Z, for Cycles a bilinear lookup through
its Smart UV map, both as Blender's Image Texture node samples.  Both use
binary AO within the same maximum distance (half the object's diagonal).

Timing: both bakers as a user waits for them, through their operators (Seamless AO's bake operator;
Smart UV Project then Bake), warm: per mesh, one untimed bake of each baker first, then every setting is
baked --runs times and the median run is reported.  Smart UV Project keeps islands 2 texels apart at each
image size (cycles_baseline.ISLAND_MARGIN_TEXELS) and Cycles' bake margin is 16 px.

Seamless AO is run with its Geometry Nodes ray caster (also once without the denoiser, to show what it
buys) and, from 16 rays, with its Cycles ray caster too (Ray Caster: Cycles; the first few rays of each
texel are the node's either way); each run names its caster. The default, Ray Caster: Automatic, takes the
Cycles caster at these settings from 5 rays and the node below.

Seamless AO is also run at each Quality preset (Draft, Good, Final; Ray Caster Automatic); the last table
sets each beside Cycles' cheapest route to the error it promises (issue 52, tests/bench/quality_promises.py).

Time to error (issue 30): each Cycles setting's RMSE is a level; for each level, Cycles' time is that of
its cheapest setting (of 256², 512², 1024² x 16, 64, 256 samples) at least as accurate, and Seamless AO's
that of its cheapest run at least as accurate, with either caster (from 256², 1 ray: the least its operator
takes); the ratio is ours over Cycles'.

Seams: for every chart border of a method (Seamless AO: mesh edges where any
of the three UV maps jumps; Cycles: UV island borders), points a tiny step
either side of the edge; the seam error is how much the shown AO jumps across
the edge beyond what the reference jumps (AO itself jumps at sharp creases).

Writes ``report.md`` (table), ``speed_error.png`` (plot) and seam close-up
renders into the output directory.
"""

import argparse
import hashlib
import json
import pathlib
import time

import numpy as np

from common import PAGES, cached_surface_samples, finish, markdown_table, say, use_gpu
from quality_promises import (HEADERS as PROMISE_HEADERS, PRESET_METHOD, cheapest_reaching, promise_rows,
                              promise_sentence)

import bpy

from accuracy import errors, reference_ao, shown_seamless, shown_single_uv, world_map
from blender_scenes import cornell_box, sphere_over_plane, suzanne
from cycles_baseline import UV_NAME, cycles_ao_bake, half_diagonal
from seams import point_normals, seam_error, seam_pairs, seam_renders
from seamless_ao.core.keys import IMAGE_KEY
from seamless_ao.core.settings import PRESETS, QUALITY_ITEMS
from seamless_ao.operators.adapters.mesh_data import read_triangles

import package

PACKAGE = package.seamless_ao
REFERENCE_RAYS = 4096
POINTS = 2000
SEAM_RAYS = 512
#: Seamless AO's settings, cheapest first: any image size from 256² (the operator's least) up is a whole number
#: of texels, rays from 1 (the operator's least; the denoiser works on any count).
SEAMLESS_RUNS = [(256, 1), (256, 2), (256, 4), (256, 8), (256, 16), (256, 32), (384, 16), (384, 32), (512, 8), (512, 16), (512, 32),
                 (768, 32), (1024, 16), (1024, 32)]
#: Cycles' settings: the image sizes and sample counts a user picks from.
CYCLES_RUNS = [(size, samples) for size in (256, 512, 1024) for samples in (16, 64, 256)]
#: Without the denoiser, to show what it buys (issue 9: keep it only if the numbers say it helps).
RAW_RUNS = [(512, 16)]
#: With the Cycles ray caster: from 16 rays, where Cycles casts at least half of each texel's rays
#: (core/rays/cycles_rules.py BULK_PILOT_RAYS are the node's).
CYCLES_CASTER_RUNS = [(256, 16), (256, 32), (384, 32), (512, 16), (512, 32), (768, 32), (1024, 32)]
#: The report's names of the kinds of Seamless AO run (the methods of its table and plot).
OURS = "Seamless AO"
#: Issue 52's time-to-error rule: below this many seconds of Cycles' a bake of ours may take up to this long.
RULE_SECONDS = 1.0
OURS_CYCLES = "Seamless AO, Cycles rays"
OURS_RAW = "Seamless AO, no denoise"


def spiral_ramp_object():
    from meshes import spiral_ramp
    from blender_scenes import add_object, mesh_from_arrays
    positions, triangles = spiral_ramp(turns=3.0, steps_per_turn=64, width_steps=6)
    return add_object("Fold", mesh_from_arrays("Fold", positions, triangles))


def interior_object():
    """The generated interior of many pieces (tests/support/real_assets.py; its counts: docs/bench/bench_meshes.md)."""
    from real_assets import interior
    from blender_scenes import add_object, mesh_from_arrays
    positions, triangles = interior()
    return add_object("Interior", mesh_from_arrays("Interior", positions, triangles))


def scan_object():
    """A scan-like mesh (one closed noisy surface with holes, shaded smooth; its counts: docs/bench/bench_meshes.md)."""
    from real_assets import noisy_scan
    from blender_scenes import add_object, mesh_from_arrays
    positions, triangles = noisy_scan(triangles=70_000)
    return add_object("Scan", mesh_from_arrays("Scan", positions, triangles, smooth=True))


MESHES = {
    "cube": lambda: _cube(),
    "suzanne": lambda: suzanne(2),
    "cornell": lambda: cornell_box(),
    "sphere_plane": lambda: sphere_over_plane(),
    "fold": spiral_ramp_object,
    "dense": lambda: suzanne(4, name="Dense Suzanne"),
    "scan": scan_object,
    "interior": interior_object,
}
#: What the report runs by default: issue 30's four meshes.
DEFAULT_MESHES = ["suzanne", "dense", "scan", "interior"]


def _cube():
    bpy.ops.mesh.primitive_cube_add()
    return bpy.context.active_object


def fresh(mesh_name):
    if hasattr(bpy.types.Scene, "seamless_ao"):
        PACKAGE.unregister()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    PACKAGE.register()
    ob = MESHES[mesh_name]()
    bpy.context.view_layer.update()
    return ob


def mesh_key(ob, mesh):
    """Cache key of a reference: the mesh as it stands in the world, the points, the rays, the maximum
    distance and falloff (binary, half the world diagonal: reference_ao's only mode) and the reference's
    own code."""
    code = (pathlib.Path(__file__).resolve().parent.parent / "support" / "plain_reference.py").read_bytes()
    code += (pathlib.Path(__file__).resolve().parent.parent / "support" / "accuracy.py").read_bytes()
    world, _ = world_map(ob)(mesh.positions)
    distance = 0.5 * float(np.linalg.norm(world.max(axis=0) - world.min(axis=0)))
    conventions = "falloff=binary distance={!r}".format(distance).encode()
    digest = hashlib.sha1(world.tobytes() + mesh.triangles.tobytes() + conventions + code).hexdigest()[:12]
    return "{}-{}-{}".format(digest, POINTS, REFERENCE_RAYS)


def reference(ob, mesh, cache):
    """Reference AO at POINTS random points, both cached in ``cache``."""
    stem = "{}-{}".format(ob.name.replace(" ", "_"), mesh_key(ob, mesh))
    triangle, bary, normals = cached_surface_samples(mesh, POINTS, 5, cache / (stem + "-points.npz"))
    path = cache / (stem + ".npy")
    if path.exists():
        return triangle, bary, normals, np.load(path), 0.0
    start = time.perf_counter()
    values = reference_ao(ob, mesh, triangle, bary, normals, rays=REFERENCE_RAYS)
    np.save(path, values)
    return triangle, bary, normals, values, time.perf_counter() - start


def fresh_with_reference(name, work_dir):
    """For the benchmarks that measure against this report's reference: a fresh scene holding mesh ``name``,
    and ``(object, its loops, (triangle, bary, normals) of the points, reference AO there)``, the reference
    cached in ``work_dir``/cache as :func:`main` caches it."""
    cache = pathlib.Path(work_dir) / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    ob = fresh(name)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, ref, _ = reference(ob, mesh, cache)
    return ob, loops, (triangle, bary, normals), ref


def bench_arguments(description, meshes, settings, runs=None):
    """Command-line options of the benchmarks that bake report meshes at "<image size>x<rays>" settings against
    this report's reference: ``(args, [(image size, rays), ...])``; ``--runs`` only if ``runs`` is given."""
    parser = argparse.ArgumentParser(description=description)
    if runs is not None:
        parser.add_argument("--runs", type=int, default=runs, help="timed runs of each setting (the median counts)")
    parser.add_argument("--meshes", nargs="+", default=meshes, choices=list(MESHES))
    parser.add_argument("--work-dir", default="out/bench", help="the reference cache (shared with report.py)")
    parser.add_argument("--settings", nargs="+", default=settings, help="image size x rays, e.g. 256x2")
    args = parser.parse_args()
    pairs = [setting.split("x") for setting in args.settings]
    if not all(len(pair) == 2 and all(n.isdigit() for n in pair) for pair in pairs):
        parser.error("a setting is <image size>x<rays>, e.g. 256x2 (got {})".format(" ".join(args.settings)))
    return args, [(int(size), int(rays)) for size, rays in pairs]


def run_mesh(name, cache, out, rows, curves, timed_runs=3):
    from blender_checks import uv_layer_array
    ob = fresh(name)
    mesh, loops = read_triangles(ob.data)
    triangle, bary, normals, ref, ref_seconds = reference(ob, mesh, cache)
    print("{}: {:,} triangles, reference {:.1f} s".format(name, len(mesh.triangles), ref_seconds), flush=True)
    distance = half_diagonal(ob, mesh)
    rng = np.random.default_rng(1)
    seam_refs = {}
    # A primitive whose AO is 1 everywhere is exact at any setting: its cheapest runs say so.
    trivial = name == "cube"

    def seam_reference(pairs):
        """Reference AO either side of each seam point (each layout has its own seams)."""
        key = hashlib.sha1(b"".join(np.ascontiguousarray(p).tobytes() for p in pairs)).hexdigest()
        if key not in seam_refs:
            ta, ba, tb, bb = pairs
            a = reference_ao(ob, mesh, ta, ba, point_normals(mesh, ta, ba), rays=SEAM_RAYS)
            b = reference_ao(ob, mesh, tb, bb, point_normals(mesh, tb, bb), rays=SEAM_RAYS)
            seam_refs[key] = (a, b)
        return seam_refs[key]

    def record(method, settings, seconds, stages, shown, seam_show, uv_layers, label):
        rmse, p99 = errors(shown, ref)
        pairs = seam_pairs(mesh, loops, uv_layers, rng)
        seam = ("-", "-")
        if pairs is not None:
            ref_a, ref_b = seam_reference(pairs)
            seam = seam_error(seam_show, ref_a, ref_b, pairs)
        rows.append([name, method, settings, "{:.2f}".format(seconds), stages, "{:.4f}".format(rmse),
                     "{:.4f}".format(p99), _fmt_seam(seam)])
        curves.setdefault((name, method), []).append((seconds, rmse, label))
        print("  " + " | ".join(rows[-1][1:]), flush=True)

    # The same warm-up for both: one untimed bake of each before any timed one (Cycles loads its
    # kernels, the add-on its Geometry Nodes caster), then every point is timed ``timed_runs`` times and
    # the median run reported.
    warm = cycles_ao_bake(ob, 256, 1, distance)[0]
    bpy.data.images.remove(warm)
    seamless_bake(ob, image_size=256, rays=1)                   # replaced by the next bake

    # Cycles first, so the last Seamless AO bake is still in place for the seam renders.
    kept = None
    for image_size, samples in CYCLES_RUNS[:1] if trivial else CYCLES_RUNS:
        unwrap, bake, image = cycles_median_bake(ob, image_size, samples, distance, timed_runs)
        record("Cycles", "{}², {} samples".format(image_size, samples), unwrap + bake,
               "unwrap {:.2f} + bake {:.2f}".format(unwrap, bake),
               shown_single_uv(ob, image, UV_NAME, loops, triangle, bary),
               lambda t, b, image=image: shown_single_uv(ob, image, UV_NAME, loops, t, b),
               [uv_layer_array(ob.data, UV_NAME)], "{}/{}".format(image_size, samples))
        if kept is not None:
            bpy.data.images.remove(kept)
        kept = image
    # Undenoised and Cycles-cast first, so the last bake left on the object (for the seam renders) is a
    # default one.
    def sized(method, size, rays, **extra):
        """A run at an image size and rays: ``(method, its setting in the table, its plot label, settings)``."""
        return method, "{}², {} rays".format(size, rays), "{}/{}".format(size, rays), \
            dict(image_size=size, rays=rays, **extra)

    runs = [sized(OURS_RAW, size, rays, denoise=False, ray_caster="GEOMETRY_NODES")
            for size, rays in ([] if trivial else RAW_RUNS)]
    runs += [sized(OURS_CYCLES, size, rays, ray_caster="CYCLES")
             for size, rays in ([] if trivial else CYCLES_CASTER_RUNS)]
    runs += [(PRESET_METHOD, "{} ({}², {} rays)".format(label, *PRESETS[quality]), label, dict(quality=quality))
             for quality, label, _ in QUALITY_ITEMS if quality in PRESETS]
    runs += [sized(OURS, size, rays, ray_caster="GEOMETRY_NODES")
             for size, rays in (SEAMLESS_RUNS[:1] if trivial else SEAMLESS_RUNS)]
    if not trivial:                                    # Cycles' own warm-up is done; the caster's scene is not
        seamless_bake(ob, image_size=256, rays=16, ray_caster="CYCLES")
    for method, setting, curve_label, settings in runs:
        seconds, image_name, stages = seamless_median_bake(ob, timed_runs, **settings)
        image = bpy.data.images[image_name]
        record(method, setting,
               seconds, " + ".join("{} {:.2f}".format(k, v) for k, v in stages.items()),
               shown_seamless(ob, image, loops, triangle, bary, normals),
               lambda t, b, image=image: shown_seamless(ob, image, loops, t, b, point_normals(mesh, t, b)),
               [uv_layer_array(ob.data, n) for n in ("AO_X", "AO_Y", "AO_Z")], curve_label)
    if name == "suzanne":
        seam_renders(ob, out, kept)


def cycles_median_bake(ob, image_size, samples, distance, timed_runs):
    """Smart UV Project + Cycles' AO bake ``timed_runs`` times: the median run's ``(unwrap s, bake s, image)``
    (the other runs' images removed)."""
    runs = []
    for _ in range(timed_runs):
        image, unwrap, bake = cycles_ao_bake(ob, image_size, samples, distance)
        runs.append((unwrap + bake, unwrap, bake, image))
    runs.sort(key=lambda run: run[0])
    for run in runs[:len(runs) // 2] + runs[len(runs) // 2 + 1:]:
        bpy.data.images.remove(run[3])
    return runs[len(runs) // 2][1:]


def seamless_median_bake(ob, timed_runs, **settings):
    """:func:`seamless_bake` ``timed_runs`` times: the median run."""
    runs = sorted((seamless_bake(ob, **settings) for _ in range(timed_runs)), key=lambda run: run[0])
    return runs[len(runs) // 2]


def seamless_bake(ob, **settings):
    """One bake through the operator, timed as the user waits: ``(seconds, image name, stage seconds)``."""
    view_layer = bpy.context.view_layer
    for other in view_layer.objects:
        other.select_set(other == ob)
    view_layer.objects.active = ob
    start = time.perf_counter()
    result = bpy.ops.object.seamless_ao_bake(**settings)
    seconds = time.perf_counter() - start
    assert result == {"FINISHED"}, result
    return seconds, ob[IMAGE_KEY], json.loads(bpy.context.scene.seamless_ao.last_bake_stages)


def _fmt_seam(seam):
    if seam[0] == "-":
        return "-"
    return "{:.4f} / {:.4f}".format(*seam)


def plot(curves, path):
    import matplotlib
    import matplotlib.ticker
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = sorted({name for name, _ in curves})
    fig, axes = plt.subplots(2, (len(names) + 1) // 2, figsize=(4.2 * ((len(names) + 1) // 2), 7.5), squeeze=False)
    for ax, name in zip(axes.ravel(), names):
        for method, style, colour in ((OURS, "o-", "tab:blue"), (OURS_RAW, "^:", "tab:cyan"),
                                      (OURS_CYCLES, "D-.", "tab:purple"), ("Cycles", "s--", "tab:orange"),
                                      (PRESET_METHOD, "*", "tab:red")):
            points = sorted(curves.get((name, method), []))
            if not points:
                continue
            ys = [max(p[1], 1e-4) for p in points]
            ax.plot([p[0] for p in points], ys, style, color=colour, label=method)
            for (seconds, _, label), y in zip(points, ys):
                ax.annotate(label, (seconds, y), fontsize=6, xytext=(2, 2), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
        for axis in (ax.xaxis, ax.yaxis):
            # Label 1, 2 and 5 of every decade: most panels span less than one.
            axis.set_major_formatter(plain)
            axis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
            axis.set_minor_formatter(plain)
        ax.set_title(name if name != "cube" else "cube (AO = 1 everywhere: both exact)")
        ax.set_xlabel("time (s, log)")
        ax.set_ylabel("RMSE vs reference (log)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes.ravel()[len(names):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def time_to_cycles_error(curves):
    """Issue 30's table: per mesh and Cycles level (each Cycles setting's RMSE), Cycles' cheapest setting at
    least as accurate, Seamless AO's cheapest run (denoised, as by default; either ray caster) at least as
    accurate, and the ratio of their times.  ``curves[(mesh, method)]`` holds ``[seconds, RMSE, "size/rays"]``
    per run.

    The last column applies issue 52's rule: where Cycles' cheapest takes at least 1 s, ours at most half of
    it; where it takes less, ours at most 1 s.

    Returns the Markdown table and ``(cells, cells at most 1.0, cells at most 0.5, cells keeping the rule)``.
    """
    rows, counts = [], [0, 0, 0, 0]
    for mesh in list(dict.fromkeys(mesh for mesh, _ in curves)):
        cycles = sorted(curves.get((mesh, "Cycles"), []))
        ours = sorted(curves.get((mesh, OURS), []) +
                      [(seconds, rmse, label + " Cycles") for seconds, rmse, label in curves.get((mesh, OURS_CYCLES), [])])
        for _, level, label in sorted(cycles, key=lambda run: -run[1]):
            their = cheapest_reaching(cycles, level)
            good = cheapest_reaching(ours, level)
            row = [mesh, "{} ({:.4f})".format(label.replace("/", "²/"), level),
                   "{:.2f} s ({})".format(their[0], their[2].replace("/", "²/"))]
            counts[0] += 1
            if good is not None:
                ratio = good[0] / their[0]
                counts[1] += ratio <= 1.0
                counts[2] += ratio <= 0.5
                kept = good[0] <= (0.5 * their[0] if their[0] >= RULE_SECONDS else RULE_SECONDS)
                counts[3] += kept
                row += ["{:.2f} s ({}, {:.4f})".format(good[0], good[2].replace("/", "²/"), good[1]),
                        "{:.2f}".format(ratio), "yes" if kept else "**no**"]
            else:
                best = min(ours, key=lambda run: run[1])
                row += ["none (best {:.4f}: {})".format(best[1], best[2].replace("/", "²/")), "-", "**no**"]
            rows.append(row)
    table = markdown_table(["mesh", "Cycles level (its RMSE)", "Cycles' cheapest to it",
                            "Seamless AO's cheapest (RMSE)", "ratio", "rule kept"], rows)
    return table, counts


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default=str(PAGES), help="where the plot and the seam renders go")
    parser.add_argument("--work-dir", default="out/bench", help="the reference cache and curves.json")
    parser.add_argument("--meshes", nargs="+", default=DEFAULT_MESHES, choices=list(MESHES))
    parser.add_argument("--runs", type=int, default=3, help="timed runs of each setting (the median is reported)")
    parser.add_argument("--plot-only", action="store_true",
                        help="redraw the plot and print the time-to-error table from curves.json")
    parser.add_argument("--gpu", metavar="TYPE", help="both bakers' Cycles on every GPU of this type (CUDA, "
                        "OPTIX, HIP, ONEAPI, METAL), as Cycles' preferences would set it; default: the CPU")
    args = parser.parse_args()
    if args.gpu:
        use_gpu(args.gpu)
    out = pathlib.Path(args.output_dir).resolve()
    work = pathlib.Path(args.work_dir).resolve()
    if args.plot_only:
        curves = {tuple(k.split("|")): v for k, v in json.loads((work / "curves.json").read_text()).items()}
        plot(curves, out / "speed_error.png")
        print(time_to_cycles_error(curves)[0])
        return
    out.mkdir(parents=True, exist_ok=True)
    cache = work / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    rows, curves = [], {}
    started = time.perf_counter()
    for name in args.meshes:
        run_mesh(name, cache, out, rows, curves, args.runs)
    headers = ["mesh", "method", "settings", "time s", "stages s", "RMSE", "p99 error", "seam mean / p99"]
    table = markdown_table(headers, rows)
    (work / "curves.json").write_text(json.dumps({"|".join(k): v for k, v in curves.items()}))
    plot(curves, out / "speed_error.png")
    say("{} reference rays at {} points per mesh; total {:.0f} s.".format(
        REFERENCE_RAYS, POINTS, time.perf_counter() - started))
    say()
    say("![RMSE against time, log-log, one panel per mesh](speed_error.png)")
    say()
    say(table)
    say()
    table, (cells, within, half, ruled) = time_to_cycles_error(curves)
    say("Time to Cycles' error: for each Cycles level, the cheapest setting of each baker that reaches it.")
    say()
    say(table)
    say()
    say("Seamless AO reaches the level in at most Cycles' time in {} of {} cells, and in at most half of it in "
        "{}.".format(within, cells, half))
    say("The rule (ours at most half of Cycles' time where Cycles takes at least {0:.0f} s, else at most {0:.0f} s) "
        "holds in {1} of {2} cells.".format(RULE_SECONDS, ruled, cells))
    say()
    promises, counts = promise_rows(curves)
    say("The Quality presets (Seamless AO's default: Good) beside Cycles' cheapest route to the error each "
        "promises to reach:")
    say()
    say(markdown_table(PROMISE_HEADERS, promises))
    say()
    say(promise_sentence(counts))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
