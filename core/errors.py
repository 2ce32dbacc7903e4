"""Exceptions raised by the core.

Operators catch :class:`SeamlessAOError` and show its message in the UI; any
other exception is a bug.
"""


class SeamlessAOError(Exception):
    """A problem with the input or settings that the user can fix.

    The message is one sentence meant for the user, e.g. "The mesh has no faces".
    """


class BakeCancelled(SeamlessAOError):
    """The bake was stopped on request (ESC or the API's cancel callback)."""

    def __init__(self, message="The bake was cancelled; nothing was changed."):
        super().__init__(message)
