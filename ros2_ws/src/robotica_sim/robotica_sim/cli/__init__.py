"""The ``robotica`` command: one module per verb, each with ``add_arguments`` and ``main``."""

__all__ = ['main', 'run']
