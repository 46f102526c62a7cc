"""
Running a scenario: the scenario file, its plan of nodes and the process supervisor.

Also the software versions that a run records, and the files shipped with the package
(scenarios, rubrics) found by name.
"""

__all__ = ['plan', 'scenario', 'shipped', 'software_versions', 'supervisor']
