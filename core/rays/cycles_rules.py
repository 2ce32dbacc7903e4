"""What the Cycles ray caster can and cannot do, in one place.

The Cycles caster (``operators/adapters/cycles_caster.py``) bakes whole texels
with Cycles' AO pass, which knows classic AO only.  The settings, the caster
choice, the ray job and the panel read these facts from here.
"""

#: Pilot rays of each texel when a caster that bakes whole texels (Cycles) takes the rest: from inside a
#: closed piece every ray meets its back faces, so a few tell the buried texels (core/rays/ao.py's ``buried_by_vote``).
BULK_PILOT_RAYS = 4

#: What the Cycles caster cannot do: (setting, the value it needs, the sentence that says so, the value in
#: a few words for the Ray Caster items' descriptions).
CYCLES_NEEDS = (
    ("falloff", "NONE", "Cycles' AO has no falloff", "no falloff"),
    ("cone_angle", 90.0, "Cycles casts over the whole hemisphere (Cone Angle 90°)", "full hemisphere"),
    ("distribution", "COSINE", "Cycles spreads its rays by the cosine", "cosine rays"),
    ("ignore_backfaces", False, "Cycles' AO counts back faces", "back faces occlude"),
    ("horizon_bias", 0.0, "Cycles has no horizon bias", "no horizon bias"),
    ("use_ground_plane", False, "Cycles' AO sees no ground plane", "no ground plane"),
)
#: The settings Cycles can follow, in a few words.
CLASSIC_AO = ", ".join(need[3] for need in CYCLES_NEEDS)

#: Settings the Cycles caster cannot follow (:data:`CYCLES_NEEDS`) or does not use: it casts a whole texel's
#: rays at once, so the adaptive stop never applies to them.
NOT_FOR_CYCLES = frozenset([need[0] for need in CYCLES_NEEDS] + ["adaptive"])


#: Memory a bake adds where the Cycles caster casts the bulk: Cycles' own scene, BVH and device (fixed, bytes)
#: and its copy of the mesh and the occluders (per triangle). The peaks ``tests/bench/bench_memory.py`` measures
#: grew by about this much when Ray Caster Automatic started taking Cycles (about 200 MB on Suzanne, 380 MB
#: at a million triangles).
CYCLES_FIXED_BYTES = 200 * 2**20
CYCLES_BYTES_PER_TRIANGLE = 170


def first_unfollowed(settings):
    """The first ``(setting, value it needs, reason, in short)`` of :data:`CYCLES_NEEDS` that ``settings`` (any
    object with those attributes, e.g. a ``BakeSettings``) breaks, or None."""
    return next((need for need in CYCLES_NEEDS if getattr(settings, need[0]) != need[1]), None)
