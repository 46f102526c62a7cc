"""
Grading a run from its bag.

The one loader (series), the metrics, the rubric, the summary line of ``robotica run``, and
the report (HTML) with its figures.
"""

__all__ = ['metrics', 'report', 'rubric', 'series', 'summary']
