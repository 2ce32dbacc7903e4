"""Ambient occlusion of texel points by ray casting (thesis §7.4, RTR §9.2).

AO at a point with normal n is ``1 - mean(occlusion of each ray)``: 1 = fully
open, 0 = fully occluded, normalised by the ray count (the thesis' formula 7.2
forgets the 1/N).  Rays are cosine-distributed (or uniform) inside a cone
around n, from :mod:`.sampling`.  A hit occludes fully (``NONE``, binary
visibility as Cycles computes it), or ``1 - d/max`` (``LINEAR``, the thesis'
falloff), or ``1 - sqrt(d/max)`` (``OBSCURANCE``); hits beyond the maximum
distance do not count.

Rays are cast by a *caster* (:class:`.ray_setup.RayCaster`), with the
parameters of :class:`.ray_setup.AOParams`, in the ray space of :func:`.ray_setup.ray_space`.

Robustness, all relative to the object's size:

* the origin is lifted off the surface along the geometric normal, on the
  shading normal's side, so the surface itself is never hit at the origin;
* a ray that the smooth shading normal sends below the geometric tangent
  plane (coarse smooth meshes) is mirrored back above it instead of hitting
  the neighbouring faces and darkening the texel wholesale;
* an optional horizon bias fades the occlusion of rays close to the tangent
  plane (faceting on coarse meshes);
* a hit on the back of a face within a few offsets of the origin is a
  rounding artefact of starting on that face (texels in a concave crease)
  and is stepped through;
* ``ignore_backfaces``: a ray that hits a face from behind (an open scan,
  seen through a hole) continues through it.

Adaptive sampling: the first quarter of the rays (at least 16; a stratified
set of their own) are cast for every texel; where they all agree (all open,
or with binary falloff all blocked), and the texel's neighbours in the atlas
agree on the same answer, the texel keeps that value and the other rays are
not cast (:class:`..job.AOJob`).  Near an occlusion boundary some
neighbour disagrees, so those texels always get every ray.
"""

import numpy as np

from .sampling import cone_components, tangent_frames, texel_samples

#: How many times a back-face hit is stepped through when back faces are ignored.
BACKFACE_STEPS = 4
#: Runs of three texels side by side below which :func:`noise_estimate` trusts only each texel's own rays.
MIN_SIDE_TRIPLES = 64


def occlusion_of_hits(distance, params):
    """Occlusion (0..1) of each ray from its hit distance (``inf`` = miss)."""
    hit = distance <= params.max_distance
    if params.falloff == "NONE":
        return hit.astype(np.float64)
    ratio = np.clip(distance / params.max_distance, 0.0, 1.0)
    if params.falloff == "LINEAR":
        return np.where(hit, 1.0 - ratio, 0.0)
    if params.falloff == "OBSCURANCE":
        return np.where(hit, 1.0 - np.sqrt(ratio), 0.0)
    raise ValueError("unknown falloff {!r}".format(params.falloff))


def ray_directions(normals, geometric, texel_ids, ray_indices, params, samples=texel_samples):
    """World (ray-space) directions of some rays of some texels.

    Parameters
    ----------
    normals : (k, 3) unit shading normals
    geometric : (k, 3) unit geometric normals, already on the shading side
    texel_ids : (k,) int
    ray_indices : (r,) int

    Returns
    -------
    directions : (k, r, 3) float64, unit, never below the geometric tangent plane
    elevation : (k, r) float64, sine of the angle above the shading tangent plane
    """
    # one (k, r) plane per component: arrays with a trailing axis of 3 are slow in numpy
    lx, ly, lz = cone_components(samples(texel_ids, ray_indices, params.seed), params.cone_angle,
                                 params.distribution)
    tangent, bitangent = tangent_frames(normals)
    world = [lx * tangent[:, c, None] + ly * bitangent[:, c, None] + lz * normals[:, c, None] for c in range(3)]
    # a ray below the geometric plane is reflected in it (a reflection keeps it unit length)
    mirror = 2.0 * np.minimum(sum(world[c] * geometric[:, c, None] for c in range(3)), 0.0)
    directions = np.empty(lx.shape + (3,))
    for c in range(3):
        directions[..., c] = world[c] - mirror * geometric[:, c, None]
    return directions, lz


def cast_with_options(caster, origins, directions, params):
    """Hit distance of each ray, honouring ``ignore_backfaces`` and the ground plane.

    A ray that starts on a surface (a texel in a concave crease lies on two)
    can hit the back of that surface at distance ~0 through rounding; such
    hits are stepped through, whatever ``ignore_backfaces`` says.

    Returns
    -------
    distance : (n,) float64, ``inf`` for rays that hit nothing in range
    behind : (n,) bool, the ray's hit is the back of a sealed face (see :func:`buried_by_vote`)
    """
    distance, facing, sealed = caster.cast(origins, directions, params.max_distance)
    facing, sealed = np.array(facing, dtype=np.float64), np.array(sealed, dtype=bool)
    near = 4.0 * params.offset
    travelled = np.zeros(len(origins))
    through = np.isfinite(distance) & (facing > 0) & ((distance < near) | params.ignore_backfaces)
    for _ in range(BACKFACE_STEPS):
        if not through.any():
            break
        index = np.flatnonzero(through)
        travelled[index] += distance[index] + params.offset
        start = origins[index] + directions[index] * travelled[index, None]
        remaining = np.maximum(params.max_distance - travelled[index], 0.0)
        again, again_facing, again_sealed = caster.cast(start, directions[index], float(remaining.max()))
        again = np.where(again <= remaining, again, np.inf)
        distance[index] = again
        facing[index] = again_facing
        sealed[index] = again_sealed
        through[:] = False
        through[index] = np.isfinite(again) & (again_facing > 0) & ((again < near) | params.ignore_backfaces)
    distance = np.where(through, np.inf, distance + travelled)
    behind = np.isfinite(distance) & (facing > 0.0) & sealed
    if params.ground_height is not None:
        down = directions[:, 2] < -1e-12
        to_ground = (params.ground_height - origins[:, 2]) / np.where(down, directions[:, 2], -1.0)
        to_ground = np.where(down & (to_ground >= 0.0), to_ground, np.inf)
        behind &= distance < to_ground
        distance = np.minimum(distance, to_ground)
    return distance, behind


def ray_origins(points, normals, geometric, offset):
    """Where a texel's rays start: the point lifted by ``offset`` along its geometric normal, turned to the
    shading normal's side (a texel on a face seen from behind casts from the side it is shaded on).

    Parameters
    ----------
    points, normals, geometric : (k, 3) float64, ray space; ``geometric`` unit length
    offset : float, ray space units

    Returns
    -------
    origins : (k, 3) float64
    geometric : (k, 3) float64, the geometric normal turned to the shading normal's side
    """
    side = np.where((geometric * normals).sum(axis=1) < 0.0, -1.0, 1.0)
    geometric = geometric * side[:, None]
    return points + offset * geometric, geometric


def occlusion_sums(points, normals, geometric, texel_ids, ray_indices, params, caster, samples=texel_samples):
    """Summed occlusion of some rays (``ray_indices`` of the sequence) of some points, in ray space.

    Parameters
    ----------
    points, normals, geometric : (k, 3) float64
    texel_ids : (k,) int, stable ids (the per-texel scramble depends on them)
    ray_indices : (r,) int
    params : AOParams
    caster : object with ``cast``

    Returns
    -------
    sums : (k,) float64 in [0, r]
    behind : (k,) int64 in [0, r], rays whose hit is the back of a sealed face
    """
    if not len(points) or not len(ray_indices):
        return np.zeros(len(points)), np.zeros(len(points), dtype=np.int64)
    origins, geometric = ray_origins(points, normals, geometric, params.offset)
    directions, elevation = ray_directions(normals, geometric, texel_ids, ray_indices, params, samples)
    count = len(ray_indices)
    start = np.repeat(origins, count, axis=0)
    distance, behind = cast_with_options(caster, start, directions.reshape(-1, 3), params)
    occlusion = occlusion_of_hits(distance.reshape(len(points), count), params)
    if params.horizon_bias > 0.0:
        occlusion *= np.clip(np.arcsin(np.clip(elevation, -1, 1)) / np.radians(params.horizon_bias), 0.0, 1.0)
    return occlusion.sum(axis=1), behind.reshape(len(points), count).sum(axis=1)


def buried_by_vote(behind, rays, params):
    """Points inside a closed piece: most of their rays hit the back of a sealed face.

    A texel whose surface point lies inside another piece (where two shells
    intersect: Suzanne's eyes in her head, a crate pushed into a wall) is
    never seen, and its AO is 0; bilinear filtering would still blend that 0
    into the visible texels beside it, a dark line along the intersection
    (:class:`..job.AOJob` shades the rim of each buried region again at the
    crease).  From inside a closed, consistently oriented piece every ray
    meets the piece's inside, the back of its faces; from a visible point rays
    meet front faces.  Only faces of (nearly) closed pieces count
    (:mod:`..mesh.sealed`): behind an open sheet (a drape before a wall) rays meet
    its back too, though the point is seen round the sheet's edges.  So a
    point is buried when more than half of its rays hit the back of sealed
    faces.  With ``ignore_backfaces`` the user has said back faces are not
    walls, and nothing is buried.

    Parameters
    ----------
    behind : (k,) int, rays per point whose hit is the back of a sealed face (:func:`occlusion_sums`)
    rays : int or (k,) int, rays cast per point
    params : AOParams

    Returns
    -------
    (k,) bool
    """
    behind = np.asarray(behind)
    if params.ignore_backfaces:
        return np.zeros(behind.shape, dtype=bool)
    return 2 * behind > np.asarray(rays)


def noise_estimate(ao, rays, neighbour=None):
    """Expected error (one standard deviation, RMS over texels) of AO estimated from ``rays`` rays each.

    Two estimates, both reading high, and the smaller is returned:

    * Each texel's own rays, as if they were independent: each ray contributes
      a value in [0, 1], so for a texel whose AO is ``m`` the variance of one
      ray is at most m (1 - m) and ``rays`` rays divide it by ``rays``; the
      estimate m̂ (1 - m̂) · n / (n - 1) is unbiased for m (1 - m) with binary
      rays.  Stratified (Sobol') rays do much better from 2 rays up: on the
      pipeline test's ring on a floor at 16 rays this figure is over 1.6
      times the truth.  One ray says nothing of its own texel's variance
      (m̂ (1 - m̂) is 0 for a binary ray), so texels with one ray share a
      pooled one: half the mean squared difference between ``neighbour``
      pairs of one-ray texels, or, without such pairs, M (1 - M) of their
      mean M (at least the mean of their m (1 - m): it is concave).
    * Texels side by side (with ``neighbour``, from :data:`MIN_SIDE_TRIPLES`
      runs of three): the mean square of a - 2b + c over runs a, b, c of
      texels is six times their variance when their rays are independent of
      each other's, plus the square of how much the AO itself bends across
      them (a straight gradient adds nothing).  It sees what stratification
      gains, and reads high where the AO changes from texel to texel (a scan
      baked at about a triangle per texel).

    It is an estimate, not a bound: the denoiser does better, and a bake
    leaves out the texels the adaptive stop settled (their pilot rays all
    agreed, which says nothing of their variance: :class:`.job.AOJob`'s
    ``settled``).

    Parameters
    ----------
    ao : (n,) float, AO estimates in [0, 1]
    rays : int or (n,) int, rays per estimate
    neighbour : (n,) int or None
        Index of an estimate beside each one (the next texel of its chart in
        its row), ``-1`` where there is none.

    Returns
    -------
    float, in AO units (0 for no estimates)
    """
    ao = np.clip(np.asarray(ao, dtype=np.float64), 0.0, 1.0)
    rays = np.broadcast_to(np.asarray(rays, dtype=np.float64), ao.shape)
    if not len(ao) or rays.min() < 1:
        return 0.0
    variance = ao * (1.0 - ao) * rays / np.maximum(rays - 1.0, 1.0)
    one = rays < 2
    if neighbour is not None:                                   # texels side by side: (p,) pairs
        neighbour = np.asarray(neighbour)
        first = np.flatnonzero(neighbour >= 0)
        second = neighbour[first]
    if one.any():
        pooled = ao[one].mean()
        pooled = pooled * (1.0 - pooled)
        if neighbour is not None:
            both = one[first] & one[second]
            if both.any():
                pooled = 0.5 * float(np.mean((ao[first[both]] - ao[second[both]]) ** 2))
        variance[one] = pooled
    own = float(np.sqrt((variance / rays).mean()))
    if neighbour is None:
        return own
    in_a_run = neighbour[second] >= 0
    if in_a_run.sum() < MIN_SIDE_TRIPLES:
        return own
    first, second = first[in_a_run], second[in_a_run]
    bend = ao[first] - 2.0 * ao[second] + ao[neighbour[second]]
    return min(own, float(np.sqrt(np.mean(bend**2) / 6.0)))


def pilot_agreement(sums, params, pilot_count):
    """Code per texel after its ``pilot_count`` rays (a number or (k,)): 0 = undecided, 1 = all open,
    2 = all fully blocked."""
    code = np.zeros(len(sums), dtype=np.int8)
    code[sums == 0.0] = 1
    if params.falloff == "NONE" and params.horizon_bias == 0.0:
        code[sums == pilot_count] = 2
    return code


def settle_pilot(sums, params, pilot_count, neighbours=None, rays=None):
    """The adaptive stop, after the pilot rays (the one place it is decided).

    A point whose pilot rays all agree (all open, or with binary falloff all
    blocked; :func:`pilot_agreement`) keeps that value for all its rays, if
    ``neighbours(code)`` (optional: (k,) bool, e.g. the texel's atlas
    neighbours agree too) allows it.

    Parameters
    ----------
    sums : (k,) float64, occlusion summed over the pilot rays; the decided ones are scaled in place to
        all their rays
    params : AOParams
    pilot_count : int or (k,) int, rays cast so far per point
    rays : int or (k,) int, optional, rays per point in all (default ``params.rays``)

    Returns
    -------
    decided : (k,) bool, the points that need no more rays
    """
    if not params.adaptive:
        return np.zeros(len(sums), dtype=bool)
    code = pilot_agreement(sums, params, pilot_count)
    decided = code > 0
    if neighbours is not None and decided.any():
        decided &= neighbours(code)
    scale = np.broadcast_to((params.rays if rays is None else rays) / np.asarray(pilot_count, dtype=np.float64),
                            sums.shape)
    sums[decided] *= scale[decided]
    return decided


