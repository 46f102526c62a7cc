"""Live view of a running graph: the Foxglove WebSocket relay of ``robotica view``."""

__all__ = ['relay']
