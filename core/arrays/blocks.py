"""Long arrays worked through a block of rows at a time.

A step over a million rows that builds index or product temporaries of the
whole length at once allocates tens of MB per temporary, and on these
machines fresh pages cost more than the arithmetic.  The same step over
blocks of :data:`BLOCK_ROWS` rows keeps its temporaries a few MB each and
gives the same values to the bit (each row is computed alone).
"""

#: Rows a block holds: a few MB per temporary of a few float64 per row.
BLOCK_ROWS = 1 << 16


def row_blocks(count):
    """Slices covering rows ``0 .. count-1`` in order, :data:`BLOCK_ROWS` at a time (read at each call, so a test
    may make blocks small); none for ``count`` 0."""
    rows = BLOCK_ROWS
    return [slice(start, min(start + rows, count)) for start in range(0, count, rows)]
