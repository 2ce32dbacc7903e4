"""What each Quality preset promises against Blender's own route (issue 52), checked on measured runs.

Pure over report.py's ``curves[(mesh, method)] = [(seconds, RMSE, label), ...]``: Cycles' runs under method
``"Cycles"`` labelled ``"<size>/<samples>"``, the presets' under :data:`PRESET_METHOD` labelled by their name.
"""

#: The columns of :func:`promise_rows`.
HEADERS = ("mesh", "preset", "ours: time, RMSE", "Cycles' level to reach", "Cycles' cheapest to it", "time allowed",
           "kept")

PRESET_METHOD = "Seamless AO, Quality"

#: ``(preset, Cycles settings whose best RMSE it must reach, share of Cycles' cheapest time to that RMSE it
#: may take, meshes where it must also finish under ``LIMIT_SECONDS``)``.
PROMISES = (
    ("Draft", ("256/16",), None, ("scan", "interior")),
    ("Good", ("512/16", "512/64", "512/256"), 0.5, ()),
    ("Final", ("1024/256",), 0.25, ()),
)
LIMIT_SECONDS = 1.0


def cheapest_reaching(runs, level):
    """The fastest of ``runs`` (``(seconds, RMSE, label)`` each) whose RMSE is at most ``level``, the more accurate
    of equally fast ones first; None if none is."""
    good = sorted(run for run in runs if run[1] <= level)
    return good[0] if good else None


def promise_rows(curves):
    """One row (:data:`HEADERS`) per mesh and preset, and ``(promises, kept)``."""
    rows, counts = [], [0, 0]
    for mesh in list(dict.fromkeys(mesh for mesh, _ in curves)):
        cycles = curves.get((mesh, "Cycles"), [])
        ours = {label: (seconds, rmse) for seconds, rmse, label in curves.get((mesh, PRESET_METHOD), [])}
        for preset, targets, share, timed in PROMISES:
            levels = [run for run in cycles if run[2] in targets]
            if preset not in ours or not levels:
                continue
            level = min(run[1] for run in levels)
            cheapest = cheapest_reaching(cycles, level)
            seconds, rmse = ours[preset]
            limit = cheapest[0] * share if share is not None else (LIMIT_SECONDS if mesh in timed else None)
            kept = rmse <= level and (limit is None or seconds <= limit)
            counts[0] += 1
            counts[1] += kept
            rows.append([mesh, preset, "{:.2f} s, {:.4f}".format(seconds, rmse),
                         "{:.4f} ({})".format(level, " / ".join(t.replace("/", "²/") for t in targets)),
                         "{:.2f} s ({})".format(cheapest[0], cheapest[2].replace("/", "²/")),
                         "-" if limit is None else "{:.2f} s".format(limit), "yes" if kept else "**no**"])
    return rows, tuple(counts)


def promise_sentence(counts):
    return ("The presets keep {} of their {} promises (Draft: Cycles' 256²/16 error, under {:.0f} s on the scan "
            "and the interior; Good: Cycles' best of 512² x 16/64/256 in at most half of Cycles' cheapest time to "
            "it; Final: Cycles' 1024²/256 in at most a quarter).".format(counts[1], counts[0], LIMIT_SECONDS))
