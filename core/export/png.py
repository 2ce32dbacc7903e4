"""PNG files of float images, for the AO that leaves Blender: 8- or 16-bit, one to four channels.

Blender saves an image at the bit depth of the scene's output settings, and its glTF exporter re-encodes
float images as it likes; the exported texture's depth and channels are a user's choice here, so the
file is written here, with nothing but zlib, and handed to Blender packed (the exporter then embeds
these bytes unchanged).
"""

import struct
import zlib

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: PNG colour type of an image with 1, 2, 3 or 4 channels: grey, grey + alpha, RGB, RGBA.
COLOUR_TYPES = {1: 0, 2: 4, 3: 2, 4: 6}
BIT_DEPTHS = (8, 16)
# The filter every row is written with: "Up" (each byte minus the byte above it), which suits smooth AO.
_UP_FILTER = 2


def quantise(values, bit_depth):
    """Integer levels of ``values`` (any shape, in [0, 1], clipped) at ``bit_depth`` bits: rounded to the
    nearest of the 2**bit_depth levels, as uint8 or big-endian uint16 (PNG's byte order)."""
    levels = (1 << bit_depth) - 1
    rounded = np.rint(np.clip(values, 0.0, 1.0) * levels)
    return rounded.astype(np.uint8 if bit_depth == 8 else ">u2")


def encode_png(values, bit_depth=16):
    """The bytes of a PNG file holding ``values``.

    Parameters
    ----------
    values : (h, w) or (h, w, c) float, c in 1..4, in [0, 1] (outside is clipped)
        Row 0 is the image's top row (Blender's pixel rows run bottom up: flip them first).
    bit_depth : {8, 16}

    Raises
    ------
    ValueError
        For a value that is not finite, an empty image, a channel count outside 1..4 or another bit depth.
    """
    values = np.asarray(values, dtype=np.float64)
    if values.ndim == 2:
        values = values[:, :, None]
    if values.ndim != 3 or values.shape[2] not in COLOUR_TYPES or min(values.shape[:2]) < 1:
        raise ValueError("an image is (h, w) or (h, w, 1..4) with h, w >= 1, not {}".format(values.shape))
    if bit_depth not in BIT_DEPTHS:
        raise ValueError("a PNG here is 8- or 16-bit, not {}".format(bit_depth))
    if not np.isfinite(values).all():
        raise ValueError("an image value is NaN or infinite")
    height, width, channels = values.shape
    rows = quantise(values, bit_depth).reshape(height, -1).view(np.uint8)          # (h, bytes per row)
    filtered = rows.copy()
    filtered[1:] -= rows[:-1]                                                        # Up: modulo 256
    scanlines = np.concatenate([np.full((height, 1), _UP_FILTER, dtype=np.uint8), filtered], axis=1)
    header = struct.pack(">IIBBBBB", width, height, bit_depth, COLOUR_TYPES[channels], 0, 0, 0)
    return b"".join([SIGNATURE, _chunk(b"IHDR", header), _chunk(b"IDAT", zlib.compress(scanlines.tobytes(), 6)),
                     _chunk(b"IEND", b"")])


def _chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
