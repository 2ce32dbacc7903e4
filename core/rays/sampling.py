"""Ray directions: a 2D Sobol' sequence, scrambled per texel, mapped into a cone.

The first two dimensions of Sobol' form a (0, 2)-sequence: every prefix of
length 2^k is stratified, so the first quarter of the rays (the adaptive
pilot) is itself a well-spread set.  Each texel XORs the sequence with its own
random 32-bit words (a random digital shift, which keeps the stratification),
drawn from a hash of the texel index and the seed: these rays do not depend on
how texels are batched, and where they are all the rays (the Geometry Nodes
caster) the same seed gives the same image bit for bit.  Cycles' bulk rays
follow its batches (docs/how-it-works.md).
"""

import numpy as np

_BITS = 32


def _direction_numbers():
    """Generator matrices (as 32 column words) of Sobol' dimensions 1 and 2."""
    first = np.array([1 << (_BITS - 1 - k) for k in range(_BITS)], dtype=np.uint64)   # van der Corput
    second = np.zeros(_BITS, dtype=np.uint64)
    value = 1 << (_BITS - 1)
    for k in range(_BITS):                      # primitive polynomial x + 1: v_k = v_{k-1} ^ (v_{k-1} >> 1)
        second[k] = value
        value ^= value >> 1
    return first, second


_FIRST, _SECOND = _direction_numbers()


def sobol_2d(indices):
    """Integer Sobol' points of the given sequence indices.

    Parameters
    ----------
    indices : (n,) int, >= 0

    Returns
    -------
    (n, 2) uint64 in [0, 2^32): divide by 2^32 for points in [0, 1)^2.
    """
    indices = np.asarray(indices, dtype=np.uint64)
    out = np.zeros((len(indices), 2), dtype=np.uint64)
    # every bit up to the highest one any index has (a bit no index has set may sit below a set one:
    # indices 16..23 all lack bit 3 but not bit 4)
    for bit in range(int(indices.max()).bit_length() if len(indices) else 0):
        set_bit = ((indices >> np.uint64(bit)) & np.uint64(1)).astype(bool)
        out[set_bit, 0] ^= _FIRST[bit]
        out[set_bit, 1] ^= _SECOND[bit]
    return out


def hash_words(keys, seed, stream):
    """Two-round 64-bit mix (splitmix64 finaliser) of ``keys`` with ``seed``: (n,) uint64 -> uint32."""
    x = np.asarray(keys, dtype=np.uint64) * np.uint64(0x9E3779B97F4A7C15)
    x ^= np.uint64((seed * 0x632BE59BD9B4E019 + stream * 0x85EBCA77C2B2AE63) & 0xFFFFFFFFFFFFFFFF)
    for multiplier in (0xBF58476D1CE4E5B9, 0x94D049BB133111EB):
        x ^= x >> np.uint64(30 if multiplier == 0xBF58476D1CE4E5B9 else 27)
        x *= np.uint64(multiplier)
    x ^= x >> np.uint64(31)
    return x >> np.uint64(32)


def texel_samples(texel_ids, ray_indices, seed):
    """Points in [0, 1)^2 for rays ``ray_indices`` of each texel, scrambled per texel.

    Parameters
    ----------
    texel_ids : (k,) int
        Stable texel identifiers (flat texel index).
    ray_indices : (r,) int
        Which rays of the sequence (0 .. N-1).
    seed : int

    Returns
    -------
    (k, r, 2) float64
    """
    points = sobol_2d(ray_indices)                                          # (r, 2)
    shift = np.stack([hash_words(texel_ids, seed, 1), hash_words(texel_ids, seed, 2)], axis=1)   # (k, 2)
    scrambled = points[None, :, :] ^ shift[:, None, :]
    return scrambled.astype(np.float64) * (1.0 / 2.0**_BITS) + 0.5 / 2.0**_BITS


def random_samples(texel_ids, ray_indices, seed):
    """Plain independent random points (the baseline the sequence must beat), shape (k, r, 2)."""
    rng = np.random.default_rng([seed, int(np.asarray(texel_ids)[:1].sum()), len(texel_ids)])
    return rng.random((len(texel_ids), len(ray_indices), 2))


def cone_directions(samples, cone_angle, distribution="COSINE"):
    """Map points of the unit square to unit directions around +Z.

    Parameters
    ----------
    samples : (..., 2) float
    cone_angle : float, degrees, half-angle of the cone (90 = hemisphere)
    distribution : "COSINE" (pdf proportional to cos theta inside the cone) or
        "UNIFORM" (uniform in solid angle inside the cone)

    Returns
    -------
    (..., 3) float64, z >= cos(cone_angle)
    """
    return np.stack(cone_components(samples, cone_angle, distribution), axis=-1)


def cone_components(samples, cone_angle, distribution="COSINE"):
    """:func:`cone_directions` as three arrays ``x, y, z`` (...,) (no trailing axis of 3 to stack)."""
    cos_max = np.cos(np.radians(cone_angle))
    u1, u2 = samples[..., 0], samples[..., 1]
    if distribution == "COSINE":
        # cos^2 theta uniform in [cos_max^2, 1]: the cosine-weighted pdf restricted to the cone
        cos_theta = np.sqrt(1.0 - u1 * (1.0 - cos_max**2))
    elif distribution == "UNIFORM":
        cos_theta = 1.0 - u1 * (1.0 - cos_max)
    else:
        raise ValueError("unknown distribution {!r}".format(distribution))
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta**2))
    phi = 2.0 * np.pi * u2
    return sin_theta * np.cos(phi), sin_theta * np.sin(phi), cos_theta


def tangent_frames(normals):
    """Orthonormal tangent and bitangent for unit normals (k, 3) (Duff et al. 2017, branchless)."""
    x, y, z = normals[:, 0], normals[:, 1], normals[:, 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    tangent = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=1)
    bitangent = np.stack([b, sign + y * y * a, -y], axis=1)
    return tangent, bitangent
