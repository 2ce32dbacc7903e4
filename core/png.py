"""A 16-bit greyscale PNG encoder (numpy and zlib only): the AO saved without losing precision."""

import zlib

import numpy as np


def png16(values):
    """The bytes of a 16-bit greyscale PNG of ``values`` (height, width) in [0, 1], row 0 at the bottom
    (Blender's pixel order; PNG's first row is the top).  Values outside [0, 1] are clipped."""
    values = np.asarray(values, dtype=np.float64)
    height, width = values.shape
    data = np.round(np.clip(values[::-1], 0.0, 1.0) * 65535.0).astype(">u2")
    raw = b"".join(b"\x00" + row.tobytes() for row in data)          # filter type 0 on every row
    header = width.to_bytes(4, "big") + height.to_bytes(4, "big") + bytes([16, 0, 0, 0, 0])
    return (b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", header) + _chunk(b"IDAT", zlib.compress(raw, 6))
            + _chunk(b"IEND", b""))


def _chunk(kind, payload):
    return len(payload).to_bytes(4, "big") + kind + payload + zlib.crc32(kind + payload).to_bytes(4, "big")
