"""PNG bytes read back without Blender: the levels a writer stored, for tests on arrays."""

import struct
import zlib

import numpy as np


def decode_png(data):
    """(height, width, channels) uint16 levels and the bit depth of PNG bytes, top row first, for the rows'
    filters None and Up (the two any writer here uses); checks every chunk's CRC."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    position, chunks = 8, {}
    while position < len(data):
        length, = struct.unpack(">I", data[position:position + 4])
        kind = data[position + 4:position + 8]
        payload = data[position + 8:position + 8 + length]
        crc, = struct.unpack(">I", data[position + 8 + length:position + 12 + length])
        assert crc == zlib.crc32(kind + payload)
        chunks[kind] = chunks.get(kind, b"") + payload
        position += 12 + length
    width, height, depth, colour = struct.unpack(">IIBB", chunks[b"IHDR"][:10])
    channels = {0: 1, 4: 2, 2: 3, 6: 4}[colour]
    row_bytes = width * channels * depth // 8
    raw = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), dtype=np.uint8).reshape(height, 1 + row_bytes)
    rows = np.zeros((height, row_bytes), dtype=np.uint8)
    for y in range(height):
        assert raw[y, 0] in (0, 2), "filter {}".format(raw[y, 0])
        above = rows[y - 1] if (y > 0 and raw[y, 0] == 2) else 0
        rows[y] = raw[y, 1:] + above                          # uint8 wraps as PNG's modulo 256
    levels = rows.view(">u2") if depth == 16 else rows
    return levels.astype(np.uint16).reshape(height, width, channels), depth
