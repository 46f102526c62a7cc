"""The one error of the world model: bad geometry, a malformed map file or ``world:`` section."""

__all__ = ['WorldError']


class WorldError(ValueError):
    """
    A world that cannot be built: the message names the file or key and the field at fault.

    A subclass of ValueError, so that a caller catching the core's documented ValueError also
    catches it (STYLE.md §5, errors in the shell).

    >>> str(WorldError('world.circles[0]: radius must be > 0 m, got -1.0'))
    'world.circles[0]: radius must be > 0 m, got -1.0'
    """
