"""User-facing errors.

Every problem with a user's input (missing or corrupt file, wrong shape, unknown joint name, NaN-only data)
raises :class:`HDVRError` with a one-line message naming the problem. The CLI prints it as ``hdvr: error: ...``
and exits with status 2 instead of showing a traceback.
"""


class HDVRError(Exception):
    """A problem with the user's input or request, described in one line."""


def require(condition: bool, message: str) -> None:
    """Raise :class:`HDVRError` with ``message`` unless ``condition`` holds."""
    if not condition:
        raise HDVRError(message)
